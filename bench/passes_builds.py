#!/usr/bin/env python3
"""Two builds of the CLI side by side on the shared renders with the renderer's passes given: relMSE
overall and in the moving region, wall seconds and peak RSS of each, for every scene, level and
configuration (the vectors; the albedo and normal passes; balanced, the hybrid and high). For a change
that should not move a number (a new path for the same arithmetic), every row should say "same".
Usage:
    python3 bench/passes_builds.py --before OLD/statfilter --after NEW/statfilter [--data DIR]
        [--scenes a,b] [--levels 0004,0016] [--configs balanced+vec,...]
"""

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = {
    "balanced+vec": ["--quality", "balanced", "--vectors", "{aux}/vector.####.exr"],
    "hybrid+vec": ["--method", "hybrid", "--vectors", "{aux}/vector.####.exr"],
    "hybrid+alb+nrm": ["--method", "hybrid", "--albedo", "{aux}/albedo.####.exr", "--normal", "{aux}/normal.####.exr"],
    "balanced+alb+nrm": ["--quality", "balanced", "--albedo", "{aux}/albedo.####.exr", "--normal", "{aux}/normal.####.exr"],
    "high+vec": ["--quality", "high", "--vectors", "{aux}/vector.####.exr"],
}


def run(cli, noisy, ref, out, args):
    """(relMSE, relMSE moving, wall s, peak MiB) of one run."""
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "%M", cli, "denoise", noisy, out, "--quiet", "--overwrite"] + args,
                          capture_output=True, text=True)
    if proc.returncode:
        raise SystemExit(f"{cli} failed: {proc.stderr[-400:]}")
    wall = time.perf_counter() - start
    peak = int(proc.stderr.strip().split()[-1]) / 1024
    cmp = subprocess.run([cli, "compare", out, ref, "--json"], capture_output=True, text=True, check=True)
    j = json.loads(cmp.stdout)
    return j["rel_mse"], j["rel_mse_moving"], wall, peak


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True)
    parser.add_argument("--after", required=True)
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--scenes", default="cornell_moving,fast_ball,camera_pan,cornell_light")
    parser.add_argument("--levels", default="0004,0016,0064")
    parser.add_argument("--configs", default=",".join(CONFIGS))
    args = parser.parse_args()
    print("| scene | spp | configuration | relMSE before | after | moving before | after | wall before / after s | "
          "peak before / after MiB | |\n|---|---|---|---|---|---|---|---|---|---|")
    same = 0
    rows = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes.split(","):
            for level in args.levels.split(","):
                noisy = str(args.data / scene / f"spp{level}" / "indirect.####.exr")
                ref = str(args.data / scene / "ref" / "indirect.####.exr")
                for name in args.configs.split(","):
                    extra = [a.format(aux=args.data / scene / "aux") for a in CONFIGS[name]]
                    b = run(args.before, noisy, ref, f"{tmp}/b.####.exr", extra)
                    a = run(args.after, noisy, ref, f"{tmp}/a.####.exr", extra)
                    equal = f"{b[0]:.6g}" == f"{a[0]:.6g}" and f"{b[1]:.6g}" == f"{a[1]:.6g}"
                    same += equal
                    rows += 1
                    print(f"| {scene} | {int(level)} | {name} | {b[0]:.6g} | {a[0]:.6g} | {b[1]:.6g} | {a[1]:.6g} | "
                          f"{b[2]:.1f} / {a[2]:.1f} | {b[3]:.0f} / {a[3]:.0f} | {'same' if equal else 'DIFFERS'} |",
                          flush=True)
    print(f"\n{same} of {rows} rows the same to 6 significant digits")


if __name__ == "__main__":
    main()
