"""Synthetic camera messages and small helpers shared by the sync_*.py rostest checks."""
import time

import numpy as np
import rospy
from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import RGBDImage
from sensor_msgs.msg import CameraInfo, Image

W, H = 64, 48
FX, CX, CY = 50.0, 32.0, 24.0


def header(msg, stamp, frame="camera_optical"):
    msg.header.stamp = stamp
    msg.header.frame_id = frame
    return msg


def image(stamp, encoding="bgr8", value=0, w=W, h=H):
    """An image whose every byte (8-bit) or value (16-bit) is `value`: it names its frame."""
    m = header(Image(), stamp)
    m.width, m.height, m.encoding = w, h, encoding
    if encoding == "16UC1":
        m.step = w * 2
        m.data = np.full(w * h, value, dtype=np.uint16).tobytes()
    else:
        channels = {"bgr8": 3, "rgb8": 3, "mono8": 1, "8UC3": 3}[encoding]
        m.step = w * channels
        m.data = np.full(w * h * channels, value % 256, dtype=np.uint8).tobytes()
    return m


def camera_info(stamp, tx=0.0, fx=FX, frame="camera_optical"):
    m = header(CameraInfo(), stamp, frame)
    m.width, m.height = W, H
    m.K = [fx, 0, CX, 0, fx, CY, 0, 0, 1]
    m.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    m.P = [fx, 0, CX, tx, 0, fx, CY, 0, 0, 0, 1, 0]
    return m


def rgbd_image(stamp, value):
    m = header(RGBDImage(), stamp)
    m.rgb = image(stamp, "bgr8", value)
    m.depth = image(stamp, "16UC1", 1000 + value)
    m.rgb_camera_info = camera_info(stamp)
    m.depth_camera_info = m.rgb_camera_info
    return m


def depth_values(msg):
    return np.frombuffer(msg.data, dtype=np.uint16)


def wait_connected(test, publishers, subscribers, timeout=30.0):
    """Waits until the nodes under test subscribe to our publishers and publish to us."""
    end = time.time() + timeout
    while time.time() < end:
        if all(p.get_num_connections() > 0 for p in publishers) and \
           all(s.get_num_connections() > 0 for s in subscribers):
            return
        time.sleep(0.1)
    missing = [p.resolved_name for p in publishers if p.get_num_connections() == 0]
    missing += [s.resolved_name for s in subscribers if s.get_num_connections() == 0]
    test.fail(f"nodes did not come up (nodelet not loaded?); unconnected: {missing}")


def wait_for(predicate, timeout):
    end = time.time() + timeout
    while time.time() < end and not predicate():
        time.sleep(0.05)
    return predicate()


class RosoutLog:
    """Collects the /rosout lines of the nodes under test."""

    def __init__(self):
        self.lines = []
        self.sub = rospy.Subscriber("/rosout", Log, self.lines.append, queue_size=100)

    def find(self, level, *words):
        return [m for m in self.lines if m.level == level and all(w in m.msg for w in words)]
