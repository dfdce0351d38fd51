# `trainsim generate` on the built-in default scenario writes a complete, deterministic dataset.
# Arguments: TRAINSIM SYNTHETIC_RUN SOURCE_DIR [DATASET_DIR]: CTest passes the default dataset
# its default_dataset fixture generated (and its stderr, DATASET_DIR.err); without one the script
# generates it.
source "$(dirname "$0")/lib.sh" "$@"

if [ -n "${4:-}" ]; then
  ln -s "$4" "$WORK/a"
  cp "$4.err" "$WORK/err"
else
  expect_exit 0 "generate default" -- "$TRAINSIM" generate --out "$WORK/a" --progress none
fi
for f in manifest.json scenario.json; do
  [ -s "$WORK/a/$f" ] && pass "$f written" || fail "$f missing"
done
[ ! -e "$WORK/a/.trainsim" ] && pass "no checkpoint left in a complete dataset" || fail ".trainsim left"
cmp -s "$WORK/a/scenario.json" <("$TRAINSIM" defaults) && pass "scenario.json is the resolved default" ||
  fail "scenario.json differs from trainsim defaults"
python3 - "$WORK/a/manifest.json" <<'PY' && pass "manifest fields" || fail "manifest fields"
import json, sys
m = json.load(open(sys.argv[1]))
assert m["format"] == "trainsim-dataset", m
assert m["seed"] == 5 and len(m["scenario_hash"]) == 16, m
assert m["sequence"] == "00" and isinstance(m["sensors"], list), m
assert isinstance(m["not_simulated"], list), m
# Every output is listed with its files, and they exist.
import os
root = os.path.dirname(sys.argv[1])
assert m["sequence_dir"] == "sequences/00", m
for s in m["sensors"]:
    assert s["files"], s
    for f in s["files"]:
        assert os.path.exists(os.path.join(root, f)), f
assert [s["files"] for s in m["sensors"] if s["kind"] == "frames"] == [
    ["sequences/00/times.txt", "sequences/00/poses.txt"]], m
PY
# Every pipeline stage is built: nothing is reported as not simulated.
grep -q "not simulated yet" "$WORK/err" && fail "generate reports stages not run" ||
  pass "generate runs every stage"
python3 -c "import json,sys; assert json.load(open(sys.argv[1]))['not_simulated'] == []" \
  "$WORK/a/manifest.json" && pass "manifest: nothing not simulated" || fail "manifest lists stages not run"
# The front camera's images, P0-P3 and Tr in calib.txt.
for d in image_2 depth_2 semantic_2 instance_2; do
  [ "$(ls "$WORK/a/sequences/00/$d" | wc -l)" -eq 305 ] && pass "$d: 305 frames" || fail "$d: not 305 frames"
done
[ "$(cut -d: -f1 "$WORK/a/sequences/00/calib.txt" | tr '\n' ' ')" = "P0 P1 P2 P3 Tr " ] &&
  pass "calib.txt: P0 P1 P2 P3 Tr" || fail "calib.txt keys: $(cut -d: -f1 "$WORK/a/sequences/00/calib.txt")"
# evaluate reads the dataset's own poses.txt and calib.txt (its Tr): against itself, no error.
S="$WORK/a/sequences/00"
expect_exit 0 "evaluate poses.txt against itself" -- "$TRAINSIM" evaluate --gt "$S/poses.txt" \
  --est "$S/poses.txt" --calib "$S/calib.txt" --json
