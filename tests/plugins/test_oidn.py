"""The oidn plugin. Without libOpenImageDenoise these tests skip, saying why, except the one that
checks the error a user then gets. CI installs it (scripts/setup.sh: pip install pyoidn)."""

import math
import os

import numpy as np
import pytest

import statfilter
from conftest import SAMPLE, SHARED, run_cli

NOISY = SAMPLE / "cornell_moving" / "spp0004" / "indirect.####.exr"
REF = SAMPLE / "cornell_moving" / "ref" / "indirect.####.exr"
AUX = SAMPLE / "cornell_moving" / "aux"


@pytest.fixture(scope="module")
def sample():
    return statfilter.read_sequence(str(NOISY)), statfilter.read_sequence(str(REF))


def test_missing_library_is_a_clear_error(tmp_path):
    env = {"STATFILTER_OIDN_LIBRARY": str(tmp_path / "libOpenImageDenoise.so.2")}
    listing = run_cli("plugins", env=env).stdout
    oidn_lines = listing.split("\noidn ", 1)[1].split("\n    --", 1)[0]
    assert "UNAVAILABLE" in oidn_lines and "pip install pyoidn" in oidn_lines
    for args in (["--method", "oidn"], ["--method", "pca", "--prefilter", "oidn"]):
        proc = run_cli("denoise", NOISY, tmp_path / "o.####.exr", *args, "--frames", "1-3", "-q", env=env, check_rc=1)
        assert "libOpenImageDenoise" in proc.stderr and "pip install pyoidn" in proc.stderr, proc.stderr
        assert "STATFILTER_OIDN_LIBRARY" in proc.stderr
    assert not list(tmp_path.glob("o.*.exr"))


def test_oidn_denoises_real_renders(oidn, sample):
    noisy, ref = sample
    out = statfilter.Filter("oidn")(noisy)
    before, after = statfilter.compare(noisy, ref), statfilter.compare(out, ref)
    assert after["rel_mse"] < 0.2 * before["rel_mse"], (before, after)
    assert after["psnr"] > before["psnr"] + 5


def test_temporal_pass_after_oidn_lowers_still_scene_jitter(oidn, sample):
    noisy, ref = sample
    alone = statfilter.compare(statfilter.Filter("oidn")(noisy), ref)
    for method in ("pca", "error-threshold", "moving-basis"):
        stabilised = statfilter.compare(statfilter.Filter(method, prefilter="oidn")(noisy), ref)
        assert stabilised["jitter"] < 0.5 * alone["jitter"], (method, alone, stabilised)
        assert stabilised["flicker"] < alone["flicker"], method
        assert stabilised["rel_mse"] < alone["rel_mse"], method


def test_parameters_and_guides(oidn, sample):
    noisy = sample[0][:4]
    default = statfilter.Filter("oidn")(noisy)
    fast = statfilter.Filter("oidn", quality="fast")(noisy)
    assert not np.array_equal(default, fast)
    # OIDN's scratch memory capped: tiles within it, the same picture within a fraction of its level.
    tiled = statfilter.Filter("oidn", max_memory_mb=16)(noisy)
    assert np.isfinite(tiled).all() and np.abs(tiled - default).mean() < 0.02 * np.abs(default).mean()
    assert np.isfinite(fast).all()
    guided = statfilter.Filter("oidn", albedo=str(AUX / "albedo.####.exr"), normal=str(AUX / "normal.####.exr"))(noisy)
    assert not np.array_equal(default, guided) and np.isfinite(guided).all()
    with pytest.raises(statfilter.InvalidArgumentError, match="normal pass needs an albedo"):
        statfilter.Filter("oidn", normal=str(AUX / "normal.####.exr"))(noisy)
    with pytest.raises(statfilter.InvalidArgumentError, match="needs an input read from files"):
        statfilter.Filter("oidn", albedo="ViewLayer.Diffuse Color")(noisy)
    with pytest.raises(statfilter.InvalidArgumentError, match="is 160 x 120, the input 8 x 8"):
        statfilter.Filter("oidn", albedo=str(AUX / "albedo.####.exr"))(noisy[:, :8, :8])
    with pytest.raises(statfilter.InvalidArgumentError, match="3 channels"):
        statfilter.Filter("oidn")(np.ones((2, 8, 8, 2), np.float32))
    nan = noisy.copy()
    nan[1, 2, 3, 0] = np.nan
    with pytest.raises(statfilter.NumericError, match="non-finite value at frame 2, pixel \\(3, 2\\)"):
        statfilter.Filter("oidn")(nan)
    # One channel and RGBA: grey is denoised as grey, alpha passes through.
    grey = statfilter.Filter("oidn")(noisy[..., :1])
    assert grey.shape == noisy[..., :1].shape and np.isfinite(grey).all()
    rgba = np.concatenate([noisy, np.full(noisy[..., :1].shape, 0.25, np.float32)], axis=-1)
    out = statfilter.Filter("oidn")(rgba)
    np.testing.assert_array_equal(out[..., 3], 0.25)
    np.testing.assert_array_equal(out[..., :3], default)


