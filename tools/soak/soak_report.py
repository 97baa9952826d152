"""The report of `make soak`: report.md (goals PASS/FAIL and figures), report.json (every figure)
and the plots rss.png, update_time.png, db_size.png, wm_size.png (matplotlib, Agg backend)."""
import json
import math
import os


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")  # files only: the soak runs without a display
    import matplotlib.pyplot as plt
    return plt


def _save(fig, plt, path):
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _minutes(samples):
    return [(s["robot_s"] / 60.0) if s.get("robot_s") is not None else float("nan") for s in samples]


def plot_rss(path, samples, figures):
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    x = _minutes(samples)
    for name in sorted({n for s in samples for n in s["rss"]}):
        ax.plot(x, [s["rss"].get(name, float("nan")) for s in samples], label="%s (VmRSS)" % name)
    ref = figures.get("rss_reference_robot_s")
    if ref is not None:
        ax.axvline(ref / 60.0, color="tab:red", linestyle="--", label="reference (20 min or WM full, the later)")
    for name, g in figures.get("rss_growth", {}).items():
        ax.axhline(g["baseline_mb"] * 1.1, color="tab:orange", linestyle=":", label="%s baseline + 10%%" % name)
    ax.set_xlabel("robot time (min)")
    ax.set_ylabel("resident memory (MB)")
    ax.set_title("Resident memory of the node processes")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    _save(fig, plt, path)


def plot_update_time(path, updates, figures):
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    t0 = updates[0]["stamp"] if updates else 0.0
    pts = [((u["stamp"] - t0) / 60.0, u["stats"]["Timing/Total/ms"]) for u in updates if "Timing/Total/ms" in u["stats"]]
    ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", markersize=2, color="tab:blue", alpha=0.4,
            label="each update")
    w = figures.get("update_time_windows", [])
    mid = [(r["start_s"] + r["end_s"]) / 120.0 for r in w]
    for key, style in (("p50", "-"), ("p95", "--"), ("p99", ":")):
        ax.plot(mid, [r[key] for r in w], style, marker="o", markersize=3, color="black", label="%s per %.0f min" %
                (key, (w[0]["end_s"] - w[0]["start_s"]) / 60.0 if w else 0))
    if figures.get("time_threshold_ms", 0) > 0:
        ax.axhline(figures["time_threshold_ms"], color="tab:red", linestyle="--",
                   label="Rtabmap/TimeThr %g ms" % figures["time_threshold_ms"])
    if figures.get("rate"):
        ax.axhline(1000.0 / figures["rate"], color="tab:purple", linestyle="-.",
                   label="frame period at replay rate %g" % figures["rate"])
    ax.set_xlabel("robot time (min)")
    ax.set_ylabel("update time, Timing/Total (ms)")
    ax.set_title("SLAM update time")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    _save(fig, plt, path)


def plot_db_size(path, samples):
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(_minutes(samples), [s["db_bytes"] / 1e6 for s in samples], color="tab:brown")
    ax.set_xlabel("robot time (min)")
    ax.set_ylabel("database on disk (MB, with its WAL)")
    ax.set_title("Database size")
    ax.grid(True, alpha=0.3)
    _save(fig, plt, path)


def plot_wm(path, updates, figures):
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    t0 = updates[0]["stamp"] if updates else 0.0
    ax.plot([(u["stamp"] - t0) / 60.0 for u in updates],
            [u["stats"].get("Memory/Working_memory_size/", float("nan")) for u in updates], color="tab:green",
            label="Working Memory (nodes)")
    if figures.get("memory_threshold", 0) > 0:
        ax.axhline(figures["memory_threshold"], color="tab:red", linestyle="--",
                   label="Rtabmap/MemoryThr %d" % figures["memory_threshold"])
    ax.set_xlabel("robot time (min)")
    ax.set_ylabel("nodes in Working Memory")
    ax.set_title("Working Memory size (the map's nodes in RAM) and nodes in the map")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax2 = ax.twinx()  # the map keeps growing while WM stays bounded
    ax2.plot([(u["stamp"] - t0) / 60.0 for u in updates], range(1, len(updates) + 1), color="tab:gray",
             label="SLAM updates so far (nodes in the map)")
    ax2.set_ylabel("updates so far")
    ax2.set_ylim(bottom=0)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="upper left", fontsize=8)
    _save(fig, plt, path)


def _fmt(v, pattern="%.1f"):
    return "n/a" if v is None or (isinstance(v, float) and math.isnan(v)) else pattern % v


