"""Each layer keeps one mapping from a workspace's name to its part there (docs/architecture.md rule 7): every
mapping names exactly the workspaces there are, so a missing entry fails here instead of drawing an empty
background without a word; and a lookup of a workspace a mapping lacks says which mapping lacks it."""
import pytest

from app.bench import TECHNIQUES, WORKSPACE_TECHNIQUE
from app.bench.frame_budget import MOVES
from app.commands.workspaces import COMMANDS
from app.gl.core.workspace_renderer import RENDERERS
from app.model.workspace import MissingEntry
from app.model.workspaces import WORKSPACES, names
from app.views.workspace_views import VIEWS

MAPPINGS = (("commands", COMMANDS), ("gl", RENDERERS), ("views", VIEWS), ("bench", WORKSPACE_TECHNIQUE),
            ("bench frames", MOVES))


def test_every_mapping_names_every_workspace_and_no_other():
    everyone = set(names())
    for layer, mapping in MAPPINGS:
        assert set(mapping) == everyone, f"{layer}: {sorted(set(mapping) ^ everyone)}"


def test_each_workspace_is_listed_under_the_name_its_state_gives_itself():
    assert [info.name for info in WORKSPACES] == [info.state.name for info in WORKSPACES]
    assert len(set(names())) == len(WORKSPACES)


def test_each_workspace_technique_is_a_bench_technique():
    assert set(WORKSPACE_TECHNIQUE.values()) <= set(TECHNIQUES)


@pytest.mark.parametrize("mapping, where", [(COMMANDS, "COMMANDS (app/commands/workspaces.py)"),
                                            (RENDERERS, "RENDERERS (app/gl/core/workspace_renderer.py)"),
                                            (VIEWS, "VIEWS (app/views/workspace_views.py)"),
                                            (MOVES, "MOVES (app/bench/frame_budget.py)")])
def test_a_workspace_a_mapping_lacks_is_an_error_naming_the_mapping(mapping, where):
    with pytest.raises(MissingEntry) as raised:
        mapping["nowhere"]
    assert str(raised.value).startswith(f"the 'nowhere' workspace has no entry in {where}")
    assert "nowhere" not in mapping  # the lookup added nothing
