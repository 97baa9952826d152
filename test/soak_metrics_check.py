#!/usr/bin/env python3
"""Unit test of the figures of `make soak` (tools/soak/soak_metrics.py) on made-up runs whose
answers are known: RSS growth, update-time windows, revisits and their closures, sync drops
against frames skipped by design, nodes lost, and the process sampling on this very process.
Run by soak_metrics.test (rostest: nothing of ROS is used but its test runner)."""
import math
import os
import sys
import unittest

import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "soak"))
import soak_metrics as m  # noqa: E402

PKG = "rtabmap_ros"


def update(stamp, node, loop=0, proximity=0, **stats):
    return {"stamp": float(stamp), "node": node, "loop": loop, "proximity": proximity,
            "stats": {k.replace("__", "/") + ("/" if not k.endswith("ms") else ""): v for k, v in stats.items()}}


class SoakMetricsTest(unittest.TestCase):

    def test_rss_growth_uses_window_medians_after_the_reference(self):
        # 100 MB flat before the reference (ignored even though it is lower), then 200 MB with
        # one 400 MB spike (a median ignores it), then 215 MB in the last window: +7.5%.
        samples = [{"robot_s": t, "rss": {"rtabmap": 100.0}} for t in range(0, 1200, 60)]
        samples += [{"robot_s": t, "rss": {"rtabmap": 200.0}} for t in range(1200, 2400, 60)]
        samples[25]["rss"]["rtabmap"] = 400.0
        samples += [{"robot_s": t, "rss": {"rtabmap": 215.0}} for t in range(2400, 2700, 60)]
        g = m.rss_growth(samples, 1200.0, window_s=300.0)["rtabmap"]
        self.assertAlmostEqual(g["baseline_mb"], 200.0)
        self.assertAlmostEqual(g["max_window_mb"], 215.0)
        self.assertAlmostEqual(g["growth"], 0.075)
        # The run's last two samples (a partial window) at 260 MB: they join the last full
        # window, whose median they do not move; alone they would make a +30% "window".
        tail = samples + [{"robot_s": t, "rss": {"rtabmap": 260.0}} for t in (2700, 2760)]
        g_tail = m.rss_growth(tail, 1200.0, window_s=300.0)["rtabmap"]
        self.assertAlmostEqual(g_tail["max_window_mb"], 215.0)
        self.assertEqual(g_tail["windows"], 5)
        self.assertAlmostEqual(g_tail["final_mb"], 260.0)
        linear = [{"robot_s": t, "rss": {"rtabmap": 100.0 + 10.0 * t / 3600.0}} for t in range(0, 7200, 60)]
        self.assertAlmostEqual(m.rss_growth(linear, 0.0)["rtabmap"]["slope_mb_per_h"], 10.0)
        checks = dict((n, ok) for n, ok, _ in m.goal_checks({"rss_growth": {"rtabmap": g}}))
        self.assertTrue(checks["RSS growth < 10% after the reference time"])
        g["growth"] = 0.12
        checks = dict((n, ok) for n, ok, _ in m.goal_checks({"rss_growth": {"rtabmap": g}}))
        self.assertFalse(checks["RSS growth < 10% after the reference time"])

    def test_update_time_windows_and_wm_full(self):
        updates = [update(1000 + t, t + 1, Timing__Total__ms=float(t % 10), Memory__Working_memory_size=min(t, 50))
                   for t in range(200)]
        w = m.windowed_update_times(updates, 100.0)
        self.assertEqual([r["updates"] for r in w], [100, 100])
        self.assertAlmostEqual(w[0]["p50"], 4.5)
        self.assertEqual(w[1]["max"], 9.0)
        self.assertEqual(m.wm_full_time(updates, 50), 50.0)
        self.assertIsNone(m.wm_full_time(updates, 51))

    def test_stage_times_compare_the_first_and_last_spans(self):
        updates = [update(t, t + 1, Timing__Total__ms=99.0, Timing__Map_assembling__ms=float(t),
                          Timing__Reactivation__ms=5.0) for t in range(100)]
        rows = m.stage_times(updates, 10.0)
        self.assertEqual([r[0] for r in rows], ["Map_assembling", "Reactivation"])  # the total is no stage
        self.assertAlmostEqual(rows[0][1], 4.5)   # t = 0..9
        self.assertAlmostEqual(rows[0][2], 94.5)  # t = 90..99
        self.assertEqual(rows[1][1:], (5.0, 5.0))

    def test_revisits_count_only_links_to_old_nodes(self):
        # Out along x for 100 s (1 m/s), back along the same line: from t=101 the robot is
        # within 1 m of a place left more than 60 s before... only once the place is old enough:
        # at t=100+k it is at x=100-k, visited at t=100-k, i.e. 2k s before: revisit when 2k > 60.
        truth, updates = {}, []
        for t in range(201):
            x = t if t <= 100 else 200 - t
            truth[float(t)] = (float(x), 0.0)
            updates.append(update(t, t + 1))
        r = m.revisits(updates, truth, radius=0.5, min_age=60.0, grace_s=5.0)
        self.assertEqual(r["episodes"], 1)
        self.assertEqual(r["updates_at_revisit"], 200 - 131 + 1)
        self.assertEqual(r["closed"], 0)
        # A link to a recent node (10 s old) does not close it; one to an old node does.
        updates[150]["proximity"] = updates[140]["node"]
        self.assertEqual(m.revisits(updates, truth, 0.5, 60.0, 5.0)["closed"], 0)
        updates[160]["loop"] = updates[40]["node"]
        self.assertEqual(m.revisits(updates, truth, 0.5, 60.0, 5.0)["closed"], 1)

    def test_sync_drops_tell_still_frames_from_dropped_ones(self):
        # 10 frames: moving 0.5 m per frame except frames 4-6 (still). Updates for all but 4, 5
        # (still: skipped by design) and 8 (moved: a drop). Frame 6 still but published (a
        # rehearsal, flagged Small_movement).
        odom, x = {}, 0.0
        for k in range(10):
            if k not in (4, 5, 6):
                x += 0.5
            odom[float(k)] = (x, 0.0, 0.0)
        updates = [update(k, k + 1, Memory__Small_movement=1.0 if k == 6 else 0.0) for k in range(10) if k not in (4, 5, 8)]
        s = m.sync_drops([float(k) for k in range(10)], updates, odom, 0.1, 0.1)
        self.assertEqual((s["frames"], s["updates"], s["skipped_still"], s["dropped"]), (10, 7, 2, 1))
        self.assertEqual(s["dropped_stamps"], [8.0])
        self.assertAlmostEqual(s["drop_fraction"], 1.0 / 8.0)
        # A turn in place is motion: with the robot turning 0.2 rad per frame, nothing is still.
        turning = {float(k): (0.0, 0.0, 0.2 * k) for k in range(10)}
        s = m.sync_drops([float(k) for k in range(10)], updates, turning, 0.1, 0.1)
        self.assertEqual((s["skipped_still"], s["dropped"]), (0, 3))

    def test_nodes_lost(self):
        infos = [{"node": 1, "durable": 0}, {"node": 2, "durable": 1}, {"node": 3, "durable": 2},
                 {"node": 4, "durable": 2}]
        ack, durable = m.acknowledged_nodes(infos)
        self.assertEqual((ack, durable), ({1, 2}, 2))
        self.assertEqual(m.lost_nodes(ack, {1, 2, 3}), [])
        self.assertEqual(m.lost_nodes(ack, {1, 3, 4}), [2])

    def test_yaw(self):
        self.assertAlmostEqual(m.yaw_of((0.0, 0.0, math.sin(0.3), math.cos(0.3))), 0.6)

    def test_resident_kinds_compare_the_window_after_the_reference_with_the_last(self):
        samples = [{"robot_s": t, "rss_kinds": {"rtabmap": {"anon": 100.0 + t / 60.0, "file": 50.0, "shmem": 0.0}}}
                   for t in range(0, 3600, 60)]
        samples.append({"robot_s": None, "rss_kinds": {"rtabmap": {"anon": 1e6, "file": 1e6, "shmem": 1e6}}})
        rows = dict((k, (a, b)) for k, a, b in m.resident_kinds(samples, 1200.0, window_s=300.0)["rtabmap"])
        self.assertAlmostEqual(rows["anon"][0], 122.0)  # t = 1200..1440: 120..124
        self.assertAlmostEqual(rows["anon"][1], 157.0)  # t = 3300..3540: 155..159 (within 300 s of the last)
        self.assertEqual(rows["file"], (50.0, 50.0))
        self.assertEqual(m.resident_kinds(samples, 4000.0), {})  # nothing after the reference

    def test_sampling_reads_this_process(self):
        rss = m.rss_mb(os.getpid())
        self.assertGreater(rss, 1.0)
        kinds = m.resident_kinds_mb(os.getpid())
        self.assertGreater(kinds["anon"], 0.5)
        self.assertGreater(kinds["file"], 0.5)
        # VmRSS is the sum of the three; two reads of /proc apart, the process may touch a few pages.
        self.assertAlmostEqual(kinds["anon"] + kinds["file"] + kinds["shmem"], rss, delta=2.0)
        self.assertIsNone(m.resident_kinds_mb(2 ** 22 + 1))
        self.assertIn(os.getpid(), m.children(os.getppid()))
        self.assertIsNone(m.rss_mb(2 ** 22 + 1))  # above the largest pid


if __name__ == "__main__":
    rostest.rosrun(PKG, "soak_metrics", SoakMetricsTest)
