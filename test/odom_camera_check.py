#!/usr/bin/python3
"""Checks odom_rgbd.test and odom_stereo.test: visual odometry on the first frames of a real
dataset (~data in ../shared/data, converted with rtabmap-bag --format ~format) publishes odom
(odom -> base_link) with a finite, non-lost covariance for nearly every frame, odom_info, the
same pose on tf, and a trajectory whose motion follows the dataset's ground truth. Skips when
the dataset is absent."""
import os
import sys
import unittest

import numpy as np
import rosbag
import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry
from rtabmap_ros.msg import OdomInfo

import odom_common as oc


class CameraOdometry(unittest.TestCase):
    def test_follows_ground_truth(self):
        name, fmt = rospy.get_param("~data"), rospy.get_param("~format")
        folder = oc.data_file(name)
        if folder is None:
            self.skipTest(f"{name} not found in ../shared/data (or $RTABMAP_DATA_DIR)")
        frames = int(rospy.get_param("~frames", 150))
        bag = os.path.join(oc.workdir(self, "rtabmap_odom_camera_"), "camera.bag")
        oc.convert(self, fmt, folder, bag, "--max-frames", str(frames), "--no-imu")
        with rosbag.Bag(bag) as b:
            images = [m.header.stamp for _, m, _ in b.read_messages(topics=[rospy.get_param("~image_topic")])]
            truth = {round(m.header.stamp.to_sec(), 3): oc.odom_matrix(m)
                     for _, m, _ in b.read_messages(topics=["/ground_truth"])}
        self.assertEqual(len(images), frames)

        odoms, infos = [], []
        sub = rospy.Subscriber("/odom", Odometry, odoms.append, queue_size=1000)
        rospy.Subscriber("/odom_info", OdomInfo, infos.append, queue_size=1000)
        tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(3600))
        listener = tf2_ros.TransformListener(tf_buffer)
        self.assertTrue(oc.wait_for(lambda: sub.get_num_connections() > 0, 30), "the odometry node did not come up")
        oc.play(self, bag, float(rospy.get_param("~rate", 0.5)))
        oc.wait_quiet(odoms, quiet=3.0)
        del listener

        self.assertGreaterEqual(len(odoms), 0.8 * frames, f"{len(odoms)} odometry updates for {frames} frames")
        tracked = [m for m in odoms if not oc.lost(m)]
        self.assertGreaterEqual(len(tracked), 0.95 * len(odoms), f"{len(odoms) - len(tracked)} lost frames")
        self.assertGreaterEqual(len(infos), len(odoms) - 2, "odom_info not published for each update")
        for m in tracked:
            self.assertEqual((m.header.frame_id, m.child_frame_id), ("odom", "base_link"))
            cov = np.diag(np.array(m.pose.covariance).reshape(6, 6))
            self.assertTrue(np.all(np.isfinite(cov)) and np.all(cov > 0) and np.all(cov < 9999), f"covariance {cov}")
        for m in tracked[::25]:
            t = tf_buffer.lookup_transform("odom", "base_link", m.header.stamp, rospy.Duration(1.0))
            np.testing.assert_allclose(oc.matrix(t.transform.translation, t.transform.rotation),
                                       oc.odom_matrix(m), atol=1e-4)

        # The trajectory from the first tracked frame, against the ground truth's.
        stamps = [round(m.header.stamp.to_sec(), 3) for m in tracked]
        first = stamps[0]
        self.assertIn(first, truth)
        od0, gt0 = oc.odom_matrix(tracked[0]), truth[first]
        errors, path = [], 0.0
        previous = gt0
        for m, s in zip(tracked, stamps):
            if s not in truth:
                continue
            gt = oc.relative(gt0, truth[s])
            od = oc.relative(od0, oc.odom_matrix(m))
            errors.append(np.linalg.norm(gt[:3, 3] - od[:3, 3]))
            path += np.linalg.norm(truth[s][:3, 3] - previous[:3, 3])
            previous = truth[s]
        rmse = float(np.sqrt(np.mean(np.square(errors))))
        print(f"{name}: {len(errors)} frames, ground-truth path {path:.3f} m: translation RMSE {rmse:.4f} m, "
              f"final error {errors[-1]:.4f} m", file=sys.stderr)
        self.assertGreater(len(errors), 0.8 * len(tracked))
        # ~min_path: how far the excerpt must move for the comparison to mean something (0 for
        # an excerpt where the camera holds still: then the check is that odometry does not drift).
        self.assertGreaterEqual(path, float(rospy.get_param("~min_path", 0.05)), "the excerpt barely moves")
        self.assertLess(rmse, 0.02 + 0.05 * path)


if __name__ == "__main__":
    rospy.init_node("odom_camera_check")
    rostest.rosrun(oc.PKG, "odom_camera", CameraOdometry, sys.argv)
