#!/usr/bin/env python3
"""rostest check (slam_multistereo.test): the rtabmap node with two stereo cameras in one
rtabmap_ros/RGBDImages (rgbdx_sync, rgbd_cameras 0). A stereo bag of the simulator's `loop`
scenario is rewritten with its stereo pair split into two stereo cameras, the left and right
halves of both images (each half keeps the pixels' geometry: same fx, fy and baseline, its own
cx), the right halves in their own optical frame. The node's nodes (get_map_data) must carry two
stereo camera models (a baseline, local transforms from tf) and words from both cameras, and
rgbd_odometry on the same bundle (/vo) must follow the bag's ground truth."""
import bisect
import math
import os
import subprocess
import sys
import unittest

import rosbag
import rospy
import rostest

from nav_msgs.msg import Odometry
from rtabmap_ros.msg import Info
from rtabmap_ros.srv import GetMap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import odom_common as common  # noqa: E402  (bag playing, temporary folders, waiting)
from slam_multicamera_check import image_half  # noqa: E402  (the column halves of an image)

PKG = "rtabmap_ros"
LEFT_FRAME = "camera_left_optical_frame"
HALF_FRAME = "camera_left_right_half_optical_frame"
CAMERA_TOPICS = {
    "/stereo_camera/left/image_rect": "left/image_rect",
    "/stereo_camera/right/image_rect": "right/image_rect",
    "/stereo_camera/left/camera_info": "left/camera_info",
    "/stereo_camera/right/camera_info": "right/camera_info",
}


def with_frame(msg, right):
    """The message of the right half in its own optical frame (both images of a half share
    the left camera's frame, as stereo_sync expects)."""
    msg.header.frame_id = HALF_FRAME if right else LEFT_FRAME
    return msg


def info_half(msg, right):
    """camera_info of a half: same intrinsics and baseline (P[3]), principal point moved for the
    right half."""
    half = msg.width // 2
    out = type(msg)()
    out.header = type(msg.header)(msg.header.seq, msg.header.stamp, msg.header.frame_id)
    out.height, out.width, out.distortion_model = msg.height, half, msg.distortion_model
    out.D = list(msg.D)
    k, p = list(msg.K), list(msg.P)
    if right:
        k[2] -= half
        p[2] -= half
    out.K, out.R, out.P = k, list(msg.R), p
    return with_frame(out, right)


def half_mounting(transforms):
    """The right halves' optical frame, at the left camera's optical frame (identity)."""
    parent = next(t for t in transforms if t.child_frame_id == LEFT_FRAME)
    mounting = type(parent)()
    mounting.header = type(parent.header)(0, parent.header.stamp, LEFT_FRAME)
    mounting.child_frame_id = HALF_FRAME
    mounting.transform.rotation.w = 1.0
    return mounting


def split_bag(source, target):
    with rosbag.Bag(source) as bag_in, rosbag.Bag(target, "w") as bag_out:
        for topic, msg, t, header in bag_in.read_messages(return_connection_header=True):
            if topic == "/tf_static":
                msg.transforms.append(half_mounting(msg.transforms))
            if topic not in CAMERA_TOPICS:
                bag_out.write(topic, msg, t, connection_header=header)
                continue
            for camera, right in (("/cam0/", False), ("/cam1/", True)):
                if topic.endswith("camera_info"):
                    part = info_half(msg, right)
                else:
                    part = with_frame(image_half(msg, right), right)
                bag_out.write(camera + CAMERA_TOPICS[topic], part, t)


def planar(pose):
    """(x, y, yaw) of a geometry_msgs/Pose."""
    q = pose.orientation
    return pose.position.x, pose.position.y, math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def relative(a, b):
    """b in a's frame, planar poses."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return c * dx + s * dy, -s * dx + c * dy, b[2] - a[2]


def ground_truth(bag):
    """Sorted stamps and planar poses of the bag's /ground_truth."""
    stamps, poses = [], []
    with rosbag.Bag(bag) as b:
        for _, msg, _ in b.read_messages(topics=["/ground_truth"]):
            stamps.append(msg.header.stamp.to_sec())
            poses.append(planar(msg.pose.pose))
    return stamps, poses


