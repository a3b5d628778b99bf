"""statfilter.distributed: the plan of tasks on a Dask LocalCluster of two worker processes, on a
shared-data scene, against the single-process run of the same options; and with a worker killed
in the middle of a task. The detect plan on the shipped sample against `statfilter detect`."""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import statfilter
from statfilter import distributed as sd


def scene(shared_data):
    return os.path.join(shared_data, "cornell_moving", "spp0016", "indirect.####.exr")


def frames(pattern):
    return np.asarray(statfilter.read_sequence(str(pattern)))


def test_the_package_works_without_dask():
    # Dask hidden: the module imports, and only denoise says what is missing.
    code = ("import sys; sys.modules['distributed'] = None; sys.modules['dask'] = None\n"
            "import statfilter, statfilter.distributed as sd\n"
            "try:\n    sd.denoise('in.####.exr', 'out.####.exr')\nexcept ImportError as e:\n    print(e)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=os.environ)
    assert proc.returncode == 0, proc.stderr
    assert "pip install statfilter[dask]" in proc.stdout


def test_plans_say_what_is_tiled(shared_data, tmp_path):
    src = scene(shared_data)
    kinds = {}
    for name, params in {"pca": {"method": "pca"}, "fast": {"quality": "fast"}, "copy": {"method": "copy"},
                         "balanced": {"quality": "balanced"}, "moving": {"method": "moving-basis"}}.items():
        plan = sd.write_plan(src, str(tmp_path / name / "o.####.exr"), str(tmp_path / (name + ".json")), tiles=3, **params)
        kinds[name] = plan["kind"]
        assert plan["reason"]
    assert kinds == {"pca": "tiles", "fast": "tiles", "copy": "frames", "balanced": "window", "moving": "tiles"}


def test_a_plan_reads_the_renderers_vectors_from_files(shared_data, tmp_path):
    src = scene(shared_data)
    vectors = os.path.join(shared_data, "cornell_moving", "aux", "vector.####.exr")
    if not os.path.exists(statfilter.pattern_format(vectors, 1)):
        pytest.skip("no %s" % vectors)
    plan = sd.write_plan(src, str(tmp_path / "o.####.exr"), str(tmp_path / "p.json"), quality="balanced",
                         inputs={"vectors": vectors})
    assert plan["kind"] == "window" and plan["front_end"]["inputs"] == {"vectors": os.path.abspath(vectors)}
    # Vectors of another size are refused when the plan is written.
    with pytest.raises(statfilter.InvalidArgumentError, match="vectors"):
        sd.write_plan(src, str(tmp_path / "b.####.exr"), str(tmp_path / "b.json"), quality="balanced",
                      inputs={"vectors": src})
    assert not (tmp_path / "b.json").exists()


def test_a_plan_writes_the_rank_map_the_single_run_makes(shared_data, tmp_path):
    src = scene(shared_data)
    results = statfilter.Filter("error-threshold", firefly_z=0).run_files(src, str(tmp_path / "single" / "o.####.exr"))
    ranks = tmp_path / "farm" / "ranks.exr"
    plan_path = str(tmp_path / "plan.json")
    plan = sd.write_plan(src, str(tmp_path / "farm" / "o.####.exr"), plan_path, method="error-threshold", firefly_z=0,
                         tile_rows=40, save={"rank_map": str(ranks)})
    assert plan["images"] == [{"name": "rank_map", "path": str(ranks)}] and plan["tasks"][-1]["phase"] == "images"
    for task in plan["tasks"]:
        sd.run_task(plan_path, task["index"])
    assert np.array_equal(frames(ranks), np.asarray(results["rank_map"]).reshape(frames(ranks).shape))
    with pytest.raises(statfilter.InvalidArgumentError, match="has no image result 'alpha'"):
        sd.write_plan(src, str(tmp_path / "x" / "o.####.exr"), str(tmp_path / "x.json"), method="pca",
                      save={"alpha": str(tmp_path / "a.exr")})


try:  # the Dask tests need the extra; the tests above run without it
    import distributed as dask_distributed
except ImportError:
    dask_distributed = None
needs_dask = pytest.mark.skipif(dask_distributed is None,
                                reason="dask.distributed is not installed (pip install statfilter[dask])")


@pytest.fixture(scope="module")
def client():
    cluster = dask_distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                            dashboard_address=":0")
    c = dask_distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


