# Every broken scenario in tests/data/invalid/ exits 2 with exactly the expected message.
source "$(dirname "$0")/lib.sh" "$@"
cd "$SRC/tests/data/invalid"
count=0
for fixture in *.json; do
  expected="${fixture%.json}.expected"
  [ -f "$expected" ] || { fail "$fixture has no $expected"; continue; }
  expect_exit 2 "validate $fixture" -- "$TRAINSIM" validate "$fixture"
  if diff -u "$expected" "$WORK/err" >"$WORK/diff"; then pass "$fixture message"; else
    fail "$fixture message differs:"; cat "$WORK/diff" >&2; fi
  count=$((count + 1))
done
[ "$count" -ge 5 ] || fail "only $count fixtures"
# The same problems come out when the scenario arrives on standard input.
expect_exit 2 "validate - (stdin)" -- bash -c "\"$TRAINSIM\" validate - < wrong_type.json"
expect_contains "$WORK/err" "<stdin>: dataset.frame_period_ns: expected an integer" "stdin source named"
finish