def markdown(figures, checks):
    f = figures
    ut = f["update_time"]
    sync = f["sync"]
    rv = f["revisits"]
    lines = ["# RTAB-Map soak", "",
             "The simulator's `long` scenario through the real ROS pipeline (`rosbag play --clock -r %g`, "
             "`launch/soak.launch`: the rtabmap node of `demo_sim_robot.launch` with Rtabmap/MemoryThr %d and "
             "Rtabmap/TimeThr %g ms). Made by `make soak` in %.1f min of wall time (bag %s, replay %.1f min)." %
             (f["rate"], f["memory_threshold"], f["time_threshold_ms"], f["wall_s"] / 60,
              "made in %.1f min" % (f["bag_make_s"] / 60) if f.get("bag_made_now") else "from the cache",
              f["play_wall_s"] / 60), "",
             "## Goals", "", "| goal | result | detail |", "|---|---|---|"]
    lines += ["| %s | **%s** | %s |" % (name, "PASS" if ok else "FAIL", detail) for name, ok, detail in checks]
    lines += ["", "## Figures", "", "| figure | value |", "|---|---|",
              "| robot time replayed | %.2f h (%d frames) |" % (f["hours_replayed"], sync["frames"]),
              "| SLAM updates | %d |" % f["updates"],
              "| update time p50 / p95 / p99 / max | %s / %s / %s / %s ms |" %
              (_fmt(ut["p50"]), _fmt(ut["p95"]), _fmt(ut["p99"]), _fmt(ut["p100"])),
              "| largest Working Memory | %d nodes (full at %s min of robot time) |" %
              (f["max_wm"], _fmt(f["wm_full_robot_s"] / 60 if f["wm_full_robot_s"] is not None else None, "%.1f")),
              "| RSS reference (20 min of robot time or WM full, the later) | %.1f min |" %
              (f["rss_reference_robot_s"] / 60),
              ]
    for name, g in sorted(f["rss_growth"].items()):
        lines.append("| RSS of %s: baseline / largest 5-min median / final / slope | %.0f / %.0f / %.0f MB / %+.1f MB/h |" %
                     (name, g["baseline_mb"], g["max_window_mb"], g["final_mb"], g["slope_mb_per_h"]))
    lines += ["| database on disk | %.0f MB |" % (f["db_bytes"] / 1e6),
              "| nodes in the database / published on info / acknowledged durable / lost | %d / %d / %d / %d |" %
              (f["nodes_in_db"], f["nodes_published"], f["acknowledged"], f["nodes_lost"]),
              "| database check (rtabmap-info --check) | %s |" % ("ok" if f["db_check_ok"] else "FAILED"),
              "| sync: frames / updates / skipped by design (robot still) / dropped | %d / %d / %d / %d (%.2f%%) |" %
              (sync["frames"], sync["updates"], sync["skipped_still"], sync["dropped"], 100 * sync["drop_fraction"]),
              "| sync: input lost as the node reported it (warnings / sets) | %d / %d |" %
              (sync.get("node_reported", {}).get("warnings", 0), sync.get("node_reported", {}).get("sets_lost", 0)),
              "| revisits (ground truth within %g m of a place left > %g s before) closed within %g s | %d of %d "
              "episodes (%s%%) |" % (f["revisit_radius"], f["revisit_age"], f["revisit_grace"], rv["closed"],
                                     rv["episodes"], _fmt(100 * rv["fraction"], "%.0f")),
              "| updates with a loop closure / a proximity link | %d / %d |" %
              (f["loop_closures_published"], f["proximity_published"]),
              "| crashes / respawns / samples without the node | %d / %d / %d |" %
              (f["crashes"], f["respawns"], f["samples_without_node"]),
              "| bag | %.2f GB, %s |" % (f["bag_bytes"] / 1e9, ", ".join("%s %d" % kv for kv in
                                                                         sorted(sync["bag_sensor_messages"].items()))),
              "", "## How the figures are defined", "",
              "- **RSS**: VmRSS of `/proc/<pid>/status` of every node process of the launch (the children of "
              "roslaunch; rosbag play and this script excluded), sampled every %g s of wall time. Growth = the "
              "largest median over a 5-min window of robot time after the reference, over the median of the first "
              "such window, minus one." % f["sample_period"],
              "- **Sync drops**: every frame of the bag (%s, one message each per frame) is expected to give "
              "one SLAM update (`info`), except the frames the node skips by design: the robot moved less than "
              "RGBD/LinearUpdate %g m and RGBD/AngularUpdate %g rad since the last node (odometry of the frame, the "
              "node's own rule; Rtabmap/DetectionRate equals the frame rate). Drops = the other frames without "
              "update; the fraction is over the frames expected." % (", ".join(sorted(sync["bag_sensor_messages"])),
                                                                      f["linear_update"], f["angular_update"]),
              "- **Revisits**: an update is at a revisit when the ground-truth position is within %g m of the "
              "position of an update more than %g s older; consecutive such updates are one episode; it is closed "
              "when an update of it (or up to %g s after) has a loop closure or proximity link to a node more than "
              "%g s older. With memory management, old places may be in the database (LTM) and not recognisable "
              "until retrieved: this fraction is reported, not a goal." % (f["revisit_radius"], f["revisit_age"],
                                                                          f["revisit_grace"], f["revisit_age"]),
              "- **Nodes lost**: every node id published on `info` up to the largest Memory/Durable_node_id "
              "(the last node whose database write committed) must be in the final database.",
              "- **Crashes**: roslaunch's `process has died` lines in run.log, a node seen with a new pid "
              "(respawn), or the node missing from the last sample.",
              "", "## Update time per %.0f min of robot time" % (f["window_s"] / 60), "",
              "| robot time (min) | updates | frames dropped | p50 | p95 | p99 | max (ms) |", "|---|---|---|---|---|---|---|"]
    for r in f["update_time_windows"]:
        lines.append("| %.0f-%.0f | %d | %d | %.0f | %.0f | %.0f | %.0f |" %
                     (r["start_s"] / 60, r["end_s"] / 60, r["updates"], r.get("dropped", 0), r["p50"], r["p95"],
                      r["p99"], r["max"]))
    if f.get("stages"):
        lines += ["", "## Stages of the update: mean time over the first and the last 20 min of robot time", "",
                  "| stage | first 20 min (ms) | last 20 min (ms) |", "|---|---|---|"]
        lines += ["| %s | %.1f | %.1f |" % row for row in f["stages"][:12]]
    if f.get("memory_breakdown"):
        lines += ["", "## Memory of the SLAM node as the core counts it: mean over the 5 min after the reference "
                  "and the last 5 min", "", "| part | after the reference (MB) | last 5 min (MB) |", "|---|---|---|"]
        lines += ["| %s | %.1f | %.1f |" % tuple(row) for row in f["memory_breakdown"]]
        lines += ["", "The resident size is the heap in use and kept free, plus code, stacks and the allocator's "
                  "per-thread arenas."]
    for name, rows in sorted(f.get("resident_kinds", {}).items()):
        lines += ["", "## Resident size of %s by kind (/proc status): mean over the 5 min after the reference and "
                  "the last 5 min" % name, "", "| kind | after the reference (MB) | last 5 min (MB) |", "|---|---|---|"]
        labels = {"anon": "anonymous (heap, thread arenas, malloc's mmap()ed blocks, stacks)",
                  "file": "file-backed (code of the executable and libraries, mapped files)", "shmem": "shared memory"}
        lines += ["| %s | %.1f | %.1f |" % (labels.get(kind, kind), a, b) for kind, a, b in rows]
        heap = dict((row[0], row[1:]) for row in f.get("memory_breakdown", [])).get("heap in use (live data)")
        anon = dict((row[0], row[1:]) for row in rows).get("anon")
        if heap and anon and name == "rtabmap":
            lines.append("| anonymous beyond the heap in use (kept free by malloc and resident, stacks) | %.1f | %.1f |" %
                         (anon[0] - heap[0], anon[1] - heap[1]))
    lines += ["", "![rss](rss.png)", "", "![update time](update_time.png)", "", "![wm](wm_size.png)", "",
              "![database](db_size.png)", "",
              "Files: `run.log` (roslaunch, the node, the tools), `report.json` (every figure), `rtabmap.db` (open "
              "with `rtabmap-info` or `rtabmap-export`), `cache/` (the bag, reused by the next run).", ""]
    return "\n".join(lines)


def write(output, figures, checks, updates, samples):
    plot_rss(os.path.join(output, "rss.png"), samples, figures)
    plot_update_time(os.path.join(output, "update_time.png"), updates, figures)
    plot_db_size(os.path.join(output, "db_size.png"), samples)
    plot_wm(os.path.join(output, "wm_size.png"), updates, figures)
    with open(os.path.join(output, "report.md"), "w") as f:
        f.write(markdown(figures, checks))
    out = dict(figures)
    out["goals"] = [{"goal": n, "passed": bool(ok), "detail": d} for n, ok, d in checks]
    out["samples"] = samples
    with open(os.path.join(output, "report.json"), "w") as f:
        json.dump(out, f, indent=1, default=str)
