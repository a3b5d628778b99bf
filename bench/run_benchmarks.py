#!/usr/bin/env python3
"""Accuracy and speed of statfilter's filters and of its peers on real renders, side by side in one run.

For every scene and noise level under the data folder (scene/spp*/indirect.####.exr with
scene/ref/indirect.####.exr), on the same frames:
  - statfilter's filters over a sweep of their parameters, with and without the OIDN prefilter,
    and the three quality presets: compute time through the C ABI on frames in memory (the filter
    alone), end-to-end CLI time and peak memory (read, filter, write EXR);
  - the peers of bench/peers.py (Intel Open Image Denoise through pyoidn, OpenCV's temporal
    non-local means, a temporal Gaussian average), each in its own process: compute time on frames
    in memory and the process's peak memory;
  - relMSE (overall, moving and static regions), PSNR, SSIM, FLIP, flicker and still-scene jitter.
A straightforward NumPy global PCA runs on the same frames as the yardstick, and a production-size
sequence (frames resized to 1920x1080) measures throughput against a plain OpenImageIO read+write.
Writes docs/benchmarks.md, docs/benchmarks.json and the PNG maps (one per scene). Usage:
    python3 bench/run_benchmarks.py [--data DIR] [--docs DIR] [--quick]
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "build" / "python"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

try:
    import statfilter  # noqa: E402
except ImportError as e:  # the benchmark measures the build in build/
    raise SystemExit(f"run_benchmarks: no statfilter package in build/python ({e}); build first: bash scripts/build.sh build")
from ssim import ssim  # noqa: E402
from flip_metric import mean_flip  # noqa: E402
import peers  # noqa: E402
import report  # noqa: E402

CLI = ROOT / "build" / "tools" / "statfilter"


def sweeps(quick):
    """(label, method, params) of every configuration measured; unnamed parameters take defaults
    (transform=log for every temporal filter)."""
    configs = [("temporal mean", "pca", {"rank": "0"})]
    ranks = ["1", "2", "4"] if quick else ["1", "2", "3", "4", "6", "8"]
    configs += [(f"pca rank {r}", "pca", {"rank": r}) for r in ranks]
    for transform in ["none", "sqrt", "log"]:
        configs.append((f"pca auto {transform}", "pca", {"rank": "auto", "transform": transform}))
    windows = [1, 9] if quick else [1, 5, 9, 15]
    thresholds = [2] if quick else [1.5, 2, 4]
    for w in windows:
        for t in thresholds:
            configs.append((f"error-threshold w{w} t{t}", "error-threshold", {"window": str(w), "threshold": str(t)}))
    configs.append(("error-threshold w9 t2 none", "error-threshold", {"transform": "none"}))
    half_widths = [4, 8] if quick else [2, 4, 8]
    for h in half_widths:
        for weights, rank in [("reconstruction", "1"), ("uniform", "2"), ("basis", "2"), ("reconstruction", "auto")]:
            configs.append((f"moving-basis h{h} {weights} r{rank}", "moving-basis",
                            {"half_width": str(h), "sigma": str(h / 2), "weights": weights, "rank": rank}))
    configs.append(("moving-basis h8 reconstruction rauto none", "moving-basis", {"transform": "none"}))
    configs.append(("diffusion", "diffusion", {}))
    configs.append(("diffusion k1 it20", "diffusion", {"k": "1", "iterations": "20"}))
    # The diffusion postfilter (docs/methods.md): on the study's filters by request, the hybrid's default.
    post = {"postfilter": "diffusion", "postfilter_params": "iterations=3,k=3"}
    configs.append(("pca auto + postfilter", "pca", dict(post)))
    configs.append(("error-threshold + postfilter", "error-threshold", dict(post)))
    configs.append(("moving-basis + postfilter", "moving-basis", dict(post)))
    configs.append(("hybrid no postfilter", "hybrid", {"postfilter": ""}))
    configs.append(("hybrid", "hybrid", {}))
    configs.append(("hybrid pca", "hybrid", {"temporal": "pca"}))
    passes = {"albedo": "{aux}/albedo.####.exr", "normal": "{aux}/normal.####.exr"}
    configs.append(("hybrid aux", "hybrid", dict(passes)))
    # Motion compensation (the hybrid's default) against the study's blend, and its speed/accuracy settings.
    configs.append(("hybrid no mc", "hybrid", {"motion_compensation": "off"}))
    configs.append(("hybrid no mc literal", "hybrid", {"motion_compensation": "off", "reading": "literal"}))
    configs.append(("hybrid aux no mc", "hybrid", dict(passes, motion_compensation="off")))
    configs.append(("hybrid aux no mc literal", "hybrid", dict(passes, motion_compensation="off", reading="literal")))
    for flow in ["ultrafast", "fast"]:
        configs.append((f"hybrid mc {flow}", "hybrid", {"mc_flow": flow}))
    configs.append(("hybrid mc ultrafast h4", "hybrid", {"mc_flow": "ultrafast", "mc_half_width": "4"}))
    configs.append(("hybrid mc h4", "hybrid", {"mc_half_width": "4"}))
    configs.append(("hybrid aux mc ultrafast h4", "hybrid", dict(passes, mc_flow="ultrafast", mc_half_width="4")))
    if "oidn" in statfilter.filters():
        for label, method, params in [("pca auto", "pca", {}), ("error-threshold", "error-threshold", {}),
                                      ("moving-basis", "moving-basis", {}), ("hybrid", "hybrid", {})]:
            configs.append((f"OIDN then {label}", method, dict(params, prefilter="oidn")))
        configs.append(("OIDN fast then error-threshold", "error-threshold",
                        {"prefilter": "oidn", "prefilter_params": "quality=fast"}))
        configs.append(("OIDN fast then hybrid", "hybrid", {"prefilter": "oidn", "prefilter_params": "quality=fast"}))
    for quality in PRESETS:
        configs.append((f"preset {quality}", "auto", {"quality": quality}))
    # The passes feed the hybrid's flow (balanced where something moves; high when OIDN is missing).
    configs.append(("preset balanced + aux", "auto", dict(passes, quality="balanced")))
    configs.append(("preset high + aux", "auto", dict(passes, quality="high")))
    return configs


PRESETS = ["fast", "balanced", "high"]


def scenes(data):
    for scene in sorted(p for p in data.iterdir() if (p / "ref").is_dir()):
        for level in sorted(scene.glob("spp*")):
            if any(level.glob("indirect.*.exr")):
                yield scene.name, level.name, level / "indirect.####.exr", scene / "ref" / "indirect.####.exr"


def run_cli(args):
    """Runs the CLI under /usr/bin/time; returns (json report, peak RSS in MiB)."""
    cmd = ["/usr/bin/time", "-f", "%M", str(CLI), *map(str, args), "--quiet", "--json"]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
    rss_kib = int(proc.stderr.strip().splitlines()[-1])
    return json.loads(proc.stdout), rss_kib / 1024


def measure(noisy, ref, output):
    m = statfilter.compare(output, ref)
    m["ssim"] = ssim(output, ref)
    m["flip"] = mean_flip(output, ref)
    return m


def timed(fn, repeats):
    best = float("inf")
    result = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return result, best


def numpy_reference(noisy, work, repeats):
    """The NumPy PCA in its own process: OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE, which some machines set
    for older OpenBLAS builds, slow a current NumPy's OpenBLAS, so they are unset for it alone."""
    np.save(work / "in.npy", noisy)
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")}
    proc = subprocess.run([sys.executable, str(Path(__file__).resolve().parent / "numpy_pca.py"), str(work / "in.npy"),
                           str(work / "out.npy"), str(repeats)], capture_output=True, text=True, check=True, env=env)
    rep = json.loads(proc.stdout)
    return np.load(work / "out.npy"), rep["rank"], rep["seconds"]


