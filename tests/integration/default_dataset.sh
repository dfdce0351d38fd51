# Fixture: the built-in default scenario's dataset, generated once for the tests that read it
# (generate_default_scenario checks what it holds, regression_default_dataset its bytes).
# Arguments: TRAINSIM SYNTHETIC_RUN SOURCE_DIR DATASET_DIR. The run's stderr goes beside the
# dataset (DATASET_DIR.err), not into it, so that the dataset's files are only its own.
# One thread: the golden digests are made with every thread the machine has, so comparing with
# them also holds the whole default run (bridges, stations, tunnels) to the same bytes for any
# thread count, on a machine with more than one core.
set -euo pipefail
TRAINSIM="$1"
out="$4"
rm -rf "$out" "$out.err"
if "$TRAINSIM" generate --out "$out" --progress none --threads 1 2>"$out.err"; then
  echo "ok: generated the default dataset into $out"
else
  echo "FAIL: trainsim generate on the default scenario failed:" >&2
  sed 's/^/  stderr: /' "$out.err" >&2
  exit 1
fi
