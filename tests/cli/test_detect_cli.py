"""statfilter detect and statfilter merge, driven as a user would, on the shipped sample."""

import json
import subprocess

import pytest

from conftest import SAMPLE, oiio_tool, run

NOISY = SAMPLE / "cornell_moving" / "spp0004" / "indirect.####.exr"
REF = SAMPLE / "cornell_moving" / "ref" / "indirect.####.exr"


@pytest.fixture(scope="module")
def detected(tmp_path_factory):
    """The sample denoised with pca --rank auto, and what detect finds in it."""
    d = tmp_path_factory.mktemp("detect")
    run("denoise", NOISY, d / "den.####.exr", "--method", "pca", "--rank", "auto", "--float", "-q")
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY, "--mask", d / "mask.####.exr", "--crops",
               d / "crops.json", "--degree-map", d / "degree.exr", "--preview", d / "degree.png", "--json")
    return d, json.loads(proc.stdout)


def rel_mse(test, ref):
    return json.loads(run("compare", test, ref, "--json").stdout)["rel_mse"]


def test_help_lists_options_and_parameters():
    text = run("detect", "--help").stdout
    for word in ("--noisy", "--mask", "--crops", "--degree-map", "--preview", "--degree", "--delta", "--threshold",
                 "--crop-padding"):
        assert word in text
    assert "{window}" in run("merge", "--help").stdout and "--feather" in run("merge", "--help").stdout
    assert "detect DENOISED" in run("--help").stdout


def test_detect_writes_mask_crops_and_degree_map(detected):
    d, report = detected
    assert report["source"] == "residual"
    assert 0.001 < report["flagged_fraction"] < 0.5
    assert report["window_fraction"] >= report["flagged_fraction"]
    assert sorted(p.name for p in d.glob("mask.*.exr")) == ["mask.%04d.exr" % f for f in range(1, 33)]
    assert (d / "degree.exr").is_file() and (d / "degree.png").is_file()
    crops = json.loads((d / "crops.json").read_text())
    assert crops["format"] == "statfilter-crops" and crops["width"] == 160 and crops["height"] == 120
    assert crops["flagged_pixels"] == report["flagged_pixel_frames"]
    assert crops["window_count"] == sum(len(f["windows"]) for f in crops["frames"])
    for f in crops["frames"]:
        for w in f["windows"]:
            assert 0 <= w["x"] and w["x"] + w["width"] <= 160 and 0 <= w["y"] and w["y"] + w["height"] <= 120
    info = subprocess.run([oiio_tool("oiiotool"), "--info", "-v", str(d / "mask.0001.exr")], capture_output=True,
                          text=True).stdout
    assert "1 channel" in info


def test_text_report_and_progress(detected, tmp_path):
    d, _ = detected
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY)
    assert "flagged" in proc.stdout and "crop windows" in proc.stdout
    assert "statfilter: regression" in proc.stderr
    assert run("detect", d / "den.####.exr", "--noisy", NOISY, "-q").stderr == ""


def test_merge_full_frames_lowers_the_error(detected):
    d, _ = detected
    proc = run("merge", d / "den.####.exr", REF, d / "merged.####.exr", "--crops", d / "crops.json", "--float",
               "--json", "-q")
    report = json.loads(proc.stdout)
    assert report["replaced_pixel_frames"] > 0
    assert rel_mse(d / "merged.####.exr", REF) < rel_mse(d / "den.####.exr", REF)


