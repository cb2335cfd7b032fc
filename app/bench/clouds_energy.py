"""The clouds' light, measured for energy (docs/clouds.md, "Energy"): `python -m app.bench.clouds_energy`.

Not a GL technique of the bench harness: these are integrals of the CPU reference's phase and sun light
(app/reference/clouds_medium.py, the shader's formulas) over the sphere of directions, which a furnace test
(tests/test_clouds_energy.py) then checks on the GPU. Everything the sun gives a sample depends on the direction
only through cos = d . sun, so a mean over the sphere is (1/2) of an integral over cos in -1..1.
"""
from __future__ import annotations

import argparse
import math
from dataclasses import replace

import numpy as np

from app.model.clouds.scene import CloudParams, CloudView, frame
from app.reference.clouds_medium import phase, sun_energy

_GAUSS = np.polynomial.legendre.leggauss(24)
# Panels 10x narrower towards each pole, where a lobe of g up to 0.99 peaks (width ~ (1 - g)^2): 24 Gauss-Legendre
# nodes each integrate every lobe of the panel's ranges to better than 1e-9.
_EDGES = np.unique(np.concatenate([[-1.0, 0.0, 1.0], *([s * (1 - 10.0 ** -k) for k in range(1, 13)]
                                                       for s in (-1.0, 1.0))]))


def sphere_nodes() -> tuple[np.ndarray, np.ndarray]:
    """(cos, weight): a quadrature over cos in -1..1 whose weights sum to 2."""
    x, w = _GAUSS
    lo, hi = _EDGES[:-1, None], _EDGES[1:, None]
    return ((lo + hi) / 2 + (hi - lo) / 2 * x).ravel(), ((hi - lo) / 2 * w).ravel()


def mean_over_directions(f) -> float:
    """(1 / 4 pi) times the integral of f(cos) over the sphere, f vectorised over cos."""
    cos, weight = sphere_nodes()
    return float((f(cos) * weight).sum() / 2)


def phase_integral(fr, scale: float = 1.0) -> float:
    """The integral over the sphere of P(cos, scale) as the shader computes it: 1 for a normalised phase."""
    return 4 * math.pi * mean_over_directions(lambda c: phase(fr, c, scale))


def sun_energy_mean(fr, tau: float, rho: float) -> float:
    """The directional mean of E powder at optical depth tau towards the sun and density rho: what a sample
    scatters in all, per unit of sun it receives unshaded (at most 1 conserves energy)."""
    return mean_over_directions(lambda c: sun_energy(fr, np.full_like(c, tau), np.full_like(c, rho), c))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m app.bench.clouds_energy")
    p.add_argument("--elevations", type=float, nargs="+", default=[25.0, 45.0], help="sun elevations, degrees")
    p.add_argument("--densities", type=float, nargs="+", default=[0.05, 1.0], help="rho of the E x powder means")
    args = p.parse_args(argv)
    print("the default parameters; phase: its integral over the sphere; E x powder: directional mean at tau 0")
    rhos = "".join(f" {'rho ' + format(r, 'g'):>9}" for r in args.densities)
    print(f"{'sun':>5} {'phase':>5} {'integral':>9}{rhos}")
    for elevation in args.elevations:
        for name, params in (("mix", CloudParams()), ("max", replace(CloudParams(), phase_max=1))):
            fr = frame(params, CloudView(sun_elevation=elevation))
            means = "".join(f" {sun_energy_mean(fr, 0.0, rho):9.4f}" for rho in args.densities)
            print(f"{elevation:5g} {name:>5} {phase_integral(fr):9.5f}{means}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
