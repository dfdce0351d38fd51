# docs/SCENARIO.md must be exactly what `trainsim schema` prints (regenerate: make docs).
set -euo pipefail
if diff -u "$2/docs/SCENARIO.md" <("$1" schema); then
  echo "docs/SCENARIO.md is current"
else
  echo "docs/SCENARIO.md is stale: run 'make docs'" >&2
  exit 1
fi
