"""Tab completion: to the longest common prefix, with the candidates to list. No Qt."""
from __future__ import annotations

import os
from dataclasses import dataclass

from app.console.registry import Registry

# Commands whose argument after the first is itself a command line: complete its command name.
TAKES_COMMAND = ("bind", "alias")


@dataclass(frozen=True)
class Completion:
    line: str                # the line with the word under completion extended
    candidates: list[str]    # what to list when there is more than one (cvars with their values)


def complete(registry: Registry, line: str) -> Completion:
    """Complete the last word: a name first; then the command's own argument completer (files for
    exec/lua/play, key names for bind, cvar names for set...); the command part of bind and alias."""
    head, sep, last = line.rpartition(" ")
    words = head.split()
    if not sep or not words:
        matches = [n for n in registry.names(":" in last) if n.startswith(last)]  # workspace:name once ':' is typed
        shown = [f"{n} = {registry.cvars[n].text()}" if n in registry.cvars else n for n in matches]
        return Completion(_extend(head + sep, last, matches), shown)
    name = words[0]
    if len(words) == 1 and name in registry.commands and registry.commands[name].completer:
        matches = registry.commands[name].completer(last)
    elif len(words) == 2 and name in TAKES_COMMAND:
        word = last.lstrip('"')
        matches = [n for n in registry.names(":" in word) if n.startswith(word)]
    else:
        return Completion(line, [])
    return Completion(_extend(head + " ", last, matches), matches)


def _extend(head: str, word: str, matches: list[str]) -> str:
    if not matches:
        return head + word
    if len(matches) == 1:
        done = matches[0]
        return head + done + ("" if done.endswith("/") else " ")
    common = os.path.commonprefix(matches)
    # Matching may ignore case (key names): never complete to less than what was typed.
    return head + (common if len(common) >= len(word) else word)
