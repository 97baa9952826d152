"""Helpers shared by the odom_*.py rostest checks: finding the datasets, converting them with
rtabmap-bag, playing a bag while collecting the odometry, and planar / 3D pose algebra."""
import math
import os
import shutil
import subprocess
import tempfile
import time

import numpy as np
import rospkg
import rospy

PKG = "rtabmap_ros"


def data_file(relative, shipped=False):
    """relative (e.g. "radish/aces.clf.bz2") in $RTABMAP_DATA_DIR, ../shared/data beside the
    package, or (shipped=True) the package's own data/. None when absent."""
    real = os.path.realpath(rospkg.RosPack().get_path(PKG))
    roots = []
    if os.environ.get("RTABMAP_DATA_DIR"):
        roots.append(os.environ["RTABMAP_DATA_DIR"])
    roots.append(os.path.join(real, "..", "shared", "data"))
    if shipped:
        roots.append(os.path.join(real, "data"))
    return next((os.path.join(r, relative) for r in roots if os.path.exists(os.path.join(r, relative))), None)


def workdir(test, prefix):
    """A temporary folder removed when the test ends (bags are tens of MB)."""
    path = tempfile.mkdtemp(prefix=prefix)
    test.addCleanup(shutil.rmtree, path, True)
    return path


def convert(test, fmt, source, bag, *args):
    """rtabmap-bag --format fmt source bag [args]; fails the test with its output on error."""
    r = subprocess.run(["rosrun", PKG, "rtabmap-bag", "--json", "--format", fmt, *args, source, bag],
                       capture_output=True, text=True, timeout=120)
    test.assertEqual(r.returncode, 0, r.stdout + r.stderr)


def play(test, bag, rate, timeout=120, start=None, duration=None):
    """rosbag play --clock at `rate`, waiting for the end; start / duration: only the bag's
    seconds [start, start + duration)."""
    part = (["-s", str(start)] if start is not None else []) + (["-u", str(duration)] if duration is not None else [])
    player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", str(rate), *part, bag],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, err = player.communicate(timeout=timeout)
    test.assertEqual(player.returncode, 0, err)


def wait_quiet(messages, quiet=2.0, timeout=30.0):
    """Waits until `messages` stops growing for `quiet` wall seconds (the node caught up)."""
    end = time.time() + timeout
    n, since = len(messages), time.time()
    while time.time() < end:
        time.sleep(0.1)
        if len(messages) != n:
            n, since = len(messages), time.time()
        elif time.time() - since >= quiet:
            return


def wait_for(predicate, timeout):
    end = time.time() + timeout
    while time.time() < end and not predicate():
        time.sleep(0.05)
    return predicate()


def matrix(position, orientation):
    """4x4 homogeneous matrix of a geometry_msgs position + quaternion."""
    x, y, z, w = orientation.x, orientation.y, orientation.z, orientation.w
    m = np.identity(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = [position.x, position.y, position.z]
    return m


def odom_matrix(msg):
    return matrix(msg.pose.pose.position, msg.pose.pose.orientation)


def planar(x, y, yaw):
    m = np.identity(4)
    m[:2, :2] = [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]
    m[:2, 3] = [x, y]
    return m


def relative(a, b):
    """The motion from pose a to pose b, in a's frame."""
    return np.linalg.inv(a) @ b


def angle(m):
    """Rotation angle of a 4x4 matrix (rad)."""
    return math.acos(max(-1.0, min(1.0, (np.trace(m[:3, :3]) - 1.0) / 2.0)))


def lost(msg):
    return msg.pose.covariance[0] >= 9999.0


def ate(estimate, truth):
    """RMSE of the 2D positions after the rigid alignment (rotation + translation) that
    minimises it (Umeyama without scale)."""
    a, b = np.asarray(estimate, float), np.asarray(truth, float)
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((b - cb).T @ (a - ca))
    d = np.diag([1.0, np.sign(np.linalg.det(u @ vt))])
    r = u @ d @ vt
    aligned = (r @ (a - ca).T).T + cb
    return float(np.sqrt(np.mean(np.sum((aligned - b) ** 2, axis=1))))


def grid_cells(grid):
    """(free, occupied) cell counts of a nav_msgs/OccupancyGrid (0 and 100; -1 is unknown)."""
    return sum(1 for v in grid.data if v == 0), sum(1 for v in grid.data if v == 100)
