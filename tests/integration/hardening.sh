# What a careless or hostile user meets on the command line (issue: hardening): unknown
# commands, --out that names a file or nothing, plan into someone else's folder, Ctrl-C and
# SIGTERM while planning and while running, and --resume from a checkpoint that does not match
# its files. Every refusal exits 2 with one line naming the file or the folder; a run stopped
# before its first frame leaves nothing; after it, the folder can be resumed and says so.
source "$(dirname "$0")/lib.sh" "$@"
cd "$WORK"

expect_exit 2 "unknown command" -- "$TRAINSIM" frobnicate
expect_contains "$WORK/err" "unknown command 'frobnicate': expected one of generate, plan" \
  "unknown command named with the commands there are"

# --- --out ------------------------------------------------------------------------------------
echo x >"$WORK/afile"
for command in plan generate; do
  expect_exit 2 "$command --out naming a file" -- "$TRAINSIM" "$command" --out "$WORK/afile"
  expect_contains "$WORK/err" "output $WORK/afile exists and is not a folder" "$command: says so"
  expect_exit 2 "$command --out below a file" -- "$TRAINSIM" "$command" --out "$WORK/afile/sub"
  expect_contains "$WORK/err" "$WORK/afile is not a folder" "$command: names the file in the way"
  expect_exit 2 "$command --out ''" -- "$TRAINSIM" "$command" --out ''
  expect_contains "$WORK/err" "the output folder name is empty" "$command: empty name explained"
done

# --- plan follows the folder rules generate follows --------------------------------------------
mkdir -p "$WORK/user"
echo '{"mine": true}' >"$WORK/user/scenario.json"
echo "notes" >"$WORK/user/notes.txt"
expect_exit 2 "plan into a foreign folder" -- "$TRAINSIM" plan --out "$WORK/user"
expect_contains "$WORK/err" "not empty and was not written by trainsim" "plan refusal explained"
[ "$(cat "$WORK/user/scenario.json")" = '{"mine": true}' ] && pass "the user's scenario.json kept" ||
  fail "plan replaced the user's scenario.json"
expect_exit 0 "plan --force into a foreign folder" -- "$TRAINSIM" plan --out "$WORK/user" --force
[ "$(cat "$WORK/user/notes.txt")" = notes ] && pass "--force keeps foreign files" ||
  fail "--force removed a foreign file"
expect_exit 2 "plan again into its own plan" -- "$TRAINSIM" plan --out "$WORK/user"
expect_contains "$WORK/err" "holds a plan: pass --force" "second plan refused, explained"

# --- interrupts during the plan stage -----------------------------------------------------------
# Waits until PID catches SIGINT and SIGTERM (bits 2 and 15 of SigCgt), so that a loaded machine
# starting the process slowly cannot turn the test's signal into a plain kill.
handlers_installed() {
  for _ in $(seq 1 500); do
    mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null || echo 0)
    [ $((0x${mask:-0} & 0x4002)) -eq $((0x4002)) ] && return 0
    sleep 0.01
  done
}

# A 400 km route plans for about 1.5 s and writes its plan files for 10 s more: a signal at any
# point stops it within a second (three allowed on a loaded machine), and nothing is left (no
# frame was complete).
echo '{"route": {"generator": {"length_m": 400000}}}' >"$WORK/long.json"
for step in "plan 0.5 INT" "plan 3 TERM" "generate 0.5 TERM" "generate 3 INT"; do
  set -- $step
  rm -rf "$WORK/cut"
  "$TRAINSIM" "$1" "$WORK/long.json" --out "$WORK/cut" >/dev/null 2>"$WORK/err" &
  pid=$!
  handlers_installed "$pid"
  sleep "$2"
  start=$(date +%s%N)
  kill -"$3" "$pid"
  code=0
  wait "$pid" || code=$?
  took=$((($(date +%s%N) - start) / 1000000))
  [ "$code" -eq 1 ] && pass "$1: SIG$3 after $2 s exits 1" || fail "$1: SIG$3 exit $code"
  [ "$took" -lt 3000 ] && pass "$1: stopped $took ms after SIG$3" || fail "$1: took $took ms"
  expect_contains "$WORK/err" "cancelled" "$1: says it was cancelled"
  [ ! -e "$WORK/cut" ] && pass "$1: nothing left after SIG$3" || fail "$1: left $(ls -A "$WORK/cut")"
done

# --- an interrupt after the first frames keeps a resumable folder --------------------------------
cat >"$WORK/run.json" <<'JSON'
{"route": {"generator": {"length_m": 20000}},
 "sensors": {"imus": [{"period_ns": 10000000}], "gnss_receivers": [{}], "odometers": [{}]}}
