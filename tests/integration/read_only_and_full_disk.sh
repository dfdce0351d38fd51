# Writing into a read-only folder or onto a full disk fails with a clear message naming the
# file, exit code 1, and leaves no partial file; a run stopped by a full disk resumes to the
# same bytes once space is freed. Runs in a private mount namespace with small tmpfs mounts
# (as root, or as an unprivileged user through a user namespace); skipped (77) where neither
# is allowed.
if [ -z "${TRAINSIM_IN_MOUNT_NS:-}" ]; then
  if [ "$(id -u)" -eq 0 ] && unshare -m true 2>/dev/null; then
    TRAINSIM_IN_MOUNT_NS=1 exec unshare -m bash "$0" "$@"
  elif unshare -rm true 2>/dev/null; then
    TRAINSIM_IN_MOUNT_NS=1 exec unshare -rm bash "$0" "$@"
  fi
  echo "SKIP: cannot create a mount namespace here" >&2
  exit 77
fi
source "$(dirname "$0")/lib.sh" "$@"

# --- read-only folder -------------------------------------------------------------------------
mkdir -p "$WORK/ro"
mount -t tmpfs -o size=1m tmpfs "$WORK/ro"
mkdir "$WORK/ro/empty"
mount -o remount,ro "$WORK/ro"
expect_exit 1 "generate into a read-only file system" -- "$TRAINSIM" generate --out "$WORK/ro/new"
expect_contains "$WORK/err" "$WORK/ro/new: Read-only file system" "message names the folder and reason"
expect_exit 1 "generate into an empty read-only folder" -- "$TRAINSIM" generate --out "$WORK/ro/empty"
expect_contains "$WORK/err" "Read-only file system" "read-only reason given"
[ -z "$(ls -A "$WORK/ro/empty")" ] && pass "nothing written" || fail "files left in read-only folder"

# --- full disk --------------------------------------------------------------------------------
expect_exit 0 "reference run" -- "$SYNTHETIC_RUN" "$WORK/ref" --samples 400 --payload 16384
mkdir -p "$WORK/full"
mount -t tmpfs -o size=256k tmpfs "$WORK/full"
expect_exit 1 "run onto a disk that fills up" -- "$SYNTHETIC_RUN" "$WORK/full/out" --samples 400 --payload 16384
expect_contains "$WORK/err" "No space left on device" "disk-full reason given"
expect_contains "$WORK/err" "$WORK/full/out/" "disk-full message names the file"
temps=$(find "$WORK/full/out" -name '.*.tmp.*' | wc -l)
[ "$temps" -eq 0 ] && pass "no temporary files left" || fail "$temps temporary files left"
bad=$(find "$WORK/full/out/sequences/00/noise_frames" -name '*.bin' ! -size 16384c | wc -l)
[ "$bad" -eq 0 ] && pass "no partial frame" || fail "$bad partial frames"
[ ! -e "$WORK/full/out/manifest.json" ] && pass "no manifest for an incomplete dataset" ||
  fail "manifest written for an incomplete dataset"
# Every CSV line is complete (cut back to the last checkpoint).
for csv in "$WORK"/full/out/sequences/00/*.csv "$WORK"/full/out/sequences/00/*.txt; do
  [ -s "$csv" ] || continue
  [ "$(tail -c1 "$csv" | od -An -c | tr -d ' ')" = '\n' ] || fail "$(basename "$csv") ends mid-line"
done
pass "append files end on whole lines"

# A disk already full before the first byte: the run fails and leaves no folder behind.
mkdir -p "$WORK/tiny"
mount -t tmpfs -o size=4k tmpfs "$WORK/tiny"
head -c 4096 /dev/zero > "$WORK/tiny/filler" 2>/dev/null || true
expect_exit 1 "generate onto a full disk" -- "$TRAINSIM" generate --out "$WORK/tiny/out"
expect_contains "$WORK/err" "No space left on device" "full-disk reason given"
[ ! -e "$WORK/tiny/out" ] && pass "no folder left behind" || fail "left $(ls -A "$WORK/tiny/out")"
umount "$WORK/tiny"

mount -o remount,size=8m "$WORK/full"
expect_exit 0 "resume once space is freed" -- "$SYNTHETIC_RUN" "$WORK/full/out" --samples 400 --payload 16384 --resume
if diff -r "$WORK/ref" "$WORK/full/out" >"$WORK/diff"; then pass "resumed dataset byte-identical"; else
  fail "resumed dataset differs"; head "$WORK/diff" >&2; fi
umount "$WORK/full" "$WORK/ro" 2>/dev/null || true
finish