def test_high_runs_oidn_last_and_streams(oidn, sample, tmp_path):
    """--quality high: the hybrid on the noisy frames, then OIDN on its result, blended back towards OIDN
    on the noisy frames; streamed from files it equals the shot in memory, and it beats OIDN alone."""
    import json
    noisy, ref = sample
    out = tmp_path / "out.####.exr"
    proc = run_cli("denoise", NOISY, out, "--quality", "high", "--float", "--json")
    results = json.loads(proc.stdout)["results"]
    assert results["method"] in ("hybrid then oidn", "pca then oidn"), results
    assert results["run.streamed"] == 1 and 0 <= results["prefilter_trust.share"] <= 1, results
    streamed = statfilter.read_sequence(str(out))
    in_memory = statfilter.Filter("auto", quality="high")(noisy)
    np.testing.assert_allclose(streamed, in_memory, rtol=1e-4, atol=1e-6)
    alone = statfilter.compare(statfilter.Filter("oidn")(noisy), ref)
    assert statfilter.compare(streamed, ref)["rel_mse"] < 0.85 * alone["rel_mse"]
    # OIDN first, the order before: also below OIDN alone, and above the order run last here.
    first = statfilter.Filter("auto", quality="high", prefilter_order="first")(noisy)
    assert statfilter.compare(streamed, ref)["rel_mse"] < statfilter.compare(first, ref)["rel_mse"] < alone["rel_mse"]


def test_oidn_run_last_keeps_the_light_of_a_narrow_crop(oidn, sample, tmp_path):
    """OIDN run last (on the temporal result) is scaled back to the light it was handed, as OIDN on the
    noisy frames is: on a one-row crop it had taken 11.8% of the light away (--quality high), streamed
    and in memory alike."""
    noisy = sample[0]
    for name, crop in (("row", noisy[:, 60:61, :]), ("column", noisy[:, :, 80:81])):
        crop = np.ascontiguousarray(crop)
        statfilter.write_sequence(str(tmp_path / name / "in.####.exr"), crop)
        out = tmp_path / name / "out" / "o.####.exr"
        run_cli("denoise", tmp_path / name / "in.####.exr", out, "--quality", "high", "--float", "-q")
        streamed = statfilter.read_sequence(str(out)).astype(np.float64)
        in_memory = statfilter.Filter("auto", quality="high", nonfinite="repair")(crop)  # holds the shot
        np.testing.assert_allclose(streamed, in_memory, rtol=1e-4, atol=1e-6)
        bias = streamed.mean() / crop.astype(np.float64).mean() - 1
        assert abs(bias) <= 0.005, (name, bias)


