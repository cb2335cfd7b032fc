"""Write a synthetic CT-like phantom as a 16-bit NRRD (Hounsfield units, int16, gzip): a chest with skin, fat,
soft tissue, two lungs, a spine and ribs, air around it and -3024 outside the scanner's round field of view, as
CT files have. docs/volume.md's scalar screenshots load it.

    PYTHONPATH=. .venv/bin/python scripts/ct_phantom.py /tmp/phantom.nrrd [size]
"""
import sys

import nrrd

from app.model.volume.phantom import ct_phantom


if __name__ == "__main__":
    size = int(sys.argv[2]) if len(sys.argv) > 2 else 128
    nrrd.write(sys.argv[1], ct_phantom(size), {"encoding": "gzip"}, index_order="C")
    print(f"wrote {sys.argv[1]}: {size}^3 int16")
