"""NVIDIA's FLIP (PyPI `flip-evaluator`), HDR mode, on a subset of frames: it costs ~25 ms per
160 x 120 frame, so every 4th frame is scored (8 of 32). Optional: None when it is not installed."""

import numpy as np

try:
    import flip_evaluator
except ImportError:  # an optional benchmark dependency
    flip_evaluator = None

STRIDE = 4


def mean_flip(output, ref, stride=STRIDE):
    if flip_evaluator is None:
        return None
    scores = []
    for t in range(0, ref.shape[0], stride):
        # HDR-FLIP wants non-negative linear RGB; float noise around black is clamped to 0.
        test = np.ascontiguousarray(np.maximum(output[t], 0), dtype=np.float32)
        _, mean, _ = flip_evaluator.evaluate(np.ascontiguousarray(ref[t], dtype=np.float32), test, "HDR")
        scores.append(mean)
    return float(np.mean(scores))
