#!/usr/bin/env python3
"""Generate the ML95-like conical wheel profile (tables/profiles/ml95_like/).

The real ML95 profile of the Lisbon metro is not public. This script builds
a stand-in with the features the paper's wheel is described with (Pombo,
Ambrosio & Silva 2007, section 5): a 1:20 conical tread, a 28 mm flange
with a 70 degree flank, a concave throat and a rounded tip, on a wheel of
0.43 m nominal rolling radius (the radius is a wheelset parameter, it is
not in the file). README.md gives every dimension and its reasoning.

Usage (Python 3 standard library only; from the repository root):

    python3 tables/profiles/ml95_like/generate.py

It writes ml95_like_wheel.csv next to itself, checks the result with
assertions and prints a summary (quoted in README.md). The output is
deterministic: rerunning rewrites a byte-identical file. Do not edit the CSV
by hand; change the parameters below and rerun.

Coordinates (the toolkit's convention for plain/CSV profiles, as EN 15302):
y lateral [mm], origin at the taping line, positive towards the field side
(flange at negative y); z [mm] up, z = 0 on the tread at the taping line
(the flange tip is at z = -28). The wheel's material lies above the curve.

1. Design curve (G1: lines and arcs, tangent at every joint). In order of
   increasing y:

     back face   straight, BACK_DRAFT_DEG from vertical, from the flange back
                 (y = -70, z = Z_BACK_END_MM) down to
     back arc    convex, radius R_BACK_MM, internally tangent to
     tip arc     convex, radius R_TIP_MM, lowest point z = -28 (flange tip)
     flank       straight at 70 deg to the horizontal, through the point
                 (y = -70 + SD_MM, z = -10) that fixes the flange thickness
     throat      concave, radius R_THROAT_MM
     tread       straight cone z = y / 20 through (0, 0)
     edge arc    convex, radius R_EDGE_MM, rounding the chamfer corner
     chamfer     straight at CHAMFER_ANGLE_DEG up to the field edge y = +65

   The centres and tangency points are solved in closed form (build_design).

2. Curvature transitions. A line-arc joint is a jump in curvature. Within
   about 0.5 mm of such a joint, the curvature of a cubic spline (not-a-knot)
   through points of the G1 curve oscillates and changes sign: on the
   straight flank it dips to -12 1/m (concave) next to the tip and bumps to
   +10 1/m (convex) next to the throat. A contact model that splits the
   profile by the sign of the curvature, or takes Hertz curvatures from the
   spline, sees spurious features there. So the written curve replaces
   every curvature jump by a smooth monotone ramp of half-length
   a = BLEND_HALF_MM of arc on each side of the joint:

       kappa(s) = k1 + (k2 - k1) S((s - s_j + a) / (2 a)),
       S(u) = 35 u^4 - 84 u^5 + 70 u^6 - 20 u^7

   (S(0) = 0, S(1) = 1, and the first three derivatives of S vanish at both
   ends, so the curvature is three times continuously differentiable and
   never overshoots). Heading and position are integrated from the
   curvature (closed form on the constant parts, 5-point Gauss-Legendre
   inside the ramps). The ramps move the curve by up to about 12
   micrometres, so the four free values (back-face length, back-arc/tip-arc
   joint angle, flank length, tread length) are re-solved by Newton's method
   to keep the defining features exact: tip at z = -28, Sd exactly SD_MM at
   z = -10, the tread on z = y / 20, the chamfer through its corner. Outside
   the ramps the written curve is exactly straight or circular.
   BLEND_HALF_MM = 0 writes the G1 design curve itself.

3. Points. Arcs and ramps every <= STEP_ARC_MM of arc; straight parts with
   spacing growing by GRADING from STEP_ARC_MM to STEP_LINE_MM (no jump in
   spacing); the tread at every multiple of STEP_TREAD_MM in y, so the
   taping line (0, 0) and the cone's points are exact. Each other point is
   moved along the curve so that its y is exactly the written 6-decimal
   value; only z is rounded (see on_written_y).

4. Summary: the flange dimensions, the design curve, and three estimates of
   the flangeway clearance, the last a 2-D flange-contact search against
   ../MBench_UIC60_v3.prr (see flange_contact).
"""

import bisect
import math
import os
import sys

# ---------------------------------------------------------------------------
# Parameters (mm and degrees). Change them here and rerun.
# ---------------------------------------------------------------------------

# Flange thickness Sd, measured at Z_SD_MM from the flange back (the inner
# face of the wheel, y = Y_FLANGE_BACK_MM). With a 1435 mm gauge and a
# 1360 mm flange-back distance the clearance per side at that height is
# (1435 - (1360 + 2 Sd)) / 2 = 37.5 - Sd. The flank meets the rail lower
# down, against the gauge corner, where the flange is thinner: the 2-D
# contact estimate printed by this script (benchmark UIC60 rail) puts the
# flange contact at 7.0 mm of lateral shift for Sd = 31.7 (30.5 would give
# 8.2). The shift changes by about -1 mm per mm of Sd.
SD_MM = 31.7
Z_SD_MM = -10.0            # 10 mm below the tread at the taping line (EN 15313)
FLANGE_HEIGHT_MM = 28.0    # Sh: the flange tip is 28 mm below the tread
TREAD_SLOPE = 1.0 / 20.0   # 1:20 cone
FLANK_ANGLE_DEG = 70.0     # flank inclination to the horizontal
R_THROAT_MM = 12.0         # concave throat fillet
R_TIP_MM = 10.0            # convex flange tip
R_BACK_MM = 22.0           # convex rounding between the tip and the back face
BACK_DRAFT_DEG = 1.0       # back face leans 1 deg from vertical (z must be a function of y)
Y_FLANGE_BACK_MM = -70.0   # flange back, 70 mm from the taping line (as S1002)
Z_BACK_END_MM = 0.0        # the profile starts on the back face at this height
Y_FIELD_EDGE_MM = 65.0     # field-side edge: wheel width 135 mm
CHAMFER_CORNER_Y_MM = 60.0 # the (rounded) corner where the chamfer starts
CHAMFER_ANGLE_DEG = 45.0   # chamfer inclination: 5 mm x 45 deg, as S1002
R_EDGE_MM = 5.0            # rounding of the tread/chamfer corner
BLEND_HALF_MM = 1.0        # curvature ramp: half-length of arc on each side of a joint

