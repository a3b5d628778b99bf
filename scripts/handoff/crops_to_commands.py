"""Commands that render the crop windows of a statfilter crops.json with Arnold or RenderMan.

    python3 crops_to_commands.py crops.json arnold    --scene 'shot.####.ass' --out 'rr.{window}.####.exr'
    python3 crops_to_commands.py crops.json renderman --scene 'shot.####.rib' --out 'rr.{window}.####.exr'

prints one line per window and needs nothing but Python 3: for Arnold a kick command (a shell script
a farm can split by line, one render per line); for RenderMan a line of RIB, ``Display`` and
``CropWindow`` for the window, to go before ``WorldBegin`` of that frame's RIB (the frame and the
RIB file are in the line's comment). ``####`` (one ``#`` per digit) or ``%04d`` is the frame number, ``{window}``
the window's index in its frame, as ``statfilter merge DENOISED rr.{window}.####.exr OUT --crops
crops.json`` reads the results back. --frames 3-5,9 keeps some frames only. docs/rerender.md
explains the coordinates:

- Arnold: ``kick -rg x0 y0 x1 y1`` is a region in pixels, inclusive, y down from the top (Arnold's
  options region_min_x/y, region_max_x/y): x0 = x, y0 = y, x1 = x + width - 1, y1 = y + height - 1.
- RenderMan: ``CropWindow xmin xmax ymin ymax`` (RIB; ``Ri.CropWindow`` in the Python API) is in NDC, (0, 0) at the top left; RenderMan renders the pixels ceil(W * xmin) ..
  ceil(W * xmax - 1), so each edge is written half a pixel inside: xmin = (x - 0.5) / W (at least
  0), xmax = (x + width - 0.5) / W, and likewise in y, which then selects exactly the window's pixels.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from typing import List, Optional, Sequence, Tuple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_render_crops import CropsError, load_crops, output_path, parse_frames, windows_by_frame  # noqa: E402


def arnold_region(w) -> Tuple[int, int, int, int]:
    """kick -rg x0 y0 x1 y1: inclusive pixel corners, y down from the top."""
    return w["x"], w["y"], w["x"] + w["width"] - 1, w["y"] + w["height"] - 1


def renderman_crop(w, width: int, height: int) -> Tuple[float, float, float, float]:
    """CropWindow xmin xmax ymin ymax in NDC (y down), each edge half a pixel inside."""
    return (max(0.0, (w["x"] - 0.5) / width), (w["x"] + w["width"] - 0.5) / width,
            max(0.0, (w["y"] - 0.5) / height), (w["y"] + w["height"] - 0.5) / height)


def commands(doc, renderer: str, scene: str, out: str, frames=None) -> List[str]:
    doc = load_crops(doc)
    lines = []
    for frame, windows in windows_by_frame(doc, frames):
        scene_file = output_path(scene, frame, 0) if ("#" in scene or "%" in scene) else scene
        for w in windows:
            target = output_path(out, frame, w["index"])
            if renderer == "arnold":
                x0, y0, x1, y1 = arnold_region(w)
                lines.append("kick -i %s -rg %d %d %d %d -o %s -dw -dp"
                             % (shlex.quote(scene_file), x0, y0, x1, y1, shlex.quote(target)))
            else:
                crop = " ".join("%.9g" % v for v in renderman_crop(w, doc["width"], doc["height"]))
                lines.append('Display "%s" "openexr" "rgba" CropWindow %s  # frame %d window %d: before WorldBegin of %s'
                             % (target.replace('"', '\\"'), crop, frame, w["index"], scene_file))
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="crops_to_commands.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("crops", help="crops.json as statfilter detect --crops wrote it")
    parser.add_argument("renderer", choices=["arnold", "renderman"])
    parser.add_argument("--scene", required=True, help="the scene per frame, e.g. shot.####.ass or shot.####.rib")
    parser.add_argument("--out", required=True, help="the image per window, e.g. rr.{window}.####.exr")
    parser.add_argument("--frames", help="only these frames, e.g. 12 or 3-5,9")
    opts = parser.parse_args(argv)
    try:
        frames = parse_frames(opts.frames) if opts.frames else None
        lines = commands(opts.crops, opts.renderer, opts.scene, opts.out, frames)
    except (CropsError, OSError, ValueError) as e:
        print("crops_to_commands.py: error: %s" % e, file=sys.stderr)
        return 2
    for line in lines:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
