"""A uniform grid over axis-aligned boxes: which hulls can touch a light's reach, in time that grows
with the answer, not with the scene (10,000 hulls far from the view cost a few dictionary lookups).
It counts the cells it visits and the boxes it tests, so a test can assert that work instead of time."""
from __future__ import annotations

import math
import numpy as np


class GridIndex:
    def __init__(self, boxes: np.ndarray) -> None:
        """boxes (n, 4): x0, y0, x1, y1."""
        self.boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
        self.cells_visited = 0  # cells looked up by every query so far
        self.boxes_tested = 0   # candidate boxes tested against a query's rectangle so far
        n = len(self.boxes)
        sizes = np.maximum(self.boxes[:, 2:] - self.boxes[:, :2], 0.0) if n else np.ones((1, 2))
        # cells about four typical boxes wide: small boxes land in few cells, queries visit few cells
        self.cell = max(float(np.median(sizes.max(axis=1))) * 4.0, 1e-6)
        lo = np.floor(self.boxes[:, :2] / self.cell).astype(np.int64)
        hi = np.floor(self.boxes[:, 2:] / self.cell).astype(np.int64)
        span = hi - lo + 1
        count = span[:, 0] * span[:, 1]
        self._big = np.flatnonzero(count > 64)  # boxes spanning many cells are checked directly
        # every (cell, box) pair of the other boxes, in numpy (10,000 hulls index in milliseconds), grouped by
        # cell: a cell's boxes are one slice of `_ids`
        small = np.flatnonzero(count <= 64)
        reps = count[small]
        step = np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
        rows = np.repeat(span[small, 1], reps)
        cx = np.repeat(lo[small, 0], reps) + step // rows
        cy = np.repeat(lo[small, 1], reps) + step % rows
        ids = np.repeat(small, reps)
        order = np.lexsort((ids, cy, cx))
        cx, cy, self._ids = cx[order], cy[order], ids[order]
        starts = np.ones(len(order), bool)
        starts[1:] = (cx[1:] != cx[:-1]) | (cy[1:] != cy[:-1])
        first = np.flatnonzero(starts)
        ends = np.r_[first[1:], len(order)]
        self._cells: dict[tuple[int, int], tuple[int, int]] = dict(zip(
            zip(cx[first].tolist(), cy[first].tolist()), zip(first.tolist(), ends.tolist())))

    def query(self, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
        """Sorted indices of boxes overlapping the rectangle."""
        if not len(self.boxes):
            return np.zeros(0, np.int64)
        c = self.cell
        cx0, cy0, cx1, cy1 = (math.floor(v / c) for v in (x0, y0, x1, y1))
        if (cx1 - cx0 + 1) * (cy1 - cy0 + 1) > 4 * len(self._cells) + 16:
            # a rectangle wider than the occupied cells: walking those is cheaper than its own cells
            keys = [k for k in self._cells if cx0 <= k[0] <= cx1 and cy0 <= k[1] <= cy1]
            self.cells_visited += len(self._cells)
        else:
            keys = [(i, j) for i in range(cx0, cx1 + 1) for j in range(cy0, cy1 + 1)]
            self.cells_visited += len(keys)
        found = [self._ids[slice(*self._cells[k])] for k in keys if k in self._cells]
        ids = np.unique(np.concatenate([self._big, *found]))
        self.boxes_tested += len(ids)
        b = self.boxes[ids]
        keep = (b[:, 0] <= x1) & (b[:, 2] >= x0) & (b[:, 1] <= y1) & (b[:, 3] >= y0)
        return ids[keep]
