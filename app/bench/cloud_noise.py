"""Wall time of the cloud noise textures at their product sizes (CPU, numpy): `python -m app.bench.cloud_noise`.

Not a GL technique of the bench harness: the textures are made once and cached (app.io.clouds.noise_cache), so only
their first build costs anything. Prints the best of --repeat runs of each.
"""
from __future__ import annotations

import argparse
import os
import time

from app.model.clouds import noise as cloud_noise

TEXTURES = (("shape", cloud_noise.shape_noise, 128), ("detail", cloud_noise.detail_noise, 32),
            ("curl", cloud_noise.curl_noise, 128))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m app.bench.cloud_noise")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    print(f"cloud noise on {os.cpu_count()} CPUs, best of {args.repeat}")
    for name, make, size in TEXTURES:
        times = []
        for _ in range(args.repeat):
            t = time.perf_counter()
            a = make(size, seed=args.seed)
            times.append(time.perf_counter() - t)
        print(f"{name:7s} {'x'.join(map(str, a.shape)):12s} {a.nbytes / 2**20:6.2f} MiB  {min(times):7.3f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
