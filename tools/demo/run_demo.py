#!/usr/bin/env python3
"""`make demo`: RTAB-Map through the real ROS pipeline on bundled real data and the simulator.

  (a) The Intel Research Lab log (laser + wheel odometry): converted to a bag by rtabmap-bag,
      played with `rosbag play --clock`, mapped by the rtabmap node (launch/demo_intel.launch:
      odometry from tf, loops closed by laser proximity detection).
  (b) The simulator's multi-session robot (RGB-D camera + laser + wheel odometry): three bags of
      rtabmap-sim, one session each, the node restarted on the same database between them
      (launch/demo_sim_robot.launch): the sessions' maps merge when a place is recognised.

Writes OUTPUT/ (demo_output/ by default): per part the database, the grid (PGM + map_server
YAML + PNG), the trajectories (TUM), a trajectory plot, a timing plot; OUTPUT/report.md with the
figures. Run from a sourced catkin workspace (make demo does it)."""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_report as report  # noqa: E402
import demo_ros as ros  # noqa: E402

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def find_data(relative):
    """relative (e.g. radish/intel.clf.bz2) in $RTABMAP_DATA_DIR, ../shared/data or the
    repository's bundled data/."""
    roots = [os.environ.get("RTABMAP_DATA_DIR", ""), os.path.join(ROOT, "..", "shared", "data"),
             os.path.join(ROOT, "data")]
    for r in roots:
        if r and os.path.exists(os.path.join(r, relative)):
            return os.path.join(r, relative)
    return None


class Part:
    """One mapping run: a folder of outputs, a log, and what the recorder saw."""

    def __init__(self, output, name):
        self.name = name
        self.dir = os.path.join(output, name)
        os.makedirs(self.dir, exist_ok=True)
        self.log = os.path.join(self.dir, "run.log")
        open(self.log, "w").close()
        self.database = os.path.join(self.dir, "rtabmap.db")
        self.updates, self.odom, self.truth, self.figures = [], {}, {}, {}
        self.started = time.time()

    def path(self, name):
        return os.path.join(self.dir, name)

    def map_session(self, launch_file, launch_args, bag, rate):
        """One session: start the node, play the bag, wait until the node has caught up, stop
        the node (it closes the database)."""
        recorder = ros.Recorder("rtabmap")
        launch = ros.Launch(launch_file, launch_args, self.log)
        try:
            ros.wait_for(lambda: service_up("/rtabmap/get_map") or not launch.alive(), 60.0)
            if not launch.alive():
                raise RuntimeError("the rtabmap node did not start, see %s" % self.log)
            time.sleep(1.0)  # subscriptions connect
            ros.play(bag, rate, self.log, timeout=3600)
            recorder.wait_quiet(quiet=5.0)
        finally:
            code = launch.stop()
            recorder.close()
        if code not in (0, None, -2, 130):
            raise RuntimeError("roslaunch ended with %s, see %s" % (code, self.log))
        if not recorder.updates:
            raise RuntimeError("the rtabmap node made no SLAM update from %s, see %s" % (bag, self.log))
        self.updates += recorder.updates
        self.odom.update(recorder.odom)
        self.truth.update(recorder.truth)

    def export(self):
        """Grid (PGM + YAML + PNG) and optimised node poses from the database, as a user would."""
        ros.run_tool(["rtabmap-export", "--json", "--grid", self.path("grid.pgm"), "--poses",
                      self.path("poses.tum"), self.database], self.log, timeout=900)
        self.figures["database"] = ros.run_tool_json(["rtabmap-info", "--json", self.database], self.log, 300)
        self.poses = report.read_tum(self.path("poses.tum"))
        report.write_tum(self.path("odom.tum"), self.odom)
        if self.truth:
            report.write_tum(self.path("ground_truth.tum"), self.truth)

    def summarise(self, time_threshold_ms):
        db = self.figures["database"]
        links = db.get("links", {})
        self.figures.update({
            "nodes": db.get("nodes", 0), "sessions": db.get("session_count", 0),
            "loop_closures": links.get("GlobalClosure", 0),
            "proximity_links": links.get("LocalSpaceClosure", 0) + links.get("LocalTimeClosure", 0),
            "timing": report.timing_figures(self.updates), "time_threshold_ms": time_threshold_ms,
            "wall_s": time.time() - self.started,
            "database_mb": db.get("size_bytes", 0) / 1e6,
        })
        wm = [u["stats"]["Memory/Working_memory_size/"] for u in self.updates
              if "Memory/Working_memory_size/" in u["stats"]]
        self.figures["max_wm"] = int(max(wm)) if wm else 0
        report.plot_timing(self.path("timing.png"), "%s: SLAM update time" % self.name, self.updates,
                           time_threshold_ms)


def service_up(name):
    return subprocess.run(["rosservice", "type", name], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL).returncode == 0


