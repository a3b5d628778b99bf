"""Hostile or absurd input through the CLI: each case fails at once with one clear line naming the
file or option at fault (or works, when it is merely unusual), never a crash, a hang or lost frames."""

import json
import os
import pathlib
import shutil
import subprocess
import tempfile

import pytest

from conftest import CLI, oiio_tool, run

NO_HANG = 60  # seconds: a blocked read of a FIFO would wait forever


def crops_document(width, height, windows):
    return json.dumps({"format": "statfilter-crops", "version": 1, "width": width, "height": height,
                       "frames": [{"frame": f, "windows": [{"x": x, "y": y, "width": w, "height": h}]}
                                  for f, x, y, w, h in windows]})


def test_crops_declaring_another_frame_size_is_refused_before_any_window_is_pasted(small_sequence, tmp_path):
    # A 160 x 40 window at y = 150 lies inside the 160 x 200 frames the document declares, but not
    # inside the 160 x 120 frames of the sequence: pasted, it would write past them.
    crops = tmp_path / "crops.json"
    crops.write_text(crops_document(160, 200, [(2, 0, 150, 160, 40)]))
    subprocess.run([oiio_tool("oiiotool"), "--create", "160x40", "3", "-o", str(tmp_path / "rr.0.0002.exr")], check=True)
    proc = run("merge", small_sequence / "noisy.####.exr", tmp_path / "rr.{window}.####.exr", tmp_path / "o.####.exr",
               "--crops", crops, check_rc=1)
    assert "crop windows are for 160 x 200 frames" in proc.stderr and "160 x 120" in proc.stderr
    assert str(crops) in proc.stderr
    assert not list(tmp_path.glob("o.*.exr"))


def test_merge_with_the_largest_feather(small_sequence, tmp_path):
    crops = tmp_path / "crops.json"
    crops.write_text(crops_document(160, 120, [(2, 10, 10, 20, 20)]))
    run("merge", small_sequence / "noisy.####.exr", small_sequence / "noisy.####.exr", tmp_path / "o.####.exr",
        "--crops", crops, "--feather", "9223372036854775807", "-q")
    assert len(list(tmp_path.glob("o.*.exr"))) == 4


@pytest.mark.parametrize("channels", [",", " ", ",,,"])
def test_channel_list_naming_nothing(small_sequence, tmp_path, channels):
    for args in (["info", small_sequence / "noisy.####.exr"],
                 ["copy", small_sequence / "noisy.####.exr", tmp_path / "c.####.exr"],
                 ["denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr"]):
        proc = run(*args, "--channels", channels, check_rc=1)
        assert "names no channel or layer" in proc.stderr, args
        assert len(proc.stderr.strip().splitlines()) == 1
    assert not list(tmp_path.glob("*.exr"))


def test_wide_padding_writes_every_frame_to_its_own_file(small_sequence, tmp_path):
    run("copy", small_sequence / "noisy.####.exr", tmp_path / "o.%040d.exr", "-q")
    assert sorted(p.name for p in tmp_path.glob("o.*.exr")) == ["o.%040d.exr" % f for f in range(1, 5)]
    report = json.loads(run("info", tmp_path / "o.%040d.exr", "--json").stdout)
    assert report["frame_count"] == 4


def test_absurd_padding_is_a_clear_error(small_sequence, tmp_path):
    proc = run("copy", small_sequence / "noisy.####.exr", tmp_path / "a.%99999999999d.exr", check_rc=1)
    assert "more than 64 digits" in proc.stderr and "internal error" not in proc.stderr
    proc = run("info", tmp_path / "a.%99999999999d.exr", check_rc=1)
    assert "more than 64 digits" in proc.stderr
    assert not list(tmp_path.glob("a.*"))
