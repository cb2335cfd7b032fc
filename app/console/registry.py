"""Commands and cvars in one registry, as the Quake console and Tex3Dtrace kept them. No Qt."""
from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any, Callable

from app.console.quoting import quote
from app.console.text import number


class CommandError(Exception):
    """A command refused its input; the message goes to the console log, the model is untouched."""


class Reported(CommandError):
    """A command failed and already said why (a script or file it ran logged the errors)."""


# Control characters, and every character str.splitlines() breaks a config line at: text that holds one
# would come back from config.cfg as two lines, the second one the attacker's. Tab is a blank.
_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f-\x9f\u2028\u2029]")


def check_text(what: str, text: str) -> str:
    """Refuse console text that holds a control character (a newline, say); else return it."""
    found = _CONTROL.search(text)
    if found:
        raise CommandError(f"{what} may not hold control characters (found {found.group()!r})")
    return text


@dataclass(frozen=True)
class Param:
    name: str
    type: type = str  # str, int or float
    optional: bool = False
    variadic: bool = False  # takes every remaining argument (a list)

    def usage(self) -> str:
        text = f"<{self.name}>" + ("..." if self.variadic else "")
        return f"[{text}]" if self.optional else text


def parse_params(spec: str) -> tuple[Param, ...]:
    """'x:float y:float [radius:float]' -> Params; a trailing '...' makes the last variadic."""
    params = []
    for word in spec.split():
        optional = word.startswith("[") and word.endswith("]")
        word = word.strip("[]")
        variadic = word.endswith("...")
        word = word.removesuffix("...")
        name, _, kind = word.partition(":")
        params.append(Param(name, {"": str, "str": str, "int": int, "float": float}[kind], optional, variadic))
    return tuple(params)


@dataclass
class Command:
    name: str
    handler: Callable[..., Any]
    params: tuple[Param, ...] = ()
    help: str = ""
    completer: Callable[[str], list[str]] | None = None  # candidates for the argument being typed
    recorded: bool = True  # False for queries and for commands that only run others (exec, lua, play)
    quiet: bool = False    # sent many times a second by a drag or hover: run without echoing the line
    scope: str | None = None  # the workspace that owns it; None: global

    @property
    def key(self) -> str:
        """The name that always means this command: `workspace:name` if scoped."""
        return f"{self.scope}:{self.name}" if self.scope else self.name

    def label(self) -> str:
        """The usage as help and cmdlist show it: `[volume] sample <name> [<size>]`."""
        return f"[{self.scope}] {self.usage()}" if self.scope else self.usage()

    def usage(self) -> str:
        return " ".join([self.name, *(p.usage() for p in self.params)])

    def bind(self, args: list[str]) -> list[Any]:
        """Convert the text arguments to the handler's types, or refuse with the usage line."""
        values: list[Any] = []
        rest = list(args)
        for p in self.params:
            if p.variadic:
                values.append([_convert(p, a, self) for a in rest])
                rest = []
                break
            if not rest:
                if p.optional:
                    break
                raise CommandError(f"missing <{p.name}>; usage: {self.usage()}")
            values.append(_convert(p, rest.pop(0), self))
        if rest:
            raise CommandError(f"too many arguments; usage: {self.usage()}")
        return values


def _convert(p: Param, text: str, cmd: Command) -> Any:
    try:
        value = p.type(text)
    except ValueError:
        raise CommandError(f"<{p.name}> must be {p.type.__name__}, got {text!r}; usage: {cmd.usage()}") from None
    if isinstance(value, float) and not math.isfinite(value):
        raise CommandError(f"<{p.name}> must be finite, got {text!r}")
    return value


_BOOL_WORDS = {"1": True, "0": False, "true": True, "false": False, "on": True, "off": False, "yes": True, "no": False}


