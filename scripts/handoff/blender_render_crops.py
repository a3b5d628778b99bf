"""Render the crop windows of a statfilter crops.json with Blender: one border render per window.

A farm runs it as it is, in Blender:

    blender -b scene.blend --python blender_render_crops.py -- crops.json OUT_PATTERN [--frames 3-5,9]

or in any Python that has the ``bpy`` module (``pip install bpy``; the scene then comes from --blend):

    python blender_render_crops.py -- crops.json OUT_PATTERN --blend scene.blend [--frames 12]

OUT_PATTERN names one file per window: ``#`` (one per digit) or ``%04d`` is the frame number,
``{window}`` the window's index in its frame (its ``index`` in crops.json), e.g.
``rr.{window}.####.exr``, which is what ``statfilter merge DENOISED rr.{window}.####.exr OUT
--crops crops.json`` reads back. Each file is the size of its window (``use_crop_to_border``), or
the whole frame with only the window rendered when --full-frame is given.

The y flip: crops.json counts rows from the top of the image (``y``, as EXR does); Blender's render
border counts from the bottom, as fractions of the frame. A window x, y, width, height of a W x H
frame is the border

    min_x = x / W,  max_x = (x + width) / W,  min_y = 1 - (y + height) / H,  max_y = 1 - y / H

(the window's ``border`` member). Blender turns a border into pixels by truncating border x W, so
this script sets each edge half a pixel inside the next pixel ((x + 0.5) / W, ...) to render exactly
the window's pixels whatever the floating-point rounding.

It can also be imported (``import blender_render_crops``) and ``render_crops(crops, pattern)``
called with the scene already open. It renders with the scene's own settings (engine, samples,
layers, output colour depth); only the border, the crop and the output format (OpenEXR) are set for
each render, and put back afterwards. The scene's resolution x percentage must be the crops.json
``width`` x ``height``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
from typing import Any, Dict, Iterable, List, Optional, Sequence, Set, Tuple

FORMAT = "statfilter-crops"
SCHEMA_VERSIONS = (1,)


class CropsError(ValueError):
    """crops.json is not a statfilter crop-window file this script reads, or does not fit the scene."""


def load_crops(path_or_doc: Any) -> Dict[str, Any]:
    """crops.json (a path or the parsed dict), checked for what this script uses."""
    if isinstance(path_or_doc, dict):
        doc = path_or_doc
    else:
        with open(path_or_doc, encoding="utf-8") as f:
            doc = json.load(f)
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise CropsError("not a statfilter crop-window file (\"format\" is not %r)" % FORMAT)
    version = doc.get("schema_version", doc.get("version"))
    if version not in SCHEMA_VERSIONS:
        raise CropsError("crops.json schema version %r is not supported (this script reads %s)"
                         % (version, ", ".join(map(str, SCHEMA_VERSIONS))))
    for key in ("width", "height"):
        if not isinstance(doc.get(key), int) or doc[key] < 1:
            raise CropsError("crops.json %r must be a positive integer" % key)
    if not isinstance(doc.get("frames"), list):
        raise CropsError("crops.json has no \"frames\" list")
    return doc


def parse_frames(text: str) -> Set[int]:
    """'3-5,9' -> {3, 4, 5, 9} (the syntax of render_frames and of --frames)."""
    frames: Set[int] = set()
    for part in filter(None, (p.strip() for p in text.split(","))):
        m = re.fullmatch(r"(-?\d+)(?:-(-?\d+))?", part)
        if not m:
            raise CropsError("bad frame list %r (expected e.g. 3-5,9)" % text)
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        if last < first:
            raise CropsError("bad frame range %r (the last frame is before the first)" % part)
        frames.update(range(first, last + 1))
    return frames


def windows_by_frame(doc: Dict[str, Any], frames: Optional[Iterable[int]] = None) -> List[Tuple[int, List[Dict[str, Any]]]]:
    """[(frame, [window, ...]), ...] ascending by frame; each window gets its index if it has none."""
    wanted = None if frames is None else set(frames)
    out = []
    for entry in doc["frames"]:
        frame = entry["frame"]
        if wanted is not None and frame not in wanted:
            continue
        windows = []
        for k, w in enumerate(entry.get("windows", [])):
            w = dict(w)
            w.setdefault("index", k)
            if w["x"] < 0 or w["y"] < 0 or w["width"] < 1 or w["height"] < 1 or \
                    w["x"] + w["width"] > doc["width"] or w["y"] + w["height"] > doc["height"]:
                raise CropsError("window %d of frame %d is outside the %d x %d frame"
                                 % (k, frame, doc["width"], doc["height"]))
            windows.append(w)
        if windows:
            out.append((frame, windows))
    out.sort(key=lambda fw: fw[0])
    return out


def blender_border(window: Dict[str, Any], width: int, height: int) -> Tuple[float, float, float, float]:
    """(min_x, min_y, max_x, max_y) of Blender's render border for a window (y flipped: Blender's y
    goes up from the bottom edge), each edge half a pixel inside so that Blender's truncation of
    border x size lands on the window's own pixel edges."""
    x0, x1 = window["x"], window["x"] + window["width"]
    # Blender row r (from the bottom) is crops.json row height - 1 - r.
    b0, b1 = height - (window["y"] + window["height"]), height - window["y"]
    return ((x0 + 0.5) / width, (b0 + 0.5) / height,
            min(1.0, (x1 + 0.5) / width), min(1.0, (b1 + 0.5) / height))