class SlamMultiStereoTest(unittest.TestCase):
    def make_bag(self, duration):
        folder = common.workdir(self, "slam_multistereo_")
        sim = os.path.join(folder, "sim")
        r = subprocess.run(["rosrun", PKG, "rtabmap-sim", "--scenario", "loop", "--rate",
                            str(rospy.get_param("~sim_rate", 6)), "--width", "320",
                            "--height", "240", "--no-urg", "--texture-size", "64", "--duration", str(duration),
                            "--start-stamp", "1700000000", "--output", sim],
                           capture_output=True, text=True, timeout=240)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        stereo_bag = os.path.join(folder, "stereo.bag")
        common.convert(self, "sim", sim + "?camera=stereo", stereo_bag)
        bag = os.path.join(folder, "two_stereo_cameras.bag")
        split_bag(stereo_bag, bag)
        return bag

    def check_odometry(self, vo, bag):
        """Each /vo pose, relative to the first, against the ground truth's at the same stamp."""
        stamps, truth = ground_truth(bag)
        self.assertGreater(len(stamps), 10, "the bag has no /ground_truth")
        tracked = [m for m in vo if m.pose.covariance[0] < 9999]
        self.assertGreaterEqual(len(tracked), 0.9 * len(vo), "visual odometry lost %d of %d frames"
                                % (len(vo) - len(tracked), len(vo)))
        self.assertGreater(len(tracked), 10, "too few /vo messages: %d" % len(tracked))

        def truth_at(t):
            i = min(bisect.bisect_left(stamps, t), len(stamps) - 1)
            self.assertLess(abs(stamps[i] - t), 1e-3, "no ground truth at %.3f" % t)
            return truth[i]

        first, start = planar(tracked[0].pose.pose), truth_at(tracked[0].header.stamp.to_sec())
        worst, travelled, last = 0.0, 0.0, start
        for m in tracked[1:]:
            gt = truth_at(m.header.stamp.to_sec())
            travelled += math.hypot(gt[0] - last[0], gt[1] - last[1])
            last = gt
            e, g = relative(first, planar(m.pose.pose)), relative(start, gt)
            worst = max(worst, math.hypot(e[0] - g[0], e[1] - g[1]))
        rospy.loginfo("slam_multistereo: visual odometry on two stereo cameras, %d poses, %.2f m travelled, "
                      "worst error %.3f m", len(tracked), travelled, worst)
        self.assertGreater(travelled, 1.0)
        self.assertLess(worst, max(0.1, 0.05 * travelled))

    def test_nodes_have_two_stereo_cameras_and_words_from_both(self):
        infos, vo = [], []
        rospy.Subscriber("/info", Info, infos.append)
        rospy.Subscriber("/vo", Odometry, vo.append)
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
            self.assertGreater(node.baseline, 0.0, "node %d is not stereo" % node.id)
            self.assertEqual(len(node.localTransform), 2)
            # The right halves' frame is the left camera's (static tf above): same local transform.
            a, b = node.localTransform
            self.assertAlmostEqual(a.translation.x, b.translation.x, places=4)
            self.assertAlmostEqual(a.rotation.w, b.rotation.w, places=4)
            self.assertAlmostEqual(node.cx[0] - node.cx[1], node.width[0], places=3)
            width = node.width[0]
            left = sum(1 for k in node.wordKpts if k.pt.x < width)
            right = len(node.wordKpts) - left
            both += 1 if left >= 20 and right >= 20 else 0
        rospy.loginfo("slam_multistereo: %d nodes, %d with >= 20 words from each camera, %d updates",
                      len(data.nodes), both, len(infos))
        self.assertGreaterEqual(both, 0.8 * len(data.nodes))
        self.check_odometry(vo, bag)


if __name__ == "__main__":
    rospy.init_node("slam_multistereo_check")
    rostest.rosrun(PKG, "slam_multistereo", SlamMultiStereoTest)
