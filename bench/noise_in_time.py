#!/usr/bin/env python3
"""Noise that is the same in every frame (a renderer's fixed seed) against noise drawn afresh for each.

For every scene and level of the data folder: the `noise_in_time` figure the presets report (the
change of the noise from frame to frame against its spread across the frame) on the shot as rendered
(a seed per frame), and on a same-seed shot made from it: frame 1's noise, as it departs from frame
1's reference, added to every frame's reference (max(ref_t + noisy_1 - ref_1, 0); on a scene whose
geometry is still and whose light only scales, noisy_1 x the frame's light level instead, which is
what a fixed seed renders there). Beside them, relMSE of OIDN, `balanced`, `high` and the
single-frame diffusion filter on the same-seed shot, where no temporal filter can help. Prints a markdown table (docs/methods.md).
    python3 bench/noise_in_time.py [--cli build-release/tools/statfilter] [--data ../shared/data]
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import bench_arguments, import_statfilter, scenes  # noqa: E402


def main():
    args = bench_arguments(__doc__.splitlines()[0], "methods.md").parse_args()
    sf = import_statfilter(args.cli)
    import numpy as np

    def denoise(noisy, out, *options):
        proc = subprocess.run([args.cli, "denoise", noisy, out, "--float", "--json", *options], check=True,
                              capture_output=True, text=True)
        return json.loads(proc.stdout)["results"]

    def rel_mse(out, ref):
        proc = subprocess.run([args.cli, "compare", out, ref, "--json"], check=True, capture_output=True, text=True)
        return json.loads(proc.stdout)["rel_mse"]

    print("| scene | level | as rendered | same seed | same seed: OIDN | `balanced` | `high` | `diffusion` |\n"
          "|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for scene, levels in scenes(Path(args.data)):
            ref_pattern = str(scene / "ref" / "indirect.####.exr")
            ref = sf.read_sequence(ref_pattern).astype(np.float64)
            vectors = scene / "aux" / "vector.0001.exr"
            still = vectors.exists() and float(np.abs(sf.read_sequence(
                str(scene / "aux" / "vector.####.exr"))).max()) < 0.05
            for level in levels:
                pattern = str(scene / level / "indirect.####.exr")
                as_rendered = denoise(pattern, str(work / "a.####.exr"), "--quality", "fast")["noise_in_time"]
                noisy = sf.read_sequence(pattern).astype(np.float64)
                if still:
                    light = ref.mean(axis=(1, 2, 3))
                    fixed = noisy[0][None] * (light / light[0])[:, None, None, None]
                else:
                    fixed = np.maximum(ref + (noisy[0] - ref[0])[None], 0)
                same = str(work / "same.####.exr")
                sf.write_sequence(same, fixed.astype(np.float32), pixel_type="float")
                figure = denoise(same, str(work / "f.####.exr"), "--quality", "fast")["noise_in_time"]
                cells = [f"{as_rendered:.3f}", f"{figure:.3f}"]
                oidn = None
                for options in (["--method", "oidn"], ["--quality", "balanced"], ["--quality", "high"],
                                ["--method", "diffusion"]):
                    out = str(work / "o.####.exr")
                    denoise(same, out, *options)
                    r = rel_mse(out, ref_pattern)
                    oidn = oidn or r
                    cells.append(f"{r:.4f}" if options[1] == "oidn" else f"{r:.4f} ({r / oidn:.2f}x)")
                print(f"| {scene.name} | {level} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
