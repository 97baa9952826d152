#!/usr/bin/env python3
"""rostest check (slam_multicamera.test): the rtabmap node with rgbd_cameras 2. A bag of the
simulator's `loop` scenario (rtabmap-sim) is rewritten with its camera split into two cameras,
the left and right halves of each image (each half keeps the pixels' geometry: same fx, fy, its
own cx), the right half in its own optical frame. The node's nodes (get_map_data) must carry
two camera models (local transforms from tf) and words from both cameras."""
import os
import subprocess
import sys
import unittest

import rosbag
import rospy
import rostest

from rtabmap_ros.msg import Info
from rtabmap_ros.srv import GetMap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import odom_common as common  # noqa: E402  (bag playing, temporary folders, waiting)

PKG = "rtabmap_ros"
RIGHT_FRAME = "camera_right_half_optical_frame"
CAMERA_TOPICS = {
    "/camera/rgb/image_rect_color": "rgb/image",
    "/camera/depth_registered/image_raw": "depth/image",
    "/camera/rgb/camera_info": "rgb/camera_info",
}


def image_half(msg, right):
    """The left or right half (columns) of a sensor_msgs/Image, as a copy."""
    half = msg.width // 2
    pixel = msg.step // msg.width
    out = type(msg)()
    out.header = type(msg.header)(msg.header.seq, msg.header.stamp, RIGHT_FRAME if right else msg.header.frame_id)
    out.height, out.width, out.encoding, out.is_bigendian = msg.height, half, msg.encoding, msg.is_bigendian
    out.step = half * pixel
    start = half * pixel if right else 0
    out.data = b"".join(bytes(msg.data[r * msg.step + start:r * msg.step + start + out.step]) for r in range(msg.height))
    return out


def info_half(msg, right):
    """camera_info of a half: same intrinsics, principal point moved for the right half."""
    half = msg.width // 2
    out = type(msg)()
    out.header = type(msg.header)(msg.header.seq, msg.header.stamp, RIGHT_FRAME if right else msg.header.frame_id)
    out.height, out.width, out.distortion_model = msg.height, half, msg.distortion_model
    out.D = list(msg.D)
    k, p = list(msg.K), list(msg.P)
    if right:
        k[2] -= half
        p[2] -= half
    out.K, out.R, out.P = k, list(msg.R), p
    return out


def right_half_mounting(transforms):
    """The right half's optical frame, at the camera's optical frame (identity)."""
    parent = next(t for t in transforms if t.child_frame_id == "camera_rgb_optical_frame")
    mounting = type(parent)()
    mounting.header = type(parent.header)(0, parent.header.stamp, "camera_rgb_optical_frame")
    mounting.child_frame_id = RIGHT_FRAME
    mounting.transform.rotation.w = 1.0
    return mounting


def split_bag(source, target):
    with rosbag.Bag(source) as bag_in, rosbag.Bag(target, "w") as bag_out:
        for topic, msg, t, header in bag_in.read_messages(return_connection_header=True):
            if topic == "/tf_static":
                msg.transforms.append(right_half_mounting(msg.transforms))
            if topic not in CAMERA_TOPICS:
                # The connection header keeps /tf_static latched on replay: published once, it
                # would be lost by a tf listener whose connection to rosbag is not up yet.
                bag_out.write(topic, msg, t, connection_header=header)
                continue
            split = info_half if topic.endswith("camera_info") else image_half
            for camera, right in (("/cam0/", False), ("/cam1/", True)):
                bag_out.write(camera + CAMERA_TOPICS[topic], split(msg, right), t)


class SlamMultiCameraTest(unittest.TestCase):
    def make_bag(self, duration):
        folder = common.workdir(self, "slam_multicamera_")
        sim_bag = os.path.join(folder, "loop.bag")
        r = subprocess.run(["rosrun", PKG, "rtabmap-sim", "--scenario", "loop", "--rate", "2", "--width", "320",
                            "--height", "240", "--no-stereo", "--no-urg", "--texture-size", "64",
                            "--duration", str(duration), "--start-stamp", "1700000000",
                            "--output", os.path.join(folder, "sim"), "--bag", sim_bag],
                           capture_output=True, text=True, timeout=240)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        bag = os.path.join(folder, "two_cameras.bag")
        split_bag(sim_bag, bag)
        return bag

    def test_nodes_have_words_from_both_cameras(self):
        infos = []
        rospy.Subscriber("/info", Info, infos.append)
        bag = self.make_bag(rospy.get_param("~duration", 30))
        rospy.wait_for_service("/get_map_data", timeout=60.0)
        common.play(self, bag, rospy.get_param("~rate", 2), timeout=120)
        common.wait_quiet(infos, quiet=3.0, timeout=30.0)
        self.assertGreater(len(infos), 10, "too few SLAM updates on info")

        data = rospy.ServiceProxy("/get_map_data", GetMap)(True, True, False).data
        self.assertGreaterEqual(len(data.nodes), 10, "too few nodes: %d" % len(data.nodes))
        both = 0
        for node in data.nodes:
            self.assertEqual(len(node.fx), 2, "node %d: %d camera models" % (node.id, len(node.fx)))
            self.assertEqual(len(node.localTransform), 2)
            # The right half's frame is the left's (static tf above): same local transform.
            a, b = node.localTransform
            self.assertAlmostEqual(a.translation.x, b.translation.x, places=4)
            self.assertAlmostEqual(a.rotation.w, b.rotation.w, places=4)
            width = node.width[0]
            left = sum(1 for k in node.wordKpts if k.pt.x < width)
            right = len(node.wordKpts) - left
            both += 1 if left >= 20 and right >= 20 else 0
        rospy.loginfo("slam_multicamera: %d nodes, %d with >= 20 words from each camera, %d updates",
                      len(data.nodes), both, len(infos))
        self.assertGreaterEqual(both, 0.8 * len(data.nodes))


if __name__ == "__main__":
    rospy.init_node("slam_multicamera_check")
    rostest.rosrun(PKG, "slam_multicamera", SlamMultiCameraTest)
