"""statfilter.compare: the project's error metrics through sf_sequence_compare."""

import numpy as np
import pytest

import statfilter
from statfilter import _capi


@pytest.fixture
def needs_compare():
    if not _capi.has("sf_sequence_compare"):
        pytest.skip("the library has no sf_sequence_compare")


def test_identical_sequences(needs_compare, rng):
    ref = rng.random((6, 8, 10, 3)).astype(np.float32)
    m = statfilter.compare(ref, ref)
    assert set(m) == {n for n, _ in _capi.sf_comparison._fields_} - {"struct_size"}
    assert m["rel_mse"] == 0.0
    assert m["flicker"] == 0.0


def test_noise_increases_error(needs_compare, rng):
    ref = rng.random((6, 8, 10, 3)).astype(np.float32)
    small = statfilter.compare(ref + 0.01 * rng.standard_normal(ref.shape).astype(np.float32), ref)
    large = statfilter.compare(ref + 0.1 * rng.standard_normal(ref.shape).astype(np.float32), ref)
    assert 0 < small["rel_mse"] < large["rel_mse"]
    assert small["psnr"] > large["psnr"]
    # Strided views give the same numbers as contiguous copies.
    view = statfilter.compare(ref[:, ::2], ref[:, ::2])
    assert view["rel_mse"] == 0.0


def test_shape_mismatch(needs_compare, rng):
    with pytest.raises(statfilter.InvalidArgumentError):
        statfilter.compare(np.zeros((2, 3, 4, 3), np.float32), np.zeros((2, 3, 4, 1), np.float32))
