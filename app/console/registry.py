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


# The names a user or script may give a new alias or cvar, or a bind's workspace: a letter or underscore, then
# letters, digits, underscores and dots. Anything else could come back from config.cfg as more than one word.
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.]{0,63}")


def check_new_name(what: str, name: str) -> str:
    if not NAME.fullmatch(name):
        raise ValueError(f"{what} {name!r} is no name: a letter or _, then letters, digits, _ and . (64 at most)")
    return name


def check_text(what: str, text: str) -> str:
    """Refuse console text that holds a control character (a newline, say); else return it."""
    found = _CONTROL.search(text)
    if found:
        raise CommandError(f"{what} may not hold control characters (found {found.group()!r})")
    return text


# Who may run a command or set a cvar (docs/architecture.md rule 6), declared where it is registered and enforced by
# the console in one place. USER: only the user's own lines (typed, a menu, a dialog); the default, so a new command
# is safe until someone decides otherwise. SCRIPTS: scripts, demos, configs, binds and aliases may run it too, their
# file parameters confined by the file policy (app/console/files.py).
USER, SCRIPTS = "user", "scripts"
ALLOWED = {USER: "the user only", SCRIPTS: "scripts too"}
FILE_KINDS = ("read", "write")  # a parameter naming a file the command reads, or one it writes


@dataclass(frozen=True)
class Param:
    name: str
    type: type = str  # str, int or float
    optional: bool = False
    variadic: bool = False  # takes every remaining argument (a list)
    file: str | None = None  # "read" or "write": a file, resolved by the console's file policy before the handler

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
        file = kind if kind in FILE_KINDS else None
        params.append(Param(name, str if file else {"": str, "str": str, "int": int, "float": float}[kind], optional,
                            variadic, file))
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
    allow: str = USER  # who may run it: USER or SCRIPTS

    @property
    def key(self) -> str:
        """The name that always means this command: `workspace:name` if scoped."""
        return f"{self.scope}:{self.name}" if self.scope else self.name

    def label(self) -> str:
        """The usage as help and cmdlist show it: `[volume] sample <name> [<size>]`."""
        return f"[{self.scope}] {self.usage()}" if self.scope else self.usage()

    def usage(self) -> str:
        return " ".join([self.name, *(p.usage() for p in self.params)])

    def capability(self) -> str:
        """What untrusted content may do with it, in words (help and docs/console.md's table)."""
        if self.allow != SCRIPTS:
            return "the user only"
        kinds = {p.file for p in self.params if p.file}
        notes = [note for kind, note in (("read", "reads from the sandbox, the resources or beside the script"),
                                         ("write", "writes into the sandbox")) if kind in kinds]
        return "scripts too" + (f" ({'; '.join(notes)})" if notes else "")

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
    allow: str = SCRIPTS  # who may set it: a setting a demo or script may change, unless declared USER

    def __post_init__(self) -> None:
        self.value = self.parse(str(self.default))
        self.kept = self.value  # the value the user gave: what config.cfg keeps (a script's lasts the session)

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

    def set(self, text: str, trusted: bool = True) -> None:
        """Validate and set; `trusted`: the user's own value, which config.cfg keeps."""
        value = self.parse(text)
        if trusted:
            self.kept = value
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

    def assignment(self, kept: bool = False) -> str:
        """The command that gives it this value again (a demo's opening lines), or the user's own (`kept`: configs)."""
        value = self.serialise(self.kept if kept else self.value)
        return f"{'seta' if self.archive else 'set'} {self.name} {quote(value)}"

    def serialise(self, value: Any = None) -> str:
        """For files, demos and digests: floats exact (repr round-trips)."""
        value = self.value if value is None else value
        if self.type is bool:
            return "1" if value else "0"
        return repr(value) if self.type is float else str(value)


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
        self.kept_aliases: dict[str, str] = {}  # those the user made, which config.cfg keeps (a script's: the session)
        self.cvar_changes = 0  # counts every cvar change: hosts redraw when it moves
        self.scope: str | None = None  # the current workspace: the editor sets it when it switches

    def command(self, name: str, spec: str = "", help: str = "", completer=None, recorded: bool = True,
                quiet: bool = False, scope: str | None = None, allow: str = USER):
        """Decorator: register `handler` under `name` with an argument spec like 'x:float [y:int] path:write', and
        who may run it (`allow`, USER unless declared)."""
        if allow not in ALLOWED:
            raise ValueError(f"{name}: allow must be one of {', '.join(ALLOWED)}, not {allow!r}")

        def register(handler):
            self.add_command(Command(name, handler, parse_params(spec), help, completer, recorded, quiet, scope,
                                     allow))
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

    def set_alias(self, name: str, text: str, trusted: bool = True) -> None:
        check_text(f"alias {name}", text)
        if name not in self.aliases:
            check_new_name("an alias", name)
            self._claim(name)
        self.aliases[name] = text
        if trusted:
            self.kept_aliases[name] = text

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
                quiet: bool = False, allow: str = USER):
        return self._registry.command(name, spec, help, completer, recorded, quiet, scope=self._scope, allow=allow)

    def __getattr__(self, attribute: str):
        return getattr(self._registry, attribute)
