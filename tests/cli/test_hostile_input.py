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


def run_quickly(*args, check_rc):
    proc = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=NO_HANG)
    assert proc.returncode == check_rc, f"exit {proc.returncode}\nstdout:{proc.stdout}\nstderr:{proc.stderr}"
    return proc


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


def test_fifo_and_device_frames_fail_at_once(small_sequence):
    os.mkfifo(small_sequence / "noisy.0005.exr")
    os.symlink("/dev/zero", small_sequence / "noisy.0006.exr")
    os.symlink("/dev/urandom", small_sequence / "noisy.0007.exr")
    for frames, kind in (("1-5", "a FIFO"), ("6", "a character device"), ("7", "a character device")):
        proc = run_quickly("info", small_sequence / "noisy.####.exr", "--frames", frames, check_rc=1)
        assert kind in proc.stderr and "not a regular file" in proc.stderr, proc.stderr
        assert "noisy.000%s.exr" % frames[-1] in proc.stderr


def test_missing_frames_are_reported_before_memory_is_taken(small_sequence):
    proc = run_quickly("info", small_sequence / "noisy.####.exr", "--frames", "1-20000", check_rc=1)
    assert "frames 5-20000 are missing (found 1-4;" in proc.stderr and "noisy.0005.exr" in proc.stderr


def test_a_sequence_that_cannot_fit_in_memory_is_refused(tmp_path):
    # One 4096 x 4096 frame (256 MiB as float, a few kB on disk) linked as enough frames to need
    # twice the memory this machine has available.
    frame = tmp_path / "big.exr"
    subprocess.run([oiio_tool("oiiotool"), "--create", "4096x4096", "4", "-d", "half", "-o", str(frame)], check=True)
    with open("/proc/meminfo") as f:
        available_kb = next(int(line.split()[1]) for line in f if line.startswith("MemAvailable:"))
    count = 2 * available_kb * 1024 // (4096 * 4096 * 4 * 4) + 2
    if count > 5000:
        pytest.skip("more memory available than a few thousand links can exceed")
    for f in range(1, count + 1):
        os.symlink(frame, tmp_path / ("s.%04d.exr" % f))
    proc = run_quickly("info", tmp_path / "s.####.exr", check_rc=1)
    needed = count * 4096 * 4096 * 4 * 4
    assert "need %d bytes" % needed in proc.stderr and "memory available" in proc.stderr, proc.stderr


def test_permission_denied_is_said(small_sequence, tmp_path):
    victim = small_sequence / "noisy.0002.exr"
    if os.geteuid() != 0:
        os.chmod(victim, 0)
        proc = run("info", small_sequence / "noisy.####.exr", check_rc=1)
    else:
        # root reads anything: run the tool as nobody on a copy that nobody may read.
        setpriv = shutil.which("setpriv")
        if not setpriv:
            pytest.skip("setpriv (util-linux) is not installed")
        shared = pathlib.Path(tempfile.mkdtemp())  # pytest's own directories are private to root
        try:
            os.chmod(shared, 0o755)
            for f in small_sequence.iterdir():
                shutil.copy(f, shared / f.name)
                os.chmod(shared / f.name, 0o644)
            os.chmod(shared / victim.name, 0o600)
            proc = subprocess.run([setpriv, "--reuid=65534", "--regid=65534", "--clear-groups", CLI, "info",
                                   str(shared / "noisy.####.exr")], capture_output=True, text=True, timeout=NO_HANG)
        finally:
            shutil.rmtree(shared)
        if "noisy" not in proc.stderr:
            pytest.skip("nobody cannot run the built tool here: " + proc.stderr.strip())
        assert proc.returncode == 1, proc.stderr
    assert "noisy.0002.exr" in proc.stderr and "Permission denied" in proc.stderr, proc.stderr
    assert "not an OpenEXR file" not in proc.stderr


@pytest.mark.parametrize("compression, why", [("zip:abc", "zip level"), ("zip:0", "zip level"), ("zip:10", "zip level"),
                                              ("zips:4.5", "zip level"), ("dwaa:-1", "DWA level"),
                                              ("piz:3", "piz takes no level"), ("lzma", "unknown EXR compression")])
def test_bad_compression_is_refused(small_sequence, tmp_path, compression, why):
    proc = run("copy", small_sequence / "noisy.####.exr", tmp_path / "c.####.exr", "--compression", compression,
               check_rc=1)
    assert why in proc.stderr and compression in proc.stderr
    assert not list(tmp_path.glob("c.*"))


def test_compression_levels_in_range_work(small_sequence, tmp_path):
    for compression in ("zip:9", "zips:1", "dwaa:45", "dwab:200.5"):
        run("copy", small_sequence / "noisy.####.exr", tmp_path / "c.####.exr", "--compression", compression, "-q")


def test_png_output_is_refused(small_sequence, tmp_path):
    for command in ("copy", "denoise"):
        proc = run(command, small_sequence / "noisy.####.exr", tmp_path / "o.####.png", check_rc=2)
        assert "o.####.png" in proc.stderr and "EXR only" in proc.stderr
    assert not list(tmp_path.glob("o.*"))
