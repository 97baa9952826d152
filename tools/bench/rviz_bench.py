#!/usr/bin/env python3
"""bench-rviz (`make bench`): `roslaunch rtabmap_ros demo_sim_robot.launch rviz:=true` under Xvfb,
on a simulator bag: rviz comes up with config/rtabmap.rviz, subscribes to the map topics, and
draws the occupancy grid. Two screenshots of the screen (xwd), before and after the replay,
go to OUTPUT/rviz_before.png and OUTPUT/rviz_after.png; the check is that the 3D view (the
pixels rviz paints in its background colour before any map arrives) gained the grid's free
(light grey) and occupied (black) cells. Installs rviz, xvfb and x11-apps (xwd) when missing and run
as root; otherwise skips, saying so."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.realpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tools", "demo"))
import demo_ros as ros  # noqa: E402
import xwd  # noqa: E402

PACKAGES = {"rviz": "rviz", "Xvfb": "xvfb", "xwd": "x11-apps"}
BACKGROUND = (48, 48, 48)  # rviz's default background colour (config/rtabmap.rviz keeps it)
MAP_TOPICS = ("/rtabmap/grid_map", "/rtabmap/graph_markers", "/scan", "/tf")


def ensure_tools():
    """None when rviz, Xvfb and xwd are there (installing them if we can), else why not."""
    missing = [pkg for exe, pkg in PACKAGES.items() if shutil.which(exe) is None]
    if not missing:
        return None
    if os.geteuid() != 0:
        return "missing %s (apt-get install %s as root)" % (", ".join(missing), " ".join(missing))
    r = subprocess.run(["apt-get", "install", "-y", "--no-install-recommends"] + missing, capture_output=True,
                       text=True)
    if r.returncode != 0:
        return "apt-get install %s failed: %s" % (" ".join(missing), r.stderr[-500:])
    return None


class Xvfb:
    def __init__(self, log_path):
        for n in range(90, 200):
            if not os.path.exists("/tmp/.X%d-lock" % n):
                self.display = ":%d" % n
                break
        self.log = open(log_path, "w")
        self.process = subprocess.Popen(["Xvfb", self.display, "-screen", "0", "1920x1080x24", "-nolisten", "tcp"],
                                        stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)
        os.environ["DISPLAY"] = self.display
        ros.wait_for(lambda: os.path.exists("/tmp/.X11-unix/X" + self.display[1:]), 20.0, "Xvfb did not start")

    def screenshot(self, png):
        """The whole screen as an RGB array, also written to png."""
        dump = png[:-4] + ".xwd"
        subprocess.run(["xwd", "-root", "-silent", "-display", self.display, "-out", dump], check=True, timeout=30)
        image = xwd.read_xwd(dump)
        os.remove(dump)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        plt.imsave(png, image)
        return image

    def stop(self):
        ros.stop_process(self.process, 10.0)
        self.log.close()


def subscribers(node_name):
    """Topics node_name subscribes to, from the master."""
    import rosgraph
    _, subs, _ = rosgraph.Master("/rviz_bench").getSystemState()
    return {topic for topic, nodes in subs if any(n.endswith(node_name) for n in nodes)}


def view_mask(image):
    """The pixels of rviz's background colour: the 3D view before anything is drawn in it."""
    import numpy as np
    mask = np.all(image == np.array(BACKGROUND, np.uint8), axis=2)
    return mask if mask.sum() >= 10000 else None


def map_pixels(image, mask):
    """Inside the 3D view: pixels of free cells (rviz's map colour scheme draws them light grey,
    about 214) and of occupied cells (near black)."""
    import numpy as np
    view = image[mask].astype(int)
    return int(np.all(view >= 190, axis=1).sum()), int(np.all(view <= 25, axis=1).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default=os.path.join(ROOT, "build", "bench_output", "rviz"))
    parser.add_argument("--duration", type=float, default=60.0, help="robot seconds of the sim bag")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    why = ensure_tools()
    if why:
        print("rviz: skipped (%s)" % why)
        print(json.dumps({"rviz_bench": {"skipped": why}}))
        return 0
    log = os.path.join(args.output, "run.log")
    open(log, "w").close()
    screen = Xvfb(os.path.join(args.output, "xvfb.log"))
    master = ros.Master(os.path.join(args.output, "roscore.log"))
    launch = None
    result = {}
    try:
        bag = os.path.join(args.output, "sim_loop.bag")
        if not os.path.exists(bag):
            ros.run_tool(["rtabmap-sim", "--json", "--scenario", "loop", "--rate", "2", "--width", "160", "--height",
                          "120", "--no-stereo", "--no-urg", "--duration", str(args.duration), "--output",
                          os.path.join(args.output, "sim"), "--bag", bag], log, timeout=600)
        launch = ros.Launch("demo_sim_robot.launch", {"rviz": "true", "delete_db": "true",
                                                      "database_path": os.path.join(args.output, "rviz.db")}, log)
        started = time.time()
        ros.wait_for(lambda: set(MAP_TOPICS) <= subscribers("rviz"), 120.0,
                     "rviz did not subscribe to %s (see %s)" % (", ".join(MAP_TOPICS), log))
        result["rviz_up_s"] = round(time.time() - started, 1)
        time.sleep(5.0)  # the first frames rendered
        before = screen.screenshot(os.path.join(args.output, "rviz_before.png"))
        mask = view_mask(before)
        if mask is None:
            raise RuntimeError("no 3D view in the screenshot (rviz background colour not found)")
        ros.play(bag, 2.0, log, timeout=600)
        time.sleep(8.0)  # the last grid drawn
        after = screen.screenshot(os.path.join(args.output, "rviz_after.png"))
        light0, dark0 = map_pixels(before, mask)
        light1, dark1 = map_pixels(after, mask)
        result.update({"view_pixels": int(mask.sum()), "free_pixels": [light0, light1],
                       "occupied_pixels": [dark0, dark1], "rviz_alive": launch.alive(),
                       "subscribed": sorted(subscribers("rviz"))})
        passed = result["rviz_alive"] and light1 - light0 > 2000 and dark1 - dark0 > 200
        result["passed"] = bool(passed)
        print("rviz: up and subscribed in %.1f s; 3D view %d px; grid pixels free %d -> %d, occupied %d -> %d: %s"
              % (result["rviz_up_s"], result["view_pixels"], light0, light1, dark0, dark1,
                 "PASS" if passed else "FAIL"))
        print("rviz: screenshots in %s (rviz_before.png, rviz_after.png)" % args.output)
    finally:
        if launch:
            launch.stop()
        master.stop()
        screen.stop()
    print(json.dumps({"rviz_bench": result}))
    return 0 if result.get("passed") else 1


if __name__ == "__main__":
    sys.exit(main())
