"""Writes docs/benchmarks.md and its plots from the benchmark rows."""

import datetime
import platform
from collections import defaultdict

import pareto

DEFAULTS = {"pca": "pca auto log", "error-threshold": "error-threshold w9 t2",
            "moving-basis": "moving-basis h8 reconstruction rauto", "diffusion": "diffusion", "hybrid": "hybrid"}
COLORS = {"numpy": "grey", "pca": "tab:blue", "error-threshold": "tab:green", "moving-basis": "tab:orange",
          "diffusion": "tab:purple", "hybrid": "tab:red", "statfilter after OIDN": "tab:pink",
          "peer oidn": "tab:cyan", "peer nlm": "tab:brown", "peer nlm-encode": "lightgrey",
          "peer gaussian": "tab:olive"}
MARKERS = {"peer oidn": "s", "peer nlm": "s", "peer nlm-encode": "x", "peer gaussian": "s", "statfilter after OIDN": "D"}


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


def by_label(rows):
    return {r["label"]: r for r in rows}


def best(rows, pred):
    """The lowest-relMSE row among those pred accepts, or None."""
    rs = [r for r in rows if pred(r)]
    return min(rs, key=lambda r: r["rel_mse"]) if rs else None


def cell(r, digits=4):
    return "-" if r is None else f"{fmt(r['rel_mse'], digits)} ({fmt(r['compute_ms_per_frame'], 2)} ms)"


def is_peer(name):
    return lambda r: r["method"] == "peer " + name