def test_nonfinite_input_names_the_sample_and_the_remedy_before_oidn(oidn, sample, tmp_path):
    bad = sample[0][:6].copy()
    bad[2, :15] = np.nan
    statfilter.write_sequence(str(tmp_path / "in.####.exr"), bad)
    for args in (["--quality", "high"], ["--prefilter", "oidn"], ["--method", "pca", "--prefilter", "oidn"]):
        proc = run_cli("denoise", tmp_path / "in.####.exr", tmp_path / "out" / "o.####.exr", *args, "-q", check_rc=1)
        assert "NaN in frame 3 at pixel (0, 0) channel 'R'" in proc.stderr, (args, proc.stderr)
        assert "set nonfinite=repair" in proc.stderr, (args, proc.stderr)
        assert not list((tmp_path / "out").glob("o.*.exr"))


def test_oidn_scratch_is_a_share_of_the_budget(oidn, tmp_path):
    """OIDN's own scratch (3000 MiB an instance by default) comes out of --memory: each instance is given
    max_memory_mb, at least 256 MiB (counted in what the run needs) and half of what the rest leaves;
    a max_memory_mb the user gives is kept."""
    import json
    mib = 1024.0 * 1024.0
    out = tmp_path / "out.####.exr"

    def results(*args):
        proc = run_cli("denoise", NOISY, out, "--frames", "1-6", "--float", "--json", *args)
        return json.loads(proc.stdout)["results"]

    shared = results("--quality", "high", "--memory", "1G", "--threads", "2")
    each, needed = shared["run.frame_stage_memory_each"], shared["run.memory_needed"]
    assert shared["run.memory_budget"] == 1024 * mib and needed <= 1024 * mib
    assert needed >= 2 * 256 * mib  # one instance a thread, each at least 256 MiB
    # 256 MiB and half of what the budget leaves, split between the two instances.
    assert each == pytest.approx(256 * mib + 0.5 * (1024 * mib - needed) / 2, rel=1e-6)
    smaller = results("--quality", "high", "--memory", "768M", "--threads", "2")
    assert 256 * mib <= smaller["run.frame_stage_memory_each"] < each
    own = results("--method", "hybrid", "--prefilter", "oidn", "--prefilter-params", "max_memory_mb=64",
                  "--memory", "1G", "--threads", "2")
    assert "run.frame_stage_memory_each" not in own
    assert own["run.memory_needed"] < needed - 2 * 200 * mib
    # Below the least share: refused before any work, with the budget that would do.
    proc = run_cli("denoise", NOISY, out, "--quality", "high", "--frames", "1-6", "--memory", "300M",
                   "--threads", "2", check_rc=1)
    assert f"give at least --memory {math.ceil(needed / mib)}M" in proc.stderr, proc.stderr


