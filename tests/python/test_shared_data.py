"""Real renders, when the shared data directory is there (skipped otherwise)."""

import os

import numpy as np
import pytest

import statfilter


def test_cornell_moving_indirect(shared_data, tmp_path):
    pattern = os.path.join(shared_data, "cornell_moving", "spp0016", "indirect.####.exr")
    if not os.path.exists(statfilter.pattern_format(pattern, 1)):
        pytest.skip("no %s" % pattern)
    a, info = statfilter.read_sequence(pattern, return_info=True)
    assert a.shape == (32, 120, 160, 3)
    assert a.dtype == np.float32
    assert info.channel_names == ["R", "G", "B"]
    assert info.frame_numbers == list(range(1, 33))
    assert np.isfinite(a).all() and a.min() >= 0 and a.mean() > 0
    # Noise is independent over time: frames differ.
    assert not np.array_equal(a[0], a[1])

    # The files are half float: copy -> write half -> read is bit exact.
    out = statfilter.Filter("copy")(a)
    np.testing.assert_array_equal(out, a)
    statfilter.write_sequence(str(tmp_path / "i.####.exr"), out[:4], frame_numbers=info.frame_numbers[:4],
                              channel_names=info.channel_names)
    b, info_b = statfilter.read_sequence(str(tmp_path / "i.####.exr"), return_info=True)
    np.testing.assert_array_equal(b, a[:4])
    assert info_b == info._replace(frame_numbers=info.frame_numbers[:4])
    assert info_b.data_window == info_b.display_window == statfilter.Window(0, 0, 160, 120)

    sub = statfilter.read_sequence(pattern, frames="3-5", channels="G")
    np.testing.assert_array_equal(sub, a[2:5, ..., 1:2])


def test_blender_multipart_layer(shared_data):
    pattern = os.path.join(shared_data, "raw", "cornell_moving_spp0016", "frame.####.exr")
    if not os.path.exists(statfilter.pattern_format(pattern, 1)):
        pytest.skip("no %s" % pattern)
    frames = statfilter.pattern_frames(pattern)
    a, info = statfilter.read_sequence(pattern, channels="ViewLayer.Diffuse Indirect", return_info=True)
    assert a.shape == (len(frames), 120, 160, 3)
    assert info.channel_names == ["R", "G", "B"]
    assert info.frame_numbers == frames
    assert np.isfinite(a).all() and a.mean() > 0
    # Another part of the same files is a different pass.
    direct = statfilter.read_sequence(pattern, channels="ViewLayer.Diffuse Direct", frames=frames[0])
    assert direct.shape == (1, 120, 160, 3)
    assert not np.array_equal(direct[0], a[0])
    # The whole file: every channel of every part, with full names.
    _, everything = statfilter.read_sequence(pattern, frames=frames[0], return_info=True)
    assert "ViewLayer.Diffuse Indirect.R" in everything.channel_names
    with pytest.raises(statfilter.NotFoundError, match="ViewLayer.Nope"):
        statfilter.read_sequence(pattern, channels="ViewLayer.Nope")


def test_blender_frames_denoised_into_copies_keep_their_other_layers(shared_data, tmp_path):
    pattern = os.path.join(shared_data, "raw", "cornell_moving_spp0016", "frame.####.exr")
    if not os.path.exists(statfilter.pattern_format(pattern, 1)):
        pytest.skip("no %s" % pattern)
    out = str(tmp_path / "into.####.exr")
    light = "ViewLayer.Diffuse Indirect"
    results = statfilter.Filter("pca", rank=2).run_files(pattern, out, channels=light, frames="1-6", into=True)
    assert results["rank"] == 2
    for layer in ("ViewLayer.Normal", "ViewLayer.Combined", "ViewLayer.Diffuse Color"):
        np.testing.assert_array_equal(statfilter.read_sequence(out, channels=layer),
                                      statfilter.read_sequence(pattern, channels=layer, frames="1-6"), err_msg=layer)
    before = statfilter.read_sequence(pattern, channels=light, frames="1-6")
    after = statfilter.read_sequence(out, channels=light)
    assert after.shape == before.shape and not np.array_equal(after, before)
    assert abs(after.mean() / before.mean() - 1) < 0.01  # the light kept
