"""The Filter class and the listing functions, generic over whatever filters the library has."""

import re

import numpy as np
import pytest

import statfilter


def test_version():
    v = statfilter.version()
    assert isinstance(v, str) and len(v.split(".")) == 3 and all(p.isdigit() for p in v.split("."))


def test_filters_listed_with_descriptions():
    listed = statfilter.filters()
    assert "copy" in listed
    assert all(isinstance(d, str) and d for d in listed.values())


@pytest.mark.parametrize("name", sorted(statfilter.filters()))
def test_every_filter_lists_consistent_params(name):
    f = statfilter.Filter(name)
    assert f.name == name
    for p in f.params():
        assert set(p) == {"name", "type", "default", "description", "min", "max", "choices", "value"}
        assert p["type"] in ("int", "float", "string")
        assert p["name"] and isinstance(p["description"], str)
        assert p["min"] <= p["max"]
        # A fresh filter holds its defaults, and get() agrees with params().
        assert p["value"] == f.get(p["name"]) == f[p["name"]]
        if p["type"] == "int":
            assert p["value"] == int(p["default"])
        elif p["type"] == "float":
            assert p["value"] == pytest.approx(float(p["default"]))
        else:
            assert p["value"] == p["default"]
        # Setting the default back (by its own Python type) works.
        f[p["name"]] = p["value"]
        for choice in p["choices"]:
            f[p["name"]] = choice
            assert f.get(p["name"]) == choice
    assert repr(f).startswith("statfilter.Filter(%r" % name)


def test_copy_filter_runs(noisy):
    f = statfilter.Filter("copy")
    out = f(noisy)
    assert out.dtype == np.float32 and out.shape == noisy.shape
    np.testing.assert_array_equal(out, noisy)
    assert isinstance(f.results, dict)


def test_copy_has_no_params():
    assert statfilter.Filter("copy").params() == []


def test_filter_close():
    with statfilter.Filter("copy") as f:
        pass
    with pytest.raises(statfilter.InvalidArgumentError, match="closed"):
        f(np.zeros((1, 1, 1, 1), np.float32))
    f.close()  # twice is fine
    assert "closed" in repr(f)


def test_progress_values(noisy):
    seen = []
    statfilter.Filter("copy")(noisy, progress=lambda fraction, stage: seen.append((fraction, stage)))
    fractions = [fr for fr, _ in seen]
    assert fractions and fractions == sorted(fractions)
    assert 0.0 <= fractions[0] and fractions[-1] == 1.0
    assert all(isinstance(s, str) and s for _, s in seen)


def test_error_hierarchy():
    assert issubclass(statfilter.InvalidArgumentError, ValueError)
    assert issubclass(statfilter.FileError, OSError)
    assert issubclass(statfilter.NotFoundError, LookupError)
    assert issubclass(statfilter.OutOfMemoryError, MemoryError)
    for cls in (statfilter.InvalidArgumentError, statfilter.OutOfMemoryError, statfilter.FileError,
                statfilter.NotFoundError, statfilter.UnsupportedError, statfilter.CancelledError,
                statfilter.NumericError, statfilter.InternalError):
        assert issubclass(cls, statfilter.Error)
        e = cls("message text")
        assert str(e) == "message text" and e.message == "message text" and e.status == cls.status
    import pickle
    e = pickle.loads(pickle.dumps(statfilter.NotFoundError("gone", 4)))
    assert isinstance(e, statfilter.NotFoundError) and e.status == 4 and e.message == "gone"


@pytest.mark.parametrize("name", sorted(statfilter.filters()))
def test_every_filter_runs_on_arrays(name, rng):
    """Each filter, with its defaults, takes a small noisy sequence and reports its results as
    numbers, text or (image results) arrays."""
    clean = np.linspace(0.2, 1.0, 16, dtype=np.float32)[:, None, None, None] * np.ones((16, 8, 10, 3), np.float32)
    noisy = (clean + 0.05 * rng.standard_normal(clean.shape)).astype(np.float32)
    f = statfilter.Filter(name)
    out = f(noisy)
    assert out.shape == noisy.shape and out.dtype == np.float32
    assert np.isfinite(out).all()
    for key, value in f.results.items():
        assert isinstance(value, (float, str, np.ndarray)), key
        if isinstance(value, str):
            assert not value.startswith("image"), "image result %r not fetched as an array" % key
            assert not re.fullmatch(r"-?[0-9.]+([eE][-+]?[0-9]+)?", value), "number %r=%r given as text" % (key, value)
        if isinstance(value, np.ndarray):
            assert value.dtype == np.float32 and value.ndim == 4
            assert value.shape[1:3] == noisy.shape[1:3]
    # Running again gives the same output (filters are deterministic) into a given buffer.
    again = np.empty_like(out)
    assert f(noisy, out=again) is again
    np.testing.assert_array_equal(again, out)


