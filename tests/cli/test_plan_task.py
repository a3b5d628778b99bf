"""statfilter plan + statfilter task, one after another from a shell as a render farm runs them: the
same output as statfilter denoise with the same options (docs/distributed.md)."""
import json
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

from conftest import CLI, SAMPLE, SHARED, run

# (options, how the plan cuts the shot, kind, bit-identical). The firefly test judges each band of
# rows against that band's own spread, so with fireflies on (the default) tiles differ from one band
# in a few decisions; the bound is the streaming tests' (relMSE 1e-4 between the two).
CASES = [
    (["--method", "pca", "--firefly-z", "0"], ["--tiles", "3"], "tiles", True),
    (["--method", "pca"], ["--tiles", "1"], "tiles", True),
    (["--method", "pca"], ["--tiles", "3"], "tiles", False),
    (["--method", "error-threshold", "--firefly-z", "0"], ["--tile-rows", "16"], "tiles", True),
    (["--quality", "fast"], ["--tiles", "4"], "tiles", False),
    (["--method", "moving-basis", "--firefly-z", "0"], ["--tiles", "5"], "tiles", True),
    (["--method", "moving-basis", "--weights", "basis", "--half_width", "3"], ["--tiles", "3"], "tiles", False),
    (["--method", "copy"], ["--frames-per-task", "5"], "frames", True),
    (["--method", "diffusion"], [], "frames", True),
    (["--quality", "balanced"], [], "window", True),
    (["--quality", "balanced"], ["--frames-per-task", "5"], "window", True),
    (["--method", "hybrid", "--mc_half_width", "2"], ["--frames-per-task", "3"], "window", True),
    (["--quality", "balanced", "--postfilter", "diffusion"], ["--frames-per-task", "6"], "window", True),
    (["--quality", "balanced", "--prefilter", "diffusion"], [], "shot", True),
    # The renderer's passes read by the window plan's tasks: the analysis in bands, the windows by frame.
    (["--method", "hybrid", "--mc_half_width", "2", "--albedo", str(SAMPLE / "cornell_moving" / "aux" / "albedo.####.exr"),
      "--normal", str(SAMPLE / "cornell_moving" / "aux" / "normal.####.exr")], ["--frames-per-task", "5"], "window", True),
    # balanced aligns along the flow on the passes as the hybrid does.
    (["--quality", "balanced", "--albedo", str(SAMPLE / "cornell_moving" / "aux" / "albedo.####.exr"),
      "--normal", str(SAMPLE / "cornell_moving" / "aux" / "normal.####.exr")], ["--frames-per-task", "5"], "window", True),
]


def plan_files(plan):
    """Where the plan's tasks keep their files: its work directory, then its run."""
    p = json.loads(Path(plan).read_text())
    return Path(p["work"]) / p["run"]


def shell_run(plan):
    """Every task in plan order (which respects each task's 'after' list), from one shell script."""
    count = len(json.loads(plan.read_text())["tasks"])
    script = 'for i in $(seq 0 $(($2 - 1))); do "$3" task "$1" "$i" --quiet || exit 1; done'
    subprocess.run(["bash", "-c", script, "farm", str(plan), str(count), CLI], check=True, timeout=600)


@pytest.mark.parametrize("options,cut,kind,identical", CASES, ids=[" ".join(c[0] + c[1]) for c in CASES])
def test_plan_and_tasks_give_the_denoise_output(sample_noisy, tmp_path, options, cut, kind, identical):
    single = tmp_path / "single" / "o.####.exr"
    run("denoise", sample_noisy, single, *options, "--quiet")
    out = tmp_path / "farm" / "o.####.exr"
    plan = tmp_path / "plan.json"
    proc = run("plan", sample_noisy, out, *options, *cut, "-o", plan, "--quiet")
    tasks = json.loads(plan.read_text())
    assert tasks["kind"] == kind and int(proc.stdout) == len(tasks["tasks"])
    for task in tasks["tasks"]:
        assert all(a < task["index"] for a in task["after"])
    assert not (tmp_path / "farm" / "o.0001.exr").exists()  # the plan writes no frame
    shell_run(plan)
    assert len(list((tmp_path / "farm").glob("o.*.exr"))) == 32
    assert not [p for p in (tmp_path / "farm").iterdir() if p.name.startswith(".")]  # no staging left
    rel_mse = json.loads(run("compare", out, single, "--json").stdout)["rel_mse"]
    if identical:
        assert rel_mse == 0
    else:
        assert 0 <= rel_mse < 1e-4


