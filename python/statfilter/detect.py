"""Artifact detection, the re-render list and merge: find the pixel-frames still wrong after
denoising, list them as crop windows for a renderer, and splice the re-rendered pixels back.

    import statfilter as sf
    found = sf.detect(denoised, noisy)             # arrays (frames, height, width, channels)
    found.mask, found.score, found.degree_map      # float32 arrays, one channel
    found.crops                                    # crop-window JSON text; found.windows as dicts
    final = sf.merge(denoised, rerendered, crops=found.crops, feather=2)
"""

from __future__ import annotations

import ctypes
import json
import os
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np

from . import _arrays, _capi
from ._progress import ProgressAdapter, ProgressCallback
from .errors import InvalidArgumentError, check, error_for
from .filter import Filter, ParamValue, ResultValue

#: A crop-window document: its JSON text, a path to it, or the parsed dict.
Crops = Union[str, bytes, "os.PathLike[str]", Dict[str, Any]]


class Detection:
    """What ``detect`` found.

    mask:       float32 (frames, height, width, 1): 1 where the pixel-frame should be re-rendered
    score:      float32 (frames, height, width, 1): its estimated relMSE (the mask is score > threshold)
    degree_map: float32 (1, height, width, 1): the polynomial degree each pixel needed (degree + 1:
                none explained it within delta)
    crops:      the crop windows as JSON text (write it to a file for ``statfilter merge``)
    windows:    the same windows as a list of dicts (frame, index, x, y, width, height)
    results:    every number the filter reported (flagged_fraction, window_fraction, delta, ...)
    """

    def __init__(self, results: Dict[str, ResultValue]) -> None:
        self.results = {k: v for k, v in results.items() if not isinstance(v, np.ndarray) and k != "crops"}
        self.mask = results["mask"]
        self.score = results["score"]
        self.degree_map = results["degree_map"]
        self.crops = results["crops"]
        self.windows = crop_windows(self.crops)

    @property
    def flagged_fraction(self) -> float:
        return self.results["flagged_fraction"]

    def __repr__(self) -> str:
        return "<statfilter.Detection: %.2f%% of pixel-frames flagged, %d windows covering %.2f%%>" % (
            100 * self.results["flagged_fraction"], int(self.results["window_count"]),
            100 * self.results["window_fraction"])


def detect(denoised: np.ndarray, noisy: Optional[np.ndarray] = None, progress: Optional[ProgressCallback] = None,
           **params: ParamValue) -> Detection:
    """Run the ``detect`` filter on a denoised sequence, with the noisy render it came from.

    denoised, noisy: arrays shaped (frames, height, width, channels). Without ``noisy`` the
    regression sees the denoised sequence alone (``source=denoised``), which finds far fewer of
    the real errors (docs/detect.md). params: the filter's parameters (degree, delta, window,
    threshold, crop_padding, crop_min_size, crop_window_cost, source, memory_mb); see
    ``statfilter.Filter("detect").params()``. Returns a Detection.
    """
    with Filter("detect", **params) as flt:
        flt(denoised, progress=progress, inputs=None if noisy is None else {"noisy": noisy})
        return Detection(flt.results)


def _crops_text(crops: Optional[Crops]) -> Optional[bytes]:
    if crops is None:
        return None
    if isinstance(crops, bytes):
        return crops
    if isinstance(crops, os.PathLike) or (isinstance(crops, str) and not crops.lstrip().startswith("{")):
        with open(crops, "rb") as f:
            return f.read()
    if isinstance(crops, (dict, list)):
        return json.dumps(crops).encode("utf-8")
    return _capi.encode(crops)


def crop_windows(crops: Crops) -> List[Dict[str, int]]:
    """The windows of a crop-window JSON document (text, a path, or the parsed dict) as a list of
    dicts with keys frame, index, x, y, width, height (row 0 at the top). Raises
    InvalidArgumentError naming the problem for a malformed document or a window outside the frame."""
    text = _crops_text(crops)
    count = ctypes.c_size_t()
    check(_capi.lib.sf_crops_windows(text, None, 0, ctypes.byref(count), None, None))
    windows = (_capi.sf_crop_window * max(count.value, 1))()
    check(_capi.lib.sf_crops_windows(text, windows, count.value, ctypes.byref(count), None, None))
    keys = ("frame", "index", "x", "y", "width", "height")
    return [{k: getattr(windows[i], k) for k in keys} for i in range(count.value)]


