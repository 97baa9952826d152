#!/usr/bin/python3
"""Checks odom_deskew.test: a lidar sweeping while the robot turns bends the walls; icp_odometry
with deskewing puts each frame's points back on them, through tf (wheel odometry), through its
own constant-velocity model, or turned as a raw IMU's gyroscope measured. Without deskewing the
points stay off by decimetres."""
import math
import sys
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs import point_cloud2
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, LaserScan, PointCloud2

SPEED, TURN_RATE = 0.4, 1.0  # m/s, rad/s: a differential drive, constant in its own frame
HALF_X, HALF_Y = 6.0, 4.0  # the room's walls
PILLARS, PILLAR_HALF = ((2.5, 1.5), (-3.0, -2.0)), 0.25  # square pillars: the room is not symmetric
MOUNT = (0.1, 0.0, 0.2)  # base_link -> laser
BEAMS, SWEEP = 360, 0.1
NODES = ("raw", "tf", "velocity", "imu")


STILL, RAMP = 1.0, 1.0  # s standing at the room's centre (the odometry starts there), s to full speed


def robot_pose(t):
    """(x, y, yaw) of the robot t seconds after the start: still, then speeding up (both speeds
    together, so the path is one circle from the room's centre) to SPEED and TURN_RATE."""
    moving = max(t - STILL, 0.0)
    yaw = TURN_RATE * (moving * moving / (2.0 * RAMP) if moving < RAMP else moving - RAMP / 2.0)
    radius = SPEED / TURN_RATE
    return radius * math.sin(yaw), radius * (1.0 - math.cos(yaw)), yaw


def yaw_rate(t):
    """d yaw / dt of robot_pose at t."""
    moving = max(t - STILL, 0.0)
    return TURN_RATE * (moving / RAMP if moving < RAMP else 1.0)


def laser_pose(t):
    x, y, yaw = robot_pose(t)
    return x + MOUNT[0] * math.cos(yaw), y + MOUNT[0] * math.sin(yaw), yaw


def range_to_walls(x, y, heading):
    """Range from (x, y) along `heading` to the room's walls or a pillar."""
    dx, dy = math.cos(heading), math.sin(heading)
    r = float("inf")
    if abs(dx) > 1e-12:
        r = min(r, ((HALF_X if dx > 0 else -HALF_X) - x) / dx)
    if abs(dy) > 1e-12:
        r = min(r, ((HALF_Y if dy > 0 else -HALF_Y) - y) / dy)
    for cx, cy in PILLARS:  # slab test of the ray against each pillar's square
        near, far = 0.0, float("inf")
        for o, d, c in ((x, dx, cx), (y, dy, cy)):
            if abs(d) < 1e-12:
                if abs(o - c) > PILLAR_HALF:
                    near, far = 1.0, 0.0
                continue
            a, b = (c - PILLAR_HALF - o) / d, (c + PILLAR_HALF - o) / d
            near, far = max(near, min(a, b)), min(far, max(a, b))
        if near <= far:
            r = min(r, near)
    return r


def transform(parent, child, stamp, x, y, z, yaw):
    t = TransformStamped()
    t.header.frame_id, t.header.stamp, t.child_frame_id = parent, stamp, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
    t.transform.rotation.z, t.transform.rotation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
    return t


def wall_error(x, y):
    """Distance of a point (in odom) to the nearest wall or pillar side."""
    error = min(abs(abs(x) - HALF_X), abs(abs(y) - HALF_Y))
    for cx, cy in PILLARS:
        ox, oy = abs(x - cx) - PILLAR_HALF, abs(y - cy) - PILLAR_HALF
        outside = math.hypot(max(ox, 0.0), max(oy, 0.0))
        error = min(error, outside if outside > 0.0 else -max(ox, oy))
    return error


