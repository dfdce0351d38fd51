# The dataset writer's folder rules as seen from the command line.
source "$(dirname "$0")/lib.sh" "$@"

mkdir -p "$WORK/foreign"
echo "keep me" > "$WORK/foreign/notes.txt"
expect_exit 2 "refuse a foreign non-empty folder" -- "$TRAINSIM" generate --out "$WORK/foreign"
expect_contains "$WORK/err" "not empty and was not written by trainsim" "refusal explains itself"
[ ! -e "$WORK/foreign/scenario.json" ] && pass "nothing written when refused" || fail "wrote into refused folder"
expect_exit 0 "--force into a foreign folder" -- "$TRAINSIM" generate --out "$WORK/foreign" --force
[ "$(cat "$WORK/foreign/notes.txt")" = "keep me" ] && pass "--force keeps foreign files" ||
  fail "--force removed a foreign file"

expect_exit 2 "refuse to overwrite a dataset" -- "$TRAINSIM" generate --out "$WORK/foreign"
expect_contains "$WORK/err" "already holds a dataset" "overwrite refusal explains itself"
expect_exit 0 "--resume on a complete dataset" -- "$TRAINSIM" generate --out "$WORK/foreign" --resume
expect_contains "$WORK/err" "nothing to do" "resume of a complete dataset does nothing"
expect_exit 2 "--resume with another seed" -- "$TRAINSIM" generate --out "$WORK/foreign" --resume --seed 9
expect_exit 2 "--force with --resume" -- "$TRAINSIM" generate --out "$WORK/foreign" --resume --force
echo "x" > "$WORK/file"
expect_exit 2 "--out is a file" -- "$TRAINSIM" generate --out "$WORK/file"
finish
