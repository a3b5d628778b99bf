#!/usr/bin/env python3
"""The peers statfilter is measured against, each run in its own process on frames in memory.

  oidn        Intel Open Image Denoise through PyPI `pyoidn`, frame by frame, HDR mode; colour only
              or with the albedo/normal passes; quality high or fast.
  nlm         OpenCV's temporal non-local means (`cv2.fastNlMeansDenoisingMulti`, PyPI
              `opencv-python-headless`). It takes 8-bit images, so HDR goes through the curve below.
  nlm-encode  the 8-bit curve alone (encode, decode): the error floor the curve puts under nlm.
  gaussian    a temporal Gaussian average of each pixel (the naive baseline).
  identity    returns the input: the harness's own memory, to read the other peers' peak RSS against.

HDR to 8 bits for NLM, per sequence: s = the median of the positive samples, M = the maximum;
code = round(255 * log(1 + x/s) / log(1 + M/s)), negatives to 0; decoded by the inverse. Nothing
clips, and at a 1000:1 range one code step is ~3% of the value, well under 4-64 spp noise (the
nlm-encode rows measure what it costs).

Usage (the benchmark calls this under /usr/bin/time for the peak memory):
    python3 bench/peers.py NAME PARAMS_JSON IN.npy OUT.npy [--aux DIR] [--repeats N]
Prints {"seconds": best compute time of the repeats}. The peers are optional: available() says
which import here.
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np


def available():
    """{peer: None if usable, else why not}."""
    out = {"gaussian": None, "identity": None}
    try:
        import pyoidn  # noqa: F401
        out["oidn"] = None
    except ImportError as e:
        out["oidn"] = f"pyoidn not installed ({e})"
    try:
        import cv2  # noqa: F401
        out["nlm"] = out["nlm-encode"] = None
    except ImportError as e:
        out["nlm"] = out["nlm-encode"] = f"opencv-python-headless not installed ({e})"
    return out


def sweep(have_aux):
    """(label, peer, params) of every peer configuration measured."""
    configs = [("OIDN high", "oidn", {"quality": "high"}), ("OIDN fast", "oidn", {"quality": "fast"})]
    if have_aux:
        configs += [("OIDN high + albedo/normal", "oidn", {"quality": "high", "aux": True}),
                    ("OIDN fast + albedo/normal", "oidn", {"quality": "fast", "aux": True})]
    configs.append(("NLM 8-bit curve only", "nlm-encode", {}))
    for window in (3, 5):
        for h in (5, 10, 20, 40):
            configs.append((f"NLM multi w{window} h{h}", "nlm", {"window": window, "h": h}))
    configs += [(f"temporal gaussian s{s}", "gaussian", {"sigma": s}) for s in (0.5, 1, 2, 4)]
    return configs


# --- the peers -------------------------------------------------------------------------------

def oidn(seq, quality="high", aux=False, albedo=None, normal=None):
    import pyoidn
    out = np.empty_like(seq)
    for t in range(seq.shape[0]):
        color = np.ascontiguousarray(np.maximum(seq[t], 0))
        if aux:
            out[t] = pyoidn.denoise(color, np.ascontiguousarray(albedo[t]), np.ascontiguousarray(normal[t]),
                                    hdr=True, quality=quality)
        else:
            out[t] = pyoidn.denoise(color, hdr=True, quality=quality)
    return out


class LogCurve8:
    """The documented HDR -> 8-bit curve (module docstring)."""

    def __init__(self, seq):
        positive = seq[seq > 0]
        self.s = float(np.median(positive)) if positive.size else 1.0
        self.span = float(np.log1p(max(float(seq.max()), self.s) / self.s))

    def encode(self, x):
        return np.clip(np.round(255 * np.log1p(np.maximum(x, 0) / self.s) / self.span), 0, 255).astype(np.uint8)

    def decode(self, code):
        return (self.s * np.expm1(code.astype(np.float32) / 255 * self.span)).astype(np.float32)


def nlm(seq, window=5, h=20, template=7, search=21):
    import cv2
    curve = LogCurve8(seq)
    codes = curve.encode(seq)
    frames = seq.shape[0]
    out = np.empty_like(codes)
    for t in range(frames):
        # OpenCV wants the frame centred in an odd window inside the sequence: shrink it at the ends.
        w = min(window, 2 * min(t, frames - 1 - t) + 1)
        imgs = [codes[i] for i in range(t - w // 2, t + w // 2 + 1)]
        out[t] = cv2.fastNlMeansDenoisingMulti(imgs, w // 2, w, None, float(h), template, search)
    return curve.decode(out)


def nlm_encode(seq):
    curve = LogCurve8(seq)
    return curve.decode(curve.encode(seq))


def gaussian(seq, sigma=1.0):
    """Each pixel's Gaussian-weighted mean over time, renormalised where the window leaves the sequence."""
    radius = max(1, int(np.ceil(3 * sigma)))
    offsets = np.arange(-radius, radius + 1)
    weights = np.exp(-0.5 * (offsets / sigma) ** 2)
    frames = seq.shape[0]
    out = np.zeros_like(seq, dtype=np.float64)
    norm = np.zeros(frames)
    for k, w in zip(offsets, weights):
        lo, hi = max(0, -k), min(frames, frames - k)
        out[lo:hi] += w * seq[lo + k:hi + k]
        norm[lo:hi] += w
    return (out / norm[:, None, None, None]).astype(np.float32)


def run(name, params, seq, aux_dir=None):
    if name == "oidn":
        extra = {}
        if params.get("aux"):
            sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "build" / "python"))
            import statfilter
            extra = dict(albedo=statfilter.read_sequence(str(Path(aux_dir) / "albedo.####.exr")),
                         normal=statfilter.read_sequence(str(Path(aux_dir) / "normal.####.exr")))
        oidn(seq[:1], **params, **{k: v[:1] for k, v in extra.items()})  # device start-up, not timed
        return lambda: oidn(seq, **params, **extra)
    if name == "nlm":
        return lambda: nlm(seq, **params)
    if name == "nlm-encode":
        return lambda: nlm_encode(seq)
    if name == "gaussian":
        return lambda: gaussian(seq, **params)
    if name == "identity":
        return lambda: seq.copy()
    raise SystemExit(f"unknown peer '{name}'")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("name")
    parser.add_argument("params")
    parser.add_argument("input", type=Path)
    parser.add_argument("output", type=Path)
    parser.add_argument("--aux", type=Path)
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    seq = np.load(args.input)
    work = run(args.name, json.loads(args.params), seq, args.aux)
    best, out = float("inf"), None
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        out = work()
        best = min(best, time.perf_counter() - t0)
    np.save(args.output, out.astype(np.float32))
    print(json.dumps({"seconds": best}))


if __name__ == "__main__":
    main()
