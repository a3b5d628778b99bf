#!/usr/bin/env python3
"""Leave-one-scene-out of each preset's own constants: held-out figures beside in-sample ones.

A preset's defaults were chosen on the scenes of the data folder; a constant that fits them and not
other shots shows here. For each preset and each of its constants (one at a time, the others at their
defaults), every value of a small grid around the default is run on every scene and level through the
CLI and scored against the references (bench/loso.py's runner). Then, for each scene held out, the
value with the lowest geometric mean of relMSE / OIDN's over the other scenes' levels is picked, and
the held-out scene's figure with that pick is reported beside its figure with the value picked on
every scene (in-sample). The done-when of the quality issue: no held-out figure more than 10% worse
than its in-sample one.

`balanced` is run as the hybrid with its preset settings (`--method hybrid --mc_flow ultrafast
--mc_half_width 4`: the same numbers where something moves, and the same global PCA where nothing
does), so that the hybrid's constants can be set. OIDN (quality high, colour only) is run once per
scene and level for the ratios.

Writes the tables between the results markers of docs/preset_loso.md (--doc) and the raw figures to
docs/preset_loso.json; a preset not swept (--presets) keeps its table and figures from the last run. Usage:
    python3 bench/preset_loso.py [--cli build/tools/statfilter] [--data ../shared/data] [--presets balanced,high]
"""

import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import Runner, bench_arguments, geomean, import_statfilter, leave_one_scene_out, scenes  # noqa: E402

BEGIN, END = "<!-- results: written by bench/preset_loso.py -->", "<!-- end of results -->"

BALANCED = ["--method", "hybrid", "--mc_flow", "ultrafast"]  # --mc_half_width 4 unless swept
# preset -> (its CLI options, {constant: (grid, default)})
PRESETS = {
    "balanced": (BALANCED, {
        "mc_half_width": (["2", "4", "8"], "4"),
        "mc_sigma": (["0.05", "0.1", "0.2"], "0.1"),
        "mc_dilate": (["2", "4", "8"], "4"),
        "change_z": (["3", "5", "8"], "5"),
        "change_z_grow": (["0", "3", "4"], "3"),
    }),
    "high": (["--quality", "high"], {
        "prefilter_order": (["first", "last"], "last"),
        "prefilter_trust_tile": (["8", "16", "32"], "16"),
        "prefilter_trust_pool": (["1", "2", "4"], "2"),
        "prefilter_trust_probe": (["0.02", "0.05", "0.2"], "0.05"),
    }),
}


def options_for(preset, name, value):
    base, constants = PRESETS[preset]
    out = list(base)
    if preset == "balanced" and name != "mc_half_width":
        out += ["--mc_half_width", "4"]
    return out + ["--" + name, value]


def sweep(runner, found, oidn, preset):
    """score[name][value][scene] = geometric mean over the scene's levels of relMSE / OIDN's."""
    _, constants = PRESETS[preset]
    score, cache = {}, {}
    for name, (grid, default) in constants.items():
        score[name] = {}
        for value in grid:
            opts = options_for(preset, name, value)
            # Every constant at its default is one configuration: run it once.
            key = tuple(opts) if value != default else ("default",)
            if key not in cache:
                cache[key] = {(s.name, lv): runner.run(s, lv, opts)["rel_mse"] for s, levels in found for lv in levels}
            figures = cache[key]
            score[name][value] = {s.name: geomean([figures[(s.name, lv)] / oidn[(s.name, lv)] for lv in levels])
                                  for s, levels in found}
    return score


def tables(report, commands):
    text = ""
    for preset, constants in report.items():
        text += f"### `{preset}`\n\nCommand: `{commands[preset]}`\n\n"
        text += ("| constant | default | picked on all scenes | held-out scene | picked on the others | held out: relMSE / OIDN "
                 "| in-sample pick: relMSE / OIDN | held-out / in-sample |\n|---|---|---|---|---|---|---|---|\n")
        for name, t in constants.items():
            for r in t["rows"]:
                text += (f"| `{name}` | {t['default']} | {t['overall']} | {r['held_out']} | {r['picked']} | "
                         f"{r['held_out_ratio']:.3f} | {r['in_sample_ratio']:.3f} | "
                         f"{r['held_out_ratio'] / r['in_sample_ratio']:.3f} |\n")
        worst = max(r["held_out_ratio"] / r["in_sample_ratio"] for t in constants.values() for r in t["rows"])
        text += f"\nWorst held-out / in-sample over its constants and scenes: **{worst:.3f}**.\n\n"
    return text


def main():
    p = bench_arguments(__doc__, "preset_loso.md")
    p.add_argument("--presets", default=",".join(PRESETS), help="comma list of the presets to sweep")
    args = p.parse_args()
    statfilter = import_statfilter(args.cli)

    found = scenes(Path(args.data))
    if len(found) < 2:
        sys.exit("leave-one-scene-out needs two scenes or more under " + args.data)
    with tempfile.TemporaryDirectory() as work:
        runner = Runner(args.cli, work, statfilter)
        oidn = {(s.name, lv): runner.run(s, lv, ["--method", "oidn"])["rel_mse"] for s, levels in found for lv in levels}
        report = {}
        for preset in args.presets.split(","):
            score = sweep(runner, found, oidn, preset)
            report[preset] = {}
            for name, (grid, default) in PRESETS[preset][1].items():
                overall, rows = leave_one_scene_out(score[name], grid, [s.name for s, _ in found], "ratio")
                report[preset][name] = {"grid": grid, "default": default, "overall": overall, "rows": rows,
                                        "score": score[name]}
    doc = Path(args.doc)
    # The presets not swept this time keep their tables from the last run, and each says what made it.
    command = "python3 bench/preset_loso.py" + ("" if args.presets == ",".join(PRESETS) else f" --presets {args.presets}")
    commands = {preset: command for preset in report}
    previous = doc.with_suffix(".json")
    if previous.exists():
        kept = json.loads(previous.read_text())
        for preset in PRESETS:
            if preset not in report and preset in kept.get("results", {}):
                report[preset] = kept["results"][preset]
                commands[preset] = kept["commands"][preset]
    report = {preset: report[preset] for preset in PRESETS if preset in report}
    text = doc.read_text()
    head, rest = text.split(BEGIN)
    _, tail = rest.split(END)
    doc.write_text(head + BEGIN + "\n\n" + tables(report, commands) + END + tail)
    previous.write_text(json.dumps({"commands": commands, "results": report}, indent=1) + "\n")
    print(tables(report, commands))


if __name__ == "__main__":
    main()
