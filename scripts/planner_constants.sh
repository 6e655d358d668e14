#!/usr/bin/env bash
# Measure the planner's constants and write tables/planner/measured.toml
# (issue 11: the constants are measured by a script, not pasted; the
# planner reads the file at compile time, src/session/plan/measured.rs).
#
# Runs `sim tradeoff --json` on the shipped bogie scene
# (tables/scenes/bogie_straight.toml, its speed, offset and length) with
# the creep law set to Polach and the variants "creep kalker",
# "creep heuristic", "creep fastsim", "creep fastrip" and "contact table" (each the
# reference — table step 0.01 m, online contact, flange always searched,
# RK4 at 0.1 ms — with that one change):
#
#   - on the scene's straight, REPEATS runs per variant: the creep laws'
#     median wall time (the integration) relative to the reference's
#     (Polach), and the contact table's largest lateral error;
#   - on tracks/curve_r300 and on tracks/irregular_300m (the scene with
#     `--set track.centerline/track.irregularities`), one run per variant:
#     the contact table's largest lateral error (`inf` where the table run
#     fails).
#
# Each study is `sim tradeoff --quick` (the reference and its four quick
# variants; the scene's length, given with --set run.distance_m, is kept)
# with the variants above added. The file is written with its provenance
# (this command, the date, the machine) and checked to parse with every
# creep law and track kind.
# Wall times are machine-specific: measure on a quiet machine, then
# rebuild `sim` (the file is compiled in) and check `sim run --plan-only`.
#
# Usage: scripts/planner_constants.sh [--quick] [--repeats N] [--out FILE]
#   (default: 3 repeats, the scene's length, out tables/planner/measured.toml)
#   --quick      a check of the procedure: 50 m, 1 repeat, out
#                target/planner-constants/measured.toml (not representative)
#   SIM=PATH     a sim binary (default: cargo build --release)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCENE="tables/scenes/bogie_straight.toml"
QUICK=0
REPEATS=""
OUT=""
ARGS="$*"
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) QUICK=1 ;;
        --repeats) REPEATS="$2"; shift ;;
        --out) OUT="$2"; shift ;;
        -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
    esac
    shift
done
if [ "$QUICK" = 1 ]; then
    REPEATS="${REPEATS:-1}"
    OUT="${OUT:-$ROOT/target/planner-constants/measured.toml}"
    DISTANCE_SET=(--set run.distance_m=50)
else
    REPEATS="${REPEATS:-3}"
    OUT="${OUT:-$ROOT/tables/planner/measured.toml}"
    DISTANCE_SET=(--set "run.distance_m=$(python3 -c 'import sys, tomllib; print(tomllib.load(open(sys.argv[1], "rb"))["run"]["distance_m"])' "$ROOT/$SCENE")")
fi

cd "$ROOT"
if [ -z "${SIM:-}" ]; then
    cargo build --release --quiet --bin sim || { echo "build failed" >&2; exit 2; }
    SIM="$ROOT/target/release/sim"
fi
PROFILE="$(case "$SIM" in */release/*) echo "release build" ;; */debug/*) echo "dev build" ;; *) echo "build $SIM" ;; esac)"

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
# A cache of its own (tables, contact tables): set-up time is not in the
# measured wall times, but an empty cache keeps the runs independent of
# earlier ones.
export RAILSIM_CACHE_DIR="$WORK/cache"
MACHINE="$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg) at the start; $PROFILE"

# The scene as every study sees it: Polach (the cost reference) and, with
# --quick, the shorter run.
COMMON=(--quick --set 'contact.creep_law="polach"' "${DISTANCE_SET[@]}")
LAWS=(kalker heuristic fastsim fastrip)
TABLE=('--variant' 'contact table:contact.method="table"')

study() { # $1 = name, $2 = repeats, rest = extra arguments
    local name="$1" repeats="$2"; shift 2
    local t0=$SECONDS
    if ! "$SIM" tradeoff "$SCENE" "${COMMON[@]}" --repeats "$repeats" --out "$WORK/$name" --json "$@" \
            >/dev/null 2>"$WORK/$name.log"; then
        cat "$WORK/$name.log" >&2
        echo "sim tradeoff ($name) failed (log above)" >&2
        exit 2
    fi
    echo "$name: $((SECONDS - t0)) s" >&2
}

creep=()
for law in "${LAWS[@]}"; do creep+=(--variant "creep $law:contact.creep_law=\"$law\""); done
study straight "$REPEATS" "${creep[@]}" "${TABLE[@]}"
study curve 1 --set 'track.centerline="../tracks/curve_r300/centerline.csv"' "${TABLE[@]}"
study irregular 1 --set 'track.centerline="../tracks/irregular_300m/centerline.csv"' \
    --set 'track.irregularities="../tracks/irregular_300m/irregularities.csv"' "${TABLE[@]}"

mkdir -p "$(dirname "$OUT")"
python3 - "$WORK" "$SCENE" "$OUT.new" "scripts/planner_constants.sh${ARGS:+ $ARGS}" "$MACHINE" "$REPEATS" "$QUICK" <<'PY'
import json, math, sys, time, tomllib

work, scene_path, out, command, machine, repeats, quick = sys.argv[1:]
with open(scene_path, "rb") as f:
    scene = tomllib.load(f)