python3 -c "
import json, sys
r = json.load(open(sys.argv[1]))
assert r['frames'] == 305 and r['paper']['axes'] == 'velodyne', r
assert r['kitti']['all']['segments'] > 0 and r['kitti']['all']['translation_percent'] == 0, r
assert r['paper']['tex_m']['max'] < 1e-9 and r['paper']['eod_percent']['max'] < 1e-9, r
" "$WORK/out" && pass "evaluate: a dataset against itself has no error" || fail "evaluate on the dataset"
# Cross-sensor: the LiDAR's points projected through calib.txt land on semantic_2 pixels of
# their own class (>= 95 % of those in view; every 15th frame, read by the test's own readers).
export TESTS_DIR="$(cd "$(dirname "$0")" && pwd)"
python3 "$TESTS_DIR/cross_sensor.py" "$WORK/a/sequences/00" 15 >"$WORK/cross.txt" &&
  pass "LiDAR points on their class in the camera: $(head -1 "$WORK/cross.txt")" ||
  fail "LiDAR points on their class in the camera: $(cat "$WORK/cross.txt")"
# The remaining checks run a shorter route (1.5 km, every sensor of the default) so that the
# suite stays fast; the full default dataset's bytes are pinned by regression_default_dataset.
# Its camera has a lens, night with headlights, sensor noise and float depth, so the thread
# count checks cover them too.
"$TRAINSIM" defaults | python3 -c '
import json, sys
s = json.load(sys.stdin)
s["route"]["generator"]["length_m"] = 1500.0
cam = s["sensors"]["cameras"][0]
cam.update({"distortion": {"k1": -0.2, "k2": 0.05, "p1": 0.0, "p2": 0.0, "k3": 0.0},
            "daytime": "night", "read_noise_dn": 2.0, "shot_noise_dn": 3.0, "iso": 400.0,
            "depth_float": True, "semantic_preview": True})
json.dump(s, sys.stdout, indent=2)' >"$WORK/short.json"
# Another sequence number: the manifest says where its files are.
expect_exit 0 "generate sequence 7" -- bash -c \
  "sed 's/\"sequence\": 0/\"sequence\": 7/' \"$WORK/short.json\" | \"$TRAINSIM\" generate - --out \"$WORK/s7\""
grep -q '"sequences/07/imu.csv"' "$WORK/s7/manifest.json" && pass "manifest lists sequences/07 files" ||
  fail "manifest does not list sequences/07 files"

# Same scenario and seed: byte-identical, whatever the thread count.
# The run loop reports its worker arena; the unit test RunLoop.* shows the renders really run
# on that many threads.
for n in 1 2 4; do
  expect_exit 0 "generate --threads $n" -- "$TRAINSIM" generate "$WORK/short.json" --out "$WORK/t$n" --threads $n
  expect_contains "$WORK/err" "run loop: $n worker threads" "--threads $n gives $n workers"
done
[ "$(ls "$WORK/t1/sequences/00/image_2" | wc -l)" -gt 50 ] && [ -n "$(ls "$WORK/t1/sequences/00/velodyne")" ] &&
  pass "the short run has camera and LiDAR frames" || fail "the short run lacks camera or LiDAR frames"
for n in 2 4; do
  diff -r "$WORK/t1" "$WORK/t$n" >/dev/null && pass "dataset with --threads $n identical to --threads 1" ||
    fail "dataset with --threads $n differs from --threads 1"
done
# The lens's coefficients follow P and Tr in calib.txt; the float depth agrees with the PNG's.
[ "$(cut -d: -f1 "$WORK/t1/sequences/00/calib.txt" | tr '\n' ' ')" = "P0 P1 P2 P3 Tr D2 " ] &&
  pass "calib.txt: P0 P1 P2 P3 Tr D2" || fail "calib.txt keys: $(cut -d: -f1 "$WORK/t1/sequences/00/calib.txt")"
