#!/usr/bin/env python3
"""`make soak`: hours of the simulator's robot through the real ROS pipeline, with memory
management on, watching for leaks, slowdowns, crashes, drops and lost nodes.

  1. rtabmap-sim's `long` scenario (a random tour of a 12-block building, laps and room visits,
     --duration seconds of robot time at 1 Hz RGB-D 320x240 + 2D laser + wheel odometry), made a
     bag by rtabmap-bag (no IMU: the node does not use it). Kept in OUTPUT/cache/ and reused
     by the next run with the same options.
  2. roscore on a free port, launch/soak.launch (the rtabmap node of demo_sim_robot.launch with
     Rtabmap/MemoryThr and Rtabmap/TimeThr set), `rosbag play --clock -r RATE`.
  3. While it plays: every --sample-period wall seconds, VmRSS of every node process of the
     launch (and its anonymous / file-backed split), the database size on disk and the
     simulated time; every `info` of the node.
  4. After: the database checked (rtabmap-info --check), every node acknowledged durable
     (Memory/Durable_node_id) looked up in it; revisits from the ground truth; sync drops from
     the bag's frames; the goals checked; OUTPUT/report.md, report.json, plots.

Run from a sourced catkin workspace (make soak does it)."""
import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.realpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tools", "demo"))
sys.path.insert(0, os.path.join(ROOT, "test"))
import demo_ros as ros  # noqa: E402
import soak_metrics as metrics  # noqa: E402
import soak_report as report  # noqa: E402

SENSOR_TOPICS = ("/camera/rgb/image_rect_color", "/camera/depth_registered/image_raw", "/camera/rgb/camera_info",
                 "/scan")
SIM_OPTIONS = ["--scenario", "long", "--rate", "1", "--width", "320", "--height", "240", "--no-stereo", "--no-urg",
               "--texture-size", "128"]
INFO_STATS = ("Timing/Total/ms", "Memory/Working_memory_size/", "Memory/Short_time_memory_size/",
              "Memory/Durable_node_id/", "Memory/Database_write_failed/", "Memory/Small_movement/",
              "Memory/Signatures_retrieved/", "Memory/RAM_usage/MB", "Memory/Local_graph_size/",
              "Memory/Heap_free/MB", "Memory/Database_memory_used/MB", "Memory/Grid_memory_used/MB",
              "Memory/Grid_nodes_resident/", "Memory/Grid_nodes_read_back/", "Memory/Grid_nodes_in_layers/",
              "Memory/Locations_memory_used/MB", "Memory/Vocabulary_memory_used/MB", "Memory/Vocabulary_index_points/",
              "Memory/RAM_estimated/MB", "Timing/Memory_release/ms")


def log(message):
    print("[soak] " + message, flush=True)


# ---------------------------------------------------------------- the bag