@dataclass
class Cvar:
    """A typed console variable; setting it validates first, then notifies listeners."""

    name: str
    type: type  # str, int, float or bool
    default: Any
    help: str = ""
    min: float | None = None
    max: float | None = None
    archive: bool = False
    on_change: list[Callable[["Cvar"], None]] = field(default_factory=list)
    user_created: bool = False  # made by `set`; a later registration of the name takes it over
    choices: tuple | None = None  # the only values it takes, of its type (words, or numbers such as 1, 3, 5)

    def __post_init__(self) -> None:
        self.value = self.parse(str(self.default))

    def parse(self, text: str) -> Any:
        check_text(f"{self.name}'s value", text)
        try:
            if self.type is bool:
                value = _BOOL_WORDS[text.strip().lower()]
            else:
                value = self.type(text)
        except (KeyError, ValueError):
            raise CommandError(f"{self.name} takes a {self.type.__name__}, got {text!r}") from None
        if isinstance(value, float) and not math.isfinite(value):
            raise CommandError(f"{self.name} must be finite, got {text!r}")
        if self.min is not None and value < self.min or self.max is not None and value > self.max:
            raise CommandError(f"{self.name} must be within {self.min:g}..{self.max:g}, got {text}")
        if self.choices is not None and value not in self.choices:
            raise CommandError(f"{self.name} must be one of {', '.join(map(str, self.choices))}, got {text!r}")
        return value

    def set(self, text: str) -> None:
        value = self.parse(text)
        if value == self.value:
            return
        old = self.value
        self.value = value
        try:
            for callback in self.on_change:
                callback(self)
        except Exception:
            self.value = old  # a listener refused (e.g. the model's own validation): nothing half-applied
            raise

    def text(self) -> str:
        """For people: floats as typed (text.number)."""
        if self.type is float:
            return number(self.value)
        return self.serialise()

    def assignment(self) -> str:
        """The command that gives it this value again (configs, a demo's opening lines)."""
        return f"{'seta' if self.archive else 'set'} {self.name} {quote(self.serialise())}"

    def serialise(self) -> str:
        """For files, demos and digests: floats exact (repr round-trips)."""
        if self.type is bool:
            return "1" if self.value else "0"
        return repr(self.value) if self.type is float else str(self.value)


class CommandTable(Mapping[str, Command]):
    """Registry.commands: iterates Command keys in registration order; a lookup (`in`, `[]`, `get`)
    resolves a name as the console runs it, in the registry's current scope (Registry.resolve)."""

    def __init__(self, registry: Registry) -> None:
        self._registry = registry

    def __getitem__(self, name: str) -> Command:
        command = self._registry.resolve(name, self._registry.scope)
        if command is None:
            raise KeyError(name)
        return command

    def __iter__(self) -> Iterator[str]:
        return iter(self._registry._by_key)

    def __len__(self) -> int:
        return len(self._registry._by_key)


