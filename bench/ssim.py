"""SSIM of tonemapped luminance (Gaussian window, sigma 1.5), averaged over frames: NumPy only."""

import numpy as np


def _blur(img, kernel):
    """Separable filtering along the last two axes, edges reflected."""
    r = len(kernel) // 2
    for axis in (-2, -1):
        pad = [(0, 0)] * img.ndim
        pad[axis] = (r, r)
        padded = np.pad(img, pad, mode="reflect")
        windows = np.lib.stride_tricks.sliding_window_view(padded, len(kernel), axis=axis)
        img = windows @ kernel
    return img


def luminance_tonemapped(seq):
    lum = 0.2126 * seq[..., 0] + 0.7152 * seq[..., 1] + 0.0722 * seq[..., 2] if seq.shape[-1] >= 3 else seq.mean(-1)
    lum = np.maximum(lum.astype(np.float64), 0)
    return lum / (1 + lum)


def ssim(test, reference):
    x, y = luminance_tonemapped(test), luminance_tonemapped(reference)
    t = np.arange(-5, 6)
    kernel = np.exp(-0.5 * (t / 1.5) ** 2)
    kernel /= kernel.sum()
    c1, c2 = 0.01 ** 2, 0.03 ** 2
    mx, my = _blur(x, kernel), _blur(y, kernel)
    sxx = _blur(x * x, kernel) - mx * mx
    syy = _blur(y * y, kernel) - my * my
    sxy = _blur(x * y, kernel) - mx * my
    s = ((2 * mx * my + c1) * (2 * sxy + c2)) / ((mx * mx + my * my + c1) * (sxx + syy + c2))
    return float(s.mean())
