"""Writes docs/benchmarks.md and its plots from the benchmark rows."""

import datetime
import platform
from collections import defaultdict

DEFAULTS = {"pca": "pca auto log", "error-threshold": "error-threshold w9 t2",
            "moving-basis": "moving-basis h8 reconstruction rauto", "diffusion": "diffusion", "hybrid": "hybrid"}
COLORS = {"input": "black", "numpy": "grey", "pca": "tab:blue", "error-threshold": "tab:green",
          "moving-basis": "tab:orange", "diffusion": "tab:purple", "hybrid": "tab:red"}


def fmt(v, digits=4):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}f}" if abs(v) >= 1e-3 or v == 0 else f"{v:.2e}"
    return str(v)


def group(rows):
    out = defaultdict(list)
    for r in rows:
        out[(r["scene"], r["level"])].append(r)
    return out


def plot(rows, docs):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    files = []
    by_scene = defaultdict(list)
    for r in rows:
        by_scene[r["scene"]].append(r)
    for scene, scene_rows in sorted(by_scene.items()):
        levels = sorted({r["level"] for r in scene_rows})
        fig, axes = plt.subplots(1, len(levels), figsize=(5 * len(levels), 4.2), squeeze=False)
        for ax, level in zip(axes[0], levels):
            for r in (r for r in scene_rows if r["level"] == level and r["method"] != "input"):
                ax.scatter(max(r["compute_ms_per_frame"], 1e-3), r["rel_mse"], color=COLORS[r["method"]], s=18,
                           marker="*" if r["label"] in DEFAULTS.values() else "o")
            noisy = next(r for r in scene_rows if r["level"] == level and r["method"] == "input")
            ax.axhline(noisy["rel_mse"], color="black", lw=0.8, ls="--")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_title(f"{scene} {level}")
            ax.set_xlabel("compute time per frame (ms)")
            ax.set_ylabel("relMSE vs reference")
        handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=m) for m, c in COLORS.items() if m != "input"]
        handles.append(plt.Line2D([], [], ls="--", color="black", label="noisy input"))
        handles.append(plt.Line2D([], [], marker="*", ls="", color="k", label="default settings"))
        axes[0][-1].legend(handles=handles, fontsize=7, loc="upper right")
        fig.tight_layout()
        name = f"benchmark_{scene}.png"
        fig.savefig(docs / name, dpi=90)
        plt.close(fig)
        files.append(name)
    return files


