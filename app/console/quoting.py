"""Writing words for the console to read back (console.split_commands) exactly as they were: what recorded
demos, config.cfg, aliases, binds and Lua's command lines write."""
from __future__ import annotations

import shlex
from collections.abc import Iterable


def quote(word: str) -> str:
    """`word` as one console word: shlex.quote, which quotes blanks, quotes, ';' and the like, and also quotes
    '//', which shlex leaves bare but which outside quotes starts a comment (so `a//b` would be cut to `a`)."""
    quoted = shlex.quote(word)
    return f"'{word}'" if quoted == word and "//" in word else quoted  # bare: word holds no quote to escape


def join(words: Iterable[str]) -> str:
    """The words as one command line."""
    return " ".join(map(quote, words))
