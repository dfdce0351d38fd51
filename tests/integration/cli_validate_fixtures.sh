# Every broken scenario in tests/data/invalid/ (and the waypoint files they name) is refused the
# same way by validate, plan and generate: exit 2 and exactly the expected message, one line per
# problem, with no output folder left and nothing written anywhere else.
source "$(dirname "$0")/lib.sh" "$@"
cp -r "$SRC/tests/data/invalid" "$WORK/fixtures"
cd "$WORK/fixtures"
# Made here rather than checked in: 100 000 nested arrays (the parser must not recurse on them).
python3 -c "print('{\"seed\": ' + '[' * 100000 + ']' * 100000 + '}')" > deep_nesting.json
echo "deep_nesting.json:1:74: nesting deeper than 64 levels" > deep_nesting.expected
snapshot() { find . -printf '%p %s\n' | sort; }
snapshot > "$WORK/before"
count=0
for fixture in *.json; do
  expected="${fixture%.json}.expected"
  [ -f "$expected" ] || { fail "$fixture has no $expected"; continue; }
  expect_exit 2 "validate $fixture" -- "$TRAINSIM" validate "$fixture"
  if diff -u "$expected" "$WORK/err" >"$WORK/diff"; then pass "$fixture message"; else
    fail "$fixture message differs:"; cat "$WORK/diff" >&2; fi
  sed 's/^/trainsim: /' "$expected" > "$WORK/expected_run"
  for command in plan generate; do
    expect_exit 2 "$command $fixture" -- "$TRAINSIM" "$command" "$fixture" --out "$WORK/dataset"
    if diff -u "$WORK/expected_run" <(grep -v '^\[info\]' "$WORK/err") >"$WORK/diff"; then
      pass "$command $fixture message"; else
      fail "$command $fixture message differs:"; cat "$WORK/diff" >&2; fi
    [ ! -e "$WORK/dataset" ] && pass "$command $fixture left no folder" ||
      fail "$command $fixture left $WORK/dataset"
  done
  count=$((count + 1))
done
[ "$count" -ge 25 ] || fail "only $count fixtures"
snapshot > "$WORK/after"
diff -u "$WORK/before" "$WORK/after" >"$WORK/diff" && pass "nothing written beside the fixtures" ||
  { fail "files appeared beside the fixtures:"; cat "$WORK/diff" >&2; }
# Every message is one line, and no line echoes a long value.
long=$(cat ./*.expected | awk 'length > 300' | wc -l)
[ "$long" -eq 0 ] && pass "no message line longer than 300 characters" || fail "$long long lines"
# The same problems come out when the scenario arrives on standard input.
expect_exit 2 "validate - (stdin)" -- bash -c "\"$TRAINSIM\" validate - < wrong_type.json"
expect_contains "$WORK/err" "<stdin>: dataset.frame_period_ns: expected an integer" "stdin source named"
finish
