#!/usr/bin/env python3
"""Submits a statfilter plan to OpenCue: one layer per phase (statistics, sum, reduce, reconstruct,
assemble; or frames; or shot), its "frames" the plan's task numbers, each layer depending on the whole
layer before it. Every frame runs `statfilter task PLAN N`; OpenCue's retries rerun a frame that died
(tasks are idempotent).

    statfilter plan shot/beauty.####.exr out/denoised.####.exr --quality fast --tiles 40 -o /shared/shot.plan.json
    python3 scripts/farm/opencue_submit.py /shared/shot.plan.json --show SHOW --shot SHOT [--dry-run]

Needs OpenCue's pyoutline (`outline`) and a configured cuebot; --dry-run prints the layers only. The
plan, its input, output and work directory must be on storage every render node sees.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plan_phases import phases  # noqa: E402
from submit_arguments import parse_submit_arguments  # noqa: E402


def main():
    args = parse_submit_arguments(__doc__, "render nodes", "node", [("--show", "statfilter"), ("--shot", "denoise")])
    plan = os.path.abspath(args.plan)
    layers = []
    for name, first, last in phases(plan):
        command = [args.statfilter, "task", plan, "#IFRAME#", "--threads", str(args.threads), "--quiet"]
        layers.append((name, "%d-%d" % (first, last), command))
    if args.dry_run:
        for name, frames, command in layers:
            print("layer %-12s frames %-8s %s" % (name, frames, " ".join(command)))
        return
    from outline import Outline, cuerun  # OpenCue's pyoutline
    from outline.modules.shell import Shell
    job = Outline("statfilter_" + os.path.basename(plan).replace(".", "_"), show=args.show, shot=args.shot)
    previous = None
    for name, frames, command in layers:
        layer = Shell(name, command=command, range=frames, chunk=1)
        if previous is not None:
            layer.depend_all(previous)  # the whole previous phase first
        job.add_layer(layer)
        previous = layer
    cuerun.launch(job, use_pycuerun=False)


if __name__ == "__main__":
    main()
