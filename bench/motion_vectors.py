#!/usr/bin/env python3
"""The renderer's motion vectors against optical flow, and the still/moving decision, per scene and
level, beside Intel OIDN (high, colour only) in the same run. Prints markdown tables for
docs/methods.md: relMSE and relMSE inside the moving region of the hybrid and of `balanced`, with
the vectors (aux/vector.####.exr, handed over as the named input "vectors") and with DIS flow, and
of `high` with and without them; then the leave-one-scene-out choice of the temporal-change
threshold (`change_z`, balanced) and of `vector_drift` (the presets balanced and high with the
vectors: the pipelines users run).
With --conventions it only establishes the pass's channel order, signs and axes: each frame's
albedo pass warped from frame t-1 (and t+1) by (X, Y) (and (Z, W)) with every sign combination,
against frame t, over the pixels whose vectors exceed half a pixel. Usage:
    python3 bench/motion_vectors.py [--data DIR] [--scenes a,b] [--levels spp0004,...] [--grids change_z,vector_drift]
    python3 bench/motion_vectors.py --conventions [--scenes fast_ball,camera_pan]
"""

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "build" / "python"))
import numpy as np  # noqa: E402
import statfilter  # noqa: E402

Z_GRID = (3, 4, 5, 6, 8)
DRIFT_GRID = (0, 0.5, 2, 8)


def run(name, noisy, ref, vectors=None, **params):
    f = statfilter.Filter(name, **params)
    out = f(noisy, inputs={"vectors": vectors} if vectors is not None else None)
    m = statfilter.compare(out, ref)
    res = f.results
    return {"rel": m["rel_mse"], "moving": m["rel_mse_moving"], "method": res.get("method", name),
            "fraction": res.get("motion_fraction", 0.0)}


def gmean(values):
    values = list(values)
    return math.exp(sum(math.log(v) for v in values) / len(values))


def loso(table, scenes, label):
    """table[value][(scene, level)] = relMSE / OIDN's; picks the value with the lowest geometric mean
    on the other scenes and reports it on the held-out one beside the in-sample choice."""
    def score(value, among):
        return gmean(r for (s, _), r in table[value].items() if s in among)
    values = sorted(table)
    in_sample = min(values, key=lambda v: (score(v, scenes), v))
    print(f"\n{label}: geometric mean of relMSE / OIDN's per scene\n")
    print("| value | " + " | ".join(scenes) + " | all |\n|" + " --- |" * (len(scenes) + 2))
    for v in values:
        print(f"| {v} | " + " | ".join(f"{score(v, [s]):.3f}" for s in scenes) + f" | {score(v, scenes):.3f} |")
    print(f"\nin-sample choice: {in_sample}\n\n| held out | chosen on the others | held-out figure | in-sample choice's figure |\n"
          "| --- | --- | --- | --- |")
    for held in scenes:
        chosen = min(values, key=lambda v: (score(v, [s for s in scenes if s != held]), v))
        print(f"| {held} | {chosen} | {score(chosen, [held]):.3f} | {score(in_sample, [held]):.3f} |")


def bilinear(image, fx, fy):
    """image (H, W, C) read at float positions (fx, fy); positions outside the frame are flagged."""
    h, w = image.shape[:2]
    inside = (fx >= 0) & (fy >= 0) & (fx <= w - 1) & (fy <= h - 1)
    fx, fy = np.clip(fx, 0, w - 1), np.clip(fy, 0, h - 1)
    x0, y0 = np.floor(fx).astype(int), np.floor(fy).astype(int)
    x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
    ax, ay = (fx - x0)[..., None], (fy - y0)[..., None]
    top = (1 - ax) * image[y0, x0] + ax * image[y0, x1]
    bottom = (1 - ax) * image[y1, x0] + ax * image[y1, x1]
    return (1 - ay) * top + ay * bottom, inside


