#!/usr/bin/env bash
# trainsim-studio as a user starts it (run under tests/studio/with-xvfb.sh): --help and
# --version answer; started on a broken scenario file (invalid values, 100 000 nested arrays,
# a duplicate key) it stays up (the problems go to a dialog, checked in studio_gui_test) until
# it is closed. Args: STUDIO_BINARY
set -euo pipefail
studio="$1"
"$studio" --help | grep -q "scenario" || { echo "FAIL: --help does not describe the argument"; exit 1; }
"$studio" --version | grep -q "TrainSim Studio" || { echo "FAIL: --version"; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
printf '{"route": {"generator": {"length_m": -5}}, "sensorz": {}}\n' >"$tmp/broken.json"
# 100 000 nested arrays once crashed the studio (a message helper recursed through the value).
python3 -c "print('{\"seed\": ' + '[' * 100000 + ']' * 100000 + '}')" >"$tmp/deep.json"
printf '{"seed": 1,\n "seed": 2}\n' >"$tmp/duplicate_keys.json"
for scenario in broken deep duplicate_keys; do
  "$studio" "$tmp/$scenario.json" &
  pid=$!
  sleep 6
  if ! kill -0 "$pid" 2>/dev/null; then
    status=0
    wait "$pid" || status=$?
    echo "FAIL: the studio exited on $scenario.json (status $status)"
    exit 1
  fi
  kill "$pid"
  wait "$pid" 2>/dev/null || true
  echo "PASS: the studio stays up on $scenario.json"
done