class Registry:
    """Typing a name is never ambiguous: global commands, cvars and aliases have names of their own, and a
    command scoped to a workspace shares its bare name only with other workspaces' commands, resolved by
    the current workspace (`scope`). `workspace:name` names a scoped command exactly."""

    def __init__(self) -> None:
        self._by_key: dict[str, Command] = {}
        self._first: dict[str, str] = {}  # a scoped command's bare name -> the key that registered it first
        self.commands = CommandTable(self)
        self.cvars: dict[str, Cvar] = {}
        self.aliases: dict[str, str] = {}
        self.cvar_changes = 0  # counts every cvar change: hosts redraw when it moves
        self.scope: str | None = None  # the current workspace: the editor sets it when it switches

    def command(self, name: str, spec: str = "", help: str = "", completer=None, recorded: bool = True,
                quiet: bool = False, scope: str | None = None):
        """Decorator: register `handler` under `name` with an argument spec like 'x:float [y:int]'."""

        def register(handler):
            self.add_command(Command(name, handler, parse_params(spec), help, completer, recorded, quiet, scope))
            return handler

        return register

    def scoped(self, scope: str) -> ScopedRegistry:
        """The registry as a workspace's command module uses it: its commands are scoped to `scope`."""
        return ScopedRegistry(self, scope)

    def add_command(self, cmd: Command) -> Command:
        if cmd.scope is None:
            self._claim(cmd.name)
        else:
            self._claim_scoped(cmd)
            self._first.setdefault(cmd.name, cmd.key)
        self._by_key[cmd.key] = cmd
        return cmd

    def resolve(self, name: str, scope: str | None) -> Command | None:
        """The command `name` runs in workspace `scope`: an exact key (a global name or `workspace:name`);
        else that workspace's own command of the name; else the one of the workspace that registered the
        name first, so a name keeps the meaning it had before other workspaces took it up."""
        command = self._by_key.get(name)
        if command is None and scope is not None:
            command = self._by_key.get(f"{scope}:{name}")
        if command is None and name in self._first:
            command = self._by_key[self._first[name]]
        return command

    def add_cvar(self, cvar: Cvar) -> Cvar:
        """Register a cvar; one that `set` made earlier (a config ran first) hands over its value."""
        old = self.cvars.get(cvar.name)
        if old is not None and old.user_created:
            try:
                cvar.value = cvar.parse(old.text())
            except CommandError:
                pass  # the text does not fit the real type: the default stands
        else:
            self._claim(cvar.name)
        cvar.on_change.append(self._count_change)
        self.cvars[cvar.name] = cvar
        self.cvar_changes += 1
        return cvar

    def _count_change(self, _cvar: Cvar) -> None:
        self.cvar_changes += 1

    def set_alias(self, name: str, text: str) -> None:
        check_text(f"alias {name}", text)
        if name not in self.aliases:
            self._claim(name)
        self.aliases[name] = text

    def names(self, qualified: bool = False) -> list[str]:
        """What Tab completes: global names, cvars, aliases and scoped commands' bare names; `qualified`
        (a ':' was typed) adds every `workspace:name`."""
        names = [*self.cvars, *self.aliases, *self._first]
        names += [key for key, command in self._by_key.items() if command.scope is None or qualified]
        return sorted(names)

    def _claim(self, name: str) -> None:
        """A global command's, cvar's or alias's name: unused, and no workspace's command's bare name."""
        _check_name(name)
        if name in self._by_key or name in self._first or name in self.cvars or name in self.aliases:
            raise ValueError(f"console name {name!r} is already registered")

    def _claim_scoped(self, cmd: Command) -> None:
        """A workspace's command: its bare name may repeat in other workspaces but names no global command,
        cvar or alias (a bare name would be ambiguous), and its key is registered once."""
        _check_name(cmd.name)
        _check_name(cmd.scope)
        if ":" in cmd.name or ":" in cmd.scope:
            raise ValueError(f"bad console name {cmd.key!r}: ':' separates the workspace from the name")
        for name in (cmd.name, cmd.key):  # a key without ':' in the table is a global command's
            if name in self._by_key or name in self.cvars or name in self.aliases:
                raise ValueError(f"console name {name!r} is already registered")


def _check_name(name: str) -> None:
    if not name or any(c.isspace() for c in name) or name[0] in "\"';" or ";" in name or _CONTROL.search(name):
        raise ValueError(f"bad console name {name!r}")


class ScopedRegistry:
    """`registry.scoped("volume")`: `command` registers commands scoped to that workspace; everything
    else (cvars, aliases, lookups) is the registry's own."""

    def __init__(self, registry: Registry, scope: str) -> None:
        self._registry, self._scope = registry, scope  # `scope` itself reads the registry's (the current one)

    def command(self, name: str, spec: str = "", help: str = "", completer=None, recorded: bool = True,
                quiet: bool = False):
        return self._registry.command(name, spec, help, completer, recorded, quiet, scope=self._scope)

    def __getattr__(self, attribute: str):
        return getattr(self._registry, attribute)
