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


def test_renderers_vectors_as_files_stream_with_the_in_memory_answer(shared_data, tmp_path):
    # The renderer's motion vectors named as files: run_files reads them beside the input a band or a
    # frame at a time, within a budget that forces bands, and gives what the filter gives in memory.
    scene = os.path.join(shared_data, "fast_ball")
    pattern = os.path.join(scene, "spp0016", "indirect.####.exr")
    vectors = os.path.join(scene, "aux", "vector.####.exr")
    if not os.path.exists(statfilter.pattern_format(vectors, 1)):
        pytest.skip("no %s" % vectors)
    a = statfilter.read_sequence(pattern, frames="1-16")
    v = statfilter.read_sequence(vectors, frames="1-16", channels="*")
    # (firefly_z=0: band by band the firefly test judges each band on its own, within 1e-4 relMSE.)
    params = dict(mc_half_width=3, firefly_z=0)
    expected = statfilter.Filter("hybrid", **params)(a, inputs={"vectors": v})
    f = statfilter.Filter("hybrid", **params)
    out = str(tmp_path / "o.####.exr")
    results = f.run_files(pattern, out, frames="1-16", pixel_type="float", memory="15M", inputs={"vectors": vectors})
    assert results["run.streamed"] == 1 and results["bands"] >= 2
    assert results["motion_compensation"] == "the renderer's motion vectors"
    np.testing.assert_allclose(statfilter.read_sequence(out), expected, rtol=1e-5, atol=1e-6)
    # The filter keeps no file input past the run: without vectors it follows the optical flow.
    f.run_files(pattern, out, frames="1-16", overwrite=True)
    assert f.results["motion_compensation"] == "optical flow on the first pass"
    with pytest.raises(statfilter.NotFoundError):
        statfilter.Filter("pca").run_files(pattern, out, frames="1-16", inputs={"vectors": vectors})