def conventions(data, scenes):
    print("| scene | vectors | to frame | x + sx * first, y + sy * second: (+,+) | (+,-) | (-,+) | (-,-) | zero flow |\n"
          "| --- | --- | --- | --- | --- | --- | --- | --- |")
    for scene in scenes:
        vec = statfilter.read_sequence(str(data / scene / "aux" / "vector.####.exr"))
        albedo = statfilter.read_sequence(str(data / scene / "aux" / "albedo.####.exr"))
        frames, h, w, _ = vec.shape
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        for channels, label in ((0, "X, Y"), (2, "Z, W")):
            for step in (-1, 1):
                errors = []
                for sx, sy in ((1, 1), (1, -1), (-1, 1), (-1, -1), (0, 0)):
                    e = []
                    for t in range(1, frames - 1):
                        u, v = vec[t, ..., channels], vec[t, ..., channels + 1]
                        warped, inside = bilinear(albedo[t + step], xx + sx * u, yy + sy * v)
                        mask = inside & (np.hypot(u, v) > 0.5)
                        if mask.any():
                            e.append(np.abs(warped - albedo[t])[mask].mean())
                    errors.append(np.mean(e))
                print(f"| {scene} | {label} | t{step:+d} | " + " | ".join(f"{e:.4f}" for e in errors) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--scenes", default="")
    parser.add_argument("--levels", default="spp0004,spp0016,spp0064")
    parser.add_argument("--grids", default="change_z,vector_drift",
                        help="the leave-one-scene-out sweeps to run (comma-separated; empty: only the main table)")
    parser.add_argument("--conventions", action="store_true", help="only the channel order, signs and axes")
    args = parser.parse_args()
    scenes = args.scenes.split(",") if args.scenes else sorted(
        p.name for p in args.data.iterdir() if (p / "aux" / "vector.0001.exr").exists())
    if args.conventions:
        conventions(args.data, scenes)
        return
    levels = args.levels.split(",")
    grids = [g for g in args.grids.split(",") if g]
    print("| scene | level | OIDN | hybrid, flow | hybrid, vectors | balanced, alpha only | balanced | balanced, vectors "
          "| high | high, vectors |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    z_table = {z: {} for z in Z_GRID}
    drift_table = {d: {} for d in DRIFT_GRID}
    for scene in scenes:
        ref = statfilter.read_sequence(str(args.data / scene / "ref" / "indirect.####.exr"))
        vectors = statfilter.read_sequence(str(args.data / scene / "aux" / "vector.####.exr"))
        for level in levels:
            noisy = statfilter.read_sequence(str(args.data / scene / level / "indirect.####.exr"))
            oidn = run("oidn", noisy, ref, quality="high")
            rows = [run("hybrid", noisy, ref), run("hybrid", noisy, ref, vectors),
                    run("auto", noisy, ref, change_z=0), run("auto", noisy, ref), run("auto", noisy, ref, vectors),
                    run("auto", noisy, ref, quality="high"), run("auto", noisy, ref, vectors, quality="high")]
            cells = [f"{r['rel']:.4f} / {r['moving']:.4f}" for r in [oidn] + rows]
            for i in (3, 4, 5):  # what balanced picked: s(till) or m(oving), and the moving fraction
                r = rows[i - 1]
                cells[i] += f" ({'s' if r['method'].startswith('pca') else 'm'}, {100 * r['fraction']:.1f}%)"
            print(f"| {scene} | {level} | " + " | ".join(cells) + " |", flush=True)
            if "change_z" in grids:
                for z in Z_GRID:
                    z_table[z][(scene, level)] = run("auto", noisy, ref, change_z=z)["rel"] / oidn["rel"]
            if "vector_drift" in grids:
                for d in DRIFT_GRID:
                    for quality in ("balanced", "high"):
                        drift_table[d][(scene, (level, quality))] = run(
                            "auto", noisy, ref, vectors, quality=quality, vector_drift=d)["rel"] / oidn["rel"]
    if "change_z" in grids:
        loso(z_table, scenes, "change_z (balanced, no vectors)")
    if "vector_drift" in grids:
        loso(drift_table, scenes, "vector_drift (balanced and high with the vectors)")


if __name__ == "__main__":
    main()
