#!/usr/bin/env python3
"""rostest check of the 3D map topics (map_topics.test): the rtabmap node and a map_assembler
(namespace /assembler) fed by its mapData, on a bag of the simulator's `loop` scenario (RGB-D +
laser, 3D local grids from both).

First part of the bag with nobody on the map topics: every info says no map was assembled
(Maps/Assembling_updates/ stays 0, no time spent). Then the test subscribes: the latched maps
come at once, built from the whole map, and follow the second part. At the end: cloud_map,
octomap_binary (decoded here: resolution, tree structure, occupied leaves), octomap_full,
octomap_occupied_space / obstacles / ground, the occupied-cell markers and octomap_grid agree
with each other and with the graph, and the map_assembler's grid_map and cloud_map equal the
node's."""
import os
import struct
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import OccupancyGrid
from sensor_msgs.msg import PointCloud2
from visualization_msgs.msg import MarkerArray

from rtabmap_ros.msg import Info, MapGraph, OctoMap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402  (the simulator bag)
import odom_common as common  # noqa: E402  (temporary folders, bag playing, waiting)

PKG = "rtabmap_ros"
CELL = 0.05  # Grid/CellSize of the test


def stat(info, key):
    return dict(zip(info.statsKeys, info.statsValues)).get(key)


def decode_binary_octree(data):
    """octomap's writeBinaryData stream (OcTree::readBinaryData's format): depth first, each
    node two bytes of 2 bits per child: 01 occupied leaf, 10 free leaf, 11 inner, 00 unknown.
    Returns (occupied leaves, free leaves, deepest level); raises ValueError if the stream is
    short, too deep, or has bytes left over."""
    raw = bytes(b & 0xFF for b in data)
    pos, occupied, free, deepest = 0, 0, 0, 0
    stack = [1]  # depths of the nodes still to read
    while stack:
        depth = stack.pop()
        if depth > 16:
            raise ValueError("tree deeper than 16")
        if pos + 2 > len(raw):
            raise ValueError(f"stream ends inside a node at byte {pos}")
        bits = raw[pos] | (raw[pos + 1] << 8)
        pos += 2
        inner = []
        for i in range(8):
            low, high = (bits >> (2 * i)) & 1, (bits >> (2 * i + 1)) & 1
            if low and high:
                inner.append(depth + 1)
            elif high:
                occupied += 1
                deepest = max(deepest, depth)
            elif low:
                free += 1
                deepest = max(deepest, depth)
        stack.extend(reversed(inner))  # children in order, depth first
    if pos != len(raw):
        raise ValueError(f"{len(raw) - pos} bytes after the tree")
    return occupied, free, deepest


def xyz(cloud):
    """(x, y, z) tuples of a packed float32 x y z [rgb] cloud."""
    offsets = {f.name: f.offset for f in cloud.fields}
    out = []
    for i in range(cloud.width * cloud.height):
        base = i * cloud.point_step
        out.append(struct.unpack_from("<fff", cloud.data, base + offsets["x"]))
    return out


