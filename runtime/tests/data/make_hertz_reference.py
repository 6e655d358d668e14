#!/usr/bin/env python3
"""Generate SciPy (and mpmath) reference values for `runtime::elliptic` and
`runtime::hertz` (docs/reference/07-contact-forces.md §7.1).

Writes ``hertz_reference.json`` next to this script; it is read by the
integration test ``runtime/tests/hertz_reference.rs``. Run from anywhere:

    python3 runtime/tests/data/make_hertz_reference.py

Needs numpy, scipy and mpmath (the latter for the 40-digit second reference).

Elliptic integrals (parameter convention m = k^2, as scipy.special):

* ``elliptic``: K(m) = ``scipy.special.ellipk(m)``, E(m) = ``ellipe(m)`` for
  m in [0, 0.999999] (linear and logarithmic grids, m -> 0 and m -> 1) and a
  few m < 0; with the 40-digit mpmath values ``mp.ellipk``/``mp.ellipe`` of
  the same binary m.
* ``elliptic_complementary``: K(1 - mc) = ``scipy.special.ellipkm1(mc)`` for
  mc down to 1e-300, and mpmath K, E of the exact 1 - mc (at 380 digits).

Hertz contact (docs/reference/07-contact-forces.md §7.1), for every case (A, B) in 1/m, N = 10 kN,
E = 210 GPa, nu = 0.3:

    theta = arccos(|B - A| / (A + B))   (SciPy: as 2 arctan(sqrt(min/max)))
    e:  max(A,B)/min(A,B) = [E(e)/(1-e^2) - K(e)] / [K(e) - E(e)]
    m = (2E(e)/(pi(1-e^2)))^(1/3),  n = m sqrt(1-e^2),  r = 2K(e)/(pi m)
    major = m c, minor = n c, c = [3N(1-nu^2)/(2E(A+B))]^(1/3)
        (major along the smaller curvature: A < B -> a, rolling, is major)
    delta = r [(1.5(1-nu^2)/E)^2 (A+B) N^2]^(1/3)
    K_H = 2E / (3(1-nu^2) r^1.5 sqrt(A+B))

SciPy solution ("scipy"): ``scipy.optimize.brentq`` with xtol=1e-300,
rtol=4*eps on the ratio equation, written in the variable that is known
accurately in each regime --
  ratio < 2:  in m = e^2 with K = ellipk(m), E = ellipe(m);
  ratio >= 2: in mc = 1 - e^2 with K = ellipkm1(mc), E = ellipe(1 - mc)
(the naive ratio formula subtracts K - E, so the nearly circular cases are
the least accurate ones of this reference: ~1e-12 at ratio 1.001).
The circle A = B is e = 0, m = n = r = 1 exactly.

mpmath solution ("mpmath"): 40 significant digits, the same equation in
u = -ln(1 - e^2) (``mp.findroot``), from the exact binary A and B. The header
records how far the SciPy values are from these.

Cases (``hertz``): curvature ratios A/B from 1e-3 to 1e3 (including 1) at
three curvature scales; theta from 1 to 89.9 degrees (B = 1.087 1/m, i.e. a
0.46 m wheel radius, A from theta, and swapped); and an ``extended`` set of
ratios up to 1e12 (runtime::hertz::MAX_CURVATURE_RATIO).

Number format: every float is a JSON *string* holding Python's ``repr`` (the
shortest decimal that round-trips); Rust's ``str::parse::<f64>`` is correctly
rounded, serde_json's default number parser is not guaranteed to be.
"""

import json
import math
import platform
from pathlib import Path

import mpmath as mp
import numpy as np
import scipy
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, ellipkm1

OUT = Path(__file__).resolve().parent / "hertz_reference.json"
DPS = 40
mp.mp.dps = DPS

YOUNG_PA = 210e9
POISSON = 0.3
NORMAL_FORCE_N = 10e3
EPS = np.finfo(float).eps

QUANTITIES = [
    "theta_rad", "e", "e_sq", "one_minus_e_sq", "k_first", "e_second",
    "m_coef", "n_coef", "r_coef", "a_rolling_m", "b_lateral_m", "approach_m",
    "stiffness_n_m15",
]


def fmt(v):
    v = float(v)
    assert math.isfinite(v), v
    return repr(v)


# ---------------------------------------------------------------- elliptic

def elliptic_cases():
    ms = [0.0, 1e-300, 1e-100, 1e-20, 1e-12, 1e-8, 1e-5]
    ms += list(np.linspace(0.0, 0.99, 100)[1:])
    ms += list(np.logspace(-16, -1, 16))
    ms += list(1.0 - np.logspace(-6, -1, 21))          # up to 0.999999
    ms += [0.5, 0.75, 0.9, 0.999, 0.99999, 0.999999]
    ms += [-1e-8, -0.5, -1.0, -10.0, -1e3]
    ms = sorted(set(float(m) for m in ms))
    out = []
    for m in ms:
        mm = mp.mpf(m)
        out.append({
            "m": fmt(m),
            "k_scipy": fmt(ellipk(m)),
            "e_scipy": fmt(ellipe(m)),
            "k_mpmath": fmt(mp.ellipk(mm)),
            "e_mpmath": fmt(mp.ellipe(mm)),
        })
    return out


