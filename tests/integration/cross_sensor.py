"""Cross-sensor check of a dataset with a LiDAR and a camera: every LiDAR point of a frame,
projected through calib.txt (Tr into camera 0's frame, then P2), that lands inside image_2 is
compared with the class of the semantic_2 pixel it lands on.

    cross_sensor.py SEQUENCE_DIR [FRAMES]   (FRAMES: every so many frames, default 15)

Prints the share of matching points and exits 1 below 95 %."""
import os
import sys

from kitti_read import apply, read_calib, read_labels, read_png, read_velodyne

seq = sys.argv[1]
step = int(sys.argv[2]) if len(sys.argv) > 2 else 15
calib = read_calib(os.path.join(seq, "calib.txt"))
P2, Tr = calib["P2"], calib["Tr"]
frames = sorted(f[:-4] for f in os.listdir(os.path.join(seq, "velodyne")))[::step]
inside = same = 0
by_class = {}
for frame in frames:
    width, height, _, semantic = read_png(os.path.join(seq, "semantic_2", frame + ".png"))
    points = read_velodyne(os.path.join(seq, "velodyne", frame + ".bin"))
    labels = read_labels(os.path.join(seq, "labels", frame + ".label"))
    assert len(points) == len(labels), frame
    for p, label in zip(points, labels):
        c = apply(Tr, p)
        if c[2] <= 0.5:  # behind the camera or nearer than its near plane
            continue
        x = apply(P2, c)
        u, v = round(x[0] / x[2]), round(x[1] / x[2])
        if not (0 <= u < width and 0 <= v < height):
            continue
        inside += 1
        cls = label & 0xFFFF
        hit = semantic[v][u] == cls
        same += hit
        n = by_class.setdefault(cls, [0, 0])
        n[0] += 1
        n[1] += hit
share = same / max(inside, 1)
print(f"{len(frames)} frames, {inside} LiDAR points in image_2, {100 * share:.2f} % on their "
      f"own class")
for cls, (n, hit) in sorted(by_class.items()):
    print(f"  class {cls}: {n} points, {100 * hit / n:.1f} %")
sys.exit(0 if inside > 1000 and share >= 0.95 else 1)
