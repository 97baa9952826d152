"""The figures of `make soak`, as pure functions of what the run recorded (no ROS here, so
test/soak_metrics_check.py can check them on made-up data):

  - resident memory of the node processes (VmRSS of /proc/<pid>/status) and its growth once
    Working Memory is full;
  - update time percentiles per window of robot time;
  - revisits (ground truth back within `radius` of a place left more than `min_age` s earlier)
    and whether RTAB-Map linked them (loop closure or proximity link to an old enough node);
  - sync drops: sensor frames of the bag that produced no SLAM update and that the node did not
    skip by design (the robot still: RGBD/LinearUpdate and RGBD/AngularUpdate);
  - nodes lost: acknowledged durable on `info` but missing from the final database.
"""
import math
import os

import numpy as np


# ---------------------------------------------------------------- processes and memory

def read_status(pid):
    """{field: value} of /proc/<pid>/status, {} when the process is gone."""
    try:
        with open("/proc/%d/status" % pid) as f:
            return dict(line.rstrip("\n").split(":\t", 1) for line in f if ":\t" in line)
    except (OSError, ValueError):
        return {}


def rss_mb(pid):
    """Resident memory (VmRSS) of a process in MB, None when it is gone."""
    value = read_status(pid).get("VmRSS")
    return int(value.split()[0]) / 1024.0 if value else None


def resident_kinds_mb(pid):
    """The resident size of a process split by kind, in MB (RssAnon, RssFile, RssShmem of
    /proc/<pid>/status): `anon` is the heap with its per-thread arenas, blocks malloc mmap()ed on
    their own and stacks; `file` the pages of the executable, its libraries and mapped files
    (code read in as it runs); `shmem` shared memory. None when the process is gone. What grows
    in a leak is anon; a process touching more of its code grows file."""
    status = read_status(pid)
    keys = {"anon": "RssAnon", "file": "RssFile", "shmem": "RssShmem"}
    if not all(k in status for k in keys.values()):
        return None
    return {kind: int(status[key].split()[0]) / 1024.0 for kind, key in keys.items()}


def children(pid):
    """Direct children of a process (from the PPid of every /proc/<n>/status)."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            status = read_status(int(entry))
            if status.get("PPid", "").strip() == str(pid):
                out.append(int(entry))
    return sorted(out)


def command_name(pid):
    """The node's name from its command line (__name:=NAME, which roslaunch always passes), else
    the executable's base name."""
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as f:
            argv = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
    except OSError:
        return None
    for a in argv:
        if a.startswith("__name:="):
            return a[len("__name:="):]
    return os.path.basename(argv[0]) if argv else None


# ---------------------------------------------------------------- windows and percentiles

def percentiles(values, ps=(50, 95, 99)):
    if not len(values):
        return {"p%d" % p: float("nan") for p in ps}
    return {"p%d" % p: float(np.percentile(values, p)) for p in ps}


