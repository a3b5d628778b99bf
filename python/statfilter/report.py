"""One self-contained HTML page about a denoise: before and after (and the reference) for a few
frames, the motion and rank maps with their legends, the error per frame against a reference, and
what the pipeline chose and why.

    python -m statfilter.report IN OUT [--ref REF] -o report.html [--show 1,16,32] [--method auto]

IN is the noisy render, OUT the denoised frames (frame patterns as ``read_sequence`` takes them),
REF an optional reference. The page embeds every image as a base64 PNG and every plot as SVG, so it
is one file that opens anywhere. "What the pipeline chose" is the result of running ``--method``
(default ``auto``, which picks the method) on IN again, with ``--param name=value``; the maps come
from the ``motion`` filter (alpha: 1 = stationary over the shot, beta: 1 = moving in that frame) and
the ``error-threshold`` filter (the per-pixel temporal rank). Those runs cost about as much as the
denoise itself; ``--no-maps`` skips the last two. Only the public API is used (statfilter's ctypes
bindings) and NumPy; ``build_report`` returns the HTML for use from Python.
"""

from __future__ import annotations

import argparse
import base64
import html
import struct
import sys
import zlib
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import __version__
from .errors import Error
from .filter import Filter
from .metrics import compare
from .sequence import read_sequence

# Viridis at 9 stops: a colour map that reads the same in grey and for most colour-blind readers.
_VIRIDIS = np.array([
    [68, 1, 84], [72, 40, 120], [62, 74, 137], [49, 104, 142], [38, 130, 142],
    [31, 158, 137], [53, 183, 121], [109, 205, 89], [180, 222, 44], [253, 231, 37]], np.float64)


# ---- images ----------------------------------------------------------------------------------

