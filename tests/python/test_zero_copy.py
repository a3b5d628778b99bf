"""NumPy arrays pass to and from the library without copies: the pointer and strides the library
sees are the array's own, and filter output lands in the caller's buffer."""

import ctypes

import numpy as np
import pytest

import statfilter
from statfilter import _arrays, _capi
from statfilter.errors import check


def library_view(handle):
    """(data pointer, (frame, row, pixel, channel) strides, shape) as the library sees them."""
    data = ctypes.POINTER(ctypes.c_float)()
    st = _capi.sf_strides()
    check(_capi.lib.sf_sequence_data(handle, ctypes.byref(data), ctypes.byref(st)))
    shape = _capi.sf_shape()
    check(_capi.lib.sf_sequence_shape(handle, ctypes.byref(shape)))
    return (ctypes.cast(data, ctypes.c_void_p).value, (st.frame, st.row, st.pixel, st.channel),
            (shape.frames, shape.height, shape.width, shape.channels))


def views(a):
    return {
        "contiguous": a,
        "every other row": a[:, ::2],
        "channel subset": a[..., 1:],
        "transposed x/y": a.transpose(0, 2, 1, 3),
        "frame step": a[::2, :, 1:4],
        "broadcast frames": np.broadcast_to(a[:1], a.shape),
        "fortran order": np.asfortranarray(a),
    }


@pytest.mark.parametrize("kind", ["contiguous", "every other row", "channel subset", "transposed x/y", "frame step",
                                  "broadcast frames", "fortran order"])
def test_wrap_uses_array_memory(noisy, kind):
    view = views(noisy)[kind]
    wrapped = _arrays.as_input(view)
    assert wrapped is view or (wrapped.ctypes.data == view.ctypes.data and wrapped.strides == view.strides)
    with _arrays.WrappedSequence(wrapped) as seq:
        pointer, strides, shape = library_view(seq.handle)
    assert pointer == view.ctypes.data
    assert strides == view.strides
    assert shape == view.shape


def test_negative_strides_are_copied(noisy):
    """The C ABI takes non-negative strides only: a reversed view is copied, and still gives the
    right values."""
    reversed_channels = noisy[..., ::-1]
    assert reversed_channels.strides[3] < 0
    wrapped = _arrays.as_input(reversed_channels)
    assert not np.shares_memory(wrapped, noisy)
    assert all(s > 0 for s in wrapped.strides)
    np.testing.assert_array_equal(wrapped, reversed_channels)
    with _arrays.WrappedSequence(wrapped) as seq:
        pointer, _, _ = library_view(seq.handle)
    assert pointer == wrapped.ctypes.data
    out = statfilter.Filter("copy")(noisy[:, ::-1, :, ::-1])
    np.testing.assert_array_equal(out, noisy[:, ::-1, :, ::-1])


def test_other_dtypes_are_converted(noisy):
    as64 = noisy.astype(np.float64)
    out = statfilter.Filter("copy")(as64)
    assert out.dtype == np.float32
    np.testing.assert_array_equal(out, noisy)
    big_endian = noisy.astype(">f4")
    np.testing.assert_array_equal(statfilter.Filter("copy")(big_endian), noisy)


def test_filter_writes_into_out(noisy):
    out = np.full_like(noisy, -7.0)
    address = out.ctypes.data
    result = statfilter.Filter("copy")(noisy, out=out)
    assert result is out
    assert result.ctypes.data == address
    np.testing.assert_array_equal(out, noisy)
    assert not np.shares_memory(out, noisy)


def test_filter_writes_into_strided_out_view(noisy):
    """out may be a non-contiguous view; only its elements are written."""
    big = np.zeros((noisy.shape[0], noisy.shape[1] * 2, noisy.shape[2], noisy.shape[3] + 1), np.float32)
    view = big[:, ::2, :, :3]
    result = statfilter.Filter("copy")(noisy, out=view)
    assert result is view
    assert np.shares_memory(result, big)
    np.testing.assert_array_equal(big[:, ::2, :, :3], noisy)
    assert not big[:, 1::2].any() and not big[..., 3].any()


def test_filter_in_place(noisy):
    a = noisy.copy()
    result = statfilter.Filter("copy")(a, out=a)
    assert result is a
    np.testing.assert_array_equal(a, noisy)


def test_filter_overlapping_out_is_safe(noisy):
    """Output overlapping the input (not the same memory) must not read half-written values."""
    buf = np.zeros((noisy.shape[0] + 1,) + noisy.shape[1:], np.float32)
    buf[:-1] = noisy
    result = statfilter.Filter("copy")(buf[:-1], out=buf[1:])
    np.testing.assert_array_equal(result, noisy)


def test_out_with_negative_strides_still_receives_result(noisy):
    out = np.zeros_like(noisy)
    view = out[..., ::-1]
    result = statfilter.Filter("copy")(noisy, out=view)
    assert result is view
    np.testing.assert_array_equal(out[..., ::-1], noisy)


def test_bad_out_is_rejected(noisy):
    f = statfilter.Filter("copy")
    with pytest.raises(statfilter.InvalidArgumentError):
        f(noisy, out=np.zeros(noisy.shape, np.float64))
    with pytest.raises(statfilter.InvalidArgumentError):
        f(noisy, out=np.zeros(noisy.shape[:-1] + (4,), np.float32))
    with pytest.raises(statfilter.InvalidArgumentError):
        f(noisy, out=np.broadcast_to(np.zeros(noisy.shape[1:], np.float32), noisy.shape))
    with pytest.raises(statfilter.InvalidArgumentError):
        f(noisy[0])


def test_read_sequence_returns_library_memory(tmp_path, noisy):
    """read_sequence does not copy: the array views the memory the library read into, and keeps
    it alive on its own."""
    statfilter.write_sequence(str(tmp_path / "a.####.exr"), noisy, pixel_type="float")
    a = statfilter.read_sequence(str(tmp_path / "a.####.exr"))
    assert not a.flags.owndata
    assert a.base is not None and hasattr(a.base, "__array_interface__")
    assert a.base.__array_interface__["data"][0] == a.ctypes.data
    view = a[2:, 1]
    del a
    import gc
    gc.collect()
    np.testing.assert_array_equal(view, noisy[2:, 1])
    view[...] = 3.0  # owned by the library sequence, writable
    assert (view == 3.0).all()
