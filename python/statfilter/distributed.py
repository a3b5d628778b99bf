"""Denoising a shot across machines: the plan of tasks (sf_plan_write) run on a Dask cluster.

``denoise(input, output, client=None, **params)`` writes the plan beside the output, submits one Dask
task per plan task with the plan's dependencies, and each worker runs its task through the C ABI
(sf_plan_run_task) on the files it sees: input, output and the plan's work directory must be on
storage every worker shares. The output is the same as ``Filter(method, **params).run_files(input,
output)`` (docs/distributed.md says where it is bit-identical and the bound where not).

``detect(denoised, noisy, mask=..., crops=..., client=None, **params)`` does the same for artifact
detection (sf_plan_write_detect_outputs): noise tasks per band, one tolerance task, detect tasks per
band, one masks task; the mask and score frames, crops JSON, degree map and its preview are
``statfilter detect``'s. Without a client it runs
the tasks here, one after another.

Dask is an optional extra (``pip install statfilter[dask]``); importing this module works without it,
calling denoise does not, nor detect with a client.
"""

from __future__ import annotations

import ctypes
import json
import os
import shutil
import sys
import tempfile
import time
from typing import Any, Dict, List, Optional, Union

from . import _capi
from .errors import InvalidArgumentError, check, error_for
from .filter import Filter, _require_input_files, _set_input_files
from .sequence import _read_options, _write_options

__all__ = ["denoise", "detect", "write_plan", "write_detect_plan", "run_task"]


def _memory_bytes(memory: Union[int, str, None]) -> int:
    if memory is None:
        return 0
    if isinstance(memory, str):
        size = ctypes.c_int64()
        status = _capi.lib.sf_memory_size_parse(_capi.encode(memory), ctypes.byref(size))
        if status != _capi.SF_OK:
            raise error_for(status, _capi.text(_capi.lib.sf_last_error()))
        return size.value
    return int(memory)


def _method(method: Optional[str], params: Dict[str, Any]) -> str:
    """The CLI's choice: --quality means auto; the default is auto (hybrid with a prefilter)."""
    if "quality" in params:
        if method not in (None, "auto"):
            raise ValueError("quality picks the method itself (it is a parameter of method auto); give one or the other")
        return "auto"
    if method:
        return method
    return "hybrid" if params.get("prefilter") else "auto"


def _plan_options(memory: Union[int, str, None], threads: int, tiles: int, tile_rows: int,
                  work_dir: Optional[str]) -> Any:
    """The run and plan option structs of a plan writer, and the encoded work folder they point at
    (keep it alive until the C call returns)."""
    run = _capi.sf_run_options()
    _capi.lib.sf_run_options_init(ctypes.byref(run))
    run.memory = _memory_bytes(memory)
    run.threads = int(threads)
    plan = _capi.sf_plan_options()
    _capi.lib.sf_plan_options_init(ctypes.byref(plan))
    plan.tiles, plan.tile_rows = int(tiles), int(tile_rows)
    work = _capi.encode_path(work_dir) if work_dir else None
    plan.work_dir = work
    return run, plan, work


def write_plan(input: str, output: str, plan_path: str, method: Optional[str] = None, tiles: int = 0,
               tile_rows: int = 0, frames_per_task: int = 0, work_dir: Optional[str] = None,
               memory: Union[int, str, None] = None, threads: int = 0, channels: Any = None, frames: Any = None,
               pixel_type: str = "half", compression: str = "zip", save: Optional[Dict[str, str]] = None,
               inputs: Optional[Dict[str, str]] = None, **params: Any) -> Dict[str, Any]:
    """Write the plan of tasks (as ``statfilter plan`` does) and return it (the parsed JSON).
    save: image results to write, {name: path} (``statfilter plan --save``: rank_map of
    error-threshold, alpha of balanced and the hybrid; a .png path gets the false-colour picture).
    inputs: the filter's named inputs as file patterns, e.g. {"vectors": "vector.####.exr"} (the
    renderer's passes, read by the tasks beside the input)."""
    _require_input_files(inputs or {})
    with Filter(_method(method, params), **params) as flt:
        _set_input_files(flt._live(), inputs or {}, lambda status: check(status, flt._live()))
        run, plan, work = _plan_options(memory, threads, tiles, tile_rows, work_dir)
        plan.frames_per_task = int(frames_per_task)
        saves = list((save or {}).items())
        keep_names = [(_capi.encode(n), _capi.encode_path(p)) for n, p in saves]
        images = (_capi.sf_image_output * max(1, len(saves)))()
        for i, (name, path) in enumerate(keep_names):
            images[i].name, images[i].path = name, path
        plan.images = ctypes.cast(images, ctypes.POINTER(_capi.sf_image_output))
        plan.image_count = len(saves)
        read, keep_read = _read_options(channels, frames)
        write, keep_write = _write_options(pixel_type, compression)
        status = _capi.lib.sf_plan_write(flt._live(), _capi.encode_path(input), ctypes.byref(read),
                                         _capi.encode_path(output), ctypes.byref(write), ctypes.byref(run),
                                         ctypes.byref(plan), _capi.encode_path(plan_path))
        check(status, flt._live())
        del keep_read, keep_write, work, keep_names, images
    with open(plan_path) as f:
        return json.load(f)


