#!/usr/bin/env bash
# Makes the camera pictures in docs/images from runs of the built trainsim: the default scenario
# on a 1.5 km route with only its front camera, at one frame, in the morning (RGB, depth,
# semantic), at night (headlights) and in fog (150 m visibility).
#
#   docs/images/make_camera_images.sh [build/bin/trainsim] [frame]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
trainsim="${1:-build/bin/trainsim}"
frame="${2:-000040}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for look in morning night fog; do
  "$trainsim" defaults | python3 -c '
import json, sys
s = json.load(sys.stdin)
s["route"]["generator"]["length_m"] = 1500.0
s["sensors"]["lidars"] = []
cam = s["sensors"]["cameras"][0]
cam["semantic_preview"] = True
look = sys.argv[1]
cam["daytime"] = {"morning": "morning", "night": "night", "fog": "noon"}[look]
if look == "fog":
    cam["fog_visibility_m"] = 150.0
json.dump(s, sys.stdout)' "$look" >"$work/$look.json"
  "$trainsim" generate "$work/$look.json" --out "$work/$look" --progress none --log-level warn
  seq="$work/$look/sequences/00"
  cp "$seq/image_2/$frame.png" "$here/camera-$look-rgb.png"
  if [ "$look" = morning ]; then
    cp "$seq/semantic_rgb_2/$frame.png" "$here/camera-$look-semantic.png"
    python3 "$here/depth_preview.py" "$seq/depth_2/$frame.png" "$here/camera-$look-depth.png"
  fi
done
echo "wrote $here/camera-{morning,night,fog}-rgb.png, camera-morning-{depth,semantic}.png"
