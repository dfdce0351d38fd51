# The dataset writer's folder rules as seen from the command line.
source "$(dirname "$0")/lib.sh" "$@"

# The rules do not depend on what is simulated: a short route with an IMU and a GNSS receiver
# keeps each run to a second (the default scenario's own run is generate_default_scenario's).
cat >"$WORK/small.json" <<'JSON'
{"route": {"generator": {"length_m": 1500}},
 "sensors": {"imus": [{}], "gnss_receivers": [{}]}}
JSON
gen=("$TRAINSIM" generate "$WORK/small.json" --progress none)

mkdir -p "$WORK/foreign"
echo "keep me" > "$WORK/foreign/notes.txt"
expect_exit 2 "refuse a foreign non-empty folder" -- "${gen[@]}" --out "$WORK/foreign"
expect_contains "$WORK/err" "not empty and was not written by trainsim" "refusal explains itself"
[ ! -e "$WORK/foreign/scenario.json" ] && pass "nothing written when refused" || fail "wrote into refused folder"
expect_exit 0 "--force into a foreign folder" -- "${gen[@]}" --out "$WORK/foreign" --force
[ "$(cat "$WORK/foreign/notes.txt")" = "keep me" ] && pass "--force keeps foreign files" ||
  fail "--force removed a foreign file"

expect_exit 2 "refuse to overwrite a dataset" -- "${gen[@]}" --out "$WORK/foreign"
expect_contains "$WORK/err" "already holds a dataset" "overwrite refusal explains itself"
expect_exit 0 "--resume on a complete dataset" -- "${gen[@]}" --out "$WORK/foreign" --resume
expect_contains "$WORK/err" "nothing to do" "resume of a complete dataset does nothing"
expect_exit 2 "--resume with another seed" -- "${gen[@]}" --out "$WORK/foreign" --resume --seed 9
expect_exit 2 "--force with --resume" -- "${gen[@]}" --out "$WORK/foreign" --resume --force
echo "x" > "$WORK/file"
expect_exit 2 "--out is a file" -- "${gen[@]}" --out "$WORK/file"
finish