def headline(grouped):
    lines = ["| scene | level | noisy | statfilter best, no OIDN | OIDN high | OIDN high + aux | OIDN then statfilter, best | "
             "NLM multi, best h | temporal Gaussian, best | preset fast | preset balanced | preset high |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = by_label(rs)
        sf = best(rs, lambda r: r["family"] == "statfilter")
        after = best(rs, lambda r: r["family"] == "statfilter + OIDN")
        nlm = best(rs, is_peer("nlm"))
        gauss = best(rs, is_peer("gaussian"))
        lines.append(f"| {scene} | {level} | {fmt(by['input (noisy)']['rel_mse'])} | "
                     f"{cell(sf)} {sf['label'] if sf else ''} | {cell(by.get('OIDN high'))} | "
                     f"{cell(by.get('OIDN high + albedo/normal'))} | {cell(after)} {after['label'] if after else ''} | "
                     f"{cell(nlm)} {nlm['label'].split()[-2] + ' ' + nlm['label'].split()[-1] if nlm else ''} | "
                     f"{cell(gauss)} {gauss['label'].split()[-1] if gauss else ''} | "
                     f"{cell(by.get('preset fast'))} | {cell(by.get('preset balanced'))} | {cell(by.get('preset high'))} |")
    return lines


def reading(grouped):
    """The generated part of the honest reading: who is lowest where, and at what cost."""
    lines = []
    wins = defaultdict(list)
    for (scene, level), rs in sorted(grouped.items()):
        top = best(rs, lambda r: r["method"] not in ("input", "peer identity"))
        sf = best(rs, lambda r: r["family"] == "statfilter")
        oidn = best(rs, is_peer("oidn"))
        nlm = best(rs, is_peer("nlm"))
        after = best(rs, lambda r: r["family"] == "statfilter + OIDN")
        wins[top["family"] if top["family"] != "peer" else top["method"]].append(f"{scene} {level}")
        parts = [f"lowest relMSE: {top['label']} {fmt(top['rel_mse'])}"]
        if sf and oidn:
            parts.append(f"statfilter alone {fmt(sf['rel_mse'])} ({sf['label']}) = {fmt(sf['rel_mse'] / oidn['rel_mse'], 2)}x "
                         f"OIDN's best {fmt(oidn['rel_mse'])} at {fmt(sf['compute_ms_per_frame'] / oidn['compute_ms_per_frame'], 2)}x "
                         "its time")
        if after and oidn:
            parts.append(f"OIDN then statfilter {fmt(after['rel_mse'] / oidn['rel_mse'], 2)}x OIDN alone")
        if sf and nlm:
            parts.append(f"NLM's best {fmt(nlm['rel_mse'])} = {fmt(nlm['rel_mse'] / sf['rel_mse'], 2)}x statfilter alone at "
                         f"{fmt(nlm['compute_ms_per_frame'] / sf['compute_ms_per_frame'], 1)}x its time")
        lines.append(f"- {scene} {level}: " + "; ".join(parts) + ".")
    summary = ", ".join(f"{k}: {len(v)}" for k, v in sorted(wins.items()))
    return [f"Lowest relMSE per scene and level, by who ({summary} of {len(grouped)}):", ""] + lines


def presets_table(grouped):
    lines = ["| scene | level | preset | picked | relMSE | ms/frame | error / front at its speed | time / front at its error |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        for r in rs:
            if r["family"] != "preset":
                continue
            err, tim = pareto.standing(r, rs)
            picked = (r.get("results") or {}).get("method", "")
            lines.append(f"| {scene} | {level} | {r['label'].replace('preset ', '')} | {picked} | {fmt(r['rel_mse'])} | "
                         f"{fmt(r['compute_ms_per_frame'], 2)} | {fmt(err, 2)}x | {fmt(tim, 2)}x |")
    return lines


def front_table(grouped):
    lines = ["| scene | level | the front, fastest first: configuration relMSE (ms/frame) |", "| --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        f = pareto.front(rs)
        lines.append(f"| {scene} | {level} | " + "; ".join(
            f"{r['label']} {fmt(r['rel_mse'])} ({fmt(r['compute_ms_per_frame'], 2)})" for r in f) + " |")
    return lines


def write(rows, production, docs, command, cores, motion=None, figure=None, environment=None, prose=""):
    grouped = group(rows)
    env = environment or {}
    lines = ["# Benchmarks", "",
             f"Made by `{command}` on {datetime.date.today()} ({platform.machine()}, {cores} cores"
             f"{', ' + env['cpu'] if env.get('cpu') else ''}; every method at its default thread count). "
             "Data: the Blender Cycles renders of the project's shared data (160 x 120, 32 frames), each noise "
             "level against its reference. One run measured everything below, on the same frames.", ""]
    if env.get("peers"):
        lines += ["Peers: " + "; ".join(f"{k} {v}" for k, v in env["peers"].items()) + ".", ""]
    lines += ["Compute time is the method alone on frames in memory (best of the repeats): statfilter through "
              "its C ABI in the benchmark's process, each peer in a process of its own (bench/peers.py). CLI time "
              "adds reading and writing the EXR sequence; peak memory is the CLI's maximum resident set for "
              "statfilter and the peer process's (Python, NumPy and the peer's library included: compare with "
              "the `harness (identity)` row, which only loads and returns the frames). At 160 x 120 fixed costs "
              "dominate, so throughput is measured on production-size frames below. Metrics follow DESIGN "
              "section 7: relMSE = mean((x - ref)^2 / (ref^2 + 0.01)); moving/static split the pixels by the "
              "reference's temporal std (> 3x / <= 3x the median); PSNR and SSIM on tonemapped x/(1+x) values "
              "(SSIM on luminance); FLIP is NVIDIA's HDR-FLIP (flip-evaluator) on every 4th frame; flicker = "
              "mean |dx/dt - dref/dt|; jitter = mean |second temporal difference| of luminance on still pixels.",
              ""]
    if prose:
        lines += [prose.strip(), ""]
    lines += ["## Headline: relMSE (compute ms per frame) against the reference", ""] + headline(grouped)
    lines += ["", "## Who wins where (generated from the table)", ""] + reading(grouped)
    plots = pareto.plot(rows, docs, COLORS, MARKERS)
    if plots:
        lines += ["", "## The speed/accuracy map", "",
                  "Every configuration (statfilter's sweeps, statfilter after OIDN, the peers) as a point; the black "
                  "steps are the Pareto front (nothing is both faster and more accurate than a point on it); the "
                  "gold stars are the quality presets; dashed: the noisy input."]
        lines += [f"\n![{p}]({p})" for p in plots]
    lines += ["", "### The front", ""] + front_table(grouped)
    lines += ["", "## Quality presets against the front", "",
              "`statfilter denoise --quality fast|balanced|high` (C ABI and Python: the `quality` parameter of the "
              "`auto` filter). 'error / front at its speed' is the preset's relMSE over the lowest relMSE any "
              "configuration reached in the same time or less; 'time / front at its error' is its time over the "
              "least time any configuration needed for the same error or lower. 1.00x on both is on the front.", ""]
    lines += presets_table(grouped)
    lines += ["", "## Moving region and still scene", "",
              "relMSE inside the moving region (reference temporal std > 3x the median) and outside it, and "
              "compute time relative to `pca auto` on the same frames.", "",
              "| scene | level | method | moving | static | time / pca |", "| --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = by_label(rs)
        base = by.get(DEFAULTS["pca"])
        for label in [DEFAULTS["pca"], DEFAULTS["error-threshold"], DEFAULTS["moving-basis"], "diffusion", "hybrid",
                      "hybrid aux", "hybrid no mc", "OIDN high", "OIDN then error-threshold", "preset fast", "preset balanced",
                      "preset high"]:
            if label in by and base:
                r = by[label]
                lines.append(f"| {scene} | {level} | {label} | {fmt(r['rel_mse_moving'])} | {fmt(r['rel_mse_static'])} | "
                             f"{fmt(r['compute_ms_per_frame'] / base['compute_ms_per_frame'], 2)}x |")
    lines += ["", "## The hybrid against the moving basis", "",
              "relMSE of the hybrid (motion-compensated, its default; with the albedo/normal passes; without its "
              "postfilter; the study's blend without motion compensation, without and with the passes) over the "
              "default moving basis on the same frames.", "",
              "| scene | level | moving-basis | hybrid | / mb | hybrid aux | / mb | hybrid no postfilter | / mb "
              "| hybrid no mc | / mb | hybrid aux no mc | / mb |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = by_label(rs)
        mb = by.get(DEFAULTS["moving-basis"])
        if not mb:
            continue
        cells = []
        for label in ("hybrid", "hybrid aux", "hybrid no postfilter", "hybrid no mc", "hybrid aux no mc"):
            r = by.get(label)
            cells += [fmt(r["rel_mse"]) if r else "-", f"{fmt(r['rel_mse'] / mb['rel_mse'], 2)}x" if r else "-"]
        lines.append(f"| {scene} | {level} | {fmt(mb['rel_mse'])} | " + " | ".join(cells) + " |")
    lines += ["", "## statfilter against the NumPy yardstick", "",
              "| scene | level | numpy pca auto | pca auto none | C++ speed-up (same computation) |",
              "| --- | --- | --- | --- | --- |"]
    for (scene, level), rs in sorted(grouped.items()):
        by = by_label(rs)
        npy, same = by.get("numpy pca auto"), by.get("pca auto none")
        if npy and same:
            lines.append(f"| {scene} | {level} | {cell(npy)} | {cell(same)} | "
                         f"{fmt(npy['compute_ms_per_frame'] / same['compute_ms_per_frame'], 2)}x |")
    lines += ["", "The NumPy PCA runs in its own process with its best OpenBLAS settings (best of the repeats)."]
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
    if production:
        lines += ["", "## Throughput on production-size frames", "",
                  f"{production['frames']} frames of {production['width']} x {production['height']} (RGB half, ZIP), "
                  "made by resizing cornell_moving 4 spp (the noise is not realistic, the cost is). Whole CLI runs "
                  "(read, filter, write) against a plain `oiiotool` read and write of the same frames in the same run: "
                  "the I/O floor no tool that reads and writes these files can go below.",
                  "", "| run | seconds | ms per megapixel-frame | x the I/O floor | peak MiB |",
                  "| --- | --- | --- | --- | --- |"]
        for r in production["rows"]:
            lines.append(f"| {r['label']} | {fmt(r['seconds'], 2)} | {fmt(r['ms_per_mpix_frame'], 1)} | "
                         f"{fmt(r['ratio_to_floor'], 2)} | {fmt(r['rss_mb'], 0)} |")
    lines += ["", "## Every configuration", ""]
    for (scene, level), rs in sorted(grouped.items()):
        lines += [f"### {scene} {level}", "",
                  "| configuration | relMSE | moving | static | PSNR | SSIM | FLIP | flicker | jitter | compute ms/frame | "
                  "CLI s | peak MiB | result |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for r in rs:
            res = r.get("results") or {}
            result = ", ".join(f"{k} {fmt(v, 2)}" for k, v in res.items() if k in ("rank", "mean_rank", "method"))
            if r["method"] == "numpy":
                result = f"rank {r['rank']}"
            lines.append(f"| {r['label']} | {fmt(r['rel_mse'])} | {fmt(r['rel_mse_moving'])} | "
                         f"{fmt(r['rel_mse_static'])} | {fmt(r['psnr'], 2)} | {fmt(r['ssim'])} | {fmt(r.get('flip'))} | "
                         f"{fmt(r['flicker'])} | {fmt(r['jitter'])} | {fmt(r['compute_ms_per_frame'], 3)} | "
                         f"{fmt(r['cli_s'], 3)} | {fmt(r['rss_mb'], 0)} | {result} |")
        lines.append("")
    (docs / "benchmarks.md").write_text("\n".join(lines) + "\n")
