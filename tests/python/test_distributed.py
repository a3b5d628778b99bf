"""statfilter.distributed: the plan of tasks on a Dask LocalCluster of two worker processes, on a
shared-data scene, against the single-process run of the same options; and with a worker killed
in the middle of a task."""
import os
import signal
import subprocess
import sys
import threading

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
                         "balanced": {"quality": "balanced"}}.items():
        plan = sd.write_plan(src, str(tmp_path / name / "o.####.exr"), str(tmp_path / (name + ".json")), tiles=3, **params)
        kinds[name] = plan["kind"]
        assert plan["reason"]
    assert kinds == {"pca": "tiles", "fast": "tiles", "copy": "frames", "balanced": "shot"}


try:  # the Dask tests need the extra; the two above run without it
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
    ({"quality": "fast"}, False),  # fireflies judged per band: relMSE bound (docs/distributed.md)
    ({"method": "copy"}, True),
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
def test_a_worker_killed_mid_task_still_gives_the_same_complete_output(shared_data, tmp_path):
    src = scene(shared_data)
    single = tmp_path / "single" / "o.####.exr"
    statfilter.Filter("pca", firefly_z=0).run_files(src, str(single))
    marker = str(tmp_path / "killed")
    cluster = dask_distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                            dashboard_address=":0")
    try:
        with dask_distributed.Client(cluster) as c:
            c.register_plugin(kill_once_plugin(marker, "reconstruct"))
            out = tmp_path / "dask" / "o.####.exr"
            report = sd.denoise(src, str(out), client=c, method="pca", firefly_z=0, tile_rows=20, progress=False)
    finally:
        cluster.close()
    assert os.path.exists(marker)  # a worker did die
    assert len(report["hosts"]) >= 2
    assert len(list((tmp_path / "dask").glob("o.*.exr"))) == 32
    assert not [p for p in (tmp_path / "dask").iterdir() if p.name.startswith(".")]
    assert np.array_equal(frames(out), frames(single))
