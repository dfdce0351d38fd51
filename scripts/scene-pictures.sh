#!/usr/bin/env bash
# Renders the README's pictures of the generated scene (default scenario) into docs/images/ with
# the project's own renderer, build/bin/trainsim-scene-shot, under a private Xvfb.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shot="$root/build/bin/trainsim-scene-shot"
[ -x "$shot" ] || { echo "scene-pictures: build first (make build)" >&2; exit 2; }
xvfb="$root/tests/studio/with-xvfb.sh"
mkdir -p "$root/docs/images"
# The station (chainage 1572-1822 m of the default route), seen from above the auxiliary track.
bash "$xvfb" "$shot" --out "$root/docs/images/scene-station.png" --chainage 1530 --side 10 \
  --height 9 --back 60 --ahead 160
# The bridge (2890-3134 m) from the side of its valley, the way toward the tunnel beyond.
bash "$xvfb" "$shot" --out "$root/docs/images/scene-bridge.png" "$@" --chainage 2900 --side -140 \
  --height 2 --back -60 --ahead 120 --radius 900
