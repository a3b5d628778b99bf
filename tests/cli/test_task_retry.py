"""A plan task killed mid-way (SIGKILL, as a render farm preempts a task) and run again gives the
outputs of an uninterrupted run, and what it leaves when killed is never a partial file under a name
a later task reads or that is a final output (docs/distributed.md, "Files and faults")."""
import json
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

from conftest import CLI, SAMPLE, run

FRAMES = 32


def strip_cap_date(data):
    """An EXR's bytes without the header's capDate (the writer's clock)."""
    return re.sub(rb"capDate\x00string\x00....[0-9: ]{19}", b"", data, flags=re.S)


def is_temporary(name):
    """A name the tasks give what they have not finished: hidden (frames, staging directories) or a
    work file's temporary (NAME.tmp-HOST-PID)."""
    return name.startswith(".") or ".tmp-" in name


def task_run(plan, index):
    run("task", plan, index, "--quiet")


class Folder:
    """One run of a plan: its input copy is shared, its outputs, plan and work directory are its own."""

    def __init__(self, root, kind, noisy, denoised=None):
        self.root, self.kind = root, kind
        self.out = root / "out"
        self.plan = root / "plan.json"
        if kind == "denoise":
            run("plan", noisy, self.out / "o.####.exr", "--method", "pca", "--tiles", "4", "--frames-per-task", "32",
                "-o", self.plan, "--quiet")
        elif kind == "shot":  # one task runs the whole shot and writes the frames
            run("plan", noisy, self.out / "o.####.exr", "--quality", "balanced", "--prefilter", "diffusion",
                "-o", self.plan, "--quiet")
        elif kind == "window":  # balanced: the analysis (a directory), then chunks of frames
            run("plan", noisy, self.out / "o.####.exr", "--quality", "balanced", "--frames-per-task", "8",
                "-o", self.plan, "--quiet")
        else:
            run("plan", "detect", denoised, "--noisy", noisy, "--mask", self.out / "m.####.exr",
                "--crops", self.out / "crops.json", "--tiles", "4", "-o", self.plan, "--quiet")
        self.tasks = json.loads(self.plan.read_text())["tasks"]
        expected = {"denoise": "tiles", "detect": "detect", "shot": "shot", "window": "window"}[kind]
        assert json.loads(self.plan.read_text())["kind"] == expected
        written = json.loads(self.plan.read_text())
        self.work = Path(written["work"]) / written["run"]  # where the plan's tasks keep their files

    def finals(self):
        """The final outputs there now, by name: frames without capDate, other files as they are."""
        found = {}
        for p in self.out.iterdir() if self.out.exists() else []:
            if not is_temporary(p.name):
                found[p.name] = strip_cap_date(p.read_bytes()) if p.suffix == ".exr" else p.read_bytes()
        return found

    def work_files(self):
        """The work directory's finished files (what later tasks read), by path within it (a window
        plan's analysis is a directory); not the task reports, which carry their seconds."""
        found = {}
        for p in sorted(self.work.rglob("*")) if self.work.exists() else []:
            rel = p.relative_to(self.work)
            if p.is_dir() or any(is_temporary(part) for part in rel.parts):
                continue
            if not (p.name.startswith("task-") and p.suffix == ".json"):
                found[str(rel)] = p.read_bytes()
        return found

    def temporaries(self):
        left = [p for p in self.work.iterdir() if is_temporary(p.name)] if self.work.exists() else []
        if self.out.exists():
            left += [p for p in self.out.iterdir() if is_temporary(p.name)]
        return sorted(p.name for p in left)


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    """The shipped sample's frames copied to a temporary directory, and each plan run once
    uninterrupted (folder A)."""
    root = tmp_path_factory.mktemp("retry")
    (root / "in").mkdir()
    for f in range(1, FRAMES + 1):
        shutil.copy(SAMPLE / "cornell_moving" / "spp0004" / f"indirect.{f:04d}.exr", root / "in" / f"noisy.{f:04d}.exr")
    noisy = root / "in" / "noisy.####.exr"
    shot = {"root": root, "noisy": noisy}
    for kind in ("denoise", "detect", "shot", "window"):
        a = Folder(root / f"A-{kind}", kind, noisy, denoised=shot.get("denoised"))
        for task in a.tasks:
            task_run(a.plan, task["index"])
        assert not a.temporaries()
        shot[kind] = a
        if kind == "denoise":
            shot["denoised"] = a.out / "o.####.exr"  # the detect plan's input
    assert len(shot["denoise"].finals()) == FRAMES and len(shot["detect"].finals()) == FRAMES + 1
    assert len(shot["shot"].finals()) == FRAMES and len(shot["window"].finals()) == FRAMES
    return shot


