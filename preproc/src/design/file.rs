//! The design file (TOML; docs/reference/02-inputs.md §2.9): the track as a
//! list of plan elements with their lengths, radii and cant at the ends,
//! and an optional vertical profile — parsed, and checked against the
//! continuity rules and the plausibility bounds of [`crate::bounds`].
//! Every error names the file, line and column of the value (toml spans).
//!
//! Continuity rules (docs/reference/03-track-preproc.md §3h):
//! - an element starts with the curvature the previous one ends with; a
//!   stated start (`radius_start_m`, or the radius of an arc or straight)
//!   that differs is refused, unless the element says `jump = true` (a
//!   curvature step, as on tram track and in yards: the position and
//!   heading stay continuous, the curvature steps);
//! - the cant never steps (a step is a vertical step of a rail): a stated
//!   start cant must be the previous end cant;
//! - the grade never breaks: a `grade` element must continue the previous
//!   grade; grades change on vertical `curve`s.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use super::cant::{CantRamp, CantUnit};
use super::shape::Ramp;
use crate::bounds::{
    MAX_CANT_ON_STANDARD_BASE_MM, MAX_CANT_RAD, MAX_COORDINATE_M, MAX_DESIGN_LENGTH_M,
    MAX_GRADE_PERMILLE, MIN_CURVE_RADIUS_M, MIN_NONZERO_GRADE_PERMILLE, MIN_PEAK_CANT_MM,
};
use crate::centerline::COVERAGE_TOLERANCE_M;
use crate::error::InputError;

/// Two curvatures (1/m) this close are equal at a joint (a radius of
/// 600 m written as 600.0000001).
const SAME_CURVATURE_1_M: f64 = 1e-12;
/// Two cants (rad) this close are equal at a joint.
const SAME_CANT_RAD: f64 = 1e-9;

/// The transition shapes of a design file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransitionShape {
    /// Curvature running along s with the shape of the ramp (clothoid:
    /// linear; Bloss; cosine).
    Ramp(Ramp),
    /// y = c·x³ from or to a straight.
    CubicParabola,
}

/// What an element is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ElementKind {
    Straight,
    Arc,
    Transition(TransitionShape),
}

/// One plan element as the file gives it, with the joint values resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementSpec {
    pub kind: ElementKind,
    pub length_m: f64,
    /// Signed curvature at the start and end (1/m; > 0 turning left).
    pub kappa_start_1_m: f64,
    pub kappa_end_1_m: f64,
    pub cant: CantRamp,
    /// 1-based line of the element's `[[element]]` header.
    pub line: usize,
}

/// One vertical element (grades in m/m).
#[derive(Debug, Clone, PartialEq)]
pub struct VerticalSpec {
    pub length_m: f64,
    pub grade_start: f64,
    pub grade_end: f64,
    pub line: usize,
}

/// Where the track starts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Start {
    pub x_m: f64,
    pub y_m: f64,
    pub z_m: f64,
    pub heading_rad: f64,
}