def write_detect_plan(denoised: str, noisy: Optional[str], plan_path: str, mask: Optional[str] = None,
                      crops: Optional[str] = None, tiles: int = 0, tile_rows: int = 0, work_dir: Optional[str] = None,
                      memory: Union[int, str, None] = None, threads: int = 0, channels: Any = None,
                      frames: Any = None, score: Optional[str] = None, degree_map: Optional[str] = None,
                      preview: Optional[str] = None, **params: Any) -> Dict[str, Any]:
    """Write the detect plan (as ``statfilter plan detect`` does) and return it (the parsed JSON).
    It writes any of mask (frame pattern), crops (JSON), score (frame pattern), degree_map and
    preview (one image each), at least one."""
    with Filter("detect", **params) as flt:
        run, plan, work = _plan_options(memory, threads, tiles, tile_rows, work_dir)
        read, keep_read = _read_options(channels, frames)
        outputs = _capi.sf_detect_outputs()
        _capi.lib.sf_detect_outputs_init(ctypes.byref(outputs))
        paths = {"mask": mask, "crops": crops, "score": score, "degree_map": degree_map, "preview": preview}
        for name, path in paths.items():
            setattr(outputs, name, _capi.encode_path(path) if path else None)
        status = _capi.lib.sf_plan_write_detect_outputs(
            flt._live(), _capi.encode_path(denoised), _capi.encode_path(noisy) if noisy else None, ctypes.byref(read),
            ctypes.byref(outputs), ctypes.byref(run), ctypes.byref(plan), _capi.encode_path(plan_path))
        check(status, flt._live())
        del keep_read, work
    with open(plan_path) as f:
        return json.load(f)


def run_task(plan_path: str, index: int, memory: Union[int, str, None] = None, threads: int = 0,
             *after: Any) -> Dict[str, Any]:
    """Run task `index` of a plan here (what a Dask worker calls); returns the task's report.
    `after` are the reports of the tasks it waits for (Dask passes them; unused)."""
    run = _capi.sf_run_options()
    _capi.lib.sf_run_options_init(ctypes.byref(run))
    run.memory = _memory_bytes(memory)
    run.threads = int(threads)
    started = time.time()
    status = _capi.lib.sf_plan_run_task(_capi.encode_path(plan_path), int(index), ctypes.byref(run))
    if status != _capi.SF_OK:
        raise error_for(status, "task %d of %s: %s" % (index, plan_path, _capi.text(_capi.lib.sf_last_error())))
    with open(plan_path) as f:
        plan = json.load(f)
    files = os.path.join(plan["work"], plan.get("run", ""))  # the plan's run (older plans: none)
    with open(os.path.join(files, "task-%d.json" % index)) as f:
        report = json.load(f)
    report["started"], report["finished"] = started, time.time()
    report["host"] = "%s:%d" % (os.uname().nodename, os.getpid())
    return report


def _progress_line(done: int, total: int, phase: str) -> None:
    sys.stderr.write("\rstatfilter: %d/%d tasks (%s)%s" % (done, total, phase, "\n" if done == total else ""))
    sys.stderr.flush()


