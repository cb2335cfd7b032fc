"""The console's own commands: the Quake set (cvars, aliases, binds, configs, log) and Lua."""
from __future__ import annotations

from dataclasses import dataclass
from functools import partial

from app.console import files
from app.console.binds import KEYS, Binds
from app.console.command_set import CommandSet, Context
from app.console.console import Console, Origin
from app.console.lua import LuaScripting
from app.console.budget import DEFAULT_SECONDS
from app.console.quoting import join, quote
from app.console.registry import SCRIPTS, USER, CommandError, Cvar, Reported, check_new_name
from app.console.text import count
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes

MAX_CONFIG_BYTES = 1 << 20  # a config runs at most MAX_EXPANDED commands anyway


@dataclass(frozen=True)
class ConsoleParts:
    """What the console's own commands reach besides the console: the key bindings and the Lua runtime."""
    binds: Binds
    lua: LuaScripting


COMMANDS = CommandSet(None)
Ctx = Context[ConsoleParts]


def _infer(text: str) -> type:
    """Tex3Dtrace's variables take their type from the content: int, float or text."""
    for kind in (int, float):
        try:
            kind(text)
            return kind
        except ValueError:
            pass
    return str


def config_lines(console: Console, binds: Binds) -> list[str]:
    """What writeconfig saves: the user's own archived cvars, binds and aliases, as commands, each word quoted by
    the one function that the console reads back whole (registry.quote). What scripts, demos and configs set
    lasts the session and is never written here (Cvar.kept, Binds.kept, Registry.kept_aliases)."""
    reg = console.registry
    lines = [c.assignment(kept=True) for _name, c in sorted(reg.cvars.items()) if c.archive]
    lines += ["unbindall", *binds.lines(kept=True)]  # the whole set: a removed default stays removed
    lines += [f"alias {quote(name)} {quote(text)}" for name, text in sorted(reg.kept_aliases.items())]
    return lines


def exec_file(console: Console, name: str, trusted: bool = False) -> bool:
    """Run a .cfg line by line; a failing line is reported with its place and the rest still runs. Untrusted (a
    config someone may have sent) unless `trusted`: the editor's own start configs (the shipped ones, and the
    user's config.cfg, which only writeconfig writes)."""
    try:
        path = files.find(name, console)
    except CommandError as exc:
        console.error(f"exec: {exc}")
        return False
    if path is None:
        console.error(f"exec: cannot find {name}")
        return False
    try:
        text = read_regular_bytes(path, MAX_CONFIG_BYTES).decode("utf-8")
    except OSError as exc:
        console.error(f"exec: cannot read {path}: {exc.strerror}")
        return False
    except UnicodeDecodeError as exc:
        console.error(f"exec: cannot read {path}: not UTF-8 text (byte {exc.start})")
        return False
    origin = None if trusted else Origin("config", path.parent)
    return console.run_lines(text.splitlines(), f"exec {path.name}", origin,
                             lambda number, line: console.error(f"exec: {path.name}:{number}: {line.strip()}"))


def register(console: Console, binds: Binds) -> LuaScripting:
    """The console's commands, the scr_budget cvar and the runner of .lua files; returns the Lua runtime."""
    reg = console.registry
    lua = LuaScripting(console)
    ctx = Ctx(console, ConsoleParts(binds, lua))
    console.file_policy = lambda kind, name: files.resolve(console, kind, name)
    budget = reg.add_cvar(Cvar("scr_budget", float, DEFAULT_SECONDS, "Seconds one demo, config or script may spend "
                               "running, with all it runs inside (scripts, aliases, waits); then it stops",
                               min=0.1, max=3600.0, archive=True, allow=USER))
    budget.on_change.append(lambda cvar: setattr(console, "budget_seconds", cvar.value))
    console.file_runners[".lua"] = partial(run_lua, ctx)
    COMMANDS.register(reg, ctx)
    return lua


def run_lua(ctx: Ctx, name: str) -> bool:
    """Run a Lua script untrusted, its edits one undo step, within what the run it is part of has left."""
    console, lua = ctx.console, ctx.state.lua
    try:
        path = files.find(name, console)
    except CommandError as exc:
        console.error(f"lua: {exc}")
        return False
    if path is None:
        console.error(f"lua: cannot find {name}")
        return False
    with console.batch(), console.untrusted("lua", path.parent):  # a script's edits undo as one
        limit = lua.time_limit
        lua.time_limit = min(limit, console.budget.remaining())  # within what its run has left
        try:
            return lua.run_file(path)
        finally:
            lua.time_limit = limit


# ---- completers ------------------------------------------------------------------------------------

def _names(ctx: Ctx, prefix: str) -> list[str]:
    return [n for n in ctx.console.registry.names(":" in prefix) if n.startswith(prefix)]


def _cvar_names(ctx: Ctx, prefix: str) -> list[str]:
    return [n for n in sorted(ctx.console.registry.cvars) if n.startswith(prefix)]


