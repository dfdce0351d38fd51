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

# `plan` writes the resolved scenario; without --scene it builds no terrain or objects.
expect_exit 0 "plan" -- "$TRAINSIM" plan --out "$WORK/plan"
cmp -s "$WORK/plan/scenario.json" <("$TRAINSIM" defaults) && pass "plan scenario.json" ||
  fail "plan scenario.json differs from defaults"
[ ! -e "$WORK/plan/scene" ] && pass "plan without --scene writes no scene" || fail "plan wrote a scene"
# `plan --scene`: terrain tiles as 16-bit PNG + JSON, objects.csv, and scene.vtm with its data.
expect_exit 0 "plan --scene" -- "$TRAINSIM" plan --out "$WORK/scene" --scene --scene-to 300
python3 - "$WORK/scene/scene" <<'PY' && pass "scene files" || fail "scene files"
import csv, json, os, struct, sys
root = sys.argv[1]
pngs = [f for f in os.listdir(os.path.join(root, "terrain")) if f.endswith(".png")]
assert len(pngs) >= 4, pngs
for f in pngs:
    head = open(os.path.join(root, "terrain", f), "rb").read(26)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f
    width, height, depth, colour = struct.unpack(">IIBB", head[16:26])
    meta = json.load(open(os.path.join(root, "terrain", f[:-4] + ".json")))
    assert width == height == meta["size"] and depth == 16 and colour == 0, (f, width, depth, colour)
rows = list(csv.DictReader(open(os.path.join(root, "objects.csv"))))
assert len(rows) > 100 and {r["kind"] for r in rows} >= {"trees", "bushes"}, len(rows)
assert len({r["instance"] for r in rows}) == len(rows)
vtis = [f for f in os.listdir(os.path.join(root, "terrain")) if f.endswith(".vti")]
assert vtis and all(open(os.path.join(root, "terrain", f), "rb").read(200).find(b"ImageData") > 0 for f in vtis), vtis
vtm = open(os.path.join(root, "scene.vtm")).read()
assert "vtkMultiBlockDataSet" in vtm
for name in vtm.split('file="')[1:]:
    assert os.path.getsize(os.path.join(root, name.split('"')[0])) > 0
PY
[ -z "$(find "$WORK/scene" -name '.*partial*')" ] && pass "no staging left" || fail "staging folder left"
expect_exit 2 "plan without --out" -- "$TRAINSIM" plan
finish
