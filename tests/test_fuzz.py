"""Hypothesis fuzzing of what a user may be handed: scene JSON files (2D lighting and snowflake), demos
and .cfg files. Whatever the input: no crash, no handler's "internal error", a refusal changes nothing
(digest), and memory stays bounded. EXAMPLES inputs each (3 to 8 s a test on 2 cores; FUZZ_N=... changes it)."""
import json
import os
import tracemalloc
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from app.console import demo
from app.console.builtins import exec_file
from app.console.demo import VirtualClock
from app.editor import Editor
from app.model.workspaces import names
from app.resources import SCENES

EXAMPLES = int(os.environ.get("FUZZ_N", 1000))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
PEAK_BYTES = 64 << 20  # a small file must never cost more than this to refuse or load


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """A working folder with a FIFO to point scenes at; files the fuzz writes land here too."""
    path = tmp_path_factory.mktemp("fuzz")
    os.mkfifo(path / "pipe.png")
    old = os.getcwd()
    os.chdir(path)
    yield path
    os.chdir(old)


@pytest.fixture(scope="module")
def editor(folder):
    """One editor for every example: building one costs more than most examples."""
    e = Editor(clock=VirtualClock(), configs=False)
    e.internal_errors = []
    e.console.log_listeners.append(lambda line: "internal error" in line.text and e.internal_errors.append(line.text))
    return e


def no_internal_error(editor) -> None:
    assert not editor.internal_errors, editor.internal_errors[0]


# ---- scene files -------------------------------------------------------------------------------------

SPECIAL_STRINGS = ["/dev/zero", "/", "pipe.png", "builtin:tiles", "builtin:flame", "builtin:nope", "", "none",
                   "point", "textured", "solid", "x" * 2000]
leaves = (st.none() | st.booleans() | st.integers(-10**45, 10**45) | st.floats() | st.sampled_from(SPECIAL_STRINGS)
          | st.text(max_size=12))
json_values = st.recursive(leaves, lambda inner: st.lists(inner, max_size=6)
                           | st.dictionaries(st.text(max_size=8) | st.sampled_from(["x", "y", "kind", "points"]), inner,
                                             max_size=4), max_leaves=24)


def paths(node, at=()):
    """Every place in a JSON tree, as key tuples, the root first."""
    yield at
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        yield from paths(child, (*at, key))


@st.composite
def mutated_tree(draw, original):
    """The original tree with a few places replaced by random JSON, deleted or repeated."""
    data = json.loads(json.dumps(original))
    for _ in range(draw(st.integers(1, 3))):
        where = draw(st.sampled_from(list(paths(data))))
        if not where:
            continue
        parent = data
        for key in where[:-1]:
            parent = parent[key]
        action = draw(st.sampled_from(["replace", "delete", "repeat"]))
        if action == "replace":
            parent[where[-1]] = draw(json_values)
        elif action == "delete":
            del parent[where[-1]]
        elif isinstance(parent, list):
            parent.extend([parent[where[-1]]] * draw(st.integers(1, 300)))
    return json.dumps(data).encode()


@st.composite
def mutated_bytes(draw, original: bytes):
    """The original bytes with a few bytes changed, dropped or inserted (brackets and quotes likely)."""
    data = bytearray(original)
    for _ in range(draw(st.integers(1, 6))):
        at = draw(st.integers(0, len(data)))
        byte = draw(st.sampled_from(b'[]{}",:0-e.9 \xff') | st.integers(0, 255))
        action = draw(st.sampled_from(["set", "drop", "insert"]))
        if action == "insert" or at == len(data):
            data[at:at] = bytes([byte]) * draw(st.sampled_from([1, 1, 2, 5000]))
        elif action == "set":
            data[at] = byte
        else:
            del data[at]
    return bytes(data)


SCENE_2D = json.loads((SCENES / "i_textured_light.json").read_text())
SCENE_2D["normal_map"] = "builtin:bumps"
SNOW = {"format": "shadelab.snowflake", "version": 1, "level": 3.5,
        "flakes": [{"x": 0.0, "y": 0.25, "radius": 0.5}, {"x": -1, "y": 2}]}


def scene_load_is_all_or_nothing(editor, folder, workspace: str, content: bytes) -> None:
    path = folder / "scene.json"
    path.write_bytes(content)
    assert editor.execute(f"workspace {workspace}")
    before = editor.digest()
    tracemalloc.start()
    try:
        ok = editor.execute(f"scene.load {path}")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    no_internal_error(editor)
    assert peak < PEAK_BYTES
    if not ok:
        assert editor.digest() == before
    elif workspace == "lighting2d":  # what loaded is what every frame relies on
        for light in editor.workspaces["lighting2d"].scene.lights:
            assert len(light.position) == len(light.origin) == len(light.scale) == 2 and len(light.color) == 3
            assert light.texture is None or isinstance(light.texture, str)


@pytest.mark.parametrize("workspace, original", [("lighting2d", SCENE_2D), ("snowflake", SNOW)])
@FUZZ
@given(data=st.data())
def test_fuzz_scene_files(editor, folder, workspace, original, data):
    content = data.draw(st.one_of(mutated_tree(original), mutated_bytes(json.dumps(original).encode())))
    scene_load_is_all_or_nothing(editor, folder, workspace, content)


