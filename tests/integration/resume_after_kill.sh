# kill -9 part-way through a run, then --resume: the dataset equals an uninterrupted run's,
# byte for byte. Uses the run stage on a synthetic trajectory (sim::runDataset, the code path of
# `trainsim generate`) with test sensors that write per-frame files, append-only CSVs and
# carry random-walk state across checkpoints.
source "$(dirname "$0")/lib.sh" "$@"

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