def write(rows, production, docs, command, cores, motion=None, figure=None):
    grouped = group(rows)
    lines = ["# Benchmarks", "",
             f"Made by `{command}` on {datetime.date.today()} ({platform.machine()}, {cores} cores; "
             "OpenBLAS and every filter at the default thread count). Data: the Blender Cycles renders of "
             "the project's shared data (160 x 120, 32 frames), each noise level against its reference.",
             "",
             "Compute time is the filter alone through the C ABI on frames in memory (best of the repeats); "
             "CLI time adds reading and writing the EXR sequence; peak memory is the CLI's maximum resident "
             "set. At 160 x 120 fixed costs dominate, so throughput is measured on production-size frames "
             "below. Metrics follow DESIGN section 7: relMSE = mean((x - ref)^2 / (ref^2 + 0.01)); "
             "moving/static split the pixels by the reference's temporal std (> 3x / <= 3x the median); "
             "PSNR and SSIM on tonemapped x/(1+x) values (SSIM on luminance); flicker = mean |dx/dt - dref/dt|; "
             "jitter = mean |second temporal difference| of luminance on still pixels.", "",
             "## Headline: relMSE against the reference", "",
             "| scene | level | noisy | numpy pca auto | pca auto | (x lower) | error-threshold | moving-basis | "
             "hybrid | hybrid aux | C++ speed-up over numpy (same transform) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = {r["label"]: r for r in rs}
        noisy, npy = by["input (noisy)"], by["numpy pca auto"]
        pca, et, mb = by.get(DEFAULTS["pca"]), by.get(DEFAULTS["error-threshold"]), by.get(DEFAULTS["moving-basis"])
        same = by.get("pca auto none")  # the numpy yardstick has no transform: compare like with like
        speed = npy["compute_ms_per_frame"] / same["compute_ms_per_frame"] if same else None
        lines.append(f"| {scene} | {level} | {fmt(noisy['rel_mse'])} | {fmt(npy['rel_mse'])} | "
                     f"{fmt(pca['rel_mse']) if pca else '-'} | "
                     f"{fmt(noisy['rel_mse'] / pca['rel_mse'], 1) if pca else '-'} | "
                     f"{fmt(et['rel_mse']) if et else '-'} | {fmt(mb['rel_mse']) if mb else '-'} | "
                     f"{fmt(by['hybrid']['rel_mse']) if 'hybrid' in by else '-'} | "
                     f"{fmt(by['hybrid aux']['rel_mse']) if 'hybrid aux' in by else '-'} | "
                     f"{fmt(speed, 2)}x |")
    lines += ["", "## Moving region and still scene", "",
              "relMSE inside the moving region (reference temporal std > 3x the median) and outside it, and "
              "compute time relative to `pca auto` on the same frames.", "",
              "| scene | level | method | moving | static | time / pca |", "| --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = {r["label"]: r for r in rs}
        base = by.get(DEFAULTS["pca"])
        for label in [DEFAULTS["pca"], DEFAULTS["error-threshold"], DEFAULTS["moving-basis"], "diffusion", "hybrid",
                      "hybrid aux"]:
            if label in by and base:
                r = by[label]
                lines.append(f"| {scene} | {level} | {label} | {fmt(r['rel_mse_moving'])} | {fmt(r['rel_mse_static'])} | "
                             f"{fmt(r['compute_ms_per_frame'] / base['compute_ms_per_frame'], 2)}x |")
    if motion:
        lines += ["", "## Motion detectors against the true moving region", "",
                  "Each detector's region (alpha < 0.5; beta set in any frame) against the reference's moving "
                  "region.", "", "| scene | level | detector | flagged | precision | recall | IoU |",
                  "| --- | --- | --- | --- | --- | --- | --- |"]
        for m in motion:
            lines.append(f"| {m['scene']} | {m['level']} | {m['detector']} | {fmt(m['flagged'], 3)} | "
                         f"{fmt(m['precision'], 3)} | {fmt(m['recall'], 3)} | {fmt(m['iou'], 3)} |")
    if figure:
        lines += ["", "## Ghosting", "", "cornell_moving at 4 spp, frame 16, the rolling ball (tonemapped crops):",
                  "", f"![{figure}]({figure})"]
    lines += ["", "pca auto uses the default log transform; the speed-up compares `pca auto none`, the same "
              "computation as the NumPy yardstick (run in its own process with its best OpenBLAS settings, "
              "best of the repeats). The log transform's own cost is in the tables below "
              "(`pca auto log` against `pca auto none`)."]
    plots = plot(rows, docs)
    if plots:
        lines += ["", "## The speed/accuracy map", "",
                  "Every configuration as a point (stars: default settings; dashed: the noisy input)."]
        lines += [f"\n![{p}]({p})" for p in plots]
    lines += ["", "## Every configuration", ""]
    for (scene, level), rs in sorted(grouped.items()):
        lines += [f"### {scene} {level}", "",
                  "| configuration | relMSE | moving | static | PSNR | SSIM | flicker | jitter | compute ms/frame | "
                  "CLI s | peak MiB | result |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for r in rs:
            res = r.get("results") or {}
            result = ", ".join(f"{k} {fmt(v, 2)}" for k, v in res.items() if k in ("rank", "mean_rank"))
            if r["method"] == "numpy":
                result = f"rank {r['rank']}"
            lines.append(f"| {r['label']} | {fmt(r['rel_mse'])} | {fmt(r['rel_mse_moving'])} | "
                         f"{fmt(r['rel_mse_static'])} | {fmt(r['psnr'], 2)} | {fmt(r['ssim'])} | {fmt(r['flicker'])} | "
                         f"{fmt(r['jitter'])} | {fmt(r['compute_ms_per_frame'], 3)} | {fmt(r['cli_s'], 3)} | "
                         f"{fmt(r['rss_mb'], 0)} | {result} |")
        lines.append("")
    if production:
        lines += ["## Throughput on production-size frames", "",
                  f"{production['frames']} frames of {production['width']} x {production['height']} (RGB half, ZIP), "
                  "made by resizing cornell_moving 4 spp (the noise is not realistic, the cost is). Whole CLI runs "
                  "(read, filter, write) against a plain `oiiotool` read and write of the same frames in the same run.",
                  "", "| run | seconds | ms per megapixel-frame | x the I/O floor | peak MiB |",
                  "| --- | --- | --- | --- | --- |"]
        for r in production["rows"]:
            lines.append(f"| {r['label']} | {fmt(r['seconds'], 2)} | {fmt(r['ms_per_mpix_frame'], 1)} | "
                         f"{fmt(r['ratio_to_floor'], 2)} | {fmt(r['rss_mb'], 0)} |")
    (docs / "benchmarks.md").write_text("\n".join(lines) + "\n")