def _key_names(ctx: Ctx, prefix: str) -> list[str]:
    return sorted(k for k in KEYS if k.lower().startswith(prefix.lower()))


# ---- cvars -----------------------------------------------------------------------------------------

def _set_cvar(ctx: Ctx, name: str, value: str, archive: bool) -> None:
    """A script's value lasts the session: it never archives a cvar nor changes the value config.cfg keeps."""
    console, reg = ctx.console, ctx.console.registry
    cvar = reg.cvars.get(name)
    archive = archive and console.trusted
    if cvar is None:
        if name in reg.commands or name in reg.aliases:
            raise CommandError(f"{name!r} is a command, not a cvar")
        check_new_name("a cvar", name)
        reg.add_cvar(Cvar(name, _infer(value), value, archive=archive, user_created=True))
        return
    if cvar.allow != SCRIPTS and not console.trusted:
        raise CommandError(f"{console.origins[-1].who()} may not set {name}: it is the user's own")
    cvar.set(value, trusted=console.trusted)
    cvar.archive = cvar.archive or archive


@COMMANDS.command("set", "name value", "Set a cvar, creating it (typed by its value) if new", completer=_cvar_names,
                  allow=SCRIPTS)
def set_(ctx: Ctx, name: str, value: str) -> None:
    _set_cvar(ctx, name, value, archive=False)


@COMMANDS.command("seta", "name value", "Set a cvar and keep it in the user config (archive)",
                  completer=_cvar_names, allow=SCRIPTS)
def seta(ctx: Ctx, name: str, value: str) -> None:
    _set_cvar(ctx, name, value, archive=True)


def _cvar(ctx: Ctx, name: str) -> Cvar:
    cvars = ctx.console.registry.cvars
    if name not in cvars:
        raise CommandError(f"no cvar {name!r}")
    return cvars[name]


@COMMANDS.command("reset", "name", "Set a cvar back to its default", completer=_cvar_names, allow=SCRIPTS)
def reset(ctx: Ctx, name: str) -> None:
    _cvar(ctx, name).set(str(_cvar(ctx, name).default))


@COMMANDS.command("toggle", "name [values...]", "Flip a bool cvar, or step it through the values given",
                  completer=_cvar_names, allow=SCRIPTS)
def toggle(ctx: Ctx, name: str, values: list[str] | None = None) -> None:
    c = _cvar(ctx, name)
    if not values:
        if c.type is not bool:
            raise CommandError(f"{name} is a {c.type.__name__}; give the values to step through")
        c.set("0" if c.value else "1")
        return
    parsed = [c.parse(v) for v in values]
    nxt = parsed[(parsed.index(c.value) + 1) % len(parsed)] if c.value in parsed else parsed[0]
    c.set(values[parsed.index(nxt)])


# ---- listing and help ------------------------------------------------------------------------------

def _listing(ctx: Ctx, lines: list[str], noun: str) -> None:
    for line in lines:
        ctx.console.print(line)
    ctx.console.print(count(len(lines), noun))


@COMMANDS.command("cvarlist", "[prefix]", "List cvars (A = archived to the user config)", recorded=False,
                  allow=SCRIPTS)
def cvarlist(ctx: Ctx, prefix: str = "") -> None:
    _listing(ctx, [f"{'A' if c.archive else ' '} {c.name:<22} {c.text():<12} {c.type.__name__:<5} {c.help}"
                   for name, c in sorted(ctx.console.registry.cvars.items()) if name.startswith(prefix)], "cvar")


@COMMANDS.command("cmdlist", "[prefix]", "List commands ([workspace] marks one workspace's own)", recorded=False,
                  allow=SCRIPTS)
def cmdlist(ctx: Ctx, prefix: str = "") -> None:
    # by bare name, so each workspace's command of a name stands beside the others; the prefix matches
    # the bare name or `workspace:name`
    commands = ctx.console.registry.commands
    shown = sorted((c for key, c in commands.items() if key.startswith(prefix) or c.name.startswith(prefix)),
                   key=lambda c: (c.name, c.scope or ""))
    _listing(ctx, [f"{c.label():<44} {c.help}" for c in shown], "command")


@COMMANDS.command("help", "[name]", "Describe a command, cvar or alias; alone, say how to find them",
                  completer=_names, recorded=False, allow=SCRIPTS)
def help_(ctx: Ctx, name: str | None = None) -> None:
    console, reg = ctx.console, ctx.console.registry
    if name is None:
        console.print("cmdlist [prefix] lists commands, cvarlist [prefix] cvars; help <name> describes one; "
                      "Tab completes.")
    elif name in reg.commands:
        command = reg.commands[name]
        console.print(f"{command.label()}: {command.help} (who may run it: {command.capability()})")
    elif name in reg.cvars:
        c = reg.cvars[name]
        bounds = f", {c.min:g}..{c.max:g}" if c.min is not None and c.max is not None else ""
        bounds += f", one of {'|'.join(map(str, c.choices))}" if c.choices else ""
        console.print(f"{name} ({c.type.__name__}{bounds}, now {c.text()}, default {c.default}): {c.help}")
    elif name in reg.aliases:
        console.print(f"alias {name} {quote(reg.aliases[name])}")
    else:
        raise CommandError(f"no command, cvar or alias {name!r}")


