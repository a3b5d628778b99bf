#!/usr/bin/env python3
"""How far a postfilter whose reach follows the data could take `balanced`: the diffusion postfilter's
step count chosen per 16 x 16 tile with the reference (an oracle, the ceiling of any rule that picks
it from the data), against balanced's 3 steps and the best single count for the shot; beside it the
count SURE picks with a white-noise estimate of the residual (the median absolute HH wavelet
coefficient per tile; the divergence by one probe, x + eps b, as the trust blend measures it), and
how much of the residual's true error that estimate sees (true / HH; on the noisy input for
comparison).

Each run is `statfilter denoise --method hybrid --mc_flow ultrafast --mc_half_width 4 --postfilter
diffusion --postfilter_params iterations=N,k=3` (balanced's settings on a moving scene); the SURE
column runs the diffusion filter through the Python package on the hybrid's output without its
postfilter. relMSE / OIDN's (oidn plugin, quality high) over the pixels the tiles cover. Prints one
line per scene and level. Usage:
    python3 bench/postfilter_oracle.py [--cli build/tools/statfilter] [--data ../shared/data[,DIR]]
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import bench_arguments, import_statfilter, scenes  # noqa: E402

STEPS = [0, 1, 2, 3, 5, 8, 12]
TILE = 16


def rel_err(out, ref):
    return (out - ref) ** 2 / (ref ** 2 + 0.01)


def tile_sums(a, per_frame=False):
    """F x H x W x C -> per tile sums (ty, tx), or (F, ty, tx), over the whole tiles."""
    F, H, W, C = a.shape
    t = a[:, :H // TILE * TILE, :W // TILE * TILE].reshape(F, H // TILE, TILE, W // TILE, TILE, C)
    return t.sum(axis=(2, 4, 5)) if per_frame else t.sum(axis=(0, 2, 4, 5))


def hh_variance(u):
    """Per tile, the white-noise variance the finest diagonal wavelet band sees (MAD / 0.6745)^2."""
    F, H, W, C = u.shape
    d = (u[:, 0:H - 1:2, 0:W - 1:2] - u[:, 1::2, 0:W - 1:2] - u[:, 0:H - 1:2, 1::2] + u[:, 1::2, 1::2]) / 2
    h = TILE // 2
    _, Hd, Wd, _ = d.shape
    blocks = np.abs(d[:, :Hd // h * h, :Wd // h * h]).reshape(F, Hd // h, h, Wd // h, h, C)
    blocks = blocks.transpose(1, 3, 0, 2, 4, 5).reshape(Hd // h, Wd // h, -1)
    return (np.median(blocks, axis=-1) / 0.6745) ** 2


def main():
    p = bench_arguments(__doc__, "quality_targets.md")
    args = p.parse_args()
    sf = import_statfilter(args.cli)
    rng = np.random.default_rng(1)
    for scene, levels in scenes(args.data):
        ref = sf.read_sequence(str(scene / "ref" / "indirect.####.exr")).astype(np.float64)
        for level in levels:
            noisy = str(scene / level / "indirect.####.exr")
            with tempfile.TemporaryDirectory() as work:
                out = str(Path(work) / "o.####.exr")

                def denoise(*options):
                    subprocess.run([args.cli, "denoise", noisy, out, "--float", "--quiet", *options], check=True)
                    return sf.read_sequence(out).astype(np.float64)

                oidn = tile_sums(rel_err(denoise("--method", "oidn"), ref)).sum()
                hybrid = ["--method", "hybrid", "--mc_flow", "ultrafast", "--mc_half_width", "4"]
                per_tile, per_frame = [], []
                for n in STEPS:
                    post = ["--postfilter", "diffusion", "--postfilter_params", f"iterations={n},k=3"] if n else ["--postfilter", ""]
                    e = rel_err(denoise(*hybrid, *post), ref)
                    per_tile.append(tile_sums(e))
                    per_frame.append(tile_sums(e, per_frame=True))
                u = denoise(*hybrid, "--postfilter", "").astype(np.float32)
            per_tile, per_frame = np.array(per_tile), np.array(per_frame)
            fixed = {n: per_tile[i].sum() / oidn for i, n in enumerate(STEPS)}
            # SURE per tile with the HH band's variance, the divergence by one sign probe.
            s2 = hh_variance(u.astype(np.float64))
            n_tile = TILE * TILE * u.shape[0] * u.shape[3]
            eps = np.full(u.shape[1:3], float(np.median(0.05 * np.sqrt(s2))))
            ty, tx = s2.shape
            eps[:ty * TILE, :tx * TILE] = np.kron(0.05 * np.sqrt(s2), np.ones((TILE, TILE)))
            eps = np.where(eps > 0, eps, np.nan)
            b = rng.choice([-1.0, 1.0], size=u.shape).astype(np.float32)
            probed = (u + np.nan_to_num(eps)[None, :, :, None] * b).astype(np.float32)
            sure = []
            for n in STEPS:
                f = sf.Filter("diffusion", iterations=n, k=3) if n else None
                d = f(u).astype(np.float64) if f else u.astype(np.float64)
                dp = f(probed).astype(np.float64) if f else probed.astype(np.float64)
                div = np.nan_to_num(tile_sums(b * (dp - d) / eps[None, :, :, None]))
                sure.append(tile_sums((d - u) ** 2) - n_tile * s2 + 2 * s2 * div)
            pick = np.array(sure).argmin(axis=0)
            by_sure = np.take_along_axis(per_tile, pick[None], 0).sum() / oidn
            true_u = tile_sums((u - ref) ** 2) / n_tile
            x = sf.read_sequence(noisy).astype(np.float64)
            true_x = tile_sums((x - ref) ** 2) / n_tile
            seen = np.median(true_u / np.maximum(s2, 1e-30))
            seen_x = np.median(true_x / np.maximum(hh_variance(x - ref), 1e-30))
            print(f"{scene.name} {level}: " + " ".join(f"{n}:{fixed[n]:.3f}" for n in STEPS) +
                  f" | best for the shot {min(fixed.values()):.3f}, per tile {per_tile.min(axis=0).sum() / oidn:.3f},"
                  f" per tile and frame {per_frame.min(axis=0).sum() / oidn:.3f}, SURE {by_sure:.3f}"
                  f" | true / HH: residual {seen:.2f}, input {seen_x:.2f}", flush=True)


if __name__ == "__main__":
    main()
