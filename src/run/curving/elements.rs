//! The track's elements from its centreline curvature: straights,
//! transitions and constant-curvature arcs, for the per-arc quasi-static
//! values and the shading of the curving plot.
//!
//! The rule (docs/guide/curving-and-safety.md, "Finding the arcs"), on the
//! signed horizontal curvature κ(s) of the centreline table:
//!
//! - **straight** where |κ| < [`STRAIGHT_FLOOR_1_M`] = 1e-4 1/m (R > 10 km:
//!   the quasi-static lateral acceleration v²/R stays below 0.08 m/s² at
//!   100 km/h, and a control-point spline's ringing on a straight stays
//!   well below it);
//! - each stretch between straights (of one sign of κ: a reverse curve is
//!   two stretches) has one **plateau** |κ|_p: the value with the most
//!   samples within [`PLATEAU_TOLERANCE`] = 5 % of it, refined to the
//!   median of those samples (a clothoid's linear
//!   κ spreads its samples, an arc's pile up; 5 % keeps a spline-built arc's
//!   ripple of a few per cent inside and a clothoid's last 5 % of its ramp
//!   outside);
//! - the **arc** is each run of samples within the tolerance of the
//!   plateau at least [`MIN_ARC_M`] = 10 m long (five 2 m windows: a
//!   shorter band is the top of a transition pair without an arc, e.g. the
//!   last 5 % of two 60 m clothoids meeting, 6 m); the rest of the stretch
//!   is **transition**. The arc so found includes the last 5 % of the
//!   curvature ramp of its transitions (3 m of a 60 m clothoid).
//!
//! A compound curve (two radii without a straight between) yields the arc
//! of its dominant radius; the other is reported as a transition.

use serde::Serialize;

/// |κ| below this is straight track (1/m; module docs).
pub const STRAIGHT_FLOOR_1_M: f64 = 1e-4;
/// Relative tolerance about the plateau curvature of an arc (module docs).
pub const PLATEAU_TOLERANCE: f64 = 0.05;
/// Shortest arc (m; module docs).
pub const MIN_ARC_M: f64 = 10.0;

/// Kind of a track element.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ElementKind {
    Straight,
    Transition,
    Arc,
}

impl ElementKind {
    /// The word for the text summary and the plot.
    pub fn text(self) -> &'static str {
        match self {
            ElementKind::Straight => "straight",
            ElementKind::Transition => "transition",
            ElementKind::Arc => "arc",
        }
    }
}

/// One element: [start, end] in track position s (m).
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct TrackElement {
    pub kind: ElementKind,
    pub start_s_m: f64,
    pub end_s_m: f64,
    /// Mean signed horizontal curvature over the element (1/m, + turning
    /// left).
    pub mean_curvature_1_m: f64,
    /// For an arc: its radius 1/|mean κ| (m), + for a left-hand curve.
    pub radius_m: Option<f64>,
}

/// The elements of the track whose centreline has curvature
/// `curvature_1_m[k]` at `s_m[k]` (increasing), in order and contiguous
/// (each ends where the next starts). Non-finite curvatures count as
/// straight.
pub fn find_elements(s_m: &[f64], curvature_1_m: &[f64]) -> Vec<TrackElement> {
    let n = s_m.len().min(curvature_1_m.len());
    let k = |i: usize| {
        let v = curvature_1_m[i];
        if v.is_finite() { v } else { 0.0 }
    };
    let mut kinds = vec![ElementKind::Straight; n];
    let mut i = 0;
    while i < n {
        if k(i).abs() < STRAIGHT_FLOOR_1_M {
            i += 1;
            continue;
        }
        // A stretch of one sign between straights.
        let sign = k(i).signum();
        let mut j = i;
        while j < n && k(j).abs() >= STRAIGHT_FLOOR_1_M && k(j).signum() == sign {
            j += 1;
        }
        let plateau = plateau(&(i..j).map(|m| k(m).abs()).collect::<Vec<_>>());
        let near = |m: usize| (k(m).abs() - plateau).abs() <= PLATEAU_TOLERANCE * plateau;
        let mut m = i;
        while m < j {
            let from = m;
            let on = near(m);
            while m < j && near(m) == on {
                m += 1;
            }
            let long = s_m[(m).min(n - 1)] - s_m[from] >= MIN_ARC_M
                || (m == n && s_m[n - 1] - s_m[from] >= MIN_ARC_M);
            let kind = if on && long {
                ElementKind::Arc
            } else {
                ElementKind::Transition
            };
            kinds[from..m].fill(kind);
        }
        i = j;
    }
    // Runs of one kind become elements.
    let mut out: Vec<TrackElement> = Vec::new();
    let mut i = 0;
    while i < n {
        let mut j = i;
        while j < n && kinds[j] == kinds[i] {
            j += 1;
        }
        let mean = (i..j).map(k).sum::<f64>() / (j - i) as f64;
        out.push(TrackElement {
            kind: kinds[i],
            start_s_m: s_m[i],
            end_s_m: s_m[j.min(n - 1)],
            mean_curvature_1_m: mean,
            radius_m: (kinds[i] == ElementKind::Arc).then(|| 1.0 / mean),
        });
        i = j;
    }
    out
}

