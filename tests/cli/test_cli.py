import json
import os
import subprocess

import pytest

from conftest import SHARED, oiio_tool, run


def test_help_and_usage_errors():
    assert "info PATTERN" in run("--help").stdout
    assert run(check_rc=2).stderr.startswith("usage:")
    bad = run("frobnicate", check_rc=2)
    assert "unknown command 'frobnicate'" in bad.stderr
    assert "--frames" in run("info", "--help").stdout
    assert "copy" in run("denoise", "--help").stdout
    assert "needs a value" in run("info", "x.####.exr", "--frames", check_rc=2).stderr


def test_info_on_shipped_sample(sample_noisy):
    out = run("info", sample_noisy, "-q").stdout
    assert "32 (1-32)" in out and "160 x 120" in out
    report = json.loads(run("info", sample_noisy, "--json").stdout)
    assert report["frame_count"] == 32 and report["width"] == 160 and report["height"] == 120
    assert [c["name"] for c in report["channels"]] == ["R", "G", "B"]
    for c in report["channels"]:
        assert c["nan"] == 0 and c["inf"] == 0 and 0 <= c["min"] <= c["mean"] <= c["max"]


def test_copy_float_is_bit_exact_and_keeps_metadata(small_sequence, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    run("copy", small_sequence / "noisy.####.exr", out / "copy.####.exr", "--float", "-q")
    assert sorted(p.name for p in out.iterdir()) == [f"copy.{f:04d}.exr" for f in range(1, 5)]
    idiff = oiio_tool("idiff")
    for f in range(1, 5):
        a, b = small_sequence / f"noisy.{f:04d}.exr", out / f"copy.{f:04d}.exr"
        assert subprocess.run([idiff, "-fail", "0", "-warn", "0", str(a), str(b)], capture_output=True).returncode == 0
    info = subprocess.run([oiio_tool("oiiotool"), "--info", "-v", str(out / "copy.0001.exr")],
                          capture_output=True, text=True).stdout
    assert "float" in info and 'colorInteropID: "lin_rec709_scene"' in info


def test_frames_option_and_progress(small_sequence, tmp_path):
    proc = run("copy", small_sequence / "noisy.%04d.exr", tmp_path / "o.#.exr", "--frames", "2-3")
    assert sorted(p.name for p in tmp_path.glob("o.*.exr")) == ["o.0002.exr", "o.0003.exr"]
    # copy streams frame by frame: read, copied and written in one stage
    assert "statfilter: frames 0%" in proc.stderr and "statfilter: done 100%" in proc.stderr
    assert run("copy", small_sequence / "noisy.####.exr", tmp_path / "q.####.exr", "--quiet").stderr == ""


def test_gap_is_reported_by_info_and_refused_by_copy(small_sequence, tmp_path):
    os.remove(small_sequence / "noisy.0003.exr")
    report = json.loads(run("info", small_sequence / "noisy.####.exr", "--json").stdout)
    assert report["missing_frames"] == "3" and report["frame_count"] == 3
    out = tmp_path / "out"
    out.mkdir()
    proc = run("copy", small_sequence / "noisy.####.exr", out / "c.####.exr", check_rc=1)
    assert "frames 3 are missing" in proc.stderr
    assert list(out.iterdir()) == []


def test_unwritable_output_directory(small_sequence, tmp_path):
    (tmp_path / "plain").write_text("a file, not a directory")
    proc = run("copy", small_sequence / "noisy.####.exr", tmp_path / "plain" / "c.####.exr", check_rc=1)
    assert "cannot be created" in proc.stderr and "plain" in proc.stderr


def test_truncated_and_non_image_files_are_named(small_sequence, tmp_path):
    victim = small_sequence / "noisy.0002.exr"
    data = victim.read_bytes()
    victim.write_bytes(data[: len(data) // 2])
    out = tmp_path / "out"
    out.mkdir()
    proc = run("copy", small_sequence / "noisy.####.exr", out / "c.####.exr", check_rc=1)
    assert "noisy.0002.exr" in proc.stderr
    assert list(out.iterdir()) == []
    victim.write_text("not an image")
    assert "noisy.0002.exr" in run("info", small_sequence / "noisy.####.exr", check_rc=1).stderr


def test_missing_channel_and_no_frames(small_sequence, tmp_path):
    proc = run("info", small_sequence / "noisy.####.exr", "--channels", "Z", check_rc=1)
    assert "no channel or layer 'Z'" in proc.stderr and "R, G, B" in proc.stderr
    assert "no files match" in run("info", tmp_path / "none.####.exr", check_rc=1).stderr


def test_unknown_method_and_parameter(small_sequence, tmp_path):
    proc = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr", "--method", "nope", check_rc=1)
    assert "unknown filter 'nope'" in proc.stderr
    # A name no filter has is a usage error; a parameter of another filter is refused by this one.
    proc = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr", "--method", "copy",
               "--bogus", "3", check_rc=2)
    assert "unknown option --bogus" in proc.stderr
    proc = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr", "--method", "copy",
               "--rank", "3", check_rc=1)
    assert "unknown parameter 'rank'" in proc.stderr


def test_denoise_json_report(small_sequence, tmp_path):
    report = json.loads(run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr", "--method",
                            "copy", "--json").stdout)
    assert report["frames"] == 4 and report["method"] == "copy" and report["seconds"] >= 0


