"""The phases of a statfilter plan as a farm submits them: each phase a contiguous range of task numbers
that waits for the whole phase before it (what every task's "after" list says)."""
import json


def phases(plan_path):
    """[(phase, first task, last task)] in the order they run; checks the plan has that shape."""
    with open(plan_path) as f:
        plan = json.load(f)
    out = []
    for task in plan["tasks"]:
        if out and out[-1][0] == task["phase"]:
            out[-1][2] = task["index"]
        else:
            out.append([task["phase"], task["index"], task["index"]])
    for k, (name, first, last) in enumerate(out):
        before = set(range(out[k - 1][1], out[k - 1][2] + 1)) if k else set()
        for task in plan["tasks"][first:last + 1]:
            if not set(task["after"]) <= before:
                raise SystemExit("%s: task %d waits for tasks outside the phase before it" % (plan_path, task["index"]))
    return [tuple(p) for p in out]