# ---- the log ---------------------------------------------------------------------------------------

@COMMANDS.command("echo", "[words...]", "Print the words", recorded=False, allow=SCRIPTS)
def echo(ctx: Ctx, words: list[str]) -> None:
    ctx.console.print(" ".join(words))


@COMMANDS.command("clear", "", "Clear the console log", recorded=False, allow=SCRIPTS)
def clear(ctx: Ctx) -> None:
    ctx.console.clear()


@COMMANDS.command("condump", "file:write", "Write the console log to a file", recorded=False, allow=SCRIPTS)
def condump(ctx: Ctx, path: str) -> None:
    log = ctx.console.log
    try:
        write_text(path, "".join(f"{line.text}\n" for line in log))
    except OSError as exc:
        raise CommandError(f"cannot write {path}: {exc.strerror}") from None
    ctx.console.print(f"dumped {count(len(log), 'line')} to {path}")


# ---- aliases and configs ---------------------------------------------------------------------------

@COMMANDS.command("alias", "[name] [commands...]", "Name a command line; alone, list the aliases", completer=_names,
                  allow=SCRIPTS)
def alias(ctx: Ctx, name: str | None = None, words: list[str] | None = None) -> None:
    console, aliases = ctx.console, ctx.console.registry.aliases
    text = _joined(words or [])
    if name is None:
        for n, t in sorted(aliases.items()):
            console.print(f"{n}: {t}")
    elif text is None:
        if name not in aliases:
            raise CommandError(f"no alias {name!r}")
        console.print(f"{name}: {aliases[name]}")
    else:
        console.registry.set_alias(name, text, trusted=console.trusted)


def _fail_unless(ok: bool) -> None:
    if not ok:
        raise Reported()


@COMMANDS.command("exec", "file", "Run a config file (.cfg) line by line", recorded=False,
                  completer=lambda ctx, p: files.complete(p, (".cfg",)), allow=SCRIPTS)
def exec_(ctx: Ctx, name: str) -> None:
    _fail_unless(exec_file(ctx.console, name))


@COMMANDS.command("writeconfig", "[file]", "Save archived cvars, binds and aliases (default: the user config)",
                  recorded=False)
def writeconfig(ctx: Ctx, path: str | None = None) -> None:
    target = files.writable(ctx.console, path) if path else files.user_config()
    try:
        write_text(target, "// written by Shadelab: archived cvars, binds, aliases\n"
                   + "".join(f"{line}\n" for line in config_lines(ctx.console, ctx.state.binds)))
    except OSError as exc:
        raise CommandError(f"cannot write {target}: {exc.strerror}") from None
    ctx.console.print(f"wrote {target}")


# ---- binds -----------------------------------------------------------------------------------------

@COMMANDS.command("bind", "key [command...]", "Bind a key (scope:key for one workspace) to a command line; "
                  "alone, show the binding", completer=_key_names, allow=SCRIPTS)
def bind(ctx: Ctx, key: str, words: list[str]) -> None:
    command = _joined(words)
    if command is None:
        ctx.console.print(ctx.state.binds.describe(ctx.console.registry.scope or "", key))
    else:
        ctx.state.binds.bind(key, command, trusted=ctx.console.trusted)


@COMMANDS.command("unbindall", "", "Remove every key binding", allow=SCRIPTS)
def unbindall(ctx: Ctx) -> None:
    ctx.state.binds.clear(trusted=ctx.console.trusted)


@COMMANDS.command("unbind", "key", "Remove a key binding", completer=_key_names, allow=SCRIPTS)
def unbind(ctx: Ctx, key: str) -> None:
    if not ctx.state.binds.unbind(key, trusted=ctx.console.trusted):
        raise CommandError(f"{key} is not bound")


@COMMANDS.command("bindlist", "", "List the key bindings", recorded=False, allow=SCRIPTS)
def bindlist(ctx: Ctx) -> None:
    for line in ctx.state.binds.lines():
        ctx.console.print(line)


# ---- Lua and leaving -------------------------------------------------------------------------------

@COMMANDS.command("lua", "file", "Run a Lua script (sandboxed); a bare name.lua does the same", recorded=False,
                  completer=lambda ctx, p: files.complete(p, (".lua",)), allow=SCRIPTS)
def lua_(ctx: Ctx, name: str) -> None:
    _fail_unless(run_lua(ctx, name))


@COMMANDS.command("quit", "", "Leave Shadelab", recorded=False)
def quit_(ctx: Ctx) -> None:
    ctx.console.request_quit()


def _joined(words: list[str]) -> str | None:
    """`bind w snow.step 0.25` and `bind w "snow.step 0.25"` mean the same, as in Quake."""
    if not words:
        return None
    return words[0] if len(words) == 1 else join(words)
