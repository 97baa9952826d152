#!/usr/bin/env python3
"""bench-ros (`make bench`): the nodes end to end on bags, as a robot runs them.

  sim   the simulator's `loop` robot (RGB-D 320x240 + 2D laser at 2 Hz, wheel odometry in tf),
        launch/demo_sim_robot.launch with Rtabmap/DetectionRate 0 (every synchronised set is an
        update, so a set without update was dropped or skipped by design), played at -r 1 and
        -r 5;
  rgbd  7-Scenes (600 RGB-D frames at 30 Hz, ../shared/data), launch/demo_rgbd.launch
        (rgbd_odometry + rtabmap), played at -r 1: a live camera's rate.

Printed per run: SLAM update time (Timing/Total/ms: median, p99), odometry time per frame
(odom_info timeEstimation) and the frames it kept up with, CPU (% of one core over the replay)
and resident memory (peak) of each node process, sync drops (frames of the bag without an
update, less the ones the node skips by design because the robot did not move:
RGBD/LinearUpdate / AngularUpdate), and the realtime factor: seconds of bag processed per wall
second, from the start of the replay to the last update (at -r 5 a node that keeps up gives ~5).
A final JSON line has every figure; OUTPUT/ros_bench.json too."""
import argparse
import json
import os
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.realpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "demo"))
sys.path.insert(0, os.path.join(ROOT, "tools", "soak"))
import demo_ros as ros  # noqa: E402  (private roscore, roslaunch, rosbag play)
import soak_metrics as metrics  # noqa: E402  (process memory, percentiles, sync drops)

CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    """utime + stime of a process in seconds, None when it is gone."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS
    except (OSError, IndexError, ValueError):
        return None


class ProcessSampler(threading.Thread):
    """Every `period` s: CPU time and VmRSS of each node process roslaunch started."""

    def __init__(self, launch_pid, period=0.5):
        super().__init__(daemon=True)
        self.launch_pid, self.period = launch_pid, period
        self.samples = {}  # name -> [(wall, cpu_s, rss_mb)]
        self.stopped = threading.Event()

    def run(self):
        while not self.stopped.is_set():
            now = time.time()
            for pid in metrics.children(self.launch_pid):
                cpu, rss = cpu_seconds(pid), metrics.rss_mb(pid)
                if cpu is not None and rss is not None:
                    self.samples.setdefault(metrics.command_name(pid), []).append((now, cpu, rss))
            self.stopped.wait(self.period)

    def usage(self, start, end):
        """{name: {cpu_percent, rss_peak_mb}} over the wall window [start, end]."""
        out = {}
        for name, s in self.samples.items():
            inside = [x for x in s if start <= x[0] <= end] or s[-1:]
            first, last = inside[0], inside[-1]
            span = last[0] - first[0]
            out[name] = {"cpu_percent": round(100.0 * (last[1] - first[1]) / span, 1) if span > 0 else float("nan"),
                         "rss_peak_mb": round(max(x[2] for x in s), 1)}
        return out


class Listener:
    """info of the rtabmap node, odom_info of an odometry node, the bag's wheel odometry."""

    def __init__(self, namespace):
        import rospy
        from nav_msgs.msg import Odometry
        from rtabmap_ros.msg import Info, OdomInfo
        self.updates, self.odom_infos, self.odom = [], [], {}
        self.subscribers = [
            rospy.Subscriber("/%s/info" % namespace, Info, self.on_info, queue_size=1000),
            rospy.Subscriber("/%s/odom_info" % namespace, OdomInfo, self.on_odom_info, queue_size=1000),
            rospy.Subscriber("/odom", Odometry, self.on_odom, queue_size=1000),
        ]

    def on_info(self, msg):
        stats = dict(zip(msg.statsKeys, msg.statsValues))
        self.updates.append({"stamp": msg.header.stamp.to_sec(), "wall": time.time(),
                             "stats": {k: stats[k] for k in ("Timing/Total/ms", "Memory/Small_movement/") if k in stats}})

    def on_odom_info(self, msg):
        self.odom_infos.append({"stamp": msg.header.stamp.to_sec(), "wall": time.time(),
                                "ms": 1000.0 * msg.timeEstimation, "lost": msg.lost})

    def on_odom(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.odom[msg.header.stamp.to_sec()] = (p.x, p.y, metrics.yaw_of((q.x, q.y, q.z, q.w)))

    def last_wall(self):
        walls = [u["wall"] for u in self.updates] + [o["wall"] for o in self.odom_infos]
        return max(walls) if walls else None

    def count(self):
        return len(self.updates) + len(self.odom_infos)

    def close(self):
        for s in self.subscribers:
            s.unregister()


def bag_frames(bag, topic):
    import rosbag
    with rosbag.Bag(bag) as b:
        stamps = [m.header.stamp.to_sec() for _, m, _ in b.read_messages(topics=[topic])]
    return stamps


def run_once(name, launch_file, launch_args, private, bag, frame_topic, rate, out, log, update_rules):
    """One replay: returns its figures."""
    import rospy
    for key, value in private.items():
        rospy.set_param(key, value)
    listener = Listener("rtabmap")
    launch = ros.Launch(launch_file, launch_args, log)
    try:
        ros.wait_for(lambda: any(t.startswith("/rtabmap/") for t, _ in rospy.get_published_topics()), 60.0,
                     "%s: the nodes did not come up (see %s)" % (name, log))
        time.sleep(3.0)  # subscriptions connected
        sampler = ProcessSampler(launch.process.pid)
        sampler.start()
        frames = bag_frames(bag, frame_topic)
        duration = frames[-1] - frames[0] if len(frames) > 1 else 0.0
        started = time.time()
        ros.play(bag, rate, log, timeout=3600)
        ros.wait_quiet(listener.count, quiet=5.0, timeout=300.0)
        ended = listener.last_wall() or time.time()
        sampler.stopped.set()
        sampler.join()
        crashed = not launch.alive()
    finally:
        code = launch.stop()
        listener.close()
        for key in private:  # the next scenario starts from its own launch file's parameters
            if rospy.has_param(key):
                rospy.delete_param(key)
    slam_ms = [u["stats"]["Timing/Total/ms"] for u in listener.updates if "Timing/Total/ms" in u["stats"]]
    odom_ms = [o["ms"] for o in listener.odom_infos if not o["lost"]]
    figures = {"scenario": name, "rate": rate, "bag_s": round(duration, 1), "frames": len(frames),
               "wall_s": round(ended - started, 1),
               "realtime_factor": round(duration / (ended - started), 2) if ended > started else float("nan"),
               "slam_updates": len(listener.updates), "slam_ms": metrics.percentiles(slam_ms, (50, 99)),
               "processes": sampler.usage(started, ended), "crashed": crashed, "exit_code": code}
    if odom_ms or listener.odom_infos:
        figures["odom_updates"] = len(listener.odom_infos)
        figures["odom_ms"] = metrics.percentiles(odom_ms, (50, 99))
        figures["odom_frames_fraction"] = round(len(listener.odom_infos) / max(1, len(frames)), 3)
    if update_rules is not None:
        drops = metrics.sync_drops(frames, listener.updates, listener.odom, *update_rules)
        drops.pop("dropped_stamps", None)
        figures["sync"] = drops
    return figures


def show(f):
    s = f["slam_ms"]
    line = ("%-5s -r %-4g %5.0f s of bag in %5.0f s wall: realtime factor %.2f; SLAM %d updates, median %.1f ms, "
            "p99 %.1f ms" % (f["scenario"], f["rate"], f["bag_s"], f["wall_s"], f["realtime_factor"],
                             f["slam_updates"], s.get("p50", float("nan")), s.get("p99", float("nan"))))
    if "odom_ms" in f:
        o = f["odom_ms"]
        line += "; odometry %d of %d frames (%.0f%%), median %.1f ms, p99 %.1f ms" % (
            f["odom_updates"], f["frames"], 100 * f["odom_frames_fraction"], o.get("p50", float("nan")),
            o.get("p99", float("nan")))
    print(line)
    if "sync" in f:
        d = f["sync"]
        print("      sync: %d frames, %d updates, %d skipped by design (robot still), %d dropped (%.2f%%)"
              % (d["frames"], d["updates"], d["skipped_still"], d["dropped"], 100 * d["drop_fraction"]))
    for name, p in sorted(f["processes"].items()):
        print("      %-20s CPU %5.1f%% of a core, RSS peak %6.1f MB" % (name, p["cpu_percent"], p["rss_peak_mb"]))
    if f["crashed"]:
        print("      a node died during the replay (exit %s)" % f["exit_code"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default=os.path.join(ROOT, "build", "bench_output", "ros"))
    parser.add_argument("--data", default=os.environ.get("RTABMAP_DATA_DIR", os.path.join(ROOT, "..", "shared", "data")))
    parser.add_argument("--sim-duration", type=float, default=240.0, help="robot seconds of the sim bag")
    parser.add_argument("--sim-rates", default="1,5")
    parser.add_argument("--rgbd-rates", default="1")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    log = os.path.join(args.output, "run.log")
    open(log, "w").close()
    master = ros.Master(os.path.join(args.output, "roscore.log"))
    results = []
    try:
        import rospy
        rospy.init_node("ros_bench", anonymous=True, disable_signals=True)
        sim_bag = os.path.join(args.output, "sim_loop.bag")
        if not os.path.exists(sim_bag):
            ros.run_tool(["rtabmap-sim", "--json", "--scenario", "loop", "--rate", "2", "--width", "320", "--height",
                          "240", "--no-stereo", "--no-urg", "--duration", str(args.sim_duration), "--output",
                          os.path.join(args.output, "sim"), "--bag", sim_bag], log, timeout=900)
        for rate in [float(r) for r in args.sim_rates.split(",") if r]:
            f = run_once("sim", "demo_sim_robot.launch",
                         {"database_path": os.path.join(args.output, "sim.db"), "delete_db": "true"},
                         {"/rtabmap/rtabmap/Rtabmap/DetectionRate": "0"}, sim_bag,
                         "/camera/rgb/image_rect_color", rate, args.output, log, (0.1, 0.1))
            show(f)
            results.append(f)
        scenes = os.path.join(args.data, "rgbd_7scenes")
        if os.path.isdir(scenes):
            rgbd_bag = os.path.join(args.output, "7scenes.bag")
            if not os.path.exists(rgbd_bag):
                ros.run_tool(["rtabmap-bag", "--json", "--format", "7scenes", "--no-imu", scenes, rgbd_bag], log,
                             timeout=600)
            for rate in [float(r) for r in args.rgbd_rates.split(",") if r]:
                f = run_once("rgbd", "demo_rgbd.launch",
                             {"database_path": os.path.join(args.output, "rgbd.db"), "delete_db": "true"}, {},
                             rgbd_bag, "/camera/rgb/image_rect_color", rate, args.output, log, None)
                show(f)
                results.append(f)
        else:
            print("rgbd: skipped (%s absent)" % scenes)
    finally:
        master.stop()
    with open(os.path.join(args.output, "ros_bench.json"), "w") as out:
        json.dump(results, out, indent=1)
    print(json.dumps({"ros_bench": results}))
    return 1 if any(f["crashed"] for f in results) else 0


if __name__ == "__main__":
    sys.exit(main())
