"""What the console shows people: counts in the singular for one, and floats as they were typed."""
import pytest

from app.console.text import count, number
from app.editor import Editor


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(configs=False)


def printed(editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level != "input"]


def test_count_and_number():
    assert [count(n, "flake") for n in (0, 1, 2)] == ["0 flakes", "1 flake", "2 flakes"]
    assert count(1, "vertex", "vertices") == "1 vertex" and count(5, "vertex", "vertices") == "5 vertices"
    assert number(0.45 + 0.025) == "0.475"  # 0.47500000000000003 in repr
    assert [number(v) for v in (0.1234567, 50.0, -2.5, 1e-7, 123456789.125)] == \
        ["0.1234567", "50", "-2.5", "1e-07", "123456789.125"]


def test_one_of_a_thing_is_singular(editor):
    editor.execute("workspace snowflake; snow.clear; snow.add 0 0 0.5; snow.list")
    assert printed(editor)[-1] == "1 flake, level 4"
    editor.execute("workspace lighting2d; lighting.clear; light.add point 0 0; light.list")
    assert printed(editor)[-1] == "1 light"
    editor.execute("cmdlist snow.cle")
    assert printed(editor)[-1] == "1 command"


def test_a_cvar_echoes_its_value_as_typed(editor):
    editor.execute("set r_x 0.1234567; r_x")  # %g showed 0.123457
    assert printed(editor)[-1] == '"r_x" is "0.1234567" (default "0.1234567")'
    editor.execute("r_shadowBlur 0.475; r_shadowBlur")
    assert printed(editor)[-1].startswith('"r_shadowBlur" is "0.475"')


def test_a_listing_shows_a_typed_coordinate_as_typed(editor):
    editor.execute("workspace snowflake; snow.clear; snow.add 0.1234567 -0.475 0.2; snow.list")
    assert printed(editor)[-2] == "0: (0.1234567, -0.475) radius 0.2"
