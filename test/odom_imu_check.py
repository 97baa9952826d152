#!/usr/bin/python3
"""Checks odom_imu.test and odom_imu_gyro.test: rgbd_odometry with an IMU simulated from the
bag's ground truth, mounted turned and upside down (imu_link, published here).

~mode orientation (odom_imu.test, wait_imu_to_init): the IMU's orientation of the base in a world
tilted by a fixed rotation. Odometry drops the frames before the first one, starts with the roll
and pitch it gives the base (heading zero), and each motion guess (odom_info's guessVelocity)
turns as the ground truth did since the previous frame.
~mode gyro (odom_imu_gyro.test): a raw IMU, angular velocities only (the ground truth's rotation
between two frames over their interval, four samples each): the guesses turn as the ground truth
did too, and odometry starts at the origin (nothing to level with)."""
import os
import sys
import unittest

import numpy as np
import rosbag
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from rtabmap_ros.msg import OdomInfo
from sensor_msgs.msg import Imu

import odom_common as oc



def rotation(roll, pitch, yaw):
    """Rz(yaw) Ry(pitch) Rx(roll), the Euler convention of rtabmap's Transform."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def euler(r):
    """(roll, pitch, yaw) of a rotation matrix, inverse of rotation()."""
    return (np.arctan2(r[2, 1], r[2, 2]), -np.arcsin(np.clip(r[2, 0], -1.0, 1.0)), np.arctan2(r[1, 0], r[0, 0]))


def quaternion(r):
    """(x, y, z, w) of a rotation matrix."""
    w = np.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2, r[2, 1] - r[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2, r[0, 2] - r[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2, r[1, 0] - r[0, 1])
    return x, y, z, w


# The IMU's world against the ground truth's, and the IMU on the base.
TILT = rotation(0.3, -0.2, 0.4)
MOUNT = rotation(np.pi, 0.0, np.pi / 2)
FIRST_IMU_FRAME = 10


def rotation_vector(r):
    """The axis times the angle of a rotation matrix."""
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))
    if angle < 1e-12:
        return np.zeros(3)
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2.0 * np.sin(angle))
    return axis * angle


def imu_message(stamp, orientation=None, angular_velocity=None):
    m = Imu()
    m.header.stamp, m.header.frame_id = stamp, "imu_link"
    if orientation is None:
        m.orientation_covariance[0] = -1.0  # sensor_msgs/Imu: no orientation
    else:
        m.orientation.x, m.orientation.y, m.orientation.z, m.orientation.w = quaternion(orientation)
    if angular_velocity is None:
        m.angular_velocity_covariance[0] = -1.0
    else:
        m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = angular_velocity
    m.linear_acceleration_covariance[0] = -1.0
    return m


class ImuOdometry(unittest.TestCase):
    def test_imu_levels_the_start_and_turns_the_guesses(self):
        mode = rospy.get_param("~mode", "orientation")
        folder = oc.data_file("rgbd_7scenes")
        if folder is None:
            self.skipTest("rgbd_7scenes not found in ../shared/data (or $RTABMAP_DATA_DIR)")
        frames = int(rospy.get_param("~frames", 90))
        bag = os.path.join(oc.workdir(self, "rtabmap_odom_imu_"), "camera.bag")
        oc.convert(self, "7scenes", folder, bag, "--max-frames", str(frames), "--no-imu")
        with rosbag.Bag(bag) as b:
            images = [m.header.stamp for _, m, _ in b.read_messages(topics=["/camera/rgb/image_rect_color"])]
            truth = [(m.header.stamp, oc.odom_matrix(m)[:3, :3]) for _, m, _ in b.read_messages(topics=["/ground_truth"])]
        self.assertEqual(len(images), frames)
        truth_at = {round(t.to_sec(), 3): r for t, r in truth}
        imu_from = images[FIRST_IMU_FRAME] if mode == "orientation" else images[0]

        mount = TransformStamped()
        mount.header.frame_id, mount.child_frame_id = "base_link", "imu_link"
        mount.transform.translation.x, mount.transform.translation.z = 0.05, 0.1
        r = mount.transform.rotation
        r.x, r.y, r.z, r.w = quaternion(MOUNT)
        static_tf = tf2_ros.StaticTransformBroadcaster()
        static_tf.sendTransform(mount)

        imu_pub = rospy.Publisher("/imu/data", Imu, queue_size=1000)
        following = {round(a.to_sec(), 3): (b, rb, ra) for (a, ra), (b, rb) in zip(truth, truth[1:])}

        def on_truth(msg):
            if msg.header.stamp < imu_from:
                return
            # Ahead of the next frame (its images may reach odometry before this message reaches
            # the check): the next frame's orientation, or the rate that turns the base from this
            # frame's orientation to the next one's, in the IMU's frame, four samples over the
            # interval.
            nxt = following.get(round(msg.header.stamp.to_sec(), 3))
            if nxt is None or not imu_pub.get_num_connections():
                return
            t1, r1, r0 = nxt
            if mode == "orientation":
                if msg.header.stamp == imu_from:
                    imu_pub.publish(imu_message(msg.header.stamp, orientation=TILT @ r0 @ MOUNT))
                imu_pub.publish(imu_message(t1, orientation=TILT @ r1 @ MOUNT))
                return
            dt = (t1 - msg.header.stamp).to_sec()
            w = MOUNT.T @ (rotation_vector(r0.T @ r1) / dt)
            if msg.header.stamp == imu_from:
                imu_pub.publish(imu_message(msg.header.stamp, angular_velocity=w))
            for k in range(1, 5):
                imu_pub.publish(imu_message(msg.header.stamp + rospy.Duration(dt * k / 4.0), angular_velocity=w))

        odoms, infos = [], []
        sub = rospy.Subscriber("/odom", Odometry, odoms.append, queue_size=1000)
        rospy.Subscriber("/odom_info", OdomInfo, infos.append, queue_size=1000)
        rospy.Subscriber("/ground_truth", Odometry, on_truth, queue_size=1000)
        self.assertTrue(oc.wait_for(lambda: sub.get_num_connections() > 0 and imu_pub.get_num_connections() > 0, 30),
                        "the odometry node did not come up")
        oc.play(self, bag, float(rospy.get_param("~rate", 0.5)))
        oc.wait_quiet(odoms, quiet=3.0)

        self.assertGreaterEqual(odoms[0].header.stamp, imu_from, "odometry started before the IMU (wait_imu_to_init)")
        tracked = [m for m in odoms if not oc.lost(m)]
        self.assertGreaterEqual(len(tracked), 0.8 * (frames - FIRST_IMU_FRAME), f"{len(tracked)} tracked frames")

        # The first pose: with an orientation, the base's roll and pitch in the IMU's world,
        # heading zero; with a raw IMU, the origin.
        first = odoms[0]
        pose = oc.odom_matrix(first)
        roll, pitch, yaw = euler(pose[:3, :3])
        if mode == "orientation":
            want_roll, want_pitch, _ = euler(TILT @ truth_at[round(first.header.stamp.to_sec(), 3)])
        else:
            want_roll, want_pitch = 0.0, 0.0
        print(f"{mode}: first pose roll {roll:.4f} pitch {pitch:.4f} yaw {yaw:.4f}; want {want_roll:.4f} {want_pitch:.4f}",
              file=sys.stderr)
        self.assertLess(abs(roll - want_roll), 0.003)
        self.assertLess(abs(pitch - want_pitch), 0.003)
        self.assertLess(abs(yaw), 1e-6)
        self.assertLess(np.linalg.norm(pose[:3, 3]), 1e-6)
        if mode == "orientation":
            self.assertGreater(abs(want_roll), 0.1, "the test's tilt should be visible")

        # Each guess after a tracked frame turns as the ground truth did since it.
        errors, turns = [], []
        for prev, cur in zip(infos, infos[1:]):
            if prev.lost:
                continue
            a, b = truth_at.get(round(prev.header.stamp.to_sec(), 3)), truth_at.get(round(cur.header.stamp.to_sec(), 3))
            g = cur.guessVelocity.rotation
            if a is None or b is None or (g.x, g.y, g.z, g.w) == (0, 0, 0, 0):
                continue
            guess = oc.matrix(cur.guessVelocity.translation, g)[:3, :3]
            want = a.T @ b
            errors.append(oc.angle(guess.T @ want))
            turns.append(oc.angle(want))
        self.assertGreaterEqual(len(errors), 0.8 * len(tracked), f"{len(errors)} guesses for {len(tracked)} frames")
        p90 = float(np.percentile(errors, 90))
        print(f"{mode}: {len(errors)} guesses, rotation error median {np.median(errors):.5f} p90 {p90:.5f} rad; "
              f"the turns between frames median {np.median(turns):.5f} rad", file=sys.stderr)
        self.assertLess(p90, 0.003)
        self.assertGreater(float(np.median(turns)), 0.003, "the camera should turn between frames")


if __name__ == "__main__":
    rospy.init_node("odom_imu_check")
    rostest.rosrun(oc.PKG, "odom_imu", ImuOdometry, sys.argv)
