"""The console's own commands: the Quake set (cvars, aliases, binds, configs, log) and Lua."""
from __future__ import annotations

from app.console import files
from app.console.binds import KEYS, Binds
from app.console.console import Console, Origin
from app.console.lua import LuaScripting
from app.console.quoting import join, quote
from app.console.registry import CommandError, Cvar, Reported
from app.console.text import count
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes

MAX_CONFIG_BYTES = 1 << 20  # a config runs at most MAX_EXPANDED commands anyway


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
    """What writeconfig saves: archived cvars, binds and aliases, as commands."""
    reg = console.registry
    lines = [c.assignment() for _name, c in sorted(reg.cvars.items()) if c.archive]
    lines += ["unbindall", *binds.lines()]  # the saved binds are the whole set: a removed default stays removed
    lines += [f"alias {name} {quote(text)}" for name, text in sorted(reg.aliases.items())]
    return lines


def exec_file(console: Console, name: str) -> bool:
    """Run a .cfg line by line; a failing line is reported with its place and the rest still runs."""
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
    return console.run_lines(text.splitlines(), f"exec {path.name}", Origin("config", path.parent),
                             lambda number, line: console.error(f"exec: {path.name}:{number}: {line.strip()}"))


def register(console: Console, binds: Binds) -> LuaScripting:
    reg = console.registry
    lua = LuaScripting(console)

    def run_lua(name: str) -> bool:
        try:
            path = files.find(name, console)
        except CommandError as exc:
            console.error(f"lua: {exc}")
            return False
        if path is None:
            console.error(f"lua: cannot find {name}")
            return False
        with console.batch(), console.untrusted("lua", path.parent):  # a script's edits undo as one
            return lua.run_file(path)

    console.file_runners[".lua"] = run_lua
    names = lambda prefix: [n for n in reg.names(":" in prefix) if n.startswith(prefix)]  # noqa: E731
    cvar_names = lambda prefix: [n for n in sorted(reg.cvars) if n.startswith(prefix)]  # noqa: E731
    key_names = lambda prefix: sorted(k for k in KEYS if k.lower().startswith(prefix.lower()))  # noqa: E731

    def fail_unless(ok: bool) -> None:
        if not ok:
            raise Reported()

    def set_cvar(name: str, value: str, archive: bool) -> None:
        cvar = reg.cvars.get(name)
        if cvar is None:
            if name in reg.commands or name in reg.aliases:
                raise CommandError(f"{name!r} is a command, not a cvar")
            reg.add_cvar(Cvar(name, _infer(value), value, archive=archive, user_created=True))
            return
        cvar.set(value)
        cvar.archive = cvar.archive or archive

    @reg.command("set", "name value", "Set a cvar, creating it (typed by its value) if new", completer=cvar_names)
    def set_(name: str, value: str) -> None:
        set_cvar(name, value, archive=False)

    @reg.command("seta", "name value", "Set a cvar and keep it in the user config (archive)", completer=cvar_names)
    def seta(name: str, value: str) -> None:
        set_cvar(name, value, archive=True)

    def cvar(name: str) -> Cvar:
        if name not in reg.cvars:
            raise CommandError(f"no cvar {name!r}")
        return reg.cvars[name]

    @reg.command("reset", "name", "Set a cvar back to its default", completer=cvar_names)
    def reset(name: str) -> None:
        cvar(name).set(str(cvar(name).default))

    @reg.command("toggle", "name [values...]", "Flip a bool cvar, or step it through the values given",
                 completer=cvar_names)
    def toggle(name: str, values: list[str] | None = None) -> None:
        c = cvar(name)
        if not values:
            if c.type is not bool:
                raise CommandError(f"{name} is a {c.type.__name__}; give the values to step through")
            c.set("0" if c.value else "1")
            return
        parsed = [c.parse(v) for v in values]
        nxt = parsed[(parsed.index(c.value) + 1) % len(parsed)] if c.value in parsed else parsed[0]
        c.set(values[parsed.index(nxt)])

    def listing(lines: list[str], noun: str) -> None:
        for line in lines:
            console.print(line)
        console.print(count(len(lines), noun))

    @reg.command("cvarlist", "[prefix]", "List cvars (A = archived to the user config)", recorded=False)
    def cvarlist(prefix: str = "") -> None:
        listing([f"{'A' if c.archive else ' '} {c.name:<22} {c.text():<12} {c.type.__name__:<5} {c.help}"
                 for name, c in sorted(reg.cvars.items()) if name.startswith(prefix)], "cvar")

    @reg.command("cmdlist", "[prefix]", "List commands ([workspace] marks one workspace's own)", recorded=False)
    def cmdlist(prefix: str = "") -> None:
        # by bare name, so each workspace's command of a name stands beside the others; the prefix matches
        # the bare name or `workspace:name`
        shown = sorted((c for key, c in reg.commands.items() if key.startswith(prefix) or c.name.startswith(prefix)),
                       key=lambda c: (c.name, c.scope or ""))
        listing([f"{c.label():<44} {c.help}" for c in shown], "command")

    @reg.command("help", "[name]", "Describe a command, cvar or alias; alone, say how to find them",
                 completer=names, recorded=False)
    def help_(name: str | None = None) -> None:
        if name is None:
            console.print("cmdlist [prefix] lists commands, cvarlist [prefix] cvars; help <name> describes one; "
                          "Tab completes.")
        elif name in reg.commands:
            console.print(f"{reg.commands[name].label()}: {reg.commands[name].help}")
        elif name in reg.cvars:
            c = reg.cvars[name]
            bounds = f", {c.min:g}..{c.max:g}" if c.min is not None and c.max is not None else ""
            bounds += f", one of {'|'.join(map(str, c.choices))}" if c.choices else ""
            console.print(f"{name} ({c.type.__name__}{bounds}, now {c.text()}, default {c.default}): {c.help}")
        elif name in reg.aliases:
            console.print(f"alias {name} {quote(reg.aliases[name])}")
        else:
            raise CommandError(f"no command, cvar or alias {name!r}")

    @reg.command("echo", "[words...]", "Print the words", recorded=False)
    def echo(words: list[str]) -> None:
        console.print(" ".join(words))

    @reg.command("clear", "", "Clear the console log", recorded=False)
    def clear() -> None:
        console.clear()

    @reg.command("condump", "file", "Write the console log to a file", recorded=False)
    def condump(path: str) -> None:
        target = files.writable(console, path)
        try:
            write_text(target, "".join(f"{line.text}\n" for line in console.log))
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {exc.strerror}") from None
        console.print(f"dumped {count(len(console.log), 'line')} to {target}")

    @reg.command("alias", "[name] [commands...]", "Name a command line; alone, list the aliases", completer=names)
    def alias(name: str | None = None, words: list[str] | None = None) -> None:
        text = _joined(words or [])
        if name is None:
            for n, t in sorted(reg.aliases.items()):
                console.print(f"{n}: {t}")
        elif text is None:
            if name not in reg.aliases:
                raise CommandError(f"no alias {name!r}")
            console.print(f"{name}: {reg.aliases[name]}")
        else:
            reg.set_alias(name, text)

    @reg.command("exec", "file", "Run a config file (.cfg) line by line", recorded=False,
                 completer=lambda p: files.complete(p, (".cfg",)))
    def exec_(name: str) -> None:
        fail_unless(exec_file(console, name))

    @reg.command("writeconfig", "[file]", "Save archived cvars, binds and aliases (default: the user config)",
                 recorded=False)
    def writeconfig(path: str | None = None) -> None:
        target = files.writable(console, path) if path else files.user_config()
        try:
            write_text(target, "// written by Shadelab: archived cvars, binds, aliases\n"
                       + "".join(f"{line}\n" for line in config_lines(console, binds)))
        except OSError as exc:
            raise CommandError(f"cannot write {target}: {exc.strerror}") from None
        console.print(f"wrote {target}")

    @reg.command("bind", "key [command...]", "Bind a key (scope:key for one workspace) to a command line; "
                 "alone, show the binding", completer=key_names)
    def bind(key: str, words: list[str]) -> None:
        command = _joined(words)
        if command is None:
            console.print(binds.describe(reg.scope or "", key))
        else:
            binds.bind(key, command)

    @reg.command("unbindall", "", "Remove every key binding")
    def unbindall() -> None:
        binds.table.clear()

    @reg.command("unbind", "key", "Remove a key binding", completer=key_names)
    def unbind(key: str) -> None:
        if not binds.unbind(key):
            raise CommandError(f"{key} is not bound")

    @reg.command("bindlist", "", "List the key bindings", recorded=False)
    def bindlist() -> None:
        for line in binds.lines():
            console.print(line)

    @reg.command("lua", "file", "Run a Lua script (sandboxed); a bare name.lua does the same", recorded=False,
                 completer=lambda p: files.complete(p, (".lua",)))
    def lua_(name: str) -> None:
        fail_unless(run_lua(name))

    @reg.command("quit", "", "Leave Shadelab", recorded=False)
    def quit_() -> None:
        console.request_quit()

    return lua


def _joined(words: list[str]) -> str | None:
    """`bind w snow.step 0.25` and `bind w "snow.step 0.25"` mean the same, as in Quake."""
    if not words:
        return None
    return words[0] if len(words) == 1 else join(words)