python3 - "$WORK/t1/sequences/00" <<'PY' && pass "depth PFM matches the depth PNG" || fail "depth PFM"
import os, struct, sys
sys.path.insert(0, os.environ.get("TESTS_DIR", "."))
from kitti_read import read_png
seq = sys.argv[1]
data = open(os.path.join(seq, "depth_2", "000020.pfm"), "rb").read()
head = data.split(b"\n", 3)
assert head[0] == b"Pf" and float(head[2]) < 0, head[:3]
w, h = map(int, head[1].split())
values = struct.unpack(f"<{w * h}f", head[3])
pw, ph, _, rows = read_png(os.path.join(seq, "depth_2", "000020.png"))
assert (w, h) == (pw, ph)
checked = 0
for v in range(h):
    for u in range(w):
        d = values[(h - 1 - v) * w + u]  # PFM rows bottom to top
        if rows[v][u]:
            assert abs(d - rows[v][u] / 256) <= 1 / 512 + 1e-6, (u, v, d, rows[v][u])
            checked += 1
assert checked > w * h // 4, checked
PY
# Signals show their aspect: instances.csv names it for every signal (never stop on the train's
# own track 0) and lists every signal as class signal, and where a signal facing the train (not
# one of the double track's own direction, index + 2^32, whose back it sees) is large in the
# night picture, its brightest pixel has the aspect's colour (the lit lamp, overexposed at
# ISO 400 as real ones are).
python3 - "$WORK/t1/sequences/00" <<'PY' && pass "signal aspects in instances.csv and in the pictures" || fail "signal aspects"
import os, sys
sys.path.insert(0, os.environ.get("TESTS_DIR", "."))
from kitti_read import read_png
seq = sys.argv[1]
lines = open(os.path.join(seq, "instances.csv")).read().splitlines()
assert lines[0] == "instance,scene_instance,class,track,state", lines[0]
aspects, facing = {}, set()
for line in lines[1:]:
    instance, scene, cls, track, state = line.split(",")
    scene = int(scene)
    signal = scene >> 56 == 1 and (scene >> 36) & 0xFF == 12  # a track asset of kind signal
    assert (state in ("proceed", "caution", "stop")) == signal and (state == "") != signal, line
    if signal:
        assert not (state == "stop" and (scene >> 44) & 0xFFF == 0), line  # the train's track
        assert cls == "signal", line  # also where its post was seen before its head
        aspects[int(instance)] = state
        if scene & ((1 << 36) - 1) < 1 << 32:
            facing.add(int(instance))
assert len(set(aspects.values())) == 3, aspects
checked = {}
frames = sorted(os.listdir(os.path.join(seq, "instance_2")))
for frame in frames[::3]:
    w, h, _, ids = read_png(os.path.join(seq, "instance_2", frame))
    count = {}
    for row in ids:
        for i in row:
            if i in facing:
                count[i] = count.get(i, 0) + 1
    large = [i for i, n in count.items() if n >= 150]
    if not large:
        continue
    _, _, _, cls = read_png(os.path.join(seq, "semantic_2", frame))
    _, _, _, rgb = read_png(os.path.join(seq, "image_2", frame))
    brightest = {}
    for v in range(h):
        for u in range(w):
            i = ids[v][u]
            if i in large and cls[v][u] == 16:
                px = rgb[v][3 * u:3 * u + 3]
                if sum(px) > sum(brightest.get(i, (0, 0, 0))):
                    brightest[i] = tuple(px)
    for i, (r, g, b) in brightest.items():
        seen = ("stop" if r - g >= 60 else
                "caution" if r >= 200 and g >= 200 and r - b >= 60 else
                "proceed" if g >= 200 and g - r >= 40 else "none")
        assert seen == aspects[i], (frame, i, aspects[i], (r, g, b))
        checked[aspects[i]] = checked.get(aspects[i], 0) + 1
assert len(checked) == 3, checked
print(checked)
PY
# The default run's instances.csv too lists every signal as class signal (a LiDAR sees many a
# signal's post before its head).
python3 - "$WORK/a/sequences/00/instances.csv" <<'PY' && pass "every signal of the default run is listed as a signal" || fail "a signal listed under another class"
import sys
signals = 0
for line in open(sys.argv[1]).read().splitlines()[1:]:
    instance, scene, cls, track, state = line.split(",")
    if int(scene) >> 56 == 1 and (int(scene) >> 36) & 0xFF == 12:
        assert cls == "signal", line
        signals += 1
