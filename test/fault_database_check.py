#!/usr/bin/env python3
"""rostest check (fault_database.test): the rtabmap node given a damaged database as
database_path (written by a newer version, truncated, corrupt, with a table deleted, random
bytes) refuses it with an error naming the file and the reason, does not crash (its services
still answer, it publishes no map while data flows, it ends cleanly on SIGINT), and leaves the
file byte-identical, with no journal file beside it."""
import os
import random
import shutil
import signal
import sqlite3
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import OccupancyGrid

from rtabmap_ros.msg import Info, MapGraph
from rtabmap_ros.srv import ListLabels

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402
import odom_common as common  # noqa: E402  (temporary folders, bag playing, waiting)


def edit(path, sql):
    with sqlite3.connect(path) as c:
        c.executescript(sql)
    c.close()


def variants(good, folder):
    """name -> (path, the words the refusal must contain); each in a folder of its own so that
    anything the node leaves beside the file is seen."""
    data = open(good, "rb").read()
    out = {}

    def place(name, content=None):
        d = os.path.join(folder, name)
        os.mkdir(d)
        path = os.path.join(d, "rtabmap.db")
        if content is None:
            shutil.copy(good, path)
        else:
            with open(path, "wb") as f:
                f.write(content)
        return path

    p = place("newer")
    edit(p, "PRAGMA user_version = 99; UPDATE Admin SET schema_version = 99, written_by = '99.0.0';")
    out["newer"] = (p, ["newer rtabmap_ros (99.0.0)"])
    out["truncated"] = (place("truncated", data[:len(data) // 2]), ["truncated"])
    rng = random.Random(4)
    # The 100-byte SQLite header kept, every page after it garbage (schema included).
    out["corrupt"] = (place("corrupt", data[:100] + bytes(rng.randrange(256) for _ in range(len(data) - 100))),
                      ["corrupt"])
    p = place("deleted_table")
    edit(p, "DROP TABLE Link;")
    out["deleted_table"] = (p, ["Link"])
    out["random"] = (place("random", bytes(rng.randrange(256) for _ in range(16384))), ["not an SQLite database"])
    return out


class FaultDatabaseTest(unittest.TestCase):
    def setUp(self):
        self.infos, self.graphs, self.grids = [], [], []
        rospy.Subscriber("/info", Info, self.infos.append)
        rospy.Subscriber("/mapGraph", MapGraph, self.graphs.append)
        rospy.Subscriber("/grid_map", OccupancyGrid, self.grids.append)

    def test_damaged_databases_are_refused_untouched(self):
        folder = common.workdir(self, "fault_database_")
        bag = fault.make_sim_bag(self, folder, 40)
        good = os.path.join(folder, "good.db")
        node = fault.SlamNode(folder, good)
        node.start()
        node.wait_ready()
        common.play(self, bag, 4, timeout=60)
        common.wait_quiet(self.infos, quiet=2.0, timeout=20.0)
        self.assertEqual(node.kill(signal.SIGINT), 0, node.log()[-3000:])
        nodes = fault.database_node_ids(good)
        self.assertGreater(len(nodes), 5, "the reference database holds too few nodes")
        rospy.loginfo("reference database: %d nodes, %d bytes", len(nodes), os.path.getsize(good))

        for name, (path, words) in variants(good, folder).items():
            with self.subTest(database=name):
                self.check_refused(folder, bag, name, path, words)

    def check_refused(self, folder, bag, name, path, words):
        before, listing = fault.sha256(path), sorted(os.listdir(os.path.dirname(path)))
        node = fault.SlamNode(folder, path)
        self.addCleanup(node.kill)
        del self.infos[:], self.graphs[:], self.grids[:]
        node.start()
        node.wait_ready()
        # The services answer (an error: there is no map), they do not hang or kill the node.
        started = time.time()
        try:
            rospy.ServiceProxy("/list_labels", ListLabels)()
        except rospy.ServiceException:
            pass
        self.assertLess(time.time() - started, 5.0)
        common.play(self, bag, 8, timeout=60)
        time.sleep(1.0)
        self.assertTrue(node.alive(), "%s: the node died:\n%s" % (name, node.log()[-3000:]))
        self.assertFalse(self.infos or self.graphs or self.grids, "%s: a map was published" % name)
        self.assertEqual(node.kill(signal.SIGINT), 0, "%s: unclean end:\n%s" % (name, node.log()[-3000:]))
        log = node.log()
        refusal = [l for l in log.splitlines() if "cannot start SLAM" in l]
        self.assertTrue(refusal, "%s: no refusal in the log:\n%s" % (name, log[-3000:]))
        rospy.loginfo("%s: %s", name, refusal[0].strip())
        self.assertIn(path, refusal[0])
        for w in words:
            self.assertIn(w, refusal[0], "%s: the refusal does not say \"%s\"" % (name, w))
        self.assertEqual(fault.sha256(path), before, "%s: the file was modified" % name)
        self.assertEqual(sorted(os.listdir(os.path.dirname(path))), listing, "%s: files left beside it" % name)


if __name__ == "__main__":
    rospy.init_node("fault_database_check")
    rostest.rosrun(fault.PKG, "fault_database", FaultDatabaseTest, sys.argv)