def read_frames(sim_dir):
    """Per frame of the simulator: stamp, odometry (x, y, yaw) and ground truth (x, y)."""
    frames = []
    with open(os.path.join(sim_dir, "frames.txt")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            frames.append({"stamp": v[1], "odom": (v[2], v[3], metrics.yaw_of(v[5:9]))})
    truth = {}
    with open(os.path.join(sim_dir, "groundtruth.txt")) as f:
        for line in f:
            if not line.startswith("#") and line.strip():
                v = [float(x) for x in line.split()]
                truth[round(v[0], 6)] = (v[1], v[2])
    for fr in frames:
        fr["truth"] = truth.get(round(fr["stamp"], 6))
    return frames


def simulator_key():
    """A hash of the simulator's sources (the same files as the SLAM tests' dataset key in
    rtabmap_core/CMakeLists.txt): a changed simulator makes a new bag, not a replay of the old."""
    digest = hashlib.sha1()
    for folder in ("rtabmap_core/include/rtabmap_core/sim", "rtabmap_core/src/sim", "rtabmap_core/tools/sim"):
        top = os.path.join(ROOT, folder)
        for name in sorted(os.listdir(top)) if os.path.isdir(top) else []:
            path = os.path.join(top, name)
            if os.path.isfile(path):
                with open(path, "rb") as f:
                    digest.update(hashlib.sha1(f.read()).hexdigest().encode())
    return digest.hexdigest()[:12]


def make_bag(cache, duration, run_log):
    """The long scenario's bag and its frames, from the cache when the options and the simulator
    match."""
    os.makedirs(cache, exist_ok=True)
    key = {"sim": SIM_OPTIONS, "duration": duration, "bag": "--no-imu", "simulator": simulator_key()}
    bag = os.path.join(cache, "long_%d.bag" % duration)
    meta_path = os.path.join(cache, "long_%d.json" % duration)
    if os.path.exists(bag) and os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
        if meta.get("key") == key:
            log("bag: reusing %s (%.1f GB, made in %.1f min)" % (bag, os.path.getsize(bag) / 1e9, meta["make_s"] / 60))
            return bag, meta
    started = time.time()
    sim_dir = os.path.join(cache, "sim")
    log("bag: simulating the long scenario (%d s of robot time, 1 Hz RGB-D 320x240 + laser)" % duration)
    ros.run_tool(["rtabmap-sim", "--json", *SIM_OPTIONS, "--duration", str(duration), "--overwrite",
                  "--output", sim_dir], run_log, timeout=7200)
    simulated = time.time()
    log("bag: converting to %s" % bag)
    ros.run_tool(["rtabmap-bag", "--json", "--format", "sim", "--no-imu", sim_dir, bag], run_log, timeout=7200)
    frames = read_frames(sim_dir)
    shutil.rmtree(sim_dir)
    meta = {"key": key, "frames": frames, "make_s": time.time() - started, "simulate_s": simulated - started,
            "convert_s": time.time() - simulated, "bytes": os.path.getsize(bag),
            "robot_s": frames[-1]["stamp"] - frames[0]["stamp"] if frames else 0.0,
            "topics": bag_topic_counts(bag)}
    with open(meta_path, "w") as f:
        json.dump(meta, f)
    meta["made_now"] = True
    log("bag: %d frames, %.0f s of robot time, %.1f GB, made in %.1f min" %
        (len(frames), meta["robot_s"], meta["bytes"] / 1e9, meta["make_s"] / 60))
    return bag, meta


def bag_topic_counts(bag):
    out = subprocess.run(["rosbag", "info", "--yaml", "--key", "topics", bag], capture_output=True, text=True,
                         check=True).stdout
    counts = {}
    for m in re.finditer(r"topic:\s*(\S+)\s*\n\s*type:.*\n\s*messages:\s*(\d+)", out):
        counts[m.group(1)] = int(m.group(2))
    return counts


# ---------------------------------------------------------------- watching the run

class Watcher:
    """The node's `info` messages, and a thread sampling the launch's node processes (VmRSS),
    the database size and the simulated time every `period` wall seconds."""

    def __init__(self, launch, database, period):
        import rospy
        from rtabmap_ros.msg import Info
        self.launch, self.database, self.period = launch, database, period
        self.updates, self.samples = [], []
        self.pids = {}  # node name -> every pid seen (a respawn shows as a second one)
        self.lock = threading.Lock()
        self.stop_event = threading.Event()
        self.rospy = rospy
        self.subscriber = rospy.Subscriber("/rtabmap/info", Info, self.on_info, queue_size=10000)
        self.thread = threading.Thread(target=self.sample_loop, daemon=True)
        self.thread.start()

    def on_info(self, msg):
        stats = dict(zip(msg.statsKeys, msg.statsValues))
        u = {"stamp": msg.header.stamp.to_sec(), "wall": time.time(), "node": msg.refId, "loop": msg.loopClosureId,
             "proximity": msg.proximityDetectionId,
             "stats": {k: v for k, v in stats.items() if k in INFO_STATS or k.startswith("Timing/")}}
        with self.lock:
            self.updates.append(u)

    def database_bytes(self):
        total = 0
        for suffix in ("", "-wal", "-journal"):
            try:
                total += os.path.getsize(self.database + suffix)
            except OSError:
                pass
        return total

    def sample(self):
        rss, kinds = {}, {}
        for pid in metrics.children(self.launch.process.pid):
            name = metrics.command_name(pid)
            mb = metrics.rss_mb(pid)
            if name is None or mb is None:
                continue
            rss[name] = mb
            kinds[name] = metrics.resident_kinds_mb(pid)
            self.pids.setdefault(name, [])
            if pid not in self.pids[name]:
                self.pids[name].append(pid)
        now = self.rospy.get_rostime().to_sec()
        with self.lock:
            wm = self.updates[-1]["stats"].get("Memory/Working_memory_size/") if self.updates else None
            n = len(self.updates)
        self.samples.append({"wall": time.time(), "sim": now if now > 0 else None, "rss": rss,
                             "rss_kinds": {n: k for n, k in kinds.items() if k is not None},
                             "db_bytes": self.database_bytes(), "wm": wm, "updates": n})

    def sample_loop(self):
        while not self.stop_event.wait(self.period):
            try:
                self.sample()
            except Exception as e:  # a sample lost is reported, the watch goes on
                log("sampling failed: %s" % e)

    def close(self):
        self.stop_event.set()
        self.thread.join()
        self.subscriber.unregister()


def crashes_in_log(path):
    """roslaunch's own words for a node that ended by itself: 'process has died' (any exit code,
    with or without respawn) and 'respawning'."""
    with open(path, errors="replace") as f:
        text = f.read()
    died = re.findall(r"process has died \[pid (\d+), exit code (-?\d+)", text)
    return {"died": [{"pid": int(p), "exit_code": int(c)} for p, c in died],
            "respawns": len(re.findall(r"respawning", text)),
            "escalated": len(re.findall(r"escalating to SIG(?:TERM|KILL)", text))}


def node_reported_losses(path):
    """The node's own count of lost input (rtabmap_sync's throttled 'input lost, about N set(s)'
    warning, DropCounter.h): the warnings logged and the last count. The harness counts drops
    from the bag; this says whether the node saw them too."""
    with open(path, errors="replace") as f:
        counts = [int(n) for n in re.findall(r"input lost, about (\d+) set\(s\)", f.read())]
    return {"warnings": len(counts), "sets_lost": counts[-1] if counts else 0}


def play_watched(bag, rate, watcher, run_log, robot_s):
    """rosbag play --clock -r rate; prints progress every few minutes."""
    with open(run_log, "a") as out:
        # -d: a pause after advertising each topic, so the node's subscriptions are connected
        # before the first frame (else the first frame is lost to the harness, not to the node).
        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-d", "0.5", "-r", str(rate), bag], stdout=out,
                                  stderr=subprocess.STDOUT, start_new_session=True)
    started = time.time()
    next_print = started + 300
    while player.poll() is None:
        time.sleep(1.0)
        if time.time() >= next_print:
            next_print += 300
            with watcher.lock:
                n = len(watcher.updates)
                last = watcher.updates[-1] if n else None
            s = watcher.samples[-1] if watcher.samples else {"rss": {}, "db_bytes": 0}
            log("%.0f min: %d updates, WM %s, RSS %s, database %.0f MB, %.0f%% of the bag" %
                ((time.time() - started) / 60, n, last["stats"].get("Memory/Working_memory_size/") if last else "-",
                 ", ".join("%s %.0f MB" % kv for kv in s["rss"].items()), s["db_bytes"] / 1e6,
                 100.0 * min(1.0, (time.time() - started) * rate / max(robot_s, 1.0))))
        if not watcher.launch.alive():
            log("the launch ended while the bag played: see %s" % run_log)
            ros.stop_process(player, 10.0)
            break
    return player.returncode, time.time() - started


