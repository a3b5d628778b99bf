#!/usr/bin/env python3
"""What a temporal pass adds to Intel Open Image Denoise, measured on real renders.

For every scene and noise level under the data folder (scene/spp*/indirect.####.exr with
scene/ref/indirect.####.exr): OIDN alone (the oidn plugin, and with the albedo/normal guides when
scene/aux has them), OIDN then each temporal filter (prefilter=oidn), and the temporal filters
without OIDN. Frames are in memory; time is the filter call through the C ABI (best of --repeats),
stated with the thread count. Metrics from statfilter.compare (relMSE overall and inside the moving
region, flicker, still-scene jitter) and SSIM from bench/ssim.py. The tables replace the part of
docs/oidn.md between the results markers. Usage:
    python3 bench/oidn_benchmark.py [--data DIR] [--build DIR] [--doc FILE] [--repeats N]
"""

import argparse
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))
from ssim import ssim  # noqa: E402

BEGIN, END = "<!-- results: written by bench/oidn_benchmark.py -->", "<!-- end of results -->"
TEMPORAL = ["pca", "error-threshold", "moving-basis", "hybrid"]


def scenes(data):
    for scene in sorted(p for p in data.iterdir() if (p / "ref").is_dir()):
        for level in sorted(scene.glob("spp*")):
            if any(level.glob("indirect.*.exr")):
                yield scene, level


def configs(statfilter, scene):
    """(label, filter name, parameters) for one scene."""
    have = set(statfilter.filters())
    out = [("OIDN alone", "oidn", {})]
    aux = scene / "aux"
    if (aux / "albedo.0001.exr").exists() and (aux / "normal.0001.exr").exists():
        out.append(("OIDN + albedo/normal guides", "oidn",
                    {"albedo": str(aux / "albedo.####.exr"), "normal": str(aux / "normal.####.exr")}))
    # OIDN first, then the temporal filter (the hybrid's own default is the other order).
    out += [("OIDN then " + m, m, {"prefilter": "oidn", "prefilter_order": "first"}) for m in TEMPORAL if m in have]
    out += [(m + " (no OIDN)", m, {}) for m in TEMPORAL if m in have]
    return out


def run(statfilter, name, params, noisy, repeats):
    best, out = float("inf"), None
    for _ in range(repeats):
        f = statfilter.Filter(name, **params)
        t0 = time.perf_counter()
        out = f(noisy)
        best = min(best, time.perf_counter() - t0)
    return out, best


def table(rows):
    head = "| method | relMSE | relMSE moving | SSIM | flicker | jitter | time (s) |\n|---|---|---|---|---|---|---|\n"
    return head + "".join(
        "| %s | %.4f | %.4f | %.4f | %.4f | %.4f | %s |\n" % (
            r["label"], r["rel_mse"], r["rel_mse_moving"], r["ssim"], r["flicker"], r["jitter"],
            "-" if r["seconds"] is None else "%.2f" % r["seconds"])
        for r in rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--doc", type=Path, default=ROOT / "docs" / "oidn.md")
    ap.add_argument("--repeats", type=int, default=2)
    args = ap.parse_args()
    sys.path.insert(0, str(args.build / "python"))
    import statfilter

    oidn = [p for p in statfilter.plugins() if p["name"] == "oidn"]
    if not oidn or not oidn[0]["available"]:
        sys.exit("oidn_benchmark: the oidn plugin cannot run: %s" % (oidn[0]["problem"] if oidn else "not found"))
    sections, summary = [], []
    for scene, level in scenes(args.data):
        noisy = statfilter.read_sequence(str(level / "indirect.####.exr"))
        ref = statfilter.read_sequence(str(scene / "ref" / "indirect.####.exr"))
        rows = [dict(label="noisy input", seconds=None, ssim=ssim(noisy, ref), **statfilter.compare(noisy, ref))]
        for label, name, params in configs(statfilter, scene):
            out, seconds = run(statfilter, name, params, noisy, args.repeats)
            rows.append(dict(label=label, seconds=seconds, ssim=ssim(out, ref), **statfilter.compare(out, ref)))
            print("%s %s %-32s relMSE %.4f moving %.4f jitter %.4f %.2fs" % (
                scene.name, level.name, label, rows[-1]["rel_mse"], rows[-1]["rel_mse_moving"], rows[-1]["jitter"],
                seconds), flush=True)
        f, h, w, c = noisy.shape
        sections.append("### %s, %s (%d frames of %d x %d)\n\n%s" % (scene.name, level.name, f, w, h, table(rows)))
        alone = next(r for r in rows if r["label"] == "OIDN alone")
        for r in rows:
            if r["label"].startswith("OIDN then"):
                summary.append((scene.name, level.name, r["label"][len("OIDN then "):],
                                r["rel_mse"] / alone["rel_mse"], r["rel_mse_moving"] / alone["rel_mse_moving"],
                                r["jitter"] / alone["jitter"], r["flicker"] / alone["flicker"]))

    try:
        from importlib import metadata
        oidn_version = "OIDN from the PyPI package pyoidn " + metadata.version("pyoidn")
    except Exception:  # noqa: BLE001 - not from pyoidn
        oidn_version = "OIDN found by the plugin's search"
    lines = ["Command: `python3 bench/oidn_benchmark.py --build %s` (data: %s; %d CPU threads; %s, %s)\n" % (
        os.path.relpath(args.build, ROOT),
        "the project's shared renders" if args.data.name == "data" else args.data.name, os.cpu_count(),
        oidn_version,
        # Only the file name: a machine's own paths do not belong in the docs.
        os.path.basename(os.environ.get("STATFILTER_OIDN_LIBRARY", "")) or "libOpenImageDenoise.so.2"),
        "### OIDN then a temporal filter, as a ratio to OIDN alone (below 1 is better)\n",
        "| scene | level | temporal filter | relMSE | relMSE moving | jitter | flicker |",
        "|---|---|---|---|---|---|---|"]
    lines += ["| %s | %s | %s | %.2f | %.2f | %.2f | %.2f |" % s for s in summary]
    results = "\n".join(lines) + "\n\n" + "\n".join(sections)
    text = args.doc.read_text() if args.doc.exists() else "# OIDN\n\n%s\n%s\n" % (BEGIN, END)
    if BEGIN not in text or END not in text:
        text += "\n%s\n%s\n" % (BEGIN, END)
    head, rest = text.split(BEGIN, 1)
    text = head + BEGIN + "\n" + results + "\n" + END + rest.split(END, 1)[1]
    args.doc.write_text(text)
    print("oidn_benchmark: wrote", args.doc)


if __name__ == "__main__":
    main()
