"""Plugins through Python and the CLI: listing, parameters as keywords and options, the prefilter."""

import json

import numpy as np
import pytest

import statfilter
from conftest import SAMPLE, run_cli


def by_name():
    return {p["name"]: p for p in statfilter.plugins()}


def test_python_lists_builtins_and_plugins():
    listed = by_name()
    assert listed["pca"]["origin"] == "built-in" and listed["pca"]["kind"] == "temporal"
    assert listed["pca"]["version"] == statfilter.version()
    scale = listed["scale"]
    assert scale["kind"] == "single-frame" and scale["available"] and scale["problem"] == ""
    assert scale["origin"].endswith("/statfilter_scale.so") and scale["version"] == "2.5.0"
    for broken in ("notlib", "nosymbol", "badabi", "misnamed"):
        assert not listed[broken]["available"]
        assert "statfilter_%s.so" % broken in listed[broken]["problem"]
    # filters() lists what can be created: the plugin, not the broken files.
    assert "scale" in statfilter.filters() and "badabi" not in statfilter.filters()


def test_python_plugin_parameters_and_prefilter(rng):
    clean = np.linspace(0.5, 1.0, 10, dtype=np.float32)[:, None, None, None] * np.ones((10, 6, 8, 3), np.float32)
    noisy = (clean + 0.02 * rng.standard_normal(clean.shape)).astype(np.float32)
    scaled = statfilter.Filter("scale", factor=3.0, offset=0.5)(noisy)
    np.testing.assert_allclose(scaled, 3 * noisy + 0.5, rtol=1e-6)
    with pytest.raises(statfilter.InvalidArgumentError, match="factor"):
        statfilter.Filter("scale", factor=1e9)
    with pytest.raises(statfilter.UnsupportedError, match="statfilter_badabi.so"):
        statfilter.Filter("badabi")

    # the plain chain: the prefilter's light as it is (keep_mean=0), no trust blend
    two_steps = statfilter.Filter("error-threshold", keep_mean=0)(scaled)
    one_step = statfilter.Filter("error-threshold", prefilter="scale", prefilter_params="factor=3,offset=0.5",
                                 keep_mean=0, prefilter_trust=0)(noisy)
    np.testing.assert_array_equal(one_step, two_steps)
    with pytest.raises(statfilter.InvalidArgumentError, match="temporal filter"):
        statfilter.Filter("pca", prefilter="pca")(noisy)


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def test_cli_plugins_lists_everything():
    out = run_cli("plugins").stdout
    for name in ("copy", "pca", "error-threshold", "moving-basis", "scale"):
        assert name in out
    assert "--factor" in out and "single-frame" in out and "2.5.0" in out
    assert "UNAVAILABLE" in out and "statfilter_badabi.so" in out and "ABI version 999" in out
    listed = {p["name"]: p for p in json.loads(run_cli("plugins", "--json").stdout)}
    assert listed["scale"]["parameters"][0]["name"] == "factor"
    assert listed["scale"]["kind"] == "single-frame" and listed["scale"]["available"] is True
    assert listed["notlib"]["available"] is False and "cannot load" in listed["notlib"]["problem"]
    assert run_cli("plugins", "extra", check_rc=2).returncode == 2


def test_cli_lists_a_plugin_whose_create_fails_as_unavailable():
    listed = {p["name"]: p for p in json.loads(run_cli("plugins", "--json").stdout)}
    assert listed["nodevice"]["available"] is False
    assert "no GPU device available" in listed["nodevice"]["problem"]
    assert "no GPU device available" in run_cli("plugins").stdout
    text = run_cli("denoise", "--help").stdout
    assert "scale:" in text and "nodevice" not in text


def test_cli_prefilter_option(tmp_path):
    noisy = SAMPLE / "cornell_moving" / "spp0004" / "indirect.####.exr"
    a, b, c = (tmp_path / d for d in "abc")
    for d in (a, b, c):
        d.mkdir()
    run_cli("denoise", noisy, a / "s.####.exr", "--method", "scale", "--factor", "2", "--float", "--frames", "1-6", "-q")
    run_cli("denoise", a / "s.####.exr", b / "p.####.exr", "--method", "pca", "--keep-mean", "0", "--float", "-q")
    run_cli("denoise", noisy, c / "p.####.exr", "--method", "pca", "--prefilter", "scale",
            "--prefilter-params", "factor=2", "--keep-mean", "0", "--prefilter-trust", "0", "--float", "--frames", "1-6",
            "-q")
    first = statfilter.read_sequence(str(b / "p.####.exr"))
    second = statfilter.read_sequence(str(c / "p.####.exr"))
    np.testing.assert_array_equal(first, second)
    # With a prefilter and no --method, denoise runs the hybrid (docs/oidn.md says why).
    report = json.loads(run_cli("denoise", noisy, c / "h.####.exr", "--prefilter", "scale", "--frames", "1-6",
                                "--json").stdout)
    assert report["method"] == "hybrid"
    bad = run_cli("denoise", noisy, c / "q.####.exr", "--method", "pca", "--prefilter", "nosymbol", "-q", check_rc=1)
    assert "statfilter_nosymbol.so" in bad.stderr and "sf_plugin_entry" in bad.stderr