# ---------------------------------------------------------------- after the run

def database_figures(database, run_log):
    r = subprocess.run(["rosrun", "rtabmap_ros", "rtabmap-info", "--json", "--check", database],
                       capture_output=True, text=True, timeout=1800)
    with open(run_log, "a") as out:
        out.write("$ rtabmap-info --json --check %s (exit %d)\n%s%s\n" % (database, r.returncode, r.stdout, r.stderr))
    lines = [l for l in r.stdout.splitlines() if l.startswith("{")]
    info = json.loads(lines[-1]) if lines else {}
    info["check_exit_code"] = r.returncode
    return info


def analyse(args, meta, recorded, database, run_log):
    import fault_common
    updates = sorted(recorded["updates"], key=lambda u: u["stamp"])
    samples = recorded["samples"]
    frames = meta["frames"]
    t0 = frames[0]["stamp"]
    figures = {"rate": args.rate, "duration_arg_s": args.duration, "robot_s": meta["robot_s"],
               "hours_replayed": meta["robot_s"] / 3600.0, "play_wall_s": recorded["play_wall_s"],
               "play_exit_code": recorded["play_exit_code"], "launch_exit_code": recorded["launch_exit_code"],
               "time_threshold_ms": args.time_threshold, "memory_threshold": args.memory_threshold,
               "bag_bytes": meta["bytes"], "bag_make_s": meta["make_s"], "bag_topics": meta["topics"],
               "updates": len(updates), "bag_made_now": meta.get("made_now", False),
               "revisit_radius": args.revisit_radius, "revisit_age": args.revisit_age,
               "revisit_grace": args.revisit_grace, "sample_period": args.sample_period, "window_s": args.window,
               "linear_update": args.linear_update, "angular_update": args.angular_update}
    for s in samples:
        s["robot_s"] = s["sim"] - t0 if s["sim"] else None
    # Memory: the reference is 20 min of robot time or Working Memory full, whichever is later.
    full = metrics.wm_full_time(updates, args.memory_threshold)
    if full is not None:
        full += updates[0]["stamp"] - t0
    figures["wm_full_robot_s"] = full
    figures["rss_reference_robot_s"] = max(1200.0, full if full is not None else 1200.0)
    figures["rss_growth"] = metrics.rss_growth(samples, figures["rss_reference_robot_s"])
    figures["update_time"] = metrics.percentiles([u["stats"]["Timing/Total/ms"] for u in updates
                                                  if "Timing/Total/ms" in u["stats"]], (50, 95, 99, 100))
    figures["update_time_windows"] = metrics.windowed_update_times(updates, args.window)
    figures["stages"] = metrics.stage_times(updates, 1200.0)
    figures["memory_breakdown"] = metrics.memory_breakdown(updates, figures["rss_reference_robot_s"])
    figures["resident_kinds"] = metrics.resident_kinds(samples, figures["rss_reference_robot_s"])
    wm = [u["stats"].get("Memory/Working_memory_size/", 0) for u in updates]
    figures["max_wm"] = int(max(wm)) if wm else 0
    # Crashes: roslaunch's reports, a node seen with a second pid, a node gone while playing.
    found = crashes_in_log(run_log)
    figures["crashes"] = len(found["died"])
    figures["died"] = found["died"]
    figures["respawns"] = found["respawns"] + sum(len(p) - 1 for p in recorded["pids"].values())
    figures["node_pids"] = recorded["pids"]
    figures["shutdown_escalated"] = found["escalated"]
    missing = [s for s in samples if s["sim"] and not s["rss"]]
    figures["sample_count"] = len(samples)
    figures["samples_without_node"] = len(missing)
    figures["crashes"] += 1 if missing and samples[-1] in missing else 0
    # Sync: the bag's frames against the node's updates.
    rules = {"linear": args.linear_update, "angular": args.angular_update}
    figures["sync"] = metrics.sync_drops([f["stamp"] for f in frames], updates,
                                         {f["stamp"]: f["odom"] for f in frames}, rules["linear"], rules["angular"])
    figures["sync"]["bag_sensor_messages"] = {t: meta["topics"].get(t, 0) for t in SENSOR_TOPICS}
    figures["sync"]["node_reported"] = node_reported_losses(run_log)
    t_first = updates[0]["stamp"] if updates else t0
    for row in figures["update_time_windows"]:  # where the drops happened
        row["dropped"] = sum(1 for s in figures["sync"]["dropped_stamps"]
                             if row["start_s"] <= s - t_first < row["end_s"])
    # Revisits from the ground truth.
    truth = {f["stamp"]: f["truth"] for f in frames if f["truth"] is not None}
    rv = metrics.revisits(updates, truth, radius=args.revisit_radius, min_age=args.revisit_age,
                          grace_s=args.revisit_grace)
    figures["revisits"] = {k: v for k, v in rv.items() if k != "list"}
    figures["revisit_episodes"] = rv["list"]
    figures["loop_closures_published"] = sum(1 for u in updates if u["loop"] > 0)
    figures["proximity_published"] = sum(1 for u in updates if u["proximity"] > 0)
    # Durability: every node acknowledged on info is in the database.
    db = database_figures(database, run_log)
    figures["database"] = db
    ids = fault_common.database_node_ids(database) if os.path.exists(database) else set()
    ack, durable = metrics.acknowledged_nodes([{"node": u["node"], "durable": u["stats"].get("Memory/Durable_node_id/", 0)}
                                               for u in updates])
    figures["acknowledged"] = len(ack)
    figures["durable_node_id"] = durable
    figures["nodes_in_db"] = len(ids)
    figures["nodes_published"] = len({u["node"] for u in updates if u["node"] > 0})
    lost = metrics.lost_nodes(ack, ids)
    figures["nodes_lost"] = len(lost)
    figures["lost_ids"] = lost[:50]
    figures["db_bytes"] = os.path.getsize(database) if os.path.exists(database) else 0
    figures["db_check_ok"] = db.get("check_exit_code") == 0
    figures["database_write_failed"] = int(max((u["stats"].get("Memory/Database_write_failed/", 0) for u in updates),
                                               default=0))
    return figures, updates


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--output", default=os.path.join(ROOT, "soak_output"))
    parser.add_argument("--rate", type=float, default=2.0,
                        help="rosbag play rate: 4 dropped 47%% of the frames in 2 h on this 2-core machine shared with "
                             "other builds (update time grows with the map), see the report")
    parser.add_argument("--duration", type=int, default=7200, help="robot seconds of the long scenario (at least)")
    parser.add_argument("--time-threshold", type=float,
                        help="Rtabmap/TimeThr (ms); default 80%% of the frame period at the replay rate (1 Hz frames: "
                             "800/RATE ms), the rest of the period left to the node's other work")
    parser.add_argument("--memory-threshold", type=int, default=400, help="Rtabmap/MemoryThr (nodes in WM)")
    parser.add_argument("--sample-period", type=float, default=10.0, help="wall seconds between RSS samples")
    parser.add_argument("--window", type=float, default=600.0, help="robot seconds per update-time window")
    parser.add_argument("--revisit-radius", type=float, default=1.0)
    parser.add_argument("--revisit-age", type=float, default=60.0)
    parser.add_argument("--revisit-grace", type=float, default=10.0)
    parser.add_argument("--bag-only", action="store_true", help="make (or check) the cached bag and stop")
    parser.add_argument("--linear-update", type=float, default=0.1, help="the node's RGBD/LinearUpdate (default)")
    parser.add_argument("--angular-update", type=float, default=0.1, help="the node's RGBD/AngularUpdate (default)")
    parser.add_argument("--reanalyse", action="store_true",
                        help="no run: analyse OUTPUT/recorded.json and the database of the last run again")
    args = parser.parse_args()
    if args.time_threshold is None:
        args.time_threshold = 800.0 / args.rate
    started = time.time()
    os.makedirs(args.output, exist_ok=True)
    run_log = os.path.join(args.output, "run.log")
    recorded_path = os.path.join(args.output, "recorded.json")
    database = os.path.join(args.output, "rtabmap.db")
    if args.reanalyse:
        with open(recorded_path) as f:
            recorded = json.load(f)
        vars(args).update(recorded["args"])
        _, meta = make_bag(os.path.join(args.output, "cache"), args.duration, run_log)
    else:
        open(run_log, "w").close()
        bag, meta = make_bag(os.path.join(args.output, "cache"), args.duration, run_log)
        if args.bag_only:
            return 0
        recorded = run(args, bag, meta, database, run_log)
        recorded["args"] = {k: v for k, v in vars(args).items() if k not in ("reanalyse", "bag_only", "output")}
        recorded["wall_s"] = time.time() - started
        with open(recorded_path, "w") as f:
            json.dump(recorded, f)
    log("analysing (database check, revisits, drops)")
    analysis_started = time.time()
    figures, updates = analyse(args, meta, recorded, database, run_log)
    figures["wall_s"] = recorded["wall_s"] + time.time() - analysis_started
    checks = metrics.goal_checks(figures)
    report.write(args.output, figures, checks, updates, recorded["samples"])
    for name, passed, detail in checks:
        log("%s  %s: %s" % ("PASS" if passed else "FAIL", name, detail))
    log("%.2f h replayed at rate %g in %.1f min (total %.1f min); update p50 %.0f ms, p99 %.0f ms; database %.0f MB, "
        "%d nodes, %d lost; revisits closed %d/%d" %
        (figures["hours_replayed"], args.rate, figures["play_wall_s"] / 60, figures["wall_s"] / 60,
         figures["update_time"]["p50"], figures["update_time"]["p99"], figures["db_bytes"] / 1e6,
         figures["nodes_in_db"], figures["nodes_lost"], figures["revisits"]["closed"], figures["revisits"]["episodes"]))
    log("report: %s (plots and run.log beside it)" % os.path.join(args.output, "report.md"))
    return 0 if all(c[1] for c in checks) else 1