class Deskewing(unittest.TestCase):
    def setUp(self):
        self.clouds = {n: [] for n in NODES}
        self.poses = {n: [] for n in NODES}
        self.lock = threading.Lock()
        self.subs = [rospy.Subscriber("/%s/odom_last_frame" % n, PointCloud2, self.on_cloud, n) for n in NODES]
        self.subs += [rospy.Subscriber("/%s/odom" % n, Odometry, self.on_odom, n) for n in NODES]
        self.scan_pub = rospy.Publisher("/scan", LaserScan, queue_size=20)
        self.imu_pub = rospy.Publisher("/imu", Imu, queue_size=200)
        self.tf = tf2_ros.TransformBroadcaster()
        self.static_tf = tf2_ros.StaticTransformBroadcaster()

    def on_cloud(self, msg, node):
        points = np.array([(p[0], p[1]) for p in point_cloud2.read_points(msg, ("x", "y"), skip_nans=True)])
        with self.lock:
            self.clouds[node].append((msg.header.stamp, points))

    def on_odom(self, msg, node):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        with self.lock:
            self.poses[node].append((msg.header.stamp, p.x, p.y, 2.0 * math.atan2(q.z, q.w)))

    def at_true_pose(self, node, stamp, points, tracked_only):
        """The frame's points (odometry frame) moved to the robot's true pose at `stamp`: what
        deskewing is responsible for (the scan's shape), apart from the odometry's drift.
        tracked_only: empty when the odometry was off by more than 5 cm or 0.02 rad there (for
        the velocity model, which is the odometry's own and so cannot be better than it: the
        scan-to-map odometry without a guess drifts in this room after a few turns)."""
        pose = next((p for p in self.poses[node] if p[0] == stamp), None)
        if pose is None or len(points) == 0:
            return []
        _, x, y, yaw = pose
        tx, ty, tyaw = robot_pose((stamp - self.origin).to_sec())
        off = math.hypot(x - tx, y - ty) > 0.05 or abs(math.atan2(math.sin(yaw - tyaw), math.cos(yaw - tyaw))) > 0.02
        if tracked_only and off:
            return []
        c, s = math.cos(tyaw - yaw), math.sin(tyaw - yaw)
        local = points - [x, y]
        return np.column_stack((c * local[:, 0] - s * local[:, 1] + tx, s * local[:, 0] + c * local[:, 1] + ty))

    def pose_errors(self, node):
        """Median position (m) and heading (rad) error of the odometry against the robot's path."""
        dp, dyaw = [], []
        for stamp, x, y, yaw in self.poses[node]:
            tx, ty, tyaw = robot_pose((stamp - self.origin).to_sec())
            dp.append(math.hypot(x - tx, y - ty))
            dyaw.append(abs(math.atan2(math.sin(yaw - tyaw), math.cos(yaw - tyaw))))
        return float(np.median(dp)), float(np.median(dyaw))

    def scan(self, start, t0):
        """The sweep starting at ROS time `start` (robot time t0): beam i from the laser's pose
        at t0 + i * time_increment."""
        msg = LaserScan()
        msg.header.frame_id, msg.header.stamp = "laser", start
        msg.angle_min, msg.angle_increment = -math.pi, 2.0 * math.pi / BEAMS
        msg.angle_max = msg.angle_min + msg.angle_increment * (BEAMS - 1)
        msg.time_increment, msg.scan_time = SWEEP / BEAMS, SWEEP
        msg.range_min, msg.range_max = 0.1, 20.0
        for i in range(BEAMS):
            x, y, yaw = laser_pose(t0 + i * msg.time_increment)
            msg.ranges.append(range_to_walls(x, y, yaw + msg.angle_min + i * msg.angle_increment))
        return msg

    def drive(self, seconds):
        """Wheel odometry at 100 Hz and a sweep every 0.1 s, stamped 0.2 s in the past so tf
        already covers the whole sweep when it arrives."""
        self.static_tf.sendTransform(transform("base_link", "laser", rospy.Time.now(), MOUNT[0], MOUNT[1], MOUNT[2], 0.0))
        origin = self.origin = rospy.Time.now() + rospy.Duration(0.3)
        rate = rospy.Rate(100)
        ticks = 0
        while not rospy.is_shutdown():
            now = rospy.Time.now()
            t = (now - origin).to_sec()
            if t > seconds:
                break
            x, y, yaw = robot_pose(t)
            self.tf.sendTransform(transform("odom", "base_link", now, x, y, 0.0, yaw))
            imu = Imu()
            imu.header.frame_id, imu.header.stamp = "base_link", now
            imu.orientation_covariance[0] = -1.0  # a raw IMU: its gyroscope only
            imu.angular_velocity.z = yaw_rate(t)
            self.imu_pub.publish(imu)
            ticks += 1
            if ticks % 10 == 0 and t > 0.3:
                start = now - rospy.Duration(0.2)
                self.scan_pub.publish(self.scan(start, (start - origin).to_sec()))
            rate.sleep()

    def test_deskewed_points_lie_on_the_walls(self):
        deadline = time.time() + 20.0
        while time.time() < deadline and any(s.get_num_connections() == 0 for s in self.subs):
            time.sleep(0.1)
        while time.time() < deadline and self.scan_pub.get_num_connections() < len(NODES):
            time.sleep(0.1)
        while time.time() < deadline and self.imu_pub.get_num_connections() < 1:
            time.sleep(0.1)
        self.drive(8.0)
        time.sleep(1.0)
        with self.lock:
            clouds = {n: list(c) for n, c in self.clouds.items()}
        median, heading_error = {}, {}
        for node in NODES:
            self.assertGreaterEqual(len(clouds[node]), 30, "%s: %d frames" % (node, len(clouds[node])))
            # From full speed on (the constant-velocity model lags while the robot speeds up).
            with self.lock:
                placed = [self.at_true_pose(node, stamp, points, node in ("velocity", "imu"))
                          for stamp, points in clouds[node][20:]]
                position, heading = self.pose_errors(node)
            tracked = sum(1 for cloud in placed if len(cloud) > 0)
            self.assertGreaterEqual(tracked, 15, "%s: odometry within 5 cm, 0.02 rad in %d frames" % (node, tracked))
            errors = [wall_error(x, y) for cloud in placed for x, y in cloud]
            median[node] = float(np.median(errors))
            heading_error[node] = heading
            rospy.loginfo("odom_deskew: %s: %d frames (%d tracked), points at the true pose: median distance to "
                          "the walls %.4f m, p90 %.4f m; odometry median error %.4f m, %.4f rad", node,
                          len(clouds[node]), tracked, median[node], float(np.percentile(errors, 90)), position, heading)
        self.assertLess(median["tf"], 0.02, median)
        self.assertLess(median["velocity"], 0.02, median)
        self.assertLess(median["imu"], 0.02, median)
        # The gyroscope also turns each frame's guess: the scan-to-map odometry keeps its heading
        # (without a guess it drifts by about 0.01 rad here).
        self.assertLess(heading_error["imu"], 0.002, heading_error)
        self.assertGreater(median["raw"], 3.0 * max(median["tf"], median["velocity"]), median)


if __name__ == "__main__":
    rospy.init_node("odom_deskew_check")
    rostest.rosrun("rtabmap_ros", "odom_deskew", Deskewing, sys.argv)