def test_a_window_plan_follows_the_renderers_vectors(tmp_path):
    scene = SHARED / "fast_ball"
    vectors = scene / "aux" / "vector.####.exr"
    if not (scene / "aux" / "vector.0001.exr").exists():
        pytest.skip(f"no {vectors}")
    noisy = scene / "spp0016" / "indirect.####.exr"
    options = ["--quality", "balanced", "--vectors", vectors, "--frames", "1-12"]
    single = tmp_path / "single" / "o.####.exr"
    report = json.loads(run("denoise", noisy, single, *options, "--json").stdout)["results"]
    assert report["hybrid.motion_compensation"] == "the renderer's motion vectors"
    plan = tmp_path / "plan.json"
    run("plan", noisy, tmp_path / "farm" / "o.####.exr", *options, "--frames-per-task", "4", "-o", plan, "--quiet")
    written = json.loads(plan.read_text())
    assert written["kind"] == "window"
    assert written["front_end"]["inputs"] == {"vectors": str(vectors)}
    shell_run(plan)
    assert json.loads(run("compare", tmp_path / "farm" / "o.####.exr", single, "--json").stdout)["rel_mse"] == 0
    analysis = json.loads((plan_files(plan) / "task-0.json").read_text())
    assert analysis["phase"] == "analysis"
    assert analysis["results"]["hybrid.motion_compensation"] == "the renderer's motion vectors"
    # Vectors of another size: refused when the plan is written, before any task.
    bad = run("plan", noisy, tmp_path / "bad" / "o.####.exr", "--quality", "balanced", "--frames", "1-12",
              "--vectors", scene / "spp0016" / "indirect.####.exr", "-o", tmp_path / "bad.json", check_rc=1)
    assert "vectors" in bad.stderr and not (tmp_path / "bad.json").exists()


def test_rerunning_finished_tasks_changes_nothing(sample_noisy, tmp_path):
    out = tmp_path / "farm" / "o.####.exr"
    plan = tmp_path / "plan.json"
    run("plan", sample_noisy, out, "--method", "pca", "--tiles", "3", "-o", plan, "--quiet")
    shell_run(plan)
    first = {p.name: p.read_bytes() for p in (tmp_path / "farm").glob("o.*.exr")}
    # A farm that reruns a statistics task after the reduction, then everything after it: the
    # reduction reads each tile's partial once, by its tile, so nothing is counted twice.
    for i in (0, 3, 4, 7):
        run("task", plan, i, "--quiet")
    shell_run(plan)
    assert {p.name: p.read_bytes() for p in (tmp_path / "farm").glob("o.*.exr")} == first


def test_a_plan_made_again_in_the_same_work_directory_never_reads_the_old_plans_files(sample_noisy, tmp_path):
    out = tmp_path / "farm" / "o.####.exr"
    plan, work = tmp_path / "plan.json", tmp_path / "work"
    run("plan", sample_noisy, out, "--method", "pca", "--rank", "2", "--tiles", "3", "--work", work, "-o", plan, "--quiet")
    first = plan_files(plan)
    shell_run(plan)
    assert (first / "reduced.bin").exists() and (first / "tile-0.f32").exists()
    # The same options again: the same plan, the same run (its finished tasks' files stand).
    run("plan", sample_noisy, out, "--method", "pca", "--rank", "2", "--tiles", "3", "--work", work, "-o", plan, "--quiet")
    assert plan_files(plan) == first
    # Other options in the same work directory: another run. Run out of order, its tasks find none of
    # the first plan's files (the reduction, its tiles) and fail, naming theirs.
    run("plan", sample_noisy, out, "--method", "pca", "--rank", "4", "--tiles", "3", "--work", work, "-o", plan, "--quiet")
    assert plan_files(plan) != first and plan_files(plan).parent == first.parent
    tasks = json.loads(plan.read_text())["tasks"]
    reconstruct = next(t["index"] for t in tasks if t["phase"] == "reconstruct")
    assemble = next(t["index"] for t in tasks if t["phase"] == "assemble")
    proc = run("task", plan, reconstruct, "--quiet", check_rc=None)
    assert proc.returncode != 0 and str(plan_files(plan) / "reduced.bin") in proc.stderr
    proc = run("task", plan, assemble, "--quiet", check_rc=None)
    assert proc.returncode != 0 and "run the reconstruction tasks before the assembly" in proc.stderr
    shell_run(plan)
    single = tmp_path / "single" / "o.####.exr"
    run("denoise", sample_noisy, single, "--method", "pca", "--rank", "4", "--quiet")
    assert json.loads(run("compare", out, single, "--json").stdout)["rel_mse"] < 1e-4


