#!/usr/bin/env bash
# with-xvfb.sh COMMAND [ARGS...]: runs COMMAND against a private Xvfb server (software OpenGL
# through Mesa's llvmpipe) and stops the server afterwards. The studio's GUI tests and the
# screenshot script use it, so they run the same on a desktop, over SSH and in CI.
set -euo pipefail
command -v Xvfb >/dev/null || { echo "with-xvfb: Xvfb is not installed (Debian package xvfb)" >&2; exit 2; }
fifo_dir="$(mktemp -d)"
trap 'kill "$xvfb_pid" 2>/dev/null || true; wait "$xvfb_pid" 2>/dev/null || true; rm -rf "$fifo_dir"' EXIT
mkfifo "$fifo_dir/display"
# -displayfd picks a free display number and writes it once the server accepts connections.
Xvfb -displayfd 3 -screen 0 1600x1000x24 -nolisten tcp -noreset +extension GLX \
  3>"$fifo_dir/display" 2>"$fifo_dir/xvfb.log" &
xvfb_pid=$!
read -r -t 30 display <"$fifo_dir/display" || { echo "with-xvfb: Xvfb did not start:" >&2; cat "$fifo_dir/xvfb.log" >&2; exit 1; }
export DISPLAY=":$display"
export QT_QPA_PLATFORM=xcb
# Mesa's software renderer; VTK needs OpenGL 3.2 core, which llvmpipe provides.
export LIBGL_ALWAYS_SOFTWARE=1
"$@"
