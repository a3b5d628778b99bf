"""write_sequence -> read_sequence round trips, and the frame-pattern helpers."""

import os

import numpy as np
import pytest

import statfilter


def bits(a):
    return np.ascontiguousarray(a).view(np.uint32)


def test_float_round_trip_is_bit_exact(tmp_path, rng):
    a = (rng.standard_normal((4, 6, 8, 3)) * 1000).astype(np.float32)
    a[0, 0, 0] = [0.0, -0.0, np.float32(1e-40)]  # zero, negative zero, a subnormal
    a[1, 0, 0] = [3.0e38, -3.0e38, np.inf]
    a[2, 0, 0] = [np.float32(1.0) + np.finfo(np.float32).eps, np.pi, -np.inf]
    pattern = str(tmp_path / "f.####.exr")
    files = statfilter.write_sequence(pattern, a, pixel_type="float")
    assert files == [str(tmp_path / ("f.%04d.exr" % i)) for i in range(1, 5)]
    assert all(os.path.isfile(f) for f in files)
    b = statfilter.read_sequence(pattern)
    assert b.dtype == np.float32 and b.shape == a.shape
    np.testing.assert_array_equal(bits(b), bits(a))


@pytest.mark.parametrize("compression", ["none", "zip", "piz", "rle"])
def test_float_lossless_compressions(tmp_path, rng, compression):
    a = rng.random((2, 5, 7, 2)).astype(np.float32)
    statfilter.write_sequence(str(tmp_path / "c.####.exr"), a, pixel_type="float", compression=compression)
    np.testing.assert_array_equal(bits(statfilter.read_sequence(str(tmp_path / "c.####.exr"))), bits(a))


def test_half_round_trip_within_half_precision(tmp_path, rng):
    a = (rng.standard_normal((3, 5, 7, 3)) * 100).astype(np.float32)
    a[0, 0, 0] = [65504.0, -65504.0, 6e-8]
    statfilter.write_sequence(str(tmp_path / "h.####.exr"), a)  # half is the default
    b = statfilter.read_sequence(str(tmp_path / "h.####.exr"))
    # Exactly what float -> half -> float rounding gives ...
    np.testing.assert_array_equal(b, a.astype(np.float16).astype(np.float32))
    # ... which is within half's precision.
    np.testing.assert_allclose(b, a, rtol=2.0 ** -11, atol=6e-8)
    assert not np.array_equal(b, a)  # and it really was stored as half


def test_channel_names_and_frame_numbers_round_trip(tmp_path, rng):
    a = rng.random((3, 4, 5, 2)).astype(np.float32)
    pattern = str(tmp_path / "n.%04d.exr")
    statfilter.write_sequence(pattern, a, pixel_type="float", channel_names=["u", "v"], frame_numbers=[10, 11, 12])
    assert statfilter.pattern_frames(pattern) == [10, 11, 12]
    b, info = statfilter.read_sequence(pattern, return_info=True)
    assert isinstance(info, statfilter.SequenceInfo)
    assert info.channel_names == ["u", "v"]
    assert info.frame_numbers == [10, 11, 12]
    np.testing.assert_array_equal(b, a)


def test_default_channel_names(tmp_path, rng):
    for count, names in [(1, ["Y"]), (3, ["R", "G", "B"]), (4, ["R", "G", "B", "A"]), (2, ["C0", "C1"])]:
        pattern = str(tmp_path / ("d%d.####.exr" % count))
        statfilter.write_sequence(pattern, rng.random((1, 2, 3, count)).astype(np.float32))
        assert statfilter.read_sequence(pattern, return_info=True)[1].channel_names == names


def test_layer_names_and_channel_selection(tmp_path, rng):
    a = rng.random((2, 3, 4, 4)).astype(np.float32)
    pattern = str(tmp_path / "l.####.exr")
    statfilter.write_sequence(pattern, a, pixel_type="float",
                              channel_names=["diffuse.R", "diffuse.G", "diffuse.B", "depth.Z"])
    b, info = statfilter.read_sequence(pattern, channels="diffuse", return_info=True)
    assert info.channel_names == ["R", "G", "B"]
    np.testing.assert_array_equal(b, a[..., :3])
    b, info = statfilter.read_sequence(pattern, channels=["depth.Z", "diffuse.R"], return_info=True)
    assert info.channel_names == ["depth.Z", "diffuse.R"]
    np.testing.assert_array_equal(b, a[..., [3, 0]])


def test_frame_selection(tmp_path, rng):
    a = rng.random((6, 2, 3, 1)).astype(np.float32)
    pattern = str(tmp_path / "s.####.exr")
    statfilter.write_sequence(pattern, a, pixel_type="float")
    for frames, expect in [("2-4", [2, 3, 4]), ("1-6x2", [1, 3, 5]), ([6, 1], [1, 6]), (5, [5]),
                           (range(2, 6, 3), [2, 5]), ("1-2,6", [1, 2, 6])]:
        b, info = statfilter.read_sequence(pattern, frames=frames, return_info=True)
        assert info.frame_numbers == expect, frames
        np.testing.assert_array_equal(b, a[[f - 1 for f in expect]])


