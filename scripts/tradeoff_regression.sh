#!/usr/bin/env bash
# Regression guard for speed and accuracy (issue 6, item 4).
#
# Runs `sim tradeoff --quick` on the shipped bogie scene at 84 m/s (release
# build, 5 repeats per variant) and compares every variant with the bounds
# in scripts/tradeoff_bounds.csv:
#
#   - an error (max lateral displacement of the leading wheelset, hunting
#     frequency, peak lateral force |Y|, peak normal force) above its bound,
#   - a median wall time more than 50 % above its bound,
#   - a variant that failed or is missing
#
# each fail the check (exit 1). Exit 2: the study itself could not run.
#
# The bounds were written from this project's 2-core VM with
# `scripts/tradeoff_regression.sh --write-bounds`: errors 2× the measured
# value (at least 1 nm, 1 µHz, 1 N, so that an exact 0 has room for
# round-off), wall time the measured median (the 50 % margin is applied by
# the check). Wall times are machine-specific: on another machine write your
# own bounds first (on a quiet machine), then run the check after changes.
#
# Usage: scripts/tradeoff_regression.sh [--write-bounds] [--out DIR]
#   TRADEOFF_BOUNDS=FILE  another bounds file
#   SIM=PATH              a sim binary (default: cargo build --release)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BOUNDS="${TRADEOFF_BOUNDS:-$ROOT/scripts/tradeoff_bounds.csv}"
OUT="$ROOT/target/tradeoff-regression"
WRITE=0
while [ $# -gt 0 ]; do
    case "$1" in
        --write-bounds) WRITE=1 ;;
        --out) OUT="$2"; shift ;;
        -h|--help) sed -n '2,27p' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
    esac
    shift
done

if [ -z "${SIM:-}" ]; then
    (cd "$ROOT" && cargo build --release --quiet --bin sim) || { echo "build failed" >&2; exit 2; }
    SIM="$ROOT/target/release/sim"
fi

mkdir -p "$OUT"
rm -rf "$OUT/study"
if ! RAILSIM_CACHE_DIR="$OUT/cache" "$SIM" tradeoff "$ROOT/tables/scenes/bogie_straight.toml" \
        --quick --repeats 5 --set initial.speed_m_s=84 --out "$OUT/study" >"$OUT/study.log" 2>&1; then
    cat "$OUT/study.log" >&2
    echo "sim tradeoff failed (log above)" >&2
    exit 2
fi
CSV="$OUT/study/tradeoff.csv"

# CSV with quoted fields (mawk has no FPAT): split by hand.
AWK_CSV='
function csvsplit(line, f,    n, i, c, field, inq) {
    n = 0; field = ""; inq = 0
    for (i = 1; i <= length(line); i++) {
        c = substr(line, i, 1)
        if (inq) {
            if (c == "\"") {
                if (substr(line, i + 1, 1) == "\"") { field = field "\""; i++ } else inq = 0
            } else field = field c
        } else if (c == "\"") inq = 1
        else if (c == ",") { f[++n] = field; field = "" }
        else field = field c
    }
    f[++n] = field
    return n
}
function max(a, b) { return a > b ? a : b }
'

if [ "$WRITE" = 1 ]; then
    awk "$AWK_CSV"'
    NR == 1 { n = csvsplit($0, h); for (i = 1; i <= n; i++) col[h[i]] = i
              print "# Bounds of scripts/tradeoff_regression.sh, written by --write-bounds from sim tradeoff --quick --repeats 5"
              print "# on the bogie at 84 m/s: errors 2x the measured (floors 1e-9 m, 1e-6 Hz, 1 N); wall time = the measured median"
              print "# (the check allows +50 %). Machine-specific wall times: rewrite on another machine."
              print "name,lateral_max_error_bound_m,frequency_error_bound_hz,peak_lateral_force_error_bound_n,peak_normal_force_error_bound_n,wall_time_bound_s"
              next }
    {
        csvsplit($0, f)
        if (f[col["status"]] != "ok") { print "variant " f[col["name"]] " did not run: " f[col["error"]] > "/dev/stderr"; bad = 1; next }
        printf "%s,%.3g,%.3g,%.3g,%.3g,%.4g\n", f[col["name"]],
            max(2 * f[col["lateral_max_error_m"]], 1e-9),
            max(2 * f[col["frequency_error_hz"]], 1e-6),
            max(2 * f[col["peak_lateral_force_error_n"]], 1),
            max(2 * f[col["peak_normal_force_error_n"]], 1),
            f[col["wall_time_median_s"]]
    }
    END { exit bad }' "$CSV" >"$BOUNDS.new"
    mv "$BOUNDS.new" "$BOUNDS"
    echo "wrote $BOUNDS"
    cat "$BOUNDS"
    exit 0
fi

[ -f "$BOUNDS" ] || { echo "no bounds file $BOUNDS (write it with --write-bounds)" >&2; exit 2; }

awk "$AWK_CSV"'
FNR == 1 { file++ }
/^#/ { next }
file == 1 && /^name,/ { next }
file == 1 && NF {
    csvsplit($0, f)
    name = f[1]; names[++nb] = name
    b_lat[name] = f[2]; b_freq[name] = f[3]; b_y[name] = f[4]; b_n[name] = f[5]; b_wall[name] = f[6]
    next
}
file == 2 && FNR == 1 { n = csvsplit($0, h); for (i = 1; i <= n; i++) col[h[i]] = i; next }
file == 2 {
    csvsplit($0, f)
    name = f[col["name"]]; seen[name] = 1
    status[name] = f[col["status"]]; err[name] = f[col["error"]]
    lat[name] = f[col["lateral_max_error_m"]]; freq[name] = f[col["frequency_error_hz"]]
    y[name] = f[col["peak_lateral_force_error_n"]]; nn[name] = f[col["peak_normal_force_error_n"]]
    wall[name] = f[col["wall_time_median_s"]]
}
function check(name, what, value, bound) {
    if (value == "" || value + 0 > bound + 0) {
        printf "FAIL %-16s %-22s %12s > limit %s\n", name, what, (value == "" ? "missing" : value), bound
        failed = 1
    }
}
END {
    printf "%-16s %12s %12s %12s %12s %10s %10s\n", "variant", "lat max [m]", "df [Hz]", "dY [N]", "dN [N]", "wall [s]", "limit [s]"
    for (i = 1; i <= nb; i++) {
        name = names[i]
        if (!(name in seen)) { printf "FAIL %-16s missing from the study\n", name; failed = 1; continue }
        if (status[name] != "ok") { printf "FAIL %-16s %s: %s\n", name, status[name], err[name]; failed = 1; continue }
        printf "%-16s %12.3g %12.3g %12.3g %12.3g %10.4f %10.4f\n", name, lat[name], freq[name], y[name], nn[name], wall[name], 1.5 * b_wall[name]
        check(name, "lateral max error", lat[name], b_lat[name])
        check(name, "frequency error", freq[name], b_freq[name])
        check(name, "peak Y error", y[name], b_y[name])
        check(name, "peak N error", nn[name], b_n[name])
        check(name, "wall time", wall[name], 1.5 * b_wall[name])
    }
    if (failed) { print "tradeoff regression: FAILED (study in '"$OUT"'/study)"; exit 1 }
    print "tradeoff regression: ok"
}' "$BOUNDS" "$CSV"
