#!/usr/bin/env bash
# What modelling only what the scene requires saves (issue 7, item 7):
# each case is run with everything modelled (`sim run --model-everything`)
# and with the planner choosing every item it may (`--plan --set
# 'plan.choose=["all"]'`), interleaved, REPEATS times each; prints the
# median wall times (integration, setup, planning, from `sim run --json`),
# what the planner chose, and the largest lateral difference of any
# wheelset between the two (`sim compare`). The table of docs/guide/speed-accuracy-tradeoff.md comes from
# this script.
#
#   scripts/planner_saving.sh [REPEATS]        (default 5; release build)
set -euo pipefail
cd "$(dirname "$0")/.."
repeats="${1:-5}"
cargo build --release --quiet --bin sim
sim=target/release/sim
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# A cache of its own (tables, flangeway clearances), filled by each case's
# warm-up runs below so that no timed run pays for building them.
export RAILSIM_CACHE_DIR="$work/cache"

curve='track.centerline="../tracks/curve_r300/centerline.csv"'
irr_c='track.centerline="../tracks/irregular_300m/centerline.csv"'
irr_i='track.irregularities="../tracks/irregular_300m/irregularities.csv"'
# name | scene | extra --set overrides (space separated)
cases=(
  "wheelset_straight|tables/scenes/wheelset_straight.toml|"
  "bogie_straight|tables/scenes/bogie_straight.toml|"
  "bogie_straight_tol_1e-5|tables/scenes/bogie_straight.toml|run.lateral_tolerance_m=1e-5"
  "cooperrider_straight|tables/scenes/cooperrider_straight.toml|"
  "bogie_curve_r300|tables/scenes/bogie_straight.toml|$curve"
  "bogie_irregular_300m|tables/scenes/bogie_straight.toml|$irr_c $irr_i"
)

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
field() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }

printf '%s\n' "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-26s %10s %10s %8s %8s  %-40s %s\n' case everything required saving planning "chose (flange, method, step, range)" "max lateral difference"
for c in "${cases[@]}"; do
  IFS='|' read -r name scene extra <<<"$c"
  sets=()
  for s in $extra; do sets+=(--set "$s"); done
  plan=(--plan --set 'plan.choose=["all"]')
  run() { # $1 = tag, rest = flags
    local tag="$1"; shift
    "$sim" run "$scene" "${sets[@]}" "$@" -o "$work/$name-$tag.h5" --no-plots --quiet --json 2>/dev/null
  }
  # warm the caches
  run everything --model-everything >/dev/null
  run required "${plan[@]}" >/dev/null
  : >"$work/e" ; : >"$work/r" ; : >"$work/p"
  for _ in $(seq "$repeats"); do
    run everything --model-everything | field "d['wall_time_s'] + d.get('setup_time_s', 0)" >>"$work/e"
    out="$(run required "${plan[@]}")"
    echo "$out" | field "d['wall_time_s'] + d.get('setup_time_s', 0) + d['plan']['planning_time_s']" >>"$work/r"
    echo "$out" | field "d['plan']['planning_time_s']" >>"$work/p"
  done
  chose="$(echo "$out" | field "', '.join({i['item']: i['value'] for i in d['plan']['decisions']}.get(k, '–') for k in ('flange_search','contact_method','table_step','track_range'))")"
  e="$(median <"$work/e")"; r="$(median <"$work/r")"; p="$(median <"$work/p")"
  diff="$("$sim" compare "$work/$name-everything.h5" "$work/$name-required.h5" --out "$work/$name.png" \
    | awk '/lateral difference/ {for (i=1;i<=NF;i++) if ($i=="max") print $(i+1)}' | sort -g | tail -1)"
  printf '%-26s %9.3fs %9.3fs %7.1f%% %7.3fs  %-40s %s µm\n' "$name" "$e" "$r" \
    "$(python3 -c "print(100*(1-$r/$e))")" "$p" "$chose" "$diff"
done