@needs_dask
@pytest.mark.parametrize("params,identical", [
    ({"method": "pca", "firefly_z": 0}, True),
    ({"method": "error-threshold", "firefly_z": 0}, True),
    ({"method": "moving-basis", "firefly_z": 0}, True),  # the operator M made from the reduced Gram
    ({"quality": "fast"}, False),  # fireflies judged per band: relMSE bound (docs/distributed.md)
    ({"method": "copy"}, True),
    ({"quality": "balanced"}, True),  # the analysis, then windows of frames
])
def test_two_workers_match_the_single_process_run(shared_data, tmp_path, client, params, identical):
    src = scene(shared_data)
    single = tmp_path / "single" / "o.####.exr"
    p = dict(params)
    method = "auto" if "quality" in p else p.pop("method")
    statfilter.Filter(method, **p).run_files(src, str(single))
    out = tmp_path / "dask" / "o.####.exr"
    report = sd.denoise(src, str(out), client=client, tile_rows=40, frames_per_task=8, progress=False, **params)
    assert report["workers"] == 2 and report["tasks"] > 1
    assert len(list((tmp_path / "dask").glob("o.*.exr"))) == 32
    a, b = frames(out), frames(single)
    if identical:
        assert np.array_equal(a, b)
    else:
        assert statfilter.compare(a, b)["rel_mse"] < 1e-4
    if report["kind"] == "tiles":
        assert set(report["phases"]) == {"statistics", "reduce", "reconstruct", "assemble"}
        assert report["phases"]["statistics"]["tasks"] == 3
        assert "rank" in report["results"] or "mean_rank" in report["results"]
    if report["kind"] == "window":
        assert set(report["phases"]) == {"analysis", "first_pass", "guides", "window"}
        assert report["phases"]["window"]["tasks"] == 4
        assert report["results"]["method"].startswith("hybrid") and report["results"]["motion_fraction"] > 0


def kill_once_plugin(marker, phase):
    class KillOnce(dask_distributed.WorkerPlugin):
        """Kills its worker's process 20 ms into the first task of `phase` any worker starts."""

        def transition(self, key, start, finish, **kwargs):
            if finish != "executing" or ("-%s-" % phase) not in str(key):
                return
            try:
                os.close(os.open(marker, os.O_CREAT | os.O_EXCL))
            except FileExistsError:
                return
            threading.Timer(0.02, lambda: os.kill(os.getpid(), signal.SIGKILL)).start()

    return KillOnce()  # defined here, so it travels to the workers by value


@needs_dask
@pytest.mark.parametrize("params,phase", [
    ({"method": "pca", "firefly_z": 0, "tile_rows": 20}, "reconstruct"),
    ({"quality": "balanced", "frames_per_task": 8}, "window"),
])
def test_a_worker_killed_mid_task_still_gives_the_same_complete_output(shared_data, tmp_path, params, phase):
    src = scene(shared_data)
    single = tmp_path / "single" / "o.####.exr"
    p = {k: v for k, v in params.items() if k not in ("tile_rows", "frames_per_task")}
    method = "auto" if "quality" in p else p.pop("method")
    statfilter.Filter(method, **p).run_files(src, str(single))
    marker = str(tmp_path / "killed")
    cluster = dask_distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                            dashboard_address=":0")
    try:
        with dask_distributed.Client(cluster) as c:
            c.register_plugin(kill_once_plugin(marker, phase))
            out = tmp_path / "dask" / "o.####.exr"
            report = sd.denoise(src, str(out), client=c, progress=False, **params)
    finally:
        cluster.close()
    assert os.path.exists(marker)  # a worker did die
    assert len(report["hosts"]) >= 2
    assert len(list((tmp_path / "dask").glob("o.*.exr"))) == 32
    assert not [p for p in (tmp_path / "dask").iterdir() if p.name.startswith(".")]
    assert np.array_equal(frames(out), frames(single))


SAMPLE = Path(__file__).resolve().parents[2] / "sample" / "cornell_moving" / "spp0004" / "indirect.####.exr"


def cli():
    """The command-line tool (ctest sets STATFILTER_CLI), or skip."""
    path = os.environ.get("STATFILTER_CLI") or shutil.which("statfilter")
    if not path:
        pytest.skip("the statfilter command-line tool is not here (STATFILTER_CLI)")
    return path


def mask_bytes(path):
    """A mask frame's bytes without the header's capDate (the writer's clock)."""
    return re.sub(rb"capDate\x00string\x00....[0-9: ]{19}", b"", path.read_bytes(), flags=re.S)


