#!/usr/bin/env python3
"""rostest check (fault_disk_full.test): the rtabmap node's database on a disk that fills up
during a simulator bag's replay, then gets room again. The node must report the failure, go on
mapping (info) and publishing map -> odom, not crash, write again once there is room (the
core's writer retries every 5 s; the locations it refused meanwhile stay in RAM and are saved
at the end), end cleanly, and leave a database that opens, passes its consistency check and
holds every node acknowledged before the failure, and at the end every node it mapped.

The small disk is a tmpfs mounted in the test's folder when this process may mount (root),
grown by a remount; otherwise the node's file size is limited with RLIMIT_FSIZE (`ulimit -f`,
SIGXFSZ ignored so that writes past it fail with EFBIG instead of killing the node, which
SQLite reports as an I/O error rather than a full disk), lifted with prlimit."""

import os
import signal
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage

from rtabmap_ros.msg import Info

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402
import odom_common as common  # noqa: E402  (temporary folders, waiting)

STM_SIZE = 10  # Mem/STMSize (the default)
ACK_DELAY = 1.0
DISK_KB = 2048
FAILURE = "the long-term memory writer stopped after an error"
WRITING_AGAIN = "long-term memory: writing to"
ROOM_AFTER = 4.0  # seconds after the failure


def small_disk(test, folder):
    """(database folder, node shell prefix, description, command giving room again; the node's
    pid is appended to it)."""
    disk = os.path.join(folder, "disk")
    os.mkdir(disk)
    # RTABMAP_FAULT_NO_TMPFS=1 takes the RLIMIT_FSIZE way even as root.
    mount = ["true", "RTABMAP_FAULT_NO_TMPFS is set"] if os.environ.get("RTABMAP_FAULT_NO_TMPFS") else \
        ["mount", "-t", "tmpfs", "-o", "size=%dk" % DISK_KB, "tmpfs", disk]
    r = subprocess.run(mount, capture_output=True, text=True)
    if mount[0] == "true":
        r.returncode, r.stderr = 1, mount[1]
    if r.returncode == 0:
        test.addCleanup(subprocess.run, ["umount", "-l", disk], capture_output=True)
        grow = ["bash", "-c", 'mount -o remount,size=64m "$0"', disk]
        return disk, "", "tmpfs of %d KiB" % DISK_KB, grow
    rospy.logwarn("cannot mount a tmpfs (%s); limiting the node's file size instead", r.stderr.strip())
    grow = ["bash", "-c", 'prlimit --fsize=unlimited: --pid "$0"']  # the soft limit only
    return disk, "trap '' XFSZ; ulimit -S -f %d" % DISK_KB, "RLIMIT_FSIZE of %d KiB" % DISK_KB, grow


class FaultDiskFullTest(unittest.TestCase):
    def setUp(self):
        self.infos, self.map_to_odom = [], []
        rospy.Subscriber("/info", Info, lambda m: self.infos.append((time.time(), m)))
        rospy.Subscriber("/tf", TFMessage, self.on_tf)

    def on_tf(self, msg):
        if any(t.header.frame_id == "map" and t.child_frame_id == "odom" for t in msg.transforms):
            self.map_to_odom.append(time.time())

    def test_disk_fills_up(self):
        duration, rate = rospy.get_param("~duration", 120), rospy.get_param("~rate", 4)
        folder = common.workdir(self, "fault_disk_full_")
        bag = fault.make_sim_bag(self, folder, duration)
        disk, prefix, how, grow = small_disk(self, folder)
        db = os.path.join(disk, "rtabmap.db")
        node = fault.SlamNode(folder, db, shell_prefix=prefix)
        self.addCleanup(node.kill)
        node.start()
        node.wait_ready()
        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", str(rate), bag],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.addCleanup(lambda: player.poll() is None and player.kill())
        failed_at = grown_at = None
        while player.poll() is None:
            time.sleep(0.1)
            if failed_at is None and FAILURE in node.log():
                failed_at = time.time()
                stored_at_failure = len(fault.database_node_ids(db))
            if failed_at and not grown_at and time.time() > failed_at + ROOM_AFTER:
                subprocess.run(grow + [str(node.process.pid)], check=True, timeout=10)
                grown_at = time.time()
        self.assertIsNotNone(grown_at, "the bag ended before the disk got room again")
        common.wait_quiet(self.infos, quiet=2.0, timeout=20.0)
        log = node.log()
        self.assertIsNotNone(failed_at, "the disk (%s) never filled up, or the failure was not reported:\n%s"
                             % (how, log[-3000:]))
        self.assertTrue(node.alive(), "the node died when the disk filled up:\n" + log[-3000:])
        reported = next(l for l in log.splitlines() if FAILURE in l)
        rospy.loginfo("%s full: %s", how, reported.strip()[:400])
        self.assertTrue("disk is full" in reported or "I/O error" in reported, reported)

        # Mapping and map -> odom go on after the failure.
        after = [i for t, i in self.infos if t > failed_at + ACK_DELAY]
        tf_after = [t for t in self.map_to_odom if t > failed_at + ACK_DELAY]
        rospy.loginfo("after the failure: %d updates, %d map -> odom", len(after), len(tf_after))
        self.assertGreater(len(after), 10, "no mapping after the disk filled up")
        self.assertGreater(len(tf_after), 20, "map -> odom stopped with the disk full")
        self.assertTrue(any(i.refId > 0 for i in after))

        # Room again: the writer wrote again before the end.
        self.assertIn(WRITING_AGAIN, node.log())
        stored_before_end = len(fault.database_node_ids(db))
        rospy.loginfo("database: %d nodes when the disk filled up, %d before the end", stored_at_failure,
                      stored_before_end)
        self.assertGreater(stored_before_end, stored_at_failure, "nothing written once there was room")
        self.assertEqual(node.kill(signal.SIGINT), 0, "unclean end:\n" + node.log()[-3000:])
        ids = sorted({i.refId for t, i in self.infos if t <= failed_at - ACK_DELAY and i.refId > 0})
        acknowledged = set(ids[:-STM_SIZE])
        self.assertGreater(len(acknowledged), 0, "no node acknowledged before the failure")
        code, summary, out = fault.tool("rtabmap-info", "--check", db)
        self.assertEqual(code, 0, out)
        self.assertTrue(summary["consistency"]["ok"], out)
        stored = fault.database_node_ids(db)
        rospy.loginfo("database: %d nodes (%d acknowledged before the failure), %d bytes", len(stored),
                      len(acknowledged), os.path.getsize(db))
        self.assertFalse(sorted(acknowledged - stored), "acknowledged nodes lost")
        # Closing saved what RAM kept: every node mapped is in the database.
        mapped = {i.refId for t, i in self.infos if i.refId > 0}
        self.assertFalse(sorted(mapped - stored), "mapped nodes missing at the end")


if __name__ == "__main__":
    rospy.init_node("fault_disk_full_check")
    rostest.rosrun(fault.PKG, "fault_disk_full", FaultDiskFullTest, sys.argv)
