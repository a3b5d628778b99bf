"""The command line every farm submitter takes: the plan, the farm's own options, the CLI as the farm's
machines run it, threads per task and --dry-run."""
import argparse


def parse_submit_arguments(doc, machines, machine, own):
    """The submitter's parsed arguments. doc: its docstring (the first line describes it); machines,
    machine: what the farm calls the computers that run tasks, for the help; own: the farm's own
    options, (flag, default) each, listed after the plan."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("plan")
    for flag, default in own:
        ap.add_argument(flag, default=default)
    ap.add_argument("--statfilter", default="statfilter", help="the CLI as the %s run it" % machines)
    ap.add_argument("--threads", type=int, default=0, help="threads per task (0: every core of the %s)" % machine)
    ap.add_argument("--dry-run", action="store_true")
    return ap.parse_args()