def test_frames_rendered_again_make_another_run(sample_noisy, tmp_path):
    """The same options on frames written again at the same paths (a re-render) make another run:
    the scales can come out the same (always with --transform none), the files' sizes and times do not."""
    shot = tmp_path / "shot"
    shot.mkdir()
    source = Path(sample_noisy).parent
    for f in sorted(source.glob("*.exr")):
        shutil.copy(f, shot / f.name)
    pattern = shot / Path(sample_noisy).name
    plan, work = tmp_path / "plan.json", tmp_path / "work"
    args = ("plan", pattern, tmp_path / "o.####.exr", "--method", "pca", "--transform", "none", "--tiles", "3",
            "--work", work, "-o", plan, "--quiet")
    run(*args)
    first = plan_files(plan)
    run(*args)
    assert plan_files(plan) == first  # nothing changed: the same run
    frame = sorted(shot.glob("*.exr"))[5]
    data = frame.read_bytes()
    frame.write_bytes(data)  # written again: a new modification time
    os.utime(frame, ns=(frame.stat().st_atime_ns, frame.stat().st_mtime_ns + 1_000_000_000))
    run(*args)
    assert plan_files(plan) != first


def test_passes_rendered_again_make_another_run(sample_noisy, tmp_path):
    """A renderer's pass written again makes another run too, whether it is named by --albedo (a
    parameter) or --vectors (a named input): the window tasks must not take the old run's analysis."""
    aux = tmp_path / "aux"
    aux.mkdir()
    for f in sorted((SAMPLE / "cornell_moving" / "aux").glob("albedo.*.exr")):
        shutil.copy(f, aux / f.name)
    plan, work = tmp_path / "plan.json", tmp_path / "work"
    args = ("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "hybrid", "--albedo", aux / "albedo.####.exr",
            "--work", work, "-o", plan, "--quiet")
    run(*args)
    first = plan_files(plan)
    run(*args)
    assert plan_files(plan) == first
    frame = sorted(aux.glob("albedo.*.exr"))[3]
    os.utime(frame, ns=(frame.stat().st_atime_ns, frame.stat().st_mtime_ns + 1_000_000_000))
    run(*args)
    assert plan_files(plan) != first


def test_a_killed_task_leaves_no_frame_and_its_rerun_completes(sample_noisy, tmp_path):
    out = tmp_path / "farm" / "o.####.exr"
    plan = tmp_path / "plan.json"
    run("plan", sample_noisy, out, "--method", "pca", "--tiles", "3", "--frames-per-task", "32", "-o", plan, "--quiet")
    tasks = json.loads(plan.read_text())["tasks"]
    for task in tasks[:-1]:
        run("task", plan, task["index"], "--quiet")
    # The one assembly task, killed as soon as it has started: no output frame half-written.
    proc = subprocess.Popen([CLI, "task", str(plan), str(tasks[-1]["index"]), "--quiet"])
    time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    for p in (tmp_path / "farm").glob("o.*.exr"):
        assert p.stat().st_size > 0
        run("info", p)  # whole frames only
    run("task", plan, tasks[-1]["index"], "--quiet")
    single = tmp_path / "single" / "o.####.exr"
    run("plan", sample_noisy, single, "--method", "pca", "--tiles", "3", "-o", tmp_path / "again.json", "--quiet")
    shell_run(tmp_path / "again.json")
    assert json.loads(run("compare", out, single, "--json").stdout)["rel_mse"] == 0


