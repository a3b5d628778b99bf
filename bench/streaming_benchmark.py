#!/usr/bin/env python3
"""Production-size runs: wall and CPU seconds, peak RSS against the memory budget, the ratio to a plain
oiiotool read + write of the same frames (the I/O floor, measured in the same run), 1 thread against all.

Frames are made here from the shipped sample (sample/cornell_moving/spp0004, resized with oiiotool and
repeated to the frame count: the noise is not realistic, the cost is) and never committed.

    python3 bench/streaming_benchmark.py                      # 1080p x 32, then 1080p x 200 and 4K x 100
    python3 bench/streaming_benchmark.py --only 1080p-32      # one shot
Writes docs/streaming.json and docs/streaming.md. Build first: bash scripts/build.sh build-release -DCMAKE_BUILD_TYPE=Release
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample" / "cornell_moving" / "spp0004"

# name: (width, height, frames, memory budget or None = the default)
SHOTS = {
    "1080p-32": (1920, 1080, 32, None),
    "1080p-200": (1920, 1080, 200, "2G"),
    "4K-100": (3840, 2160, 100, "4G"),
}
# label: (CLI arguments after IN OUT, also on 1 thread, shots it runs on)
ALL = tuple(SHOTS)
CONFIGS = [
    ("copy", ["copy"], True, ALL),
    ("--quality fast", ["denoise", "--quality", "fast"], True, ALL),
    ("--method pca (log, automatic rank)", ["denoise", "--method", "pca"], False, ("1080p-32",)),
    ("--method error-threshold", ["denoise", "--method", "error-threshold"], False, ("1080p-32",)),
    ("--quality fast --memory 3G", ["denoise", "--quality", "fast", "--memory", "3G"], False, ("1080p-200",)),
    ("--quality balanced", ["denoise", "--quality", "balanced"], True, ALL),
    ("--prefilter oidn", ["denoise", "--prefilter", "oidn"], False, ("1080p-32",)),
    # a budget just above the least this shot runs in: many bands, every buffer counted
    ("--quality balanced --memory 1200M", ["denoise", "--quality", "balanced", "--memory", "1200M"], False,
     ("1080p-32",)),
]


def size_bytes(text):
    """'1200M', '4G' as the CLI reads them (binary units)."""
    units = {"K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}
    return float(text[:-1]) * units[text[-1].upper()] if text[-1].upper() in units else float(text)


def make_frames(work, width, height, frames):
    """Resized sample frames, repeated; made once per size and reused by later runs."""
    oiiotool = shutil.which("oiiotool")
    if not oiiotool:
        sys.exit("oiiotool (openimageio-tools) is needed")
    shot = work / f"{width}x{height}x{frames}"
    if (shot / f"in.{frames:04d}.exr").exists():
        return shot
    shot.mkdir(parents=True, exist_ok=True)
    base = work / f"{width}x{height}"
    base.mkdir(exist_ok=True)
    for f in range(1, 33):
        target = base / f"in.{f:04d}.exr"
        if not target.exists():
            subprocess.run([oiiotool, str(SAMPLE / f"indirect.{f:04d}.exr"), "--resize", f"{width}x{height}", "-d", "half",
                            "--compression", "zip", "-o", str(target)], check=True)
    for f in range(1, frames + 1):  # links: the same 32 frames back and forth, no jump at the seams
        k = (f - 1) % 62
        src = base / f"in.{(k if k < 32 else 62 - k) + 1:04d}.exr"
        dst = shot / f"in.{f:04d}.exr"
        if not dst.exists():
            os.link(src, dst)
    return shot


def timed(cmd, env=None):
    """Runs cmd under /usr/bin/time: (exit code, wall s, cpu s, peak RSS bytes, stderr tail)."""
    t0 = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "TIME %e %U %S %M", *map(str, cmd)], capture_output=True, text=True,
                          env=env)
    wall = time.perf_counter() - t0
    line = [l for l in proc.stderr.splitlines() if l.startswith("TIME ")][-1].split()
    cpu = float(line[2]) + float(line[3])
    rest = [l for l in proc.stderr.splitlines() if not l.startswith(("TIME ", "Command exited"))]
    return proc.returncode, wall, cpu, int(line[4]) * 1024, (rest[-1] if rest else "")


def run_shot(name, cli, work, threads_all, only_configs=None):
    width, height, frames, memory = SHOTS[name]
    shot = make_frames(work, width, height, frames)
    out = work / "out"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir()
    oiiotool = shutil.which("oiiotool")
    rows = []
    # The floor: a plain read + write of the same frames, same compression.
    rc, wall, cpu, rss, _ = timed([oiiotool, "--frames", f"1-{frames}", shot / "in.%04d.exr", "-d", "half",
                                   "--compression", "zip", "-o", out / "io.%04d.exr"])
    floor = wall
    rows.append(dict(config="oiiotool read + write (I/O floor)", threads=None, wall=wall, cpu=cpu, rss=rss, rc=rc))
    budget_args = ["--memory", memory] if memory else []
    for label, args, one_thread, shots in CONFIGS:
        if name not in shots or (only_configs and label not in only_configs):
            continue
        # 1 thread against all on the 1080p x 32 shot; the long shots at all threads only
        both = threads_all > 1 and one_thread and name == "1080p-32"
        for threads in ([1, threads_all] if both else [threads_all]):
            own_budget = [] if "--memory" in args else budget_args  # a row may name its own budget
            cmd = [cli, args[0], shot / "in.####.exr", out / "o.####.exr", *args[1:], *own_budget,
                   "--threads", str(threads), "--quiet", "--overwrite"]
            env = None
            if threads == 1:  # the libraries' own pools too (OpenCV in the in-memory filters, OpenBLAS)
                env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OPENCV_FOR_THREADS_NUM="1", OMP_NUM_THREADS="1")
            rc, wall, cpu, rss, tail = timed(cmd, env)
            row = dict(config=label, threads=threads, wall=wall, cpu=cpu, rss=rss, rc=rc)
            given = args[args.index("--memory") + 1] if "--memory" in args else memory
            if given and rc == 0:
                row["note"] = f"peak RSS - budget ({given}): {(rss - size_bytes(given)) / 2**30:+.2f} GiB"
            if rc != 0:
                row["error"] = tail
            rows.append(row)
            print(f"{name} {label} threads {threads}: rc {rc} {wall:.1f} s, {rss / 2**30:.2f} GiB {tail if rc else ''}",
                  flush=True)
            if rc != 0:
                break  # refused (memory) or unavailable: the thread count does not change that
    for r in rows:
        r["ratio_to_floor"] = r["wall"] / floor
    return dict(shot=name, width=width, height=height, frames=frames, memory=memory, floor=floor, rows=rows)


def report(results, command):
    lines = ["# Production-size runs: streaming, memory and threads", "",
             f"Command: `{command}` (frames made from the shipped sample by resizing; the CLI built in Release).",
             f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores. Wall and CPU seconds, "
             "peak resident memory (`/usr/bin/time`), and the wall time over a plain `oiiotool` read + write of the "
             "same frames measured in the same run.", ""]
    for shot in results:
        lines += [f"## {shot['width']} x {shot['height']}, {shot['frames']} frames"
                  + (f", `--memory {shot['memory']}`" if shot["memory"] else ", default memory budget"), "",
                  "| run | threads | wall s | CPU s | peak RSS | / I/O floor | note |", "|---|---|---|---|---|---|---|"]
        for r in shot["rows"]:
            note = (r.get("error") or r.get("note", ""))[:160].replace("|", "/")
            lines.append(f"| {r['config']} | {r['threads'] or ''} | {r['wall']:.1f} | {r['cpu']:.1f} | "
                         f"{r['rss'] / 2**30:.2f} GiB | {r['ratio_to_floor']:.2f}x | {note} |")
        by = {(r["config"], r["threads"]): r for r in shot["rows"]}
        speedups = [f"{c}: {by[(c, 1)]['wall'] / by[(c, 2)]['wall']:.2f}x" for c, *_ in CONFIGS
                    if (c, 1) in by and (c, 2) in by and by[(c, 1)]["rc"] == 0 and by[(c, 2)]["rc"] == 0]
        if speedups:
            lines += ["", "Wall time on 1 thread over 2 threads: " + ", ".join(speedups) + "."]
        lines.append("")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", action="append", choices=list(SHOTS), help="run only these shots")
    ap.add_argument("--config", action="append", help="run only these configurations (labels); the other rows of "
                    "the shot are kept from docs/streaming.json, the I/O floor is measured again")
    ap.add_argument("--cli", default=str(ROOT / "build-release" / "tools" / "statfilter"))
    ap.add_argument("--work", default=str(ROOT / "build-release" / "bench-frames"))
    args = ap.parse_args()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    threads = os.cpu_count() or 1
    docs = ROOT / "docs"
    old = {}
    if (docs / "streaming.json").exists():
        old = {s["shot"]: s for s in json.loads((docs / "streaming.json").read_text())}
    for name in args.only or list(SHOTS):
        new = run_shot(name, args.cli, work, threads, args.config)
        if args.config and name in old:  # keep the rows not re-run
            rerun = {(r["config"], r["threads"]) for r in new["rows"]}
            kept = [r for r in old[name]["rows"] if (r["config"], r["threads"]) not in rerun and r["threads"] is not None]
            for r in kept:  # measured against the floor of their own run, which the note names
                if "earlier run" not in r.get("note", ""):
                    r["note"] = (f"earlier run (I/O floor {old[name]['floor']:.1f} s) " + r.get("note", "")).strip()
            new["rows"] = new["rows"][:1] + kept + new["rows"][1:]
        old[name] = new
        results = [old[n] for n in SHOTS if n in old]
        (docs / "streaming.json").write_text(json.dumps(results, indent=1))
        (docs / "streaming.md").write_text(report(results, "python3 bench/streaming_benchmark.py --only 1080p-32; "
                                                  "python3 bench/streaming_benchmark.py --only 1080p-200" +
                                                  "".join(f" --config '{c}'" for c in (args.config or []))))


if __name__ == "__main__":
    main()
