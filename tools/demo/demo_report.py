"""The figures and plots of `make demo`: trajectory error against ground truth, update-time
percentiles, and the PNG plots that report.md shows."""
import math

import numpy as np


def read_tum(path):
    """stamp -> (x, y) of a TUM trajectory file (stamp x y z qx qy qz qw)."""
    poses = {}
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 3 and not line.startswith("#"):
                poses[float(fields[0])] = (float(fields[1]), float(fields[2]))
    return poses


def write_tum(path, poses):
    with open(path, "w") as f:
        for stamp in sorted(poses):
            x, y = poses[stamp]
            f.write("%.6f %.6f %.6f 0 0 0 0 1\n" % (stamp, x, y))


def associate(estimate, truth, max_difference=0.01):
    """Pairs (estimate xy, truth xy) whose stamps are within max_difference seconds."""
    stamps = np.array(sorted(truth))
    pairs = []
    if len(stamps) == 0:
        return pairs
    for stamp, xy in sorted(estimate.items()):
        i = int(np.searchsorted(stamps, stamp))
        best = min((j for j in (i - 1, i) if 0 <= j < len(stamps)), key=lambda j: abs(stamps[j] - stamp))
        if abs(stamps[best] - stamp) <= max_difference:
            pairs.append((xy, truth[stamps[best]]))
    return pairs


def align_2d(estimate, truth):
    """Rotation r and translation t minimising |r * estimate + t - truth| (Umeyama, no scale)."""
    a, b = np.asarray(estimate, float), np.asarray(truth, float)
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((b - cb).T @ (a - ca))
    r = u @ np.diag([1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
    return r, cb - r @ ca


def ate(estimate, truth):
    """RMSE of the positions after the best rigid alignment, with the alignment and the number
    of poses compared; None when fewer than 3 stamps match."""
    pairs = associate(estimate, truth)
    if len(pairs) < 3:
        return None
    a = np.array([p[0] for p in pairs])
    b = np.array([p[1] for p in pairs])
    r, t = align_2d(a, b)
    error = (r @ a.T).T + t - b
    return {"rmse": float(math.sqrt(np.mean(np.sum(error ** 2, axis=1)))), "poses": len(pairs), "r": r, "t": t}


def percentile(values, p):
    return float(np.percentile(values, p)) if len(values) else float("nan")


def timing_figures(updates):
    total = [u["stats"]["Timing/Total/ms"] for u in updates if "Timing/Total/ms" in u["stats"]]
    return {"updates": len(updates), "median_ms": percentile(total, 50), "p95_ms": percentile(total, 95),
            "p99_ms": percentile(total, 99), "max_ms": max(total) if total else float("nan")}


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")  # files only: the demo may run without a display
    import matplotlib.pyplot as plt
    return plt


def with_breaks(stamped, gap=5.0):
    """(x, y) in stamp order, with a (nan, nan) wherever the stamps jump by more than `gap`
    seconds (between sessions), so a plot does not join them with a line."""
    xy, previous = [], None
    for stamp in sorted(stamped):
        if previous is not None and stamp - previous > gap:
            xy.append((float("nan"), float("nan")))
        xy.append(stamped[stamp])
        previous = stamp
    return xy


def plot_trajectories(path, title, curves):
    """curves: (label, [(x, y), ...], style) drawn in the map frame, equal axes; (nan, nan)
    breaks a line."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 7))
    for label, xy, style in curves:
        if len(xy):
            xy = np.asarray(xy, dtype=float)
            ax.plot(xy[:, 0], xy[:, 1], style, label=label, linewidth=1.0, markersize=2)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_timing(path, title, updates, time_threshold_ms):
    """Per-update time (Timing/Total/ms) over the run against the time budget, with the size of
    Working Memory on a second axis: memory management keeps the first under the second."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    t0 = updates[0]["stamp"] if updates else 0.0
    x = [u["stamp"] - t0 for u in updates if "Timing/Total/ms" in u["stats"]]
    y = [u["stats"]["Timing/Total/ms"] for u in updates if "Timing/Total/ms" in u["stats"]]
    ax.plot(x, y, ".", markersize=2, color="tab:blue", label="update time (ms)")
    if time_threshold_ms > 0:
        ax.axhline(time_threshold_ms, color="tab:red", linestyle="--",
                   label="time budget Rtabmap/TimeThr = %g ms" % time_threshold_ms)
    ax.set_xlabel("data time since the first update (s)")
    ax.set_ylabel("update time (ms)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    wm = [(u["stamp"] - t0, u["stats"]["Memory/Working_memory_size/"]) for u in updates
          if "Memory/Working_memory_size/" in u["stats"]]
    if wm:
        ax2 = ax.twinx()
        ax2.plot([w[0] for w in wm], [w[1] for w in wm], color="tab:green", linewidth=1.0,
                 label="Working Memory (nodes)")
        ax2.set_ylabel("Working Memory size (nodes)")
        lines = ax.get_legend_handles_labels()
        lines2 = ax2.get_legend_handles_labels()
        ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], loc="upper left", fontsize=8)
    else:
        ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
