"""statfilter report: the review page through the CLI (which starts the Python package on it)."""
import os

from conftest import SAMPLE, run


def python_env(**extra):
    """The environment for a run that starts Python on the package: under the sanitizers the ASan
    runtime preloaded for the uninstrumented interpreter (and leak checks off: CPython keeps memory)."""
    env = dict(os.environ, **extra)
    preload = os.environ.get("STATFILTER_SANITIZER_PRELOAD")
    if preload:
        env["LD_PRELOAD"] = preload
        env["ASAN_OPTIONS"] = "detect_leaks=0"
    return env


def test_report_on_the_shipped_sample(sample_noisy, tmp_path):
    den = tmp_path / "den.####.exr"
    run("denoise", sample_noisy, den, "--frames", "1-8", "--quality", "fast", "-q")
    ref = SAMPLE / "cornell_moving" / "ref" / "indirect.####.exr"
    page = tmp_path / "report.html"
    proc = run("report", sample_noisy, den, "--ref", ref, "--frames", "1-8", "--no-maps", "-o", page, env=python_env())
    assert "statfilter report: wrote" in proc.stdout
    html = page.read_text(encoding="utf-8")
    for part in ("Before and after", "What the pipeline chose", "Error per frame", "relMSE"):
        assert part in html, part


def test_report_usage_errors_exit_2_and_a_missing_python_is_named(sample_noisy, tmp_path):
    bad = run("report", sample_noisy, check_rc=2, env=python_env())
    assert "statfilter report" in bad.stderr and "-o" in bad.stderr
    missing = run("report", sample_noisy, sample_noisy, "-o", tmp_path / "r.html", check_rc=1,
                  env=python_env(STATFILTER_PYTHON=str(tmp_path / "no-python")))
    assert "no-python" in missing.stderr and "STATFILTER_PYTHON" in missing.stderr