def run(args, bag, meta, database, run_log):
    """The ROS part: master, launch, bag, watcher. What was seen, as plain data."""
    master = ros.Master(os.path.join(args.output, "roscore.log"))
    try:
        subprocess.run(["rosparam", "set", "/use_sim_time", "true"], check=True)
        import rospy
        rospy.init_node("rtabmap_soak", anonymous=True, disable_signals=True)
        launch = ros.Launch("soak.launch", {"database_path": database, "time_threshold": "%g" % args.time_threshold,
                                            "memory_threshold": str(args.memory_threshold)}, run_log)
        watcher = None
        try:
            ros.wait_for(lambda: service_up("/rtabmap/get_map") or not launch.alive(), 120.0)
            if not launch.alive():
                raise RuntimeError("the rtabmap node did not start, see %s" % run_log)
            watcher = Watcher(launch, database, args.sample_period)
            time.sleep(2.0)  # subscriptions connect
            log("playing %.0f s of robot time at rate %g (about %.0f min); RSS every %g s" %
                (meta["robot_s"], args.rate, meta["robot_s"] / args.rate / 60, args.sample_period))
            play_code, play_wall_s = play_watched(bag, args.rate, watcher, run_log, meta["robot_s"])
            ros.wait_quiet(lambda: len(watcher.updates), quiet=10.0, timeout=600.0, period=0.5)
            watcher.sample()
        finally:
            if watcher:
                watcher.close()  # before the launch stops: a sample of a node shutting down is no crash
            launch_code = launch.stop()
    finally:
        master.stop()
    return {"updates": watcher.updates, "samples": watcher.samples, "pids": watcher.pids,
            "launch_exit_code": launch_code, "play_exit_code": play_code, "play_wall_s": play_wall_s}


def service_up(name):
    return subprocess.run(["rosservice", "type", name], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL).returncode == 0


if __name__ == "__main__":
    sys.exit(main())