/// A parsed and checked design file.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignInput {
    pub path: PathBuf,
    pub title: Option<String>,
    pub start: Start,
    pub elements: Vec<ElementSpec>,
    /// Empty: level track at the start height.
    pub vertical: Vec<VerticalSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    title: Option<String>,
    start: Option<RawStart>,
    #[serde(default)]
    element: Vec<Spanned<RawElement>>,
    #[serde(default)]
    vertical: Vec<Spanned<RawVertical>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStart {
    x_m: Option<Spanned<f64>>,
    y_m: Option<Spanned<f64>>,
    z_m: Option<Spanned<f64>>,
    heading_deg: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawElement {
    #[serde(rename = "type")]
    kind: Spanned<String>,
    length_m: Spanned<f64>,
    shape: Option<Spanned<String>>,
    radius_m: Option<Spanned<f64>>,
    radius_start_m: Option<Spanned<f64>>,
    radius_end_m: Option<Spanned<f64>>,
    jump: Option<bool>,
    cant_mm: Option<Spanned<f64>>,
    cant_start_mm: Option<Spanned<f64>>,
    cant_end_mm: Option<Spanned<f64>>,
    cant_rad: Option<Spanned<f64>>,
    cant_start_rad: Option<Spanned<f64>>,
    cant_end_rad: Option<Spanned<f64>>,
    cant_ramp: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawVertical {
    #[serde(rename = "type")]
    kind: Spanned<String>,
    length_m: Spanned<f64>,
    grade_permille: Option<Spanned<f64>>,
    grade_end_permille: Option<Spanned<f64>>,
}

/// Line and column (1-based; the column counts characters) of a byte
/// offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Errors at spans of one file.
struct Errors<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Errors<'_> {
    fn at(&self, span: Range<usize>, rule: impl Into<String>) -> InputError {
        let (line, column) = line_column(self.text, span.start);
        InputError::at_value(self.path, line, column, rule)
    }

    fn line(&self, span: &Range<usize>) -> usize {
        line_column(self.text, span.start).0
    }
}

/// A cant value of an element with its unit and where it is.
struct CantValue {
    unit: CantUnit,
    /// m (height) or rad.
    value: f64,
    span: Range<usize>,
}

impl DesignInput {
    /// Parse and check a design file; `cant_base_m` (e0) converts cant
    /// heights to angles, φ = asin(h/e0).
    pub fn parse(path: &Path, text: &str, cant_base_m: f64) -> Result<Self, InputError> {
        let err = Errors { path, text };
        let raw: RawFile = toml::from_str(text).map_err(|e| match e.span() {
            Some(span) => err.at(span, e.message().to_string()),
            None => InputError::new(path, None, e.message().to_string()),
        })?;
        if raw.element.is_empty() {
            return Err(InputError::new(
                path,
                None,
                "a design file needs at least one [[element]] (type = \"straight\", \"arc\" or \"transition\")",
            ));
        }
        let start = match &raw.start {
            None => Start::default(),
            Some(s) => {
                let coord = |v: &Option<Spanned<f64>>, key: &str| -> Result<f64, InputError> {
                    match v {
                        None => Ok(0.0),
                        Some(v) if v.get_ref().abs() <= MAX_COORDINATE_M => Ok(*v.get_ref()),
                        Some(v) => Err(err.at(
                            v.span(),
                            format!(
                                "[start] {key} = {} m is beyond ±{MAX_COORDINATE_M:e} m, more than any map coordinate (check the unit: metres)",
                                v.get_ref()
                            ),
                        )),
                    }
                };
                let heading_deg = match &s.heading_deg {
                    None => 0.0,
                    Some(h) if h.get_ref().is_finite() => *h.get_ref(),
                    Some(h) => return Err(err.at(h.span(), "[start] heading_deg must be finite")),
                };
                Start {
                    x_m: coord(&s.x_m, "x_m")?,
                    y_m: coord(&s.y_m, "y_m")?,
                    z_m: coord(&s.z_m, "z_m")?,
                    heading_rad: heading_deg.to_radians(),
                }
            }
        };
        let mut elements: Vec<ElementSpec> = Vec::with_capacity(raw.element.len());
        for e in &raw.element {
            let prev = elements.last();
            elements.push(element(&err, e, prev, cant_base_m)?);
        }
        let total: f64 = elements.iter().map(|e| e.length_m).sum();
        if total > MAX_DESIGN_LENGTH_M {
            return Err(InputError::new(
                path,
                None,
                format!(
                    "the elements add up to {total:e} m, beyond the {MAX_DESIGN_LENGTH_M:e} m of the longest railway line (check the unit: metres)"
                ),
            ));
        }
        let vertical = vertical(&err, &raw.vertical, total)?;
        Ok(Self {
            path: path.to_path_buf(),
            title: raw.title,
            start,
            elements,
            vertical,
        })
    }

    /// Plan length of the track (m).
    pub fn plan_length_m(&self) -> f64 {
        self.elements.iter().map(|e| e.length_m).sum()
    }
}

fn length(err: &Errors, v: &Spanned<f64>, what: &str) -> Result<f64, InputError> {
    let l = *v.get_ref();
    if l.is_finite() && l > 0.0 && l <= MAX_DESIGN_LENGTH_M {
        Ok(l)
    } else {
        Err(err.at(
            v.span(),
            format!(
                "{what} length_m = {l} must lie in (0, {MAX_DESIGN_LENGTH_M:e}] m, the longest railway line (check the unit: metres)"
            ),
        ))
    }
}

/// Signed curvature of a radius key (1/m): `inf` for a straight.
fn curvature(
    err: &Errors,
    v: &Spanned<f64>,
    key: &str,
    infinite_ok: bool,
) -> Result<f64, InputError> {
    let r = *v.get_ref();
    if r.is_infinite() && infinite_ok {
        return Ok(0.0);
    }
    if !r.is_finite() || r.abs() < MIN_CURVE_RADIUS_M {
        return Err(err.at(
            v.span(),
            format!(
                "{key} = {r} m: a radius must be at least {MIN_CURVE_RADIUS_M} m in magnitude, the tightest tram curves{} (check the unit: metres; + turns left, − right)",
                if infinite_ok { "; write inf for a straight" } else { "" }
            ),
        ));
    }
    Ok(1.0 / r)
}

fn cant_value(
    err: &Errors,
    mm: &Option<Spanned<f64>>,
    rad: &Option<Spanned<f64>>,
    keys: (&str, &str),
    cant_base_m: f64,
) -> Result<Option<CantValue>, InputError> {
    match (mm, rad) {
        (Some(_), Some(r)) => Err(err.at(
            r.span(),
            format!("{} and {} both given; keep one", keys.0, keys.1),
        )),
        (Some(h), None) => {
            let v = *h.get_ref();
            let bad = |rule: String| Err(err.at(h.span(), format!("{} = {v} mm: {rule}", keys.0)));
            if !v.is_finite() {
                return bad("not a number".into());
            }
            if v != 0.0 && v.abs() < MIN_PEAK_CANT_MM {
                return bad(format!(
                    "below the {MIN_PEAK_CANT_MM} mm of any real cant: these are metres in a millimetre key (check the unit: write 120 for 120 mm)"
                ));
            }
            if v.abs() * 1e-3 >= cant_base_m || (v * 1e-3 / cant_base_m).asin().abs() > MAX_CANT_RAD
            {
                return bad(format!(
                    "beyond the ±{MAX_CANT_RAD:.4} rad of any track ({MAX_CANT_ON_STANDARD_BASE_MM} mm on the standard cant base 1.5 m; EN 13803 allows 180 mm) on the cant base {cant_base_m} m (check the unit: mm)"
                ));
            }
            Ok(Some(CantValue {
                unit: CantUnit::Height { cant_base_m },
                value: v * 1e-3,
                span: h.span(),
            }))
        }
        (None, Some(r)) => {
            let v = *r.get_ref();
            if !v.is_finite() || v.abs() > MAX_CANT_RAD {
                return Err(err.at(
                    r.span(),
                    format!(
                        "{} = {v} rad is beyond the ±{MAX_CANT_RAD:.4} rad of any track ({MAX_CANT_ON_STANDARD_BASE_MM} mm on the standard cant base 1.5 m): check the unit ({} is in rad, {} in mm)",
                        keys.1, keys.1, keys.0
                    ),
                ));
            }
            Ok(Some(CantValue {
                unit: CantUnit::Angle,
                value: v,
                span: r.span(),
            }))
        }
        (None, None) => Ok(None),
    }
}

fn element(
    err: &Errors,
    e: &Spanned<RawElement>,
    prev: Option<&ElementSpec>,
    cant_base_m: f64,
) -> Result<ElementSpec, InputError> {
    let span = e.span();
    let r = e.get_ref();
    let line = err.line(&span);
    let kind_name = r.kind.get_ref().as_str();
    let shape_name = r.shape.as_ref().map(|s| s.get_ref().as_str());
    let forbid = |v: &Option<Spanned<f64>>, key: &str| -> Result<(), InputError> {
        match v {
            Some(v) => Err(err.at(
                v.span(),
                format!("{key} does not belong to a {kind_name} element"),
            )),
            None => Ok(()),
        }
    };
    let kind = match kind_name {
        "straight" => ElementKind::Straight,
        "arc" => ElementKind::Arc,
        "transition" => ElementKind::Transition(match shape_name.unwrap_or("clothoid") {
            "clothoid" => TransitionShape::Ramp(Ramp::Linear),
            "bloss" => TransitionShape::Ramp(Ramp::Bloss),
            "cosine" => TransitionShape::Ramp(Ramp::Cosine),
            "cubic-parabola" => TransitionShape::CubicParabola,
            other => {
                return Err(err.at(
                    r.shape.as_ref().map_or(span.clone(), Spanned::span),
                    format!(
                        "shape = \"{other}\": a transition is \"clothoid\", \"cubic-parabola\", \"bloss\" or \"cosine\""
                    ),
                ));
            }
        }),
        other => {
            return Err(err.at(
                r.kind.span(),
                format!(
                    "type = \"{other}\": an element is \"straight\", \"arc\" or \"transition\""
                ),
            ));
        }
    };
    if let (Some(s), false) = (&r.shape, matches!(kind, ElementKind::Transition(_))) {
        return Err(err.at(
            s.span(),
            format!("shape belongs to transitions, not to a {kind_name}"),
        ));
    }
    let length_m = length(err, &r.length_m, kind_name)?;
    let prev_kappa = prev.map(|p| p.kappa_end_1_m);
    // The start curvature the element states, with where, and its end.
    let (stated, kappa_end_1_m) = match kind {
        ElementKind::Straight => {
            forbid(&r.radius_m, "radius_m")?;
            forbid(&r.radius_start_m, "radius_start_m")?;
            forbid(&r.radius_end_m, "radius_end_m")?;
            (Some((0.0, r.kind.span())), 0.0)
        }
        ElementKind::Arc => {
            forbid(&r.radius_start_m, "radius_start_m")?;
            forbid(&r.radius_end_m, "radius_end_m")?;
            let radius = r.radius_m.as_ref().ok_or_else(|| {
                err.at(span.clone(), "an arc needs radius_m (signed: + turns left)")
            })?;
            let k = curvature(err, radius, "radius_m", false)?;
            (Some((k, radius.span())), k)
        }
        ElementKind::Transition(_) => {
            forbid(&r.radius_m, "radius_m")?;
            let end = r.radius_end_m.as_ref().ok_or_else(|| {
                err.at(
                    span.clone(),
                    "a transition needs radius_end_m (signed: + turns left; inf ends on a straight)",
                )
            })?;
            let start = match &r.radius_start_m {
                Some(v) => Some((curvature(err, v, "radius_start_m", true)?, v.span())),
                None => None,
            };
            (start, curvature(err, end, "radius_end_m", true)?)
        }
    };
    let kappa_start_1_m = match (stated, prev_kappa) {
        (Some((k, at)), Some(p)) if (k - p).abs() > SAME_CURVATURE_1_M && r.jump != Some(true) => {
            return Err(err.at(
                at,
                format!(
                    "this element starts with the curvature {k:.6e} 1/m (radius {}) but the previous one ends with {p:.6e} 1/m (radius {}): put a transition between them, or write jump = true for a curvature step",
                    radius_text(k),
                    radius_text(p)
                ),
            ));
        }
        (Some((k, _)), _) => k,
        (None, Some(p)) => p,
        (None, None) => 0.0,
    };
    if let ElementKind::Transition(shape) = kind {
        if (kappa_end_1_m - kappa_start_1_m).abs() <= SAME_CURVATURE_1_M {
            return Err(err.at(
                span.clone(),
                format!(
                    "a transition from radius {} to radius {} changes nothing: use a straight or an arc",
                    radius_text(kappa_start_1_m),
                    radius_text(kappa_end_1_m)
                ),
            ));
        }
        if shape == TransitionShape::CubicParabola && kappa_start_1_m != 0.0 && kappa_end_1_m != 0.0
        {
            return Err(err.at(
                r.shape.as_ref().map_or(span.clone(), Spanned::span),
                "a cubic parabola runs from or to a straight (radius inf at one end); between two arcs use a clothoid, bloss or cosine transition",
            ));
        }
    }

    // Cant.
    let constant = cant_value(
        err,
        &r.cant_mm,
        &r.cant_rad,
        ("cant_mm", "cant_rad"),
        cant_base_m,
    )?;
    let start = cant_value(
        err,
        &r.cant_start_mm,
        &r.cant_start_rad,
        ("cant_start_mm", "cant_start_rad"),
        cant_base_m,
    )?;
    let end = cant_value(
        err,
        &r.cant_end_mm,
        &r.cant_end_rad,
        ("cant_end_mm", "cant_end_rad"),
        cant_base_m,
    )?;
    if let (Some(c), true) = (&constant, start.is_some() || end.is_some()) {
        return Err(err.at(
            c.span.clone(),
            "give either a constant cant (cant_mm / cant_rad) or a ramp (cant_start_*, cant_end_*), not both",
        ));
    }
    let stated_start = constant.as_ref().or(start.as_ref());
    let stated_end = constant.as_ref().or(end.as_ref());
    let prev_cant = prev.map(|p| (CantRamp::angle_of(p.cant.unit, p.cant.end), p.cant));
    let unit = stated_end
        .or(stated_start)
        .map(|c| c.unit)
        .or(prev.map(|p| p.cant.unit))
        .unwrap_or(CantUnit::Height { cant_base_m });
    if let (Some(a), Some(b)) = (stated_start, stated_end)
        && a.unit != b.unit
    {
        return Err(err.at(
            b.span.clone(),
            "the cant of one element is given in one unit: both ends in mm or both in rad",
        ));
    }
    // The start value in the element's unit.
    let start_value = match (stated_start, prev_cant) {
        (Some(c), Some((phi, _))) => {
            let own = CantRamp::angle_of(c.unit, c.value);
            if (own - phi).abs() > SAME_CANT_RAD {
                return Err(err.at(
                    c.span.clone(),
                    format!(
                        "the cant steps from {phi:.6} rad ({:.1} mm) at the end of the previous element to {own:.6} rad ({:.1} mm) here: a cant changes along a ramp (cant_end_mm on the element before), never in a step",
                        cant_base_m * phi.sin() * 1e3,
                        cant_base_m * own.sin() * 1e3
                    ),
                ));
            }
            c.value
        }
        (Some(c), None) => c.value,
        (None, Some((phi, _))) => match unit {
            CantUnit::Height { cant_base_m } => cant_base_m * phi.sin(),
            CantUnit::Angle => phi,
        },
        (None, None) => 0.0,
    };
    let end_value = stated_end.map_or(start_value, |c| c.value);
    let ramp = match &r.cant_ramp {
        None => match kind {
            ElementKind::Transition(TransitionShape::Ramp(r)) => r,
            _ => Ramp::Linear,
        },
        Some(v) => match v.get_ref().as_str() {
            "linear" => Ramp::Linear,
            "bloss" => Ramp::Bloss,
            "cosine" => Ramp::Cosine,
            other => {
                return Err(err.at(
                    v.span(),
                    format!("cant_ramp = \"{other}\": a cant ramp is \"linear\", \"bloss\" or \"cosine\""),
                ));
            }
        },
    };
    let cant = CantRamp {
        unit,
        start: start_value,
        end: end_value,
        ramp,
    };
    // Cant on the inner rail's side: the sign convention mistaken.
    for (k, v, which) in [
        (kappa_start_1_m, start_value, "start"),
        (kappa_end_1_m, end_value, "end"),
    ] {
        let phi = CantRamp::angle_of(unit, v);
        if k * phi > 0.0 {
            let at = stated_end
                .or(stated_start)
                .map_or(span.clone(), |c| c.span.clone());
            return Err(err.at(
                at,
                format!(
                    "at its {which} the element turns {} (radius {}) with a cant of {:.1} mm that raises the inner rail: cant is positive when the left rail is higher (docs/reference/01-units-frames.md §1.5), so a curve turning left takes a negative cant",
                    if k > 0.0 { "left" } else { "right" },
                    radius_text(k),
                    cant_base_m * phi.sin() * 1e3
                ),
            ));
        }
    }
    Ok(ElementSpec {
        kind,
        length_m,
        kappa_start_1_m,
        kappa_end_1_m,
        cant,
        line,
    })
}

fn radius_text(kappa_1_m: f64) -> String {
    if kappa_1_m == 0.0 {
        "inf".into()
    } else {
        format!("{:.3} m", 1.0 / kappa_1_m)
    }
}

fn grade(err: &Errors, v: &Spanned<f64>, key: &str) -> Result<f64, InputError> {
    let g = *v.get_ref();
    if !g.is_finite()
        || g.abs() > MAX_GRADE_PERMILLE
        || (g != 0.0 && g.abs() < MIN_NONZERO_GRADE_PERMILLE)
    {
        return Err(err.at(
            v.span(),
            format!(
                "{key} = {g} ‰: a grade is 0 or lies within {MIN_NONZERO_GRADE_PERMILLE} … {MAX_GRADE_PERMILLE} ‰ in magnitude (check the unit: per mille; 12 for 1.2 %)"
            ),
        ));
    }
    Ok(g * 1e-3)
}

fn vertical(
    err: &Errors,
    raw: &[Spanned<RawVertical>],
    plan_length_m: f64,
) -> Result<Vec<VerticalSpec>, InputError> {
    let mut out: Vec<VerticalSpec> = Vec::with_capacity(raw.len());
    for v in raw {
        let r = v.get_ref();
        let line = err.line(&v.span());
        let length_m = length(err, &r.length_m, "vertical")?;
        let prev = out.last().map(|p| p.grade_end);
        let (grade_start, grade_end) = match r.kind.get_ref().as_str() {
            "grade" => {
                if let Some(g) = &r.grade_end_permille {
                    return Err(err.at(
                        g.span(),
                        "grade_end_permille belongs to a vertical curve (type = \"curve\")",
                    ));
                }
                let g = match &r.grade_permille {
                    Some(g) => {
                        let value = grade(err, g, "grade_permille")?;
                        if let Some(p) = prev
                            && (value - p).abs() > 1e-12
                        {
                            return Err(err.at(
                                g.span(),
                                format!(
                                    "the grade breaks from {} ‰ to {} ‰: a grade changes on a vertical curve (type = \"curve\", grade_end_permille)",
                                    p * 1e3,
                                    value * 1e3
                                ),
                            ));
                        }
                        value
                    }
                    None => prev.unwrap_or(0.0),
                };
                (g, g)
            }
            "curve" => {
                if let Some(g) = &r.grade_permille {
                    return Err(err.at(g.span(), "a vertical curve starts with the previous grade and gives grade_end_permille"));
                }
                let end = r
                    .grade_end_permille
                    .as_ref()
                    .ok_or_else(|| err.at(v.span(), "a vertical curve needs grade_end_permille"))?;
                (prev.unwrap_or(0.0), grade(err, end, "grade_end_permille")?)
            }
            other => {
                return Err(err.at(
                    r.kind.span(),
                    format!("type = \"{other}\": a vertical element is \"grade\" or \"curve\""),
                ));
            }
        };
        out.push(VerticalSpec {
            length_m,
            grade_start,
            grade_end,
            line,
        });
    }
    if let Some(last) = raw.last() {
        let total: f64 = out.iter().map(|v| v.length_m).sum();
        if (total - plan_length_m).abs() > COVERAGE_TOLERANCE_M {
            return Err(err.at(
                last.span(),
                format!(
                    "the vertical elements cover {total} m of plan length but the plan elements {plan_length_m} m: they must cover the same length"
                ),
            ));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_of_an_offset() {
        let t = "a\nbé c\n";
        assert_eq!(line_column(t, 0), (1, 1));
        assert_eq!(line_column(t, 2), (2, 1));
        assert_eq!(line_column(t, 6), (2, 4));
    }
}