def windowed_update_times(updates, window_s):
    """Update time (Timing/Total/ms) percentiles per window of robot time since the first update:
    [{start_s, end_s, updates, p50, p95, p99, max}]."""
    timed = [(u["stamp"], u["stats"]["Timing/Total/ms"]) for u in updates if "Timing/Total/ms" in u["stats"]]
    if not timed:
        return []
    t0 = timed[0][0]
    buckets = {}
    for stamp, ms in timed:
        buckets.setdefault(int((stamp - t0) // window_s), []).append(ms)
    out = []
    for k in sorted(buckets):
        row = {"start_s": k * window_s, "end_s": (k + 1) * window_s, "updates": len(buckets[k]),
               "max": float(max(buckets[k]))}
        row.update(percentiles(buckets[k]))
        out.append(row)
    return out


def stage_times(updates, span_s):
    """Mean time of each stage of the update (Timing/*/ms but the total) over the first and the last
    span_s of robot time: which stages grow over the run. [(stage, first_ms, last_ms)], largest
    last first."""
    if not updates:
        return []
    t0, t1 = updates[0]["stamp"], updates[-1]["stamp"]
    first = [u["stats"] for u in updates if u["stamp"] - t0 < span_s]
    last = [u["stats"] for u in updates if t1 - u["stamp"] < span_s]
    keys = sorted({k for s in first + last for k in s if k.startswith("Timing/") and k != "Timing/Total/ms"})

    def mean(rows, k):
        return float(np.mean([r.get(k, 0.0) for r in rows])) if rows else float("nan")
    rows = [(k[len("Timing/"):-len("/ms")], mean(first, k), mean(last, k)) for k in keys]
    return sorted(rows, key=lambda r: -r[2])


MEMORY_STATS = (("heap in use (live data)", "Memory/RAM_usage/MB"), ("heap kept free by malloc", "Memory/Heap_free/MB"),
                ("SQLite (page caches)", "Memory/Database_memory_used/MB"),
                ("global grid (map, WM cells, LTM cache)", "Memory/Grid_memory_used/MB"),
                ("locations in RAM (STM, WM: words, compressed images, scans, local grids)",
                 "Memory/Locations_memory_used/MB"),
                ("vocabulary (words, kd-tree index with the removed words until its rebuild)",
                 "Memory/Vocabulary_memory_used/MB"))


def memory_breakdown(updates, reference_s, window_s=300.0):
    """Where the node's RAM goes, from the core's own counts in `info` (heap in use and free, SQLite,
    the grid's per-node cache): mean over the first window after the reference and over the last
    window. [(what, first_mb, last_mb)], only the counts the node published."""
    if not updates:
        return []
    t0, t1 = updates[0]["stamp"], updates[-1]["stamp"]
    first = [u["stats"] for u in updates if reference_s <= u["stamp"] - t0 < reference_s + window_s]
    last = [u["stats"] for u in updates if t1 - u["stamp"] < window_s]
    rows = []
    for name, key in MEMORY_STATS:
        a, b = [r[key] for r in first if key in r], [r[key] for r in last if key in r]
        if a and b:
            rows.append((name, float(np.mean(a)), float(np.mean(b))))
    return rows


def resident_kinds(samples, reference_s, window_s=300.0):
    """Mean resident size by kind (resident_kinds_mb) per process over the first window after
    the reference and over the last window of robot time: which kind grows.
    samples: [{"robot_s", "rss_kinds": {name: {kind: MB}}}]. {name: [(kind, first_mb, last_mb)]}."""
    names = sorted({n for s in samples for n in s.get("rss_kinds", {})})
    timed = [s for s in samples if s.get("robot_s") is not None]
    if not timed:
        return {}
    t1 = max(s["robot_s"] for s in timed)
    out = {}
    for name in names:
        first = [s["rss_kinds"][name] for s in timed
                 if name in s.get("rss_kinds", {}) and reference_s <= s["robot_s"] < reference_s + window_s]
        last = [s["rss_kinds"][name] for s in timed if name in s.get("rss_kinds", {}) and t1 - s["robot_s"] < window_s]
        if first and last:
            out[name] = [(kind, float(np.mean([k[kind] for k in first])), float(np.mean([k[kind] for k in last])))
                         for kind in ("anon", "file", "shmem")]
    return out


def wm_full_time(updates, memory_threshold):
    """Robot time (s since the first update) when Working Memory first held memory_threshold
    nodes (Rtabmap/MemoryThr: from then on every new node moves an old one to the database);
    None if it never did."""
    if not updates or memory_threshold <= 0:
        return None
    t0 = updates[0]["stamp"]
    for u in updates:
        if u["stats"].get("Memory/Working_memory_size/", 0) >= memory_threshold:
            return u["stamp"] - t0
    return None


def rss_growth(samples, reference_s, window_s=300.0):
    """Growth of resident memory after the reference robot time, per process.

    samples: [{"robot_s": s since the first update, "rss": {name: MB}}]. The baseline is the
    median RSS over the first window after reference_s; growth is the largest median of any
    later window over the baseline, minus one (window medians, so a single sample taken during
    a transient allocation does not decide). A window with fewer than half the samples of a
    full one (the run's last few, after the bag ends) joins the one before it: its median would
    be of a sample or two. Also the least-squares slope in MB per hour after the reference.
    {name: {baseline_mb, max_window_mb, final_mb, growth, slope_mb_per_h}}."""
    names = sorted({n for s in samples for n in s["rss"]})
    out = {}
    for name in names:
        points = [(s["robot_s"], s["rss"][name]) for s in samples
                  if s["rss"].get(name) is not None and s["robot_s"] is not None and s["robot_s"] >= reference_s]
        if len(points) < 2:
            continue
        windows = {}
        for t, mb in points:
            windows.setdefault(int((t - reference_s) // window_s), []).append(mb)
        full = max(len(v) for v in windows.values())
        merged = []
        for k in sorted(windows):
            if merged and len(windows[k]) < 0.5 * full:
                merged[-1] = merged[-1] + windows[k]
            else:
                merged.append(list(windows[k]))
        medians = [float(np.median(w)) for w in merged]
        baseline = medians[0]
        t = np.array([p[0] for p in points])
        y = np.array([p[1] for p in points])
        slope = float(np.polyfit(t / 3600.0, y, 1)[0]) if t.max() > t.min() else 0.0
        out[name] = {"baseline_mb": baseline, "max_window_mb": max(medians), "final_mb": float(points[-1][1]),
                     "growth": max(medians) / baseline - 1.0 if baseline > 0 else float("nan"),
                     "slope_mb_per_h": slope, "windows": len(medians)}
    return out


# ---------------------------------------------------------------- revisits and closures

def position_at(truth_stamps, truth_xy, stamp, tolerance=0.05):
    """Ground-truth (x, y) at `stamp` (nearest sample within tolerance seconds), or None."""
    if not len(truth_stamps):
        return None
    i = int(np.searchsorted(truth_stamps, stamp))
    best = min((j for j in (i - 1, i) if 0 <= j < len(truth_stamps)), key=lambda j: abs(truth_stamps[j] - stamp))
    return truth_xy[best] if abs(truth_stamps[best] - stamp) <= tolerance else None


def revisits(updates, truth, radius=1.0, min_age=60.0, grace_s=10.0):
    """Revisit episodes and whether RTAB-Map closed them.

    An update is at a revisit when the ground-truth robot position at its stamp is within
    `radius` of the position at an earlier update stamped more than `min_age` s before. An
    episode is a run of consecutive such updates. It counts as closed when an update of the
    episode, or of the `grace_s` seconds after it, carries a loop closure or a proximity link to
    a node stamped more than `min_age` s before that update (a link to a recent neighbour is
    odometry's job, not a revisit's). Returns {episodes, closed, fraction, updates_at_revisit,
    list: [{start_s, end_s, updates, closed}]}."""
    stamps = np.array(sorted(truth))
    xy = [truth[s] for s in stamps]
    node_stamp = {u["node"]: u["stamp"] for u in updates if u["node"] > 0}
    placed = [(u["stamp"], position_at(stamps, xy, u["stamp"])) for u in updates]
    placed = [(s, p) for s, p in placed if p is not None]
    pstamps = np.array([s for s, _ in placed])
    pxy = np.array([p for _, p in placed], dtype=float).reshape(-1, 2)
    flags = []
    for u in updates:
        p = position_at(stamps, xy, u["stamp"])
        n_old = int(np.searchsorted(pstamps, u["stamp"] - min_age)) if len(pstamps) else 0
        flags.append(p is not None and n_old > 0 and
                     bool(np.hypot(pxy[:n_old, 0] - p[0], pxy[:n_old, 1] - p[1]).min() <= radius))

    def closes(u):
        for target in (u["loop"], u["proximity"]):
            if target > 0 and target in node_stamp and node_stamp[target] < u["stamp"] - min_age:
                return True
        return False

    t0 = updates[0]["stamp"] if updates else 0.0
    episodes = []
    k = 0
    while k < len(updates):
        if not flags[k]:
            k += 1
            continue
        start = k
        while k < len(updates) and flags[k]:
            k += 1
        end_stamp = updates[k - 1]["stamp"]
        closed = False
        for u in updates[start:]:
            if u["stamp"] > end_stamp + grace_s or closed:
                break
            closed = closes(u)
        episodes.append({"start_s": updates[start]["stamp"] - t0, "end_s": end_stamp - t0,
                         "updates": k - start, "closed": closed})
    closed = sum(1 for e in episodes if e["closed"])
    return {"episodes": len(episodes), "closed": closed,
            "fraction": closed / len(episodes) if episodes else float("nan"),
            "updates_at_revisit": int(sum(flags)), "list": episodes}


# ---------------------------------------------------------------- sync drops

def yaw_of(q):
    """Yaw of a quaternion (x, y, z, w)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def still_since(a, b, linear, angular):
    """Whether odometry pose b ((x, y, yaw)) is within RGBD/LinearUpdate and RGBD/AngularUpdate of
    a: the node then skips the frame by design (no new node, no update published)."""
    if linear <= 0 and angular <= 0:
        return False
    d = math.hypot(b[0] - a[0], b[1] - a[1])
    turn = abs(math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))
    return d < linear and turn < angular


def sync_drops(frame_stamps, updates, odom, linear, angular, tolerance=0.005):
    """Frames of the bag that gave no SLAM update, split into skipped by design and dropped.

    frame_stamps: the stamps of the synchronised sensor set in the bag (one per frame);
    updates: the `info` messages the node published (stamp, stats), one per update;
    odom: {stamp: (x, y, yaw)} wheel odometry. A frame without update is skipped by design when
    the robot moved less than (linear, angular) since the last node (the node's RGBD/LinearUpdate
    and RGBD/AngularUpdate rule: an update flagged Memory/Small_movement added no node, so the
    last node stays the one before); otherwise it was dropped (a sync queue overflow, a refused
    frame or a lost message). Returns {frames, updates, skipped_still, dropped, drop_fraction,
    dropped_stamps}."""
    by_stamp = {}
    for u in updates:
        by_stamp[round(u["stamp"] / tolerance)] = u
    ostamps = np.array(sorted(odom))
    opose = [odom[s] for s in ostamps]

    def update_at(s):
        k = round(s / tolerance)
        return by_stamp.get(k) or by_stamp.get(k - 1) or by_stamp.get(k + 1)

    last_node_pose = None
    updated = skipped = 0
    dropped = []
    for s in sorted(frame_stamps):
        pose = position_at(ostamps, opose, s, tolerance=0.05)
        u = update_at(s)
        if u is not None:
            updated += 1
            if not u["stats"].get("Memory/Small_movement/", 0) and pose is not None:
                last_node_pose = pose
        elif pose is not None and last_node_pose is not None and still_since(last_node_pose, pose, linear, angular):
            skipped += 1
        else:
            dropped.append(s)
    frames = len(frame_stamps)
    expected = frames - skipped
    return {"frames": frames, "updates": updated, "skipped_still": skipped, "dropped": len(dropped),
            "drop_fraction": len(dropped) / expected if expected > 0 else float("nan"),
            "dropped_stamps": dropped}


# ---------------------------------------------------------------- durability

def acknowledged_nodes(infos):
    """Node ids the node acknowledged as durable: every id published on `info` up to the largest
    Memory/Durable_node_id received (the writer commits in order). infos: [{node, durable}]."""
    durable = int(max((i.get("durable", 0) or 0 for i in infos), default=0))
    ids = {i["node"] for i in infos if 0 < i["node"] <= durable}
    if durable > 0:
        ids.add(durable)
    return ids, durable


def lost_nodes(acknowledged, database_ids):
    return sorted(set(acknowledged) - set(database_ids))


# ---------------------------------------------------------------- goals

def goal_checks(figures, rss_limit=0.10, drop_limit=0.01):
    """[(name, passed, detail)] of the soak's goals."""
    growth = figures.get("rss_growth", {})
    worst = max((g["growth"] for g in growth.values()), default=float("nan"))
    checks = [
        ("RSS growth < %d%% after the reference time" % round(rss_limit * 100),
         bool(growth) and worst < rss_limit,
         ", ".join("%s %+.1f%% (%.0f -> max %.0f MB)" % (n, 100 * g["growth"], g["baseline_mb"], g["max_window_mb"])
                   for n, g in sorted(growth.items())) or "no RSS samples after the reference time"),
        ("zero crashes (node exits and respawns)", figures.get("crashes", 1) == 0,
         "%d crash(es), %d respawn(s)" % (figures.get("crashes", 0), figures.get("respawns", 0))),
        ("sync drops < %g%%" % (drop_limit * 100),
         figures.get("sync", {}).get("drop_fraction", 1.0) < drop_limit,
         "%d dropped of %d frames expected (%d skipped by design)" %
         (figures.get("sync", {}).get("dropped", -1),
          figures.get("sync", {}).get("frames", 0) - figures.get("sync", {}).get("skipped_still", 0),
          figures.get("sync", {}).get("skipped_still", 0))),
        ("0 nodes lost", figures.get("nodes_lost", 1) == 0 and figures.get("acknowledged", 0) > 0,
         "%d lost of %d acknowledged durable" % (figures.get("nodes_lost", -1), figures.get("acknowledged", 0))),
    ]
    return checks