def test_strided_and_converted_inputs_write_correctly(tmp_path, rng):
    base = rng.random((4, 10, 6, 4)).astype(np.float32)
    cases = {
        "rows": base[:, ::2, :, :3],           # zero-copy, strided
        "reversed": base[::-1, :, ::-1, 2::-1],  # negative strides: copied
        "float64": base[..., :3].astype(np.float64),
        "transposed": base.transpose(0, 2, 1, 3)[..., :3],
    }
    for name, arr in cases.items():
        pattern = str(tmp_path / (name + ".####.exr"))
        statfilter.write_sequence(pattern, arr, pixel_type="float")
        np.testing.assert_array_equal(statfilter.read_sequence(pattern), np.asarray(arr, np.float32), err_msg=name)


def test_single_file_without_frame_token(tmp_path, rng):
    a = rng.random((1, 3, 4, 3)).astype(np.float32)
    path = str(tmp_path / "still.exr")
    assert statfilter.write_sequence(path, a, pixel_type="float") == [path]
    np.testing.assert_array_equal(statfilter.read_sequence(path), a)
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "x.exr"), np.zeros((2, 3, 4, 3), np.float32))


def test_filter_then_write(tmp_path, noisy):
    f = statfilter.Filter("copy")
    out = f(noisy)
    assert f.results == {}
    statfilter.write_sequence(str(tmp_path / "o.####.exr"), out, pixel_type="float")
    np.testing.assert_array_equal(statfilter.read_sequence(str(tmp_path / "o.####.exr")), noisy)


def test_pattern_format():
    assert statfilter.pattern_format("a/b.####.exr", 7) == "a/b.0007.exr"
    assert statfilter.pattern_format("b.%06d.exr", 12) == "b.000012.exr"
    assert statfilter.pattern_format("b.#.exr", 3) == "b.0003.exr"
    assert statfilter.pattern_format("b.@@.exr", 3) == "b.03.exr"


def test_progress_reports(tmp_path, noisy):
    seen = []
    statfilter.write_sequence(str(tmp_path / "p.####.exr"), noisy, progress=lambda f, s: seen.append((f, s)))
    assert seen and all(s == "write" for _, s in seen)
    assert [f for f, _ in seen] == sorted(f for f, _ in seen) and seen[-1][0] == 1.0
    seen.clear()
    statfilter.read_sequence(str(tmp_path / "p.####.exr"), progress=lambda f, s: seen.append((f, s)) or True)
    assert seen and all(s == "read" for _, s in seen) and seen[-1][0] == 1.0
    seen.clear()
    statfilter.Filter("copy")(noisy, progress=lambda f, s: seen.append((f, s)))
    assert seen and seen[-1][0] == 1.0


def test_a_region_keeps_its_windows_through_numpy(tmp_path, rng):
    a = rng.random((2, 12, 15, 3), dtype=np.float32)
    written = statfilter.write_sequence(str(tmp_path / "region.####.exr"), a, pixel_type="float",
                                        data_window=(5, 2, 15, 12), display_window=(0, 0, 24, 16))
    assert len(written) == 2
    b, info = statfilter.read_sequence(str(tmp_path / "region.####.exr"), return_info=True)
    np.testing.assert_array_equal(b, a)
    assert info.data_window == statfilter.Window(5, 2, 15, 12)
    assert info.display_window == statfilter.Window(0, 0, 24, 16)
    # filtered in NumPy and written back where it was
    statfilter.write_sequence(str(tmp_path / "again.####.exr"), b * 2, pixel_type="float",
                              data_window=info.data_window, display_window=info.display_window)
    c, again = statfilter.read_sequence(str(tmp_path / "again.####.exr"), return_info=True)
    np.testing.assert_array_equal(c, a * 2)
    assert again[2:] == info[2:]
    # without windows a frame sits at the origin of its own size
    statfilter.write_sequence(str(tmp_path / "plain.####.exr"), a, pixel_type="float")
    _, plain = statfilter.read_sequence(str(tmp_path / "plain.####.exr"), return_info=True)
    assert plain.data_window == plain.display_window == statfilter.Window(0, 0, 15, 12)


def test_windows_that_do_not_fit_the_array_are_refused(tmp_path, rng):
    a = rng.random((1, 4, 6, 3), dtype=np.float32)
    with pytest.raises(statfilter.InvalidArgumentError, match="not the sequence's size"):
        statfilter.write_sequence(str(tmp_path / "w.exr"), a, data_window=(0, 0, 5, 4))
    with pytest.raises(statfilter.InvalidArgumentError, match="data_window"):
        statfilter.write_sequence(str(tmp_path / "w.exr"), a, display_window=(0, 0, 8, 8))
    with pytest.raises(statfilter.InvalidArgumentError, match="x, y, width, height"):
        statfilter.write_sequence(str(tmp_path / "w.exr"), a, data_window=(0, 0, 6))
    assert not (tmp_path / "w.exr").exists()