def present(folder, name):
    """A task report's output is there: a work file or an output, or for a frame pattern (a shot
    task's), every frame of the shot."""
    if "#" not in name:
        return (folder.work / name).exists() or (folder.out / name).exists()
    hashes = "#" * name.count("#")
    return all((folder.out / name.replace(hashes, f"{f:0{len(hashes)}d}")).exists() for f in range(1, FRAMES + 1))


def watched_entries(folder):
    """Every file and directory in the work and output directories (staging directories included),
    with its size."""
    entries = {}
    for d in (folder.work, folder.out):
        for p in d.rglob("*") if d.exists() else []:
            try:
                entries[p] = p.stat().st_size if p.is_file() else 0
            except FileNotFoundError:  # renamed while we looked
                pass
    return entries


def start_and_kill(folder, index, when):
    """Starts task `index` and kills it with SIGKILL as soon as it has made its first file (a
    temporary or a staging directory: "first-file") or once a file it makes has bytes in it (it is
    writing: "writing"). Returns whether it was killed: it may finish first, and the test holds
    either way."""
    before = watched_entries(folder)

    def started():
        now = watched_entries(folder)
        new = {p: size for p, size in now.items() if p not in before}
        return bool(new) if when == "first-file" else any(size > 0 for size in new.values())

    proc = subprocess.Popen([CLI, "task", str(folder.plan), str(index), "--quiet"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while proc.poll() is None and time.monotonic() < deadline and not started():
        time.sleep(0.001)
    proc.send_signal(signal.SIGKILL)
    rc = proc.wait(timeout=60)
    assert rc in (0, -signal.SIGKILL), f"task {index} exited {rc}"
    return rc == -signal.SIGKILL


# (plan, the phase of the task killed: the first of that phase). The reconstruction and detect tasks
# write the files the next phase reads (the analysis a directory of them); the assembly, masks and
# window tasks write the final outputs, and so does a shot plan's one task.
TARGETS = [("denoise", "reconstruct"), ("denoise", "assemble"), ("detect", "detect"), ("detect", "masks"),
           ("shot", "shot"), ("window", "analysis"), ("window", "first_pass"), ("window", "window")]


@pytest.mark.parametrize("when", ["first-file", "writing"])
@pytest.mark.parametrize("kind,phase", TARGETS, ids=["-".join(t) for t in TARGETS])
def test_a_killed_task_rerun_gives_the_uninterrupted_outputs(shot, tmp_path, kind, phase, when):
    a = shot[kind]
    b = Folder(tmp_path / "B", kind, shot["noisy"], denoised=shot.get("denoised"))
    index = next(t["index"] for t in b.tasks if t["phase"] == phase)
    for task in b.tasks[:index]:
        task_run(b.plan, task["index"])
    start_and_kill(b, index, when)

    # What the killed task left: every file under a final name (work file or output) whole, the same
    # bytes as the uninterrupted run's; anything else has a temporary's name. Its report, if there
    # (killed after writing it, on its way out), says every one of its files is there.
    a_work, a_finals = a.work_files(), a.finals()
    for name, data in b.work_files().items():
        assert data == a_work[name], f"{name} in the work directory differs from the uninterrupted run's"
    for name, data in b.finals().items():
        assert data == a_finals[name], f"output {name} differs from the uninterrupted run's"
    own = [Path(p).name for p in json.loads((a.work / f"task-{index}.json").read_text())["outputs"]]
    missing = [n for n in own if not present(b, n)]
    assert not ((b.work / f"task-{index}.json").exists() and missing), f"a report without {missing}"
    # The next phase, run now (after the killed task's siblings), takes nothing partial: when the
    # killed task's files are not all there it fails before writing any output.
    later = [t for t in b.tasks if index in t["after"]]
    if later and missing:
        for task in b.tasks:  # the killed task's siblings, so that only its files are missing
            if task["phase"] == phase and task["index"] != index:
                task_run(b.plan, task["index"])
        finals_before, temporaries_before = b.finals(), b.temporaries()
        proc = run("task", b.plan, later[0]["index"], "--quiet", check_rc=None)
        assert proc.returncode != 0, f"task {later[0]['index']} ran without {missing}"
        assert b.finals() == finals_before and b.temporaries() == temporaries_before

    # Run again from the killed task: the uninterrupted run's outputs, byte for byte, and nothing
    # left behind by the killed run.
    for task in b.tasks[index:]:
        task_run(b.plan, task["index"])
    assert b.finals() == a_finals
    assert b.work_files() == a_work
    assert not b.temporaries(), "left behind by the killed run"
