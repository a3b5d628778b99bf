#!/usr/bin/env python3
"""The study's blend inside the hybrid (motion_compensation=off): its moving-basis window (mb_half_width) on the moving scenes: relMSE over the default
moving-basis filter's, and relMSE inside the moving region, for a few window half-widths. Usage:
    python3 bench/hybrid_window.py [--data DIR] [--widths 8 4 3 2 1]
"""

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "build" / "python"))
import statfilter  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--scenes", nargs="+", default=["camera_pan", "cornell_moving"])
    parser.add_argument("--widths", nargs="+", type=int, default=[8, 4, 3, 2, 1])
    args = parser.parse_args()
    print("| scene | level | " + " | ".join(f"h{w}: / mb, moving" for w in args.widths) + " |")
    print("| --- | --- | " + " | ".join("---" for _ in args.widths) + " |")
    for scene in args.scenes:
        ref = statfilter.read_sequence(str(args.data / scene / "ref" / "indirect.####.exr"))
        for level in sorted((args.data / scene).glob("spp*")):
            noisy = statfilter.read_sequence(str(level / "indirect.####.exr"))
            mb = statfilter.compare(statfilter.Filter("moving-basis")(noisy), ref)["rel_mse"]
            cells = []
            for w in args.widths:
                m = statfilter.compare(statfilter.Filter("hybrid", motion_compensation="off", mb_half_width=w)(noisy), ref)
                cells.append(f"{m['rel_mse'] / mb:.2f}x, {m['rel_mse_moving']:.4f}")
            print(f"| {scene} | {level.name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
