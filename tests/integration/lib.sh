# Shared helpers for the integration scripts. Usage: source lib.sh "$@"
# Arguments: TRAINSIM SYNTHETIC_RUN SOURCE_DIR
set -euo pipefail
TRAINSIM="$1"
SYNTHETIC_RUN="$2"
SRC="$3"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/trainsim-it.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
failures=0

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

# expect_exit CODE DESCRIPTION -- COMMAND...   (stdout/stderr kept in $WORK/out, $WORK/err)
expect_exit() {
  local want="$1" what="$2"; shift 3
  local got=0
  "$@" >"$WORK/out" 2>"$WORK/err" || got=$?
  if [ "$got" -eq "$want" ]; then pass "$what (exit $got)"; else
    fail "$what: exit $got, expected $want"; sed 's/^/  stderr: /' "$WORK/err" >&2; fi
}

expect_contains() {  # FILE TEXT DESCRIPTION
  if grep -qF -- "$2" "$1"; then pass "$3"; else fail "$3: '$2' not in $(basename "$1")";
    sed 's/^/  | /' "$1" >&2; fi
}

finish() {
  if [ "$failures" -gt 0 ]; then echo "$failures check(s) failed" >&2; exit 1; fi
  echo "all checks passed"
}