def test_crop_json_round_trips_through_merge_with_window_renders(detected, tmp_path):
    """Each window cut out of the reference as its own file (a crop render), merged through the JSON,
    gives exactly what merging the full reference frames gives."""
    d, _ = detected
    oiiotool = oiio_tool("oiiotool")
    crops = json.loads((d / "crops.json").read_text())
    frames = crops["frames"][:4]
    crops["frames"] = frames
    (tmp_path / "crops4.json").write_text(json.dumps(crops))
    for f in frames:
        for i, w in enumerate(f["windows"]):
            src = str(REF).replace("####", "%04d" % f["frame"])
            subprocess.run([oiiotool, src, "--cut", "%dx%d+%d+%d" % (w["width"], w["height"], w["x"], w["y"]),
                            "-d", "float", "-o", str(tmp_path / ("win.%d.%04d.exr" % (i, f["frame"])))], check=True)
    run("merge", d / "den.####.exr", tmp_path / "win.{window}.####.exr", tmp_path / "a.####.exr", "--crops",
        tmp_path / "crops4.json", "--float", "-q")
    run("merge", d / "den.####.exr", REF, tmp_path / "b.####.exr", "--crops", tmp_path / "crops4.json", "--float",
        "-q")
    idiff = oiio_tool("idiff")
    for f in range(1, 33):
        a, b = tmp_path / ("a.%04d.exr" % f), tmp_path / ("b.%04d.exr" % f)
        assert subprocess.run([idiff, "-fail", "0", "-warn", "0", str(a), str(b)], capture_output=True).returncode == 0
    # A window file of the wrong size is named in the error.
    victim = tmp_path / ("win.0.%04d.exr" % frames[0]["frame"])
    subprocess.run([oiiotool, str(REF).replace("####", "0001"), "--cut", "3x3+0+0", "-o", str(victim)], check=True)
    proc = run("merge", d / "den.####.exr", tmp_path / "win.{window}.####.exr", tmp_path / "c.####.exr", "--crops",
               tmp_path / "crops4.json", check_rc=1)
    assert victim.name in proc.stderr and "3 x 3" in proc.stderr
    assert not list(tmp_path.glob("c.*.exr"))


def test_merge_with_mask_and_feather(detected):
    d, _ = detected
    run("merge", d / "den.####.exr", REF, d / "m.####.exr", "--crops", d / "crops.json", "--mask", d / "mask.####.exr",
        "--feather", "1", "-q")
    assert len(list(d.glob("m.*.exr"))) == 32


def test_bad_input_fails_with_one_line(detected, tmp_path):
    d, _ = detected
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY, "--degree", "40", "-q", check_rc=1)
    assert proc.stderr.startswith("statfilter detect: error: degree 40 needs at least 41 frames")
    assert len(proc.stderr.strip().splitlines()) == 1
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "statfilter-crops", "version": 1, "width": 160,')
    proc = run("merge", d / "den.####.exr", REF, tmp_path / "o.####.exr", "--crops", bad, check_rc=1)
    assert "malformed JSON" in proc.stderr
    crops = json.loads((d / "crops.json").read_text())
    crops["width"] = 100
    bad.write_text(json.dumps(crops))
    proc = run("merge", d / "den.####.exr", REF, tmp_path / "o.####.exr", "--crops", bad, check_rc=1)
    assert "extends past the image width 100" in proc.stderr or "are for 100 x 120" in proc.stderr
    crops = json.loads((d / "crops.json").read_text())
    crops["frames"] = []
    bad.write_text(json.dumps(crops))
    proc = run("merge", d / "den.####.exr", REF, tmp_path / "o.####.exr", "--crops", bad, check_rc=1)
    assert "nothing to merge" in proc.stderr
    # A re-render with other channels (the one-channel mask) is refused.
    proc = run("merge", d / "den.####.exr", d / "mask.####.exr", tmp_path / "o.####.exr", "--crops", d / "crops.json",
               check_rc=1)
    assert "channels" in proc.stderr
    assert not list(tmp_path.glob("o.*.exr"))
    assert "needs --crops, --mask" in run("merge", d / "den.####.exr", REF, tmp_path / "o.####.exr", check_rc=2).stderr
    assert "--feather" in run("merge", d / "den.####.exr", REF, tmp_path / "o.####.exr", "--crops", d / "crops.json",
                              "--feather", "two", check_rc=2).stderr
    assert "one DENOISED" in run("detect", check_rc=2).stderr


def test_outputs_are_checked_before_the_detection_runs(detected, tmp_path):
    d, _ = detected
    # A mask without a frame token for 32 frames, a degree map under a file: refused at once, nothing written.
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY, "--mask", tmp_path / "m.exr", "-q", check_rc=1)
    assert "image result 'mask'" in proc.stderr and "no frame token" in proc.stderr
    (tmp_path / "a_file").write_text("")
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY, "--crops", tmp_path / "c.json", "--degree-map",
               tmp_path / "a_file" / "degree.exr", "-q", check_rc=1)
    assert "image result 'degree_map'" in proc.stderr and "cannot be created" in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]