assert signals > 10, signals
PY
# Obstacle detection: the default scenario's three obstacles (a person crossing the double track,
# a car and a cow in the fields) are listed with their class and track, and the LiDAR's labels
# hold points of each class.
python3 - "$WORK/a/sequences/00" "$WORK/obstacles.txt" <<'PY' && pass "obstacles seen: $(cat "$WORK/obstacles.txt")" || fail "obstacles"
import array, os, sys
seq = sys.argv[1]
seen, ids = {}, {}
for line in open(os.path.join(seq, "instances.csv")).read().splitlines()[1:]:
    instance, scene, cls, track, state = line.split(",")
    if int(scene) >> 56 == 1 and (int(scene) >> 36) & 0xFF == 13:
        seen[int(scene) & 0xFFFFFFFFF] = (cls, track)
        ids[int(instance)] = cls
assert seen == {0: ("person", "1"), 1: ("car", "0"), 2: ("animal", "0")}, seen
points = {18: 0, 19: 0, 20: 0}
for name in sorted(os.listdir(os.path.join(seq, "labels"))):
    labels = array.array("I")
    with open(os.path.join(seq, "labels", name), "rb") as f:
        labels.frombytes(f.read())
    for label in labels:
        if label & 0xFFFF in points:
            points[label & 0xFFFF] += 1
            assert ids[label >> 16] == {18: "person", 19: "car", 20: "animal"}[label & 0xFFFF], label
assert all(n > 0 for n in points.values()), points
open(sys.argv[2], "w").write(f"LiDAR points person {points[18]}, car {points[19]}, animal {points[20]}")
PY
# Track discrimination: instances.csv gives each rail's layout track, and the LiDAR's rail points
# 5-15 m ahead lie within 1 m of the sensor's axis exactly when their rail is the train's own
# track 0 (the others are 4 m and more to the side).
python3 - "$WORK/t1/sequences/00" "$WORK/rails.txt" <<'PY' && pass "rails of the train's own track: $(cat "$WORK/rails.txt")" || fail "rails' tracks"
import os, sys
sys.path.insert(0, os.environ.get("TESTS_DIR", "."))
from kitti_read import read_labels, read_velodyne
seq = sys.argv[1]
track = {}
for line in open(os.path.join(seq, "instances.csv")).read().splitlines()[1:]:
    instance, scene, cls, on, state = line.split(",")
    if cls == "rail":
        track[int(instance)] = int(on)
assert 0 in track.values() and len(set(track.values())) > 1, track
near = {True: 0, False: 0}
for frame in sorted(os.listdir(os.path.join(seq, "velodyne")))[::10]:
    points = read_velodyne(os.path.join(seq, "velodyne", frame))
    labels = read_labels(os.path.join(seq, "labels", frame[:-4] + ".label"))
    for (x, y, z, _), label in zip(points, labels):
        if label & 0xFFFF != 1 or not 5.0 < x < 15.0:
            continue
        ego = track[label >> 16] == 0
        assert (abs(y) < 1.0) == ego, (frame, x, y, z, track[label >> 16])
        near[ego] += 1
assert near[True] > 100 and near[False] > 100, near
print(f"{near[True]} points on it, {near[False]} on other tracks", file=open(sys.argv[2], "w"))
PY
# A different seed is a different run.
expect_exit 0 "generate --seed 7" -- "$TRAINSIM" generate "$WORK/short.json" --out "$WORK/d" --seed 7
grep -q '"seed": 7' "$WORK/d/scenario.json" && pass "--seed recorded in scenario.json" ||
  fail "--seed not recorded"
cmp -s "$WORK/t1/sequences/00/poses.txt" "$WORK/d/sequences/00/poses.txt" &&
  fail "--seed 7 gives the same route" || pass "--seed 7 gives another route"