def test_window_plan_reads_only_its_frames_and_reruns_change_nothing(sample_noisy, tmp_path):
    out = tmp_path / "farm" / "o.####.exr"
    plan = tmp_path / "plan.json"
    run("plan", sample_noisy, out, "--quality", "balanced", "--frames-per-task", "4", "-o", plan, "--quiet")
    tasks = json.loads(plan.read_text())
    assert tasks["window_half"] == 4
    # The analysis; the first passes in chunks after it; the guides after those; the frames in
    # chunks after the guides, each reading its frames and four either side.
    phases = [t["phase"] for t in tasks["tasks"]]
    assert phases == ["analysis"] + ["first_pass"] * 8 + ["guides"] + ["window"] * 8
    assert all(t["after"] == [0] for t in tasks["tasks"][1:9])
    assert tasks["tasks"][9]["after"] == list(range(1, 9))
    assert all(t["after"] == [9] for t in tasks["tasks"][10:])
    window = tasks["tasks"][11]
    assert window["frames"] == [4, 8] and window["read_frames"] == [0, 12]
    # A task before the phases it needs fails, naming what is missing, and writes nothing.
    for index, missing in ((1, "analysis task"), (9, "analysis task"), (11, "analysis task")):
        proc = run("task", plan, index, "--quiet", check_rc=None)
        assert proc.returncode != 0 and f"run the {missing} first" in proc.stderr
    assert not list((tmp_path / "farm").glob("o.*.exr"))
    shell_run(plan)
    work = plan_files(plan)
    frame_bytes = 160 * 120 * 3 * 4
    report = json.loads((work / "task-11.json").read_text())
    assert report["pixel_bytes_read"] == 12 * frame_bytes  # frames 0-11 of the input, once each
    report = json.loads((work / "task-2.json").read_text())
    assert report["pixel_bytes_read"] == 4 * frame_bytes  # a first pass: its own frames 4-7
    first = {p.name: p.read_bytes() for p in (tmp_path / "farm").glob("o.*.exr")}
    # The analysis run again (as a farm retries a task), then a window task: the same frames.
    for index in (0, 3, 9, 12):
        run("task", plan, index, "--quiet")
    assert not [p for p in work.iterdir() if ".tmp-" in p.name]  # no temporary left
    assert {p.name: p.read_bytes() for p in (tmp_path / "farm").glob("o.*.exr")} == first


def test_plan_checks_before_any_work(sample_noisy, tmp_path):
    proc = run("plan", sample_noisy, tmp_path / "o.exr", "--method", "pca", "-o", tmp_path / "p.json", check_rc=1)
    assert "frame token" in proc.stderr and not (tmp_path / "p.json").exists()
    proc = run("plan", sample_noisy, sample_noisy, "--method", "pca", "--overwrite", "-o", tmp_path / "p.json", check_rc=2)
    assert "overwrite" in proc.stderr
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "pca", check_rc=2)
    assert "-o PLAN" in proc.stderr
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--tiles", "2", "--tile-rows", "3", "-o", tmp_path / "p.json",
               check_rc=2)
    assert "not both" in proc.stderr
    # Image results the method does not have, or that the plan's tasks do not make, or written over
    # the output: refused before the plan is written.
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "pca", "--save", "alpha=a.exr", "-o",
               tmp_path / "p.json", check_rc=2)
    assert "method pca has no image result 'alpha'" in proc.stderr and not (tmp_path / "p.json").exists()
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--quality", "fast", "--save", "alpha=a.exr", "-o",
               tmp_path / "p.json", check_rc=1)
    assert "a 'tiles' plan's tasks do not make the image result 'alpha'" in proc.stderr
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "error-threshold", "--save",
               f"rank_map={tmp_path / 'r.exr'},rank_map={tmp_path / 'r.png'}", "-o", tmp_path / "p.json", check_rc=1)
    assert "'rank_map' is asked for twice" in proc.stderr
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--save", f"alpha={tmp_path / 'o.####.exr'}", "-o",
               tmp_path / "p.json", check_rc=1)
    assert "would be written to the plan's output" in proc.stderr and not (tmp_path / "p.json").exists()
    proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "motion", "--save", f"beta={tmp_path / 'b.exr'}",
               "-o", tmp_path / "p.json", check_rc=1)
    assert "image result 'beta'" in proc.stderr and "no frame token" in proc.stderr
    for frame in (tmp_path / "o.0002.exr", str(sample_noisy).replace("####", "0003")):  # an output or input frame
        proc = run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "error-threshold", "--save",
                   f"rank_map={frame}", "-o", tmp_path / "p.json", check_rc=1)
        assert "is a frame of" in proc.stderr and not (tmp_path / "p.json").exists()
    run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "pca", "-o", tmp_path / "p.json", "--quiet")
    proc = run("task", tmp_path / "p.json", 99, check_rc=1)
    assert "task 99 is not in the plan" in proc.stderr
    tasks = json.loads((tmp_path / "p.json").read_text())["tasks"]
    phase = {t["phase"]: t["index"] for t in reversed(tasks)}  # each phase's first task
    proc = run("task", tmp_path / "p.json", phase["reconstruct"], check_rc=1)  # before its reduction
    assert "reduced.bin" in proc.stderr
    proc = run("task", tmp_path / "p.json", phase["assemble"], check_rc=1)
    assert "run the reconstruction tasks before the assembly" in proc.stderr
    assert not list(tmp_path.glob("o.*.exr")) and not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


