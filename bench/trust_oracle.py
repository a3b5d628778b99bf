#!/usr/bin/env python3
"""How far the trust blend's share of the temporal change is from the best one, on one scene and level.

`--quality high` blends each 16 x 16 tile of each frame as y - w d (y: OIDN on the noisy frame x; z:
OIDN on the temporal result; d = y - z) with w fitted from x (docs/methods.md, "Trusting time after
a prefilter"). This script runs the CLI for y and z, then scores, per frame and tile (no pooling, no
prior: the estimates alone):

- oracle: w = sum (y - ref) d / sum d^2, the reference's least-squares share (the blend's best);
- naive: w from sum (y - x) d alone (no Stein term);
- stein y: plus sigma^2 sum dy/dx, the term the library adds (dy/dx from a second run on x + eps b);
- stein y, z: minus sigma^2 sum dz/dx as well (z depends on x too: OIDN on the temporal result of x);
- pooled, y and pooled, y, z: the same two with the library's pooling over +-2 frames and prior.

Usage: python3 bench/trust_oracle.py --scene DIR --level spp0004 [--cli build-release/tools/statfilter]
(the Python package of the same build on PYTHONPATH, STATFILTER_LIBRARY naming its library).
"""
import argparse
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import statfilter

TILE = 16


def rel_mse(a, ref):
    return float(np.mean((a - ref) ** 2 / (ref ** 2 + 1e-2)))  # as `statfilter compare`


def denoise(cli, src, out, args):
    subprocess.run([cli, "denoise", src, out, "--float", "--quiet", "--overwrite"] + args, check=True)
    return statfilter.read_sequence(out).astype(np.float64)


def tiles(shape):
    frames, height, width, _ = shape
    for f in range(frames):
        for ty in range(0, height, TILE):
            for tx in range(0, width, TILE):
                yield (f, slice(ty, ty + TILE), slice(tx, tx + TILE))


def blend(y, d, share):
    """y - w d with w = clamp(share(tile), 0, 1) in every tile."""
    out = np.empty_like(y)
    for s in tiles(y.shape):
        den = float((d[s] * d[s]).sum())
        w = float(np.clip(share(s) / den, 0, 1)) if den > 0 else 1.0
        out[s] = y[s] - w * d[s]
    return out


def pooled_blend(y, d, num, sigma2, pool=2):
    """The library's form: each tile's sums pooled over frames t - pool .. t + pool, the fit weighed
    against the prior w = 1 by its evidence sum d^2 / sigma^2 (lib/time_trust.cpp)."""
    frames = y.shape[0]
    key = lambda s: (s[0], s[1].start, s[2].start)  # noqa: E731 (slices are not hashable before 3.12)
    sums = {key(s): (float(num(s)), float((d[s] * d[s]).sum()), float(sigma2[s].mean())) for s in tiles(y.shape)}
    out = np.empty_like(y)
    for s in tiles(y.shape):
        f = s[0]
        near = [(g, s[1].start, s[2].start) for g in range(max(0, f - pool), min(frames - 1, f + pool) + 1)]
        n = sum(sums[k][0] for k in near)
        den = sum(sums[k][1] for k in near)
        noise = sum(sums[k][2] for k in near) / len(near)
        evidence = den / noise if noise > 0 else 0.0
        fit = float(np.clip(n / den, 0, 1)) if den > 0 else 1.0
        w = (evidence * fit + 1.0) / (evidence + 1.0)
        out[s] = y[s] - w * d[s]
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", required=True, help="a scene folder: LEVEL/indirect.####.exr and ref/indirect.####.exr")
    p.add_argument("--level", default="spp0004")
    p.add_argument("--cli", default=str(Path(__file__).resolve().parents[1] / "build-release" / "tools" / "statfilter"))
    a = p.parse_args()
    scene = Path(a.scene)
    src = str(scene / a.level / "indirect.####.exr")
    x = statfilter.read_sequence(src).astype(np.float64)
    ref = statfilter.read_sequence(str(scene / "ref" / "indirect.####.exr")).astype(np.float64)
    with tempfile.TemporaryDirectory() as tmp:
        y = denoise(a.cli, src, f"{tmp}/y.####.exr", ["--method", "oidn"])
        z = denoise(a.cli, src, f"{tmp}/z.####.exr", ["--quality", "high", "--prefilter_trust", "0"])
        high = denoise(a.cli, src, f"{tmp}/h.####.exr", ["--quality", "high"])
        # The probe: x + eps b, eps a twentieth of the tile's noise (as the library's), b a fixed sign.
        sigma = np.empty_like(x)
        for s in tiles(x.shape):
            sigma[s] = np.sqrt(np.mean((x[s] - y[s]) ** 2))
        b = np.random.default_rng(1).choice([-1.0, 1.0], size=x.shape)
        probed = np.maximum(x + 0.05 * sigma * b, 0)
        step = probed - x
        statfilter.write_sequence(f"{tmp}/xp.####.exr", probed.astype(np.float32), pixel_type="float")
        yp = denoise(a.cli, f"{tmp}/xp.####.exr", f"{tmp}/yp.####.exr", ["--method", "oidn"])
        zp = denoise(a.cli, f"{tmp}/xp.####.exr", f"{tmp}/zp.####.exr", ["--quality", "high", "--prefilter_trust", "0"])
    moved = step != 0
    dy = np.where(moved, (yp - y) / np.where(moved, step, 1), 0)
    dz = np.where(moved, (zp - z) / np.where(moved, step, 1), 0)
    d = y - z
    s2 = sigma ** 2
    rows = {
        "OIDN (y)": y,
        "temporal (z)": z,
        "high": high,
        "oracle w": blend(y, d, lambda s: ((y[s] - ref[s]) * d[s]).sum()),
        "naive w": blend(y, d, lambda s: ((y[s] - x[s]) * d[s]).sum()),
        "stein y": blend(y, d, lambda s: ((y[s] - x[s]) * d[s]).sum() + (s2[s] * dy[s]).sum()),
        "stein y, z": blend(y, d, lambda s: ((y[s] - x[s]) * d[s]).sum() + (s2[s] * (dy[s] - dz[s])).sum()),
        "pooled, y": pooled_blend(y, d, lambda s: ((y[s] - x[s]) * d[s]).sum() + (s2[s] * dy[s]).sum(), s2),
        "pooled, y, z": pooled_blend(y, d, lambda s: ((y[s] - x[s]) * d[s]).sum() + (s2[s] * (dy[s] - dz[s])).sum(), s2),
    }
    oidn = rel_mse(y, ref)
    print(f"{scene.name} {a.level}: relMSE (/ OIDN's)")
    for name, out in rows.items():
        r = rel_mse(out, ref)
        print(f"  {name:14s} {r:.5f} ({r / oidn:.3f})")


if __name__ == "__main__":
    main()