# From standard input.
expect_exit 0 "generate from stdin" -- bash -c \
  "\"$TRAINSIM\" generate - --out \"$WORK/e\" <\"$WORK/short.json\""
diff -r "$WORK/t1" "$WORK/e" >/dev/null && pass "stdin run identical" || fail "stdin run differs"
# A second camera turned against camera 0: its P is K [R | t], which KITTI's rectified readers
# misread, and the run says so; one turned as camera 0 is not warned about.
cat >"$WORK/turned.json" <<'JSON'
{"route": {"source": "blocks", "blocks": [{"type": "straight", "length_m": 300}]},
 "trajectory": {"static_only": true, "standstill_start_s": 1},
 "dataset": {"frame_period_ns": 1000000000},
 "sensors": {"cameras": [{"width": 64, "height": 48, "period_ns": 1000000000},
   {"width": 64, "height": 48, "period_ns": 1000000000, "mount": {"x_m": 10.5, "y_m": -0.5, "z_m": 3.2}},
   {"width": 64, "height": 48, "period_ns": 1000000000, "mount": {"x_m": 10.5, "z_m": 3.2, "yaw_deg": 90}},
   {"width": 64, "height": 48, "period_ns": 1000000000, "mount": {"x_m": 10.5, "z_m": 0.4, "pitch_deg": -70}}]}}
JSON
expect_exit 0 "generate with a turned camera" -- "$TRAINSIM" generate "$WORK/turned.json" --out "$WORK/turned" --progress none
expect_contains "$WORK/err" "sensors.cameras[2]: the camera is turned against camera 0, so calib.txt's P4 is K [R | t]" "the turned camera's P is flagged"
grep -q "sensors.cameras\[1\]: the camera is turned" "$WORK/err" && fail "a camera turned as camera 0 was flagged" ||
  pass "a camera turned as camera 0 is not flagged"
# Without a LiDAR, classes.yaml's content is the first camera's semantic pixels, class by class
# (semantic-kitti-api's trainers weigh classes by it; all 0 would divide by zero).
python3 - "$WORK/turned" <<'PY' && pass "camera-only content: the semantic pixels' shares" || fail "camera-only content"
import collections, os, sys
sys.path.insert(0, os.environ["TESTS_DIR"])
from kitti_read import read_png
root = sys.argv[1]
counts = collections.Counter()
folder = os.path.join(root, "sequences", "00", "semantic_2")
for name in os.listdir(folder):
    _, _, _, rows = read_png(os.path.join(folder, name))
    for row in rows:
        counts.update(row)
total = sum(counts.values())
lines = open(os.path.join(root, "classes.yaml")).read().split("\ncontent:")[1].split("\n")
assert "first camera's semantic pixels" in lines[0], lines[0]
content = {}
for line in lines[1:]:
    if not line.startswith("  "):
        break
    k, v = line.split(":")
    content[int(k)] = float(v)
assert abs(sum(content.values()) - 1) < 1e-6
for k, v in content.items():
    assert abs(v - counts.get(k, 0) / total) < 1e-8, (k, v, counts.get(k, 0) / total)
PY
# A camera low down looking steeply at the track (an inspection camera) loses the track nearer
# than near_m: the run says so; the windscreen cameras are not warned about.
expect_contains "$WORK/err" "sensors.cameras[3]: the camera sees the rail-top plane from 0.35 m along its axis, nearer than near_m" "a near plane cutting the track is flagged"
grep -q "cameras\[[012]\]: the camera sees the rail-top plane" "$WORK/err" && fail "a windscreen camera was flagged for its near plane" ||
  pass "windscreen cameras are not flagged for their near plane"
