"""The table of what untrusted content may do with each command, made from the registry (docs/console.md holds
it between markers; tests/test_trust.py fails when the two differ, and says how to write it again)."""
from __future__ import annotations

from app.console.registry import Registry

BEGIN = "<!-- capabilities: made by app/console/capabilities.py; do not edit by hand -->"
END = "<!-- end of capabilities -->"


def rows(registry: Registry) -> list[tuple[str, str]]:
    """(command as cmdlist names it, what scripts may do with it), by name."""
    commands = sorted((registry.commands[key] for key in registry.commands), key=lambda c: (c.name, c.scope or ""))
    return [(c.label(), c.capability()) for c in commands]


def table(registry: Registry) -> str:
    lines = [BEGIN, "", "| command | who may run it |", "| --- | --- |"]
    lines += [f"| `{label}` | {capability} |" for label, capability in rows(registry)]
    return "\n".join([*lines, "", END])


def replaced(text: str, registry: Registry) -> str:
    """`text` (docs/console.md) with the table between its markers made again."""
    start, end = text.index(BEGIN), text.index(END) + len(END)
    return text[:start] + table(registry) + text[end:]