def bench_scene(scene, level, noisy_pattern, ref_pattern, configs, work, repeats, baselines=True):
    noisy = statfilter.read_sequence(str(noisy_pattern))
    ref = statfilter.read_sequence(str(ref_pattern))
    frames = noisy.shape[0]
    rows = []
    if baselines:
        base = measure(noisy, ref, noisy)
        rows.append(dict(scene=scene, level=level, label="input (noisy)", method="input", family="baseline", compute_ms_per_frame=0,
                         cli_s=None, rss_mb=None, **base))
        np_out, np_rank, np_time = numpy_reference(noisy, work, repeats)
        rows.append(dict(scene=scene, level=level, label="numpy pca auto", method="numpy", family="baseline", rank=np_rank,
                         compute_ms_per_frame=1000 * np_time / frames, cli_s=None, rss_mb=None,
                         **measure(noisy, ref, np_out)))
    aux = Path(str(noisy_pattern)).parent.parent / "aux"
    for label, method, params in configs:
        if any("{aux}" in v for v in params.values()):
            if not aux.is_dir():
                continue
            params = {k: v.replace("{aux}", str(aux)) for k, v in params.items()}
        flt = statfilter.Filter(method, **params)
        out, seconds = timed(lambda: flt(noisy), repeats)
        results = {k: v for k, v in flt.results.items() if not isinstance(v, np.ndarray)}
        out_pattern = work / "out.####.exr"
        report_json, rss = run_cli(["denoise", noisy_pattern, out_pattern, "--method", method, "--float",
                                    *[x for k, v in params.items() for x in (f"--{k}", v)]])
        family = "preset" if label.startswith("preset") else "statfilter + OIDN" if "prefilter" in params else "statfilter"
        rows.append(dict(scene=scene, level=level, label=label, method=method, family=family,
                         params={k: v.replace(str(aux), "{aux}") for k, v in params.items()},
                         compute_ms_per_frame=1000 * seconds / frames, cli_s=report_json["seconds"], rss_mb=rss,
                         results=results, **measure(noisy, ref, out)))
        print(f"  {scene}/{level} {label:38s} relMSE {rows[-1]['rel_mse']:.4f} "
              f"{rows[-1]['compute_ms_per_frame']:.2f} ms/frame", file=sys.stderr)
    if baselines:
        rows += bench_peers(scene, level, noisy, ref, aux, work, repeats)
    return rows


