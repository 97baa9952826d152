#!/usr/bin/env python3
"""rostest check (service_paths.test): load_database is confined to database_directory.
Refused requests (with clear = true, which would delete the file) leave the file outside
byte-identical, create nothing outside, keep the node on its database and say why in the log;
a database inside the directory, relative or absolute, is accepted."""
import os
import signal
import sys
import unittest

import rospy
import rostest

from rtabmap_ros.srv import ListLabels, LoadDatabase

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402
import odom_common as common  # noqa: E402


def listing(folder):
    return sorted(os.listdir(folder))


class ServicePathsTest(unittest.TestCase):
    def load(self, path, clear=True):
        """True when the node accepted the request."""
        try:
            rospy.ServiceProxy("/load_database", LoadDatabase)(database_path=path, clear=clear)
            return True
        except rospy.ServiceException:
            return False

    def test_load_database_is_confined(self):
        folder = common.workdir(self, "service_paths_")
        maps, outside = os.path.join(folder, "maps"), os.path.join(folder, "outside")
        os.mkdir(maps)
        os.mkdir(outside)
        precious = os.path.join(outside, "precious.db")
        with open(precious, "wb") as f:
            f.write(b"someone else's file" * 100)
        os.symlink(precious, os.path.join(maps, "link.db"))
        os.symlink(os.path.join(outside, "new.db"), os.path.join(maps, "dangling.db"))
        os.symlink(outside, os.path.join(maps, "outdir"))
        before = fault.sha256(precious)

        node = fault.SlamNode(folder, os.path.join(maps, "rtabmap.db"))
        self.addCleanup(node.kill)
        node.start()
        node.wait_ready()
        refused = {
            "../outside/precious.db": "..",
            precious: "outside",
            "link.db": "outside",
            "outdir/precious.db": "outside",
            "dangling.db": "symbolic link",
            os.path.join(outside, "fresh.db"): "outside",
            "": "empty",
        }
        for path in refused:
            with self.subTest(path=path):
                self.assertFalse(self.load(path), "load_database accepted %r" % path)
        rospy.ServiceProxy("/list_labels", ListLabels)()  # still serving, on its database
        self.assertEqual(fault.sha256(precious), before, "the file outside was modified")
        self.assertEqual(listing(outside), ["precious.db"], "a file was created outside")

        # Inside the directory: relative and absolute paths are accepted.
        self.assertTrue(self.load("other.db", clear=False))
        self.assertTrue(self.load(os.path.join(maps, "rtabmap.db"), clear=False))
        self.assertIn("other.db", listing(maps))
        self.assertTrue(node.alive())
        self.assertEqual(node.kill(signal.SIGINT), 0, node.log()[-3000:])

        log = node.log()
        for path, reason in refused.items():
            lines = [l for l in log.splitlines()
                     if "load_database refused" in l and ('"%s"' % path in l or (not path and reason in l))]
            self.assertTrue(lines, "no refusal naming %r in the log:\n%s" % (path, log[-4000:]))
            self.assertIn(reason, lines[0])
        self.assertEqual(fault.sha256(precious), before)
        self.assertEqual(listing(outside), ["precious.db"])


if __name__ == "__main__":
    rospy.init_node("service_paths_check")
    rostest.rosrun(fault.PKG, "service_paths", ServicePathsTest, sys.argv)
