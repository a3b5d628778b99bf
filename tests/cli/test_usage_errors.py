"""Usage errors exit 2 and name the option, with the nearest known one; --json gives numbers as numbers."""

import json
import re

import pytest

from conftest import run


@pytest.mark.parametrize("argv, message", [
    (["denoise", "in.####.exr", "out.####.exr", "--rnak", "3"], "unknown option --rnak (did you mean --rank?)"),
    (["denoise", "in.####.exr", "out.####.exr", "--qaulity", "high"], "unknown option --qaulity (did you mean --quality?)"),
    (["denoise", "in.####.exr", "out.####.exr", "--framse", "1-4"], "unknown option --framse (did you mean --frames?)"),
    (["denoise", "in.####.exr", "out.####.exr", "--jsno"], "unknown option --jsno (did you mean --json?)"),
    (["denoise", "in.####.exr", "out.####.exr", "--memory-mbb", "9"], "unknown option --memory-mbb (did you mean --memory-mb?)"),
    (["detect", "den.####.exr", "--thresold", "2"], "unknown option --thresold (did you mean --threshold?)"),
    (["detect", "den.####.exr", "--crop-paddin", "2"], "unknown option --crop-paddin (did you mean --crop-padding?)"),
    # Nothing near: no suggestion.
    (["denoise", "in.####.exr", "out.####.exr", "--zzzzzzzz", "1"], "unknown option --zzzzzzzz\n"),
])
def test_unknown_option_exits_2_with_a_suggestion(argv, message):
    proc = run(*argv, check_rc=2)
    assert message in proc.stderr, proc.stderr


def test_unknown_option_is_not_mistaken_for_a_missing_value():
    # Last on the line, so it has no value: still an unknown option, not "--foo needs a value".
    proc = run("info", "x.####.exr", "--foo", check_rc=2)
    assert "unknown option --foo" in proc.stderr and "needs a value" not in proc.stderr
    # info takes no filter parameters.
    assert "unknown option --rank" in run("info", "x.####.exr", "--rank", "3", check_rc=2).stderr
    # detect takes only the detect filter's.
    assert "unknown option --rank" in run("detect", "x.####.exr", "--rank", "3", check_rc=2).stderr
    assert "unknown option -x" in run("info", "x.####.exr", "-x", check_rc=2).stderr
    # A known option without its value is still named so.
    assert "--frames needs a value" in run("info", "x.####.exr", "--frames", check_rc=2).stderr


def test_parameters_are_options_with_dashes_or_underscores(small_sequence, tmp_path):
    for name in ("--memory-mb", "--memory_mb"):
        run("denoise", small_sequence / "noisy.####.exr", tmp_path / "o.####.exr", "--method", "pca", name, "256", "-q")


def test_denoise_json_results_are_numbers(small_sequence, tmp_path):
    report = json.loads(run("denoise", small_sequence / "noisy.####.exr", tmp_path / "d.####.exr", "--method",
                            "pca", "--rank", "2", "--json").stdout)
    results = report["results"]
    assert results["rank"] == 2 and isinstance(results["rank"], (int, float))
    assert results["nonfinite_repaired"] == 0 and not isinstance(results["nonfinite_repaired"], str)
    # auto keeps the chosen method's results as text in the library ("pca.rank": "1"): numbers here too,
    # and its words stay strings.
    report = json.loads(run("denoise", small_sequence / "noisy.####.exr", tmp_path / "a.####.exr", "--quality",
                            "fast", "--json").stdout)
    results = report["results"]
    assert isinstance(results["quality"], str) and isinstance(results["reason"], str)
    numbers = {k: v for k, v in results.items() if k.startswith("pca.")}
    assert numbers and all(isinstance(v, (int, float)) for v in numbers.values()), results
    for value in results.values():
        assert not (isinstance(value, str) and re.fullmatch(r"-?[0-9.]+(e[-+]?[0-9]+)?", value)), results


def test_unknown_command_is_named_with_the_nearest():
    assert "unknown command 'denoize' (did you mean denoise?)" in run("denoize", "a", "b", check_rc=2).stderr
    assert "unknown command 'frobnicate'\n" in run("frobnicate", check_rc=2).stderr


def test_help_documents_patterns_as_nuke_and_houdini():
    text = run("--help").stdout
    assert "Nuke and Houdini" in text and "follow oiiotool" not in text
