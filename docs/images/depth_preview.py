"""A KITTI depth PNG (uint16, metres x 256, 0 = none) as a picture: near warm, far cool,
nothing black.   depth_preview.py IN.png OUT.png"""
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "integration"))
from kitti_read import read_png  # noqa: E402

width, height, _, rows = read_png(sys.argv[1])
stops = [(0.0, (255, 240, 120)), (0.15, (250, 140, 40)), (0.35, (200, 40, 90)),
         (0.65, (90, 30, 160)), (1.0, (20, 30, 90))]


def colour(metres):
    t = min(1.0, (metres / 100.0) ** 0.7)  # 0..100 m, more steps near the train
    for (t0, c0), (t1, c1) in zip(stops, stops[1:]):
        if t <= t1:
            w = (t - t0) / (t1 - t0)
            return bytes(round(a + w * (b - a)) for a, b in zip(c0, c1))
    return bytes(stops[-1][1])


raw = bytearray()
for row in rows:
    raw.append(0)
    for d in row:
        raw += colour(d / 256.0) if d else b"\0\0\0"


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


with open(sys.argv[2], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))