def test_quality_presets_through_the_auto_filter(rng):
    """--quality of the CLI is the auto filter's `quality` parameter: the same names, the same picks."""
    seq = (1 + 0.1 * rng.standard_normal((12, 10, 14, 3))).astype(np.float32)
    choices = next(p["choices"] for p in statfilter.Filter("auto").params() if p["name"] == "quality")
    assert choices == ["fast", "balanced", "high"]
    fast = statfilter.Filter("auto", quality="fast")
    out = fast(seq)
    assert fast.results["method"] == "pca" and fast.results["quality"] == "fast"
    np.testing.assert_array_equal(out, statfilter.Filter("pca", transform="none")(seq))
    # The chosen method's own results, which the library keeps as text ("pca.rank": "1"), are numbers.
    assert isinstance(fast.results["pca.rank"], float) and fast.results["pca.rank"] >= 0
    with pytest.raises(statfilter.InvalidArgumentError, match="balanced"):
        statfilter.Filter("auto", quality="best")


def moving_scene(rng, frames=12, height=24, width=32):
    """Noisy light on a wall with a bright square crossing it, and the matching albedo pass (the
    square's colour where it is, the wall's elsewhere): what the renderer hands the hybrid."""
    base = np.full((frames, height, width, 3), 0.5, np.float32)
    albedo = np.full_like(base, 0.8)
    for f in range(frames):
        x0 = 2 + 2 * f
        base[f, 8:16, x0:x0 + 6] = 2.0
        albedo[f, 8:16, x0:x0 + 6] = 0.3
    noisy = (base * (1 + 0.2 * rng.standard_normal(base.shape))).astype(np.float32)
    return noisy, albedo


def test_guide_passes_handed_in_memory_equal_the_same_passes_from_files(rng, tmp_path):
    """The albedo pass as a named input (an array) gives what the same pass read from files gives."""
    noisy, albedo = moving_scene(rng)
    statfilter.write_sequence(str(tmp_path / "albedo.####.exr"), albedo, pixel_type="float")
    from_memory = statfilter.Filter("hybrid")
    a = from_memory(noisy, inputs={"albedo": albedo})
    from_files = statfilter.Filter("hybrid", albedo=str(tmp_path / "albedo.####.exr"))
    b = from_files(noisy)
    np.testing.assert_array_equal(a, b)
    assert from_memory.results["motion_compensation"] == "optical flow on the albedo/normal passes"
    # balanced measures the motion with them too, and says the scene moves.
    balanced = statfilter.Filter("auto")
    balanced(noisy, inputs={"albedo": albedo})
    assert balanced.results["motion_fraction"] > 0


def test_a_named_guide_pass_is_checked_even_where_the_scene_does_not_need_it(rng, tmp_path):
    """A still scene needs no pass, but a pass that is named and missing, or of the wrong size, is an
    error before any work, not a silent success."""
    still = (0.5 * (1 + 0.1 * rng.standard_normal((12, 16, 20, 3)))).astype(np.float32)
    for name in ("hybrid", "auto", "motion"):
        with pytest.raises(statfilter.Error, match="missing.####.exr|missing"):
            statfilter.Filter(name, albedo=str(tmp_path / "missing.####.exr"))(still)
        with pytest.raises(statfilter.InvalidArgumentError, match="albedo pass"):
            statfilter.Filter(name)(still, inputs={"albedo": np.zeros((12, 8, 20, 3), np.float32)})


def test_noise_the_same_in_every_frame_is_a_warning(rng):
    """One noise pattern on every frame (a renderer's fixed seed): the presets warn, through Python's
    warnings, and report the figure; independent noise gives neither warning nor a low figure."""
    picture = np.linspace(0.2, 1.0, 40 * 48 * 3, dtype=np.float32).reshape(40, 48, 3)
    pattern = rng.gamma(16.0, 1.0 / 16.0, size=picture.shape).astype(np.float32)
    fixed = np.stack([picture * pattern * (1 + 0.05 * f) for f in range(6)]).astype(np.float32)
    f = statfilter.Filter("auto", quality="fast")
    with pytest.warns(statfilter.StatfilterWarning, match="the same in every frame"):
        f(fixed)
    assert f.results["noise_in_time"] < 0.5 and "seed" in f.results["warning"]
    independent = np.stack([picture * rng.gamma(16.0, 1.0 / 16.0, size=picture.shape) for _ in range(6)])
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", statfilter.StatfilterWarning)
        f(independent.astype(np.float32))
    assert f.results["noise_in_time"] > 0.8 and "warning" not in f.results