def run_intel(output, work, rate, time_threshold_ms):
    source = find_data("radish/intel.clf.bz2")
    if not source:
        raise RuntimeError("radish/intel.clf.bz2 not found (data/ of the repository)")
    part = Part(output, "intel")
    bag = os.path.join(work, "intel.bag")
    print("[demo] intel: converting %s to a bag" % source, flush=True)
    ros.run_tool(["rtabmap-bag", "--json", "--format", "carmen", "--no-images", source, bag], part.log, 600)
    print("[demo] intel: mapping (rosbag play -r %g, about %.0f min)" % (rate, 45.0 / rate), flush=True)
    part.map_session("demo_intel.launch", {"database_path": part.database, "delete_db": "true",
                                           "time_threshold": "%g" % time_threshold_ms}, bag, rate)
    part.export()
    part.summarise(time_threshold_ms)
    # Intel has no relations, but posegraphs/intel.g2o (../shared/data) is a pose graph others
    # built from the same log: at its optimum, its path is an independent map of the run, and
    # rtabmap-eval path measures how far the map's nodes (and the wheel odometry) are from it.
    graph = find_data("posegraphs/intel.g2o")
    if graph:
        reference = part.path("intel_g2o_optimum.g2o")
        ros.run_tool_json(["rtabmap-g2o", "--json", "--iterations", "100", graph, reference], part.log, 300)
        for name, est in (("path_slam", "poses.tum"), ("path_odom", "odom.tum")):
            part.figures[name] = ros.run_tool_json(["rtabmap-eval", "path", "--json", "--ref", reference,
                                                    "--est", part.path(est)], part.log, 300)
    # The wheel odometry starts where the map starts (the first node is the map's origin).
    report.plot_trajectories(part.path("trajectory.png"), "Intel Research Lab: RTAB-Map vs wheel odometry",
                             [("wheel odometry", report.with_breaks(part.odom), "-"),
                              ("RTAB-Map (optimised nodes)", report.with_breaks(part.poses), "-")])
    return part


def run_sim(output, work, rate, time_threshold_ms):
    part = Part(output, "sim_multisession")
    sim_dir = os.path.join(work, "sim")
    print("[demo] simulator: rendering the multi-session scenario (3 sessions, RGB-D + laser)", flush=True)
    ros.run_tool(["rtabmap-sim", "--json", "--scenario", "multisession", "--rate", "2", "--width", "320",
                  "--height", "240", "--no-stereo", "--no-urg", "--texture-size", "128", "--overwrite",
                  "--output", sim_dir, "--bag", os.path.join(work, "sim.bag")], part.log, 1200)
    sessions = sorted(f for f in os.listdir(work) if f.startswith("sim_session") and f.endswith(".bag"))
    if not sessions:
        raise RuntimeError("rtabmap-sim wrote no session bag, see %s" % part.log)
    per_session = []
    for i, bag in enumerate(sessions):
        print("[demo] simulator: session %d/%d (rosbag play -r %g)" % (i + 1, len(sessions), rate), flush=True)
        before = len(part.updates)
        # The first session starts a new database; the others continue it (multi-session).
        part.map_session("demo_sim_robot.launch", {"database_path": part.database,
                                                   "delete_db": "true" if i == 0 else "false",
                                                   "time_threshold": "%g" % time_threshold_ms},
                         os.path.join(work, bag), rate)
        per_session.append(part.updates[before:])
    part.export()
    part.summarise(time_threshold_ms)
    result = report.ate(part.poses, part.truth)
    odom_ates, node_ates = [], []
    for updates in per_session:  # each session's odometry starts at its own origin
        stamps = {u["stamp"] for u in updates}
        odom = {s: xy for s, xy in part.odom.items() if s in stamps}
        r = report.ate(odom, part.truth)
        if r:
            odom_ates.append(r["rmse"])
        # The session's optimised nodes alone: tells a wrong merge between sessions (the
        # one-alignment ATE above) from a session that is wrong in itself.
        first, last = (updates[0]["stamp"] - 1, updates[-1]["stamp"] + 1) if updates else (0, -1)
        r = report.ate({s: xy for s, xy in part.poses.items() if first <= s <= last}, part.truth)
        if r:
            node_ates.append(r["rmse"])
    part.figures["ate_rmse"] = result["rmse"] if result else None
    part.figures["ate_poses"] = result["poses"] if result else 0
    part.figures["odom_ate_rmse_per_session"] = odom_ates
    part.figures["ate_rmse_per_session"] = node_ates
    curves = [("ground truth", report.with_breaks(part.truth), "-")]
    if result:
        for i, updates in enumerate(per_session):
            stamps = sorted(s for s in part.poses if updates and updates[0]["stamp"] - 1 <= s <= updates[-1]["stamp"] + 1)
            aligned = [tuple(result["r"] @ part.poses[s] + result["t"]) for s in stamps]
            curves.append(("RTAB-Map session %d (aligned)" % (i + 1), aligned, ".-"))
    report.plot_trajectories(part.path("trajectory.png"), "Simulator, 3 sessions: RTAB-Map vs ground truth", curves)
    return part