def bench_peers(scene, level, noisy, ref, aux, work, repeats):
    """Every usable peer configuration, each in its own process under /usr/bin/time."""
    usable = peers.available()
    np.save(work / "peer_in.npy", noisy)
    rows = []
    for label, name, params in [("harness (identity)", "identity", {})] + peers.sweep(aux.is_dir()):
        if usable.get(name):
            continue
        cmd = ["/usr/bin/time", "-f", "%M", sys.executable, str(Path(__file__).resolve().parent / "peers.py"), name,
               json.dumps(params), str(work / "peer_in.npy"), str(work / "peer_out.npy"), "--aux", str(aux),
               # NLM takes ~100x statfilter's time per frame: one run is precise enough, and saves minutes
               "--repeats", str(1 if name == "nlm" else repeats)]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
        seconds = json.loads(proc.stdout)["seconds"]
        rss = int(proc.stderr.strip().splitlines()[-1]) / 1024
        out = np.load(work / "peer_out.npy")
        rows.append(dict(scene=scene, level=level, label=label, method="peer " + name, family="peer", params=params,
                         compute_ms_per_frame=1000 * seconds / noisy.shape[0], cli_s=None, rss_mb=rss,
                         **measure(noisy, ref, out)))
        print(f"  {scene}/{level} {label:38s} relMSE {rows[-1]['rel_mse']:.4f} "
              f"{rows[-1]['compute_ms_per_frame']:.2f} ms/frame", file=sys.stderr)
    return rows


def true_moving_region(ref):
    """DESIGN section 7: pixels whose reference luminance varies over time more than 3x the median."""
    lum = 0.2126 * ref[..., 0] + 0.7152 * ref[..., 1] + 0.0722 * ref[..., 2]
    std = lum.std(axis=0)
    return std > 3 * np.median(std)


def motion_detectors(scene, level, noisy_pattern, ref_pattern):
    """Each detector's moving region (any frame) against the true one: precision, recall, IoU."""
    noisy = statfilter.read_sequence(str(noisy_pattern))
    truth = true_moving_region(statfilter.read_sequence(str(ref_pattern)))
    aux = Path(str(noisy_pattern)).parent.parent / "aux"
    detectors = [("alpha (global)", {}, lambda r: r["alpha"][0, ..., 0] < 0.5),
                 ("beta z-scores", {"beta_source": "zscore"}, lambda r: r["beta"][..., 0].max(axis=0) > 0.5)]
    if aux.is_dir():
        detectors.append(("beta albedo+normal", {"albedo": str(aux / "albedo.####.exr"),
                                                 "normal": str(aux / "normal.####.exr")},
                          lambda r: r["beta"][..., 0].max(axis=0) > 0.5))
    rows = []
    for name, params, region in detectors:
        f = statfilter.Filter("motion", **params)
        f(noisy)
        found = region(f.results)
        tp = float((found & truth).sum())
        rows.append(dict(scene=scene, level=level, detector=name, flagged=float(found.mean()),
                         precision=tp / max(found.sum(), 1), recall=tp / max(truth.sum(), 1),
                         iou=tp / max((found | truth).sum(), 1)))
    return rows


