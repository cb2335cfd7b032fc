"""A synthetic CT-like chest in Hounsfield units (int16): skin, fat, soft tissue, two lungs, a spine and ribs, air
around it with scanner noise and -3024 outside the scanner's round field of view, as CT files have. The scalar
modes' bench and tests draw it; scripts/ct_phantom.py writes it as an NRRD for the docs' screenshots."""
from __future__ import annotations

import numpy as np


def ct_phantom(n: int) -> np.ndarray:
    z, y, x = np.mgrid[0:n, 0:n, 0:n] / (n - 1) * 2 - 1  # -1..1 in index order: z slices, y down, x right
    rng = np.random.default_rng(0)
    hu = np.full((n, n, n), -1000.0) + rng.normal(0, 15, (n, n, n))  # air, with scanner noise
    chest = (x / 0.8) ** 2 + (y / 0.55) ** 2
    inside = (chest < 1) & (np.abs(z) < 0.8)
    hu[inside & (chest > 0.85)] = -100  # fat under the skin
    hu[inside & (chest <= 0.85)] = 40  # soft tissue
    for side in (-1, 1):  # lungs
        lung = ((x - side * 0.35) / 0.28) ** 2 + ((y + 0.02) / 0.38) ** 2 + (z / 0.7) ** 2 < 1
        hu[lung] = -850
    spine = ((x / 0.09) ** 2 + ((y - 0.4) / 0.09) ** 2 < 1) & (np.abs(z) < 0.85)
    hu[spine] = 700
    for rib_z in np.linspace(-0.6, 0.6, 7):  # ribs: thin elliptic hoops inside the fat
        hoop = np.abs(np.sqrt((x / 0.72) ** 2 + (y / 0.48) ** 2) - 1) < 0.035
        hu[hoop & (np.abs(z - rib_z) < 0.035) & (y < 0.35)] = 900
    hu[inside] += rng.normal(0, 15, np.count_nonzero(inside))
    hu[x ** 2 + y ** 2 > 1] = -3024  # outside the field of view
    return np.round(hu).astype(np.int16)