# Point spacing.
STEP_TREAD_MM = 0.5        # tread: every multiple of 0.5 mm in y (y = 0 included)
STEP_LINE_MM = 0.5         # other straight parts: at most 0.5 mm of length
STEP_ARC_MM = 0.2          # arcs and curvature ramps: at most 0.2 mm of arc
DECIMALS = 6               # decimals written (1 nm); see README on curvature noise
GRADING = 1.25             # straight parts: spacing grows by at most this factor per point
MIN_GAP_MM = 0.1           # grid points closer than this to a part's end are dropped

# Wheelset and track the flange is dimensioned for (summary only).
NOMINAL_RADIUS_M = 0.43
GAUGE_MM = 1435.0                  # measured GAUGE_POINT_DEPTH_MM below the top of rail
FLANGE_BACK_DISTANCE_MM = 1360.0   # back-to-back spacing of the wheels
GAUGE_POINT_DEPTH_MM = 14.0
TARGET_CLEARANCE_MM = 7.0          # flange contact at ~7 mm lateral shift (paper, section 5.1)
# The rail the estimate uses: the benchmark UIC60, already canted 1:40.
RAIL_FILE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "MBench_UIC60_v3.prr")

OUTPUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "ml95_like_wheel.csv")
TOL = 1e-9

PHI = math.radians(FLANK_ANGLE_DEG)
ALPHA = math.atan(TREAD_SLOPE)
THETA_BACK = -math.radians(90.0 - BACK_DRAFT_DEG)
THETA_CHAMFER = math.radians(CHAMFER_ANGLE_DEG)
Y_SD = Y_FLANGE_BACK_MM + SD_MM


def normal(theta):
    """Unit normal to the left of the direction of increasing y (upwards)."""
    return (-math.sin(theta), math.cos(theta))


def dot(p, q):
    return p[0] * q[0] + p[1] * q[1]


def sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def dist(p, q):
    return math.hypot(p[0] - q[0], p[1] - q[1])


# ---------------------------------------------------------------------------
# 1. The G1 design curve, in closed form.
# ---------------------------------------------------------------------------

def centre_from_two_lines(m1, b1, d1, m2, b2, d2):
    """Point at signed distance d1 from z = m1 y + b1 and d2 from z = m2 y + b2
    (positive = above the line)."""
    c1 = b1 + d1 * math.hypot(1.0, m1)
    c2 = b2 + d2 * math.hypot(1.0, m2)
    y = (c1 - c2) / (m2 - m1)
    return (y, m1 * y + c1)


