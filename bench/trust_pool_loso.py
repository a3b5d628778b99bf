#!/usr/bin/env python3
"""Leave-one-scene-out choice of `prefilter_trust_pool_still`, the frames the trust blend's fit pools
over where the temporal stage followed no motion, for `--quality high`.

The value trades flicker against error, so it is scored on the quality targets themselves
(bench/quality_targets.py's checks for `high`: relMSE, moving-region relMSE and still-scene jitter
against OIDN's): per scene, the number of failed checks over its levels; ties broken by the geometric
mean of relMSE / OIDN's. For each scene held out, the value picked on the others is scored on it
beside the value picked on all of them. Prints a Markdown table (for docs/preset_loso.md). Usage:
    python3 bench/trust_pool_loso.py [--cli build/tools/statfilter] [--data ../shared/data[,held-out dir]]
        [--values 2,4,8,16]
"""

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from loso import Runner, bench_arguments, geomean, import_statfilter, scenes  # noqa: E402
from quality_targets import checks  # noqa: E402


def main():
    p = bench_arguments(__doc__, "preset_loso.md")
    p.add_argument("--values", default="2,4,8,16")
    args = p.parse_args()
    values = args.values.split(",")
    found = scenes(args.data)
    sf = import_statfilter(args.cli)
    # score[value][scene] = (failed checks, geometric mean of relMSE / OIDN's)
    score = {v: {} for v in values}
    rows = []
    with tempfile.TemporaryDirectory() as work:
        runner = Runner(args.cli, work, sf)
        for scene, levels in found:
            fails = {v: 0 for v in values}
            ratios = {v: [] for v in values}
            for level in levels:
                oidn = runner.run(scene, level, ["--method", "oidn"])
                for v in values:
                    fig = runner.run(scene, level, ["--quality", "high", "--prefilter_trust_pool_still", v])
                    targets = [c for c in checks("high", level, fig, oidn) if c[0] != "|bias|" and c[0] != "negative"]
                    fails[v] += sum(1 for c in targets if not c[3])
                    ratios[v].append(fig["rel_mse"] / oidn["rel_mse"])
                    rows.append((scene.name, level, v, fig["rel_mse"] / oidn["rel_mse"], fig["jitter"] / oidn["jitter"]))
            for v in values:
                score[v][scene.name] = (fails[v], geomean(ratios[v]))
    names = [s.name for s, _ in found]

    def best(among):
        return min(values, key=lambda v: (sum(score[v][n][0] for n in among), geomean([score[v][n][1] for n in among])))

    overall = best(names)
    print(f"Command: `python3 bench/trust_pool_loso.py --data {args.data}` (values {args.values})\n")
    print("| scene held out | picked on the others | held-out fails | held-out relMSE / OIDN | "
          "in-sample pick | its fails | its relMSE / OIDN |")
    print("|---|---|---|---|---|---|---|")
    for held in names:
        picked = best([n for n in names if n != held])
        print(f"| {held} | {picked} | {score[picked][held][0]} | {score[picked][held][1]:.4f} | {overall} | "
              f"{score[overall][held][0]} | {score[overall][held][1]:.4f} |")
    print("\nPer value (failed checks over every scene, geometric mean of relMSE / OIDN's, of jitter / OIDN's):\n")
    for v in values:
        print(f"- {v}: {sum(score[v][n][0] for n in names)} fails, relMSE {geomean([score[v][n][1] for n in names]):.4f}, "
              f"jitter {geomean([r[4] for r in rows if r[2] == v]):.4f}")


if __name__ == "__main__":
    main()
