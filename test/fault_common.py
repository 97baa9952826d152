"""Helpers shared by the fault-injection rostest checks (test/fault_*_check.py): a simulator bag
made at test time, the rtabmap SLAM node run as a child process (so a check can SIGKILL it,
restart it, or limit what it may write), and reading its database from outside."""
import hashlib
import json
import os
import signal
import sqlite3
import subprocess
import time

import rosgraph
import rospy

PKG = "rtabmap_ros"
NODE = "rtabmap"  # the node's name: its private parameters live under /rtabmap

# The slam_rtabmap rostest's configuration (2D laser + RGB-D simulator, wheel odometry in tf).
SLAM_PARAMETERS = {
    "subscribe_depth": True,
    "subscribe_scan": True,
    "approx_sync": False,
    "frame_id": "base_link",
    "odom_frame_id": "odom",
    "wait_for_transform_duration": 0.5,
    "Rtabmap/DetectionRate": "1",
    "RGBD/CreateOccupancyGrid": "true",
    "Grid/Sensor": "0",
    "Reg/Strategy": "2",
    "Reg/Force3DoF": "true",
    "RGBD/ProximityPathMaxNeighbors": "5",
    "RGBD/MaxLoopClosureDistance": "2",
    "Icp/VoxelSize": "0.05",
    "Icp/PointToPlane": "true",
    "Icp/CorrespondenceRatio": "0.3",
    "Icp/MaxCorrespondenceDistance": "0.3",
    "Icp/Iterations": "50",
}
REMAPS = ["rgb/image:=/camera/rgb/image_rect_color", "depth/image:=/camera/depth_registered/image_raw",
          "rgb/camera_info:=/camera/rgb/camera_info"]
CAMERA_TOPICS = ("/camera/rgb/image_rect_color", "/camera/depth_registered/image_raw", "/camera/rgb/camera_info")


def make_sim_bag(test, folder, duration, start_stamp=1700000000, scenario="loop"):
    """A bag of the simulator (2 Hz RGB-D 160x120 + 2D laser + wheel odometry in tf), as the
    slam_rtabmap rostest makes it."""
    bag = os.path.join(folder, scenario + ".bag")
    r = subprocess.run(["rosrun", PKG, "rtabmap-sim", "--scenario", scenario, "--rate", "2", "--width", "160",
                        "--height", "120", "--no-stereo", "--no-urg", "--texture-size", "64",
                        "--duration", str(duration), "--start-stamp", str(start_stamp),
                        "--output", os.path.join(folder, "sim"), "--bag", bag],
                       capture_output=True, text=True, timeout=240)
    test.assertEqual(r.returncode, 0, r.stdout + r.stderr)
    return bag


class SlamNode:
    """The rtabmap node (standalone executable) as a child process, its output in a log file.
    `shell_prefix` is a bash snippet run before exec'ing the node (the equivalent of a
    roslaunch launch-prefix, e.g. "ulimit -f 64")."""

    def __init__(self, folder, database_path, parameters=None, shell_prefix=""):
        self.folder = folder
        self.database_path = database_path
        self.parameters = dict(SLAM_PARAMETERS)
        self.parameters.update(parameters or {})
        self.shell_prefix = shell_prefix
        self.process = None
        self.log_path = None
        self.runs = 0

    def start(self, args=()):
        if rospy.has_param("/" + NODE):
            rospy.delete_param("/" + NODE)
        for key, value in self.parameters.items():
            rospy.set_param("/%s/%s" % (NODE, key), value)
        rospy.set_param("/%s/database_path" % NODE, self.database_path)
        self.runs += 1
        self.log_path = os.path.join(self.folder, "rtabmap_run%d.log" % self.runs)
        command = ["rosrun", PKG, "rtabmap", "__name:=" + NODE, *REMAPS, *args]
        if self.shell_prefix:
            command = ["bash", "-c", self.shell_prefix + '; exec "$0" "$@"', *command]
        with open(self.log_path, "w") as log:
            # rosrun execs the node: the pid is the node's (SIGKILL reaches it, not a wrapper).
            self.process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
        return self.process

    def wait_ready(self, service="/list_labels", timeout=30.0):
        """The node is up when its services are advertised (after the core opened the database)
        and the master lists it as a subscriber of the bag's sensor topics and tf: the node
        subscribes after advertising its services, and a bag played in between (a loaded
        machine) would map nothing."""
        rospy.wait_for_service(service, timeout=timeout)
        wanted = {"/tf"}
        if self.parameters.get("subscribe_depth"):
            wanted |= set(CAMERA_TOPICS)
        if self.parameters.get("subscribe_scan"):
            wanted.add("/scan")
        master = rosgraph.Master("/fault_common")
        deadline = time.time() + timeout
        while True:
            _, subscribers, _ = master.getSystemState()
            missing = wanted - {topic for topic, nodes in subscribers if "/" + NODE in nodes}
            if not missing:
                return
            if time.time() > deadline or not self.alive():
                raise AssertionError("the rtabmap node did not subscribe to %s within %.0f s" %
                                     (", ".join(sorted(missing)), timeout))
            time.sleep(0.05)

    def alive(self):
        return self.process is not None and self.process.poll() is None

    def kill(self, sig=signal.SIGKILL, timeout=30.0):
        """Sends sig and waits for the process to end; returns its exit status."""
        if self.alive():
            self.process.send_signal(sig)
        try:
            return self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            return self.process.wait()

    def log(self):
        with open(self.log_path, errors="replace") as f:
            return f.read()


def tool(name, *args, timeout=120):
    """rosrun rtabmap_ros <name> --json args: (exit code, the JSON summary or None, output)."""
    r = subprocess.run(["rosrun", PKG, name, "--json", *args], capture_output=True, text=True, timeout=timeout)
    lines = [l for l in r.stdout.splitlines() if l.startswith("{")]
    summary = None
    if lines:
        try:
            summary = json.loads(lines[-1])
        except ValueError:
            pass
    return r.returncode, summary, r.stdout + r.stderr


def database_node_ids(path):
    """Node ids in the database file, read by SQLite itself (read-only; the WAL, if a killed
    writer left one, is part of the database)."""
    with sqlite3.connect("file:%s?mode=ro" % path, uri=True) as c:
        return {row[0] for row in c.execute("SELECT id FROM Node")}


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def stat(info, key, default=None):
    """A statistic of an Info message by name (e.g. "Loop/Map_id"; keys end with "/unit")."""
    for k, v in zip(info.statsKeys, info.statsValues):
        if k == key or k.startswith(key + "/"):
            return v
    return default
