#!/usr/bin/env python3
"""rostest check of launch/*.launch (launch_files.test): each file is loaded by roslaunch's own
parser with the arguments users give, and the rtabmap node it would start is inspected (its
arguments, private parameters and remappings); nothing is started."""
import glob
import os
import subprocess
import unittest

import rospkg
import rostest
from roslaunch.config import load_config_default

PKG = "rtabmap_ros"
LAUNCH = os.path.join(rospkg.RosPack().get_path(PKG), "launch")
CONFIG = os.path.join(rospkg.RosPack().get_path(PKG), "config")


def load(name, **args):
    """The roslaunch configuration of launch/name with name:=value arguments."""
    return load_config_default([(os.path.join(LAUNCH, name), ["%s:=%s" % kv for kv in args.items()])], None,
                               verbose=False)


def node(config, ns_name):
    found = [n for n in config.nodes if (n.namespace + n.name).strip("/") == ns_name.strip("/")]
    return found[0] if found else None


def param(config, name):
    p = config.params.get(name)
    return p.value if p else None


class LaunchFilesTest(unittest.TestCase):
    def test_every_preset_is_accepted_by_the_core(self):
        """config/*.ini: every key known, every value valid (the core refuses the file
        otherwise, naming the line), and each demo launch file's config_path exists."""
        presets = sorted(glob.glob(os.path.join(CONFIG, "*.ini")))
        names = {os.path.basename(p) for p in presets}
        self.assertTrue({"lidar2d.ini", "lidar3d.ini", "rgbd.ini", "stereo.ini"} <= names, names)
        for p in presets:
            r = subprocess.run(["rosrun", PKG, "rtabmap-dataset", "--config", p, "--params"],
                               capture_output=True, text=True, timeout=60)
            self.assertEqual(r.returncode, 0, p + ": " + r.stderr)
            self.assertNotIn("error", r.stderr, p)
        for f in sorted(glob.glob(os.path.join(LAUNCH, "demo_*.launch"))):
            path = param(load(os.path.basename(f)), "/rtabmap/rtabmap/config_path")
            self.assertTrue(path and os.path.isfile(path), "%s: config_path %s" % (f, path))

    def test_every_launch_file_parses_with_its_defaults(self):
        files = sorted(glob.glob(os.path.join(LAUNCH, "*.launch")))
        self.assertGreaterEqual(len(files), 3)
        for f in files:
            config = load(os.path.basename(f))
            self.assertIsNotNone(node(config, "rtabmap/rtabmap"), f + ": no rtabmap node")

    def test_demo_launch_files_delete_the_database_only_when_asked(self):
        for name in ("demo_intel.launch", "demo_sim_robot.launch"):
            fresh = node(load(name), "rtabmap/rtabmap")
            self.assertEqual(fresh.args.split(), ["-d"], name)
            continued = node(load(name, delete_db="false"), "rtabmap/rtabmap")
            self.assertEqual(continued.args.split(), [], name)

    def test_time_threshold_and_detection_rate_reach_the_node(self):
        config = load("demo_intel.launch", time_threshold="250", detection_rate="2")
        self.assertEqual(param(config, "/rtabmap/rtabmap/Rtabmap/TimeThr"), "250")
        self.assertEqual(param(config, "/rtabmap/rtabmap/Rtabmap/DetectionRate"), "2")
        self.assertTrue(param(config, "/rtabmap/rtabmap/config_path").endswith("config/lidar2d.ini"))
        self.assertFalse(param(config, "/rtabmap/rtabmap/subscribe_depth"))
        self.assertTrue(param(config, "/rtabmap/rtabmap/subscribe_scan"))
        self.assertFalse(param(config, "/rtabmap/rtabmap/subscribe_odom"))  # wheel odometry from tf
        sim = load("demo_sim_robot.launch", time_threshold="400", namespace="robot1")
        self.assertEqual(param(sim, "/robot1/rtabmap/Rtabmap/TimeThr"), "400")
        self.assertIsNotNone(node(sim, "robot1/rtabmap"))

    def test_localization_opens_the_map_read_only(self):
        config = load("rtabmap.launch", localization="true")
        self.assertEqual(param(config, "/rtabmap/rtabmap/Mem/IncrementalMemory"), "false")
        self.assertEqual(param(load("rtabmap.launch"), "/rtabmap/rtabmap/Mem/IncrementalMemory"), "true")

    def test_rviz_only_when_asked_with_the_stock_configuration(self):
        self.assertIsNone(node(load("rtabmap.launch"), "rviz"))
        viewer = node(load("demo_sim_robot.launch", rviz="true"), "rviz")
        self.assertIsNotNone(viewer)
        config_file = viewer.args.split()[-1]
        self.assertTrue(os.path.isfile(config_file), config_file)
        with open(config_file) as f:
            text = f.read()
        for topic in ("/rtabmap/grid_map", "/rtabmap/graph_markers", "/rtabmap/mapPath", "/rtabmap/goal"):
            self.assertIn(topic, text)

    def test_icp_odometry_feeds_the_slam_node(self):
        config = load("rtabmap.launch", icp_odometry="true", visual_odometry="false", depth="false",
                      subscribe_scan="true")
        odom = node(config, "rtabmap/icp_odometry")
        self.assertIsNotNone(odom)
        self.assertIsNone(node(config, "rtabmap/visual_odometry"))
        slam = node(config, "rtabmap/rtabmap")
        self.assertIn(("odom", "odom"), [(a.split("/")[-1], b.split("/")[-1]) for a, b in slam.remap_args])


if __name__ == "__main__":
    rostest.rosrun(PKG, "launch_files", LaunchFilesTest)
