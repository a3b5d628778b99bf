"""NumPy arrays <-> sf_sequence handles, without copying when possible.

A NumPy array shaped (frames, height, width, channels) maps onto an sf_sequence by its data
pointer and byte strides: numpy strides (frame, row, pixel, channel) become
sf_strides{channel, pixel, row, frame}. The C ABI takes non-negative strides that are multiples
of 4 bytes and 4-byte aligned data, so arrays with negative strides (e.g. ``a[..., ::-1]``),
odd strides or misaligned data are copied to a contiguous float32 array first; so are arrays of
another dtype or byte order.
"""

import ctypes

import numpy as np

from . import _capi
from ._handle import OwnsHandle
from .errors import InvalidArgumentError, check

FLOAT32 = np.dtype("=f4")


def _check_ndim(array, what):
    if array.ndim != 4:
        raise InvalidArgumentError(
            "%s must have 4 dimensions (frames, height, width, channels), got shape %s" % (what, array.shape))


def wrappable(array):
    """True when the C ABI can use this float32 array's memory as it is."""
    if array.dtype != FLOAT32 or not array.flags.aligned:
        return False
    return all(s >= 0 and s % 4 == 0 for s in array.strides)


def as_input(array, what="array"):
    """A float32 4-D array the C ABI can wrap: the array itself when possible, else a copy."""
    a = np.asarray(array)
    _check_ndim(a, what)
    if a.dtype != FLOAT32:
        if not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)
                or a.dtype == np.bool_):
            raise InvalidArgumentError("%s has dtype %s; a real number type is needed" % (what, a.dtype))
        a = a.astype(FLOAT32)
    if not wrappable(a):
        a = np.ascontiguousarray(a)
    return a


def shape_of(array):
    f, h, w, c = array.shape
    return _capi.sf_shape(f, h, w, c)


def strides_of(array):
    sf, sh, sw, sc = array.strides
    return _capi.sf_strides(channel=sc, pixel=sw, row=sh, frame=sf)


class WrappedSequence(OwnsHandle):
    """An sf_sequence borrowing a NumPy array's memory (sf_sequence_wrap). ``array`` is the array
    actually wrapped; keep this object (it references the array) until the handle is released.
    Use as a context manager, or call close()."""

    def __init__(self, array):
        if not wrappable(array) or array.ndim != 4:
            raise InvalidArgumentError("internal: array is not wrappable; call as_input first")
        self.array = array
        self.handle = _capi.sf_sequence()
        data = ctypes.cast(ctypes.c_void_p(array.ctypes.data), ctypes.POINTER(ctypes.c_float))
        check(_capi.lib.sf_sequence_wrap(data, shape_of(array), strides_of(array), ctypes.byref(self.handle)))

    def close(self):
        if self.handle:
            _capi.lib.sf_sequence_release(self.handle)
            self.handle = _capi.sf_sequence()


def channel_names(handle, count):
    names = []
    for c in range(count):
        name = ctypes.c_char_p()
        check(_capi.lib.sf_sequence_channel_name(handle, c, ctypes.byref(name)))
        names.append(_capi.text(name.value))
    return names


def frame_numbers(handle, count):
    numbers = []
    for f in range(count):
        number = ctypes.c_int64()
        check(_capi.lib.sf_sequence_frame_number(handle, f, ctypes.byref(number)))
        numbers.append(number.value)
    return numbers


def set_attributes(handle, names=None, numbers=None):
    for c, name in enumerate(names or ()):
        check(_capi.lib.sf_sequence_set_channel_name(handle, c, _capi.encode(name)))
    for f, number in enumerate(numbers or ()):
        check(_capi.lib.sf_sequence_set_frame_number(handle, f, int(number)))


class _OwnedMemory:
    """Owns an sf_sequence allocated by the library and exposes its memory to NumPy through
    __array_interface__; the array made from it keeps it (and so the handle) alive, and the
    handle is released when the last array viewing it goes away."""

    def __init__(self, handle):
        self._handle = handle
        shape = _capi.sf_shape()
        check(_capi.lib.sf_sequence_shape(handle, ctypes.byref(shape)))
        data = ctypes.POINTER(ctypes.c_float)()
        st = _capi.sf_strides()
        check(_capi.lib.sf_sequence_data(handle, ctypes.byref(data), ctypes.byref(st)))
        self.__array_interface__ = {
            "version": 3,
            "shape": (shape.frames, shape.height, shape.width, shape.channels),
            "typestr": FLOAT32.str,
            "data": (ctypes.cast(data, ctypes.c_void_p).value, False),
            "strides": (st.frame, st.row, st.pixel, st.channel),
        }

    def __del__(self):
        handle, self._handle = self._handle, None
        if handle:
            try:
                _capi.lib.sf_sequence_release(handle)
            except Exception:
                pass


def adopt(handle):
    """A NumPy array over the memory of a library-owned sequence (no copy); takes ownership of
    the handle."""
    try:
        owner = _OwnedMemory(handle)
    except BaseException:
        _capi.lib.sf_sequence_release(handle)
        raise
    return np.asarray(owner)
