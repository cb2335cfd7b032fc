"""The main window's status bar: what lies under the cursor, the current tool and render mode, the frame time
(the GL renderer in its tooltip).

Each part asks the viewport's tool (app/views/tool.py) what to say, so a workspace adds nothing here. Each may be
cut short rather than widen the window."""
from __future__ import annotations

from PySide6.QtCore import QObject
from PySide6.QtWidgets import QLabel, QStatusBar

from app.views.weak_callback import weak_callback


class StatusParts(QObject):
    def __init__(self, bar: QStatusBar, viewport, console) -> None:
        super().__init__(bar)
        self.viewport = viewport
        self.cursor_label, self.tool_label, self.frame_label = (QLabel(), QLabel(), QLabel())
        for label in (self.cursor_label, self.tool_label, self.frame_label):
            label.setMinimumWidth(1)  # not the text's width: a long text is cut, the window keeps its size
            label.setContentsMargins(6, 0, 6, 0)
        bar.addWidget(self.cursor_label, 1)
        bar.addPermanentWidget(self.tool_label)
        bar.addPermanentWidget(self.frame_label)
        viewport.hovered.connect(self.cursor_label.setText)
        viewport.gl_ready.connect(lambda renderer: self.frame_label.setToolTip(f"drawn by {renderer}"))
        viewport.view_changed.connect(self.sync)
        viewport.frame_rendered.connect(self.frame)
        console.executed_listeners.append(weak_callback(self, "sync", drop_args=True))  # a mode or tool changed

    def sync(self) -> None:
        """The tool and render mode of the workspace in view."""
        tool = self.viewport.tool
        parts = [] if tool is None else [f"{what}: {text}" for what, text in
                                          (("tool", tool.tool_name()), ("render", tool.render_mode())) if text]
        self.tool_label.setText("  ·  ".join(parts))

    def frame(self, _ms: float) -> None:
        """One measure: the mean time of the recent frames, and the frames per second that mean makes."""
        mean = self.viewport.mean_frame_ms()
        self.frame_label.setText(f"{mean:.1f} ms/frame ({1e3 / mean:.1f} frames/s), mean of the last "
                                 f"{len(self.viewport.frame_ms)}")
