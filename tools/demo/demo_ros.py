"""The ROS side of `make demo`: a private ROS master, bag conversion, launching the rtabmap node,
playing a bag with --clock, and recording what the node publishes while it maps."""
import json
import os
import signal
import socket
import subprocess
import time

PKG = "rtabmap_ros"


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


class Master:
    """roscore on a free port of its own, so the demo never talks to a robot's master. The
    environment of this process (and of every child) points at it while it runs."""

    def __init__(self, log_path):
        self.port = free_port()
        os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % self.port
        self.log = open(log_path, "w")
        self.process = subprocess.Popen(["roscore", "-p", str(self.port)], stdout=self.log,
                                        stderr=subprocess.STDOUT, start_new_session=True)
        wait_for(self.is_up, 30.0, "roscore did not start (see %s)" % log_path)

    def is_up(self):
        return subprocess.run(["rosparam", "get", "/rosdistro"], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL).returncode == 0

    def stop(self):
        stop_process(self.process, 15.0)
        self.log.close()


def wait_for(predicate, timeout, error=None):
    end = time.time() + timeout
    while time.time() < end:
        if predicate():
            return True
        time.sleep(0.2)
    if error:
        raise RuntimeError(error)
    return False


def wait_quiet(count, quiet, timeout, period=0.2):
    """Waits until count() (messages received so far) has not changed for `quiet` seconds, or
    `timeout` seconds in all: the node processed what it had queued."""
    end = time.time() + timeout
    n, since = count(), time.time()
    while time.time() < end:
        time.sleep(period)
        if count() != n:
            n, since = count(), time.time()
        elif time.time() - since >= quiet:
            return


def stop_process(process, timeout):
    """SIGINT to the whole process group (roslaunch passes it to its nodes, which then close
    their database), SIGKILL if it does not end in time."""
    if process.poll() is not None:
        return process.returncode
    try:
        os.killpg(process.pid, signal.SIGINT)
        return process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        return process.wait()


def run_tool(args, log, timeout):
    """Runs one of the package's tools (rosrun rtabmap_ros NAME ...), appending its output to
    log; raises with the tail of the log when it fails."""
    with open(log, "a") as out:
        out.write("$ %s\n" % " ".join(args))
        out.flush()
        r = subprocess.run(["rosrun", PKG] + args, stdout=out, stderr=subprocess.STDOUT, timeout=timeout)
    if r.returncode != 0:
        with open(log) as f:
            tail = f.read()[-2000:]
        raise RuntimeError("%s failed (exit %d):\n%s" % (args[0], r.returncode, tail))


def run_tool_json(args, log, timeout):
    """run_tool for a tool given --json: its stdout goes to log too, and its last line (the JSON
    summary) is returned parsed."""
    with open(log, "a") as out:
        out.write("$ %s\n" % " ".join(args))
    r = subprocess.run(["rosrun", PKG] + args, capture_output=True, text=True, timeout=timeout)
    with open(log, "a") as out:
        out.write(r.stdout + r.stderr)
    if r.returncode != 0:
        raise RuntimeError("%s failed (exit %d):\n%s" % (args[0], r.returncode, r.stderr[-2000:]))
    return json.loads(r.stdout.strip().splitlines()[-1])


class Launch:
    """roslaunch rtabmap_ros FILE with arguments, its output in log_path."""

    def __init__(self, launch_file, args, log_path):
        self.log = open(log_path, "a")
        self.process = subprocess.Popen(["roslaunch", "--wait", PKG, launch_file] +
                                        ["%s:=%s" % kv for kv in args.items()],
                                        stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)

    def alive(self):
        return self.process.poll() is None

    def stop(self):
        code = stop_process(self.process, 60.0)
        self.log.close()
        return code


def play(bag, rate, log_path, timeout):
    """rosbag play --clock at `rate`, waiting for its end."""
    with open(log_path, "a") as log:
        r = subprocess.run(["rosbag", "play", "--clock", "-q", "-r", str(rate), bag], stdout=log,
                           stderr=subprocess.STDOUT, timeout=timeout)
    if r.returncode != 0:
        raise RuntimeError("rosbag play %s failed (exit %d), see %s" % (bag, r.returncode, log_path))


class Recorder:
    """Subscribes to the rtabmap node's info and to the bag's odometry and ground truth; keeps,
    per SLAM update, the data stamp, the node id, the links found and the statistics that the
    report plots."""

    STATS = ("Timing/Total/ms", "Memory/Working_memory_size/")

    def __init__(self, namespace):
        import rospy
        from nav_msgs.msg import Odometry
        from rtabmap_ros.msg import Info
        self.updates = []  # dicts: stamp, wall, node, loop, proximity, stats
        self.odom = {}     # stamp -> (x, y)
        self.truth = {}    # stamp -> (x, y)
        self.subscribers = [
            rospy.Subscriber("/%s/info" % namespace, Info, self.on_info, queue_size=1000),
            rospy.Subscriber("/odom", Odometry, self.on_pose(self.odom), queue_size=1000),
            rospy.Subscriber("/ground_truth", Odometry, self.on_pose(self.truth), queue_size=1000),
        ]

    def on_info(self, msg):
        stats = dict(zip(msg.statsKeys, msg.statsValues))
        self.updates.append({"stamp": msg.header.stamp.to_sec(), "wall": time.time(), "node": msg.refId,
                             "loop": msg.loopClosureId, "proximity": msg.proximityDetectionId,
                             "stats": {k: stats[k] for k in self.STATS if k in stats}})

    @staticmethod
    def on_pose(store):
        def callback(msg):
            p = msg.pose.pose.position
            store[msg.header.stamp.to_sec()] = (p.x, p.y)
        return callback

    def wait_quiet(self, quiet=5.0, timeout=300.0):
        """Waits until no info arrived for `quiet` seconds: the node processed what it had."""
        wait_quiet(lambda: len(self.updates), quiet, timeout)

    def close(self):
        for s in self.subscribers:
            s.unregister()