def elliptic_complementary_cases():
    mcs = [1e-300, 1e-200, 1e-100, 1e-50, 1e-30, 1e-20, 1e-16, 1e-14, 1e-12,
           1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 0.01, 0.1, 0.3, 0.5, 0.7, 1.0]
    out = []
    for mc in mcs:
        # Enough digits to hold the exact complement of the binary mc.
        with mp.workdps(DPS + 340):
            m = 1 - mp.mpf(mc)
            k_mp, e_mp = mp.ellipk(m), mp.ellipe(m)
        out.append({
            "mc": fmt(mc),
            "k_scipy": fmt(ellipkm1(mc)),
            "k_mpmath": fmt(k_mp),
            "e_mpmath": fmt(e_mp),
        })
    return out


# ---------------------------------------------------------------- Hertz

class Ops:
    """The arithmetic of one solution: floats (SciPy) or 40-digit mpf."""

    def __init__(self, const, cbrt, sqrt, pi):
        self.const, self.cbrt, self.sqrt, self.pi = const, cbrt, sqrt, pi


FLOAT_OPS = Ops(float, np.cbrt, math.sqrt, math.pi)
MP_OPS = Ops(mp.mpf, mp.cbrt, mp.sqrt, mp.pi)


def derived(a_curv, b_curv, e_sq, mc, k, e_int, ops, theta):
    """docs/reference/07-contact-forces.md §7.1 quantities from the solved eccentricity."""
    young, nu, force = ops.const(YOUNG_PA), ops.const(POISSON), ops.const(NORMAL_FORCE_N)
    s = a_curv + b_curv
    m_coef = ops.cbrt(2 * e_int / (ops.pi * mc))
    n_coef = m_coef * ops.sqrt(mc)
    r_coef = 2 * k / (ops.pi * m_coef)
    compl = (1 - nu ** 2) / young
    c = ops.cbrt(3 * force * compl / (2 * s))
    major, minor = m_coef * c, n_coef * c
    if a_curv <= b_curv:
        a_roll, b_lat = major, minor
    else:
        a_roll, b_lat = minor, major
    approach = r_coef * ops.cbrt((ops.const(1.5) * compl) ** 2 * s * force ** 2)
    stiffness = 2 / (3 * compl * r_coef ** ops.const(1.5) * ops.sqrt(s))
    return {
        "theta_rad": theta, "e": ops.sqrt(e_sq), "e_sq": e_sq, "one_minus_e_sq": mc,
        "k_first": k, "e_second": e_int, "m_coef": m_coef, "n_coef": n_coef,
        "r_coef": r_coef, "a_rolling_m": a_roll, "b_lateral_m": b_lat,
        "approach_m": approach, "stiffness_n_m15": stiffness,
    }


def ratio_eq(k, e_int, mc):
    return (e_int / mc - k) / (k - e_int)


def scipy_solution(a_curv, b_curv):
    lo, hi = min(a_curv, b_curv), max(a_curv, b_curv)
    rho = hi / lo
    if rho == 1.0:
        e_sq, mc, k, e_int = 0.0, 1.0, math.pi / 2, math.pi / 2
    elif rho < 2.0:
        def f(m):
            return ratio_eq(ellipk(m), ellipe(m), 1.0 - m) - rho
        # e^2 <= u = -ln(1 - e^2) <= (4/3) ln(rho) <= (4/3)(rho - 1).
        guess = 4.0 / 3.0 * (rho - 1.0)
        e_sq = brentq(f, 0.25 * guess, min(1.01 * guess, 0.95), xtol=1e-300, rtol=4 * EPS)
        mc, k, e_int = 1.0 - e_sq, ellipk(e_sq), ellipe(e_sq)
    else:
        def f(mc):
            return ratio_eq(ellipkm1(mc), ellipe(1.0 - mc), mc) - rho
        mc = brentq(f, 1e-30, 0.6, xtol=1e-300, rtol=4 * EPS)
        e_sq, k, e_int = 1.0 - mc, ellipkm1(mc), ellipe(1.0 - mc)
    # theta = arccos(|B - A|/(A + B)) evaluated as the identical
    # 2 arctan(sqrt(min/max)): in floats, arccos of an argument near 1 loses
    # half the digits (1e-5 relative at ratio 1e12).
    theta = 2.0 * math.atan(math.sqrt(lo / hi))
    return derived(a_curv, b_curv, e_sq, mc, k, e_int, FLOAT_OPS, theta)


