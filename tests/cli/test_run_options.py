"""denoise/copy --memory, --threads, --overwrite: the scheduler's options on the command line."""
import json

from conftest import run


def test_memory_too_small_is_refused_before_any_work_naming_a_size(small_sequence, tmp_path):
    out = tmp_path / "o.####.exr"
    proc = run("denoise", small_sequence / "noisy.####.exr", out, "--method", "pca", "--memory", "64K", check_rc=1)
    assert "--memory" in proc.stderr and "needs" in proc.stderr
    assert "basis" not in proc.stderr  # no progress line: refused before the first pass
    assert not list(tmp_path.glob("o.*.exr"))
    size = proc.stderr.split("give at least --memory ")[1].split()[0]
    run("denoise", small_sequence / "noisy.####.exr", out, "--method", "pca", "--memory", size, "--quiet")
    assert len(list(tmp_path.glob("o.*.exr"))) == 4


def test_threads_do_not_change_the_answer(small_sequence, tmp_path):
    outs = []
    for threads in ("1", "2"):
        out = tmp_path / f"t{threads}.####.exr"
        run("denoise", small_sequence / "noisy.####.exr", out, "--method", "error-threshold", "--threads", threads,
            "--float", "--quiet")
        outs.append(out)
    proc = run("compare", outs[0], outs[1], "--json")
    assert json.loads(proc.stdout)["rel_mse"] == 0


def test_bad_run_options_are_usage_errors(small_sequence, tmp_path):
    for args in (("--memory", "lots"), ("--threads", "-2"), ("--threads", "two")):
        proc = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "o.####.exr", *args, check_rc=2)
        assert args[0] in proc.stderr


def test_output_over_the_input_needs_overwrite(small_sequence, tmp_path):
    pattern = small_sequence / "noisy.####.exr"
    before = (small_sequence / "noisy.0001.exr").read_bytes()
    proc = run("denoise", pattern, pattern, "--method", "pca", check_rc=1)
    assert "overwrite" in proc.stderr
    assert (small_sequence / "noisy.0001.exr").read_bytes() == before
    run("denoise", pattern, pattern, "--method", "pca", "--overwrite", "--quiet")
    assert (small_sequence / "noisy.0001.exr").read_bytes() != before


def test_missing_output_directory_is_created(small_sequence, tmp_path):
    run("copy", small_sequence / "noisy.####.exr", tmp_path / "new" / "dir" / "c.####.exr", "--quiet")
    assert len(list((tmp_path / "new" / "dir").glob("c.*.exr"))) == 4


def test_sigterm_stops_the_run_and_leaves_no_file(sample_noisy, tmp_path):
    import signal
    import subprocess

    from conftest import CLI
    out = tmp_path / "o.####.exr"
    # A slow prefilter, so the run is still going when the signal comes.
    proc = subprocess.Popen([CLI, "denoise", str(sample_noisy), str(out), "--method", "pca", "--prefilter", "diffusion",
                             "--prefilter_params", "iterations=400", "--threads", "1"],
                            stderr=subprocess.PIPE, text=True)
    first = proc.stderr.readline()  # the first progress line: the work has started
    assert first.startswith("statfilter:"), first
    proc.send_signal(signal.SIGTERM)
    rest = proc.stderr.read()
    assert proc.wait(timeout=120) == 128 + signal.SIGTERM, first + rest
    assert "interrupted" in rest
    assert list(tmp_path.iterdir()) == []  # no frame, no temporary file, no lock


def test_every_output_frame_says_what_made_it(small_sequence, tmp_path):
    import subprocess

    from conftest import oiio_tool
    run("denoise", small_sequence / "noisy.####.exr", tmp_path / "p.####.exr", "--method", "pca", "--rank", "2", "--quiet")
    run("denoise", small_sequence / "noisy.####.exr", tmp_path / "b.####.exr", "--quality", "balanced", "--quiet")
    info = subprocess.run([oiio_tool("oiiotool"), "--info", "-v", str(tmp_path / "p.0003.exr")],
                          capture_output=True, text=True).stdout
    assert 'statfilter:filter: "pca"' in info and "rank=2" in info and "statfilter:version" in info
    info = subprocess.run([oiio_tool("oiiotool"), "--info", "-v", str(tmp_path / "b.0001.exr")],
                          capture_output=True, text=True).stdout
    assert "statfilter:method" in info and "statfilter:reason" in info  # what the preset picked, and why


def test_vectors_are_handed_to_the_hybrid_and_refused_by_others(small_sequence, tmp_path):
    import pytest

    from conftest import SHARED
    scene = SHARED / "fast_ball"
    if not scene.is_dir():
        pytest.skip("../shared/data is not here")
    noisy, vectors = scene / "spp0004" / "indirect.####.exr", scene / "aux" / "vector.####.exr"
    proc = run("denoise", noisy, tmp_path / "p.####.exr", "--method", "pca", "--vectors", vectors, check_rc=2)
    assert "--vectors" in proc.stderr and "does not use motion vectors" in proc.stderr
    proc = run("denoise", noisy, tmp_path / "h.####.exr", "--method", "hybrid", "--vectors", vectors, "--json")
    assert "vectors" in proc.stdout  # the hybrid says it aligned along the renderer's vectors


def test_noise_the_same_in_every_frame_is_a_warning_even_when_quiet(small_sequence, tmp_path):
    """A renderer with a fixed seed leaves the same noise on every frame: no temporal filter removes it,
    so the run says so on stderr (with --quiet too) and in its results, and still writes its frames."""
    import shutil
    fixed = tmp_path / "fixed"
    fixed.mkdir()
    for f in range(1, 5):  # frame 1's samples on every frame: one seed for the whole shot
        shutil.copy(small_sequence / "noisy.0001.exr", fixed / f"noisy.{f:04d}.exr")
    for quality in ("fast", "balanced"):
        out = tmp_path / quality / "o.####.exr"
        proc = run("denoise", fixed / "noisy.####.exr", out, "--quality", quality, "--quiet")
        assert "statfilter: warning: the noise is the same in every frame" in proc.stderr, proc.stderr
        assert "seed" in proc.stderr
        assert len(list(out.parent.glob("o.*.exr"))) == 4
    proc = run("denoise", fixed / "noisy.####.exr", tmp_path / "j.####.exr", "--json")
    results = json.loads(proc.stdout)["results"]
    assert results["noise_in_time"] < 0.5 and "the same in every frame" in results["warning"]
    # The shot as rendered, a seed per frame: no warning.
    proc = run("denoise", small_sequence / "noisy.####.exr", tmp_path / "s.####.exr", "--json")
    results = json.loads(proc.stdout)["results"]
    assert results["noise_in_time"] > 0.8 and "warning" not in results
    assert "warning" not in proc.stderr
