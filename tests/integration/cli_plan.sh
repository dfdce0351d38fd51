# `trainsim plan` writes railroad.json, trajectory.csv and design_report.json; the files read
# with independent readers (Python's csv and json); bad routes are reported, bad input exits 2.
source "$(dirname "$0")/lib.sh" "$@"

expect_exit 0 "plan default" -- "$TRAINSIM" plan --out "$WORK/p"
for f in scenario.json railroad.json trajectory.csv design_report.json; do
  [ -s "$WORK/p/$f" ] && pass "$f written" || fail "$f missing"
done
python3 - "$WORK/p" <<'PY' && pass "plan files read back with csv/json" || fail "plan files"
import csv, json, re, sys
d = sys.argv[1]
rows = list(csv.reader(open(d + "/trajectory.csv")))
head, body = rows[0], rows[1:]
assert head[0] == "t_ns", head
unit = re.compile(r".*_(m|m_s|m_s2|m_s3|rad|rad_s|rad_s2|1_m|ns)$")
for c in head:
    assert unit.match(c) or c in ("block_id", "track_id"), c
period = json.load(open(d + "/scenario.json"))["trajectory"]["sample_period_ns"]
t = [int(r[0]) for r in body]
assert t == [k * period for k in range(len(t))], "t_ns is not k * T_S"
col = {c: i for i, c in enumerate(head)}
v = [float(r[col["speed_m_s"]]) for r in body]
lim = [float(r[col["speed_limit_m_s"]]) for r in body]
assert all(a <= b + 1e-9 for a, b in zip(v, lim)), "speed above the limit"
assert v[0] == 0 and v[-1] == 0 and max(v) > 10
report = json.load(open(d + "/design_report.json"))
assert report["violation_count"] == 0, report["violations"][:3]
rail = json.load(open(d + "/railroad.json"))
kinds = [t["kind"] for t in rail["tracks"]]
assert kinds[0] == "main" and "double" in kinds, kinds
types = {b["type"] for b in rail["main_track"]["blocks"]}
assert {"straight", "curve"} <= types, types
for t in rail["tracks"]:
    assert len(t["polyline_m"]) > 10 and all(len(p) == 3 for p in t["polyline_m"])
PY

# A bad waypoint file: the plan is written and the report names the rules at their chainages.
expect_exit 0 "plan bad waypoints" -- "$TRAINSIM" plan "$SRC/tests/data/routes/bad_waypoints.json" \
  --out "$WORK/bad"
python3 - "$WORK/bad/design_report.json" <<'PY' && pass "bad route reported" || fail "bad route report"
import json, sys
r = json.load(open(sys.argv[1]))
rules = {v["rule"] for v in r["violations"]}
assert {"min_radius", "gradient", "cant_deficiency"} <= rules, rules
radius = [v for v in r["violations"] if v["rule"] == "min_radius"][0]
assert radius["value"] == 300 and 1000 < radius["chainage_begin_m"] < 2000, radius
PY

# Bad input: a missing waypoint file names the file and exits 2; nothing is written.
sed 's/bad_waypoints.csv/missing.csv/' "$SRC/tests/data/routes/bad_waypoints.json" >"$WORK/missing.json"
expect_exit 2 "missing waypoint file" -- "$TRAINSIM" plan "$WORK/missing.json" --out "$WORK/m"
expect_contains "$WORK/err" "missing.csv" "message names the missing file"
[ ! -e "$WORK/m/railroad.json" ] && pass "nothing written for bad input" || fail "files written"
printf '{"route": {"source": "waypoints"}}' >"$WORK/nofile.json"
expect_exit 2 "waypoints without a file" -- "$TRAINSIM" validate "$WORK/nofile.json"
expect_contains "$WORK/err" "route.waypoints_file" "validator names route.waypoints_file"
# A scene window that is empty, past the route's end (6000 m) or without --scene is a usage
# error naming the option; nothing is written.
expect_exit 2 "scene window ending before it starts" -- \
  "$TRAINSIM" plan --out "$WORK/w1" --scene --scene-from 500 --scene-to 100
expect_contains "$WORK/err" "--scene-to" "message names --scene-to"
expect_exit 2 "scene window past the route's end" -- \
  "$TRAINSIM" plan --out "$WORK/w2" --scene --scene-from 6000 --scene-to 7000
expect_contains "$WORK/err" "--scene-from: 6000 m lies at or beyond the route's end" "message names --scene-from"
expect_exit 2 "--scene-from without --scene" -- "$TRAINSIM" plan --out "$WORK/w3" --scene-from 5
[ ! -e "$WORK/w1" ] && [ ! -e "$WORK/w2" ] && [ ! -e "$WORK/w3" ] &&
  pass "nothing written for a bad scene window" || fail "files written for a bad scene window"
finish
