#!/usr/bin/env python3
"""The plan of tile tasks measured: 1 against 2 Dask worker processes on a 1080p x 32 shot (beside the
single-process CLI at 1 and 2 threads, in the same run), the bytes the reduction and the tile halos move,
per-tile costs measured on a 4K x 200 shot, and from them a model of that shot on 10, 100 and 1000 nodes
(docs/distributed.md, docs/distributed_model.png).

Frames are made from the shipped sample as bench/streaming_benchmark.py makes them (resized, repeated).

    python3 bench/distributed_benchmark.py            # both parts
    python3 bench/distributed_benchmark.py --model-only   # the model again from docs/distributed.json
    python3 bench/distributed_benchmark.py --balanced     # --quality balanced (analysis + windows) alone
Build first: bash scripts/build.sh build-release -DCMAKE_BUILD_TYPE=Release
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
from streaming_benchmark import make_frames, timed  # noqa: E402

# The model's shared storage: aggregate bandwidth of the farm's file server, an assumption (not measured
# here), and what one task's scheduling costs on top of its work (measured: the 2-worker run's overhead).
STORAGE_BYTES_PER_S = (2e9, 10e9)
NODES = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000)
MODEL_ROWS = (8, 16, 32, 64, 135, 270, 540, 2160)


def cli_env(build):
    return dict(os.environ, PYTHONPATH=str(build / "python"), STATFILTER_LIBRARY=str(build / "capi" / "libstatfilter.so.0"))


def dask_run(build, shot, out, workers, params, tile_rows, frames_per_task=0):
    """One Dask run in a child process (its own cluster): (wall of the run, report)."""
    code = f"""
