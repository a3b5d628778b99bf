"""Measures a renderer start-up in pixels: the crop-window merge parameter crop_window_cost
(--crop-window-cost), "the pixels one more render start-up is worth", for Blender Cycles.

    STATFILTER_BPY_PYTHON=venv/bin/python python3 bench/render_cost.py [--blend scene.blend] [--samples 16 64]

Without --blend it renders the hand-off tests' scene (tests/handoff/make_scene.py) at 320 x 240.
For each sample count it times, in one Blender process, a render of a 4 x 4 border (the start-up:
scene sync, BVH build, kernel set-up, writing the file) and of the whole frame, and prints

    start-up seconds, seconds per pixel, start-up in pixels = start-up / seconds per pixel,

plus the cost of a new process (Python, import bpy, open the .blend), which a farm pays per job
when each window is its own job. Each timing is the best of --repeat runs.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CHILD = r'''
import json, sys, time
t = time.perf_counter()
import bpy
bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
process = time.perf_counter() - t
scene = bpy.context.scene
r = scene.render
r.image_settings.file_format = "OPEN_EXR"
out = {"process_seconds": process, "width": r.resolution_x * r.resolution_percentage // 100,
       "height": r.resolution_y * r.resolution_percentage // 100, "rows": []}
for samples in json.loads(sys.argv[3]):
    scene.cycles.samples = samples
    def render(border):
        r.use_border = border is not None
        r.use_crop_to_border = True
        if border:
            r.border_min_x, r.border_min_y, r.border_max_x, r.border_max_y = border
        r.filepath = sys.argv[2]
        best = None
        for _ in range(int(sys.argv[4])):
            t = time.perf_counter()
            bpy.ops.render.render(write_still=True)
            d = time.perf_counter() - t
            best = d if best is None else min(best, d)
        return best
    W, H = out["width"], out["height"]
    small = render((0.5, 0.5, 0.5 + 4.5 / W, 0.5 + 4.5 / H))
    full = render(None)
    per_pixel = max(full - small, 1e-9) / (W * H - 16)
    out["rows"].append({"samples": samples, "startup_seconds": small, "full_seconds": full,
                        "seconds_per_pixel": per_pixel, "startup_pixels": small / per_pixel,
                        "process_pixels": process / per_pixel})
print("RESULT " + json.dumps(out))
'''


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--blend", help="the scene (default: the hand-off tests' scene at 320 x 240)")
    ap.add_argument("--samples", type=int, nargs="+", default=[16, 64])
    ap.add_argument("--repeat", type=int, default=3)
    opts = ap.parse_args()
    python = os.environ.get("STATFILTER_BPY_PYTHON", sys.executable)
    with tempfile.TemporaryDirectory() as d:
        blend = opts.blend
        if not blend:
            blend = os.path.join(d, "scene.blend")
            subprocess.run([python, os.path.join(ROOT, "tests", "handoff", "make_scene.py"), blend, "320", "240"],
                           check=True, capture_output=True)
        proc = subprocess.run([python, "-c", CHILD, os.path.abspath(blend), os.path.join(d, "out.exr"),
                               json.dumps(opts.samples), str(opts.repeat)], check=True, capture_output=True, text=True)
    result = json.loads(next(l for l in proc.stdout.splitlines() if l.startswith("RESULT "))[7:])
    print("%d x %d; a new process (Python, import bpy, open the .blend): %.2f s"
          % (result["width"], result["height"], result["process_seconds"]))
    print("| samples | start-up (4 x 4 border), s | whole frame, s | us per pixel | start-up in pixels | new process in pixels |")
    print("|---|---|---|---|---|---|")
    for row in result["rows"]:
        print("| %d | %.3f | %.3f | %.2f | %.0f | %.0f |" % (row["samples"], row["startup_seconds"], row["full_seconds"],
                                                         row["seconds_per_pixel"] * 1e6, row["startup_pixels"],
                                                         row["process_pixels"]))


if __name__ == "__main__":
    main()