# ---- demos and configs ---------------------------------------------------------------------------------

ints = st.integers(-3, 70).map(str) | st.sampled_from(["9999", "100000", "-100000", "10" * 30, "1.5", "x"])
floats = (st.floats(-500, 500).map(repr) | st.integers(-5, 5).map(str)
          | st.sampled_from(["1e308", "-1e308", "nan", "inf", "0", "-0", "1e-300"]))
small = st.integers(0, 12).map(str) | st.just("5000")
words = st.sampled_from(["x", "y", "z", "w", "point", "spot", "textured", "radius", "kind", "texture", "scale",
                         "rotation", "position", "enabled", "color", "builtin:flame", "builtin:tiles", "/dev/zero",
                         "pipe.png", "none", "exact", "magic", *names(), "cl_steps", "r_shadowMethod", "r_new"])
anything = st.text(alphabet=st.characters(codec="utf-8", exclude_categories=["Cs"]), max_size=10).map(repr)
# name -> arguments; lists repeat their strategy 0..8 times. File-writing commands are left out on purpose.
VOCABULARY = {
    "snow.add": [floats, floats, floats], "snow.move": [ints, floats, floats], "snow.remove": [ints],
    "snow.level": [floats], "snow.step": [floats], "snow.clear": [], "snow.view": [floats, floats, floats],
    "voxel": [ints] * 7, "slice": [words, ints], "slice.step": [ints], "pick": [ints] * 3,
    "stroke": [words, ints, ints, ints, ints, ints, ints, [ints]], "fill": [words, ints, ints, ints] + [ints] * 4,
    "new": [small] * 3, "rotate": [words], "sample": [st.just("coords3d"), st.sampled_from(["8", "9", "4"])],
    "brush.color": [ints] * 4, "mode": [ints], "orbit": [floats, floats], "light": [floats] * 3,
    "vol.background": [ints] * 3, "undo": [], "redo": [], "workspace": [words],
    "light.add": [words, floats, floats], "light.set": [ints, words, [floats | words]],
    "light.move": [ints, floats, floats], "light.remove": [ints], "hull.add": [[floats]],
    "hull.set": [ints, words, [floats]], "hull.move": [ints, floats, floats], "hull.points": [ints, [floats]],
    "hull.vertex": [ints, ints, floats, floats], "hull.insert": [ints, ints, floats, floats],
    "hull.delete": [ints, ints], "hull.remove": [ints], "lighting.clear": [], "ambient": [floats] * 3,
    "lighting.view": [floats] * 3, "lighting.background": [words], "lighting.normalmap": [words],
    "lighting.sample": [st.sampled_from(["a_penumbra_transition", "nope"])],
    "set": [words, words | floats], "seta": [words, ints], "cl_steps": [ints], "r_shadowMethod": [words],
    "wait": [ints], "alias": [words, st.just("'snow.step 1'")], "echo": [[words]], "digest": [],
}


@st.composite
def command_lines(draw):
    name = draw(st.sampled_from(sorted(VOCABULARY)))
    args = []
    for spec in VOCABULARY[name]:
        args += draw(st.lists(spec[0], max_size=8)) if isinstance(spec, list) else [draw(spec)]
    if draw(st.integers(0, 9)) == 0:  # now and then a stray word, or a second command on the line
        args.append(draw(anything | command_lines().map(lambda line: f"; {line}")))
    return " ".join([name, *args])


@st.composite
def demo_texts(draw):
    header = draw(st.sampled_from(["shadelab-demo 1"] * 8 + ["shadelab-demo 2", "demo", ""]))
    lines = draw(st.lists(command_lines(), max_size=8))
    times = sorted(draw(st.lists(st.floats(0, 3), min_size=len(lines), max_size=len(lines))))
    stamps = [f"{t:.3f}" for t in times]
    if stamps and draw(st.integers(0, 9)) == 0:  # now and then a time no host could wait for
        stamps[-1] = draw(st.sampled_from(["1e308", "nan", "-1", "86401", "soon"]))
    return "\n".join([header, *(f"{t} {line}" for t, line in zip(stamps, lines))]) + "\n"


@FUZZ
@given(text=demo_texts(), speed=st.sampled_from([1.0, 4.0, 0.5]))
def test_fuzz_demos(editor, text, speed):
    console, clock = editor.console, editor.demos.clock
    before = editor.digest()
    tracemalloc.start()
    try:
        try:
            events = demo.parse(text)
            demo.check(console, events, "fuzz", editor.demos.arg_checks)
        except demo.DemoError:
            assert editor.digest() == before  # refused before anything ran
            return
        player = demo.Player(console, clock, events, speed)
        while not player.done:
            clock.advance(0.25)
            player.update()
            console.frame()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
        console.waiting.clear()  # a `wait` left over must not run in the next example
    no_internal_error(editor)
    assert peak < PEAK_BYTES
    if player.failed_at is not None:
        assert player.index == player.failed_at + 1  # nothing ran after the failure


@FUZZ
@given(lines=st.lists(command_lines() | anything | st.sampled_from(["// note", '"unbalanced', "; ;", ""]), max_size=8))
def test_fuzz_cfg_files(editor, folder, lines):
    path = Path(folder / "fuzz.cfg")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    exec_file(editor.console, str(path))
    editor.console.waiting.clear()
    no_internal_error(editor)
