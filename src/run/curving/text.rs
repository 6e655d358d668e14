//! The text form of the curving, safety and wear figures (what `sim run`
//! prints under the Nadal lines).

use super::CurvingSummary;
use super::arcs::ArcSummary;
use super::safety::{SafetyVerdict, WheelsetSafety};

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".to_string(), |v| format!("{v:.digits$}"))
}

fn verdict(v: SafetyVerdict) -> String {
    format!(" — {}", v.text())
}

/// Two lines per wheelset: ΣY against Prud'homme with P, then ΔQ/Q0, the
/// angle of attack and Tγ of each wheel.
pub fn safety_text(name: &str, s: &WheelsetSafety) -> String {
    let p = &s.prudhomme;
    let mut t = format!(
        "  wheelset {name}: ΣY max {} kN, 2 m mean max {} kN against {} kN (P = {} kN, {} of {} samples){} [{}]\n",
        opt(p.max_abs_sum_y_kn, 2),
        opt(p.max_abs_sum_y_2m_kn, 2),
        opt(p.limit_kn, 2),
        opt(s.static_axle_load_kn, 2),
        s.static_load_source,
        s.static_load_samples,
        verdict(p.verdict),
        p.criterion,
    );
    t += &format!("  wheelset {name}: ΔQ/Q0");
    for (k, u) in s.unloading.iter().enumerate() {
        t += &format!(
            "{} {} max {}, 2 m mean max {}{}",
            if k == 0 { "" } else { ";" },
            u.wheel,
            opt(u.max_delta_q_over_q0, 3),
            opt(u.max_delta_q_over_q0_2m, 3),
            verdict(u.verdict),
        );
    }
    t += &format!(
        " [{}]; angle of attack max {} mrad (+ nose left); Tγ",
        s.unloading.first().map_or("", |u| u.criterion),
        opt(s.max_angle_of_attack_mrad, 2)
    );
    for (k, w) in s.wear.iter().enumerate() {
        t += &format!(
            "{} {} mean {} N, max {} N",
            if k == 0 { "" } else { ";" },
            w.wheel,
            opt(w.mean_wear_number_n, 1),
            opt(w.max_wear_number_n, 1)
        );
    }
    t + "\n"
}

/// The track's elements on one line, then per arc and wheelset the
/// quasi-static values (50 %) and the 99.85 % (or 0.15 %, whichever is
/// larger in magnitude) of the 2 m means.
pub fn curving_text(c: &CurvingSummary) -> String {
    if c.track_elements.is_empty() {
        return String::new();
    }
    let mut t = format!("  track elements ({}):", c.track_elements_source.text());
    for e in &c.track_elements {
        t += &format!(
            " {} {:.1}–{:.1} m{};",
            e.kind.text(),
            e.start_s_m,
            e.end_s_m,
            e.radius_m
                .map_or(String::new(), |r| format!(" (R {r:.0} m)"))
        );
    }
    t.pop();
    t += "\n";
    for a in &c.arcs {
        t += &arc_text(a);
    }
    t
}

fn arc_text(a: &ArcSummary) -> String {
    let cant = if a.cant_mm.is_finite() && a.cant_deficiency_mm.is_finite() {
        format!(
            ", cant {:.0} mm, cant deficiency {:.0} mm",
            a.cant_mm, a.cant_deficiency_mm
        )
    } else {
        String::new()
    };
    let mut t = format!(
        "  arc {:.1}–{:.1} m (R {:.0} m{cant}), quasi-static (50 %) / extreme 2 m mean (0.15 or 99.85 %):\n",
        a.start_s_m, a.end_s_m, a.radius_m
    );
    for w in &a.wheelsets {
        t += &format!("    wheelset {} (covers {:.1} m):", w.name, w.covered_m);
        for q in w.quantities.iter().filter(|q| q.quantity != "speed") {
            let extreme = match (q.low_2m, q.high_2m) {
                (Some(l), Some(h)) => Some(if l.abs() > h.abs() { l } else { h }),
                _ => None,
            };
            let units = if q.units == "1" {
                String::new()
            } else {
                format!(" {}", q.units)
            };
            t += &format!(
                " {} {}/{}{units};",
                q.quantity,
                opt(q.quasi_static, 3),
                opt(extreme, 3),
            );
        }
        t.pop();
        t += "\n";
    }
    t
}

#[cfg(test)]
mod tests {
    use super::super::arcs::{ArcWheelset, QuasiStatic};
    use super::*;

    #[test]
    fn an_arc_line_gives_the_larger_extreme_and_units() {
        let q = |quantity, units, low, high| QuasiStatic {
            quantity,
            units,
            samples: 10,
            quasi_static: Some(1.0),
            windows: 5,
            low_2m: Some(low),
            high_2m: Some(high),
        };
        let a = ArcSummary {
            start_s_m: 107.1,
            end_s_m: 263.0,
            radius_m: 300.0,
            cant_mm: f64::NAN,
            cant_deficiency_mm: f64::NAN,
            wheelsets: vec![ArcWheelset {
                name: "front".into(),
                covered_m: 155.8,
                quantities: vec![
                    q("sum_y", "kN", -12.0, 11.0),
                    q("y_over_q_left", "1", 0.2, 0.4),
                    q("speed", "m/s", 20.0, 20.0),
                ],
            }],
        };
        let mut c = CurvingSummary {
            track_elements: vec![],
            arcs: vec![a],
            ..Default::default()
        };
        // No elements: nothing to print.
        assert_eq!(curving_text(&c), "");
        let t = arc_text(&c.arcs[0]);
        assert!(t.contains("arc 107.1–263.0 m (R 300 m)"), "{t}");
        assert!(t.contains("sum_y 1.000/-12.000 kN;"), "{t}");
        assert!(t.contains("y_over_q_left 1.000/0.400\n"), "{t}");
        assert!(!t.contains("speed"), "{t}");
        // The element line names where the elements come from.
        c.track_elements = vec![crate::run::curving::TrackElement {
            kind: crate::run::curving::ElementKind::Straight,
            start_s_m: 0.0,
            end_s_m: 10.0,
            mean_curvature_1_m: 0.0,
            radius_m: None,
        }];
        let t = curving_text(&c);
        assert!(
            t.starts_with("  track elements (from the curvature): straight 0.0–10.0 m\n"),
            "{t}"
        );
        c.track_elements_source = crate::run::curving::ElementSource::DesignFile;
        assert!(curving_text(&c).starts_with("  track elements (design file): straight"));
    }
}
