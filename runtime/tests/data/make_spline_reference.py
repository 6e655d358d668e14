#!/usr/bin/env python3
"""Generate SciPy reference values for `runtime::spline::PiecewiseCubic`.

Writes ``spline_reference.json`` next to this script; it is read by the
integration test ``runtime/tests/spline_scipy.rs``. Run from anywhere:

    python3 runtime/tests/data/make_spline_reference.py

Schemes and the SciPy objects they are compared with:

    cubic          CubicSpline(x, y, bc_type="not-a-knot")
    cubic-natural  CubicSpline(x, y, bc_type="natural")
    akima          Akima1DInterpolator(x, y, method="akima", extrapolate=True)
    pchip          PchipInterpolator(x, y)

(CubicSpline and PchipInterpolator extrapolate by default; Akima1DInterpolator
does not, so extrapolation is requested explicitly.) For each data set and
scheme the value, first and second derivative are evaluated at

* every knot (SciPy's PPoly uses the piece to the right of an interior knot,
  and the last piece at the last knot),
* the largest float below every interior knot (``nextafter(x_k, -inf)``), so
  the left piece is used there -- this catches off-by-one piece lookups,
  including on the O(1) uniform-knot path,
* several points strictly inside every interval,
* two points beyond each end of the range (extrapolation of the end pieces).

Data sets (all deterministic; the one pseudo-random set uses
``numpy.random.default_rng(SEED)`` and its values are written to the JSON):

* smooth_nonuniform     sin/exp mix on 12 irregular knots
* uniform_linspace      smooth data on ``linspace`` knots (uniform lookup path)
* uniform_seeded        seeded normal noise on exactly uniform knots
* clustered_knots       very uneven spacing (ratios ~100), short end intervals
                        (stresses the tridiagonal solve and not-a-knot rows)
* step                  a unit step on uniform knots (flat runs either side)
* corner_flat_runs      corners, flat runs and slope sign changes: Akima's
                        weights vanish (f1 + f2 == 0) at several knots, PCHIP
                        gets zero and sign-changing secants
* akima_near_degenerate flat run with a 1e-13 wiggle before a ramp: Akima's
                        f1 + f2 is tiny but non-zero, below SciPy's 1e-9
                        cut-off, so the fill value is used
* pchip_end_cases       PCHIP end slopes hitting both limiter branches
                        (d -> 3*m0 on the left, d -> 0 on the right)
* small_n2 .. small_n5  n = 2, 3, 4, 5 points (n = 3 is the not-a-knot
                        parabola special case, n = 2 the straight line)
* track_wide            x = chainage in metres up to 3000, y ~ 1.2e3 m
* track_offset          large absolute coordinates (x ~ 1.5e5, y ~ 5.4e6)

Number format: every float is written as a JSON *string* holding Python's
``repr`` (the shortest decimal that round-trips). Rust's ``str::parse::<f64>``
is correctly rounded, whereas serde_json's default number parser may be off
by one ulp -- enough to move a ``nextafter`` evaluation point onto a knot.
"""

import json
import math
import platform
from pathlib import Path

import numpy as np
import scipy
from scipy.interpolate import Akima1DInterpolator, CubicSpline, PchipInterpolator

SEED = 20240611
OUT = Path(__file__).resolve().parent / "spline_reference.json"

# Fractions of each interval at which interior points are evaluated.
INSIDE = (0.1, 0.37, 0.5, 0.9)
# Extrapolation distances, as fractions of the end interval.
OUTSIDE = (0.05, 0.5)

SCHEMES = {
    "cubic": lambda x, y: CubicSpline(x, y, bc_type="not-a-knot"),
    "cubic-natural": lambda x, y: CubicSpline(x, y, bc_type="natural"),
    "akima": lambda x, y: Akima1DInterpolator(x, y, method="akima", extrapolate=True),
    "pchip": lambda x, y: PchipInterpolator(x, y),
}