def mpmath_solution(a_curv, b_curv):
    a, b = mp.mpf(a_curv), mp.mpf(b_curv)
    lo, hi = min(a, b), max(a, b)
    s = mp.log(hi / lo)
    if s == 0:
        e_sq, mc, k, e_int = mp.mpf(0), mp.mpf(1), mp.pi / 2, mp.pi / 2
    else:
        def g(u):
            mc = mp.exp(-u)
            m = -mp.expm1(-u)
            return mp.log(ratio_eq(mp.ellipk(m), mp.ellipe(m), mc)) - s
        # u/s lies in (1, 4/3] (4/3 at the circle, -> 1 for elongated shapes).
        u = mp.findroot(g, (s, s * mp.mpf(4) / 3), solver="anderson")
        e_sq, mc = -mp.expm1(-u), mp.exp(-u)
        k, e_int = mp.ellipk(e_sq), mp.ellipe(e_sq)
        assert abs(g(u)) < mp.mpf(10) ** (10 - DPS), (a_curv, b_curv)
    theta = mp.acos(abs(b - a) / (a + b))  # the reference form (docs/reference/07-contact-forces.md), exact at 40 digits
    return derived(a, b, e_sq, mc, k, e_int, MP_OPS, theta)


def hertz_cases():
    """(name, A, B) in 1/m."""
    cases = []
    ratios = [1e-3, 2e-3, 5e-3, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9,
              0.99, 0.999, 1.0, 1.001, 1.01, 1.1, 1.5, 1.9, 2.0, 3.0, 5.0, 10.0,
              20.0, 50.0, 100.0, 200.0, 500.0, 1e3]
    for i, q in enumerate(ratios):
        base = (1.0, 2.5, 0.4)[i % 3]
        a = base * math.sqrt(q)
        b = base / math.sqrt(q)
        cases.append((f"ratio A/B={q:g} scale {base:g}", a, b))
    # Same ratios at a fixed wheel-like scale (A = 1.087 1/m).
    for q in (1e-3, 0.1, 1.0, 10.0, 1e3):
        cases.append((f"ratio A/B={q:g} A=1.087", 1.087, 1.087 / q))
    b_curv = 1.087
    for deg in (1, 5, 10, 20, 30, 40, 45, 50, 60, 70, 75, 80, 85, 89, 89.9):
        c = math.cos(math.radians(deg))
        a_curv = b_curv * (1 - c) / (1 + c)
        cases.append((f"theta={deg:g} deg, A<B", a_curv, b_curv))
        cases.append((f"theta={deg:g} deg, A>B", b_curv, a_curv))
    for q in (1e4, 1e5, 1e6, 1e8, 1e10, 1e12):
        cases.append((f"extended ratio B/A={q:g}", 0.5, 0.5 * q))
        cases.append((f"extended ratio A/B={q:g}", 3.0 * q, 3.0))
    return cases


def main():
    hertz = []
    worst = {q: 0.0 for q in QUANTITIES}
    for name, a_curv, b_curv in hertz_cases():
        sp = scipy_solution(a_curv, b_curv)
        ex = mpmath_solution(a_curv, b_curv)
        for q in QUANTITIES:
            if ex[q] != 0:
                worst[q] = max(worst[q], float(abs((mp.mpf(float(sp[q])) - ex[q]) / ex[q])))
        hertz.append({
            "name": name,
            "a_curv_1_m": fmt(a_curv),
            "b_curv_1_m": fmt(b_curv),
            "scipy": {q: fmt(sp[q]) for q in QUANTITIES},
            "mpmath": {q: fmt(ex[q]) for q in QUANTITIES},
        })
    doc = {
        "generator": "runtime/tests/data/make_hertz_reference.py",
        "scipy_version": scipy.__version__,
        "numpy_version": np.__version__,
        "mpmath_version": mp.__version__,
        "mpmath_dps": DPS,
        "python_version": platform.python_version(),
        "number_format": "floats are strings holding Python repr (shortest round-trip decimal)",
        "parameter_convention": "elliptic integrals take the parameter m = k^2 (scipy.special.ellipk/ellipe)",
        "material": {"young_pa": fmt(YOUNG_PA), "poisson": fmt(POISSON)},
        "normal_force_n": fmt(NORMAL_FORCE_N),
        "scipy_vs_mpmath_max_rel": {q: f"{worst[q]:.3e}" for q in QUANTITIES},
        "elliptic": elliptic_cases(),
        "elliptic_complementary": elliptic_complementary_cases(),
        "hertz": hertz,
    }
    compact = {"separators": (",", ":")}
    head = {k: v for k, v in doc.items() if k not in ("elliptic", "elliptic_complementary", "hertz")}
    header = json.dumps(head, indent=1)
    parts = []
    for key in ("elliptic", "elliptic_complementary", "hertz"):
        rows = ",\n".join(json.dumps(c, **compact) for c in doc[key])
        parts.append(f' "{key}": [\n{rows}\n ]')
    with open(OUT, "w", encoding="utf-8") as f:
        f.write(header[:-2] + ",\n" + ",\n".join(parts) + "\n}\n")
    json.loads(OUT.read_text(encoding="utf-8"))  # well-formed
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes: {len(doc['elliptic'])} elliptic, "
          f"{len(doc['elliptic_complementary'])} complementary, {len(hertz)} Hertz cases)")
    print("SciPy vs mpmath, max relative difference:")
    for q in QUANTITIES:
        print(f"  {q:16s} {worst[q]:.2e}")


if __name__ == "__main__":
    main()