# (options, how the plan cuts the shot, the image results, the phase that writes them)
IMAGE_CASES = [
    (["--method", "error-threshold", "--firefly-z", "0"], ["--tile-rows", "16"], ["rank_map"], "images"),
    (["--method", "error-threshold"], ["--tiles", "1"], ["rank_map"], "images"),
    (["--quality", "balanced"], ["--frames-per-task", "8"], ["alpha"], "analysis"),
    (["--method", "motion"], [], ["alpha", "beta"], "shot"),
]


@pytest.mark.parametrize("options,cut,names,phase", IMAGE_CASES, ids=[" ".join(c[0] + c[1]) for c in IMAGE_CASES])
def test_plan_writes_image_results_as_denoise_does(sample_noisy, tmp_path, options, cut, names, phase):
    # Each result as EXRs and as pictures from one denoise (a frame token: beta has a frame per frame).
    single_saves = ",".join(f"{n}={tmp_path / 'single' / n}.####.exr,{n}={tmp_path / 'single' / n}_view.####.png"
                            for n in names)
    run("denoise", sample_noisy, tmp_path / "single" / "o.####.exr", *options, "--save", single_saves, "--quiet")
    plan = tmp_path / "plan.json"
    farm_saves = ",".join(f"{n}={tmp_path / 'farm' / n}.####.exr" for n in names)
    run("plan", sample_noisy, tmp_path / "farm" / "o.####.exr", *options, *cut, "--save", farm_saves, "-o", plan, "--quiet")
    tasks = json.loads(plan.read_text())
    assert [i["name"] for i in tasks["images"]] == names
    shell_run(plan)
    for n in names:
        single = sorted(p.name for p in (tmp_path / "single").glob(f"{n}.*.exr"))
        assert single and sorted(p.name for p in (tmp_path / "farm").glob(f"{n}.*.exr")) == single
        for name in single:
            assert _mask_bytes(tmp_path / "farm" / name) == _mask_bytes(tmp_path / "single" / name), name
    reports = [json.loads((plan_files(plan) / f"task-{t['index']}.json").read_text()) for t in tasks["tasks"]]
    writers = [t["phase"] for t, r in zip(tasks["tasks"], reports)
               if any(f"/{n}." in o for o in r["outputs"] for n in names)]
    assert writers == [phase]
    # The first result as pictures, from a second plan.
    pictures = tmp_path / "farm2" / f"{names[0]}_view.####.png"
    run("plan", sample_noisy, tmp_path / "farm2" / "o.####.exr", *options, *cut, "--save", f"{names[0]}={pictures}", "-o",
        tmp_path / "plan2.json", "--quiet")
    shell_run(tmp_path / "plan2.json")
    single = sorted((tmp_path / "single").glob(f"{names[0]}_view.*.png"))
    assert single and [p.read_bytes() for p in single] == [
        (tmp_path / "farm2" / p.name).read_bytes() for p in single]


def test_farm_submission_scripts_lay_the_phases_out(sample_noisy, tmp_path):
    import sys
    from pathlib import Path
    farm = Path(__file__).resolve().parents[2] / "scripts" / "farm"
    plan = tmp_path / "plan.json"
    run("plan", sample_noisy, tmp_path / "o.####.exr", "--method", "pca", "--tiles", "3", "-o", plan, "--quiet")
    cue = subprocess.run([sys.executable, farm / "opencue_submit.py", plan, "--dry-run"], capture_output=True, text=True,
                         check=True).stdout.splitlines()
    assert [line.split()[1:4] for line in cue] == [["statistics", "frames", "0-2"], ["reduce", "frames", "3-3"],
                                                  ["reconstruct", "frames", "4-6"], ["assemble", "frames", "7-10"]]
    deadline = subprocess.run([sys.executable, farm / "deadline_submit.py", plan, "--dry-run"], capture_output=True,
                              text=True, check=True).stdout
    assert deadline.count("Plugin=CommandLine") == 4 and deadline.count("JobDependencies=") == 3
    assert "<STARTFRAME>" in deadline
    # The rank map's task waits for the reconstructions, two phases back: still a chain of phases.
    ranks = tmp_path / "ranks.plan.json"
    run("plan", sample_noisy, tmp_path / "r.####.exr", "--method", "error-threshold", "--tiles", "3", "--save",
        f"rank_map={tmp_path / 'ranks.exr'}", "-o", ranks, "--quiet")
    cue = subprocess.run([sys.executable, farm / "opencue_submit.py", ranks, "--dry-run"], capture_output=True, text=True,
                         check=True).stdout.splitlines()
    assert [line.split()[1] for line in cue] == ["statistics", "reduce", "reconstruct", "assemble", "images"]


