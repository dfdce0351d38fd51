#!/usr/bin/env bash
# Renders the README's pictures of the generated scene (default scenario) into docs/images/ with
# the project's own renderer, build/bin/trainsim-scene-shot, under a private Xvfb.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shot="$root/build/bin/trainsim-scene-shot"
[ -x "$shot" ] || { echo "scene-pictures: build first (make build)" >&2; exit 2; }
xvfb="$root/tests/studio/with-xvfb.sh"
mkdir -p "$root/docs/images"
# The station (chainage 1572-1822 m of the default route), from above the tracks.
bash "$xvfb" "$shot" --out "$root/docs/images/scene-station.png" --chainage 1560 --side -2 \
  --height 5.5 --back 20 --ahead 150
# The bridge (2890-3134 m) from the side of its valley.
bash "$xvfb" "$shot" --out "$root/docs/images/scene-bridge.png" --chainage 2900 --side -140 \
  --height 2 --back -60 --ahead 120 --radius 900
# The second tunnel's portal (4552 m) in its cutting, from above the main track.
bash "$xvfb" "$shot" --out "$root/docs/images/scene-tunnel.png" --chainage 4500 --side 0 \
  --height 7 --back 60 --ahead 60