def data_sets():
    """(name, description, x, y) of every data set."""
    sets = []

    x = np.array([0.0, 0.3, 0.7, 1.4, 1.8, 2.9, 3.1, 4.2, 5.0, 5.3, 6.6, 7.5])
    sets.append(("smooth_nonuniform", "sin(x) + 0.5 exp(0.3 x) on 12 irregular knots",
                 x, np.sin(x) + 0.5 * np.exp(0.3 * x)))

    x = np.linspace(-2.0, 3.0, 21)
    sets.append(("uniform_linspace", "cos(1.3 x) + 0.1 x^2 on linspace(-2, 3, 21)",
                 x, np.cos(1.3 * x) + 0.1 * x * x))

    rng = np.random.default_rng(SEED)
    x = 0.25 * np.arange(16.0)
    sets.append(("uniform_seeded",
                 f"default_rng({SEED}).normal(size=16) on x = 0.25 k",
                 x, rng.normal(size=16)))

    x = np.array([0.0, 0.04, 1.0, 1.08, 1.5, 3.0, 3.05, 3.3, 6.0, 9.85, 10.0])
    sets.append(("clustered_knots",
                 "tanh(x - 3) + 0.1 x on knots with spacing ratios up to ~100",
                 x, np.tanh(x - 3.0) + 0.1 * x))

    x = np.arange(10.0)
    y = np.array([0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    sets.append(("step", "unit step between x = 3 and 4 on uniform knots", x, y))

    x = np.array([0.0, 1.0, 2.0, 3.0, 4.5, 5.0, 6.0, 7.0, 8.0, 9.5, 10.0, 11.0])
    y = np.array([0.0, 0.0, 0.0, 1.0, 2.5, 3.0, 3.0, 3.0, 1.0, -2.0, -2.0, 1.0])
    sets.append(("corner_flat_runs",
                 "flat runs, corners and sign changes (Akima f1 + f2 = 0 at x = 2, 5, 7)",
                 x, y))

    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    y = np.array([0.0, 1e-13, 0.0, 1.0, 2.0, 3.0, 4.0])
    sets.append(("akima_near_degenerate",
                 "flat run with a 1e-13 wiggle, then a ramp (Akima f1 + f2 below the cut-off)",
                 x, y))

    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    y = np.array([0.0, 1.0, -4.0, -3.0, 2.0, 3.0])
    sets.append(("pchip_end_cases",
                 "secants 1, -5, 1, 5, 1: PCHIP end slope 3*m0 on the left, 0 on the right",
                 x, y))

    sets.append(("small_n2", "two points", np.array([0.5, 2.0]), np.array([1.0, -0.5])))
    sets.append(("small_n3", "three points (not-a-knot parabola)",
                 np.array([-1.0, 0.2, 1.5]), np.array([2.0, -0.3, 0.7])))
    sets.append(("small_n4", "four points",
                 np.array([0.0, 0.4, 1.5, 2.0]), np.array([1.0, 1.8, 0.2, 0.9])))
    sets.append(("small_n5", "five points",
                 np.array([0.0, 0.7, 1.0, 2.2, 3.0]), np.array([0.0, 0.5, 0.4, -0.6, 0.3])))

    x = np.array([0.0, 150.0, 420.0, 600.0, 875.5, 1200.0, 1380.0, 1710.25, 2050.0,
                  2300.0, 2640.0, 3000.0])
    y = 1.2e3 + 40.0 * np.sin(x / 350.0) + 0.002 * x
    sets.append(("track_wide", "chainage in m up to 3000, y ~ 1.2e3 m", x, y))

    x = 152_000.0 + np.array([0.0, 250.0, 500.0, 750.0, 1000.0, 1250.0, 1500.0,
                              1750.0, 2000.0, 2250.0, 2500.0, 2750.0, 3000.0])
    y = 5_431_000.0 + 0.8 * (x - 152_000.0) + 25.0 * np.cos((x - 152_000.0) / 500.0)
    sets.append(("track_offset", "large absolute coordinates, uniform 250 m knots", x, y))

    return sets


def eval_points(x):
    pts = list(x)
    pts += [np.nextafter(xk, -np.inf) for xk in x[1:-1]]
    for a, b in zip(x[:-1], x[1:]):
        pts += [a + f * (b - a) for f in INSIDE]
    h0, h1 = x[1] - x[0], x[-1] - x[-2]
    pts += [x[0] - f * h0 for f in OUTSIDE]
    pts += [x[-1] + f * h1 for f in OUTSIDE]
    return np.array(sorted(set(float(p) for p in pts)))


def fmt(values):
    out = []
    for v in values:
        v = float(v)
        assert math.isfinite(v), v
        out.append(repr(v))
    return out


def main():
    cases = []
    for name, description, x, y in data_sets():
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        ex = eval_points(x)
        for scheme, make in SCHEMES.items():
            s = make(x, y)
            cases.append({
                "name": name,
                "description": description,
                "scheme": scheme,
                "x": fmt(x),
                "y": fmt(y),
                "eval_x": fmt(ex),
                "value": fmt(s(ex)),
                "d1": fmt(s(ex, 1)),
                "d2": fmt(s(ex, 2)),
            })
    doc = {
        "generator": "runtime/tests/data/make_spline_reference.py",
        "scipy_version": scipy.__version__,
        "numpy_version": np.__version__,
        "python_version": platform.python_version(),
        "seed": SEED,
        "number_format": "floats are strings holding Python repr (shortest round-trip decimal)",
        "schemes": {
            "cubic": 'CubicSpline(x, y, bc_type="not-a-knot")',
            "cubic-natural": 'CubicSpline(x, y, bc_type="natural")',
            "akima": 'Akima1DInterpolator(x, y, method="akima", extrapolate=True)',
            "pchip": "PchipInterpolator(x, y)",
        },
        "cases": cases,
    }
    # One case per line keeps the file compact and its diffs readable.
    compact = {"separators": (",", ":")}
    header = json.dumps({k: v for k, v in doc.items() if k != "cases"}, indent=1)
    lines = [json.dumps(c, **compact) for c in cases]
    with open(OUT, "w", encoding="utf-8") as f:
        f.write(header[:-2] + ',\n "cases": [\n' + ",\n".join(lines) + "\n ]\n}\n")
    json.loads(OUT.read_text(encoding="utf-8"))  # well-formed
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes, {len(cases)} cases)")


if __name__ == "__main__":
    main()