@pytest.mark.skipif(not (SHARED / "raw").is_dir(), reason="real multi-part renders not present")
def test_blender_multipart_layer(tmp_path):
    raw = SHARED / "raw" / "cornell_moving_spp0016" / "frame.####.exr"
    report = json.loads(run("info", raw, "--json").stdout)
    assert "ViewLayer.Diffuse Indirect" in report["layers"]
    run("copy", raw, tmp_path / "ind.####.exr", "--channels", "ViewLayer.Diffuse Indirect", "--float", "-q")
    layer = json.loads(run("info", tmp_path / "ind.####.exr", "--json").stdout)
    assert [c["name"] for c in layer["channels"]] == ["R", "G", "B"]
    full = {c["name"]: c for c in report["channels"]}
    for c in layer["channels"]:
        assert c["mean"] == pytest.approx(full["ViewLayer.Diffuse Indirect." + c["name"]]["mean"], rel=1e-6)


def test_motion_maps_and_previews(sample_noisy, tmp_path):
    proc = run("motion", sample_noisy, "--frames", "1-8", "--alpha", tmp_path / "alpha.exr",
               "--beta", tmp_path / "beta.####.exr", "--alpha-preview", tmp_path / "alpha.png",
               "--beta-preview", tmp_path / "beta.####.png", "--json")
    report = json.loads(proc.stdout)
    assert 0 <= report["moving_fraction"] <= 1 and report["beta_source"] == "zscore"
    assert (tmp_path / "alpha.exr").is_file() and (tmp_path / "alpha.png").is_file()
    assert len(list(tmp_path.glob("beta.*.exr"))) == 8 and len(list(tmp_path.glob("beta.*.png"))) == 8
    alpha = json.loads(run("info", tmp_path / "alpha.exr", "--json").stdout)
    assert [c["name"] for c in alpha["channels"]] == ["alpha"]
    assert 0 <= alpha["channels"][0]["min"] and alpha["channels"][0]["max"] <= 1
    # A frame per frame needs a frame token: refused before the maps are made, nothing written.
    proc = run("motion", sample_noisy, "--frames", "1-8", "--alpha", tmp_path / "again" / "alpha.exr",
               "--beta-preview", tmp_path / "again" / "beta.png", "--json", check_rc=1)
    assert "image result 'beta'" in proc.stderr and "8 frames" in proc.stderr and not proc.stdout
    assert not list((tmp_path / "again").iterdir())


def test_quality_presets(small_sequence, tmp_path):
    def picked(*extra):
        out = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "q.####.exr", *extra, "--json").stdout
        return json.loads(out)["results"]
    fast = picked("--quality", "fast")
    assert fast["method"] == "pca" and fast["quality"] == "fast" and "fast" in fast["reason"]
    assert picked("--quality", "balanced", "--method", "auto")["method"] in ("pca then diffusion",
                                                                         "hybrid then diffusion")
    high = picked("--quality", "high")
    assert high["quality"] == "high" and high["reason"]
    conflict = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "r.####.exr", "--quality", "fast",
                   "--method", "pca", check_rc=2)
    assert "--quality picks the method" in conflict.stderr
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "r.####.exr", "--quality", "best", check_rc=1)
    assert "fast" in bad.stderr and "balanced" in bad.stderr  # the valid choices are named
    assert not list(tmp_path.glob("r.*.exr"))


def test_save_image_results_and_auto(small_sequence, tmp_path):
    report = json.loads(run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr",
                            "--method", "auto", "--json").stdout)
    assert report["results"]["method"].split()[0] in ("pca", "error-threshold") and report["results"]["reason"]
    run("denoise", small_sequence / "noisy.####.exr", tmp_path / "e.####.exr", "--method", "error-threshold",
        "--save", f"rank_map={tmp_path / 'ranks.exr'}", "-q")
    ranks = json.loads(run("info", tmp_path / "ranks.exr", "--json").stdout)
    assert ranks["channels"][0]["name"] == "rank" and ranks["channels"][0]["max"] <= 8
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "f.####.exr", "--save", "oops", check_rc=2)
    assert "NAME=PATTERN" in bad.stderr
    # Where a result cannot be written is found before any work too: a frame a frame (beta) without a
    # frame token, a directory under a file, an input frame.
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "f.####.exr", "--method", "motion",
              "--save", f"beta={tmp_path / 'beta.exr'}", check_rc=1)
    assert "image result 'beta'" in bad.stderr and "no frame token" in bad.stderr
    (tmp_path / "a_file").write_text("")
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "f.####.exr", "--method", "error-threshold",
              "--save", f"rank_map={tmp_path / 'a_file' / 'r.exr'}", check_rc=1)
    assert "image result 'rank_map'" in bad.stderr and "cannot be created" in bad.stderr
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "f.####.exr", "--method", "motion",
              "--save", f"alpha={small_sequence / 'noisy.####.exr'}", check_rc=1)
    assert "refusing to write over it" in bad.stderr
    assert not list(tmp_path.glob("f.*.exr"))  # refused before any work
    # The --frames selection is what counts: one frame needs no token, three do.
    run("denoise", small_sequence / "noisy.####.exr", tmp_path / "g.####.exr", "--method", "motion", "--frames", "1-1",
        "--save", f"beta={tmp_path / 'beta1.exr'}", "-q")
    assert (tmp_path / "beta1.exr").exists()
    bad = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "g.####.exr", "--method", "motion", "--frames",
              "1-2,4", "--save", f"beta={tmp_path / 'beta3.exr'}", check_rc=1)
    assert "has 3 frames" in bad.stderr
