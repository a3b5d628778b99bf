#!/usr/bin/env python3
"""The quality targets against Intel Open Image Denoise, on every scene and level of the data folder.

Beside OIDN alone (the oidn plugin at quality high, colour only), in one run: `--quality high`,
`--prefilter oidn` (its default temporal method), `--quality balanced`, and the other presets and
methods for the light and the sign of the output. Each is run through the CLI (`statfilter denoise
... --float`) and scored with `statfilter compare --json` against the scene's reference (bench/loso.py's
runner). The targets checked (from the quality issue's done-when):

- high and --prefilter oidn: relMSE <= 0.85x OIDN's at 4 and 16 spp, <= 1.0x at 64 spp; relMSE inside
  the moving region <= 1.0x OIDN's (scenes with a moving region); still-scene jitter <= 0.2x OIDN's;
- balanced: relMSE <= 1.0x OIDN's at 4 and 16 spp;
- every configuration: |mean(output) / mean(input) - 1| <= 0.5%, no negative sample.

Writes the tables between the results markers of docs/quality_targets.md (--doc) and the raw figures
to docs/quality_targets.json. About ten minutes on two cores. Usage:
    python3 bench/quality_targets.py [--cli build/tools/statfilter] [--data ../shared/data]
"""

import json
import math
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import Runner, bench_arguments, geomean, import_statfilter, scenes  # noqa: E402

BEGIN, END = "<!-- results: written by bench/quality_targets.py -->", "<!-- end of results -->"

CONFIGS = {
    "OIDN": ["--method", "oidn"],
    "high": ["--quality", "high"],
    "prefilter oidn": ["--prefilter", "oidn"],
    "balanced": ["--quality", "balanced"],
    "fast": ["--quality", "fast"],
    "pca": ["--method", "pca"],
    "error-threshold": ["--method", "error-threshold"],
    "hybrid": ["--method", "hybrid"],
    "moving-basis": ["--method", "moving-basis"],
    "diffusion": ["--method", "diffusion"],
}
SPP = {"spp0004": 4, "spp0016": 16, "spp0064": 64}


def relmse_limit(label, level):
    if label in ("high", "prefilter oidn"):
        return 0.85 if SPP[level] < 64 else 1.0
    if label == "balanced" and SPP[level] < 64:
        return 1.0
    return None


def checks(label, level, fig, oidn):
    """(target, ratio or value, limit, passed) for one run."""
    out = []
    limit = relmse_limit(label, level)
    if limit is not None:
        r = fig["rel_mse"] / oidn["rel_mse"]
        out.append(("relMSE / OIDN", r, limit, r <= limit))
    if label in ("high", "prefilter oidn"):
        if fig["moving_fraction"] > 0 and oidn["rel_mse_moving"] > 0:
            r = fig["rel_mse_moving"] / oidn["rel_mse_moving"]
            out.append(("moving relMSE / OIDN", r, 1.0, r <= 1.0))
        if oidn["jitter"] > 0:
            r = fig["jitter"] / oidn["jitter"]
            out.append(("jitter / OIDN", r, 0.2, r <= 0.2))
    if label != "OIDN":
        out.append(("|bias|", abs(fig["bias"]), 0.005, abs(fig["bias"]) <= 0.005))
        out.append(("negative", fig["negative"], 0.0, fig["negative"] == 0.0))
    return [(name, float(value), limit, bool(ok)) for name, value, limit, ok in out]


def fmt(v):
    return "%.3g" % v if abs(v) >= 1e-3 or v == 0 else "%.1e" % v