# validate says what the run's start says, before any run.
expect_exit 0 "validate with turned and low cameras" -- "$TRAINSIM" validate "$WORK/turned.json"
expect_contains "$WORK/err" "sensors.cameras[2]: the camera is turned against camera 0, so calib.txt's P4 is K [R | t]" "validate flags the turned camera"
expect_contains "$WORK/err" "sensors.cameras[3]: the camera sees the rail-top plane from 0.35 m along its axis" "validate flags the near plane"
# LiDAR ranges beyond the device's datasheet, either way, are said once when the run starts.
cat >"$WORK/ranges.json" <<'JSON'
{"route": {"source": "blocks", "blocks": [{"type": "straight", "length_m": 300}]},
 "trajectory": {"static_only": true, "standstill_start_s": 1},
 "dataset": {"frame_period_ns": 1000000000},
 "sensors": {"lidars": [{"model": "vlp16", "period_ns": 1000000000, "columns": 90, "range_min_m": 0.5, "range_max_m": 150},
   {"model": "vlp16", "period_ns": 1000000000, "columns": 90, "range_min_m": 0.9, "range_max_m": 100}]}}
JSON
expect_exit 0 "generate with ranges beyond the datasheet" -- "$TRAINSIM" generate "$WORK/ranges.json" --out "$WORK/ranges" --progress none
expect_contains "$WORK/err" "sensors.lidars[0]: range_min_m 0.5 m is below the vlp16's 0.9 m" "a range_min_m below the device's is said"
expect_contains "$WORK/err" "sensors.lidars[0]: range_max_m 150 m is beyond the vlp16's 100 m" "a range_max_m beyond the device's is said"
grep -qE "sensors.lidars\[1\]: range_(min|max)_m" "$WORK/err" && fail "the device's own ranges were flagged" ||
  pass "the device's own ranges are not flagged"
# Daylight does not reach far into a tunnel: at noon, the pictures 100 m or more inside an 800 m
# tunnel are much darker than those outside it (the headlights light the tube). And it is the
# surfaces that are lit or not, not the whole picture: from outside, the bore seen through the
# portal is dark beyond daylight's 50 m; from inside, the world beyond the exit is daylit.
cat >"$WORK/tunnel.json" <<'JSON'
{"route": {"source": "blocks", "blocks": [{"type": "straight", "length_m": 400}, {"type": "tunnel", "length_m": 800}, {"type": "straight", "length_m": 400}]},
 "dataset": {"frame_period_ns": 1000000000},
 "sensors": {"cameras": [{"width": 240, "height": 80, "period_ns": 1000000000}]}}
JSON
expect_exit 0 "generate through a tunnel" -- "$TRAINSIM" generate "$WORK/tunnel.json" --out "$WORK/tunnel" --progress none
python3 - "$WORK/tunnel" <<'PY' && pass "tunnel pictures are dark inside, daylit outside; the bore dark from outside, beyond the exit daylit from inside" || fail "tunnel lighting"
import bisect, csv, os, sys
sys.path.insert(0, os.environ["TESTS_DIR"])
from kitti_read import read_png
root = sys.argv[1]
seq = os.path.join(root, "sequences", "00")
rows = list(csv.DictReader(open(os.path.join(root, "trajectory.csv"))))
t_ns = [int(r["t_ns"]) for r in rows]
inside, outside = [], []
for i, line in enumerate(open(os.path.join(seq, "times.txt"))):
    chainage = float(rows[bisect.bisect_left(t_ns, round(float(line) * 1e9))]["chainage_m"])
    _, _, _, px = read_png(os.path.join(seq, "image_2", "%06d.png" % i))
    mean = sum(sum(row) for row in px) / sum(len(row) for row in px)
    if 500 < chainage < 1100:
        inside.append(mean)
    elif chainage < 350 or chainage > 1250:
        outside.append(mean)