def write_report(output, parts, total_s):
    lines = ["# RTAB-Map demo", "",
             "RTAB-Map through the real ROS pipeline (`rosbag play --clock`, the `rtabmap` node, its "
             "launch files) on bundled real data and on the simulator. Made by `make demo` in %.1f min." % (total_s / 60),
             ""]
    for p in parts:
        f = p.figures
        t = f["timing"]
        lines += ["## %s" % p.name, "",
                  "| figure | value |", "|---|---|",
                  "| nodes in the map | %d |" % f["nodes"],
                  "| sessions in the database (a map id each; linked maps share one referential) | %d |" % f["sessions"],
                  "| loop closures (appearance) | %d |" % f["loop_closures"],
                  "| proximity links (laser) | %d |" % f["proximity_links"],
                  "| SLAM updates | %d |" % t["updates"],
                  "| update time median / p95 / p99 / max | %.1f / %.1f / %.1f / %.1f ms |" %
                  (t["median_ms"], t["p95_ms"], t["p99_ms"], t["max_ms"]),
                  "| time budget (Rtabmap/TimeThr) | %s |" % ("%g ms" % f["time_threshold_ms"] if f["time_threshold_ms"] > 0 else "none"),
                  "| largest Working Memory | %d nodes |" % f["max_wm"],
                  "| database size | %.1f MB |" % f["database_mb"],
                  "| wall time of this part | %.1f min |" % (f["wall_s"] / 60)]
        if "path_slam" in f:
            d, o = f["path_slam"], f["path_odom"]
            lines.append("| deviation of the nodes from the path of intel.g2o's optimum (an independent map of "
                         "the log; `rtabmap-eval path`) median / p99 / max | %.3f / %.3f / %.3f m (wheel "
                         "odometry median %.2f m) |" % (d["deviation"]["median"], d["p99"], d["deviation"]["max"],
                                                        o["deviation"]["median"]))
        if "ate_rmse" in f:
            lines.append("| ATE RMSE of the nodes vs ground truth (all sessions, one alignment) | %s |" %
                         ("%.3f m over %d nodes" % (f["ate_rmse"], f["ate_poses"]) if f["ate_rmse"] is not None else "n/a"))
            lines.append("| ATE RMSE of the nodes, each session aligned on its own | %s |" %
                         ", ".join("%.3f m" % a for a in f["ate_rmse_per_session"]))
            lines.append("| ATE RMSE of the wheel odometry, each session aligned on its own | %s |" %
                         ", ".join("%.3f m" % a for a in f["odom_ate_rmse_per_session"]))
        lines += ["", "Files in `%s/`: `rtabmap.db` (open with `rtabmap-info`, `rtabmap-export`, or "
                      "`roslaunch rtabmap_ros rtabmap.launch database_path:=... localization:=true`), "
                      "`grid.pgm` + `grid.yaml` (`rosrun map_server map_server grid.yaml`), `poses.tum`, "
                      "`odom.tum`, `run.log`." % p.name, "",
                  "![grid](%s/grid.png)" % p.name, "", "![trajectory](%s/trajectory.png)" % p.name, "",
                  "![timing](%s/timing.png)" % p.name, ""]
    with open(os.path.join(output, "report.md"), "w") as f:
        f.write("\n".join(lines))
    with open(os.path.join(output, "report.json"), "w") as f:
        json.dump({p.name: p.figures for p in parts}, f, indent=2, default=str)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--output", default=os.path.join(ROOT, "demo_output"))
    parser.add_argument("--intel-rate", type=float, default=6.0, help="rosbag play rate of the Intel log")
    parser.add_argument("--sim-rate", type=float, default=3.0, help="rosbag play rate of the simulator sessions")
    parser.add_argument("--intel-time-threshold", type=float, default=200.0,
                        help="Rtabmap/TimeThr (ms) of the Intel run: memory management's time budget (0 = none); "
                             "an update over it moves the oldest nodes of Working Memory to the database")
    parser.add_argument("--sim-time-threshold", type=float, default=0.0,
                        help="Rtabmap/TimeThr (ms) of the simulator's sessions (0 = none)")
    parser.add_argument("--only", choices=["intel", "sim"], help="run one part only")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    work = os.path.join(args.output, "work")
    os.makedirs(work, exist_ok=True)
    started = time.time()
    master = ros.Master(os.path.join(args.output, "roscore.log"))
    parts = []
    try:
        subprocess.run(["rosparam", "set", "/use_sim_time", "true"], check=True)
        import rospy
        rospy.init_node("rtabmap_demo", anonymous=True, disable_signals=True)
        if args.only in (None, "intel"):
            parts.append(run_intel(args.output, work, args.intel_rate, args.intel_time_threshold))
        if args.only in (None, "sim"):
            parts.append(run_sim(args.output, work, args.sim_rate, args.sim_time_threshold))
    finally:
        master.stop()
    write_report(args.output, parts, time.time() - started)
    subprocess.run(["rm", "-rf", work])
    print("[demo] done in %.1f min. Report: %s" % ((time.time() - started) / 60, os.path.join(args.output, "report.md")))
    for p in parts:
        print("[demo]   %s: %d nodes, %d loop closures, %d proximity links, update median %.0f ms; map %s" %
              (p.name, p.figures["nodes"], p.figures["loop_closures"], p.figures["proximity_links"],
               p.figures["timing"]["median_ms"], p.path("grid.png")))


if __name__ == "__main__":
    main()