def build_design():
    """Segments of the design curve: dicts with name, kind ('line' or 'arc'),
    start, end, theta0, theta1 (tangent angles, slope = tan), curvature
    (+1/R convex, -1/R concave, 0 line), centre and radius for arcs."""
    m_t, m_f, m_c = math.tan(ALPHA), math.tan(PHI), math.tan(THETA_CHAMFER)
    b_f = Z_SD_MM - m_f * Y_SD
    # Tip arc: lowest point at z = -Sh, tangent to the flank.
    zc_t = -FLANGE_HEIGHT_MM + R_TIP_MM
    c_t = (Y_SD - R_TIP_MM * math.sin(PHI) + (zc_t - R_TIP_MM * math.cos(PHI) - Z_SD_MM) / m_f, zc_t)
    # Back arc: tangent to the back face through E (C_b = E + s u + R_b n) and
    # internally tangent to the tip arc (|C_b - C_t| = R_b - R_t).
    e = (Y_FLANGE_BACK_MM, Z_BACK_END_MM)
    u_b, n_b = (math.cos(THETA_BACK), math.sin(THETA_BACK)), normal(THETA_BACK)
    q = (e[0] + R_BACK_MM * n_b[0] - c_t[0], e[1] + R_BACK_MM * n_b[1] - c_t[1])
    qu = dot(q, u_b)
    disc = qu * qu - (dot(q, q) - (R_BACK_MM - R_TIP_MM) ** 2)
    assert R_BACK_MM > R_TIP_MM and disc > 0, "back arc cannot reach the tip arc: increase R_BACK_MM"
    s_back = -qu - math.sqrt(disc)  # the upper solution (centre above the tip centre)
    c_b = (e[0] + s_back * u_b[0] + R_BACK_MM * n_b[0], e[1] + s_back * u_b[1] + R_BACK_MM * n_b[1])
    g = ((c_t[0] - c_b[0]) / (R_BACK_MM - R_TIP_MM), (c_t[1] - c_b[1]) / (R_BACK_MM - R_TIP_MM))
    theta_j = math.atan2(g[0], -g[1])
    assert s_back > 0, "no straight back face left: raise Z_BACK_END_MM or lower R_BACK_MM"
    assert THETA_BACK < theta_j < 0, "back arc would cut the flange tip: raise R_BACK_MM"
    # Throat: concave, centre below the tread (z = m_t y) and the flank.
    c_h = centre_from_two_lines(m_t, 0.0, -R_THROAT_MM, m_f, b_f, -R_THROAT_MM)
    # Field edge: chamfer through the corner on the tread, convex rounding.
    corner = (CHAMFER_CORNER_Y_MM, m_t * CHAMFER_CORNER_Y_MM)
    b_c = corner[1] - m_c * corner[0]
    c_e = centre_from_two_lines(m_t, 0.0, R_EDGE_MM, m_c, b_c, R_EDGE_MM)

    def arc(name, c, r, t0, t1, convex):
        sgn = 1.0 if convex else -1.0
        at = lambda t: (c[0] + sgn * r * math.sin(t), c[1] - sgn * r * math.cos(t))
        return dict(name=name, kind="arc", centre=c, radius=r, theta0=t0, theta1=t1,
                    start=at(t0), end=at(t1), curvature=sgn / r, length=r * abs(t1 - t0))

    def line(name, p0, p1, theta):
        return dict(name=name, kind="line", theta0=theta, theta1=theta, start=p0, end=p1,
                    curvature=0.0, length=dist(p0, p1))

    back_arc = arc("back arc", c_b, R_BACK_MM, THETA_BACK, theta_j, True)
    tip = arc("tip arc", c_t, R_TIP_MM, theta_j, PHI, True)
    throat = arc("throat", c_h, R_THROAT_MM, PHI, ALPHA, False)
    edge = arc("edge arc", c_e, R_EDGE_MM, ALPHA, THETA_CHAMFER, True)
    chamfer_end = (Y_FIELD_EDGE_MM, corner[1] + m_c * (Y_FIELD_EDGE_MM - corner[0]))
    segs = [
        line("back face", e, back_arc["start"], THETA_BACK),
        back_arc,
        tip,
        line("flank", tip["end"], throat["start"], PHI),
        throat,
        line("tread", throat["end"], edge["start"], ALPHA),
        edge,
        line("chamfer", edge["end"], chamfer_end, THETA_CHAMFER),
    ]
    # Straight parts lie on the lines they are defined by; joints are
    # continuous in position and tangent angle (slope), to 1e-9.
    lines = {
        "back face": lambda p: dot(sub(p, e), n_b),
        "flank": lambda p: (p[1] - m_f * p[0] - b_f) / math.hypot(1, m_f),
        "tread": lambda p: (p[1] - m_t * p[0]) / math.hypot(1, m_t),
        "chamfer": lambda p: (p[1] - m_c * p[0] - b_c) / math.hypot(1, m_c),
    }
    for s in segs:
        if s["kind"] == "line":
            for p in (s["start"], s["end"]):
                assert abs(lines[s["name"]](p)) < TOL, (s["name"], lines[s["name"]](p))
            assert abs(math.atan2(s["end"][1] - s["start"][1], s["end"][0] - s["start"][0]) - s["theta0"]) < TOL
        assert s["length"] > 0, f"{s['name']} has no length: check the parameters"
    joints = []
    for a, b in zip(segs, segs[1:]):
        dp, dt = dist(a["end"], b["start"]), abs(a["theta1"] - b["theta0"])
        dslope = abs(math.tan(a["theta1"]) - math.tan(b["theta0"])) / max(1.0, abs(math.tan(a["theta1"])))
        assert dp < TOL and dt < TOL and dslope < TOL, (a["name"], b["name"], dp, dt, dslope)
        joints.append((a["name"], b["name"], dp, dt))
    assert segs[3]["start"][1] < Z_SD_MM < segs[3]["end"][1], "the Sd point must lie on the flank"
    assert segs[5]["start"][0] < 0.0 < segs[5]["end"][0], "the taping line must be on the tread"
    assert segs[5]["end"][0] < CHAMFER_CORNER_Y_MM < segs[7]["start"][0] < Y_FIELD_EDGE_MM
    free = [segs[0]["length"], theta_j, segs[3]["length"], segs[5]["length"]]
    return segs, joints, free


# ---------------------------------------------------------------------------
# 2. The written curve: curvature with smooth ramps, integrated.
# ---------------------------------------------------------------------------

def ramp(u):
    return u ** 4 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u)))


def ramp_integral(u):
    return u ** 5 * (7.0 + u * (-14.0 + u * (10.0 - 2.5 * u)))


_GL = (
    (0.0, 128.0 / 225.0),
    (math.sqrt(5.0 - 2.0 * math.sqrt(10.0 / 7.0)) / 3.0, (322.0 + 13.0 * math.sqrt(70.0)) / 900.0),
    (-math.sqrt(5.0 - 2.0 * math.sqrt(10.0 / 7.0)) / 3.0, (322.0 + 13.0 * math.sqrt(70.0)) / 900.0),
    (math.sqrt(5.0 + 2.0 * math.sqrt(10.0 / 7.0)) / 3.0, (322.0 - 13.0 * math.sqrt(70.0)) / 900.0),
    (-math.sqrt(5.0 + 2.0 * math.sqrt(10.0 / 7.0)) / 3.0, (322.0 - 13.0 * math.sqrt(70.0)) / 900.0),
)