@pytest.fixture(scope="module")
def sample_detect(tmp_path_factory):
    """The sample denoised (pca), and `statfilter detect` on it in one process: (dir, denoised pattern)."""
    tool = cli()
    d = tmp_path_factory.mktemp("detect")
    den = d / "den" / "d.####.exr"
    statfilter.Filter("pca", firefly_z=0).run_files(str(SAMPLE), str(den))
    subprocess.run([tool, "detect", str(den), "--noisy", str(SAMPLE), "--mask", str(d / "single" / "m.####.exr"),
                    "--crops", str(d / "single.json"), "--degree-map", str(d / "single" / "degree.exr"),
                    "--preview", str(d / "single" / "degree.png"), "--quiet"], check=True, timeout=300)
    return d, den


def assert_same_as_single(d, out, crops):
    single = sorted((d / "single").glob("m.*.exr"))
    assert len(single) == 32
    assert sorted(p.name for p in out.glob("m.*.exr")) == [p.name for p in single]
    for p in single:
        assert mask_bytes(out / p.name) == mask_bytes(p), p.name
    assert crops.read_bytes() == (d / "single.json").read_bytes()
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


@needs_dask
def test_detect_on_two_workers_gives_statfilter_detects_mask_and_crops(sample_detect, client):
    d, den = sample_detect
    out = d / "dask"
    report = sd.detect(str(den), str(SAMPLE), mask=str(out / "m.####.exr"), crops=str(d / "dask.json"),
                       client=client, tile_rows=40, progress=False)
    assert report["kind"] == "detect" and report["workers"] == 2
    assert {p: v["tasks"] for p, v in report["phases"].items()} == {"noise": 3, "tolerance": 1, "detect": 3, "masks": 1}
    assert report["tasks"] == 8 and report["shape"]["frames"] == 32
    assert_same_as_single(d, out, d / "dask.json")
    windows = json.loads((d / "single.json").read_text())
    assert report["results"]["window_count"] == sum(len(f["windows"]) for f in windows["frames"])
    assert 0 < report["results"]["flagged_fraction"] < 1 and report["results"]["source"] == "residual"


def test_detect_without_a_client_runs_here(sample_detect, capsys):
    d, den = sample_detect
    out = d / "here"
    report = sd.detect(str(den), str(SAMPLE), mask=str(out / "m.####.exr"), crops=str(d / "here.json"), tiles=2,
                       degree_map=str(out / "degree.exr"), preview=str(out / "degree.png"))
    assert report["workers"] == 1 and report["tasks"] == 2 + 1 + 2 + 1
    assert_same_as_single(d, out, d / "here.json")
    assert mask_bytes(out / "degree.exr") == mask_bytes(d / "single" / "degree.exr")
    assert (out / "degree.png").read_bytes() == (d / "single" / "degree.png").read_bytes()
    assert "statfilter: 6/6 tasks (masks)" in capsys.readouterr().err
    assert not [p for p in d.iterdir() if p.name.startswith(".statfilter-plan-")]


def test_detect_usage_errors(tmp_path):
    missing = str(tmp_path / "nowhere" / "d.####.exr")
    with pytest.raises(statfilter.NotFoundError, match="no files match '%s'" % re.escape(missing)):
        sd.detect(missing, str(SAMPLE), crops=str(tmp_path / "c.json"), progress=False)
    with pytest.raises(statfilter.InvalidArgumentError, match="mask, crops, score, degree_map or preview"):
        sd.detect(str(SAMPLE), str(SAMPLE))
    with pytest.raises(statfilter.InvalidArgumentError, match="degree"):
        sd.detect(str(SAMPLE), str(SAMPLE), crops=str(tmp_path / "c.json"), degree=40, progress=False)
    assert not (tmp_path / "c.json").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".statfilter-plan-")]


def test_denoise_that_cannot_plan_leaves_no_plan_directory(tmp_path):
    pytest.importorskip("distributed")
    missing = str(tmp_path / "nowhere" / "n.####.exr")
    with pytest.raises(statfilter.NotFoundError, match="no files match '%s'" % re.escape(missing)):
        sd.denoise(missing, str(tmp_path / "out" / "d.####.exr"), progress=False)
    with pytest.raises(statfilter.InvalidArgumentError):
        sd.denoise(str(SAMPLE), str(tmp_path / "out" / "d.####.exr"), method="pca", rank=-3, progress=False)
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".statfilter-plan-")]
