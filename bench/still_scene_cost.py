#!/usr/bin/env python3
"""What the hybrid costs on a scene without motion, beside pca, in one process (best of --repeats,
the filters interleaved so machine noise hits them alike). The hybrid's still-scene path is global
PCA from the basis it computed for alpha, then its default diffusion postfilter; so it is compared
with pca, and with pca followed by the same postfilter. Usage:
    python3 bench/still_scene_cost.py [--data DIR] [--scene cornell_light] [--repeats 10]
"""

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "build" / "python"))
import statfilter  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--scene", default="cornell_light")
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args()
    post = dict(postfilter="diffusion", postfilter_params="iterations=3,k=3")
    print("| level | pca ms/frame | pca + postfilter | hybrid | hybrid, postfilter off | hybrid / (pca + postfilter) | "
          "hybrid off / pca | moving fraction |\n| --- | --- | --- | --- | --- | --- | --- | --- |")
    for level in sorted((args.data / args.scene).glob("spp*")):
        seq = statfilter.read_sequence(str(level / "indirect.####.exr"))
        filters = {"pca": statfilter.Filter("pca"), "post": statfilter.Filter("pca", **post),
                   "hybrid": statfilter.Filter("hybrid"), "off": statfilter.Filter("hybrid", postfilter="")}
        best = dict.fromkeys(filters, float("inf"))
        for _ in range(args.repeats):
            for name, f in filters.items():
                t0 = time.perf_counter()
                f(seq)
                best[name] = min(best[name], time.perf_counter() - t0)
        ms = {k: 1000 * v / seq.shape[0] for k, v in best.items()}
        print(f"| {level.name} | {ms['pca']:.2f} | {ms['post']:.2f} | {ms['hybrid']:.2f} | {ms['off']:.2f} | "
              f"{best['hybrid'] / best['post']:.2f}x | {best['off'] / best['pca']:.2f}x | "
              f"{filters['hybrid'].results['motion_fraction']:.5f} |")


if __name__ == "__main__":
    main()
