"""Reads an X Window Dump (what `xwd` writes) of a 24/32-bit TrueColor screen into an RGB array:
the screenshot of the rviz bench (Xvfb has no other way out without extra packages)."""
import struct

import numpy as np

_FIELDS = ("header_size", "file_version", "pixmap_format", "pixmap_depth", "width", "height", "xoffset",
           "byte_order", "bitmap_unit", "bitmap_bit_order", "bitmap_pad", "bits_per_pixel", "bytes_per_line",
           "visual_class", "red_mask", "green_mask", "blue_mask", "bits_per_rgb", "colormap_entries", "ncolors")


def read_xwd(path):
    """H x W x 3 uint8 array; raises ValueError for a dump this reader does not handle."""
    with open(path, "rb") as f:
        data = f.read()
    h = dict(zip(_FIELDS, struct.unpack(">20I", data[:80])))
    # Xvfb's depth-24 screens store 4 bytes per pixel whatever bits_per_pixel says (24 or 32).
    if h["file_version"] != 7 or h["pixmap_format"] != 2 or h["pixmap_depth"] != 24 or \
            h["bytes_per_line"] < 4 * h["width"]:
        raise ValueError("%s: only version 7 ZPixmap dumps of depth 24, 4 bytes per pixel, are read (got %s)"
                         % (path, h))
    start = h["header_size"] + 12 * h["ncolors"]
    rows = np.frombuffer(data, np.uint8, h["height"] * h["bytes_per_line"], start)
    pixels = rows.reshape(h["height"], h["bytes_per_line"])[:, :4 * h["width"]].reshape(h["height"], h["width"], 4)
    if h["byte_order"] == 1:  # MSBFirst: X R G B
        pixels = pixels[:, :, ::-1]
    channel = {0xFF0000: 2, 0xFF00: 1, 0xFF: 0}  # byte of each mask in a little-endian pixel
    order = [channel[h["red_mask"]], channel[h["green_mask"]], channel[h["blue_mask"]]]
    return np.ascontiguousarray(pixels[:, :, order])
