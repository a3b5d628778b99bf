#!/usr/bin/env python3
"""Submits a statfilter plan to Thinkbox Deadline: one CommandLine job per phase (statistics, sum,
reduce, reconstruct, assemble; or frames; or shot), its frames the plan's task numbers (chunk size 1), each
job depending on the job of the phase before it. Every frame runs `statfilter task PLAN N`; Deadline's
task requeue reruns a task that died (tasks are idempotent).

    statfilter plan shot/beauty.####.exr out/denoised.####.exr --quality fast --tiles 40 -o /shared/shot.plan.json
    python3 scripts/farm/deadline_submit.py /shared/shot.plan.json [--pool POOL] [--dry-run]

Needs `deadlinecommand` on PATH; --dry-run writes and prints the job files only. The plan, its input,
output and work directory must be on storage every worker sees.
"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plan_phases import phases  # noqa: E402
from submit_arguments import parse_submit_arguments  # noqa: E402


def main():
    args = parse_submit_arguments(__doc__, "workers", "worker", [("--pool", "none")])
    plan = os.path.abspath(args.plan)
    files = tempfile.mkdtemp(prefix="statfilter-deadline-")
    previous = None
    for name, first, last in phases(plan):
        job_info = os.path.join(files, name + ".job")
        plugin_info = os.path.join(files, name + ".plugin")
        with open(job_info, "w") as f:
            f.write("Plugin=CommandLine\nName=statfilter %s (%s)\nFrames=%d-%d\nChunkSize=1\nPool=%s\n"
                    % (name, os.path.basename(plan), first, last, args.pool))
            if previous:
                f.write("JobDependencies=%s\n" % previous)
        with open(plugin_info, "w") as f:
            f.write("Executable=%s\nArguments=task \"%s\" <STARTFRAME> --threads %d --quiet\nShell=default\n"
                    % (args.statfilter, plan, args.threads))
        if args.dry_run:
            print("== %s\n%s%s" % (name, open(job_info).read(), open(plugin_info).read()))
            previous = "<job id of %s>" % name
            continue
        out = subprocess.run(["deadlinecommand", job_info, plugin_info], capture_output=True, text=True, check=True).stdout
        found = re.search(r"JobID=(\S+)", out)
        if not found:
            sys.exit("deadlinecommand gave no JobID for phase %s:\n%s" % (name, out))
        previous = found.group(1)
        print("%s: job %s" % (name, previous))


if __name__ == "__main__":
    main()
