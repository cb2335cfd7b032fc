"""Commands and cvars in one registry, as the Quake console and Tex3Dtrace kept them. No Qt."""
from __future__ import annotations

import math
import re
import shlex
from dataclasses import dataclass, field
from typing import Any, Callable


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
        """For people: floats shortened (%g)."""
        if self.type is float:
            return f"{self.value:g}"
        return self.serialise()

    def assignment(self) -> str:
        """The command that gives it this value again (configs, a demo's opening lines)."""
        return f"{'seta' if self.archive else 'set'} {self.name} {shlex.quote(self.serialise())}"

    def serialise(self) -> str:
        """For files, demos and digests: floats exact (repr round-trips)."""
        if self.type is bool:
            return "1" if self.value else "0"
        return repr(self.value) if self.type is float else str(self.value)


class Registry:
    """Names are unique across commands and cvars, so typing a name is never ambiguous."""

    def __init__(self) -> None:
        self.commands: dict[str, Command] = {}
        self.cvars: dict[str, Cvar] = {}
        self.aliases: dict[str, str] = {}
        self.cvar_changes = 0  # counts every cvar change: hosts redraw when it moves

    def command(self, name: str, spec: str = "", help: str = "", completer=None, recorded: bool = True,
                quiet: bool = False):
        """Decorator: register `handler` under `name` with an argument spec like 'x:float [y:int]'."""

        def register(handler):
            self.add_command(Command(name, handler, parse_params(spec), help, completer, recorded, quiet))
            return handler

        return register

    def add_command(self, cmd: Command) -> Command:
        self._claim(cmd.name)
        self.commands[cmd.name] = cmd
        return cmd

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

    def names(self) -> list[str]:
        return sorted([*self.commands, *self.cvars, *self.aliases])

    def _claim(self, name: str) -> None:
        if not name or any(c.isspace() for c in name) or name[0] in "\"';" or ";" in name or _CONTROL.search(name):
            raise ValueError(f"bad console name {name!r}")
        if name in self.commands or name in self.cvars or name in self.aliases:
            raise ValueError(f"console name {name!r} is already registered")
