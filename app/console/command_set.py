"""A module's console commands as module-level functions: each is declared where it is written, with its name,
argument spec and who may run it, and takes the context it works on (the workspace's state, the console) as its
first argument instead of reaching it through a closure. So a command can be found by name, imported and called
alone (`snowflake.add(ctx, 0, 0)`), and the set walked (`COMMANDS.declared`)."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any, Generic, TypeVar

from app.console.demo import ArgChecks, ScopedArgChecks
from app.console.registry import ALLOWED, USER, Command, Registry, parse_params

S = TypeVar("S")


@dataclass(frozen=True)
class Context(Generic[S]):
    """What a workspace's commands reach: the console (to print, to run or look up others) and the state."""
    console: Any  # app.console.console.Console (imported by type only: the console imports the command modules' hosts)
    state: S


@dataclass(frozen=True)
class Declared:
    """One command as declared: registered by `CommandSet.register` with its function bound to the context."""
    name: str
    function: Callable[..., Any]
    spec: str
    help: str
    completer: Callable[..., list[str]] | None  # (context, prefix) -> candidates
    recorded: bool
    quiet: bool
    allow: str


class CommandSet:
    """The commands (and their demo argument checks) of one module; `scope` names the workspace that owns them
    (None: global commands)."""

    def __init__(self, scope: str | None = None) -> None:
        self.scope = scope
        self.declared: list[Declared] = []
        self._checks: list[tuple[str, str | None, Callable[..., Any]]] = []

    def command(self, name: str, spec: str = "", help: str = "", completer=None, recorded: bool = True,
                quiet: bool = False, allow: str = USER):
        """Decorator: declare `function(context, *arguments)` as command `name` (see Registry.command)."""
        if allow not in ALLOWED:
            raise ValueError(f"{name}: allow must be one of {', '.join(ALLOWED)}, not {allow!r}")
        parse_params(spec)  # a bad spec fails at import, not when the set is registered

        def declare(function):
            self.declared.append(Declared(name, function, spec, help, completer, recorded, quiet, allow))
            return function

        return declare

    def check(self, name: str, model: str | None = None):
        """Decorator: declare `function(context, *arguments)` as the demo check of command or cvar `name`, reading
        `model`'s shape (ArgChecks.add); the command calls the same function first."""
        def declare(function):
            self._checks.append((name, model, function))
            return function

        return declare

    def register(self, registry: Registry, context: Any, checks: ArgChecks | ScopedArgChecks | None = None) -> None:
        """Register every declared command, bound to `context`, and every check in `checks` (scoped to the
        workspace by the caller, as the registry's commands are here; a set without checks needs none)."""
        if self._checks and checks is None:
            raise ValueError("these commands have demo checks: give the ArgChecks to register them in")
        for d in self.declared:
            completer = partial(d.completer, context) if d.completer else None
            registry.add_command(Command(d.name, partial(d.function, context), parse_params(d.spec), d.help,
                                         completer, d.recorded, d.quiet, self.scope, d.allow))
        for name, model, function in self._checks:
            checks.add(name, model)(partial(function, context))
