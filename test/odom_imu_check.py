#!/usr/bin/python3
"""Checks odom_imu.test: rgbd_odometry with wait_imu_to_init drops the frames that come before
the first IMU orientation, then starts with the roll and pitch the IMU gives the robot's base
(its heading left at zero), and tracks the rest of the frames along the ground truth. The IMU is
simulated from the bag's ground truth: the base's orientation in a world tilted by a fixed
rotation, seen through an IMU mounted turned and upside down (imu_link, published here)."""
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


class ImuOdometry(unittest.TestCase):
    def test_waits_for_the_imu_and_starts_levelled(self):
        folder = oc.data_file("rgbd_7scenes")
        if folder is None:
            self.skipTest("rgbd_7scenes not found in ../shared/data (or $RTABMAP_DATA_DIR)")
        frames = int(rospy.get_param("~frames", 90))
        bag = os.path.join(oc.workdir(self, "rtabmap_odom_imu_"), "camera.bag")
        oc.convert(self, "7scenes", folder, bag, "--max-frames", str(frames), "--no-imu")
        with rosbag.Bag(bag) as b:
            images = [m.header.stamp for _, m, _ in b.read_messages(topics=["/camera/rgb/image_rect_color"])]
        self.assertEqual(len(images), frames)
        imu_from = images[FIRST_IMU_FRAME]

        mount = TransformStamped()
        mount.header.frame_id, mount.child_frame_id = "base_link", "imu_link"
        mount.transform.translation.x, mount.transform.translation.z = 0.05, 0.1
        r = mount.transform.rotation
        r.x, r.y, r.z, r.w = quaternion(MOUNT)
        static_tf = tf2_ros.StaticTransformBroadcaster()
        static_tf.sendTransform(mount)

        base_in_world = {}  # stamp -> the base's orientation the IMU reported
        imu_pub = rospy.Publisher("/imu/data", Imu, queue_size=100)

        def on_truth(msg):
            if msg.header.stamp < imu_from:
                return
            base = TILT @ oc.odom_matrix(msg)[:3, :3]
            base_in_world[round(msg.header.stamp.to_sec(), 3)] = base
            q = quaternion(base @ MOUNT)
            imu = Imu()
            imu.header.stamp = msg.header.stamp
            imu.header.frame_id = "imu_link"
            imu.orientation.x, imu.orientation.y, imu.orientation.z, imu.orientation.w = q
            imu.angular_velocity_covariance[0] = -1.0  # orientation only, as documented by sensor_msgs/Imu
            imu.linear_acceleration_covariance[0] = -1.0
            imu_pub.publish(imu)

        odoms = []
        sub = rospy.Subscriber("/odom", Odometry, odoms.append, queue_size=1000)
        rospy.Subscriber("/ground_truth", Odometry, on_truth, queue_size=1000)
        self.assertTrue(oc.wait_for(lambda: sub.get_num_connections() > 0 and imu_pub.get_num_connections() > 0, 30),
                        "the odometry node did not come up")
        oc.play(self, bag, float(rospy.get_param("~rate", 0.5)))
        oc.wait_quiet(odoms, quiet=3.0)

        self.assertGreater(len(base_in_world), 0, "no ground truth to make the IMU from")
        self.assertGreaterEqual(odoms[0].header.stamp, imu_from, "odometry started before the IMU (wait_imu_to_init)")
        tracked = [m for m in odoms if not oc.lost(m)]
        self.assertGreaterEqual(len(tracked), 0.8 * (frames - FIRST_IMU_FRAME), f"{len(tracked)} tracked frames")

        # The first pose: the base's roll and pitch in the IMU's world, heading zero, at the origin.
        first = odoms[0]
        pose = oc.odom_matrix(first)
        roll, pitch, yaw = euler(pose[:3, :3])
        stamp = round(first.header.stamp.to_sec(), 3)
        self.assertIn(stamp, base_in_world)
        want_roll, want_pitch, _ = euler(base_in_world[stamp])
        print(f"first pose roll {roll:.4f} pitch {pitch:.4f} yaw {yaw:.4f}; the IMU's {want_roll:.4f} {want_pitch:.4f}",
              file=sys.stderr)
        # A frame may take the sample before its own (the IMU message came after the images): one
        # frame of a hand-held camera's turn.
        self.assertLess(abs(roll - want_roll), 0.03)
        self.assertLess(abs(pitch - want_pitch), 0.03)
        self.assertLess(abs(yaw), 1e-6)
        self.assertLess(np.linalg.norm(pose[:3, 3]), 1e-6)
        self.assertGreater(abs(want_roll), 0.1, "the test's tilt should be visible")


if __name__ == "__main__":
    rospy.init_node("odom_imu_check")
    rostest.rosrun(oc.PKG, "odom_imu", ImuOdometry, sys.argv)
