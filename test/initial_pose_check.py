#!/usr/bin/env python3
"""rostest check (initial_pose.test) of the rtabmap node's initial pose: the `initialpose` topic
and the `initial_pose` parameter, in localization mode on a map of the simulator's ring (laser
only); and get_map_data at the start of a new session on an existing database.

The truth in the map frame: the simulator's ground truth (bag topic /ground_truth) brought
into the map frame by the mapped node nearest to that place (its optimised pose against the
ground truth at its stamp), so the error measured is the localization's against the map, not
the odometry drift the map kept."""
import math
import os
import signal
import sys
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from rtabmap_ros.msg import Info, MapGraph
from rtabmap_ros.srv import GetMap
from std_srvs.srv import Empty

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402  (sim bag, the node as a child process)
import odom_common as common  # noqa: E402  (bag playing, temporary folders, waiting, pose algebra)

MAPPED = 120.0  # seconds of the bag in the map
START = 30.0    # localization starts there: 16 m from the map's end (RGBD/LocalRadius is 10 m)
PART = 15.0     # seconds of each localization replay
LASER_ONLY = {
    "subscribe_depth": False,
    "Reg/Strategy": "1",
    "Kp/MaxFeatures": "-1",
    "RGBD/CreateOccupancyGrid": "false",
    # As the core's simulator tests: a proximity guess carries the odometry drift, and a pose
    # clicked in rviz is a few decimetres off; ICP may correct more than between scans.
    "Icp/MaxTranslation": "1",
    "Icp/MaxRotation": "0.5",
}


def yaw_of(m):
    return math.atan2(m[1, 0], m[0, 0])