def _mask_bytes(path):
    """A mask frame's bytes without the header's capDate (the writer's clock)."""
    import re
    return re.sub(rb"capDate\x00string\x00....[0-9: ]{19}", b"", path.read_bytes(), flags=re.S)


@pytest.mark.parametrize("cut", [["--tiles", "3"], ["--tile-rows", "7"], ["--tiles", "1"]], ids=" ".join)
def test_detect_plan_and_tasks_give_the_detect_outputs(sample_noisy, tmp_path, cut):
    den = tmp_path / "den.####.exr"
    run("denoise", sample_noisy, den, "--method", "pca", "--firefly-z", "0", "--quiet")

    def outputs(where):
        return ["--mask", tmp_path / where / "m.####.exr", "--crops", tmp_path / (where + ".json"),
                "--score", tmp_path / where / "s.####.exr", "--degree-map", tmp_path / where / "degree.exr",
                "--preview", tmp_path / where / "degree.png"]

    run("detect", den, "--noisy", sample_noisy, *outputs("single"), "--quiet")
    plan = tmp_path / "detect.plan.json"
    proc = run("plan", "detect", den, "--noisy", sample_noisy, *outputs("farm"), *cut, "-o", plan, "--quiet")
    tasks = json.loads(plan.read_text())
    assert tasks["kind"] == "detect" and int(proc.stdout) == len(tasks["tasks"])
    assert not (tmp_path / "farm.json").exists() and not list((tmp_path / "farm").iterdir())  # the plan writes nothing
    shell_run(plan)
    assert (tmp_path / "farm.json").read_bytes() == (tmp_path / "single.json").read_bytes()
    single = sorted((tmp_path / "single").glob("*.exr"))
    assert len(single) == 32 + 32 + 1  # mask and score frames, the degree map
    for p in single:
        assert _mask_bytes(tmp_path / "farm" / p.name) == _mask_bytes(p), p.name
    assert (tmp_path / "farm" / "degree.png").read_bytes() == (tmp_path / "single" / "degree.png").read_bytes()
    assert not [p for p in (tmp_path / "farm").iterdir() if p.name.startswith(".")]


def test_detect_plan_of_the_degree_map_alone(sample_noisy, tmp_path):
    """A plan that writes only the maps: no mask or score frames, no staging left, the same map."""
    den = tmp_path / "den.####.exr"
    run("denoise", sample_noisy, den, "--method", "pca", "--firefly-z", "0", "--quiet")
    run("detect", den, "--noisy", sample_noisy, "--degree-map", tmp_path / "single.exr", "--quiet")
    plan = tmp_path / "p.json"
    run("plan", "detect", den, "--noisy", sample_noisy, "--degree-map", tmp_path / "maps" / "farm.exr",
        "--tiles", "2", "-o", plan, "--quiet")
    shell_run(plan)
    assert sorted(p.name for p in (tmp_path / "maps").iterdir()) == ["farm.exr"]
    assert _mask_bytes(tmp_path / "maps" / "farm.exr") == _mask_bytes(tmp_path / "single.exr")


def test_detect_plan_usage_errors(sample_noisy, tmp_path):
    assert "plan detect DENOISED" in run("plan", "--help").stdout
    assert "--crops" in run("plan", "detect", "--help").stdout
    err = run("plan", "detect", sample_noisy, "-o", tmp_path / "p.json", check_rc=2).stderr
    assert "--mask" in err and "--degree-map" in err and "Traceback" not in err
    err = run("plan", "detect", sample_noisy, "--noisy", sample_noisy, "--score", tmp_path / "s.####.exr",
              "--mask", tmp_path / "s.####.exr", "-o", tmp_path / "p.json", check_rc=None)
    assert err.returncode != 0 and "both" in err.stderr and not (tmp_path / "p.json").exists()
    err = run("plan", "detect", sample_noisy, "--noisy", sample_noisy, "--crops", tmp_path / "c.json",
              "--degree", "40", "-o", tmp_path / "p.json", check_rc=None)
    assert err.returncode != 0 and "degree" in err.stderr and not (tmp_path / "p.json").exists()
