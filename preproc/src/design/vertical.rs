//! The vertical profile: constant grades and parabolic vertical curves
//! along the plan distance σ (docs/reference/03-track-preproc.md §3h). On
//! a vertical curve the grade g = dz/dσ runs linearly from g₀ to g₁ (the
//! parabola z = z₀ + g₀τ + (g₁ − g₀)τ²/(2L) of railway and road design;
//! Lindahl 2001 §2.5; EN 13803 §6.5 gives its radius R_v = L/|g₁ − g₀|).
//! The track distance s is the 3D arc length,
//! s(σ) = ∫ √(1 + g²) dσ, closed form: with u = g(σ),
//! ∫ √(1 + u²) du = ½(u√(1 + u²) + asinh u).

/// One vertical element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerticalElement {
    /// Plan distance at its start (m).
    pub sigma_start_m: f64,
    pub length_m: f64,
    pub z_start_m: f64,
    /// Grade dz/dσ at the start and end (m/m).
    pub grade_start: f64,
    pub grade_end: f64,
}

/// Height, grade and its rate at one σ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerticalPoint {
    pub z_m: f64,
    /// dz/dσ.
    pub grade: f64,
    /// d²z/dσ² (1/m).
    pub grade_rate_1_m: f64,
}

fn h(u: f64) -> f64 {
    0.5 * (u * (1.0 + u * u).sqrt() + u.asinh())
}

impl VerticalElement {
    fn rate(&self) -> f64 {
        (self.grade_end - self.grade_start) / self.length_m
    }

    /// At τ = σ − σ₀ ∈ [0, L].
    pub fn at(&self, tau_m: f64) -> VerticalPoint {
        let k = self.rate();
        VerticalPoint {
            z_m: self.z_start_m + self.grade_start * tau_m + 0.5 * k * tau_m * tau_m,
            grade: self.grade_start + k * tau_m,
            grade_rate_1_m: k,
        }
    }

    /// 3D arc length from the start to τ (m), closed form.
    pub fn arc_length(&self, tau_m: f64) -> f64 {
        let k = self.rate();
        let g0 = self.grade_start;
        if k == 0.0 {
            tau_m * (1.0 + g0 * g0).sqrt()
        } else {
            (h(g0 + k * tau_m) - h(g0)) / k
        }
    }

    /// τ at the arc length `s_m` from the start (Newton; ds/dτ ≥ 1).
    pub fn tau_at(&self, s_m: f64) -> f64 {
        let mut tau = s_m / (1.0 + self.grade_start.powi(2)).sqrt();
        for _ in 0..50 {
            let g = self.at(tau).grade;
            let step = (self.arc_length(tau) - s_m) / (1.0 + g * g).sqrt();
            tau -= step;
            if step.abs() < 1e-14 * (1.0 + s_m) {
                break;
            }
        }
        tau
    }
}

/// The whole profile, with the arc length at each element's start.
#[derive(Debug, Clone, PartialEq)]
pub struct Vertical {
    elements: Vec<VerticalElement>,
    s_start_m: Vec<f64>,
}

impl Vertical {
    /// Elements in order, each starting where the previous ends.
    pub fn new(elements: Vec<VerticalElement>) -> Self {
        let mut s_start_m = Vec::with_capacity(elements.len());
        let mut s = 0.0;
        for e in &elements {
            s_start_m.push(s);
            s += e.arc_length(e.length_m);
        }
        Self {
            elements,
            s_start_m,
        }
    }

    /// Total 3D arc length (m).
    pub fn length_m(&self) -> f64 {
        self.elements
            .last()
            .zip(self.s_start_m.last())
            .map_or(0.0, |(e, s)| s + e.arc_length(e.length_m))
    }

    fn index_by<F: Fn(usize) -> f64>(&self, v: f64, start: F) -> usize {
        (0..self.elements.len())
            .rev()
            .find(|&k| start(k) <= v)
            .unwrap_or(0)
    }

    /// The plan distance σ at track distance s (m).
    pub fn sigma_at(&self, s_m: f64) -> f64 {
        let k = self.index_by(s_m, |k| self.s_start_m[k]);
        let e = &self.elements[k];
        e.sigma_start_m + e.tau_at(s_m - self.s_start_m[k])
    }

    /// The track distance at σ (m).
    pub fn s_at(&self, sigma_m: f64) -> f64 {
        let k = self.index_by(sigma_m, |k| self.elements[k].sigma_start_m);
        let e = &self.elements[k];
        self.s_start_m[k] + e.arc_length(sigma_m - e.sigma_start_m)
    }

    /// Height and grade at σ.
    pub fn at(&self, sigma_m: f64) -> VerticalPoint {
        let k = self.index_by(sigma_m, |k| self.elements[k].sigma_start_m);
        let e = &self.elements[k];
        e.at(sigma_m - e.sigma_start_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// s(σ) of a vertical curve agrees with Simpson's rule, and σ(s)
    /// inverts it.
    #[test]
    fn arc_length_and_its_inverse() {
        let e = VerticalElement {
            sigma_start_m: 0.0,
            length_m: 200.0,
            z_start_m: 0.0,
            grade_start: -0.02,
            grade_end: 0.015,
        };
        let n = 2000;
        let f = |t: f64| (1.0 + e.at(t).grade.powi(2)).sqrt();
        let simpson: f64 = (0..n)
            .map(|i| {
                let (a, b) = (
                    200.0 * i as f64 / n as f64,
                    200.0 * (i + 1) as f64 / n as f64,
                );
                (b - a) / 6.0 * (f(a) + 4.0 * f(0.5 * (a + b)) + f(b))
            })
            .sum();
        assert!((e.arc_length(200.0) - simpson).abs() < 1e-11);
        let v = Vertical::new(vec![e]);
        for s in [0.0, 13.0, 100.0, 200.0] {
            assert!((v.s_at(v.sigma_at(s)) - s).abs() < 1e-11);
        }
    }
}