class InitialPoseTest(unittest.TestCase):
    def setUp(self):
        self.truth, self.infos, self.graphs, self.localizations = {}, [], [], []
        rospy.Subscriber("/ground_truth", Odometry, lambda m: self.truth.__setitem__(m.header.stamp.to_nsec(), m))
        rospy.Subscriber("/info", Info, self.infos.append)
        rospy.Subscriber("/mapGraph", MapGraph, self.graphs.append)
        rospy.Subscriber("/localization_pose", PoseWithCovarianceStamped, self.localizations.append)
        self.initialpose = rospy.Publisher("/initialpose", PoseWithCovarianceStamped, queue_size=1, latch=False)
        self.rate = rospy.get_param("~rate", 6)
        self.tf_buffer = tf2_ros.Buffer(rospy.Duration(600.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)

    def node(self, folder, db, name, **parameters):
        """The rtabmap node, its log in folder/name/; stdout line-buffered, so its INFO lines
        (what it did with an initial pose) are in the log as they are printed."""
        p = dict(LASER_ONLY)
        p.update(parameters)
        logs = os.path.join(folder, name)
        os.makedirs(logs, exist_ok=True)
        n = fault.SlamNode(logs, db, p, shell_prefix='exec stdbuf -oL "$0" "$@"')
        self.addCleanup(n.kill)
        return n

    def play(self, start, duration):
        common.play(self, self.bag, self.rate, timeout=120, start=start, duration=duration)

    def truth_at(self, stamp_ns):
        """Ground truth (4x4, world frame) at the nearest stamp."""
        key = min(self.truth, key=lambda k: abs(k - stamp_ns))
        self.assertLess(abs(key - stamp_ns), 0.3e9, "no ground truth near %.3f" % (stamp_ns * 1e-9))
        return common.odom_matrix(self.truth[key])

    def keep_map(self, graph):
        """The mapped nodes' optimised poses (4x4) and stamps, for truth_in_map()."""
        stamps = {i.refId: i.header.stamp.to_nsec() for i in self.infos if i.refId > 0}
        self.nodes = [(stamps[n], common.matrix(p.position, p.orientation))
                      for n, p in zip(graph.posesId, graph.poses) if n in stamps]
        self.assertGreater(len(self.nodes), 50)

    def truth_in_map(self, stamp_ns):
        """The ground truth at a stamp of the mapped part, in the map frame as the map has that
        place: through the node mapped nearest in time (the robot passed there once), so the
        odometry drift the map kept elsewhere does not count."""
        node_stamp, pose = min(self.nodes, key=lambda n: abs(n[0] - stamp_ns))
        self.assertLess(abs(node_stamp - stamp_ns), 1.5e9)
        return pose @ np.linalg.inv(self.truth_at(node_stamp)) @ self.truth_at(stamp_ns)

    def check_tf(self, localization):
        """map -> odom in tf puts the robot where localization_pose says (the timer publishes
        the core's correction; odom -> base_link is the bag's)."""
        stamp = localization.header.stamp
        t = self.tf_buffer.lookup_transform("map", "base_link", stamp, rospy.Duration(2.0)).transform.translation
        p = localization.pose.pose.position
        self.assertLess(math.hypot(t.x - p.x, t.y - p.y), 0.1, "map -> base_link in tf vs localization_pose")

    def pose_text(self, m):
        return "%.4f %.4f 0 0 0 %.5f" % (m[0, 3], m[1, 3], yaw_of(m))

    def errors(self, since):
        """Distance (m) of each localization_pose from `since` on to the truth at its stamp."""
        out = []
        for msg in self.localizations[since:]:
            truth = self.truth_in_map(msg.header.stamp.to_nsec())
            p = msg.pose.pose.position
            out.append(math.hypot(p.x - truth[0, 3], p.y - truth[1, 3]))
        return out

    def test_initial_pose(self):
        folder = common.workdir(self, "initial_pose_")
        self.bag = fault.make_sim_bag(self, folder, MAPPED + 10)
        db = os.path.join(folder, "map.db")

        # 1. The map (mapping, a fresh database).
        mapper = self.node(folder, db, "mapping")
        mapper.start(["-d"])
        mapper.wait_ready()
        self.play(0, MAPPED)
        common.wait_quiet(self.infos, quiet=3.0, timeout=30.0)
        self.assertTrue(self.graphs, "no mapGraph while mapping")
        graph = self.graphs[-1]
        self.t0 = min(self.truth)
        self.keep_map(graph)
        self.assertEqual(mapper.kill(signal.SIGINT), 0, mapper.log()[-3000:])
        saved = set(fault.database_node_ids(db))
        start_truth = self.truth_in_map(self.t0 + int(START * 1e9))
        end_truth = self.truth_in_map(self.t0 + int((MAPPED - 1) * 1e9))
        self.assertGreater(np.linalg.norm(start_truth[:2, 3] - end_truth[:2, 3]), 14.0)

        # 2. A new mapping session on it: before its first node, get_map_data gives the saved
        # graph (optimised), not the new session's empty map.
        node = self.node(folder, db, "session")
        node.start()
        node.wait_ready()
        rospy.wait_for_service("/get_map_data", timeout=10.0)
        data = rospy.ServiceProxy("/get_map_data", GetMap)(True, True, True).data
        rospy.loginfo("get_map_data at the start of a new session: %d poses, %d links (database: %d nodes)",
                      len(data.graph.posesId), len(data.graph.links), len(saved))
        self.assertEqual(set(data.graph.posesId), saved, "get_map_data(global, optimized) at a new session's start")
        self.assertGreater(len(data.graph.links), len(saved) - 2)

        # 3. Localization (after a mode switch) without a pose: the robot is assumed where the
        # map ended, 16 m away; it never localises at its true place.
        rospy.wait_for_service("/set_mode_localization", timeout=10.0)
        rospy.ServiceProxy("/set_mode_localization", Empty)()
        before = len(self.localizations)
        self.play(START, PART)
        common.wait_quiet(self.infos, quiet=2.0, timeout=15.0)
        lost = self.errors(before)
        rospy.loginfo("localization without a pose: %d localization_pose, errors %s", len(lost),
                      ["%.2f" % e for e in lost])
        self.assertTrue(all(e > 1.0 for e in lost), "localised at the true place without knowing where")

        # 4. The user gives the pose on `initialpose` (the robot stands where the replay stopped):
        # the next part localises at once near the truth.
        here = self.truth_in_map(self.t0 + int((START + PART) * 1e9))
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = "map"
        msg.header.stamp = rospy.Time(0)
        msg.pose.pose.position.x, msg.pose.pose.position.y = here[0, 3], here[1, 3]
        msg.pose.pose.orientation.z = math.sin(yaw_of(here) / 2)
        msg.pose.pose.orientation.w = math.cos(yaw_of(here) / 2)
        self.assertTrue(common.wait_for(lambda: self.initialpose.get_num_connections() > 0, 10.0),
                        "the node does not subscribe to initialpose")
        self.initialpose.publish(msg)
        self.assertTrue(common.wait_for(lambda: "initialpose: the robot is at" in node.log(), 10.0),
                        "initialpose not taken:\n" + node.log()[-3000:])
        before = len(self.localizations)
        self.play(START + PART, PART)
        common.wait_quiet(self.infos, quiet=2.0, timeout=15.0)
        placed = self.errors(before)
        rospy.loginfo("localization after initialpose: %d localization_pose, errors %s", len(placed),
                      ["%.2f" % e for e in placed])
        self.assertGreater(len(placed), 2, "no localization after initialpose")
        self.assertLess(max(placed), 0.25)
        self.check_tf(self.localizations[-1])
        self.assertEqual(node.kill(signal.SIGINT), 0, node.log()[-3000:])

        # 5. The initial_pose parameter, at the start of a localization node.
        param = self.node(folder, db, "parameter", **{"Mem/IncrementalMemory": "false", "initial_pose": self.pose_text(start_truth)})
        param.start()
        param.wait_ready()
        before = len(self.localizations)
        self.play(START, PART)
        common.wait_quiet(self.infos, quiet=2.0, timeout=15.0)
        given = self.errors(before)
        rospy.loginfo("localization from initial_pose: %d localization_pose, errors %s", len(given),
                      ["%.2f" % e for e in given])
        self.assertGreater(len(given), 2, "no localization from initial_pose")
        # The pose is the truth at the replay's first frame, and the robot is already moving (0.5
        # m/s at 2 Hz): when the node's first update is a frame or two later (tf not buffered yet),
        # that update starts up to ~1 s of motion off (seen once in ten runs: 0.65 m), and the
        # next localisations correct it. Every later one must be on the truth.
        self.assertLess(given[0], 1.0)
        self.assertLess(max(given[1:]), 0.25)
        self.assertEqual(param.kill(signal.SIGINT), 0, param.log()[-3000:])
        self.assertIn("initial_pose: the robot is at", param.log())
        self.assertEqual(set(fault.database_node_ids(db)), saved, "localization modified the map")

        # 6. The same on the global scan map (RGBD/ProximityGlobalScanMap): every node's scan read
        # once, from the database too, and matched around the given pose.
        scan_map = self.node(folder, db, "global_scan_map", **{
            "Mem/IncrementalMemory": "false", "initial_pose": self.pose_text(start_truth),
            "RGBD/ProximityGlobalScanMap": "true"})
        scan_map.start()
        scan_map.wait_ready()
        before = len(self.localizations)
        self.play(START, PART)
        common.wait_quiet(self.infos, quiet=2.0, timeout=15.0)
        on_map = self.errors(before)
        rospy.loginfo("localization on the global scan map: %d localization_pose, errors %s", len(on_map),
                      ["%.2f" % e for e in on_map])
        self.assertGreater(len(on_map), 3, "no localization on the global scan map")
        # As above: the first update may start a frame or two late; on a loaded machine (seen once:
        # 0.30 m) the second is still being corrected, as a localization is applied only once a
        # later one agrees with it (RGBD/MaxOdomCacheSize). From the third on, on the truth.
        self.assertLess(on_map[0], 1.0)
        self.assertLess(on_map[1], 0.5)
        self.assertLess(max(on_map[2:]), 0.25)
        self.assertEqual(scan_map.kill(signal.SIGINT), 0, scan_map.log()[-3000:])
        self.assertIn("global scan map (RGBD/ProximityGlobalScanMap)", scan_map.log())
        self.assertEqual(set(fault.database_node_ids(db)), saved, "localization modified the map")


if __name__ == "__main__":
    rospy.init_node("initial_pose_check")
    rostest.rosrun("rtabmap_ros", "initial_pose", InitialPoseTest, sys.argv)
