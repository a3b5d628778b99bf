"""Bad input raises the right statfilter.Error subclass with the library's message, and leaves no
partial output."""

import os

import numpy as np
import pytest

import statfilter


def listing(path):
    return sorted(os.listdir(path))


def write_frames(directory, numbers, shape=(2, 3, 3)):
    pattern = str(directory / "seq.####.exr")
    a = np.ones((len(numbers),) + shape, np.float32)
    statfilter.write_sequence(pattern, a, frame_numbers=numbers)
    return pattern


def test_gap_in_sequence(tmp_path):
    pattern = write_frames(tmp_path, [1, 2, 3, 5, 6, 9])
    with pytest.raises(statfilter.NotFoundError) as info:
        statfilter.read_sequence(pattern)
    e = info.value
    assert "missing" in e.message
    assert "4" in e.message and "7-8" in e.message
    assert e.status == 4 and e.status_name == "SF_ERROR_NOT_FOUND"
    assert isinstance(e, LookupError) and isinstance(e, statfilter.Error)
    # Choosing frames explicitly skips the gap ...
    assert statfilter.read_sequence(pattern, frames="1-3,5-6").shape[0] == 5
    # ... and naming a missing one names its file.
    with pytest.raises(statfilter.NotFoundError, match="seq.0004.exr"):
        statfilter.read_sequence(pattern, frames="1-5")


def test_no_files(tmp_path):
    with pytest.raises(statfilter.NotFoundError, match="no files match"):
        statfilter.read_sequence(str(tmp_path / "none.####.exr"))
    with pytest.raises(statfilter.NotFoundError):
        statfilter.pattern_frames(str(tmp_path / "none.####.exr"))


def test_wrong_channel(tmp_path):
    pattern = write_frames(tmp_path, [1, 2])
    with pytest.raises(statfilter.NotFoundError) as info:
        statfilter.read_sequence(pattern, channels="R,Z")
    assert "'Z'" in info.value.message
    assert "R, G, B" in info.value.message  # lists the channels there are
    with pytest.raises(statfilter.NotFoundError):
        statfilter.read_sequence(pattern, channels=["NoSuchLayer"])


def test_non_image_file(tmp_path):
    (tmp_path / "junk.0001.exr").write_text("this is not an image\n")
    with pytest.raises(statfilter.FileError) as info:
        statfilter.read_sequence(str(tmp_path / "junk.####.exr"))
    assert "junk.0001.exr" in info.value.message
    assert isinstance(info.value, OSError)


def test_truncated_file(tmp_path):
    pattern = write_frames(tmp_path, [1, 2], shape=(64, 64, 3))
    path = tmp_path / "seq.0002.exr"
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(statfilter.FileError, match="seq.0002.exr"):
        statfilter.read_sequence(pattern)


def test_frames_of_different_sizes(tmp_path):
    statfilter.write_sequence(str(tmp_path / "m.####.exr"), np.zeros((1, 4, 4, 3), np.float32), frame_numbers=[1])
    statfilter.write_sequence(str(tmp_path / "m.####.exr"), np.zeros((1, 5, 4, 3), np.float32), frame_numbers=[2])
    with pytest.raises(statfilter.InvalidArgumentError, match="m.0002.exr"):
        statfilter.read_sequence(str(tmp_path / "m.####.exr"))


def test_missing_output_directory_is_created(tmp_path, noisy):
    statfilter.write_sequence(str(tmp_path / "new" / "o.####.exr"), noisy)
    assert (tmp_path / "new" / "o.0001.exr").exists()


def test_output_directory_that_cannot_be_created(tmp_path, noisy):
    (tmp_path / "plain").write_text("a file, not a directory")
    before = listing(tmp_path)
    with pytest.raises(statfilter.FileError) as info:
        statfilter.write_sequence(str(tmp_path / "plain" / "sub" / "o.####.exr"), noisy)
    assert "plain" in info.value.message and "cannot be created" in info.value.message
    assert listing(tmp_path) == before


def test_unwritable_output_directory(tmp_path, noisy):
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        pytest.skip("root can write into read-only directories")
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(statfilter.FileError):
            statfilter.write_sequence(str(ro / "o.####.exr"), noisy)
        assert listing(ro) == []
    finally:
        ro.chmod(0o755)


def test_output_path_under_a_file(tmp_path, noisy):
    (tmp_path / "plain").write_text("x")
    before = listing(tmp_path)
    with pytest.raises(statfilter.FileError):
        statfilter.write_sequence(str(tmp_path / "plain" / "o.####.exr"), noisy)
    assert listing(tmp_path) == before


def test_half_overflow_raises_and_writes_nothing(tmp_path):
    a = np.ones((3, 2, 2, 3), np.float32)
    a[2, 1, 1, 2] = 1e6  # in the last frame: the check must run before the first file
    with pytest.raises(statfilter.NumericError) as info:
        statfilter.write_sequence(str(tmp_path / "h.####.exr"), a)
    assert "65504" in info.value.message
    assert isinstance(info.value, ArithmeticError)
    assert listing(tmp_path) == []


