"""A demo recorded before the workspace unit (main at 9aeae41, every workspace touched) replays to the
digests it had then: command names, arguments and the demo format are a contract."""
import hashlib
import json
import re
import shutil
from pathlib import Path

from app.console.demo import VirtualClock
from app.editor import Editor

FIXTURES = Path(__file__).parent / "fixtures"


def legacy_digest(editor: Editor, cvar_names: list[str]) -> dict[str, str]:
    """The digest as 9aeae41 computed it, over the cvars that existed then."""
    cvars = editor.console.registry.cvars
    text = "".join(f"{n}={cvars[n].serialise()};" for n in sorted(cvar_names))
    view = editor.workspaces["volume"].view
    return {"snowflake": editor.workspaces["snowflake"].scene.digest(),
            "volume": editor.workspaces["volume"].volume.voxels.digest(),
            "lighting2d": editor.workspaces["lighting2d"].scene.digest(),
            "cvars": hashlib.sha256(text.encode()).hexdigest()[:16],
            "view": hashlib.sha256(repr((view.key(), editor.workspace)).encode()).hexdigest()[:16]}


def test_a_demo_recorded_on_9aeae41_replays_to_its_digests(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    demo = FIXTURES / "recorded_9aeae41.demo"
    expected = json.loads((FIXTURES / "recorded_9aeae41.json").read_text())
    shutil.copy(demo, tmp_path / "legacy.demo")
    cvar_names = re.findall(r"^0\.000 seta? (\S+) ", demo.read_text(), re.M)

    clock = VirtualClock()
    editor = Editor(clock=clock, configs=False)
    editor.execute("workspace volume")  # replay must not depend on where it starts
    assert editor.execute("play legacy")
    clock.advance(60)
    editor.demos.update()
    assert not editor.demos.playing
    assert not [line.text for line in editor.console.log if line.level == "error"]
    assert legacy_digest(editor, cvar_names) == expected["digest"]
    cams = (editor.workspaces["snowflake"].camera, editor.workspaces["lighting2d"].camera)
    assert [[c.cx, c.cy, c.height] for c in cams] == [expected["snowflake_view"], expected["lighting_view"]]
    assert editor.workspace == expected["workspace"]