/// The plateau of `v` (all > 0): the median of the values within the
/// tolerance of the value that has the most of them (the larger on a tie;
/// the median, so that a band reaching down a transition's ramp does not
/// pull the plateau below the arc's value).
fn plateau(v: &[f64]) -> f64 {
    let mut sorted = v.to_vec();
    sorted.sort_by(f64::total_cmp);
    let (mut best, mut best_count) = (0, 0);
    let (mut lo, mut hi) = (0, 0);
    for &c in &sorted {
        while sorted[lo] < c * (1.0 - PLATEAU_TOLERANCE) {
            lo += 1;
        }
        while hi < sorted.len() && sorted[hi] <= c * (1.0 + PLATEAU_TOLERANCE) {
            hi += 1;
        }
        if hi - lo >= best_count {
            (best, best_count) = (lo, hi - lo);
        }
    }
    match sorted.get(best..best + best_count) {
        Some(band) if !band.is_empty() => band[band.len() / 2],
        _ => sorted.last().copied().unwrap_or(0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Straight 0–50, clothoid 50–110 to 1/300, arc 110–260, clothoid
    /// 260–320, straight 320–370, then a reverse arc R 500 m 370–400 with
    /// 0.5 % ripple (a spline-built arc), sampled every 0.5 m.
    fn curve() -> (Vec<f64>, Vec<f64>) {
        let s: Vec<f64> = (0..=800).map(|k| 0.5 * f64::from(k)).collect();
        let k = s
            .iter()
            .map(|&s| {
                let c = 1.0 / 300.0;
                match s {
                    s if s < 50.0 => 1e-6,
                    s if s < 110.0 => c * (s - 50.0) / 60.0,
                    s if s < 260.0 => c,
                    s if s < 320.0 => c * (320.0 - s) / 60.0,
                    s if s < 370.0 => 0.0,
                    s => -(1.0 + 0.005 * (s * 0.7).sin()) / 500.0,
                }
            })
            .collect();
        (s, k)
    }

    #[test]
    fn straight_transition_arc_are_found_from_the_curvature() {
        let (s, k) = curve();
        let e = find_elements(&s, &k);
        let kinds: Vec<_> = e.iter().map(|e| e.kind).collect();
        use ElementKind::*;
        assert_eq!(
            kinds,
            [Straight, Transition, Arc, Transition, Straight, Arc],
            "{e:#?}"
        );
        // The clothoid's first 1e-4·300·60 = 1.8 m are below the floor;
        // the arc is where κ is within 5 % of 1/300: the last 3 m of the
        // clothoids belong to it.
        assert_eq!(e[1].start_s_m, 52.0);
        // (107 m and 263 m are on the 5 % boundary itself.)
        assert!((107.0..=107.5).contains(&e[2].start_s_m), "{:?}", e[2]);
        assert!((263.0..=263.5).contains(&e[2].end_s_m), "{:?}", e[2]);
        assert!((e[2].radius_m.unwrap() - 300.0).abs() < 3.0, "{:?}", e[2]);
        assert!((e[5].radius_m.unwrap() + 500.0).abs() < 1.0, "{:?}", e[5]);
        assert_eq!(e[5].end_s_m, 400.0);
        // Contiguous.
        for p in e.windows(2) {
            assert_eq!(p[0].end_s_m, p[1].start_s_m);
        }
    }

    #[test]
    fn no_arc_without_a_plateau_and_no_panic_on_odd_input() {
        // Two 60 m clothoids meeting at 1/300 without an arc: the band
        // within 5 % of the top is 6 m long, shorter than an arc.
        let s: Vec<f64> = (0..=240).map(|k| 0.5 * f64::from(k)).collect();
        let k: Vec<f64> = s
            .iter()
            .map(|s| (60.0 - (s - 60.0).abs()) / 60.0 / 300.0)
            .collect();
        let e = find_elements(&s, &k);
        assert!(e.iter().all(|e| e.kind != ElementKind::Arc), "{e:#?}");
        assert!(find_elements(&[], &[]).is_empty());
        let e = find_elements(&[0.0, 1.0], &[f64::NAN, f64::INFINITY]);
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].kind, ElementKind::Straight);
    }
}
