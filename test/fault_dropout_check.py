#!/usr/bin/env python3
"""rostest check (fault_dropout.test): sensor dropouts through the rtabmap node on a simulator
bag rewritten with holes: the camera topics silent for 30 s, the odometry (odom -> base_link in
tf, and /odom) missing for 10 s, then the bag played again from 2 s in (the clock jumps
backwards, odometry restarted). The node must not crash, must say what is missing
(the "did not receive data since 5 seconds" warning naming the camera topics, the missing
odom -> base_link transform), map again after each hole, and start a new map on the restart."""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest

from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import Info, MapGraph

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402
import odom_common as common  # noqa: E402  (temporary folders, bag playing, waiting)

START = 1700000000
CAMERA_HOLE = (40.0, 70.0)  # seconds from the start of the bag
ODOM_HOLE = (100.0, 110.0)
NEW_RECORD = re.compile(r"^(\x1b\[[0-9;]*m)*\[ ?(DEBUG|INFO|WARN|ERROR|FATAL)\]")  # a rosconsole or core log line


def odometry_tf(transform):
    return transform.header.frame_id.lstrip("/") == "odom" and transform.child_frame_id.lstrip("/") == "base_link"


def punch_holes(source, target):
    """Copies the bag without the camera topics in CAMERA_HOLE and without odometry (tf and
    /odom) in ODOM_HOLE."""
    dropped = {"camera": 0, "odometry": 0}
    with rosbag.Bag(source) as src, rosbag.Bag(target, "w") as dst:
        # With their connection headers: /tf_static stays latched.
        for topic, msg, t, header in src.read_messages(return_connection_header=True):
            s = t.to_sec() - START
            if topic in fault.CAMERA_TOPICS and CAMERA_HOLE[0] <= s < CAMERA_HOLE[1]:
                dropped["camera"] += 1
                continue
            if ODOM_HOLE[0] <= s < ODOM_HOLE[1]:
                if topic == "/odom":
                    dropped["odometry"] += 1
                    continue
                if topic == "/tf":
                    kept = [x for x in msg.transforms if not odometry_tf(x)]
                    dropped["odometry"] += len(msg.transforms) - len(kept)
                    if not kept:
                        continue
                    msg.transforms = kept
            dst.write(topic, msg, t, connection_header=header)
    return dropped