class Curve:
    """A plane curve given by its start point, start heading and a curvature
    that is piecewise constant with smooth ramps between the pieces.

    pieces: [(name, curvature, length)]; the joints between pieces get ramps
    of half-length BLEND_HALF_MM. Parts alternate: constant (closed form) and
    ramp (integrated), each stored with its start point and heading."""

    def __init__(self, start, theta0, pieces, half=BLEND_HALF_MM):
        self.pieces = pieces
        self.parts = []
        s, p, th = 0.0, start, theta0
        joint_s = 0.0
        for i, (name, kappa, length) in enumerate(pieces):
            joint_s += length
            last = i == len(pieces) - 1
            a = 0.0 if last else half
            const_end = joint_s - a
            assert const_end - s > 1e-6, f"{name}: the curvature ramps overlap (lower BLEND_HALF_MM)"
            part = dict(kind="const", name=name, s0=s, s1=const_end, p0=p, th0=th, k=kappa)
            self.parts.append(part)
            p, th, s = self._const_at(part, const_end), th + kappa * (const_end - s), const_end
            if a > 0.0:
                k2 = pieces[i + 1][1]
                part = dict(kind="ramp", name=f"{name} / {pieces[i + 1][0]}", s0=s, s1=s + 2 * a,
                            p0=p, th0=th, k=kappa, dk=k2 - kappa, a=a)
                self.parts.append(part)
                p, th, s = self._ramp_at(part, s + 2 * a), self._ramp_theta(part, s + 2 * a), s + 2 * a
        self.length = s
        self.end, self.end_theta = p, th

    @staticmethod
    def _const_at(part, s):
        ds, th0, k = s - part["s0"], part["th0"], part["k"]
        th1 = th0 + k * ds
        if abs(k * ds) < 1e-9:  # straight (or a vanishing step): exact enough
            thm = 0.5 * (th0 + th1)
            return (part["p0"][0] + ds * math.cos(thm), part["p0"][1] + ds * math.sin(thm))
        return (part["p0"][0] + (math.sin(th1) - math.sin(th0)) / k,
                part["p0"][1] + (math.cos(th0) - math.cos(th1)) / k)

    @staticmethod
    def _ramp_theta(part, s):
        t = s - part["s0"]
        u = t / (2.0 * part["a"])
        return part["th0"] + part["k"] * t + part["dk"] * 2.0 * part["a"] * ramp_integral(u)

    def _ramp_at(self, part, s):
        """Position in a ramp: Gauss-Legendre over sub-intervals of <= 0.05 mm."""
        t_total = s - part["s0"]
        n = max(1, math.ceil(t_total / 0.05))
        h = t_total / n
        y, z = part["p0"]
        for k in range(n):
            mid = part["s0"] + (k + 0.5) * h
            for x, w in _GL:
                th = self._ramp_theta(part, mid + 0.5 * h * x)
                y += 0.5 * h * w * math.cos(th)
                z += 0.5 * h * w * math.sin(th)
        return (y, z)

    def part_at(self, s):
        for part in self.parts:
            if s <= part["s1"] + 1e-12:
                return part
        return self.parts[-1]

    def at(self, s):
        part = self.part_at(s)
        return self._const_at(part, s) if part["kind"] == "const" else self._ramp_at(part, s)

    def theta(self, s):
        part = self.part_at(s)
        if part["kind"] == "const":
            return part["th0"] + part["k"] * (s - part["s0"])
        return self._ramp_theta(part, s)

    def curvature(self, s):
        part = self.part_at(s)
        if part["kind"] == "const":
            return part["k"]
        return part["k"] + part["dk"] * ramp((s - part["s0"]) / (2.0 * part["a"]))

    def const(self, name):
        return next(p for p in self.parts if p["kind"] == "const" and p["name"] == name)

    def s_at_z(self, z, s_lo, s_hi):
        """Arc length in [s_lo, s_hi] (where z increases) at height z."""
        for _ in range(200):
            mid = 0.5 * (s_lo + s_hi)
            if self.at(mid)[1] < z:
                s_lo = mid
            else:
                s_hi = mid
        return 0.5 * (s_lo + s_hi)


def make_curve(free, half=BLEND_HALF_MM):
    l_back, theta_j, l_flank, l_tread = free
    pieces = [
        ("back face", 0.0, l_back),
        ("back arc", 1.0 / R_BACK_MM, (theta_j - THETA_BACK) * R_BACK_MM),
        ("tip arc", 1.0 / R_TIP_MM, (PHI - theta_j) * R_TIP_MM),
        ("flank", 0.0, l_flank),
        ("throat", -1.0 / R_THROAT_MM, (PHI - ALPHA) * R_THROAT_MM),
        ("tread", 0.0, l_tread),
        ("edge arc", 1.0 / R_EDGE_MM, (THETA_CHAMFER - ALPHA) * R_EDGE_MM),
        ("chamfer", 0.0, 30.0),  # cut at the field edge afterwards
    ]
    return Curve((Y_FLANGE_BACK_MM, Z_BACK_END_MM), THETA_BACK, pieces, half)


def tip_lowest(curve):
    """(s, point) of the flange tip: where the heading is 0 on the tip arc."""
    part = curve.const("tip arc")
    s = part["s0"] - part["th0"] / part["k"]
    assert part["s0"] <= s <= part["s1"], "the flange tip lies in a curvature ramp (lower BLEND_HALF_MM)"
    return s, curve.at(s)


