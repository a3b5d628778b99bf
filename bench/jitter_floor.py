#!/usr/bin/env python3
"""The still-scene jitter the truth itself has, beside OIDN's and `--quality high`'s.

The jitter figure (statfilter compare: mean |second temporal difference| of tone-mapped luminance
over the pixels whose reference barely changes) counts real change as well as noise: a light that
swings over the shot has second differences of its own. On a scene whose geometry does not move
(its renderer's motion vectors are zero everywhere), every pixel's light is the shot's light level
times its own mean: the model S(t) = mean over time of the reference x the reference's mean level at
frame t / its mean level. Its jitter is a floor no denoiser that keeps the light can go below; the
quality target "jitter <= 0.2x OIDN's" cannot be met where the floor is above it.

Scenes with moving geometry are listed without a floor (the model does not hold there). `high` is
read from docs/quality_targets.json (bench/quality_targets.py). Usage:
    python3 bench/jitter_floor.py [--cli build-release/tools/statfilter] [--data ../shared/data]
"""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import bench_arguments, import_statfilter, scenes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main():
    args = bench_arguments(__doc__.splitlines()[0], "quality_targets.md").parse_args()
    sf = import_statfilter(args.cli)
    import numpy as np
    high = {}
    targets = ROOT / "docs" / "quality_targets.json"
    if targets.exists():
        for row in json.loads(targets.read_text()):
            if row["label"] in ("high", "OIDN"):
                high[(row["scene"], row["level"], row["label"])] = row["jitter"]
    print("| scene | level | geometry | OIDN's jitter | floor (the light model) | floor / OIDN | `high` / OIDN |\n"
          "|---|---|---|---|---|---|---|")
    for scene, levels in scenes(Path(args.data)):
        ref = sf.read_sequence(str(scene / "ref" / "indirect.####.exr"))
        vectors = scene / "aux" / "vector.0001.exr"
        still = False
        if vectors.exists():
            v = sf.read_sequence(str(scene / "aux" / "vector.####.exr"))
            still = float(np.abs(v).max()) < 0.05
        floor = None
        if still:
            level = ref.astype(np.float64).mean(axis=(1, 2, 3))
            model = (ref.astype(np.float64).mean(axis=0)[None] * (level / level.mean())[:, None, None, None])
            floor = sf.compare(model.astype(np.float32), ref)["jitter"]
        for lv in levels:
            noisy = sf.read_sequence(str(scene / lv / "indirect.####.exr"))
            oidn = sf.compare(sf.Filter("oidn", quality="high")(noisy), ref)["jitter"]
            h = high.get((scene.name, lv, "high"))
            o = high.get((scene.name, lv, "OIDN"))
            cells = [scene.name, lv, "still" if still else "moving", f"{oidn:.5f}",
                     f"{floor:.5f}" if floor is not None else "-",
                     f"{floor / oidn:.3f}" if floor is not None else "-",
                     f"{h / o:.3f}" if h is not None and o else "-"]
            print("| " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