assert len(inside) >= 5 and len(outside) >= 10, (len(inside), len(outside))
print("inside", max(inside), "outside", min(outside))
assert max(inside) < 0.3 * min(outside), (inside, outside)
# By surface: the bore seen from outside, the world beyond the exit seen from inside.
# Mean colour and count of the pixels whose depth (along the optical axis, the camera looking
# down the straight track) lies in (lo, hi) m.
def pixels(i, lo, hi):
    _, _, _, px = read_png(os.path.join(seq, "image_2", "%06d.png" % i))
    _, _, _, dp = read_png(os.path.join(seq, "depth_2", "%06d.png" % i))
    total = n = 0
    for prow, drow in zip(px, dp):
        for x, d in enumerate(drow):
            if lo < d / 256.0 < hi:
                total += sum(prow[3 * x:3 * x + 3])
                n += 1
    return total, n
bore, near, beyond = [0, 0], [0, 0], [0, 0]
for i, line in enumerate(open(os.path.join(seq, "times.txt"))):
    # The camera is 1.75 m ahead of the front pivot (mount 10.5 m, bogie spacing 17.5 m).
    c = float(rows[bisect.bisect_left(t_ns, round(float(line) * 1e9))]["chainage_m"]) + 1.75
    parts = []
    if 300 < c < 395:  # before the portal at 400 m: the bore past 60 m in, the open track
        parts = [(bore, 400 - c + 60, 99), (near, 0.1, 400 - c - 5)]
    elif 1100 < c < 1195:  # before the exit at 1200 m: what lies beyond it
        parts = [(beyond, 1200 - c + 2, 99)]
    for acc, lo, hi in parts:
        total, n = pixels(i, lo, hi)
        acc[0] += total
        acc[1] += n
assert min(bore[1], near[1], beyond[1]) >= 20, (bore, near, beyond)
mean = lambda acc: acc[0] / (3.0 * acc[1])
print("bore", mean(bore), "open track", mean(near), "beyond the exit", mean(beyond))
assert mean(bore) < 40 and mean(near) > 80 and mean(beyond) > 70, (mean(bore), mean(near), mean(beyond))
PY
# Dual returns with one ray a pulse have nothing to pair: the run says so (and not for a LiDAR
# whose pulses have sub-rays). Without a camera, calib.txt still has P0-P3 for pykitti.
cat >"$WORK/dual.json" <<'JSON'
{"route": {"source": "blocks", "blocks": [{"type": "straight", "length_m": 300}]},
 "trajectory": {"static_only": true, "standstill_start_s": 1},
 "dataset": {"frame_period_ns": 1000000000},
 "sensors": {"lidars": [{"model": "vlp16", "period_ns": 1000000000, "returns": "dual"},
   {"name": "divergent", "model": "vlp16", "period_ns": 1000000000, "returns": "dual", "sub_rays": 4, "mount": {"x_m": 9}}]}}
JSON
expect_exit 0 "generate with dual returns" -- "$TRAINSIM" generate "$WORK/dual.json" --out "$WORK/dual" --progress none
expect_contains "$WORK/err" "sensors.lidars[0]: returns is dual but sub_rays is 1" "dual returns without sub-rays are flagged"
grep -q "sensors.lidars\[1\]: returns is dual" "$WORK/err" && fail "dual returns with sub-rays were flagged" ||
  pass "dual returns with sub-rays are not flagged"
expect_exit 0 "validate with dual returns" -- "$TRAINSIM" validate "$WORK/dual.json"
expect_contains "$WORK/err" "sensors.lidars[0]: returns is dual but sub_rays is 1" "validate flags dual returns without sub-rays"
[ "$(cut -d: -f1 "$WORK/dual/sequences/00/calib.txt" | tr '\n' ' ')" = "P0 P1 P2 P3 Tr Tr_1 " ] &&
  pass "LiDAR-only calib.txt: P0 P1 P2 P3 Tr Tr_1" || fail "LiDAR-only calib.txt keys: $(cut -d: -f1 "$WORK/dual/sequences/00/calib.txt")"
finish