def front_s_at_z(curve, z):
    """Arc length where the front of the flange (tip to tread) is at height z."""
    s_tip, _ = tip_lowest(curve)
    return curve.s_at_z(z, s_tip, curve.const("tread")["s0"])


def residuals(free, half=BLEND_HALF_MM):
    c = make_curve(free, half)
    _, tip = tip_lowest(c)
    sd = c.at(front_s_at_z(c, Z_SD_MM))
    tread = c.const("tread")
    chamfer = c.const("chamfer")
    corner = (CHAMFER_CORNER_Y_MM, TREAD_SLOPE * CHAMFER_CORNER_Y_MM)
    return [
        tip[1] + FLANGE_HEIGHT_MM,                       # tip at z = -Sh
        sd[0] - Y_SD,                                    # Sd exact at z = -10
        dot(tread["p0"], normal(ALPHA)),                 # tread on z = y/20
        dot(sub(chamfer["p0"], corner), normal(THETA_CHAMFER)),  # chamfer through its corner
    ]


def solve(free0, half=BLEND_HALF_MM):
    """Newton's method (forward-difference Jacobian) on the four free values."""
    x = list(free0)
    for it in range(30):
        r = residuals(x, half)
        if max(abs(v) for v in r) < 1e-12:
            return x, r, it
        h = 1e-7
        jac = []
        for j in range(4):
            xp = list(x)
            xp[j] += h
            rp = residuals(xp, half)
            jac.append([(rp[i] - r[i]) / h for i in range(4)])
        # Solve J dx = -r (J[i][j] = dr_i/dx_j), Gaussian elimination with pivoting.
        m = [[jac[j][i] for j in range(4)] + [-r[i]] for i in range(4)]
        for col in range(4):
            piv = max(range(col, 4), key=lambda i: abs(m[i][col]))
            m[col], m[piv] = m[piv], m[col]
            for i in range(col + 1, 4):
                f = m[i][col] / m[col][col]
                for k in range(col, 5):
                    m[i][k] -= f * m[col][k]
        dx = [0.0] * 4
        for i in range(3, -1, -1):
            dx[i] = (m[i][4] - sum(m[i][k] * dx[k] for k in range(i + 1, 4))) / m[i][i]
        x = [a + b for a, b in zip(x, dx)]
    raise RuntimeError(f"Newton did not converge: residuals {r}")


# ---------------------------------------------------------------------------
# Sampling, output and checks.
# ---------------------------------------------------------------------------

def sample(curve):
    pts = [curve.at(0.0)]
    s_tip, _ = tip_lowest(curve)
    chamfer = curve.const("chamfer")
    s_end = chamfer["s0"] + (Y_FIELD_EDGE_MM - chamfer["p0"][0]) / math.cos(THETA_CHAMFER)
    for part in curve.parts:
        s0, s1 = part["s0"], min(part["s1"], s_end)
        if part["kind"] == "const" and part["name"] == "tread":
            # Every multiple of STEP_TREAD_MM in y (the taping line y = 0
            # included), exactly on the cone: Newton left the tread on
            # z = y/20 to < 1e-12 mm.
            y0, y1 = part["p0"][0], curve.at(s1)[0]
            ks = range(math.ceil(y0 / STEP_TREAD_MM), math.floor(y1 / STEP_TREAD_MM) + 1)
            ys = [k * STEP_TREAD_MM for k in ks]
            pts.extend((y, y * TREAD_SLOPE) for y in ys if y - y0 >= MIN_GAP_MM and y1 - y >= MIN_GAP_MM)
            ss = [s1]
        elif part["kind"] == "const" and part["k"] == 0.0:
            ss = graded(s0, s1)
        elif part["name"] == "tip arc":  # the flange tip itself is a point
            ss = uniform(s0, s_tip) + uniform(s_tip, s1)
        else:
            ss = uniform(s0, s1)
        pts.extend(on_written_y(curve, s, curve.at(s)) for s in ss)
        if s1 >= s_end:
            break
    pts[-1] = (Y_FIELD_EDGE_MM, pts[-1][1])
    return pts, s_end


def uniform(s0, s1):
    """Positions in (s0, s1], at most STEP_ARC_MM apart."""
    n = max(1, math.ceil((s1 - s0) / STEP_ARC_MM - 1e-9))
    return [s0 + (s1 - s0) * k / n for k in range(1, n + 1)]


def graded(s0, s1):
    """Positions in (s0, s1] on a straight part: steps grow by GRADING from
    STEP_ARC_MM at both ends to at most STEP_LINE_MM in the middle, so the
    spacing never jumps (a jump in spacing next to a curvature ramp shows up
    as a wiggle in a cubic spline's second derivative)."""
    length = s1 - s0
    ramp_steps, h = [], STEP_ARC_MM
    while h < STEP_LINE_MM:
        ramp_steps.append(h)
        h *= GRADING
    if 2.0 * sum(ramp_steps) >= length:
        n = max(1, math.ceil(length / STEP_ARC_MM - 1e-9))
        steps = [length / n] * n
    else:
        middle = length - 2.0 * sum(ramp_steps)
        n = max(1, math.ceil(middle / STEP_LINE_MM - 1e-9))
        steps = ramp_steps + [middle / n] * n + ramp_steps[::-1]
    ss, s = [], s0
    for h in steps[:-1]:
        s += h
        ss.append(s)
    return ss + [s1]


