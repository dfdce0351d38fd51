#!/usr/bin/env bash
# Regenerates the studio screenshots in docs/images/ (linked from README.md): runs the GUI
# test's screenshot case against a private Xvfb server. Needs a built tree (make build).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
test_bin="$root/build/bin/studio_gui_test"
[ -x "$test_bin" ] || { echo "studio-screenshots: $test_bin missing; run 'make build' first" >&2; exit 2; }
mkdir -p "$root/docs/images"
TRAINSIM_SCREENSHOT_DIR="$root/docs/images" \
  "$root/tests/studio/with-xvfb.sh" "$test_bin" screenshots
ls -l "$root/docs/images"/studio-*.png