def _frame_numbers(array: np.ndarray, numbers: Optional[Sequence[int]], default: Sequence[int],
                   what: str) -> List[int]:
    if numbers is None:
        if array.shape[0] != len(default):
            raise InvalidArgumentError(
                "%s has %d frames and the denoised sequence %d: give %s_frame_numbers to say which frames it holds"
                % (what, array.shape[0], len(default), what))
        return list(default)
    numbers = [int(n) for n in numbers]
    if len(numbers) != array.shape[0]:
        raise InvalidArgumentError("%s_frame_numbers has %d entries for %d frames" % (what, len(numbers), array.shape[0]))
    return numbers


def merge(denoised: np.ndarray, rerender: np.ndarray, crops: Optional[Crops] = None, mask: Optional[np.ndarray] = None,
          feather: int = 0, frame_numbers: Optional[Sequence[int]] = None,
          rerender_frame_numbers: Optional[Sequence[int]] = None, mask_frame_numbers: Optional[Sequence[int]] = None,
          progress: Optional[ProgressCallback] = None) -> np.ndarray:
    """Splice re-rendered pixels into a denoised sequence; returns a new float32 array.

    denoised:  (frames, height, width, channels)
    rerender:  full-size re-rendered frames, (n, height, width, channels); pixels outside the
               replaced region are not read, so crop-window renders can be pasted into zeros
    crops:     crop-window JSON (text, path or dict) as ``detect`` wrote it; the union of a frame's
               windows is replaced
    mask:      (n, height, width, 1) flagged pixels (non-zero); with crops, only the mask's pixels
               are replaced (they must lie inside the windows)
    feather:   the re-render's weight rises over this many pixels inside the region's edge
    frame_numbers: the denoised frames' numbers (default 1..frames, as ``detect`` on arrays uses);
               rerender_frame_numbers / mask_frame_numbers: theirs (default: the same as the
               denoised frames, which then needs the same frame count)
    """
    den = _arrays.as_input(denoised, "denoised")
    rr = _arrays.as_input(rerender, "rerender")
    numbers = list(range(1, den.shape[0] + 1)) if frame_numbers is None else [int(n) for n in frame_numbers]
    if len(numbers) != den.shape[0]:
        raise InvalidArgumentError("frame_numbers has %d entries for %d frames" % (len(numbers), den.shape[0]))
    rr_numbers = _frame_numbers(rr, rerender_frame_numbers, numbers, "rerender")
    m = None if mask is None else _arrays.as_input(mask, "mask")
    m_numbers = None if m is None else _frame_numbers(m, mask_frame_numbers, numbers, "mask")
    out = np.empty(den.shape, dtype=np.float32)
    options = _capi.sf_merge_options()
    _capi.lib.sf_merge_options_init(ctypes.byref(options))
    options.crops = _crops_text(crops)
    options.feather = int(feather)
    adapter = ProgressAdapter(progress)
    if progress is not None:
        options.progress = adapter.c_function
    replaced = ctypes.c_int64()
    with _arrays.WrappedSequence(den) as s_den, _arrays.WrappedSequence(rr) as s_rr, \
            _arrays.WrappedSequence(out) as s_out:
        _arrays.set_attributes(s_den.handle, numbers=numbers)
        _arrays.set_attributes(s_out.handle, numbers=numbers)
        _arrays.set_attributes(s_rr.handle, numbers=rr_numbers)
        s_mask = None
        try:
            if m is not None:
                s_mask = _arrays.WrappedSequence(m)
                _arrays.set_attributes(s_mask.handle, numbers=m_numbers)
                options.mask = s_mask.handle
            status = _capi.lib.sf_merge(s_den.handle, s_rr.handle, ctypes.byref(options), s_out.handle,
                                        ctypes.byref(replaced))
            # The message now, before the releases below (each call clears the thread's last error).
            error = None if status == _capi.SF_OK else error_for(status, _capi.text(_capi.lib.sf_last_error()))
        finally:
            if s_mask is not None:
                s_mask.close()
    adapter.reraise()
    if error is not None:
        raise error
    return out