def on_written_y(curve, s, p):
    """The curve point whose y is p's y rounded to the written DECIMALS.

    Only z is then rounded when written: on the steep flank a rounding of y
    would move the point off the curve by slope x 5e-7 mm, and a cubic
    spline's second derivative amplifies such noise by 1/h^2."""
    y_r = round(p[0], DECIMALS)
    for _ in range(3):  # Newton on y(s) = y_r, dy/ds = cos(theta) > 0
        s += (y_r - p[0]) / math.cos(curve.theta(s))
        p = curve.at(s)
    assert abs(p[0] - y_r) < 1e-10, (p[0], y_r)
    return (y_r, p[1])


def write_csv(pts):
    def fmt(v):
        return f"{round(v, DECIMALS) + 0.0:.{DECIMALS}f}"  # + 0.0: no "-0.000000"
    text = "y_mm,z_mm\n" + "".join(f"{fmt(y)},{fmt(z)}\n" for y, z in pts)
    tmp = OUTPUT + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(text)
    os.replace(tmp, OUTPUT)


def read_csv():
    with open(OUTPUT) as f:
        rows = f.read().splitlines()
    assert rows[0] == "y_mm,z_mm"
    return [tuple(float(v) for v in r.split(",")) for r in rows[1:]]


def distance_to_design(p, segs):
    best = math.inf
    for s in segs:
        if s["kind"] == "line":
            a, b = s["start"], s["end"]
            d = sub(b, a)
            t = max(0.0, min(1.0, dot(sub(p, a), d) / dot(d, d)))
            best = min(best, dist(p, (a[0] + t * d[0], a[1] + t * d[1])))
        else:
            c, r = s["centre"], s["radius"]
            conv = s["curvature"] > 0
            # tangent angle of the point of the arc's circle nearest to p
            v = sub(p, c)
            th = math.atan2(v[0], -v[1]) if conv else math.atan2(-v[0], v[1])
            lo, hi = sorted((s["theta0"], s["theta1"]))
            if lo <= th <= hi:
                best = min(best, abs(math.hypot(*v) - r))
            else:
                best = min(best, dist(p, s["start"]), dist(p, s["end"]))
    return best


def check(written, curve, s_end, segs):
    ys = [p[0] for p in written]
    zs = [p[1] for p in written]
    assert all(b > a for a, b in zip(ys, ys[1:])), "y must increase strictly"
    assert ys[0] == Y_FLANGE_BACK_MM and ys[-1] == Y_FIELD_EDGE_MM
    assert min(zs) == -FLANGE_HEIGHT_MM, min(zs)
    assert (0.0, 0.0) in written, "the taping line (0, 0) must be a point"
    # The heading stays within (-90, 90) deg, so y grows along the whole curve.
    n = 20000
    ths = [curve.theta(s_end * k / n) for k in range(n + 1)]
    assert -math.pi / 2 < min(ths) and max(ths) < math.pi / 2
    # Joints of the written curve: heading and curvature continuous at every
    # ramp end (closed form of each side), to 1e-9.
    worst_th = worst_k = 0.0
    for a, b in zip(curve.parts, curve.parts[1:]):
        if a["kind"] == "const":
            th_a, k_a = a["th0"] + a["k"] * (a["s1"] - a["s0"]), a["k"]
        else:
            th_a, k_a = Curve._ramp_theta(a, a["s1"]), a["k"] + a["dk"] * ramp(1.0)
        worst_th = max(worst_th, abs(th_a - b["th0"]))
        worst_k = max(worst_k, abs(k_a - b["k"]))
    assert worst_th < TOL, worst_th
    assert BLEND_HALF_MM == 0.0 or worst_k < TOL, worst_k
    # Curvature: concave only from the flank/throat ramp to the throat/tread ramp.
    s_flank_end = curve.const("flank")["s1"]
    s_tread_start = curve.const("tread")["s0"]
    for k in range(n + 1):
        s = s_end * k / n
        kap = curve.curvature(s)
        if s < s_flank_end or s > s_tread_start:
            assert kap >= -1e-12, (s, kap)
        else:
            assert kap <= 1e-12, (s, kap)
    # Spacing: at most STEP_ARC_MM of arc on arcs and ramps (a chord is
    # shorter than its arc), at most STEP_LINE_MM (+ the tread's end gaps)
    # elsewhere.
    chords = [dist(a, b) for a, b in zip(written, written[1:])]
    assert max(chords) <= max(STEP_LINE_MM, STEP_TREAD_MM / math.cos(ALPHA)) + MIN_GAP_MM + 1e-6
    for part in curve.parts:
        if part["kind"] == "ramp" or part["k"] != 0.0:
            y0, y1 = curve.at(part["s0"])[0], curve.at(min(part["s1"], s_end))[0]
            inside = [p for p in written if y0 - 1e-6 <= p[0] <= y1 + 1e-6]
            worst = max(dist(a, b) for a, b in zip(inside, inside[1:]))
            # + 1e-4: snapping y to 6 decimals slides a point along the
            # curve by up to 5e-7 / cos(theta), 3e-5 mm at the 89 deg back face
            assert worst <= STEP_ARC_MM + 1e-4, (part["name"], worst)
    # Slopes of the straight parts from the written points (6 decimals).
    def slope_dev(name, target):
        part = curve.const(name)
        p0, p1 = part["p0"], curve.at(part["s1"])
        pts = [p for p in written if p0[0] - 1e-6 <= p[0] <= p1[0] + 1e-6]
        return max(abs((b[1] - a[1]) / (b[0] - a[0]) - target) for a, b in zip(pts, pts[1:]))
    flank_dev = slope_dev("flank", math.tan(PHI))
    tread_dev = slope_dev("tread", TREAD_SLOPE)
    assert flank_dev < 1e-4 and tread_dev < 1e-4, (flank_dev, tread_dev)
    max_dev = max(distance_to_design(p, segs) for p in written)
    return flank_dev, tread_dev, max_dev, max(chords)


