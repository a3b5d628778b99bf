#!/usr/bin/env python3
"""Leave-one-scene-out: the numerics' tunable constants, and every method's light, on real renders.

For every scene under the data folder (scene/spp*/indirect.####.exr beside scene/ref/...):

1. Each tunable constant of the value transform (transform_scale, firefly_z) is picked on all scenes
   but one, by the geometric mean of relMSE over their levels, and reported on the one left out
   (held-out) beside its figure with the value picked on every scene (in-sample).
2. Every method and preset is run through the CLI (`statfilter denoise ... --float`), scored with
   `statfilter compare --json` (relMSE overall and inside the moving region), and its output read
   back for the mean bias (mean(output) / mean(input) - 1, over the shot) and the share of negative
   samples. With --before CLI (a statfilter built from an earlier commit) the same runs are made
   with it, side by side.

Writes the tables between the results markers of docs/quality.md (--doc) and the raw figures to
docs/quality.json. A few minutes on two cores. Usage:
    python3 bench/loso.py [--cli build/tools/statfilter] [--before OLD_CLI] [--data ../shared/data]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- results: written by bench/loso.py -->", "<!-- end of results -->"
LEVELS = ("spp0004", "spp0016", "spp0064")

# label -> CLI options (after `denoise IN OUT`).
METHODS = {
    "pca": ["--method", "pca"],
    "error-threshold": ["--method", "error-threshold"],
    "moving-basis": ["--method", "moving-basis"],
    "hybrid": ["--method", "hybrid"],
    "diffusion": ["--method", "diffusion"],
    "fast": ["--quality", "fast"],
    "balanced": ["--quality", "balanced"],
    "high": ["--quality", "high"],
}

# Tunable constants: name -> (grid, the methods whose relMSE picks it).
TUNABLE = {
    "transform_scale": (["0.5", "1", "2", "4"], ["pca", "error-threshold"]),
    "firefly_z": (["0", "5", "8", "12"], ["pca", "error-threshold"]),
}


def scenes(data):
    """(scene folder, its levels) of every scene under `data`: one folder, or several separated by
    commas (the shared renders and a validation scene's folder: bench/validation_scene.py)."""
    out = []
    for folder in str(data).split(","):
        for scene in sorted(p for p in Path(folder).iterdir() if (p / "ref").is_dir()):
            levels = [lv for lv in LEVELS if any((scene / lv).glob("indirect.*.exr"))]
            if levels:
                out.append((scene, levels))
    names = [scene.name for scene, _ in out]
    if len(set(names)) != len(names):
        sys.exit(f"two scenes of the same name under {data}: {sorted(n for n in set(names) if names.count(n) > 1)}")
    return out


def geomean(values):
    values = [v for v in values if v > 0]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else float("nan")


class Runner:
    def __init__(self, cli, work, statfilter):
        self.cli, self.work, self.sf = cli, Path(work), statfilter
        self.means = {}  # input pattern -> mean of the input

    def mean_of(self, pattern):
        if pattern not in self.means:
            self.means[pattern] = float(self.sf.read_sequence(pattern).astype("float64").mean())
        return self.means[pattern]

    def run(self, scene, level, options):
        noisy = str(scene / level / "indirect.####.exr")
        ref = str(scene / "ref" / "indirect.####.exr")
        out_dir = self.work / "out"
        out_dir.mkdir(exist_ok=True)
        for f in out_dir.iterdir():
            f.unlink()
        out = str(out_dir / "den.####.exr")
        print(f"{scene.name} {level} {' '.join(options)}", file=sys.stderr, flush=True)
        subprocess.run([self.cli, "denoise", noisy, out, "--float", "--quiet", *options], check=True)
        scores = json.loads(subprocess.run([self.cli, "compare", out, ref, "--json"], check=True,
                                           capture_output=True, text=True).stdout)
        result = self.sf.read_sequence(out).astype("float64")
        return {"rel_mse": scores["rel_mse"], "rel_mse_moving": scores["rel_mse_moving"], "jitter": scores["jitter"],
                "moving_fraction": scores["moving_fraction"],
                "bias": result.mean() / self.mean_of(noisy) - 1, "negative": float((result < 0).mean())}


def tune(runner, found):
    """For each constant: the value picked on every scene but one, scored on that one."""
    report = {}
    for name, (grid, methods) in TUNABLE.items():
        # score[value][scene] = geometric mean of relMSE over the scene's levels and the methods.
        score = {v: {} for v in grid}
        for value in grid:
            for scene, levels in found:
                figures = [runner.run(scene, lv, METHODS[m] + ["--" + name, value])["rel_mse"]
                           for lv in levels for m in methods]
                score[value][scene.name] = geomean(figures)
        overall, rows = leave_one_scene_out(score, grid, [s.name for s, _ in found], "rel_mse")
        report[name] = {"grid": grid, "methods": methods, "overall": overall, "rows": rows, "score": score}
    return report


def leave_one_scene_out(score, grid, names, figure):
    """score[value][scene] (lower is better): the value picked on every scene, and for each scene held
    out the value picked on the others with the held-out scene's figure beside its in-sample one."""
    overall = min(grid, key=lambda v: geomean([score[v][n] for n in names]))
    rows = []
    for held in names:
        rest = [n for n in names if n != held]
        picked = min(grid, key=lambda v: geomean([score[v][n] for n in rest]))
        rows.append({"held_out": held, "picked": picked, "held_out_" + figure: score[picked][held],
                     "in_sample_value": overall, "in_sample_" + figure: score[overall][held]})
    return overall, rows


def bench_arguments(description, doc):
    """The command line the quality benches share: the CLI measured, the data folder, the document."""
    p = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cli", default=str(ROOT / "build" / "tools" / "statfilter"))
    p.add_argument("--data", default=str(ROOT.parent / "shared" / "data"),
                   help="the scenes' folder, or several separated by commas")
    p.add_argument("--doc", default=str(ROOT / "docs" / doc))
    return p


def import_statfilter(cli):
    """The Python package of the build being measured (staged beside its CLI)."""
    sys.path.insert(0, str(Path(cli).resolve().parents[1] / "python"))
    import statfilter
    return statfilter


def evaluate(runner, found, methods):
    rows = []
    for label in methods:
        for scene, levels in found:
            for lv in levels:
                r = runner.run(scene, lv, METHODS[label])
                rows.append({"method": label, "scene": scene.name, "level": lv, **r})
    return rows


def summary(rows, methods):
    out = {}
    for m in methods:
        mine = [r for r in rows if r["method"] == m]
        if mine:
            out[m] = {"rel_mse": geomean([r["rel_mse"] for r in mine]),
                      "rel_mse_moving": geomean([r["rel_mse_moving"] for r in mine]),
                      "worst_bias": max((r["bias"] for r in mine), key=abs),
                      "negative": max(r["negative"] for r in mine)}
    return out


def tables(tuning, after, before, methods):
    text = "### Tunable constants, leave-one-scene-out\n\n"
    for name, t in tuning.items():
        text += (f"`{name}`, grid {', '.join(t['grid'])}, picked by the geometric mean of relMSE of "
                 f"{' and '.join(t['methods'])} over the levels; picked on all four scenes: "
                 f"**{t['overall']}**.\n\n| held-out scene | picked on the other three | relMSE held out | "
                 f"relMSE with the all-scene pick (in-sample) |\n|---|---|---|---|\n")
        for r in t["rows"]:
            text += (f"| {r['held_out']} | {r['picked']} | {r['held_out_rel_mse']:.4f} | "
                     f"{r['in_sample_rel_mse']:.4f} |\n")
        text += "\n"
    a, b = summary(after, methods), summary(before, methods) if before else {}
    text += ("### Every method and preset, over the scenes and levels\n\n"
             "Geometric means of relMSE (overall and in the moving region) over every scene and level; "
             "the bias with the largest magnitude and the largest share of negative samples over them.\n\n")
    if b:
        text += ("| method | relMSE before | after | moving before | after | worst bias before | after | "
                 "negative before | after |\n|---|---|---|---|---|---|---|---|---|\n")
        for m in a:
            x, y = b.get(m), a[m]
            if not x:
                continue
            text += (f"| {m} | {x['rel_mse']:.4f} | {y['rel_mse']:.4f} | {x['rel_mse_moving']:.4f} | "
                     f"{y['rel_mse_moving']:.4f} | {100 * x['worst_bias']:+.2f}% | {100 * y['worst_bias']:+.2f}% | "
                     f"{100 * x['negative']:.3f}% | {100 * y['negative']:.3f}% |\n")
    else:
        text += "| method | relMSE | moving | worst bias | negative |\n|---|---|---|---|---|\n"
        for m, y in a.items():
            text += (f"| {m} | {y['rel_mse']:.4f} | {y['rel_mse_moving']:.4f} | {100 * y['worst_bias']:+.2f}% | "
                     f"{100 * y['negative']:.3f}% |\n")
    text += "\n### Per scene and level (after)\n\n| method | scene | level | relMSE | moving | bias | negative |\n"
    text += "|---|---|---|---|---|---|---|\n"
    for r in after:
        text += (f"| {r['method']} | {r['scene']} | {r['level']} | {r['rel_mse']:.4f} | {r['rel_mse_moving']:.4f} | "
                 f"{100 * r['bias']:+.2f}% | {100 * r['negative']:.3f}% |\n")
    return text


def main():
    p = bench_arguments(__doc__, "quality.md")
    p.add_argument("--before", help="a statfilter CLI built from an earlier commit, run side by side")
    p.add_argument("--methods", default=",".join(METHODS), help="comma list of the methods and presets to score")
    p.add_argument("--no-tune", action="store_true", help="skip the leave-one-scene-out of the constants")
    args = p.parse_args()
    statfilter = import_statfilter(args.cli)

    found = scenes(Path(args.data))
    if not found:
        sys.exit(f"no scenes under {args.data}")
    methods = [m for m in args.methods.split(",") if m]
    has_oidn = any(p.get("name") == "oidn" and p.get("available") for p in statfilter.plugins())
    if not has_oidn:
        methods = [m for m in methods if m != "high"]  # without OIDN it is the hybrid
    with tempfile.TemporaryDirectory() as work:
        runner = Runner(args.cli, work, statfilter)
        tuning = {} if args.no_tune else tune(runner, found)
        after = evaluate(runner, found, methods)
        before = evaluate(Runner(args.before, work, statfilter), found, methods) if args.before else []
    doc = Path(args.doc)
    text = doc.read_text() if doc.exists() else f"{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    doc.write_text(head + BEGIN + "\n\n" + tables(tuning, after, before, methods) + "\n" + END + tail)
    doc.with_suffix(".json").write_text(json.dumps({"tuning": tuning, "after": after, "before": before}, indent=1) + "\n")
    print(f"wrote {doc} and {doc.with_suffix('.json')}")


if __name__ == "__main__":
    main()
