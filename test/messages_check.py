#!/usr/bin/python3
"""Checks the generated rtabmap_ros messages and services: every definition in rtabmap_msgs/
is importable, round-trips through serialisation, and keeps the classic field layout."""
import io
import os
import sys
import unittest

import rospkg
import rostest
import rtabmap_ros.msg as msgs
import rtabmap_ros.srv as srvs

PKG_DIR = rospkg.RosPack().get_path("rtabmap_ros")


def definitions(kind):
    folder = os.path.join(PKG_DIR, "rtabmap_msgs", kind)
    return sorted(f[: -len(kind) - 1] for f in os.listdir(folder) if f.endswith("." + kind))


def round_trip(message):
    buf = io.BytesIO()
    message.serialize(buf)
    copy = type(message)()
    copy.deserialize(buf.getvalue())
    return copy


class Messages(unittest.TestCase):
    def test_every_message_is_generated_and_round_trips(self):
        names = definitions("msg")
        self.assertGreaterEqual(len(names), 18)
        for name in names:
            cls = getattr(msgs, name, None)
            self.assertIsNotNone(cls, f"rtabmap_ros/{name} was not generated")
            self.assertEqual(round_trip(cls()), cls(), name)

    def test_every_service_is_generated(self):
        expected = {"GetMap", "PublishMap", "GetNodeData", "SetGoal", "SetLabel", "ListLabels",
                    "RemoveLabel", "LoadDatabase", "ResetPose", "AddLink", "GetNodesInRadius",
                    "GetPlan"}
        names = set(definitions("srv"))
        self.assertTrue(expected <= names, f"missing services: {expected - names}")
        for name in names:
            srv = getattr(srvs, name, None)
            self.assertIsNotNone(srv, f"rtabmap_ros/{name} service was not generated")
            round_trip(getattr(srvs, name + "Request")())
            round_trip(getattr(srvs, name + "Response")())

    def test_octomap_has_the_octomap_msgs_fields(self):
        m = msgs.OctoMap()
        self.assertEqual(m.__slots__, ["header", "binary", "id", "resolution", "data"])
        m.binary, m.id, m.resolution, m.data = True, "OcTree", 0.05, [1, -2, 3]
        self.assertEqual(list(round_trip(m).data), [1, -2, 3])

    def test_classic_fields_kept(self):
        link = msgs.Link(fromId=3, toId=7, type=1)
        link.information = [float(i) for i in range(36)]
        copy = round_trip(link)
        self.assertEqual((copy.fromId, copy.toId, copy.type), (3, 7, 1))
        self.assertEqual(list(copy.information), [float(i) for i in range(36)])
        for field in ("rgb", "depth", "rgb_camera_info", "depth_camera_info", "rgb_compressed",
                      "depth_compressed", "key_points", "points", "descriptors", "global_descriptor"):
            self.assertIn(field, msgs.RGBDImage.__slots__)
        for field in ("refId", "loopClosureId", "proximityDetectionId", "loopClosureTransform",
                      "wmState", "posteriorKeys", "posteriorValues", "likelihoodKeys",
                      "rawLikelihoodKeys", "weightsKeys", "labelsKeys", "statsKeys", "statsValues"):
            self.assertIn(field, msgs.Info.__slots__)
        self.assertEqual(msgs.MapData.__slots__, ["header", "graph", "nodes"])
        self.assertEqual(msgs.MapGraph.__slots__, ["header", "mapToOdom", "posesId", "poses", "links"])


if __name__ == "__main__":
    rostest.rosrun("rtabmap_ros", "messages", Messages, sys.argv)