def output_path(pattern: str, frame: int, window: int) -> str:
    """The pattern with {window} and the frame number (#### or %04d) filled in."""
    path = pattern.replace("{window}", str(window))
    m = re.search(r"#+", path)
    if m:
        digits = len(m.group(0))
        sign = "-" if frame < 0 else ""
        return path[:m.start()] + sign + str(abs(frame)).zfill(digits) + path[m.end():]
    if re.search(r"%0?\d*d", path):
        return re.sub(r"%0?\d*d", lambda mm: mm.group(0) % frame, path, count=1)
    raise CropsError("the output pattern %r has no frame number (#### or %%04d)" % pattern)


def render_crops(doc: Any, pattern: str, scene: Any = None, frames: Optional[Iterable[int]] = None,
                 full_frame: bool = False, log=print) -> List[str]:
    """Renders every window of crops.json (a path or dict) in the open Blender file; returns the
    files written, in the order rendered."""
    import bpy  # only here, so the helpers above import without Blender

    doc = load_crops(doc)
    scene = scene or bpy.context.scene
    r = scene.render
    width = r.resolution_x * r.resolution_percentage // 100
    height = r.resolution_y * r.resolution_percentage // 100
    if (width, height) != (doc["width"], doc["height"]):
        raise CropsError("the scene renders %d x %d (resolution x percentage); crops.json is for %d x %d"
                         % (width, height, doc["width"], doc["height"]))
    if "{window}" not in pattern and any(len(ws) > 1 for _, ws in windows_by_frame(doc, frames)):
        raise CropsError("a frame has several windows: the output pattern needs {window}")
    saved = (r.use_border, r.use_crop_to_border, r.border_min_x, r.border_min_y, r.border_max_x,
             r.border_max_y, r.filepath, r.image_settings.file_format, scene.frame_current)
    written = []
    try:
        r.image_settings.file_format = "OPEN_EXR"
        r.use_border = True
        r.use_crop_to_border = not full_frame
        for frame, windows in windows_by_frame(doc, frames):
            scene.frame_set(frame)
            for w in windows:
                r.border_min_x, r.border_min_y, r.border_max_x, r.border_max_y = blender_border(w, width, height)
                path = os.path.abspath(output_path(pattern, frame, w["index"]))
                os.makedirs(os.path.dirname(path), exist_ok=True)
                r.filepath = path
                bpy.ops.render.render(write_still=True, scene=scene.name)
                if not os.path.exists(path):
                    raise RuntimeError("Blender wrote no %s (render.use_file_extension adds an extension: "
                                       "end OUT_PATTERN with .exr)" % path)
                log("statfilter handoff: frame %d window %d (x %d, y %d, %d x %d) -> %s"
                    % (frame, w["index"], w["x"], w["y"], w["width"], w["height"], path))
                written.append(path)
    finally:
        (r.use_border, r.use_crop_to_border, r.border_min_x, r.border_min_y, r.border_max_x,
         r.border_max_y, r.filepath, r.image_settings.file_format, frame_current) = saved
        scene.frame_set(frame_current)
    return written


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    # Blender passes its own arguments before "--"; plain Python passes the script's after it too.
    args = argv[argv.index("--") + 1:] if "--" in argv else argv[1:]
    parser = argparse.ArgumentParser(prog="blender_render_crops.py",
                                     description="Render the crop windows of a statfilter crops.json.")
    parser.add_argument("crops", help="crops.json as statfilter detect --crops wrote it")
    parser.add_argument("pattern", help="output files, e.g. rr.{window}.####.exr")
    parser.add_argument("--frames", help="only these frames, e.g. 12 or 3-5,9 (default: all with windows)")
    parser.add_argument("--blend", help="open this .blend first (when run outside Blender, with bpy)")
    parser.add_argument("--full-frame", action="store_true",
                        help="write whole frames with only the window rendered (default: window-sized files)")
    opts = parser.parse_args(args)
    try:
        import bpy
        if opts.blend:
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(opts.blend))
        frames = parse_frames(opts.frames) if opts.frames else None
        written = render_crops(opts.crops, opts.pattern, frames=frames, full_frame=opts.full_frame)
    except (CropsError, OSError, json.JSONDecodeError) as e:
        print("blender_render_crops.py: error: %s" % e, file=sys.stderr)
        return 2
    print("statfilter handoff: %d window renders written" % len(written))
    return 0


if __name__ == "__main__":
    code = main()
    if code:
        sys.exit(code)