offset_m = abs(scene["initial"]["lateral_m"])
if offset_m == 0:
    sys.exit("the scene's initial.lateral_m is 0: the table error is scaled by it")


def report(name):
    with open(f"{work}/{name}/tradeoff.json") as f:
        return json.load(f)


def variant(r, name):
    for v in r["variants"]:
        if v["name"] == name:
            return v
    sys.exit(f"variant '{name}' missing from the study")


straight = report("straight")
speed = straight["speed_m_s"]
distance = straight["distance_m"]
ref = variant(straight, "reference")
if ref["status"] != "ok" or not ref["wall_time_median_s"]:
    sys.exit(f"the reference run failed: {ref['error']}")
laws = [("polach", 1.0, ref["wall_time_median_s"])]
for law in ("kalker", "heuristic", "fastsim", "fastrip"):
    v = variant(straight, f"creep {law}")
    if v["status"] != "ok" or not v["wall_time_median_s"]:
        sys.exit(f"creep {law} failed: {v['error']}")
    laws.append((law, v["wall_time_median_s"] / ref["wall_time_median_s"], v["wall_time_median_s"]))

where = {
    "straight": f"sim tradeoff {scene_path} (bogie, {speed:g} m/s, {distance:g} m)",
    "curve": f"sim tradeoff of the bogie scene on tracks/curve_r300 ({speed:g} m/s, {distance:g} m)",
    "irregular": f"sim tradeoff of the bogie scene on tracks/irregular_300m ({speed:g} m/s, {distance:g} m)",
}
errors = []
for kind in ("straight", "irregular", "curve"):
    r = report(kind)
    if variant(r, "reference")["status"] != "ok":
        sys.exit(f"the reference run on the {kind} track failed: {variant(r, 'reference')['error']}")
    v = variant(r, "contact table")
    if v["errors"] is not None and v["status"] == "ok":
        errors.append((kind, v["errors"]["lateral_max_m"], where[kind]))
    else:
        why = (v["error"] or v["status"]).splitlines()[0][:200]
        errors.append((kind, math.inf, f"{where[kind]}: the table run fails: {why}"))


def q(s):
    return json.dumps(s, ensure_ascii=False)


def num(x):
    return "inf" if math.isinf(x) else f"{x:.4g}"


procedure = (
    f"sim tradeoff --json, medians of {repeats} run(s) on the straight (1 on the curve and the "
    "irregular track), the ratios computed from the unrounded medians"
    + ("; --quick: a check of the procedure, not representative" if quick == "1" else "")
)
lines = [
    "# The planner's measured constants (src/session/plan/measured.rs reads",
    "# this file at compile time): the creep laws' wall time relative to",
    "# Polach's (the creep-law line of the plan) and the contact lookup table's",
    "# lateral error on each kind of track (the contact-method decision).",
    "#",
    "# Written by scripts/planner_constants.sh (see its header): `sim tradeoff",
    "# --json` on the shipped bogie scene on its straight, on tracks/curve_r300",
    "# and on tracks/irregular_300m. Wall times belong to one machine and go",
    "# stale: rerun the script and rebuild `sim`.",
    "",
    "[provenance]",
    f"command = {q(command)}",
    f"date = {q(time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime()))}",
    f"machine = {q(machine)}",
    f"note = {q(procedure)}",
    "",
    "# Wall time of each creep law relative to Polach's (the integration's",
    "# median wall time of the variant over the reference's).",
    "[creep_law_cost]",
    f"study = {q(f'sim tradeoff, bogie at {speed:g} m/s')}",
    'reference = "polach"',
]
for law, rel, wall in laws:
    lines += [
        "",
        "[[creep_law_cost.laws]]",
        f"law = {q(law)}",
        f"relative_wall_time = {rel:.2f}",
        f"wall_time_median_s = {wall:.3f}",
    ]
lines += [
    "",
    "# The contact lookup table's largest error of the leading wheelset's",
    "# lateral displacement against online contact (variant \"contact table\"",
    "# against the reference), per kind of track; `inf` where the table run",
    "# failed. The method decision scales the error by |y0| / initial_offset_m",
    "# when the scene's offset is larger.",
]
for kind, err, source in errors:
    lines += [
        "[[table_contact_error]]",
        f"track = {q(kind)}",
        f"max_lateral_error_m = {num(err)}",
        f"initial_offset_m = {offset_m:g}",
        f"source = {q(source)}",
        "",
    ]
text = "\n".join(lines)
# The planner's checks (measured.rs tests): every law and kind, in order.
parsed = tomllib.loads(text)
assert [l["law"] for l in parsed["creep_law_cost"]["laws"]] == ["polach", "kalker", "heuristic", "fastsim", "fastrip"]
assert sorted(e["track"] for e in parsed["table_contact_error"]) == ["curve", "irregular", "straight"]
with open(out, "w") as f:
    f.write(text)
for law, rel, wall in laws:
    print(f"{law:<10} x{rel:.2f}  ({wall:.3f} s)", file=sys.stderr)
for kind, err, source in errors:
    print(f"{kind:<10} {num(err)} m", file=sys.stderr)
PY
mv "$OUT.new" "$OUT"
echo "wrote $OUT (rebuild sim to use it)" >&2