def denoise(input: str, output: str, client: Any = None, method: Optional[str] = None, tiles: int = 0,
            tile_rows: int = 0, frames_per_task: int = 0, work_dir: Optional[str] = None,
            memory: Union[int, str, None] = None, threads: int = 1, channels: Any = None, frames: Any = None,
            pixel_type: str = "half", compression: str = "zip", retries: int = 3, progress: bool = True,
            keep_work: bool = False, save: Optional[Dict[str, str]] = None, inputs: Optional[Dict[str, str]] = None,
            **params: Any) -> Dict[str, Any]:
    """Denoise the EXR sequence `input` into `output` on a Dask cluster.

    client:    a dask.distributed Client; None = a LocalCluster of two single-threaded worker
               processes for the call.
    method, **params: as ``statfilter denoise`` (``quality="fast"`` is method auto).
    tiles, tile_rows, frames_per_task: how the plan cuts the shot (sf_plan_options).
    work_dir:  where the plan and its work files go, on storage every worker sees (default: a hidden
               directory beside the output, removed afterwards unless keep_work).
    memory, threads: each task's budget and threads (threads=1: one task per worker thread).
    retries:   times Dask reruns a task whose worker died (tasks are idempotent).
    save:      image results to write, {name: path}, each by the task that makes it (write_plan).
    inputs:    the renderer's passes as file patterns, {"vectors": ...} (write_plan).
    Returns the report: the plan's kind and reason, tasks, bytes read and written, seconds per phase,
    the method's results. The output frames appear as the assembly tasks finish, each at once.
    """
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError as exc:  # the optional extra
        raise ImportError("statfilter.distributed needs Dask: pip install statfilter[dask]") from exc
    out_dir = os.path.dirname(os.path.abspath(output))
    os.makedirs(out_dir, exist_ok=True)
    plan_dir = tempfile.mkdtemp(prefix=".statfilter-plan-", dir=work_dir or out_dir)
    plan_path = os.path.join(plan_dir, "plan.json")
    started = time.time()
    try:
        plan = write_plan(input, output, plan_path, method=method, tiles=tiles, tile_rows=tile_rows,
                          frames_per_task=frames_per_task, work_dir=os.path.join(plan_dir, "work"), memory=memory,
                          threads=threads, channels=channels, frames=frames, pixel_type=pixel_type,
                          compression=compression, save=save, inputs=inputs, **params)
    except BaseException:
        shutil.rmtree(plan_dir, ignore_errors=True)  # nothing was written but the empty plan directory
        raise
    planned = time.time()
    own_cluster = None
    if client is None:
        own_cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
        client = Client(own_cluster)
    try:
        reports = _run_on_client(client, as_completed, plan, plan_path, os.path.basename(plan_dir), memory, threads,
                                 retries, progress)
        finished = time.time()
        workers = _worker_count(client)
    finally:
        if own_cluster is not None:
            client.close()
            own_cluster.close()
    report = _report(plan, reports, planned - started, finished - planned, workers)
    if not keep_work:
        shutil.rmtree(plan_dir, ignore_errors=True)
    else:
        report["plan"] = plan_path
    return report


def _run_on_client(client: Any, as_completed: Any, plan: Dict[str, Any], plan_path: str, tag: str,
                   memory: Union[int, str, None], threads: int, retries: int, progress: bool) -> List[Dict[str, Any]]:
    """Submits one Dask task per plan task, each after the futures of the tasks its "after" list names
    (tasks of one phase with nothing between them run in parallel); returns the reports in task order."""
    futures: List[Any] = []
    for task in plan["tasks"]:
        after = [futures[i] for i in task["after"]]
        futures.append(client.submit(run_task, plan_path, task["index"], memory, threads, *after,
                                     key="statfilter-%s-%d-%s" % (task["phase"], task["index"], tag),
                                     pure=False, retries=retries))
    reports: List[Optional[Dict[str, Any]]] = [None] * len(futures)
    index_of = {f.key: i for i, f in enumerate(futures)}
    done = 0
    for future in as_completed(futures):
        i = index_of[future.key]
        reports[i] = future.result()  # raises the task's error
        done += 1
        if progress:
            _progress_line(done, len(futures), plan["tasks"][i]["phase"])
    return [r for r in reports if r is not None]


def _run_here(plan: Dict[str, Any], plan_path: str, memory: Union[int, str, None], threads: int,
              progress: bool) -> List[Dict[str, Any]]:
    """Runs every task of the plan in this process, in index order (each task's "after" tasks come
    before it in the plan); returns the reports in task order."""
    reports: List[Dict[str, Any]] = []
    for task in plan["tasks"]:
        if any(i >= task["index"] for i in task["after"]):
            raise InvalidArgumentError("%s: task %d waits for a later task" % (plan_path, task["index"]))
        reports.append(run_task(plan_path, task["index"], memory, threads))
        if progress:
            _progress_line(len(reports), len(plan["tasks"]), task["phase"])
    return reports


