"""Help > Documentation: the docs/ pages shown in the editor (Qt renders their Markdown, pictures included), with
links between pages followed in place and outside links handed to the desktop."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QUrl
from PySide6.QtGui import QDesktopServices, QTextDocument
from PySide6.QtWidgets import QDialog, QHBoxLayout, QPushButton, QTextBrowser, QVBoxLayout


class DocsViewer(QDialog):
    def __init__(self, parent, folder: Path) -> None:
        super().__init__(parent, windowTitle="Shadelab documentation")
        self.folder = folder
        self.browser = QTextBrowser(openLinks=False)
        self.browser.setSearchPaths([str(folder), str(folder.parent)])  # pictures beside a page, or the repo's
        self.browser.anchorClicked.connect(self._follow)
        back = QPushButton("Back", clicked=self.browser.backward)
        self.browser.backwardAvailable.connect(back.setEnabled)
        back.setEnabled(False)
        bar = QHBoxLayout()
        bar.addWidget(back)
        bar.addStretch(1)
        layout = QVBoxLayout(self)
        layout.addLayout(bar)
        layout.addWidget(self.browser)
        self.resize(820, 720)

    def show_page(self, page: Path) -> None:
        self.browser.setSource(QUrl.fromLocalFile(str(page)), QTextDocument.ResourceType.MarkdownResource)
        self.setWindowTitle(f"Shadelab documentation: {page.name}")
        self.show()
        self.raise_()

    def _follow(self, url: QUrl) -> None:
        """A page of ours (a .md beside this one, an anchor in it) in place; anything else on the desktop."""
        target = self.browser.source().resolved(url)
        path = Path(target.toLocalFile()) if target.isLocalFile() else None
        if path is not None and path.suffix == ".md" and path.is_file():
            self.browser.setSource(target, QTextDocument.ResourceType.MarkdownResource)
            self.setWindowTitle(f"Shadelab documentation: {path.name}")
        elif path is not None and not path.suffix and url.hasFragment():
            self.browser.scrollToAnchor(url.fragment())
        else:
            QDesktopServices.openUrl(target)
