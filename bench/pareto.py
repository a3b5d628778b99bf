"""The speed/accuracy map: the Pareto front of (time per frame, error) and where a point stands to it."""

from collections import defaultdict


def on_map(rows):
    """The rows that are methods (not the noisy input, not the peers' harness)."""
    return [r for r in rows if r["method"] not in ("input", "peer identity")]


def front(rows, error="rel_mse"):
    """The rows no other row beats in both time and error, fastest first."""
    pts = sorted(on_map(rows), key=lambda r: (r["compute_ms_per_frame"], r[error]))
    out, best = [], float("inf")
    for r in pts:
        if r[error] < best:
            out.append(r)
            best = r[error]
    return out


def standing(row, rows, error="rel_mse"):
    """How far a row is from the front: (its error / the lowest error reached as fast or faster,
    its time / the least time that reaches its error or lower). (1, 1) means on the front."""
    pts = on_map(rows)
    as_fast = [r[error] for r in pts if r["compute_ms_per_frame"] <= row["compute_ms_per_frame"]]
    as_good = [r["compute_ms_per_frame"] for r in pts if r[error] <= row[error]]
    err_ratio = row[error] / min(as_fast) if as_fast else 1.0
    time_ratio = row["compute_ms_per_frame"] / max(min(as_good), 1e-9) if as_good else 1.0
    return err_ratio, time_ratio


def plot(rows, docs, colors, markers):
    """One PNG per scene: a panel per noise level, every configuration a point, the front drawn,
    the presets marked. Returns the file names."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    by_scene = defaultdict(list)
    for r in rows:
        by_scene[r["scene"]].append(r)
    files = []
    for scene, scene_rows in sorted(by_scene.items()):
        levels = sorted({r["level"] for r in scene_rows})
        fig, axes = plt.subplots(1, len(levels), figsize=(5.6 * len(levels), 4.6), squeeze=False)
        for ax, level in zip(axes[0], levels):
            rs = [r for r in scene_rows if r["level"] == level]
            for r in on_map(rs):
                key = color_key(r)
                ax.scatter(max(r["compute_ms_per_frame"], 1e-3), r["rel_mse"], color=colors.get(key, "grey"), s=16,
                           marker=markers.get(key, "o"), alpha=0.85, zorder=2)
            f = front(rs)
            ax.step([max(r["compute_ms_per_frame"], 1e-3) for r in f], [r["rel_mse"] for r in f], where="post",
                    color="black", lw=1, zorder=1)
            for r in rs:
                if r["family"] == "preset":
                    ax.scatter(max(r["compute_ms_per_frame"], 1e-3), r["rel_mse"], s=140, marker="*",
                               facecolor="gold", edgecolor="black", zorder=3)
                    ax.annotate(r["label"].replace("preset ", ""), (r["compute_ms_per_frame"], r["rel_mse"]),
                                textcoords="offset points", xytext=(4, 4), fontsize=6)
            noisy = next((r for r in rs if r["method"] == "input"), None)
            if noisy:
                ax.axhline(noisy["rel_mse"], color="black", lw=0.8, ls="--")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_title(f"{scene} {level}")
            ax.set_xlabel("compute time per frame (ms, log)")
            ax.set_ylabel("relMSE vs reference (log)")
        handles = [plt.Line2D([], [], marker=markers.get(k, "o"), ls="", color=c, label=k) for k, c in colors.items()]
        handles.append(plt.Line2D([], [], marker="*", ls="", markerfacecolor="gold", markeredgecolor="black",
                                  markersize=11, label="quality presets"))
        handles.append(plt.Line2D([], [], color="black", lw=1, label="Pareto front"))
        handles.append(plt.Line2D([], [], ls="--", color="black", lw=0.8, label="noisy input"))
        axes[0][-1].legend(handles=handles, fontsize=6, loc="upper right")
        fig.tight_layout()
        name = f"benchmark_{scene}.png"
        fig.savefig(docs / name, dpi=90)
        plt.close(fig)
        files.append(name)
    return files


def color_key(row):
    """The legend entry of a row: the statfilter method, 'OIDN then ...', or the peer."""
    if row["family"] == "statfilter + OIDN":
        return "statfilter after OIDN"
    if row["family"] == "preset":
        return "auto"
    return row["method"]