def detect(denoised: str, noisy: Optional[str], mask: Optional[str] = None, crops: Optional[str] = None,
           client: Any = None, tiles: int = 0, tile_rows: int = 0, work_dir: Optional[str] = None,
           memory: Union[int, str, None] = None, threads: Optional[int] = None, channels: Any = None,
           frames: Any = None, retries: int = 3, progress: bool = True, keep_work: bool = False,
           score: Optional[str] = None, degree_map: Optional[str] = None, preview: Optional[str] = None,
           **params: Any) -> Dict[str, Any]:
    """Detect the artifacts of the denoised EXR sequence `denoised` (made from the noisy render
    `noisy`; None = without it, as ``statfilter detect`` without --noisy) as a plan of tasks, writing
    the mask frames to `mask`, the crop windows (JSON) to `crops`, the estimated relMSE frames to
    `score`, the degree map to `degree_map` and its false-colour picture to `preview` (at least one).

    client:    a dask.distributed Client: the noise tasks run in parallel, then the tolerance task,
               the detect tasks in parallel, then the masks task. None = every task here, in order
               (Dask is not needed then).
    **params:  the detect filter's parameters, as ``statfilter detect`` (degree, delta, window,
               threshold, crop_padding, ...).
    tiles, tile_rows: the bands of rows (sf_plan_options; default 256 rows a band).
    work_dir:  where the plan and its work files go, on storage every worker sees (default: a hidden
               directory beside the first output given, in the order above; removed afterwards
               unless keep_work).
    memory, threads: each task's budget and threads (threads default: 1 on a client, one task per
               worker thread; every core here).
    retries:   times Dask reruns a task whose worker died (tasks are idempotent).
    Returns the report as ``denoise`` does (kind "detect"); its results are the detect filter's
    (flagged_fraction, window_count, delta, ...). Every output is that of ``statfilter detect
    DENOISED --noisy NOISY --mask MASK --crops CROPS --score ... --degree-map ... --preview ...`` with
    the same parameters.
    """
    outputs = [mask, crops, score, degree_map, preview]
    if not any(outputs):
        raise InvalidArgumentError("detect writes the mask, crops, score, degree_map or preview: give one")
    as_completed = None
    if client is not None:
        try:
            from distributed import as_completed
        except ImportError as exc:  # the optional extra
            raise ImportError("statfilter.distributed needs Dask: pip install statfilter[dask]") from exc
    if threads is None:
        threads = 1 if client is not None else 0
    out_dir = os.path.dirname(os.path.abspath(next(path for path in outputs if path)))
    os.makedirs(out_dir, exist_ok=True)
    plan_dir = tempfile.mkdtemp(prefix=".statfilter-plan-", dir=work_dir or out_dir)
    plan_path = os.path.join(plan_dir, "plan.json")
    started = time.time()
    try:
        plan = write_detect_plan(denoised, noisy, plan_path, mask=mask, crops=crops, tiles=tiles, tile_rows=tile_rows,
                                 work_dir=os.path.join(plan_dir, "work"), memory=memory, threads=threads,
                                 channels=channels, frames=frames, score=score, degree_map=degree_map,
                                 preview=preview, **params)
    except BaseException:
        shutil.rmtree(plan_dir, ignore_errors=True)  # nothing was written but the empty plan directory
        raise
    planned = time.time()
    if client is not None:
        reports = _run_on_client(client, as_completed, plan, plan_path, os.path.basename(plan_dir), memory, threads,
                                 retries, progress)
        workers = _worker_count(client)
    else:
        reports = _run_here(plan, plan_path, memory, threads, progress)
        workers = 1
    finished = time.time()
    report = _report(plan, reports, planned - started, finished - planned, workers)
    if not keep_work:
        shutil.rmtree(plan_dir, ignore_errors=True)
    else:
        report["plan"] = plan_path
    return report


def _worker_count(client: Any) -> int:
    """The workers the scheduler has now. Asked directly (nthreads is one call to the scheduler): the
    client's cached scheduler_info() is refreshed in the background with no per-worker entries, so it
    can say 0 workers in a race (seen in CI with two live workers)."""
    return len(client.nthreads())


def _report(plan: Dict[str, Any], reports: List[Dict[str, Any]], plan_seconds: float, run_seconds: float,
            workers: int) -> Dict[str, Any]:
    phases: Dict[str, Dict[str, Any]] = {}
    for r in reports:
        p = phases.setdefault(r["phase"], {"tasks": 0, "seconds": 0.0, "cpu_seconds": 0.0, "pixel_bytes_read": 0,
                                           "bytes_read": 0, "bytes_written": 0, "started": r["started"],
                                           "finished": r["finished"]})
        p["tasks"] += 1
        for k in ("seconds", "cpu_seconds", "pixel_bytes_read", "bytes_read", "bytes_written"):
            p[k] += r[k]
        p["started"], p["finished"] = min(p["started"], r["started"]), max(p["finished"], r["finished"])
    for p in phases.values():
        p["wall_seconds"] = p.pop("finished") - p.pop("started")
    results: Dict[str, Any] = {}
    for r in reports:
        if r["phase"] in ("reduce", "reconstruct", "frames", "shot", "analysis", "guides", "window", "tolerance", "masks"):
            for k, v in r["results"].items():
                results.setdefault(k, v)
    return {
        "kind": plan["kind"], "reason": plan["reason"], "tasks": len(reports), "workers": workers,
        "shape": plan["shape"], "plan_seconds": plan_seconds, "run_seconds": run_seconds,
        "pixel_bytes_read": sum(r["pixel_bytes_read"] for r in reports),
        "bytes_read": sum(r["bytes_read"] for r in reports),
        "bytes_written": sum(r["bytes_written"] for r in reports),
        "cpu_seconds": sum(r["cpu_seconds"] for r in reports),
        "phases": phases, "results": results, "hosts": sorted({r["host"] for r in reports}),
    }