def test_half_overflow_clamp(tmp_path):
    a = np.ones((2, 2, 2, 3), np.float32)
    a[0, 0, 0, 0] = 1e6
    a[1, 1, 1, 1] = -1e6
    a[1, 0, 0, 2] = np.inf  # not finite: kept as it is
    statfilter.write_sequence(str(tmp_path / "h.####.exr"), a, half_overflow="clamp")
    b = statfilter.read_sequence(str(tmp_path / "h.####.exr"))
    assert b[0, 0, 0, 0] == 65504.0
    assert b[1, 1, 1, 1] == -65504.0
    assert np.isposinf(b[1, 0, 0, 2])
    # Float output takes 1e6 as it is.
    statfilter.write_sequence(str(tmp_path / "f.####.exr"), a, pixel_type="float")
    assert statfilter.read_sequence(str(tmp_path / "f.####.exr"))[0, 0, 0, 0] == 1e6


def test_invalid_write_options(tmp_path, noisy):
    with pytest.raises(statfilter.InvalidArgumentError, match="compression"):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy, compression="bogus")
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy, pixel_type="double")
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy, half_overflow="wrap")
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy, channel_names=["R"])
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy, frame_numbers=[1, 1, 2, 3, 4])
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.write_sequence(str(tmp_path / "o.####.exr"), noisy[0])
    assert listing(tmp_path) == []


def test_invalid_frame_range(tmp_path):
    pattern = write_frames(tmp_path, [1, 2])
    with pytest.raises(statfilter.InvalidArgumentError, match="invalid frame range"):
        statfilter.read_sequence(pattern, frames="5-1")
    with pytest.raises(TypeError):
        statfilter.read_sequence(pattern, frames=[1.5])


def test_unknown_filter():
    with pytest.raises(statfilter.NotFoundError) as info:
        statfilter.Filter("no-such-filter")
    assert "no-such-filter" in info.value.message
    assert "copy" in info.value.message  # lists the known filters


def test_unknown_parameter():
    with pytest.raises(statfilter.NotFoundError, match="nope"):
        statfilter.Filter("copy", nope=1)
    f = statfilter.Filter("copy")
    for value in (1, 1.5, "x"):
        with pytest.raises(statfilter.NotFoundError, match="nope") as info:
            f.set(nope=value)
        assert info.value.status == 4
    with pytest.raises(statfilter.NotFoundError):
        f.get("nope")
    with pytest.raises(TypeError):
        f["nope"] = [1, 2]


def numeric_params():
    out = []
    for name in statfilter.filters():
        for p in statfilter.Filter(name).params():
            if p["type"] in ("int", "float") and np.isfinite(p["max"]):
                out.append((name, p))
    return out


def test_out_of_range_parameter():
    params = numeric_params()
    if not params:
        pytest.skip("no filter has a bounded numeric parameter yet")
    for name, p in params:
        f = statfilter.Filter(name)
        before = f.get(p["name"])
        too_big = int(p["max"]) + 1 if p["type"] == "int" else p["max"] * 2 + 1
        with pytest.raises(statfilter.InvalidArgumentError) as info:
            f[p["name"]] = too_big
        assert p["name"] in info.value.message
        assert f.get(p["name"]) == before  # unchanged


def test_wrong_shape_for_filter(noisy):
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.Filter("copy")(np.zeros((0, 2, 2, 3), np.float32))


class Boom(Exception):
    pass


def test_cancel_filter(noisy):
    f = statfilter.Filter("copy")
    with pytest.raises(statfilter.CancelledError) as info:
        f(noisy, progress=lambda fraction, stage: False)
    assert info.value.status == 6 and "cancel" in info.value.message
    # The callback is not kept: the next run without one completes.
    np.testing.assert_array_equal(f(noisy), noisy)


def test_cancel_read_and_write(tmp_path, noisy):
    pattern = str(tmp_path / "c.####.exr")
    with pytest.raises(statfilter.CancelledError):
        statfilter.write_sequence(pattern, noisy, progress=lambda fraction, stage: False)
    assert listing(tmp_path) == []
    statfilter.write_sequence(pattern, noisy)
    with pytest.raises(statfilter.CancelledError):
        statfilter.read_sequence(pattern, progress=lambda fraction, stage: fraction < 0.5)


def test_cancel_midway_leaves_no_partial_files(tmp_path, noisy):
    """Cancelled halfway: the sequence is committed only at the end, so nothing is left, not even a
    temporary file or the lock."""
    pattern = str(tmp_path / "c.####.exr")
    with pytest.raises(statfilter.CancelledError):
        statfilter.write_sequence(pattern, noisy, pixel_type="float", progress=lambda fraction, stage: fraction < 0.5)
    assert listing(tmp_path) == []


def test_callback_exception_propagates(tmp_path, noisy):
    calls = []

    def bad(fraction, stage):
        calls.append(fraction)
        raise Boom("from the callback at %s" % stage)

    f = statfilter.Filter("copy")
    with pytest.raises(Boom, match="from the callback at copy"):
        f(noisy, progress=bad)
    assert len(calls) == 1  # cancelled at the first call
    with pytest.raises(Boom, match="write"):
        statfilter.write_sequence(str(tmp_path / "e.####.exr"), noisy, progress=bad)
    assert listing(tmp_path) == []
    statfilter.write_sequence(str(tmp_path / "e.####.exr"), noisy)
    with pytest.raises(Boom, match="read"):
        statfilter.read_sequence(str(tmp_path / "e.####.exr"), progress=bad)
    # Everything still works afterwards.
    np.testing.assert_array_equal(f(noisy), noisy)


def test_keyboard_interrupt_in_callback_propagates(noisy):
    def interrupt(fraction, stage):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        statfilter.Filter("copy")(noisy, progress=interrupt)


def test_progress_must_be_callable(noisy):
    with pytest.raises(TypeError):
        statfilter.Filter("copy")(noisy, progress=42)
