#!/usr/bin/python3
"""bench-odom_nodes: the odometry nodes end to end on real data played from bags.

For each dataset found in the data folders (--data, ':'-separated, laid out as ../shared/data):
converts it with rtabmap-bag, starts a private ROS master, the node (rgbd_odometry,
stereo_odometry or icp_odometry, as the standalone wrapper) and `rosbag play --clock -r RATE`,
and prints: frames in the bag, odometry updates and lost frames, frames the node dropped
(it was busy), the registration time per update (median, p99, from odom_info), the node's CPU
time and peak memory, and the realtime factor (data seconds processed per wall second).
The last line is one JSON object with every figure."""
import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

DATASETS = [
    # name, rtabmap-bag format, relative path, node, remaps, params, frames (0 = all), rate
    ("aces", "carmen", "radish/aces.clf.bz2", "icp_odometry", ["scan:=/scan"],
     ["_odom_frame_id:=icp_odom", "_guess_frame_id:=odom", "_scan_voxel_size:=0.05",
      "_Icp/MaxCorrespondenceDistance:=0.1", "_Reg/Force3DoF:=true"], 2000, 5.0),
    ("7scenes", "7scenes", "rgbd_7scenes", "rgbd_odometry",
     ["rgb/image:=/camera/rgb/image_rect_color", "depth/image:=/camera/depth_registered/image_raw",
      "rgb/camera_info:=/camera/rgb/camera_info"], ["_approx_sync:=false"], 0, 1.0),
    ("euroc", "euroc", "euroc_v1_01_micro", "stereo_odometry",
     ["left/image_rect:=/stereo_camera/left/image_rect", "right/image_rect:=/stereo_camera/right/image_rect",
      "left/camera_info:=/stereo_camera/left/camera_info", "right/camera_info:=/stereo_camera/right/camera_info"],
     ["_approx_sync:=false"], 0, 1.0),
]


def free_port():
    with socket.socket() as s:
        s.bind(("", 0))
        return s.getsockname()[1]


def percentile(values, p):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(round(p / 100.0 * (len(v) - 1))))]


def process_figures(pid):
    """CPU seconds (user + system) and peak resident memory (MiB) of a live process."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    cpu = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    peak = 0.0
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                peak = int(line.split()[1]) / 1024.0
    return cpu, peak


def run(dataset, source, work):
    name, fmt, _, node, remaps, params, frames, rate = dataset
    import rosbag  # after ROS_MASTER_URI is set
    import rospy
    from nav_msgs.msg import Odometry
    from rtabmap_ros.msg import OdomInfo

    bag = os.path.join(work, name + ".bag")
    cmd = ["rosrun", "rtabmap_ros", "rtabmap-bag", "--json", "--no-imu", "--format", fmt]
    if frames:
        cmd += ["--max-frames", str(frames)]
    subprocess.run(cmd + [source, bag], check=True, capture_output=True, timeout=1800)
    with rosbag.Bag(bag) as b:
        info = b.get_type_and_topic_info().topics
        sensor = "/scan" if node == "icp_odometry" else (
            "/camera/rgb/image_rect_color" if node == "rgbd_odometry" else "/stereo_camera/left/image_rect")
        n_frames = info[sensor].message_count
        duration = b.get_end_time() - b.get_start_time()

    odoms, infos = [], []
    subs = [rospy.Subscriber(f"/{name}/odom", Odometry, odoms.append, queue_size=10000),
            rospy.Subscriber(f"/{name}/odom_info", OdomInfo, infos.append, queue_size=10000)]
    proc = subprocess.Popen(["rosrun", "rtabmap_ros", node, f"__ns:=/{name}", *remaps, *params],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        end = time.time() + 60
        while time.time() < end and subs[0].get_num_connections() == 0:
            time.sleep(0.1)
        cpu0, _ = process_figures(proc.pid)
        start = time.time()
        subprocess.run(["rosbag", "play", "--clock", "-q", "-r", str(rate), bag], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        last, n = time.time(), len(odoms)
        while time.time() - last < 3.0:  # wait for the node to catch up
            time.sleep(0.1)
            if len(odoms) != n:
                last, n = time.time(), len(odoms)
        wall = last - start
        cpu1, peak = process_figures(proc.pid)
    finally:
        proc.terminate()
        proc.wait(timeout=20)
        for s in subs:
            s.unregister()
    times = [i.timeEstimation * 1000.0 for i in infos]
    processed = (odoms[-1].header.stamp - odoms[0].header.stamp).to_sec() if len(odoms) > 1 else 0.0
    return {
        "dataset": name, "node": node, "frames": n_frames, "data_seconds": round(duration, 2), "rate": rate,
        "updates": len(odoms), "lost": sum(1 for o in odoms if o.pose.covariance[0] >= 9999.0),
        "dropped": n_frames - len(odoms),
        "registration_ms_median": round(percentile(times, 50), 2), "registration_ms_p99": round(percentile(times, 99), 2),
        "cpu_seconds": round(cpu1 - cpu0, 2), "cpu_percent": round(100.0 * (cpu1 - cpu0) / max(wall, 1e-9), 1),
        "peak_memory_mib": round(peak, 1),
        "realtime_factor": round(processed / max(wall, 1e-9), 2),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=os.environ.get("RTABMAP_DATA_DIR", ""),
                        help="data folders laid out as ../shared/data, separated by ':'")
    args = parser.parse_args()
    port = free_port()
    os.environ["ROS_MASTER_URI"] = f"http://localhost:{port}"
    master = subprocess.Popen(["roscore", "-p", str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    work = tempfile.mkdtemp(prefix="rtabmap_bench_odom_")
    results, skipped = [], []
    try:
        import rospy
        time.sleep(3.0)
        subprocess.run(["rosparam", "set", "/use_sim_time", "true"], check=True, timeout=30)
        rospy.init_node("odom_nodes_bench", anonymous=True)
        for d in DATASETS:
            source = next((os.path.join(r, d[2]) for r in args.data.split(":")
                           if r and os.path.exists(os.path.join(r, d[2]))), None)
            if source is None:
                print(f"{d[0]}: skipped (no {d[2]} in the data folders)")
                skipped.append(d[0])
                continue
            r = run(d, source, work)
            results.append(r)
            print(f"{r['dataset']} ({r['node']}, rosbag play -r {r['rate']:g}): {r['updates']} updates for "
                  f"{r['frames']} frames ({r['dropped']} dropped, {r['lost']} lost); registration "
                  f"{r['registration_ms_median']:.1f} ms median, {r['registration_ms_p99']:.1f} ms p99; "
                  f"CPU {r['cpu_percent']:.0f} %, peak memory {r['peak_memory_mib']:.0f} MiB; "
                  f"realtime factor {r['realtime_factor']:.2f}", flush=True)
    finally:
        master.terminate()
        master.wait(timeout=20)
        shutil.rmtree(work, ignore_errors=True)
    print(json.dumps({"bench": "odom_nodes", "results": results, "skipped": skipped}))
    return 0 if results else 1


if __name__ == "__main__":
    sys.exit(main())
