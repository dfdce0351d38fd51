# The command-line contract: help, exit codes, defaults/validate/schema round trips.
source "$(dirname "$0")/lib.sh" "$@"

expect_exit 0 "defaults | validate -" -- bash -c "\"$TRAINSIM\" defaults | \"$TRAINSIM\" validate -"
expect_exit 0 "validate the default config file" -- "$TRAINSIM" validate "$SRC/configs/default.json"
expect_exit 0 "schema" -- "$TRAINSIM" schema
expect_contains "$WORK/out" '| `trajectory.sample_period_ns` | integer | ns |' "schema lists T_S"
for cmd in generate plan validate defaults schema; do
  expect_exit 0 "$cmd --help" -- "$TRAINSIM" "$cmd" --help
done
expect_exit 0 "--version" -- "$TRAINSIM" --version
expect_exit 2 "no subcommand" -- "$TRAINSIM"
expect_exit 2 "unknown subcommand" -- "$TRAINSIM" fly
expect_exit 2 "unknown option" -- "$TRAINSIM" generate --speed 3
expect_exit 2 "missing scenario file" -- "$TRAINSIM" generate "$WORK/nope.json" --out "$WORK/o1"
expect_contains "$WORK/err" "$WORK/nope.json: No such file or directory" "missing file is named"
expect_exit 2 "negative --threads" -- "$TRAINSIM" generate --threads -1 --out "$WORK/o2"
expect_exit 2 "bad --progress" -- "$TRAINSIM" generate --progress loud --out "$WORK/o3"
expect_exit 2 "seed out of range" -- "$TRAINSIM" generate --seed 18014398509481984 --out "$WORK/o4"
expect_contains "$WORK/err" "seed: 18014398509481984 is above the maximum" "seed range named"
expect_exit 2 "invalid scenario for generate" -- "$TRAINSIM" generate \
  "$SRC/tests/data/invalid/out_of_range.json" --out "$WORK/o5"
for o in o1 o2 o3 o4 o5; do
  [ ! -e "$WORK/$o" ] || fail "a rejected run created $o"
done
pass "rejected runs wrote nothing"

# `plan` writes the resolved scenario and says what it could not plan.
expect_exit 0 "plan" -- "$TRAINSIM" plan --out "$WORK/plan"
cmp -s "$WORK/plan/scenario.json" <("$TRAINSIM" defaults) && pass "plan scenario.json" ||
  fail "plan scenario.json differs from defaults"
expect_contains "$WORK/err" "not built yet" "plan says what is missing"
expect_exit 2 "plan without --out" -- "$TRAINSIM" plan
finish
