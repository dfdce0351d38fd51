# Golden output: the default scenario's dataset, file by file, against the SHA-256 digests in
# tests/data/golden/default_dataset.sha256. A change that alters the output on purpose updates
# the digests with: tests/regression/default_dataset.sh build/bin/trainsim - . --update
# The digests are made with every thread the machine has and checked with one, so the check
# also holds the whole default run (bridges, stations, tunnels) to the same bytes for any
# thread count, on a machine with more than one core.
source "$(dirname "$0")/../integration/lib.sh" "$@"
golden="$SRC/tests/data/golden/default_dataset.sha256"
threads=1
[ "${4:-}" = "--update" ] && threads=0
expect_exit 0 "generate default (--threads $threads)" -- \
  "$TRAINSIM" generate --out "$WORK/d" --progress none --threads $threads
(cd "$WORK/d" && find . -type f | LC_ALL=C sort | xargs sha256sum) >"$WORK/digests"
if [ "${4:-}" = "--update" ]; then
  cp "$WORK/digests" "$golden"
  echo "updated $golden"
fi
if diff -u "$golden" "$WORK/digests" >"$WORK/diff"; then
  pass "default dataset matches the golden digests"
else
  fail "default dataset differs from the golden digests (tests/data/golden):"
  cat "$WORK/diff" >&2
fi
finish
