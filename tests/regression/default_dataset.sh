# Golden output: the default scenario's dataset, file by file, against the SHA-256 digests in
# tests/data/golden/default_dataset.sha256.
# Arguments: TRAINSIM SYNTHETIC_RUN SOURCE_DIR [DATASET_DIR | --update]. CTest passes the
# dataset its default_dataset fixture generated (with one thread; the digests are made with every
# thread the machine has, so the check also holds the whole default run to the same bytes for
# any thread count). Without a dataset the script generates one. A change that alters the output
# on purpose updates the digests with:
#   tests/regression/default_dataset.sh build/bin/trainsim - . --update
source "$(dirname "$0")/../integration/lib.sh" "$@"
golden="$SRC/tests/data/golden/default_dataset.sha256"
dataset="${4:-}"
if [ -z "$dataset" ] || [ "$dataset" = "--update" ]; then
  threads=1
  [ "$dataset" = "--update" ] && threads=0
  expect_exit 0 "generate default (--threads $threads)" -- \
    "$TRAINSIM" generate --out "$WORK/d" --progress none --threads $threads
  dataset="$WORK/d"
fi
(cd "$dataset" && find . -type f | LC_ALL=C sort | xargs sha256sum) >"$WORK/digests"
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