def test_high_with_the_same_noise_in_every_frame_is_oidn_alone(oidn, sample, tmp_path):
    """A fixed seed leaves one noise pattern on every frame: no temporal filter removes it, so --quality
    high runs OIDN alone (streamed, with the renderer's passes given too) and warns."""
    import json
    import warnings
    noisy = sample[0][:5]
    fixed = np.repeat(noisy[:1], 5, axis=0) * np.linspace(1.0, 1.2, 5, dtype=np.float32)[:, None, None, None]
    pattern = str(tmp_path / "fixed.####.exr")
    statfilter.write_sequence(pattern, fixed, pixel_type="float")
    alone = statfilter.Filter("oidn")(fixed)
    # OIDN alone, and OIDN with the noisy shot's light per channel (keep_mean): what high gives lies
    # between the two (the trust blend weighs them tile by tile).
    gain = fixed.sum(axis=(0, 1, 2), dtype=np.float64) / alone.sum(axis=(0, 1, 2), dtype=np.float64)
    low, high = np.minimum(alone, alone * gain), np.maximum(alone, alone * gain)

    def between(out):
        assert np.all(out >= low - 1e-5 - 1e-4 * np.abs(low)) and np.all(out <= high + 1e-5 + 1e-4 * np.abs(high))

    proc = run_cli("denoise", pattern, tmp_path / "o.####.exr", "--quality", "high", "--float", "--json")
    results = json.loads(proc.stdout)["results"]
    assert results["method"] == "oidn" and results["run.streamed"] == 1, results
    assert "the same in every frame" in results["warning"] and "warning" in proc.stderr
    between(statfilter.read_sequence(str(tmp_path / "o.####.exr")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", statfilter.StatfilterWarning)
        f = statfilter.Filter("auto", quality="high", albedo=str(AUX / "albedo.####.exr"))
        f.run_files(pattern, str(tmp_path / "p.####.exr"), pixel_type="float")
    assert f.results["method"] == "oidn" and f.results["run.streamed"] == 1, f.results
    between(statfilter.read_sequence(str(tmp_path / "p.####.exr")))
    # The shot as rendered (a seed per frame) keeps the temporal pipeline.
    f = statfilter.Filter("auto", quality="high")
    f(noisy)
    assert f.results["method"] in ("hybrid then oidn", "pca then oidn") and "warning" not in f.results


def test_black_stays_black(oidn, sample):
    """Zero in, zero out: OIDN alone returned a faint level (about 4e-6) on a frame of zeros."""
    zero = np.zeros((6, 40, 48, 3), np.float32)
    for f in (statfilter.Filter("oidn"), statfilter.Filter("auto", quality="high"),
              statfilter.Filter("pca", prefilter="oidn")):
        np.testing.assert_array_equal(f(zero), zero)
    # A black frame among lit ones stays black; the lit ones are denoised as before.
    noisy = sample[0][:4].copy()
    noisy[2] = 0
    out = statfilter.Filter("oidn")(noisy)
    np.testing.assert_array_equal(out[2], 0)
    np.testing.assert_array_equal(out[[0, 1, 3]], statfilter.Filter("oidn")(noisy[[0, 1, 3]]))


def test_cli_prefilter_oidn(oidn, tmp_path):
    out = tmp_path / "out.####.exr"
    run_cli("denoise", NOISY, out, "--method", "pca", "--rank", "auto", "--prefilter", "oidn",
            "--prefilter-params", "quality=high", "--frames", "1-8", "-q")
    assert len(list(tmp_path.glob("out.*.exr"))) == 8


def test_layers_of_the_input_files(oidn, tmp_path):
    raw = SHARED / "raw" / "cornell_moving_spp0016"
    if not raw.is_dir():
        pytest.skip("no multi-part Blender frames in %s" % raw)
    out = tmp_path / "out.####.exr"
    run_cli("denoise", raw / "frame.####.exr", out, "--channels", "ViewLayer.Diffuse Indirect", "--method", "oidn",
            "--albedo", "ViewLayer.Diffuse Color", "--normal", "ViewLayer.Normal", "-q")
    bad = run_cli("denoise", raw / "frame.####.exr", out, "--channels", "ViewLayer.Diffuse Indirect",
                  "--method", "oidn", "--albedo", "ViewLayer.No Such Layer", "-q", check_rc=1)
    assert "albedo" in bad.stderr and "No Such Layer" in bad.stderr


def test_high_quality_repairs_nonfinite_samples_before_oidn(oidn, sample):
    """nonfinite=repair reaches the prefilter too: OIDN refuses NaN, so the samples are repaired first."""
    noisy, ref = sample
    bad = noisy[:8].copy()
    bad[3, 10, 20, 1] = np.nan
    bad[5, 40, 60, 0] = np.inf
    f = statfilter.Filter("auto", quality="high", nonfinite="repair")
    out = f(bad)
    assert np.isfinite(out).all()
    # nonfinite=error (the default): the same error as without OIDN, naming the sample and the remedy,
    # in memory and streamed from files (before, OIDN's own "non-finite value", without the remedy).
    with pytest.raises(statfilter.NumericError, match="nonfinite=repair"):
        statfilter.Filter("auto", quality="high")(bad)
    with pytest.raises(statfilter.NumericError, match="nonfinite=repair"):
        statfilter.Filter("pca", prefilter="oidn")(bad)