def write_doc(doc, rows, command, note=""):
    levels = sorted({r["level"] for r in rows}, key=lambda lv: SPP[lv])
    labels = [lb for lb in CONFIGS if lb != "OIDN"]
    lines = [BEGIN, "", "Command: `%s`%s" % (command, note), ""]
    lines += ["Geometric mean over the scenes of relMSE / OIDN's (OIDN: the oidn plugin, quality high, colour only):", ""]
    lines += ["| | " + " | ".join("%d spp" % SPP[lv] for lv in levels) + " |", "|---|" + "---|" * len(levels)]
    for lb in labels:
        cells = [fmt(geomean([r["ratio"] for r in rows if r["label"] == lb and r["level"] == lv])) for lv in levels]
        lines.append("| `%s` | %s |" % (lb, " | ".join(cells)))
    failed = [(r, c) for r in rows for c in r["checks"] if not c[3]]
    passed = sum(1 for r in rows for c in r["checks"] if c[3])
    lines += ["", "Targets: %d checks pass, %d fail." % (passed, len(failed)), ""]
    lines += ["| scene | spp | configuration | relMSE | / OIDN | moving / OIDN | jitter / OIDN | bias | negative | fails |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    oidn = {(r["scene"], r["level"]): r for r in rows if r["label"] == "OIDN"}
    for r in rows:
        o = oidn[(r["scene"], r["level"])]
        mv = r["rel_mse_moving"] / o["rel_mse_moving"] if r["moving_fraction"] > 0 and o["rel_mse_moving"] > 0 else float("nan")
        jt = r["jitter"] / o["jitter"] if o["jitter"] > 0 else float("nan")
        fails = ", ".join(c[0] for c in r["checks"] if not c[3])
        lines.append("| %s | %d | `%s` | %s | %s | %s | %s | %+.2f%% | %s | %s |" % (
            r["scene"], SPP[r["level"]], r["label"], fmt(r["rel_mse"]), fmt(r["ratio"]),
            "-" if math.isnan(mv) else fmt(mv), "-" if math.isnan(jt) else fmt(jt), 100 * r["bias"],
            fmt(r["negative"]), fails or "-"))
    lines += ["", END]
    text = doc.read_text() if doc.exists() else ""
    block = "\n".join(lines)
    if BEGIN in text and END in text:
        text = text[:text.index(BEGIN)] + block + text[text.index(END) + len(END):]
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    doc.write_text(text)


def main():
    p = bench_arguments(__doc__, "quality_targets.md")
    p.add_argument("--configs", default=",".join(CONFIGS), help="comma list of the configurations to run")
    args = p.parse_args()
    statfilter = import_statfilter(args.cli)
    wanted = ["OIDN"] + [c for c in args.configs.split(",") if c != "OIDN"]
    rows = []
    with tempfile.TemporaryDirectory() as work:
        runner = Runner(args.cli, work, statfilter)
        for scene, levels in scenes(Path(args.data)):
            for lv in levels:
                oidn = None
                for label in wanted:
                    fig = runner.run(scene, lv, CONFIGS[label])
                    oidn = oidn or fig
                    rows.append(dict(fig, scene=scene.name, level=lv, label=label,
                                     ratio=fig["rel_mse"] / oidn["rel_mse"], checks=checks(label, lv, fig, oidn)))
    command = "python3 bench/quality_targets.py" + ("" if args.configs == ",".join(CONFIGS) else " --configs " + args.configs)
    if args.data != p.get_default("data"):  # named by its folders' names: no path of this machine in the docs
        command += " --data " + ",".join(Path(d).name for d in args.data.split(","))
    doc = Path(args.doc)
    # A run of some configurations keeps the others' rows from the last run's figures.
    kept, note = [], ""
    if doc.with_suffix(".json").exists() and args.configs != ",".join(CONFIGS):
        kept = [r for r in json.loads(doc.with_suffix(".json").read_text()) if r["label"] not in wanted]
        if kept:
            note = " (the other configurations' rows kept from the run before, %s)" % doc.with_suffix(".json").name
    order = list(CONFIGS)
    rows = sorted(rows + kept, key=lambda r: (r["scene"], SPP[r["level"]],
                                              order.index(r["label"]) if r["label"] in order else len(order)))
    write_doc(doc, rows, command, note)
    doc.with_suffix(".json").write_text(json.dumps(rows, indent=1) + "\n")
    failed = sum(1 for r in rows for c in r["checks"] if not c[3])
    print("%s: %d checks fail" % (doc, failed))


if __name__ == "__main__":
    main()
