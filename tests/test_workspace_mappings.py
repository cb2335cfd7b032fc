"""Each layer keeps one mapping from a workspace's name to its part there (docs/architecture.md rule 7): every
mapping names exactly the workspaces there are, so a missing entry fails here instead of drawing an empty
background without a word."""
from app.bench import WORKSPACE_TECHNIQUE
from app.bench.frame_budget import MOVES
from app.commands.workspaces import COMMANDS
from app.gl.core.workspace_renderer import RENDERERS
from app.model.workspaces import names
from app.views.workspace_views import VIEWS


def test_every_mapping_names_every_workspace_and_no_other():
    everyone = set(names())
    for layer, mapping in (("commands", COMMANDS), ("gl", RENDERERS), ("views", VIEWS),
                           ("bench", WORKSPACE_TECHNIQUE), ("bench frames", MOVES)):
        assert set(mapping) == everyone, f"{layer}: {sorted(set(mapping) ^ everyone)}"