import json, sys, time
from distributed import Client, LocalCluster
import statfilter.distributed as sd
if __name__ == "__main__":
    cluster = LocalCluster(n_workers={workers}, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(cluster)
    t = time.perf_counter()
    r = sd.denoise({str(shot / 'in.####.exr')!r}, {str(out)!r}, client=client, tile_rows={tile_rows}, threads=1,
                   frames_per_task={frames_per_task},
                   progress=False, **{params!r})
    r["wall"] = time.perf_counter() - t
    client.close(); cluster.close()
    print("REPORT" + json.dumps(r))
"""
    env = cli_env(build)
    env.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        sys.exit(proc.stderr[-3000:])
    return json.loads([l for l in proc.stdout.splitlines() if l.startswith("REPORT")][-1][6:])


def rel_mse(cli, a, b):
    out = subprocess.run([cli, "compare", a, b, "--json"], capture_output=True, text=True, check=True).stdout
    return json.loads(out)["rel_mse"]


def measure_1080p(build, work, cli):
    shot = make_frames(work, 1920, 1080, 32)
    width, height, frames, channels = 1920, 1080, 32, 3
    rows = []
    for label, method_args, params in (("--quality fast", ["--quality", "fast"], {"quality": "fast"}),
                                       ("--method error-threshold", ["--method", "error-threshold"],
                                        {"method": "error-threshold"})):
        single = work / "single" / "o.####.exr"
        for threads in (1, 2):
            shutil.rmtree(work / "single", ignore_errors=True)
            env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1") if threads == 1 else None
            rc, wall, cpu, rss, tail = timed([cli, "denoise", shot / "in.####.exr", single, *method_args, "--threads",
                                              str(threads), "--quiet"], env)
            if rc:
                sys.exit(tail)
            rows.append(dict(config=label, runner="statfilter denoise", slots=threads, wall=wall, cpu=cpu, rss=rss))
            print(rows[-1], flush=True)
        for workers in (1, 2):
            out = work / f"dask{workers}" / "o.####.exr"
            shutil.rmtree(out.parent, ignore_errors=True)
            r = dask_run(build, shot, out, workers, params, 135)
            halo_rows = 0
            rec = r["phases"]["reconstruct"]
            # rows read beyond the tiles' own by the reconstructions: their halos
            halo_rows = rec["pixel_bytes_read"] / (width * channels * 4 * frames) - height
            reduction = (r["phases"]["statistics"]["bytes_written"] + r["phases"]["reduce"]["bytes_read"] +
                         r["phases"]["reduce"]["bytes_written"] + rec["bytes_read"])
            rows.append(dict(config=label, runner="statfilter.distributed (Dask)", slots=workers, wall=r["wall"],
                             cpu=r["cpu_seconds"], tasks=r["tasks"], phases=r["phases"], reduction_bytes=reduction,
                             halo_bytes=halo_rows * width * channels * 4 * frames,
                             tile_bytes=rec["bytes_written"], pixel_bytes_read=r["pixel_bytes_read"],
                             rel_mse_to_single=rel_mse(cli, str(out), str(single)), results=r["results"]))
            print({k: v for k, v in rows[-1].items() if k != "phases"}, flush=True)
    input_bytes = sum(p.stat().st_size for p in shot.glob("in.*.exr"))
    return dict(shot="1920x1080x32", input_bytes=input_bytes, rows=rows)


def measure_balanced_1080p(build, work, cli):
    """--quality balanced on 1080p x 32: the CLI at 1 and 2 threads, the plan (one analysis task, then
    windows of 4 frames) on 1 and 2 Dask workers, in one run."""
    shot = make_frames(work, 1920, 1080, 32)
    rows = []
    single = work / "single" / "o.####.exr"
    for threads in (1, 2):
        shutil.rmtree(work / "single", ignore_errors=True)
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1") if threads == 1 else None
        rc, wall, cpu, rss, tail = timed([cli, "denoise", shot / "in.####.exr", single, "--quality", "balanced",
                                          "--threads", str(threads), "--quiet"], env)
        if rc:
            sys.exit(tail)
        rows.append(dict(config="--quality balanced", runner="statfilter denoise", slots=threads, wall=wall, cpu=cpu, rss=rss))
        print(rows[-1], flush=True)
    for workers in (1, 2):
        out = work / f"dask{workers}" / "o.####.exr"
        shutil.rmtree(out.parent, ignore_errors=True)
        r = dask_run(build, shot, out, workers, {"quality": "balanced"}, 0, 4)
        rows.append(dict(config="--quality balanced", runner="statfilter.distributed (Dask)", slots=workers,
                         wall=r["wall"], cpu=r["cpu_seconds"], tasks=r["tasks"], phases=r["phases"],
                         pixel_bytes_read=r["pixel_bytes_read"], bytes_written=r["bytes_written"],
                         rel_mse_to_single=rel_mse(cli, str(out), str(single)), results=r["results"]))
        print({k: v for k, v in rows[-1].items() if k != "results"}, flush=True)
    return dict(shot="1920x1080x32", input_bytes=sum(p.stat().st_size for p in shot.glob("in.*.exr")), rows=rows)


def balanced_model(measured):
    """Seconds for 3840 x 2160 x 200 at --quality balanced on N nodes, from the 1080p x 32 phases measured on
    one worker (linear in pixel-frames: each phase's work is per pixel and frame), one single-threaded task per
    node at a time: the analysis and the guides run on one node; the first passes and the windows in chunks of
    frames, in waves over the nodes, each task with the scheduling overhead measured on two workers; every
    phase at least its bytes through shared storage."""
    one = [r for r in measured["rows"] if r.get("tasks") and r["slots"] == 1][0]
    two = [r for r in measured["rows"] if r.get("tasks") and r["slots"] == 2][0]
    scale = (3840 * 2160 * 200) / (1920 * 1080 * 32)
    frames, per_frame_scale = 200, (3840 * 2160) / (1920 * 1080)
    overhead = max(0.0, (two["wall"] * 2 - sum(p["seconds"] for p in two["phases"].values())) / two["tasks"])
    def phase_bytes(name):
        p = one["phases"][name]
        return (p["pixel_bytes_read"] + p["bytes_read"] + p["bytes_written"]) * scale
    out = {}
    for bandwidth in STORAGE_BYTES_PER_S:
        for n in (1, 10, 100, 1000):
            per_task = max(1, math.ceil(frames / n))
            waves = math.ceil(math.ceil(frames / per_task) / n)
            row = {}
            for name in ("analysis", "guides"):
                row[name] = max(one["phases"][name]["seconds"] * scale, phase_bytes(name) / bandwidth)
            for name in ("first_pass", "window"):
                each = one["phases"][name]["seconds"] / 32 * per_frame_scale  # one frame's share, at 4K
                row[name] = max(waves * (per_task * each + overhead), phase_bytes(name) / bandwidth)
            row["total"] = sum(row.values())
            out[(bandwidth, n)] = row
    return out


def run_task(cli, plan, index):
    rc, wall, cpu, rss, tail = timed([cli, "task", plan, index, "--threads", "1", "--quiet"],
                                     dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1"))
    if rc:
        sys.exit(tail)
    return wall, cpu


def measure_4k_tiles(work, cli):
    """Per-tile costs of --quality fast on 3840 x 2160 x 200: a statistics and a reconstruction task at two
    band heights, the reduction of all bands. The reconstruction's reduction is made from copies of band
    0's partial (the cost depends on the rank, not on the values; the rank it chose is recorded)."""
    shot = make_frames(work, 3840, 2160, 200)
    costs = dict(shot="3840x2160x200", input_bytes=sum(p.stat().st_size for p in shot.glob("in.*.exr")), tiles=[])
    for rows in (16, 64):
        plan = work / f"plan4k-{rows}.json"
        out = work / "out4k" / "o.####.exr"
        subprocess.run([cli, "plan", shot / "in.####.exr", out, "--quality", "fast", "--tile-rows", str(rows), "-o", plan,
                        "--quiet"], check=True, capture_output=True)
        p = json.loads(plan.read_text())
        tiles = len([t for t in p["tasks"] if t["phase"] == "statistics"])
        stat = run_task(cli, plan, 0)
        wdir = Path(p["work"]) / p.get("run", "")
        for t in range(1, tiles):
            shutil.copy(wdir / "partial-0.bin", wdir / f"partial-{t}.bin")
        # The cost of reading a partial: every sum task of the plan (a flat reduction when it has none)
        # and its reduction, summed over the partials they read.
        index = {ph: [t["index"] for t in p["tasks"] if t["phase"] == ph] for ph in ("sum", "reduce", "reconstruct")}
        red = [0.0, 0.0]
        for i in index["sum"] + index["reduce"]:
            w, c = run_task(cli, plan, i)
            red = [red[0] + w, red[1] + c]
        reads = tiles + len(index["sum"])  # the partials, then the sums
        red = [red[0] * tiles / reads, red[1] * tiles / reads]
        rec = run_task(cli, plan, index["reconstruct"][0])
        report = json.loads((wdir / f"task-{index['reconstruct'][0]}.json").read_text())
        costs["tiles"].append(dict(rows=rows, tiles=tiles, statistics=stat, reduce=red, reconstruct=rec,
                                   rank=report["results"].get("rank"), partial_bytes=(wdir / "partial-0.bin").stat().st_size))
        print(costs["tiles"][-1], flush=True)
        shutil.rmtree(wdir, ignore_errors=True)
    return costs


def model(measured, tiles4k):
    """Seconds for 3840 x 2160 x 200 (--quality fast) on N nodes, one single-threaded task per node at a time,
    as measured here: each phase takes the longer of its compute (tasks in waves over the nodes, each with the
    scheduling overhead) and its bytes through shared storage."""
    W, H, F, C = 3840, 2160, 200, 3
    a, b = tiles4k["tiles"][0], tiles4k["tiles"][1]
    def line(key, rows):  # per-task wall, linear in the band height between the two measured heights
        slope = (b[key][0] - a[key][0]) / (b["rows"] - a["rows"])
        return max(0.05, a[key][0] + slope * (rows - a["rows"]))
    per_partial = max(b["reduce"][0] / b["tiles"], a["reduce"][0] / a["tiles"])
    fast2 = [r for r in measured["rows"] if r["config"] == "--quality fast" and r.get("tasks") and r["slots"] == 2][0]
    asm = fast2["phases"]["assemble"]
    per_frame_1080p = asm["seconds"] / 32
    per_frame = per_frame_1080p * (W * H) / (1920 * 1080)
    overhead = max(0.0, (fast2["wall"] * 2 - sum(p["seconds"] for p in fast2["phases"].values())) / fast2["tasks"])
    input_bytes = tiles4k["input_bytes"]
    tile_bytes = W * H * F * C * 4.0
    out = {}
    for bandwidth in STORAGE_BYTES_PER_S:
        for rows in MODEL_ROWS:
            T = math.ceil(H / rows)
            for n in NODES:
                waves = math.ceil(T / n)
                frames_per_task = max(1, math.ceil(F / n))
                stats = max(waves * (line("statistics", rows) + overhead), input_bytes / bandwidth)
                # The plan's reduction (tile_plan.cpp): one task up to 32 bands, else sqrt(T) sum tasks
                # of about sqrt(T) partials each (in waves over the nodes), then one of their sums.
                if T <= 32:
                    reduce = per_partial * T + overhead
                else:
                    parts = math.isqrt(T - 1) + 1
                    reduce = (math.ceil(parts / n) * (per_partial * math.ceil(T / parts) + overhead) +
                              per_partial * parts + overhead)
                rec = max(waves * (line("reconstruct", rows) + overhead), (input_bytes + tile_bytes) / bandwidth)
                assemble = max(math.ceil(F / frames_per_task / n) * (frames_per_task * per_frame + overhead),
                               (tile_bytes + input_bytes) / bandwidth)
                out[(bandwidth, rows, n)] = dict(statistics=stats, reduce=reduce, reconstruct=rec, assemble=assemble,
                                                 total=stats + reduce + rec + assemble,
                                                 storage=(2 * input_bytes + 2 * tile_bytes + input_bytes) / bandwidth)
    return out, dict(per_partial=per_partial, per_frame=per_frame, overhead=overhead, tile_bytes=tile_bytes,
                     input_bytes=input_bytes)


def plot(result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, bandwidth in zip(axes, STORAGE_BYTES_PER_S):
        for rows in MODEL_ROWS:
            ax.plot(NODES, [result[(bandwidth, rows, n)]["total"] for n in NODES], marker=".", label=f"{rows} rows")
        ax.plot(NODES, [result[(bandwidth, MODEL_ROWS[0], n)]["storage"] for n in NODES], "k--", label="storage floor")
        ax.set_xscale("log"), ax.set_yscale("log")
        ax.set_xlabel("nodes (one task each at a time)")
        ax.set_title(f"4K x 200, --quality fast, storage {bandwidth / 1e9:.0f} GB/s")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("modelled seconds")
    axes[1].legend(fontsize=8, title="band height")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(ROOT / "build-release"))
    ap.add_argument("--work", default=str(ROOT / "build-release" / "bench-frames"))
    ap.add_argument("--model-only", action="store_true")
    ap.add_argument("--balanced", action="store_true", help="measure --quality balanced alone (docs/distributed_balanced.json)")
    ap.add_argument("--balanced-model-only", action="store_true", help="its model again from docs/distributed_balanced.json")
    args = ap.parse_args()
    build, work = Path(args.build), Path(args.work)
    cli = str(build / "tools" / "statfilter")
    docs = ROOT / "docs"
    if args.balanced or args.balanced_model_only:
        path = docs / "distributed_balanced.json"
        if args.balanced_model_only:
            data = json.loads(path.read_text())
        else:
            work.mkdir(parents=True, exist_ok=True)
            data = measure_balanced_1080p(build, work, cli)
            path.write_text(json.dumps(data, indent=1))
        result = balanced_model(data)
        for bandwidth in STORAGE_BYTES_PER_S:
            print(f"\nstorage {bandwidth / 1e9:.0f} GB/s: | nodes | modelled s | analysis | first passes | guides | windows |")
            for n in (1, 10, 100, 1000):
                m = result[(bandwidth, n)]
                print(f"| {n} | {m['total']:.0f} | {m['analysis']:.0f} | {m['first_pass']:.0f} | {m['guides']:.0f} | {m['window']:.0f} |")
        return
    data_path = docs / "distributed.json"
    if args.model_only:
        data = json.loads(data_path.read_text())
    else:
        work.mkdir(parents=True, exist_ok=True)
        data = dict(measured=measure_1080p(build, work, cli), tiles4k=measure_4k_tiles(work, cli))
        data_path.write_text(json.dumps(data, indent=1))
    result, constants = model(data["measured"], data["tiles4k"])
    plot(result, docs / "distributed_model.png")
    print(json.dumps(constants))
    for bandwidth in STORAGE_BYTES_PER_S:
        print(f"\nstorage {bandwidth / 1e9:.0f} GB/s: | nodes | best band rows | modelled s | statistics | reduce | "
              "reconstruct | assemble | storage floor |")
        for n in (1, 10, 100, 1000):
            best = min(MODEL_ROWS, key=lambda r: result[(bandwidth, r, n)]["total"])
            m = result[(bandwidth, best, n)]
            print(f"| {n} | {best} | {m['total']:.0f} | {m['statistics']:.0f} | {m['reduce']:.1f} | {m['reconstruct']:.0f} | "
                  f"{m['assemble']:.0f} | {m['storage']:.0f} |")


if __name__ == "__main__":
    main()