JSON
expect_exit 0 "reference run" -- "$TRAINSIM" generate "$WORK/run.json" --out "$WORK/ref" --progress none
interrupted=0
for attempt in 1 2 3; do
  rm -rf "$WORK/part"
  "$TRAINSIM" generate "$WORK/run.json" --out "$WORK/part" --threads 1 --progress none \
    >/dev/null 2>"$WORK/part.err" &
  pid=$!
  handlers_installed "$pid"
  for _ in $(seq 1 500); do
    grep -qE '"next_sample": [1-9]' "$WORK/part/.trainsim/checkpoint.json" 2>/dev/null && break
    sleep 0.01
  done
  kill -INT "$pid" 2>/dev/null || true
  code=0
  wait "$pid" || code=$?
  if [ "$code" -eq 1 ] && [ -e "$WORK/part/.trainsim/checkpoint.json" ]; then interrupted=1; break; fi
done
if [ "$interrupted" -eq 1 ]; then
  expect_contains "$WORK/part.err" "continue it with --resume" "interrupted run says how to go on"
  cp -r "$WORK/part" "$WORK/pristine"
  checkpoint="$WORK/part/.trainsim/checkpoint.json"
  # Tampered checkpoints are refused, naming the checkpoint; each from a fresh copy.
  tamper() {  # DESCRIPTION EXPECTED-TEXT COMMAND...
    local what="$1" text="$2"; shift 2
    rm -rf "$WORK/part"; cp -r "$WORK/pristine" "$WORK/part"
    "$@"
    expect_exit 2 "resume refuses $what" -- "$TRAINSIM" generate "$WORK/run.json" --out "$WORK/part" \
      --resume --progress none
    expect_contains "$WORK/err" "$checkpoint" "$what: names the checkpoint"
    expect_contains "$WORK/err" "$text" "$what: says what is wrong"
    ! grep -q "continue it with --resume" "$WORK/err" && pass "$what: no advice to resume" ||
      fail "$what: a refused resume advised --resume"
  }
  tamper "a negative next_sample" "next_sample -5 is negative" \
    sed -i -E 's/"next_sample": [0-9]+/"next_sample": -5/' "$checkpoint"
  tamper "a next_sample off the frame grid" "is not a frame boundary" \
    sed -i -E 's/"next_sample": ([0-9]+)/"next_sample": \13/' "$checkpoint"
  tamper "a shortened file" "sequences/00/imu.csv" truncate -s 10 "$WORK/part/sequences/00/imu.csv"
  tamper "a deleted file" "which is missing" rm "$WORK/part/sequences/00/odometer.csv"
  tamper "a path leaving the folder" "not a path inside the dataset" \
    sed -i 's|"sequences/00/imu.csv"|"../../imu.csv"|' "$checkpoint"
  tamper "a damaged checkpoint" "is damaged" truncate -s 20 "$checkpoint"
  tamper "lost sensor state" "holds no state for sensor imu" \
    python3 -c "import json,sys; p=sys.argv[1]; d=json.load(open(p)); d['state'].pop('imu'); json.dump(d, open(p,'w'))" "$checkpoint"
  rm -rf "$WORK/part"; cp -r "$WORK/pristine" "$WORK/part"
  expect_exit 0 "resume the untouched interrupted run" -- "$TRAINSIM" generate "$WORK/run.json" \
    --out "$WORK/part" --resume --progress none
  diff -r "$WORK/ref" "$WORK/part" >"$WORK/diff" && pass "resumed dataset byte-identical" ||
    { fail "resumed dataset differs"; head "$WORK/diff" >&2; }
else
  echo "note: the run finished before it could be interrupted; resume checks skipped"
fi

# --- a stale DISPLAY ----------------------------------------------------------------------------
# VTK aborts the process on a display it cannot open (an SSH session's forwarding gone): the run
# says so and renders on a private Xvfb instead.
cat >"$WORK/camera.json" <<'JSON'
{"route": {"source": "blocks", "blocks": [{"type": "straight", "length_m": 300}]},
 "trajectory": {"static_only": true, "standstill_start_s": 1},
 "dataset": {"frame_period_ns": 1000000000},
 "sensors": {"cameras": [{"width": 160, "height": 48, "period_ns": 1000000000}]}}
JSON
DISPLAY=:987 expect_exit 0 "generate with a stale DISPLAY" -- "$TRAINSIM" generate \
  "$WORK/camera.json" --out "$WORK/stale" --progress none
expect_contains "$WORK/err" "cannot open the X display DISPLAY=:987" "the stale DISPLAY is named"
[ -f "$WORK/stale/sequences/00/image_2/000001.png" ] && pass "the cameras rendered anyway" ||
  fail "no image from the run with a stale DISPLAY"
finish