# ---------------------------------------------------------------------------
# Flange-contact estimate against the benchmark rail (summary only).
# ---------------------------------------------------------------------------

def read_simpack_rail(path):
    """(y, z_up) points [mm] of a SIMPACK .prr whose header asks for no
    shift, rotation or mirroring (true of MBench_UIC60_v3.prr)."""
    with open(path) as f:
        text = f.read()
    head, body = text.split("point.begin", 1)
    body = body.split("point.end", 1)[0]
    settings = {}
    for line in head.splitlines():
        line = line.split("!", 1)[0].strip()
        if "=" in line:
            k, v = (x.strip() for x in line.split("=", 1))
            settings[k] = v
    for key in ("shift.y", "shift.z", "rotate", "mirror.y", "mirror.z"):
        assert float(settings[key]) == 0.0, f"{path}: {key} = {settings[key]} is not handled here"
    assert float(settings["units.len.f"]) == 1000.0 and int(settings["type"]) == 0
    pts = []
    for line in body.splitlines():
        line = line.strip()
        if line and not line.startswith("!"):
            y, z = (float(v) for v in line.split()[:2])
            pts.append((y, -z))  # SIMPACK z points down
    pts.sort()
    assert all(b[0] > a[0] for a, b in zip(pts, pts[1:]))
    return pts


def interp(xs, ys, x):
    """Linear interpolation in sorted xs; None outside."""
    i = bisect.bisect_right(xs, x)
    if i == 0 or i == len(xs):
        return None
    t = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    return ys[i - 1] + t * (ys[i] - ys[i - 1])


def flange_contact(wheel, rail, y_split):
    """Lateral shift of the wheel towards its rail at which the flange
    touches (2-D rigid profiles, each wheel resting on its rail: the
    two-point contact of tread and flank).

    Placement as in the toolkit: rail's gauge point (GAUGE_POINT_DEPTH_MM
    below its top) at GAUGE/2 from the track centre, the wheel's taping line
    at FLANGE_BACK_DISTANCE/2 + 70 mm. Both profiles have the flange/gauge
    face at negative y and z up."""
    ry, rz = [p[0] for p in rail], [p[1] for p in rail]
    top = max(rz)
    y_top = ry[rz.index(top)]
    z_g = top - GAUGE_POINT_DEPTH_MM
    y_gp = None
    for (y0, z0), (y1, z1) in zip(rail, rail[1:]):
        if y1 < y_top and (z0 - z_g) * (z1 - z_g) <= 0 and z0 != z1:
            y_gp = y0 + (z_g - z0) / (z1 - z0) * (y1 - y0)
            break
    offset = FLANGE_BACK_DISTANCE_MM / 2.0 - Y_FLANGE_BACK_MM - GAUGE_MM / 2.0
    wy, wz = [p[0] for p in wheel], [p[1] for p in wheel]

    def gaps(dy):
        """Smallest vertical gap wheel - rail over the flange and the tread,
        with where it is (wheel y)."""
        shift = y_gp + offset + dy
        best = {True: (math.inf, None), False: (math.inf, None)}
        for y, z in wheel:  # wheel points over the rail
            r = interp(ry, rz, y + shift)
            if r is not None and z - r < best[y <= y_split][0]:
                best[y <= y_split] = (z - r, y)
        for y, z in rail:  # rail points under the wheel
            w = interp(wy, wz, y - shift)
            if w is not None and w - z < best[y - shift <= y_split][0]:
                best[y - shift <= y_split] = (w - z, y - shift)
        return best[True], best[False]

    lo, hi = 0.0, 20.0
    assert gaps(lo)[0][0] > gaps(lo)[1][0] and gaps(hi)[0][0] < gaps(hi)[1][0]
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        flange, tread = gaps(mid)
        if flange[0] > tread[0]:
            lo = mid
        else:
            hi = mid
    flange, tread = gaps(hi)
    y_f = flange[1]
    return dict(dy=0.5 * (lo + hi), y_gauge_point=y_gp, rail_top=top,
                flank_y=y_f, flank_z=interp(wy, wz, y_f), tread_y=tread[1],
                tread_y_centred=gaps(0.0)[1][1],
                rail_depth=top - interp(ry, rz, y_f + y_gp + offset + 0.5 * (lo + hi)))


