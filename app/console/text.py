"""Numbers as the console shows them to people (files and demos keep floats exact: Cvar.serialise, repr)."""
from __future__ import annotations

SIGNIFICANT = 15  # any decimal typed with at most 15 significant digits comes back from a float as typed


def number(value: float) -> str:
    """A float as it was typed: 0.475 stays 0.475, 50.0 is 50, and the noise of arithmetic goes
    (0.45 + 0.025 shows as 0.475, not 0.47500000000000003); %g would cut 0.1234567 to 0.123457."""
    return f"{value:.{SIGNIFICANT}g}"


def count(n: int, noun: str, plural: str | None = None) -> str:
    """'1 flake', '2 flakes', '0 flakes'; `plural` where adding an s is wrong ('vertices')."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"