class FaultDropoutTest(unittest.TestCase):
    """One node for both tests, in order: the holes, then the same bag again from its start."""
    infos, graphs, logs, node, bag = [], [], [], None, None

    @classmethod
    def setUpClass(cls):
        rospy.Subscriber("/info", Info, cls.infos.append)
        rospy.Subscriber("/mapGraph", MapGraph, cls.graphs.append)
        rospy.Subscriber("/rosout", Log, cls.logs.append)
        cls.folder = tempfile.mkdtemp(prefix="fault_dropout_")

    @classmethod
    def tearDownClass(cls):
        if cls.node:
            cls.node.kill()
        shutil.rmtree(cls.folder, True)

    def test_1_dropouts(self):
        cls = type(self)
        source = fault.make_sim_bag(self, cls.folder, rospy.get_param("~duration", 150), start_stamp=START)
        cls.bag = os.path.join(cls.folder, "holes.bag")
        dropped = punch_holes(source, cls.bag)
        rospy.loginfo("bag with holes: %s messages dropped", dropped)
        self.assertGreater(dropped["camera"], 3 * 50)
        self.assertGreater(dropped["odometry"], 10)

        cls.node = fault.SlamNode(cls.folder, os.path.join(cls.folder, "dropout.db"))
        cls.node.start()
        cls.node.wait_ready()
        common.play(self, cls.bag, rospy.get_param("~rate", 3), timeout=200)
        common.wait_quiet(self.infos, quiet=2.0, timeout=20.0)
        self.assertTrue(cls.node.alive(), "the node died during the dropouts:\n" + cls.node.log()[-3000:])
        self.check_holes(list(self.infos), cls.node.log())

    def test_2_restarted_bag(self):
        """The bag again from near its start: time jumps back, odometry restarted. Its first 2 s
        are skipped, so the first frame after the jump is not at the odometry origin (as when the
        first frames are lost while tf refills): the jump itself must start the new map."""
        node = type(self).node
        if not node or not node.alive() or not self.infos:
            self.fail("test_1_dropouts did not leave a mapping node")
        first = list(self.infos)
        subprocess.run(["rosbag", "play", "--clock", "-q", "-r", str(rospy.get_param("~rate", 3)), "-s", "2", "-u",
                        "38", type(self).bag], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120,
                       check=True)
        common.wait_quiet(self.infos, quiet=2.0, timeout=20.0)
        log = node.log()
        self.assertTrue(node.alive(), "the node died when the bag restarted:\n" + log[-3000:])
        again = self.infos[len(first):]
        # rtabmap_sync starts over when ROS time jumps back (its warning says so).
        self.assertIn("ROS time jumped back", log)
        self.assertGreater(len(again), 5, "no mapping after the bag restarted:\n" + log[-3000:])
        first_map = fault.stat(first[-1], "Loop/Map_id")
        new_map = fault.stat(again[-1], "Loop/Map_id")
        rospy.loginfo("restarted bag: %d updates in map %s (was %s)", len(again), new_map, first_map)
        self.assertGreater(new_map, first_map, "no new map when odometry restarted")
        self.assertIn(again[-1].refId, self.graphs[-1].posesId)
        # The core's own log (here its "new map" line) reaches /rosout, not only stderr.
        core = [l for l in self.logs if "new map" in l.msg and l.file.endswith("CoreLog.cpp")]
        self.assertTrue(core, "the core's \"new map\" message is not on /rosout")
        self.assertEqual(node.kill(signal.SIGINT), 0, "unclean end:\n" + node.log()[-3000:])

    def check_holes(self, infos, log):
        def at(i):
            return i.header.stamp.to_sec() - START

        before = [i for i in infos if at(i) < CAMERA_HOLE[0]]
        between = [i for i in infos if CAMERA_HOLE[1] <= at(i) < ODOM_HOLE[0]]
        after = [i for i in infos if at(i) >= ODOM_HOLE[1]]
        no_camera = [i for i in infos if CAMERA_HOLE[0] <= at(i) < CAMERA_HOLE[1]]
        # Frames of the odometry hole still queued when odometry comes back get a pose that tf2
        # interpolates across the whole gap: counted, not refused (the node's behaviour).
        no_odometry = [round(at(i), 1) for i in infos if ODOM_HOLE[0] <= at(i) < ODOM_HOLE[1]]
        rospy.loginfo("updates: %d before the camera hole, %d between the holes, %d after; in the odometry hole "
                      "(tf interpolated across it) at %s s", len(before), len(between), len(after), no_odometry)
        self.assertGreater(len(before), 10)
        self.assertGreater(len(between), 10, "no mapping after the camera came back")
        self.assertGreater(len(after), 10, "no mapping after odometry came back")
        self.assertFalse(no_camera, "updates without camera data")
        # The 30 s camera hole is input the node never got: its info says how much (rtabmap_sync
        # counts the messages missing from each topic's stamps).
        self.assertGreater(fault.stat(after[-1], "Sync/Missing_from_stamps/"), 3 * 50)
        # One map throughout: a hole is not an odometry reset.
        self.assertEqual(fault.stat(before[0], "Loop/Map_id"), fault.stat(after[-1], "Loop/Map_id"))

        lines = log.splitlines()
        silent = [l for l in lines if "did not receive data since" in l]
        self.assertTrue(silent, "no \"did not receive data\" warning:\n" + log[-3000:])
        # The warning lists each subscribed topic on a line of its own, with its last stamp.
        first = next(n for n, l in enumerate(lines) if "did not receive data since" in l)
        end = next((n for n in range(first + 1, len(lines)) if NEW_RECORD.match(lines[n])), len(lines))
        block = "\n".join(lines[first:end])
        for topic in fault.CAMERA_TOPICS[:2] + ("/scan",):
            self.assertIn(topic, block, "the warning does not name " + topic)
        missing_tf = [l for l in lines if "odom" in l and "base_link" in l and ("WARN" in l or "ERROR" in l)]
        self.assertTrue(missing_tf, "no warning about the missing odom -> base_link:\n" + log[-3000:])
        rospy.loginfo("warnings: %s | %s", silent[0].strip(), missing_tf[0].strip())


if __name__ == "__main__":
    rospy.init_node("fault_dropout_check")
    rostest.rosrun(fault.PKG, "fault_dropout", FaultDropoutTest, sys.argv)