def ghosting_figure(data, docs):
    """Side by side: one frame of the moving ball, noisy, global PCA, moving basis, error threshold, the
    hybrid without and with the albedo/normal passes, reference."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    scene = data / "cornell_moving"
    if not (scene / "spp0004").is_dir():
        return None
    noisy = statfilter.read_sequence(str(scene / "spp0004" / "indirect.####.exr"))
    ref = statfilter.read_sequence(str(scene / "ref" / "indirect.####.exr"))
    aux = scene / "aux"
    panels = [("noisy 4 spp", noisy), ("pca auto", statfilter.Filter("pca")(noisy)),
              ("moving-basis", statfilter.Filter("moving-basis")(noisy)),
              ("error-threshold", statfilter.Filter("error-threshold")(noisy)),
              ("hybrid", statfilter.Filter("hybrid")(noisy)),
              ("hybrid (albedo+normal)", statfilter.Filter("hybrid", albedo=str(aux / "albedo.####.exr"),
                                                          normal=str(aux / "normal.####.exr"))(noisy)),
              ("reference", ref)]
    frame = 16
    fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3))
    for ax, (title, seq) in zip(axes, panels):
        img = np.clip(seq[frame, 50:120, 20:140, :] / (1 + seq[frame, 50:120, 20:140, :]), 0, 1) ** (1 / 2.2)
        ax.imshow(img, interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    name = "ghosting_cornell_moving.png"
    fig.savefig(docs / name, dpi=110)
    plt.close(fig)
    return name


def production_size(data, work, quick):
    """Throughput on 1920x1080 frames made by resizing a real sequence, against a plain OIIO read+write."""
    oiiotool = shutil.which("oiiotool")
    source = next((p for p in [data / "cornell_moving" / "spp0004"] if p.is_dir()), None)
    if not oiiotool or source is None:
        return None
    frames = 8 if quick else 32
    big = work / "big"
    big.mkdir(exist_ok=True)
    for f in range(1, frames + 1):
        subprocess.run([oiiotool, str(source / f"indirect.{f:04d}.exr"), "--resize", "1920x1080",
                        "-d", "half", "--compression", "zip", "-o", str(big / f"in.{f:04d}.exr")], check=True)
    pattern = big / "in.####.exr"
    t0 = time.perf_counter()
    subprocess.run([oiiotool, "--frames", f"1-{frames}", str(big / "in.#.exr"), "-d", "half", "--compression", "zip",
                    "-o", str(big / "io.#.exr")], check=True, capture_output=True)
    floor = time.perf_counter() - t0
    rows = [dict(label="oiiotool read + write (I/O floor)", seconds=floor, rss_mb=None)]
    for label, method, params in [("copy", "copy", {}), ("pca auto", "pca", {"rank": "auto"}),
                                  ("preset fast", "auto", {"quality": "fast"}),
                                  ("preset balanced", "auto", {"quality": "balanced"}),
                                  ("preset high", "auto", {"quality": "high"}),
                                  ("hybrid", "hybrid", {}),
                                  ("hybrid no mc", "hybrid", {"motion_compensation": "off"}),
                                  ("pca auto, memory_mb 64", "pca", {"rank": "auto", "memory_mb": "64"}),
                                  ("error-threshold", "error-threshold", {}),
                                  ("moving-basis", "moving-basis", {})]:
        t0 = time.perf_counter()
        rep, rss = run_cli(["denoise", pattern, big / "out.####.exr", "--method", method,
                            *[x for k, v in params.items() for x in (f"--{k}", v)]])
        rows.append(dict(label=label, seconds=time.perf_counter() - t0, rss_mb=rss))
    megapixel_frames = frames * 1920 * 1080 / 1e6
    for r in rows:
        r["ms_per_mpix_frame"] = 1000 * r["seconds"] / megapixel_frames
        r["ratio_to_floor"] = r["seconds"] / floor
    return dict(frames=frames, width=1920, height=1080, rows=rows)


def environment():
    """The CPU and the peers' versions (or why a peer is missing), for the report's header."""
    cpu = ""
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    versions = {}
    for label, module in [("pyoidn", "pyoidn"), ("opencv-python-headless", "cv2"), ("flip-evaluator", "flip_evaluator")]:
        try:
            from importlib import metadata
            versions[label] = metadata.version(label)
        except Exception:  # noqa: BLE001 - not installed: say so
            versions[label] = "not installed (its rows are missing)"
    return dict(cpu=cpu, peers=versions)


def reading_prose():
    """The hand-written reading of the results (bench/reading.md), kept next to the code that measures."""
    path = Path(__file__).resolve().parent / "reading.md"
    return path.read_text() if path.exists() else ""


def save(docs, results):
    (docs / "benchmarks.json").write_text(json.dumps(results, indent=1, default=float))


def render(docs, results, figure):
    """docs/benchmarks.md and the maps from the results (rows, motion, production, environment, command)."""
    report.write(results["rows"], results.get("production"), docs,
                 results.get("command", "python3 bench/run_benchmarks.py"), os.cpu_count(),
                 motion=results.get("motion"), figure=figure, environment=results.get("environment"),
                 prose=reading_prose())


def update_only(args, configs, repeats):
    """Re-measures some configurations and merges them into docs/benchmarks.json and the report."""
    old = json.loads((args.docs / "benchmarks.json").read_text())
    fresh = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene, level, noisy, ref in scenes(args.data):
            fresh += bench_scene(scene, level, noisy, ref, configs, Path(tmp), repeats, baselines=False)
    key = lambda r: (r["scene"], r["level"], r["label"])
    replaced = {key(r) for r in fresh}
    rows = [r for r in old["rows"] if key(r) not in replaced]
    for r in fresh:  # keep each scene's rows in the sweep's order
        rows.append(r)
    order = {label: i for i, (label, _, _) in enumerate(sweeps(False))}
    rows.sort(key=lambda r: (r["scene"], r["level"], -1 if r["method"] in ("input", "numpy") else order.get(r["label"], 999)))
    command = "python3 bench/run_benchmarks.py, then python3 bench/run_benchmarks.py " + " ".join(
        f"--only '{p}'" for p in args.only)
    results = dict(old, rows=rows, command=command)
    save(args.docs, results)
    render(args.docs, results, ghosting_figure(args.data, args.docs))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--docs", type=Path, default=ROOT / "docs")
    parser.add_argument("--quick", action="store_true", help="fewer configurations, one repeat")
    parser.add_argument("--scene", action="append", help="only these scenes (default: every scene found)")
    parser.add_argument("--report-only", action="store_true",
                        help="measure nothing: rewrite docs/benchmarks.md and the maps from docs/benchmarks.json "
                             "(after editing bench/reading.md or bench/report.py)")
    parser.add_argument("--only", action="append", metavar="PREFIX",
                        help="re-measure only the configurations whose label starts with PREFIX (with pca auto "
                             "log, the time base, in the same run) and merge them into the existing results")
    args = parser.parse_args()
    if not args.data.is_dir():
        args.data = ROOT / "sample"
    if args.report_only:
        figure = "ghosting_cornell_moving.png" if (args.docs / "ghosting_cornell_moving.png").exists() else None
        render(args.docs, json.loads((args.docs / "benchmarks.json").read_text()), figure)
        return
    configs = sweeps(args.quick)
    repeats = 1 if args.quick else 3
    if args.only:
        update_only(args, [c for c in configs if c[0] == "pca auto log" or c[0].startswith(tuple(args.only))], repeats)
        return
    rows, motion = [], []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for scene, level, noisy, ref in scenes(args.data):
            if args.scene and scene not in args.scene:
                continue
            rows += bench_scene(scene, level, noisy, ref, configs, work, repeats)
            motion += motion_detectors(scene, level, noisy, ref)
        production = production_size(args.data, work, args.quick)
    args.docs.mkdir(exist_ok=True)
    figure = ghosting_figure(args.data, args.docs)
    command = "python3 bench/run_benchmarks.py" + (" --quick" if args.quick else "") + "".join(
        f" --scene {s}" for s in args.scene or [])
    results = dict(rows=rows, motion=motion, production=production, environment=environment(), command=command)
    save(args.docs, results)
    render(args.docs, results, figure)


if __name__ == "__main__":
    main()
