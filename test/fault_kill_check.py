#!/usr/bin/env python3
"""rostest check (fault_kill.test): the rtabmap node is killed with SIGKILL at random (seeded)
points of a simulator bag's replay and restarted on the same database each time; after every
kill the database opens and passes its consistency check, and holds every node the node had
acknowledged; after the last restart the node maps the rest of the bag, and the final database
gives a pose for every node.

"Acknowledged": what the node told the world is safe on disk. Each `info` carries
Memory/Durable_node_id, the last node whose write committed (the writer commits in order), so
every node id published on `info` up to the largest Durable_node_id received before the kill
must be in the database, that node included."""
import math
import os
import random
import signal
import subprocess
import sys
import time
import unittest

import rospy
import rostest

from rtabmap_ros.msg import Info, MapGraph

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402
import odom_common as common  # noqa: E402  (temporary folders, waiting)

STM_SIZE = 10  # Mem/STMSize (the default)


def acknowledged(infos, before):
    """Node ids acknowledged as durable by `info` messages [(wall time, Info)] received before
    `before`."""
    seen = [i for t, i in infos if t <= before]
    durable = int(max((fault.stat(i, "Memory/Durable_node_id", 0) for i in seen), default=0))
    ids = {i.refId for i in seen if 0 < i.refId <= durable}
    if durable > 0:
        ids.add(durable)
    return ids


class FaultKillTest(unittest.TestCase):
    def setUp(self):
        self.infos, self.graphs = [], []
        rospy.Subscriber("/info", Info, lambda m: self.infos.append((time.time(), m)))
        rospy.Subscriber("/mapGraph", MapGraph, self.graphs.append)

    def check_database(self, path, must_hold, what):
        code, summary, out = fault.tool("rtabmap-info", "--check", path)
        self.assertEqual(code, 0, "%s: rtabmap-info --check failed:\n%s" % (what, out))
        self.assertTrue(summary and summary["consistency"]["ok"], "%s: inconsistent database:\n%s" % (what, out))
        ids = fault.database_node_ids(path)
        missing = sorted(must_hold - ids)
        self.assertFalse(missing, "%s: acknowledged nodes missing from the database: %s" % (what, missing))
        return summary, ids

    def test_sigkill_and_restart(self):
        kills = rospy.get_param("~kills", 3)
        rng = random.Random(rospy.get_param("~seed", 10))
        duration, rate = rospy.get_param("~duration", 180), rospy.get_param("~rate", 4)
        folder = common.workdir(self, "fault_kill_")
        bag = fault.make_sim_bag(self, folder, duration)
        db = os.path.join(folder, "kill.db")
        node = fault.SlamNode(folder, db)
        self.addCleanup(node.kill)
        node.start()
        node.wait_ready()

        # The player's status line goes to a file: once (with -q and its output to /dev/null) the
        # clock stopped for good after a kill; its last status then says where it stood.
        player_log = os.path.join(folder, "player.log")
        with open(player_log, "w") as out:
            player = subprocess.Popen(["rosbag", "play", "--clock", "-r", str(rate), bag], stdout=out,
                                      stderr=subprocess.STDOUT)
        self.addCleanup(lambda: player.poll() is None and player.kill())
        # One run per slice of the replay, killed at a random point once it mapped more than
        # Mem/STMSize nodes (before, nothing can be acknowledged yet).
        slice_seconds = duration / rate / (kills + 1)
        must_hold = set()
        for k in range(kills):
            run_start = time.time()
            common.wait_for(lambda: len([t for t, _ in self.infos if t >= run_start]) > STM_SIZE, 2 * slice_seconds)
            time.sleep(rng.uniform(0.0, 0.6) * slice_seconds)
            killed_at = time.time()
            self.assertTrue(node.alive(), "the node died before the kill:\n" + node.log()[-3000:])
            self.assertEqual(node.kill(signal.SIGKILL), -signal.SIGKILL)
            run = [(t, i) for t, i in self.infos if t >= run_start]
            ack = acknowledged(run, killed_at)
            must_hold |= ack
            summary, ids = self.check_database(db, must_hold, "after kill %d" % (k + 1))
            rospy.loginfo("kill %d after %.1f s: %d nodes acknowledged in this run (%d in all), database holds %d "
                          "(%d sessions)", k + 1, killed_at - run_start, len(ack), len(must_hold), len(ids),
                          summary["session_count"])
            node.start()
            node.wait_ready()

        self.assertGreater(len(must_hold), 0, "no node acknowledged before any kill")
        last_run_start = time.time()
        player.wait(timeout=duration / rate + 60)
        common.wait_quiet(self.infos, quiet=3.0, timeout=30.0)
        last = [i for t, i in self.infos if t >= last_run_start]
        self.assertGreater(len(last), 5, "too few updates after the last restart:\n%s\nplayer: %s" % (
            node.log()[-3000:], open(player_log, errors="replace").read()[-300:]))
        self.check_last_run(last)
        self.assertEqual(node.kill(signal.SIGINT), 0, "the node did not end cleanly:\n" + node.log()[-3000:])

        # Closing saved the last run's nodes too; each start was a session of its own.
        must_hold |= {i.refId for i in last if i.refId > 0}
        summary, ids = self.check_database(db, must_hold, "at the end")
        self.assertEqual(summary["session_count"], kills + 1)
        self.check_poses(db, folder, ids)

    def check_last_run(self, last):
        """The restarted node maps in a new map of its own, and its graph optimises (finite
        poses for its nodes, the latest included)."""
        first_map = fault.stat(self.infos[0][1], "Loop/Map_id")
        self.assertGreater(fault.stat(last[-1], "Loop/Map_id"), first_map)
        self.assertTrue(self.graphs, "no mapGraph")
        graph = self.graphs[-1]
        self.assertIn(last[-1].refId, graph.posesId)
        for p in graph.poses:
            self.assertTrue(all(math.isfinite(v) for v in (p.position.x, p.position.y, p.orientation.w)))
        rospy.loginfo("last run: %d updates, mapGraph of %d nodes and %d links", len(last), len(graph.posesId),
                      len(graph.links))

    def check_poses(self, db, folder, ids):
        poses = os.path.join(folder, "poses.tum")
        code, _, out = fault.tool("rtabmap-export", "--poses", poses, db)
        self.assertEqual(code, 0, out)
        with open(poses) as f:
            rows = [l.split() for l in f if l.strip() and not l.startswith("#")]
        self.assertEqual(len(rows), len(ids), "rtabmap-export --poses: one line per node")
        self.assertTrue(all(len(r) == 8 and all(math.isfinite(float(v)) for v in r) for r in rows))


if __name__ == "__main__":
    rospy.init_node("fault_kill_check")
    rostest.rosrun(fault.PKG, "fault_kill", FaultKillTest, sys.argv)
