#!/usr/bin/env python3
"""bench-faults (`make bench`): the SIGKILL fault injection (test/fault_kill.test) with 5 kills
instead of make test's 3, and other seeds; prints what each run acknowledged and what the
database held, then one JSON summary line."""
import argparse
import json
import os
import re
import subprocess
import sys
import time

KILL = re.compile(r"kill (\d+) after ([\d.]+) s: (\d+) nodes acknowledged in this run \((\d+) in all\), "
                  r"database holds (\d+) \((\d+) sessions\)")
LAST = re.compile(r"last run: (\d+) updates, mapGraph of (\d+) nodes and (\d+) links")


def run(kills, seed):
    env = dict(os.environ, RTABMAP_FAULT_KILLS=str(kills), RTABMAP_FAULT_SEED=str(seed))
    started = time.time()
    r = subprocess.run(["rostest", "--text", "rtabmap_ros", "fault_kill.test"], env=env, capture_output=True,
                       text=True, timeout=900)
    out = r.stdout + r.stderr
    passed = r.returncode == 0 and "RESULT: SUCCESS" in out
    kills_seen = [tuple(float(x) for x in m.groups()) for m in KILL.finditer(out)]
    last = LAST.search(out)
    print("seed %d: %s in %.0f s" % (seed, "PASS" if passed else "FAIL", time.time() - started))
    for k, after, ack, ack_all, held, sessions in kills_seen:
        print("  kill %d after %.1f s: %d acknowledged (%d in all), database %d nodes, %d sessions"
              % (k, after, ack, ack_all, held, sessions))
    if last:
        print("  last run: %s updates, mapGraph %s nodes, %s links" % last.groups())
    if not passed:
        print(out[-4000:])
    return {"seed": seed, "passed": passed, "kills": len(kills_seen),
            "acknowledged": int(kills_seen[-1][3]) if kills_seen else 0,
            "database_nodes_at_last_kill": int(kills_seen[-1][4]) if kills_seen else 0,
            "final_graph_nodes": int(last.group(2)) if last else 0}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--kills", type=int, default=5)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    results = [run(args.kills, s) for s in args.seeds]
    print(json.dumps({"bench": "faults", "kills_per_run": args.kills, "runs": results,
                      "passed": all(r["passed"] for r in results)}))
    return 0 if all(r["passed"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
