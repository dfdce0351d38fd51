# kill -9 part-way through a run, then --resume: the dataset equals an uninterrupted run's,
# byte for byte. First the real `trainsim generate` on a 100 km route with tunnels (plan files,
# times.txt, poses.txt, IMU, GNSS, odometer and balise files, all carrying state); then a short
# route with a LiDAR; then the run stage on a synthetic trajectory with test sensors that also write
# per-frame files and append-only CSVs and carry random-walk state across checkpoints.
source "$(dirname "$0")/lib.sh" "$@"

cat >"$WORK/long.json" <<'JSON'
{"trajectory": {"sample_period_ns": 100000000},
 "dataset": {"frame_period_ns": 100000000},
 "route": {"generator": {"length_m": 100000, "tunnel": {"probability": 0.3}}},
 "sensors": {"imus": [{"preset": "consumer", "period_ns": 100000000, "mount": {"x_m": 8, "z_m": 3.5}}],
             "gnss_receivers": [{}], "odometers": [{"period_ns": 100000000}],
             "balise_readers": [{"period_ns": 100000000}]}}
JSON
expect_exit 0 "generate: uninterrupted run" -- "$TRAINSIM" generate "$WORK/long.json" \
  --out "$WORK/gref" --progress none
for attempt in 1 2 3; do
  rm -rf "$WORK/gcut"
  "$TRAINSIM" generate "$WORK/long.json" --out "$WORK/gcut" --progress none >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 400); do
    n=$({ wc -l <"$WORK/gcut/sequences/00/poses.txt"; } 2>/dev/null || echo 0)
    [ "$n" -ge 500 ] && break
    sleep 0.02
  done
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  [ -e "$WORK/gcut/.trainsim/checkpoint.json" ] && [ ! -e "$WORK/gcut/manifest.json" ] && break
done
[ -e "$WORK/gcut/.trainsim/checkpoint.json" ] && pass "generate: killed run left a checkpoint" ||
  fail "generate: no interrupted run to resume"
expect_exit 0 "generate: resume" -- "$TRAINSIM" generate "$WORK/long.json" --out "$WORK/gcut" \
  --resume --progress none
if diff -r "$WORK/gref" "$WORK/gcut" >"$WORK/diff"; then
  pass "generate: resumed dataset byte-identical"
else
  fail "generate: resumed dataset differs"; head -20 "$WORK/diff" >&2
fi
rm -rf "$WORK/gref" "$WORK/gcut"

# The same with a LiDAR and a camera: per-scan velodyne, labels and point_info files, lidar.csv,
# the camera's image, depth, semantic and instance PNGs (rendered under the Xvfb `generate`
# starts), the instance table both share (carried in the checkpoint) and calib.txt; the
# uninterrupted run on 2 threads, the resumed one on 1.
cat >"$WORK/lidar.json" <<'JSON'
{"seed": 3, "route": {"generator": {"length_m": 600, "station": {"probability": 0.5}}},
 "dataset": {"frame_period_ns": 500000000},
 "sensors": {"lidars": [{"model": "vlp16", "columns": 600, "period_ns": 500000000}],
             "cameras": [{"width": 320, "height": 96, "period_ns": 500000000}],
             "imus": [{}]}}
JSON
expect_exit 0 "LiDAR: uninterrupted run" -- "$TRAINSIM" generate "$WORK/lidar.json" \
  --out "$WORK/lref" --progress none --threads 2
for attempt in 1 2 3; do
  rm -rf "$WORK/lcut"
  "$TRAINSIM" generate "$WORK/lidar.json" --out "$WORK/lcut" --progress none --threads 2 \
    >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 500); do
    n=$(ls "$WORK/lcut/sequences/00/labels" 2>/dev/null | wc -l || true)
    [ "$n" -ge 60 ] && break
    sleep 0.02
  done
  xvfb=$(pgrep -P "$pid" -x Xvfb || true)  # the private X server it started (no DISPLAY)
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  [ -e "$WORK/lcut/.trainsim/checkpoint.json" ] && [ ! -e "$WORK/lcut/manifest.json" ] && break
done
# Its Xvfb goes with it (the parent-death signal), not left running for good.
if [ -n "$xvfb" ]; then
  alive() { local s; s=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null); [ -n "$s" ] && [ "$s" != Z ]; }
  for _ in $(seq 1 100); do alive "$xvfb" || break; sleep 0.05; done
  if alive "$xvfb"; then
    fail "LiDAR: the killed run's Xvfb ($xvfb) lives on"; kill "$xvfb"
  else
    pass "LiDAR: the killed run's Xvfb went with it"
  fi
fi
[ -e "$WORK/lcut/.trainsim/checkpoint.json" ] && pass "LiDAR: killed run left a checkpoint" ||
  fail "LiDAR: no interrupted run to resume"
expect_exit 0 "LiDAR: resume" -- "$TRAINSIM" generate "$WORK/lidar.json" --out "$WORK/lcut" \
  --resume --progress none --threads 1
if diff -r "$WORK/lref" "$WORK/lcut" >"$WORK/diff"; then
  pass "LiDAR: resumed dataset byte-identical"
else
  fail "LiDAR: resumed dataset differs"; head -20 "$WORK/diff" >&2
fi
rm -rf "$WORK/lref" "$WORK/lcut"

expect_exit 0 "uninterrupted run" -- "$SYNTHETIC_RUN" "$WORK/ref" --samples 400
frames_dir="$WORK/cut/sequences/00/noise_frames"
for attempt in 1 2 3; do
  rm -rf "$WORK/cut"
  "$SYNTHETIC_RUN" "$WORK/cut" --samples 400 --delay-ms 40 >/dev/null 2>&1 &
  pid=$!
  # Wait until some frames are on disk, then kill without warning.
  for _ in $(seq 1 200); do
    n=$(ls "$frames_dir" 2>/dev/null | grep -c '\.bin$' || true)
    [ "$n" -ge 12 ] && break
    sleep 0.05
  done
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  [ -e "$WORK/cut/.trainsim/checkpoint.json" ] && [ ! -e "$WORK/cut/manifest.json" ] && break
done
[ -e "$WORK/cut/.trainsim/checkpoint.json" ] && pass "killed run left a checkpoint" ||
  fail "no interrupted run to resume"
expect_exit 2 "interrupted folder needs --resume or --force" -- "$SYNTHETIC_RUN" "$WORK/cut" --samples 400
expect_exit 0 "resume" -- "$SYNTHETIC_RUN" "$WORK/cut" --samples 400 --resume
if diff -r "$WORK/ref" "$WORK/cut" >"$WORK/diff"; then pass "resumed dataset byte-identical"; else
  fail "resumed dataset differs"; head -20 "$WORK/diff" >&2; fi
finish