def main():
    segs, joints, free0 = build_design()
    # With no ramps the curve is the design curve: a check of the integrator.
    r0 = residuals(free0, 0.0)
    assert max(abs(v) for v in r0) < 1e-9, r0
    free, r, iterations = solve(free0)
    curve = make_curve(free)
    pts, s_end = sample(curve)
    write_csv(pts)
    written = read_csv()
    flank_dev, tread_dev, max_dev, max_chord = check(written, curve, s_end, segs)

    def front_y(z):
        return curve.at(front_s_at_z(curve, z))[0]

    def back_y(z):
        return curve.at(_back_s_at_z(curve, z))[0]

    sd = front_y(Z_SD_MM) - Y_FLANGE_BACK_MM
    s14 = front_y(-GAUGE_POINT_DEPTH_MM) - Y_FLANGE_BACK_MM
    qr = front_y(Z_SD_MM) - front_y(-FLANGE_HEIGHT_MM + 2.0)
    thick = front_y(Z_SD_MM) - back_y(Z_SD_MM)
    half = lambda s: (GAUGE_MM - (FLANGE_BACK_DISTANCE_MM + 2.0 * s)) / 2.0
    _, tip = tip_lowest(curve)

    out = []
    p = out.append
    p("ML95-like wheel profile (tables/profiles/ml95_like/generate.py)")
    p(f"  output: {os.path.basename(OUTPUT)}, {len(written)} points, "
      f"y {written[0][0]:.3f} .. {written[-1][0]:.3f} mm, "
      f"z {min(z for _, z in written):.3f} .. {max(z for _, z in written):.3f} mm, max spacing {max_chord:.3f} mm")
    p(f"  nominal rolling radius at the taping line (wheelset parameter, not in the file): {NOMINAL_RADIUS_M} m")
    p(f"  tread 1:{1 / TREAD_SLOPE:g}; flank {FLANK_ANGLE_DEG:g} deg; flange height Sh = {-tip[1]:.6f} mm, "
      f"tip at y = {tip[0]:.6f} mm")
    p(f"  Sd (flank at z = {Z_SD_MM:g} from the flange-back plane y = {Y_FLANGE_BACK_MM:g}) = {sd:.6f} mm "
      f"(material thickness there {thick:.3f} mm)")
    p(f"  qR (Sd point to the flank 2 mm above the tip) = {qr:.3f} mm")
    p(f"  flank slope from the written points vs tan {FLANK_ANGLE_DEG:g} deg = {math.tan(PHI):.6f}: "
      f"max deviation {flank_dev:.1e}; tread slope vs 1/20: {tread_dev:.1e}")
    p("  design curve (G1; position and tangent-angle jumps at its "
      f"{len(joints)} joints <= {max(max(j[2], j[3]) for j in joints):.1e}):")
    for s in segs:
        extra = ""
        if s["kind"] == "arc":
            extra = f"  R {s['radius']:g}, centre ({s['centre'][0]:.6f}, {s['centre'][1]:.6f})"
        kind = "line" if s["kind"] == "line" else ("convex arc" if s["curvature"] > 0 else "concave arc")
        p(f"    {s['name']:9s} {kind:11s} ({s['start'][0]:10.6f}, {s['start'][1]:10.6f}) -> "
          f"({s['end'][0]:10.6f}, {s['end'][1]:10.6f})  {s['length']:6.3f} mm{extra}")
    p(f"  back arc meets tip arc at tangent angle {math.degrees(free0[1]):.3f} deg (design)")
    p(f"  curvature ramps: +-{BLEND_HALF_MM:g} mm of arc at each of the 7 curvature jumps; Newton "
      f"converged in {iterations} iterations (residuals <= {max(abs(v) for v in r):.0e} mm)")
    p(f"  written curve vs design curve: max distance {max_dev * 1000:.2f} um; "
      f"written arc centres: "
      + ", ".join(f"{part['name']} ({c[0]:.4f}, {c[1]:.4f})" for part, c in _centres(curve)))
    p(f"  flangeway clearance per side, gauge {GAUGE_MM:g} / flange backs {FLANGE_BACK_DISTANCE_MM:g}:")
    p(f"    at the Sd height (z = {Z_SD_MM:g}): {half(sd):.3f} mm")
    p(f"    at the gauge-point depth (z = {-GAUGE_POINT_DEPTH_MM:g}, flange {s14:.3f} mm thick): {half(s14):.3f} mm")
    if os.path.exists(RAIL_FILE):
        y_split = curve.const("throat")["p0"][0]
        fc = flange_contact(written, read_simpack_rail(RAIL_FILE), y_split)
        p(f"    2-D flange contact with {os.path.basename(RAIL_FILE)} (canted 1:40, rail inclination 0), "
          f"gauge point at {GAUGE_MM / 2:g} mm, taping lines at {FLANGE_BACK_DISTANCE_MM / 2 - Y_FLANGE_BACK_MM:g} mm:")
        p(f"      tread contact when centred at wheel y = {fc['tread_y_centred']:.2f} mm; the flank touches after a "
          f"lateral shift of {fc['dy']:.3f} mm")
        p(f"      at wheel (y, z) = ({fc['flank_y']:.2f}, {fc['flank_z']:.2f}) mm, {fc['rail_depth']:.2f} mm "
          f"below the top of rail (tread contact then at wheel y = {fc['tread_y']:.2f})")
        p(f"      Sd for a {TARGET_CLEARANCE_MM:g} mm shift: {SD_MM + fc['dy'] - TARGET_CLEARANCE_MM:.2f} mm "
          f"(the flank moves rigidly with Sd)")
    else:
        p(f"    (no 2-D flange-contact estimate: {RAIL_FILE} not found)")
    print("\n".join(out))


def _back_s_at_z(curve, z):
    """Arc length where the back of the flange (start to tip) is at height z."""
    s_tip, _ = tip_lowest(curve)
    lo, hi = 0.0, s_tip  # z decreases from the start to the tip
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if curve.at(mid)[1] > z:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _centres(curve):
    for part in curve.parts:
        if part["kind"] == "const" and part["k"] != 0.0 and part["name"] != "chamfer":
            n = normal(part["th0"])
            r = 1.0 / part["k"]
            yield part, (part["p0"][0] + r * n[0], part["p0"][1] + r * n[1])


if __name__ == "__main__":
    sys.exit(main())
