#!/usr/bin/env python3
"""rostest check (fault_dropout.test): sensor dropouts through the rtabmap node on a simulator
bag rewritten with holes: the camera topics silent for 30 s, the lidar (/scan) silent for 30 s,
the odometry (odom -> base_link in tf, and /odom) missing for 10 s, then the bag played again
from 2 s in (the clock jumps backwards, odometry restarted). The node must not crash, must say
what is missing (the "did not receive data since 5 seconds" warning, whose per-topic last stamps
show the silent topics stopped at the hole while the others went on; the missing
odom -> base_link transform), map again after each hole in the same map, and start a new map on
the restart."""
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
SCAN_HOLE = (95.0, 125.0)
ODOM_HOLE = (150.0, 160.0)
SCAN_TOPIC = "/scan"
NEW_RECORD = re.compile(r"^(\x1b\[[0-9;]*m)*\[ ?(DEBUG|INFO|WARN|ERROR|FATAL)\]")  # a rosconsole or core log line
# A topic's line in that warning: what came since the last synchronised set, or that it stopped.
TOPIC_STATUS = re.compile(r"^\s+(/\S+) \[[^]]*\]: (\d+ received|stopped)\D*last stamp ([0-9.]+)")


def odometry_tf(transform):
    return transform.header.frame_id.lstrip("/") == "odom" and transform.child_frame_id.lstrip("/") == "base_link"


def punch_holes(source, target):
    """Copies the bag without the camera topics in CAMERA_HOLE, the lidar in SCAN_HOLE and
    odometry (tf and /odom) in ODOM_HOLE."""
    dropped = {"camera": 0, "lidar": 0, "odometry": 0}
    with rosbag.Bag(source) as src, rosbag.Bag(target, "w") as dst:
        # With their connection headers: /tf_static stays latched.
        for topic, msg, t, header in src.read_messages(return_connection_header=True):
            s = t.to_sec() - START
            if topic in fault.CAMERA_TOPICS and CAMERA_HOLE[0] <= s < CAMERA_HOLE[1]:
                dropped["camera"] += 1
                continue
            if topic == SCAN_TOPIC and SCAN_HOLE[0] <= s < SCAN_HOLE[1]:
                dropped["lidar"] += 1
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
        source = fault.make_sim_bag(self, cls.folder, rospy.get_param("~duration", 180), start_stamp=START)
        cls.bag = os.path.join(cls.folder, "holes.bag")
        dropped = punch_holes(source, cls.bag)
        rospy.loginfo("bag with holes: %s messages dropped", dropped)
        self.assertGreater(dropped["camera"], 3 * 50)
        self.assertGreater(dropped["lidar"], 50)
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

        def within(hole):
            return [i for i in infos if hole[0] <= at(i) < hole[1]]

        before = within((0.0, CAMERA_HOLE[0]))
        after_camera = within((CAMERA_HOLE[1], SCAN_HOLE[0]))
        after_scan = within((SCAN_HOLE[1], ODOM_HOLE[0]))
        after = within((ODOM_HOLE[1], float("inf")))
        # Frames of the odometry hole still queued when odometry comes back get a pose that tf2
        # interpolates across the whole gap: counted, not refused (the node's behaviour).
        no_odometry = [round(at(i), 1) for i in within(ODOM_HOLE)]
        rospy.loginfo("updates: %d before the camera hole, %d after it, %d after the lidar hole, %d after the "
                      "odometry hole; in the odometry hole (tf interpolated across it) at %s s", len(before),
                      len(after_camera), len(after_scan), len(after), no_odometry)
        self.assertGreater(len(before), 10)
        self.assertGreater(len(after_camera), 10, "no mapping after the camera came back")
        self.assertGreater(len(after_scan), 10, "no mapping after the lidar came back")
        self.assertGreater(len(after), 10, "no mapping after odometry came back")
        # The node synchronises camera and lidar exactly: no update without either.
        self.assertFalse(within(CAMERA_HOLE), "updates without camera data")
        self.assertFalse(within(SCAN_HOLE), "updates without a laser scan")
        # The holes are input the node never got: its info says how much (rtabmap_sync counts the
        # messages missing from each topic's stamps): 3 camera topics x 2 Hz x 30 s, 2 Hz x 30 s.
        missing = [fault.stat(x[-1], "Sync/Missing_from_stamps/") for x in (before, after_camera, after_scan)]
        self.assertGreater(missing[1] - missing[0], 3 * 50, "camera hole not counted: %s" % missing)
        self.assertGreater(missing[2] - missing[1], 50, "lidar hole not counted: %s" % missing)
        # One map throughout: a hole is not an odometry reset.
        self.assertEqual(fault.stat(before[0], "Loop/Map_id"), fault.stat(after[-1], "Loop/Map_id"))

        lines = log.splitlines()
        warnings = self.silence_warnings(lines)
        self.assertTrue(warnings, "no \"did not receive data\" warning:\n" + log[-3000:])
        # Each hole has its warning, and the per-topic stamps in it tell which input went silent:
        # the silent topics' last stamps just before the hole, the others' after its start.
        self.assertTrue(self.names_silent(warnings, fault.CAMERA_TOPICS, (SCAN_TOPIC,), CAMERA_HOLE[0]),
                        "no warning showing the camera topics silent from %.0f s: %s" % (CAMERA_HOLE[0], warnings))
        self.assertTrue(self.names_silent(warnings, (SCAN_TOPIC,), fault.CAMERA_TOPICS, SCAN_HOLE[0]),
                        "no warning showing %s silent from %.0f s: %s" % (SCAN_TOPIC, SCAN_HOLE[0], warnings))
        missing_tf = [l for l in lines if "odom" in l and "base_link" in l and ("WARN" in l or "ERROR" in l)]
        self.assertTrue(missing_tf, "no warning about the missing odom -> base_link:\n" + log[-3000:])
        rospy.loginfo("%d silence warnings; %s", len(warnings), missing_tf[0].strip())

    @staticmethod
    def silence_warnings(lines):
        """Each "did not receive data" warning as {topic: (stopped, last stamp in s from the bag's
        start)}: the warning lists each subscribed topic on a line of its own."""
        warnings = []
        for n, line in enumerate(lines):
            if "did not receive data since" not in line:
                continue
            stamps = {}
            for l in lines[n + 1:]:
                if NEW_RECORD.match(l):
                    break
                m = TOPIC_STATUS.match(l)
                if m:
                    stamps[m.group(1)] = (m.group(2) == "stopped", float(m.group(3)) - START)
            warnings.append(stamps)
        return warnings

    @staticmethod
    def names_silent(warnings, silent, going, hole_start):
        """A warning that says every `silent` topic stopped, its last stamp within 1.5 s before
        hole_start (2 Hz), while every `going` topic came on past hole_start + 2 s."""
        for w in warnings:
            if all(t in w for t in silent + going) and \
                    all(w[t][0] and hole_start - 1.5 <= w[t][1] < hole_start for t in silent) and \
                    all(not w[t][0] and w[t][1] > hole_start + 2.0 for t in going):
                return True
        return False


if __name__ == "__main__":
    rospy.init_node("fault_dropout_check")
    rostest.rosrun(fault.PKG, "fault_dropout", FaultDropoutTest, sys.argv)