class MapTopicsTest(unittest.TestCase):
    def setUp(self):
        self.info, self.graphs, self.got = [], [], {}
        rospy.Subscriber("/info", Info, self.info.append)
        rospy.Subscriber("/mapGraph", MapGraph, self.graphs.append)
        self.subscribers = []

    def listen(self, topic, msg_type):
        self.got[topic] = []
        self.subscribers.append(rospy.Subscriber(topic, msg_type, self.got[topic].append))

    def make_bag(self, duration):
        return fault.make_sim_bag(self, common.workdir(self, "map_topics_"), duration)

    def play(self, bag, start, duration=None):
        """rosbag play --clock of [start, start + duration) s of the bag, then waits for the node."""
        common.play(self, bag, rospy.get_param("~rate", 6), start=start, duration=duration)
        common.wait_quiet(self.info, quiet=3.0, timeout=30.0)

    def same_update(self, topics, timeout=15.0):
        """Waits until the last message of every topic comes from one update (same header
        stamp): a large message (the marker cubes) can still be on its way when a smaller view
        of the next update has arrived."""
        def stamp(msg):
            if hasattr(msg, "markers"):  # MarkerArray: no header of its own
                return msg.markers[-1].header.stamp if msg.markers else None
            return msg.header.stamp

        def agree():
            stamps = {stamp(self.got[t][-1]) for t in topics if self.got[t]}
            return all(self.got[t] for t in topics) and len(stamps) == 1
        self.assertTrue(common.wait_for(agree, timeout), "the views of %s never came from one update" % topics)

    def latest(self, topic, timeout=15.0):
        self.assertTrue(common.wait_for(lambda: self.got[topic], timeout), f"nothing on {topic}")
        return self.got[topic][-1]

    def test_map_topics(self):
        bag = self.make_bag(rospy.get_param("~duration", 120))
        split = rospy.get_param("~split", 50)
        started = time.time()
        self.play(bag, 0, split)
        self.check_nothing_assembled()

        for topic, msg_type in [("/cloud_map", PointCloud2), ("/octomap_binary", OctoMap),
                                ("/octomap_full", OctoMap), ("/octomap_occupied_space", PointCloud2),
                                ("/octomap_obstacles", PointCloud2), ("/octomap_ground", PointCloud2),
                                ("/octomap_empty_space", PointCloud2), ("/occupied_cells_vis_array", MarkerArray),
                                ("/octomap_grid", OccupancyGrid), ("/grid_map", OccupancyGrid),
                                ("/assembler/grid_map", OccupancyGrid), ("/assembler/cloud_map", PointCloud2),
                                ("/assembler/octomap_binary", OctoMap)]:
            self.listen(topic, msg_type)
        # The clock is stopped: what comes now was built at subscription, from the whole map.
        nodes = len(self.graphs[-1].posesId)
        cloud = self.latest("/cloud_map")
        self.latest("/octomap_binary")
        assembler_grid = self.latest("/assembler/grid_map")
        rospy.loginfo("at subscription (%d nodes): cloud_map %d points, assembler grid_map %dx%d", nodes,
                      cloud.width, assembler_grid.info.width, assembler_grid.info.height)
        self.assertGreater(cloud.width, 1000)

        info_before = len(self.info)
        self.play(bag, split)
        rospy.loginfo("bag played in %.1f s wall", time.time() - started)
        after = self.info[info_before:]
        self.assertGreater(len(after), 10)
        self.assertTrue(all(stat(i, "Maps/Assembling_updates/") > 0 for i in after))
        last = self.info[-1]
        graph = self.graphs[-1]
        times = sorted(stat(i, "Maps/Time/ms") for i in after)
        rospy.loginfo("last update: %d nodes in the graph, cloud %d nodes, octomap %d nodes; second part: %d updates, "
                      "octomap rebuilt at %d, maps time median %.1f ms, max %.1f ms", len(graph.posesId),
                      stat(last, "Maps/Cloud_nodes/"), stat(last, "Maps/OctoMap_nodes/"), len(after),
                      sum(stat(i, "Maps/OctoMap_rebuilt/") for i in after), times[len(times) // 2], times[-1])
        # The maps are assembled off the SLAM update (a worker thread): info's Maps/* describe the
        # last COMPLETED assembly, an earlier update's (Maps/Graph_nodes/: the size of its graph),
        # and updates arriving while it works coalesce into one job.
        assembled = stat(last, "Maps/Graph_nodes/")
        rospy.loginfo("last info: its assembly had %d graph nodes, %d grids fetched; %d updates coalesced",
                      assembled, stat(last, "Maps/Grids_fetched/"), stat(last, "Maps/Coalesced_jobs/"))
        self.assertIn(assembled, {len(g.posesId) for g in self.graphs}, "not the graph of an update")
        # Every node of the graph has a 3D local grid here: each map assembles all of them.
        self.assertEqual(stat(last, "Maps/Cloud_nodes/"), assembled)
        self.assertEqual(stat(last, "Maps/OctoMap_nodes/"), assembled)
        self.assertLess(stat(last, "Maps/Grids_fetched/"), 0.25 * assembled,
                        "the grids of the updates' nodes only, not the whole map again")
        # ... and the worker's last job is the last update's: the cloud catches up with the update
        # that added the graph's last node.
        complete = min(g.header.stamp for g in self.graphs if len(g.posesId) == len(graph.posesId))
        self.assertTrue(common.wait_for(lambda: self.got["/cloud_map"][-1].header.stamp >= complete, 15.0),
                        "cloud_map never caught up with the last update")

        self.check_cloud_map()
        self.check_octomap()
        self.check_assembler()

    def check_nothing_assembled(self):
        self.assertGreater(len(self.info), 10, "too few SLAM updates on info")
        for i in self.info:
            self.assertEqual(stat(i, "Maps/Assembling_updates/"), 0.0, "a map was assembled with nobody listening")
            self.assertEqual(stat(i, "Maps/Grids_fetched/"), 0.0)
            self.assertEqual(stat(i, "Maps/Cloud_nodes/"), 0.0)
            self.assertEqual(stat(i, "Maps/OctoMap_nodes/"), 0.0)
            self.assertEqual(stat(i, "Maps/Time/ms"), 0.0)
        rospy.loginfo("first part: %d updates, no map assembled", len(self.info))

    def check_cloud_map(self):
        cloud = self.latest("/cloud_map")
        grid = self.latest("/grid_map")
        self.assertEqual(cloud.header.frame_id, "map")
        self.assertIn("rgb", [f.name for f in cloud.fields], "the RGB-D nodes' colours are lost")
        points = xyz(cloud)
        # In the map frame, within the 2D grid's extent (same nodes, same poses); voxel filtered
        # at the cell size: no two points in one voxel.
        x0, y0 = grid.info.origin.position.x, grid.info.origin.position.y
        x1, y1 = x0 + grid.info.width * grid.info.resolution, y0 + grid.info.height * grid.info.resolution
        outside = [p for p in points if not (x0 - CELL <= p[0] <= x1 + CELL and y0 - CELL <= p[1] <= y1 + CELL)]
        self.assertFalse(outside, f"{len(outside)} cloud points outside the grid's extent, e.g. {outside[:3]}")
        voxels = {(int(p[0] // CELL), int(p[1] // CELL), int(p[2] // CELL)) for p in points}
        self.assertGreater(len(voxels), 0.9 * len(points))
        heights = sorted(p[2] for p in points)
        rospy.loginfo("cloud_map: %d points, z from %.2f to %.2f m", len(points), heights[0], heights[-1])
        self.assertGreater(heights[-1] - heights[0], 0.3, "the cloud is flat: no 3D local grids?")

    def check_octomap(self):
        self.same_update(["/octomap_binary", "/octomap_full", "/octomap_occupied_space", "/octomap_obstacles",
                          "/octomap_ground", "/octomap_empty_space", "/occupied_cells_vis_array"])
        binary = self.latest("/octomap_binary")
        full = self.latest("/octomap_full")
        self.assertEqual(binary.header.frame_id, "map")
        self.assertTrue(binary.binary)
        self.assertEqual(binary.id, "OcTree")
        self.assertAlmostEqual(binary.resolution, CELL, places=6)
        occupied, free, deepest = decode_binary_octree(binary.data)
        self.assertEqual(deepest, 16, "leaves at full resolution")
        self.assertFalse(full.binary)
        self.assertEqual(full.id, "ColorOcTree")
        self.assertAlmostEqual(full.resolution, CELL, places=6)
        self.assertGreater(len(full.data), len(binary.data), "full: probabilities and colours per node")

        occupied_space = self.latest("/octomap_occupied_space")
        obstacles, ground = self.latest("/octomap_obstacles"), self.latest("/octomap_ground")
        empty = self.latest("/octomap_empty_space")
        markers = self.latest("/occupied_cells_vis_array")
        rospy.loginfo("octomap: %d bytes binary (%d occupied, %d free leaves), %d full; occupied_space %d "
                      "(%d obstacles + %d ground), empty_space %d", len(binary.data), occupied, free, len(full.data),
                      occupied_space.width, obstacles.width, ground.width, empty.width)
        # One tree state, several views: they must agree exactly.
        self.assertGreater(obstacles.width, 500)
        self.assertGreater(ground.width, 500)
        self.assertEqual(occupied_space.width, obstacles.width + ground.width)
        self.assertEqual(occupied, occupied_space.width, "decoded occupied leaves != occupied voxels published")
        cubes = [m for m in markers.markers if m.action == m.ADD]
        self.assertEqual(sorted(m.ns for m in cubes), ["ground", "obstacles"])
        self.assertEqual(sum(len(m.points) for m in cubes), occupied_space.width)
        self.assertTrue(all(abs(m.scale.x - CELL) < 1e-6 for m in cubes))
        # Free voxels between the sensor and what it saw, none of them occupied.
        self.assertGreater(empty.width, 0)
        self.assertFalse(set(xyz(empty)) & set(xyz(occupied_space)))

        projected = self.latest("/octomap_grid")
        self.assertAlmostEqual(projected.info.resolution, CELL, places=6)
        cells = projected.data
        self.assertEqual(len(cells), projected.info.width * projected.info.height)
        self.assertGreater(sum(1 for v in cells if v == 100), 100)
        self.assertGreater(sum(1 for v in cells if v == 0), 1000)

    def check_assembler(self):
        """map_assembler, fed only by mapData, ends with the node's maps."""
        # The assembler publishes when its grid changes: at least at the update that added the
        # graph's last node. Compared with the node's grid of the same update.
        final = len(self.graphs[-1].posesId)
        complete = min(g.header.stamp for g in self.graphs if len(g.posesId) == final)
        ok = common.wait_for(lambda: self.got["/assembler/grid_map"][-1].header.stamp >= complete, 10.0)
        self.assertTrue(ok, "map_assembler did not follow the last update")
        theirs = self.got["/assembler/grid_map"][-1]
        mine = [g for g in self.got["/grid_map"] if g.header.stamp == theirs.header.stamp]
        self.assertTrue(mine, "no grid_map of the node at the assembler's last stamp")
        mine = mine[-1]
        self.assertEqual(theirs.header.frame_id, "map")
        self.assertEqual((theirs.info.width, theirs.info.height), (mine.info.width, mine.info.height))
        self.assertAlmostEqual(theirs.info.resolution, mine.info.resolution, places=6)
        self.assertAlmostEqual(theirs.info.origin.position.x, mine.info.origin.position.x, places=4)
        self.assertAlmostEqual(theirs.info.origin.position.y, mine.info.origin.position.y, places=4)
        differ = sum(1 for a, b in zip(mine.data, theirs.data) if a != b)
        known = sum(1 for v in mine.data if v != -1)
        rospy.loginfo("grid_map %dx%d: %d known cells, %d differ from map_assembler's", mine.info.width,
                      mine.info.height, known, differ)
        self.assertGreater(known, 1000)
        # Same local grids, same final poses, and GridGlobal/UpdateError 0 in both (every node
        # that moved is re-placed), so neither depends on which updates it assembled (the
        # assembler's worker coalesces some): equal, 0 cells differ in every run seen. With the
        # default 1 cm, nodes nudged under it stay where each happened to place them: up to 1.9%
        # differed under load.
        self.assertLessEqual(differ, 0.001 * known)

        cloud, theirs_cloud = self.latest("/cloud_map"), self.latest("/assembler/cloud_map")
        self.assertLessEqual(abs(cloud.width - theirs_cloud.width), 0.001 * cloud.width)
        octomap = self.latest("/assembler/octomap_binary")
        occupied, _, _ = decode_binary_octree(octomap.data)
        rospy.loginfo("map_assembler: cloud_map %d points (node %d), octomap %d occupied leaves", theirs_cloud.width,
                      cloud.width, occupied)
        self.assertGreater(occupied, 1000)


if __name__ == "__main__":
    rospy.init_node("map_topics_check")
    rostest.rosrun(PKG, "map_topics", MapTopicsTest, sys.argv)
