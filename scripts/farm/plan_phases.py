"""The phases of a statfilter plan as a farm submits them: each phase a contiguous range of task numbers
that waits for the whole phase before it. That is enough when every task's "after" list names tasks of
earlier phases only (a chain of phases waits for all of them: the "images" task waits for the
reconstructions, two phases back)."""
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
        for task in plan["tasks"][first:last + 1]:
            if not all(a < first for a in task["after"]):
                raise SystemExit("%s: task %d waits for a task of its own phase or a later one" % (plan_path, task["index"]))
    return [tuple(p) for p in out]