def png(rgb: np.ndarray) -> bytes:
    """An 8-bit RGB PNG of an (height, width, 3) uint8 array (zlib, no other dependency)."""
    rgb = np.ascontiguousarray(rgb, np.uint8)
    h, w = rgb.shape[:2]
    raw = b"".join(b"\0" + rgb[y].tobytes() for y in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def _img(rgb: np.ndarray, alt: str) -> str:
    """An <img> with the PNG inline; small pictures are shown at 2x or more (pixels kept sharp)."""
    data = base64.b64encode(png(rgb)).decode("ascii")
    zoom = max(1, min(4, 320 // max(1, rgb.shape[1])))
    return '<img src="data:image/png;base64,%s" alt="%s" width="%d" height="%d">' % (
        data, html.escape(alt), rgb.shape[1] * zoom, rgb.shape[0] * zoom)


def _rgb(frame: np.ndarray) -> np.ndarray:
    """(h, w, c) -> (h, w, 3): the first three channels, or one channel as grey."""
    if frame.shape[2] >= 3:
        return frame[:, :, :3]
    return np.repeat(frame[:, :, :1], 3, axis=2)


def _shrink(image: np.ndarray, max_width: int) -> np.ndarray:
    step = max(1, -(-image.shape[1] // max_width))
    return image[::step, ::step]


def tonemap(frame: np.ndarray, exposure: float) -> np.ndarray:
    """Linear HDR -> sRGB-ish 8 bits: scaled by exposure, clipped to [0, 1], gamma 2.2."""
    x = np.nan_to_num(_rgb(frame).astype(np.float64) * exposure, nan=0.0, posinf=1.0, neginf=0.0)
    return (np.clip(x, 0.0, 1.0) ** (1 / 2.2) * 255 + 0.5).astype(np.uint8)


def colormap(values: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(h, w) values -> (h, w, 3) uint8 through viridis, lo at the dark end, hi at the bright end."""
    t = np.clip((np.nan_to_num(values.astype(np.float64)) - lo) / (hi - lo if hi > lo else 1.0), 0.0, 1.0)
    pos = t * (len(_VIRIDIS) - 1)
    i = np.minimum(pos.astype(int), len(_VIRIDIS) - 2)
    f = (pos - i)[..., None]
    return (_VIRIDIS[i] * (1 - f) + _VIRIDIS[i + 1] * f + 0.5).astype(np.uint8)


def legend(lo: float, hi: float, low_label: str, high_label: str, width: int = 260) -> str:
    """An SVG colour bar for colormap(), with the values and what they mean at both ends."""
    stops = "".join('<stop offset="%.3f" stop-color="rgb(%d,%d,%d)"/>' % ((k / (len(_VIRIDIS) - 1),) + tuple(c))
                    for k, c in enumerate(_VIRIDIS.astype(int)))
    gid = "g%d" % (abs(hash((lo, hi, low_label, high_label))) % 10 ** 8)
    return ('<svg class="legend" width="%d" height="38" viewBox="0 0 %d 38">'
            '<defs><linearGradient id="%s">%s</linearGradient></defs>'
            '<rect x="0" y="0" width="%d" height="14" fill="url(#%s)"/>'
            '<text x="0" y="30" font-size="11">%s %s</text>'
            '<text x="%d" y="30" font-size="11" text-anchor="end">%s %s</text></svg>'
            % (width, width, gid, stops, width, gid, _num(lo), html.escape(low_label), width, _num(hi),
               html.escape(high_label)))


def _num(v: float) -> str:
    return "%.4g" % v


# ---- the error plot --------------------------------------------------------------------------

def error_plot(frames: Sequence[int], series: Mapping[str, Sequence[float]], width: int = 640,
               height: int = 260) -> str:
    """An SVG line plot of relMSE per frame (log y axis), one line per series."""
    colours = ["#c0392b", "#2471a3", "#229954", "#7d3c98"]
    left, right, top, bottom = 60, 150, 12, 36
    vals = np.array([v for s in series.values() for v in s if np.isfinite(v) and v > 0] or [1.0])
    ylo, yhi = np.floor(np.log10(vals.min())), np.ceil(np.log10(vals.max()))
    if yhi <= ylo:
        yhi = ylo + 1
    f0, f1 = min(frames), max(frames)
    pw, ph = width - left - right, height - top - bottom

    def px(f):
        return left + (0.5 if f1 == f0 else (f - f0) / (f1 - f0)) * pw

    def py(v):
        return top + (yhi - np.log10(max(v, 10 ** ylo))) / (yhi - ylo) * ph
    parts = ['<svg class="plot" width="%d" height="%d" viewBox="0 0 %d %d">' % (width, height, width, height),
             '<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#999"/>' % (left, top, pw, ph)]
    for e in range(int(ylo), int(yhi) + 1):
        y = py(10.0 ** e)
        parts.append('<line x1="%d" x2="%d" y1="%.1f" y2="%.1f" stroke="#ddd"/>' % (left, left + pw, y, y))
        parts.append('<text x="%d" y="%.1f" font-size="11" text-anchor="end">1e%d</text>' % (left - 6, y + 4, e))
    for f in sorted(set([f0, f1] + list(frames[:: max(1, len(frames) // 8)]))):
        parts.append('<text x="%.1f" y="%d" font-size="11" text-anchor="middle">%d</text>' % (px(f), top + ph + 16, f))
    parts.append('<text x="%.1f" y="%d" font-size="11" text-anchor="middle">frame</text>' % (left + pw / 2, height - 4))
    parts.append('<text x="14" y="%.1f" font-size="11" transform="rotate(-90 14 %.1f)" text-anchor="middle">'
                 'relMSE</text>' % (top + ph / 2, top + ph / 2))
    for k, (name, values) in enumerate(series.items()):
        c = colours[k % len(colours)]
        points = " ".join("%.1f,%.1f" % (px(f), py(v)) for f, v in zip(frames, values))
        parts.append('<polyline class="series" data-name="%s" fill="none" stroke="%s" stroke-width="1.8" points="%s"/>'
                     % (html.escape(name), c, points))
        parts.append('<line x1="%d" x2="%d" y1="%d" y2="%d" stroke="%s" stroke-width="3"/>'
                     % (left + pw + 12, left + pw + 32, top + 10 + 18 * k, top + 10 + 18 * k, c))
        parts.append('<text x="%d" y="%d" font-size="12">%s</text>' % (left + pw + 38, top + 14 + 18 * k, html.escape(name)))
    parts.append("</svg>")
    return "".join(parts)


# ---- the page --------------------------------------------------------------------------------

_CSS = """
body { font-family: sans-serif; margin: 24px; color: #222; max-width: 1200px; }
h1 { font-size: 22px; } h2 { font-size: 18px; margin-top: 28px; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; font-size: 13px; } td, th { padding: 3px 10px; border-bottom: 1px solid #eee; text-align: left; }
figure { display: inline-block; margin: 0 12px 12px 0; vertical-align: top; } figcaption { font-size: 12px; color: #555; }
img { image-rendering: pixelated; border: 1px solid #ccc; } .note { font-size: 12px; color: #555; }
figure.map { max-width: 340px; }
"""


def _table(rows: Sequence[Tuple[str, object]]) -> str:
    body = "".join("<tr><th>%s</th><td>%s</td></tr>" % (html.escape(str(k)), html.escape(_fmt(v))) for k, v in rows)
    return "<table>%s</table>" % body


def _fmt(v) -> str:
    return _num(v) if isinstance(v, float) else str(v)


def _pick_frames(numbers: List[int], show: Optional[Sequence[int]], errors: Optional[List[float]]) -> List[int]:
    """Indices of the frames to show: those asked for, else the first, the worst (with a reference)
    or the middle one, and the last."""
    if show:
        missing = [f for f in show if f not in numbers]
        if missing:
            raise ValueError("--show: frame(s) %s are not in the sequence (frames %d-%d)"
                             % (",".join(map(str, missing)), numbers[0], numbers[-1]))
        return [numbers.index(f) for f in show]
    middle = int(np.argmax(errors)) if errors else len(numbers) // 2
    return sorted(set([0, middle, len(numbers) - 1]))


def build_report(noisy: np.ndarray, denoised: np.ndarray, reference: Optional[np.ndarray] = None,
                 frame_numbers: Optional[Sequence[int]] = None, show: Optional[Sequence[int]] = None,
                 method: str = "auto", params: Optional[Mapping[str, object]] = None, maps: bool = True,
                 names: Optional[Mapping[str, str]] = None, max_width: int = 480) -> str:
    """The report's HTML. noisy, denoised (and reference): (frames, height, width, channels) arrays
    of one shape. method and params: the filter run again on noisy for "what the pipeline chose"."""
    if noisy.shape != denoised.shape or (reference is not None and reference.shape != noisy.shape):
        raise ValueError("IN, OUT%s must have one shape: %s, %s%s" % (
            " and REF" if reference is not None else "", noisy.shape, denoised.shape,
            "" if reference is None else ", %s" % (reference.shape,)))
    n, h, w, c = noisy.shape
    numbers = list(frame_numbers) if frame_numbers is not None else list(range(1, n + 1))
    names = dict(names or {})
    params = dict(params or {})

    # What the pipeline chose: the method run again on the noisy frames.
    with Filter(method, **params) as flt:
        flt(noisy)
        chosen = dict(flt.results)
    choice_images = {k: v for k, v in chosen.items() if isinstance(v, np.ndarray)}
    choice_values = [(k, v) for k, v in chosen.items() if not isinstance(v, np.ndarray)]

    errors = totals = None
    if reference is not None:
        errors = {"IN (noisy)": [compare(noisy[i:i + 1], reference[i:i + 1])["rel_mse"] for i in range(n)],
                  "OUT (denoised)": [compare(denoised[i:i + 1], reference[i:i + 1])["rel_mse"] for i in range(n)]}
        totals = {"IN": compare(noisy, reference), "OUT": compare(denoised, reference)}
    shown = _pick_frames(numbers, show, errors["OUT (denoised)"] if errors else None)

    # One exposure for every picture: the 99th percentile of what is shown maps to white.
    basis = reference if reference is not None else denoised
    level = float(np.percentile(np.nan_to_num(_rgb(basis[shown[0]])), 99.0)) or 1.0
    exposure = 1.0 / level

    out = ['<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">',
           '<title>statfilter report</title><style>%s</style></head><body>' % _CSS,
           '<h1>statfilter report</h1>']
    out.append('<section id="summary"><h2>Inputs</h2>')
    out.append(_table([("IN (noisy)", names.get("in", "array")), ("OUT (denoised)", names.get("out", "array")),
                       ("REF (reference)", names.get("ref", "none") if reference is not None else "none"),
                       ("frames", "%d (%d-%d)" % (n, numbers[0], numbers[-1])),
                       ("size", "%d x %d, %d channel%s" % (w, h, c, "" if c == 1 else "s")),
                       ("statfilter", __version__)]))
    out.append("</section>")

    out.append('<section id="choice"><h2>What the pipeline chose, and why</h2>')
    out.append('<p class="note">The filter <code>%s</code>%s run again on IN; its results as the library '
               'reports them.</p>' % (html.escape(method), " with " + html.escape(
                   ", ".join("%s=%s" % kv for kv in params.items())) if params else ""))
    for key in ("method", "reason"):
        if key in chosen:
            out.append('<p id="chosen-%s"><b>%s:</b> %s</p>' % (key, key, html.escape(_fmt(chosen[key]))))
    out.append(_table(choice_values))
    out.append("</section>")

    out.append('<section id="frames"><h2>Before and after</h2>')
    out.append('<p class="note">Linear values x %s (the 99th percentile of %s frame %d is white), clipped, '
               'gamma 2.2; every picture at the same exposure.</p>'
               % (_num(exposure), "REF" if reference is not None else "OUT", numbers[shown[0]]))
    for i in shown:
        out.append('<div class="frame" data-frame="%d"><h3>Frame %d</h3>' % (numbers[i], numbers[i]))
        panels = [("IN (noisy)", noisy[i]), ("OUT (denoised)", denoised[i])]
        if reference is not None:
            panels.append(("REF (reference)", reference[i]))
        for label, frame in panels:
            caption = label
            if errors is not None and label != "REF (reference)":
                caption += ", relMSE %s" % _num(errors[label][i])
            out.append("<figure>%s<figcaption>%s</figcaption></figure>"
                       % (_img(_shrink(tonemap(frame, exposure), max_width), "%s frame %d" % (label, numbers[i])),
                          html.escape(caption)))
        out.append("</div>")
    out.append("</section>")

    map_images: List[Tuple[str, np.ndarray, float, float, str, str, str]] = []
    if maps:
        with Filter("motion") as flt:
            flt(noisy)
            motion = dict(flt.results)
        map_images.append(("motion alpha", motion["alpha"][0, :, :, 0], 0.0, 1.0, "moving", "stationary",
                           "alpha, per pixel over the shot: 1 = stationary (the temporal methods' part), "
                           "0 = moving; moving fraction %s" % _num(float(motion["moving_fraction"]))))
        for i in shown:
            map_images.append(("motion beta, frame %d" % numbers[i], motion["beta"][i, :, :, 0], 0.0, 1.0, "still",
                               "moving", "beta, frame %d: 1 = the pixel moves in this frame (source: %s)"
                               % (numbers[i], motion.get("beta_source", "?"))))
        with Filter("error-threshold") as flt:
            flt(noisy)
            ranks = dict(flt.results)
        rank_map = ranks["rank_map"][0, :, :, 0]
        map_images.append(("rank map", rank_map, 0.0, max(1.0, float(rank_map.max())), "rank", "rank",
                           "error-threshold's temporal rank per pixel (components kept); mean %s"
                           % _num(float(ranks.get("mean_rank", float(rank_map.mean()))))))
    for name, image in choice_images.items():
        img = image[0, :, :, 0]
        lo, hi = float(np.nanmin(img)), float(np.nanmax(img))
        map_images.append(("%s: %s" % (method, name), img, lo, hi if hi > lo else lo + 1, "", "",
                           "the image result %r of %s" % (name, method)))
    if map_images:
        out.append('<section id="maps"><h2>Motion and rank maps</h2>')
        for title, img, lo, hi, lo_label, hi_label, caption in map_images:
            out.append('<figure class="map">%s<br>%s<figcaption>%s</figcaption></figure>'
                       % (_img(_shrink(colormap(img, lo, hi), max_width), title), legend(lo, hi, lo_label, hi_label),
                          html.escape(caption)))
        out.append("</section>")

    if errors is not None:
        out.append('<section id="errors"><h2>Error per frame against REF</h2>')
        out.append(error_plot(numbers, errors))
        rows = []
        for key in ("rel_mse", "rel_mse_moving", "rel_mse_static", "psnr", "flicker", "jitter"):
            if key in totals["IN"]:
                rows.append("<tr><th>%s</th><td>%s</td><td>%s</td></tr>"
                            % (key, _num(totals["IN"][key]), _num(totals["OUT"][key])))
        out.append('<table id="totals"><tr><th></th><th>IN</th><th>OUT</th></tr>%s</table>' % "".join(rows))
        out.append("</section>")
    out.append('<p class="note">Written by python -m statfilter.report (statfilter %s).</p></body></html>' % __version__)
    return "\n".join(out)


def _param(text: str) -> Tuple[str, object]:
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError("expected name=value, got %r" % text)
    for kind in (int, float):
        try:
            return name, kind(value)
        except ValueError:
            pass
    return name, value


def main(argv: Optional[Sequence[str]] = None, prog: str = "python -m statfilter.report") -> int:
    """The command line; `statfilter report` (the CLI) runs this with prog="statfilter report"."""
    ap = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n\n")[0])
    ap.add_argument("input", metavar="IN", help="the noisy frames, e.g. 'render/indirect.####.exr'")
    ap.add_argument("output", metavar="OUT", help="the denoised frames")
    ap.add_argument("--ref", metavar="REF", help="reference frames: adds the error per frame")
    ap.add_argument("-o", "--html", required=True, metavar="report.html", help="the page to write")
    ap.add_argument("--frames", help="read only these frames, e.g. 1-12")
    ap.add_argument("--channels", help="channels to read, e.g. R,G,B")
    ap.add_argument("--show", help="frames to show side by side, e.g. 1,16,32 (default: first, worst or middle, last)")
    ap.add_argument("--method", default="auto", help="the filter whose choice is reported (default auto)")
    ap.add_argument("--param", action="append", type=_param, default=[], metavar="NAME=VALUE",
                    help="a parameter of --method (repeatable)")
    ap.add_argument("--no-maps", action="store_true", help="skip the motion and rank maps (two more filter runs)")
    ap.add_argument("--max-width", type=int, default=480, help="pictures wider than this are shown subsampled")
    opts = ap.parse_args(argv)
    try:
        noisy, info = read_sequence(opts.input, channels=opts.channels, frames=opts.frames, return_info=True)
        denoised = read_sequence(opts.output, channels=opts.channels, frames=opts.frames or info.frame_numbers)
        reference = None
        if opts.ref:
            reference = read_sequence(opts.ref, channels=opts.channels, frames=opts.frames or info.frame_numbers)
        show = [int(s) for s in opts.show.split(",")] if opts.show else None
        page = build_report(noisy, denoised, reference, info.frame_numbers, show, opts.method, dict(opts.param),
                            not opts.no_maps, {"in": opts.input, "out": opts.output, "ref": opts.ref or ""},
                            opts.max_width)
    except (Error, ValueError, OSError) as e:
        print("%s: error: %s" % (prog, e), file=sys.stderr)
        return 2
    with open(opts.html, "w", encoding="utf-8") as f:
        f.write(page)
    print("%s: wrote %s (%d KiB)" % (prog, opts.html, (len(page.encode()) + 1023) // 1024))
    return 0


if __name__ == "__main__":
    sys.exit(main())
