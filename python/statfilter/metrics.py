"""Error metrics of a sequence against a reference (sf_sequence_compare)."""

from __future__ import annotations

import ctypes
from typing import Dict

import numpy as np

from . import _arrays, _capi
from .errors import InvalidArgumentError, UnsupportedError, check


def compare(array: np.ndarray, reference: np.ndarray) -> Dict[str, float]:
    """Compare ``array`` with ``reference`` (both shaped (frames, height, width, channels), the
    same shape) using the project's metrics. Returns a dict of floats, one per field of the C
    struct sf_comparison (rel_mse, rel_mse_moving, rel_mse_static, moving_fraction, psnr, flicker,
    jitter, ... as the loaded library defines them). Arrays pass without copies where possible."""
    if not (_capi.has("sf_sequence_compare") and _capi.has("sf_comparison_init")):
        raise UnsupportedError("the loaded library (%s) has no sf_sequence_compare" % _capi.library_path)
    test = _arrays.as_input(array, "array")
    ref = _arrays.as_input(reference, "reference")
    if test.shape != ref.shape:
        raise InvalidArgumentError("array has shape %s, the reference %s" % (test.shape, ref.shape))
    result = _capi.sf_comparison()
    _capi.lib.sf_comparison_init(ctypes.byref(result))
    with _arrays.WrappedSequence(test) as a, _arrays.WrappedSequence(ref) as r:
        check(_capi.lib.sf_sequence_compare(a.handle, r.handle, ctypes.byref(result)))
    return {name: getattr(result, name) for name, _ in result._fields_ if name != "struct_size"}
