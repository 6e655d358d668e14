//! Report-quality PNG charts: plain data in, PNG file out.
//!
//! A small layer over [`plotters`] with its bitmap backend only. The font
//! (DejaVu Sans, `preproc/assets/`) is embedded in the binary and registered
//! once with plotters' `ab_glyph` text renderer, so drawing needs no system
//! font, fontconfig or freetype.
//!
//! - [`write_line_chart`] draws one [`LineChart`] (lines and/or markers, grid,
//!   axis labels, legend when more than one series is labelled);
//! - [`write_multi_panel`] draws several charts in a grid in one PNG (e.g.
//!   rolling radius, contact angle and semi-axes against the lateral
//!   displacement, side by side);
//! - [`render_line_chart`] / [`render_multi_panel`] draw the same into an RGB
//!   buffer in memory (tests, embedding).
//!
//! Ranges are automatic (data extent plus a small margin) unless given;
//! NaN and infinite coordinates are skipped (a line is broken at them);
//! empty series, single points and zero-width ranges are drawn without
//! complaint; data outside given ranges is clipped. `equal_aspect` gives the
//! same scale on both axes (profiles in mm) by widening the range that has
//! fewer units per pixel. Colours come from the Okabe–Ito palette
//! ([`PALETTE`]); series lines are 2 px wide.
//!
//! Images up to 8 Mpx are drawn at twice the size and box-filtered down, so
//! lines and markers are anti-aliased. Files are written atomically
//! ([`runtime::io::atomic`]): the PNG is encoded to a temporary file in the
//! target directory, then renamed over the target; an error leaves nothing
//! behind.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use runtime::io::{AtomicWriteError, write_atomically_keeping_extension};

/// The embedded font (DejaVu Sans 2.37, Bitstream Vera licence; see
/// `preproc/assets/README.md`).
static FONT_TTF: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The family name under which the embedded font is registered; plotters'
/// own defaults also ask for `sans-serif`.
const FONT: &str = "sans-serif";

/// Okabe–Ito colour-blind-safe palette, in the order series take colours:
/// blue, vermillion, bluish green, reddish purple, orange, sky blue, black,
/// yellow.
pub const PALETTE: [(u8, u8, u8); 8] = [
    (0x00, 0x72, 0xB2),
    (0xD5, 0x5E, 0x00),
    (0x00, 0x9E, 0x73),
    (0xCC, 0x79, 0xA7),
    (0xE6, 0x9F, 0x00),
    (0x56, 0xB4, 0xE9),
    (0x00, 0x00, 0x00),
    (0xF0, 0xE4, 0x42),
];

/// Largest accepted image side, px.
const MAX_SIDE_PX: u32 = 16_384;
/// Coordinates larger than this in magnitude are treated like infinities
/// (so spans and pixel mappings stay finite).
const MAX_ABS_COORD: f64 = 1e200;
/// Line width of series, px.
const LINE_WIDTH_PX: u32 = 2;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// A polyline through the points (2 px), broken at non-finite points.
    #[default]
    Line,
    /// A marker at each point.
    Points,
    /// Both.
    LineAndPoints,
}

/// One data series.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend text; series with an empty label get no legend entry.
    pub label: String,
    /// `(x, y)` in the units of the axis labels; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    pub style: SeriesStyle,
    /// Index into [`PALETTE`] (wraps); `None` takes the series' position.
    /// The marker shape follows the colour index too.
    pub colour: Option<usize>,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            style: SeriesStyle::Line,
            colour: None,
        }
    }

    /// A marker-only series.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            style: SeriesStyle::Points,
            ..Self::line(label, points)
        }
    }

    /// The same series with another style.
    pub fn with_style(mut self, style: SeriesStyle) -> Self {
        self.style = style;
        self
    }

    /// The same series with a fixed palette colour.
    pub fn with_colour(mut self, colour: usize) -> Self {
        self.colour = Some(colour);
        self
    }
}

/// One chart: title, axis labels (with units, as they should be printed),
/// series and optional fixed ranges.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Fixed x range `(min, max)`; `None` (or a non-finite value) for automatic.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range `(min, max)`; `None` (or a non-finite value) for automatic.
    pub y_range: Option<(f64, f64)>,
    /// Same scale (units per pixel) on both axes; the range that would be
    /// drawn at the larger scale is widened about its centre.
    pub equal_aspect: bool,
    /// Shaded bands across the whole height, behind the series (e.g. the
    /// elements of a track along its position).
    pub x_bands: Vec<XBand>,
}

/// A shaded band `from ≤ x ≤ to` across a chart's height, drawn behind the
/// series in `rgb` at 30 % opacity; parts outside the x range are clipped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XBand {
    pub from: f64,
    pub to: f64,
    pub rgb: (u8, u8, u8),
}

impl LineChart {
    /// An empty chart with a title and axis labels.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// The same chart with one more series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
}

/// Why a chart could not be drawn or written; always names the file
/// (`<memory>` for in-memory rendering).
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Bad arguments (image size, file name, an image too small for its panels).
    #[error("plot {}: {message}", path.display())]
    Invalid { path: PathBuf, message: String },
    /// The drawing itself failed (font, backend).
    #[error("plot {}: drawing failed: {message}", path.display())]
    Draw { path: PathBuf, message: String },
    /// The file could not be written (missing directory, permissions, rename).
    #[error("plot {}: cannot write: {message}", path.display())]
    Write { path: PathBuf, message: String },
}

impl PlotError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Invalid { path, .. } | Self::Draw { path, .. } | Self::Write { path, .. } => path,
        }
    }

    /// What went wrong, without the path.
    pub fn message(&self) -> &str {
        match self {
            Self::Invalid { message, .. }
            | Self::Draw { message, .. }
            | Self::Write { message, .. } => message,
        }
    }
}

/// Where one chart ended up in the image: the final axis ranges and the
/// plotting rectangle in output pixels `(x0, y0, x1, y1)` (`x1`, `y1`
/// exclusive; fractional when the image was drawn supersampled).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelLayout {
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub plot_px: (f64, f64, f64, f64),
}

impl PanelLayout {
    /// Data units per pixel along x and y.
    pub fn units_per_px(&self) -> (f64, f64) {
        let (x0, y0, x1, y1) = self.plot_px;
        (
            (self.x_range.1 - self.x_range.0) / (x1 - x0),
            (self.y_range.1 - self.y_range.0) / (y1 - y0),
        )
    }
}

/// An image rendered in memory: row-major RGB, 3 bytes a pixel.
#[derive(Debug, Clone)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    /// One entry per chart drawn, in order.
    pub panels: Vec<PanelLayout>,
}

impl RgbImage {
    /// Number of pixels that are not pure white.
    pub fn non_white_pixels(&self) -> usize {
        self.rgb
            .chunks_exact(3)
            .filter(|p| p != &[255, 255, 255])
            .count()
    }
}

/// Draw `chart` into a PNG of `size_px = (width, height)` at `path`.
pub fn write_line_chart(
    path: &Path,
    chart: &LineChart,
    size_px: (u32, u32),
) -> Result<(), PlotError> {
    write_png(path, size_px, |root, k| {
        draw_panel(root, chart, font_scale(size_px) * f64::from(k), k).map(|l| vec![l])
    })
}

/// Draw several charts in a grid of `cols` columns (rows as needed) under a
/// common `title` (may be empty) into one PNG at `path`.
pub fn write_multi_panel(
    path: &Path,
    title: &str,
    panels: &[LineChart],
    cols: usize,
    size_px: (u32, u32),
) -> Result<(), PlotError> {
    write_png(path, size_px, |root, k| {
        draw_multi(root, title, panels, cols, k)
    })
}

/// [`write_line_chart`] into memory.
pub fn render_line_chart(chart: &LineChart, size_px: (u32, u32)) -> Result<RgbImage, PlotError> {
    render_rgb(size_px, |root, k| {
        draw_panel(root, chart, font_scale(size_px) * f64::from(k), k).map(|l| vec![l])
    })
}

/// [`write_multi_panel`] into memory.
pub fn render_multi_panel(
    title: &str,
    panels: &[LineChart],
    cols: usize,
    size_px: (u32, u32),
) -> Result<RgbImage, PlotError> {
    render_rgb(size_px, |root, k| draw_multi(root, title, panels, cols, k))
}

// ---------------------------------------------------------------------------
// Output plumbing

type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

const MEMORY: &str = "<memory>";

/// Largest output (pixels) that is drawn with 2×2 supersampling for
/// anti-aliased lines; larger images are drawn directly.
const SUPERSAMPLE_MAX_PX: u64 = 8_000_000;

/// Registers the embedded font once; later calls return the first outcome.
fn ensure_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_TTF)
                .map_err(|_| "the embedded font DejaVuSans.ttf could not be parsed".to_string())
        })
        .clone()
}

fn check_size(path: &Path, (w, h): (u32, u32)) -> Result<(), PlotError> {
    if w == 0 || h == 0 || w > MAX_SIDE_PX || h > MAX_SIDE_PX {
        return Err(PlotError::Invalid {
            path: path.to_path_buf(),
            message: format!("image size {w}×{h} px is outside 1…{MAX_SIDE_PX} px"),
        });
    }
    Ok(())
}

/// Draws with `draw(root, k)` on a white canvas `k` times the output size
/// (k = 2, or 1 for very large images), then box-filters it down to
/// `size`: anti-aliased lines and markers from a non-anti-aliasing
/// rasteriser. Panel layouts are returned in output pixels.
fn render_pixels<F>(size: (u32, u32), draw: F) -> Result<(Vec<u8>, Vec<PanelLayout>), String>
where
    F: FnOnce(&Root<'_>, u32) -> Result<Vec<PanelLayout>, String>,
{
    ensure_font()?;
    let k: u32 = if u64::from(size.0) * u64::from(size.1) <= SUPERSAMPLE_MAX_PX {
        2
    } else {
        1
    };
    let big = (size.0 * k, size.1 * k);
    let mut canvas = vec![255u8; big.0 as usize * big.1 as usize * 3];
    let panels = {
        let root = BitMapBackend::with_buffer(&mut canvas, big).into_drawing_area();
        let panels = draw(&root, k)?;
        root.present().map_err(|e| e.to_string())?;
        panels
    };
    let kf = f64::from(k);
    let panels = panels
        .into_iter()
        .map(|l| {
            let (x0, y0, x1, y1) = l.plot_px;
            PanelLayout {
                plot_px: (x0 / kf, y0 / kf, x1 / kf, y1 / kf),
                ..l
            }
        })
        .collect();
    if k == 1 {
        return Ok((canvas, panels));
    }
    let (w, h, k) = (size.0 as usize, size.1 as usize, k as usize);
    let big_w = w * k;
    let mut out = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let mut sum = 0u32;
                for dy in 0..k {
                    let row = (y * k + dy) * big_w;
                    for dx in 0..k {
                        sum += u32::from(canvas[(row + x * k + dx) * 3 + c]);
                    }
                }
                let n = (k * k) as u32;
                out[(y * w + x) * 3 + c] = ((sum + n / 2) / n) as u8;
            }
        }
    }
    Ok((out, panels))
}

fn render_rgb<F>(size: (u32, u32), draw: F) -> Result<RgbImage, PlotError>
where
    F: FnOnce(&Root<'_>, u32) -> Result<Vec<PanelLayout>, String>,
{
    let path = Path::new(MEMORY);
    check_size(path, size)?;
    let (rgb, panels) = render_pixels(size, draw).map_err(|message| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    })?;
    Ok(RgbImage {
        width: size.0,
        height: size.1,
        rgb,
        panels,
    })
}

fn write_png<F>(path: &Path, size: (u32, u32), draw: F) -> Result<(), PlotError>
where
    F: FnOnce(&Root<'_>, u32) -> Result<Vec<PanelLayout>, String>,
{
    check_size(path, size)?;
    let invalid = |message: String| PlotError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let write_err = |message: String| PlotError::Write {
        path: path.to_path_buf(),
        message,
    };
    path.file_name()
        .ok_or_else(|| invalid("the path has no file name".into()))?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(write_err(format!(
            "directory {} does not exist",
            dir.display()
        )));
    }
    let (rgb, _) = render_pixels(size, draw).map_err(|message| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    })?;

    // The bitmap backend picks the encoder from the extension: keep `.png`.
    let written = write_atomically_keeping_extension(path, |tmp| {
        let mut file = BitMapBackend::new(tmp, size);
        let copied = file
            .blit_bitmap((0, 0), size, &rgb)
            .map_err(|e| e.to_string());
        // Save even if the copy failed (the backend would on drop anyway),
        // so that the temporary file is surely there to be removed.
        let encoded = file.present().map_err(|e| e.to_string());
        copied.and(encoded)
    });
    written.map_err(|e| match e {
        AtomicWriteError::Write(message) => write_err(message),
        AtomicWriteError::Commit { source, .. } => {
            write_err(format!("rename from temporary file: {source}"))
        }
    })
}

// ---------------------------------------------------------------------------
// Layout

/// Size factor of fonts, ticks and markers for an area of `w`×`h` px
/// (1 at about 700×500).
fn font_scale((w, h): (u32, u32)) -> f64 {
    (f64::from(w).min(f64::from(h) * 1.4) / 700.0).clamp(0.8, 2.5)
}

struct Sizes {
    title: f64,
    axis: f64,
    tick: f64,
    legend: f64,
    tick_mark: i32,
    marker: f64,
    pad: i32,
    /// Series line width.
    line: u32,
    /// Grid, axis and frame line width.
    hair: u32,
    /// The supersampling factor (render px per output px).
    k: u32,
}

impl Sizes {
    /// `s`: size factor in render pixels (font scale × `k`).
    fn new(s: f64, k: u32) -> Self {
        Self {
            line: LINE_WIDTH_PX * k,
            hair: k,
            k,
            title: 21.0 * s,
            axis: 16.0 * s,
            tick: 14.0 * s,
            legend: 14.0 * s,
            tick_mark: (5.0 * s).round().max(3.0) as i32,
            marker: (3.5 * s).max(2.5),
            pad: (8.0 * s).round() as i32,
        }
    }
}

fn text_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    px: f64,
) -> Result<(i32, i32), String> {
    if text.is_empty() {
        return Ok((0, 0));
    }
    let style: TextStyle = (FONT, px).into();
    area.estimate_text_size(text, &style)
        .map(|(w, h)| (w as i32, h as i32))
        .map_err(|e| e.to_string())
}

/// Tick positions and the labels' number format for one axis.
#[derive(Debug, Clone)]
struct Ticks {
    major: Vec<f64>,
    minor: Vec<f64>,
    labels: Vec<String>,
}

/// "Nice" ticks (1, 2, 5 × 10ⁿ) in `[lo, hi]`, about `target` of them.
fn nice_ticks((lo, hi): (f64, f64), target: usize) -> Ticks {
    let span = hi - lo;
    let target = target.max(2) as f64;
    let mag = 10f64.powf((span / target).log10().floor());
    // The 1-2-5 step whose number of intervals is nearest the target
    // (ties: the coarser step).
    let (step, minor_div) = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0]
        .into_iter()
        .map(|m: f64| {
            let step = m * mag;
            let div = if (m / 10f64.powf(m.log10().floor()) - 2.0).abs() < 1e-9 {
                4.0
            } else {
                5.0
            };
            (step, div)
        })
        .min_by(|a, b| {
            let da = (span / a.0 - target).abs();
            let db = (span / b.0 - target).abs();
            da.total_cmp(&db).then(b.0.total_cmp(&a.0))
        })
        .unwrap_or((mag, 5.0));
    let multiples = |step: f64| -> Vec<f64> {
        let k0 = (lo / step - 1e-9).ceil();
        let k1 = (hi / step + 1e-9).floor();
        if !(k0.is_finite() && k1.is_finite()) || k1 - k0 > 10_000.0 {
            return Vec::new();
        }
        let mut v = Vec::new();
        let mut k = k0;
        while k <= k1 {
            let t = k * step;
            v.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
            k += 1.0;
        }
        v
    };
    let major = multiples(step);
    let minor_step = step / minor_div;
    let minor = multiples(minor_step)
        .into_iter()
        .filter(|t| {
            let r = t / step;
            (r - r.round()).abs() > 1e-6
        })
        .collect();
    let labels = format_ticks(&major, step);
    Ticks {
        major,
        minor,
        labels,
    }
}

/// Labels with as many decimals as the step needs; scientific notation for
/// very large or very small numbers.
fn format_ticks(ticks: &[f64], step: f64) -> Vec<String> {
    let max_abs = ticks.iter().fold(0.0f64, |a, t| a.max(t.abs()));
    let step_exp = step.log10().floor() as i32;
    if max_abs >= 1e6 || (max_abs > 0.0 && max_abs < 1e-3) {
        let exp = max_abs.log10().floor() as i32;
        let digits = (exp - step_exp).clamp(0, 12) as usize;
        ticks
            .iter()
            .map(|&t| {
                if t == 0.0 {
                    "0".to_string()
                } else {
                    format!("{t:.digits$e}")
                }
            })
            .collect()
    } else {
        let decimals = (-step_exp).clamp(0, 12) as usize;
        ticks
            .iter()
            .map(|&t| {
                let s = format!("{t:.decimals$}");
                if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
                    s[1..].to_string()
                } else {
                    s
                }
            })
            .collect()
    }
}

fn usable(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_ABS_COORD
}

fn usable_point(&(x, y): &(f64, f64)) -> bool {
    usable(x) && usable(y)
}

/// A range with positive width: ordered, zero width widened.
fn widen((a, b): (f64, f64)) -> (f64, f64) {
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    let scale = lo.abs().max(hi.abs());
    if hi - lo > scale * 1e-12 && hi - lo > 1e-300 {
        (lo, hi)
    } else {
        let c = 0.5 * (lo + hi);
        let half = if scale > 0.0 { scale * 0.05 } else { 1.0 };
        (c - half, c + half)
    }
}

/// The ranges before any equal-aspect adjustment.
fn base_ranges(chart: &LineChart) -> ((f64, f64), (f64, f64)) {
    let given = |r: Option<(f64, f64)>| r.filter(|&(a, b)| usable(a) && usable(b));
    let mut ext: Option<(f64, f64, f64, f64)> = None;
    for p in chart.series.iter().flat_map(|s| &s.points) {
        if !usable_point(p) {
            continue;
        }
        // With one axis fixed, size the other from the points it shows.
        if let Some((a, b)) = given(chart.x_range)
            && (p.0 < a.min(b) || p.0 > a.max(b))
        {
            continue;
        }
        if let Some((a, b)) = given(chart.y_range)
            && (p.1 < a.min(b) || p.1 > a.max(b))
        {
            continue;
        }
        ext = Some(match ext {
            None => (p.0, p.0, p.1, p.1),
            Some((x0, x1, y0, y1)) => (x0.min(p.0), x1.max(p.0), y0.min(p.1), y1.max(p.1)),
        });
    }
    let auto = |lo: f64, hi: f64| {
        let (lo, hi) = widen((lo, hi));
        let m = 0.04 * (hi - lo);
        (lo - m, hi + m)
    };
    let (ax, ay) = match ext {
        Some((x0, x1, y0, y1)) => (auto(x0, x1), auto(y0, y1)),
        None => ((0.0, 1.0), (0.0, 1.0)),
    };
    (
        given(chart.x_range).map(widen).unwrap_or(ax),
        given(chart.y_range).map(widen).unwrap_or(ay),
    )
}

/// Equal units per pixel on both axes for a plot of `w`×`h` px: the range
/// with fewer units per pixel is widened about its centre to match the other.
fn equalise((x, y): ((f64, f64), (f64, f64)), (w, h): (i32, i32)) -> ((f64, f64), (f64, f64)) {
    let (w, h) = (f64::from(w.max(1)), f64::from(h.max(1)));
    let u = ((x.1 - x.0) / w).max((y.1 - y.0) / h);
    let grow = |(lo, hi): (f64, f64), px: f64| {
        let c = 0.5 * (lo + hi);
        let half = 0.5 * u * px;
        if half > 0.5 * (hi - lo) {
            (c - half, c + half)
        } else {
            (lo, hi)
        }
    };
    (grow(x, w), grow(y, h))
}

struct Layout {
    x_range: (f64, f64),
    y_range: (f64, f64),
    x_ticks: Ticks,
    y_ticks: Ticks,
    margin: (i32, i32, i32, i32), // top, bottom, left, right
    x_area: i32,
    y_area: i32,
    plot: (i32, i32),
}

fn layout<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &LineChart,
    sz: &Sizes,
) -> Result<Layout, String> {
    let (w, h) = area.dim_in_pixel();
    let (w, h) = (w as i32, h as i32);
    let (_, tick_h) = text_size(area, "0123456789", sz.tick)?;
    let (_, x_desc_h) = text_size(area, &chart.x_label, sz.axis)?;
    let (_, y_desc_h) = text_size(area, &chart.y_label, sz.axis)?;
    let label_dist = 2 * sz.tick_mark;
    let top = sz.pad + tick_h / 2 + 2;
    let bottom = sz.pad / 2;
    let left = sz.pad;
    let x_area =
        label_dist + tick_h + if x_desc_h > 0 { sz.pad + x_desc_h } else { 0 } + sz.pad / 2;

    let (base_x, base_y) = base_ranges(chart);
    let mut right = 2 * sz.pad;
    let mut y_labels_w = 0;
    const ROUNDS: usize = 6;
    let mut round = 0;
    loop {
        round += 1;
        let y_area = y_desc_h + if y_desc_h > 0 { sz.pad } else { 0 } + y_labels_w + label_dist;
        let plot_w = w - left - right - y_area;
        let plot_h = h - top - bottom - x_area;
        if plot_w < 20 * sz.k as i32 || plot_h < 20 * sz.k as i32 {
            return Err(format!(
                "an area of {w}×{h} px is too small for the chart {:?}",
                chart.title
            ));
        }
        let (x_range, y_range) = if chart.equal_aspect {
            equalise((base_x, base_y), (plot_w, plot_h))
        } else {
            (base_x, base_y)
        };
        let y_ticks = nice_ticks(y_range, (plot_h as f64 / (65.0 * sz.tick / 14.0)) as usize);
        // Fewer x ticks until their labels fit with some room between them.
        let mut target = ((plot_w as f64 / (80.0 * sz.tick / 14.0)) as usize).clamp(2, 12);
        let (x_ticks, widest_x) = loop {
            let t = nice_ticks(x_range, target);
            let widest = t
                .labels
                .iter()
                .map(|l| text_size(area, l, sz.tick).map(|s| s.0))
                .try_fold(0, |a, r| r.map(|b| a.max(b)))?;
            let fits = t.major.len() <= 1 || (widest + 2 * sz.pad) * t.major.len() as i32 <= plot_w;
            if fits || target <= 2 {
                break (t, widest);
            }
            target -= 1;
        };
        let need_y_w = y_ticks
            .labels
            .iter()
            .map(|l| text_size(area, l, sz.tick).map(|s| s.0))
            .try_fold(0, |a, r| r.map(|b| a.max(b)))?;
        let need_right = (2 * sz.pad).max(widest_x / 2 + sz.pad / 2);
        // Each round only widens the label areas, so this settles in two or
        // three; should it not, the last round is used as it is.
        if (need_y_w <= y_labels_w && need_right <= right) || round == ROUNDS {
            return Ok(Layout {
                x_range,
                y_range,
                x_ticks,
                y_ticks,
                margin: (top, bottom, left, right),
                x_area,
                y_area,
                plot: (plot_w, plot_h),
            });
        }
        y_labels_w = y_labels_w.max(need_y_w);
        right = right.max(need_right);
    }
}

// ---------------------------------------------------------------------------
// Drawing

/// A linear f64 axis with our own major (labelled, grid) and minor (light
/// grid) tick positions.
struct TickedAxis {
    lo: f64,
    hi: f64,
    major: Vec<f64>,
    minor: Vec<f64>,
}

impl TickedAxis {
    fn new((lo, hi): (f64, f64), ticks: &Ticks) -> Self {
        Self {
            lo,
            hi,
            major: ticks.major.clone(),
            minor: ticks.minor.clone(),
        }
    }
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, (p0, p1): (i32, i32)) -> i32 {
        // As plotters' own f64 axis; values are pre-clipped to the range.
        let f = (v - self.lo) / (self.hi - self.lo);
        let len = f64::from(p1 - p0);
        if !f.is_finite() {
            return p0;
        }
        if len >= 0.0 {
            p0 + (len * f + 1e-3).floor() as i32
        } else {
            p0 + (len * f - 1e-3).ceil() as i32
        }
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor.clone()
        } else {
            self.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

fn colour(index: usize) -> RGBColor {
    let (r, g, b) = PALETTE[index % PALETTE.len()];
    RGBColor(r, g, b)
}

/// Marker outline offsets (px) for the shape belonging to a colour index:
/// circle, square, triangle, diamond.
fn marker_shape(index: usize, r: f64) -> Vec<(i32, i32)> {
    let polygon = |n: usize, r: f64, phase: f64| -> Vec<(i32, i32)> {
        (0..n)
            .map(|k| {
                let a = phase + std::f64::consts::TAU * k as f64 / n as f64;
                ((r * a.cos()).round() as i32, (r * a.sin()).round() as i32)
            })
            .collect()
    };
    match index % 4 {
        0 => polygon(16, r, 0.0),
        1 => polygon(4, r * 1.2, std::f64::consts::FRAC_PI_4),
        2 => polygon(3, r * 1.35, -std::f64::consts::FRAC_PI_2),
        _ => polygon(4, r * 1.35, 0.0),
    }
}

/// Clip the segment `a`–`b` to the box (Liang–Barsky).
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    Some((
        if t0 > 0.0 { at(t0) } else { a },
        if t1 < 1.0 { at(t1) } else { b },
    ))
}

/// The visible pieces of a series' polyline: broken at unusable points and
/// clipped to the ranges.
fn visible_polylines(
    points: &[(f64, f64)],
    xr: (f64, f64),
    yr: (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let mut flush = |current: &mut Vec<(f64, f64)>| {
        if current.len() >= 2 {
            out.push(std::mem::take(current));
        } else {
            current.clear();
        }
    };
    for pair in points.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if !(usable_point(&a) && usable_point(&b)) {
            flush(&mut current);
            continue;
        }
        match clip_segment(a, b, xr, yr) {
            None => flush(&mut current),
            Some((ca, cb)) => {
                if current.last() != Some(&ca) {
                    flush(&mut current);
                    current.push(ca);
                }
                current.push(cb);
            }
        }
    }
    flush(&mut current);
    out
}

/// A polyline made safe for plotters' wide strokes: points within a pixel
/// of the previous kept one are dropped (the last is kept), and the line is
/// cut where it turns back by more than 120°. Plotters joins the segments
/// of a wide line with mitres, whose length grows as 1/sin(θ/2) for a turn
/// of θ: a spike that reverses within a pixel or two (a flange impact in a
/// force history) would be drawn as a line across the whole image.
fn stroke_pieces(line: Vec<(f64, f64)>, (ux, uy): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    if line.len() < 3 || !(ux > 0.0 && uy > 0.0) {
        return vec![line];
    }
    let last = line[line.len() - 1];
    let mut thin: Vec<(f64, f64)> = Vec::with_capacity(line.len());
    for p in line {
        match thin.last() {
            Some(q) if ((p.0 - q.0) / ux).abs() < 1.0 && ((p.1 - q.1) / uy).abs() < 1.0 => {}
            _ => thin.push(p),
        }
    }
    if thin.last() != Some(&last) {
        if thin.len() >= 2 {
            thin.pop();
        }
        thin.push(last);
    }
    let dir = |a: (f64, f64), b: (f64, f64)| {
        let (dx, dy) = ((b.0 - a.0) / ux, (b.1 - a.1) / uy);
        let n = dx.hypot(dy);
        if n > 0.0 {
            (dx / n, dy / n)
        } else {
            (0.0, 0.0)
        }
    };
    let mut pieces = Vec::new();
    let mut current = vec![thin[0]];
    for i in 1..thin.len() {
        current.push(thin[i]);
        if i + 1 < thin.len() {
            let (a, b) = (dir(thin[i - 1], thin[i]), dir(thin[i], thin[i + 1]));
            if a.0 * b.0 + a.1 * b.1 < -0.5 {
                pieces.push(std::mem::replace(&mut current, vec![thin[i]]));
            }
        }
    }
    pieces.push(current);
    pieces
}

/// Usable points whose neighbours are both missing or unusable.
fn isolated_points(points: &[(f64, f64)]) -> impl Iterator<Item = (f64, f64)> + '_ {
    let usable_at = |i: Option<usize>| i.and_then(|i| points.get(i)).is_some_and(usable_point);
    (0..points.len())
        .filter(move |&i| {
            usable_point(&points[i]) && !usable_at(i.checked_sub(1)) && !usable_at(Some(i + 1))
        })
        .map(|i| points[i])
}

fn inside(p: &(f64, f64), (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> bool {
    usable_point(p) && p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1
}

/// Picks the plot corner where the legend box of `(w, h)` px covers the
/// least data.
fn legend_corner(chart: &LineChart, lay: &Layout, (w, h): (i32, i32), inset: i32) -> (i32, i32) {
    const N: usize = 48;
    let (pw, ph) = (f64::from(lay.plot.0), f64::from(lay.plot.1));
    let (xr, yr) = (lay.x_range, lay.y_range);
    let mut grid = vec![false; N * N];
    let mut mark = |p: (f64, f64)| {
        let fx = (p.0 - xr.0) / (xr.1 - xr.0);
        let fy = (yr.1 - p.1) / (yr.1 - yr.0);
        let i = ((fx * N as f64) as usize).min(N - 1);
        let j = ((fy * N as f64) as usize).min(N - 1);
        grid[j * N + i] = true;
    };
    for s in &chart.series {
        if s.style != SeriesStyle::Points {
            for line in visible_polylines(&s.points, xr, yr) {
                for seg in line.windows(2) {
                    let (a, b) = (seg[0], seg[1]);
                    let len_px = (((b.0 - a.0) / (xr.1 - xr.0) * pw).powi(2)
                        + ((b.1 - a.1) / (yr.1 - yr.0) * ph).powi(2))
                    .sqrt();
                    let n = ((len_px / 3.0).ceil() as usize).clamp(1, 10_000);
                    for k in 0..=n {
                        let t = k as f64 / n as f64;
                        mark((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                    }
                }
            }
        }
        if s.style != SeriesStyle::Line {
            s.points
                .iter()
                .filter(|p| inside(p, xr, yr))
                .for_each(|&p| mark(p));
        }
    }
    let (plot_w, plot_h) = lay.plot;
    // In order of preference when equally good.
    let candidates = [
        (plot_w - w - inset, inset),
        (inset, inset),
        ((plot_w - w) / 2, inset),
        (plot_w - w - inset, plot_h - h - inset),
        (inset, plot_h - h - inset),
        ((plot_w - w) / 2, plot_h - h - inset),
    ];
    let cost = |&(x, y): &(i32, i32)| {
        let cells = |a: i32, len: i32, total: i32| {
            let lo = ((f64::from(a) / f64::from(total)) * N as f64)
                .floor()
                .max(0.0) as usize;
            let hi = ((f64::from(a + len) / f64::from(total)) * N as f64)
                .ceil()
                .clamp(0.0, N as f64) as usize;
            lo..hi
        };
        let mut n = 0;
        for j in cells(y, h, plot_h) {
            for i in cells(x, w, plot_w) {
                n += usize::from(grid[j * N + i]);
            }
        }
        n
    };
    candidates
        .iter()
        .min_by_key(|c| cost(c))
        .copied()
        .unwrap_or(candidates[0])
}

/// Draws one chart into `area`; returns where it went.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &LineChart,
    scale: f64,
    k: u32,
) -> Result<PanelLayout, String> {
    let sz = Sizes::new(scale, k);
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let area = if chart.title.is_empty() {
        area.clone()
    } else {
        let a = area.margin(sz.pad / 2, 0, 0, 0);
        a.titled(&chart.title, (FONT, sz.title).into_font().color(&BLACK))
            .map_err(e)?
    };
    let lay = layout(&area, chart, &sz)?;
    let (top, bottom, left, right) = lay.margin;
    let (x0, x1) = lay.x_range;
    let (y0, y1) = lay.y_range;
    let mut cc = ChartBuilder::on(&area)
        .margin_top(top)
        .margin_bottom(bottom)
        .margin_left(left)
        .margin_right(right)
        .x_label_area_size(lay.x_area)
        .y_label_area_size(lay.y_area)
        .build_cartesian_2d(
            TickedAxis::new((x0, x1), &lay.x_ticks),
            TickedAxis::new((y0, y1), &lay.y_ticks),
        )
        .map_err(e)?;

    let label_of = |ticks: &Ticks, v: f64| {
        ticks
            .major
            .iter()
            .zip(&ticks.labels)
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    };
    let fmt_x = |v: &f64| label_of(&lay.x_ticks, *v);
    let fmt_y = |v: &f64| label_of(&lay.y_ticks, *v);
    let text = |px: f64| (FONT, px).into_font().color(&BLACK);
    cc.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .axis_desc_style(text(sz.axis))
        .label_style(text(sz.tick))
        .x_label_formatter(&fmt_x)
        .y_label_formatter(&fmt_y)
        .bold_line_style(RGBColor(200, 200, 200).stroke_width(sz.hair))
        .light_line_style(RGBColor(236, 236, 236).stroke_width(sz.hair))
        .axis_style(BLACK.stroke_width(sz.hair))
        .set_all_tick_mark_size(sz.tick_mark)
        .draw()
        .map_err(e)?;

    for b in &chart.x_bands {
        let (from, to) = (b.from.max(x0), b.to.min(x1));
        if from < to {
            let (r, g, bl) = b.rgb;
            cc.draw_series(std::iter::once(Rectangle::new(
                [(from, y0), (to, y1)],
                RGBColor(r, g, bl).mix(0.3).filled(),
            )))
            .map_err(e)?;
        }
    }

    let labelled = chart
        .series
        .iter()
        .filter(|s| !s.label.trim().is_empty())
        .count();
    let show_legend = labelled > 1;
    let marker_r = sz.marker;
    for (k, s) in chart.series.iter().enumerate() {
        let ci = s.colour.unwrap_or(k);
        let c = colour(ci);
        let lines = if s.style == SeriesStyle::Points {
            Vec::new()
        } else {
            visible_polylines(&s.points, lay.x_range, lay.y_range)
        };
        let line_style = c.stroke_width(sz.line);
        let px = (
            (lay.x_range.1 - lay.x_range.0) / f64::from(lay.plot.0.max(1)),
            (lay.y_range.1 - lay.y_range.0) / f64::from(lay.plot.1.max(1)),
        );
        cc.draw_series(
            lines
                .into_iter()
                .flat_map(|l| stroke_pieces(l, px))
                .map(|l| PathElement::new(l, line_style)),
        )
        .map_err(e)?;
        if s.style != SeriesStyle::Line {
            let shape = marker_shape(ci, marker_r);
            cc.draw_series(
                s.points
                    .iter()
                    .filter(|p| inside(p, lay.x_range, lay.y_range))
                    .map(|&p| EmptyElement::at(p) + marker(&shape, c)),
            )
            .map_err(e)?;
        } else {
            // A point with no usable neighbour would not show as a line.
            let dot = marker_shape(0, f64::from(sz.line) * 1.1);
            cc.draw_series(
                isolated_points(&s.points)
                    .filter(|p| inside(p, lay.x_range, lay.y_range))
                    .map(|p| EmptyElement::at(p) + marker(&dot, c)),
            )
            .map_err(e)?;
        }
    }

    // Frame around the plotting area.
    let plot_area = cc.plotting_area().strip_coord_spec();
    let (pw, ph) = plot_area.dim_in_pixel();
    plot_area
        .draw(&Rectangle::new(
            [(0, 0), (pw as i32 - 1, ph as i32 - 1)],
            BLACK.stroke_width(sz.hair),
        ))
        .map_err(e)?;

    if show_legend {
        draw_legend(&plot_area, chart, &lay, &sz, scale)?;
    }

    let (x0, y0) = plot_area.get_base_pixel();
    Ok(PanelLayout {
        x_range: lay.x_range,
        y_range: lay.y_range,
        plot_px: (
            f64::from(x0),
            f64::from(y0),
            f64::from(x0) + f64::from(pw),
            f64::from(y0) + f64::from(ph),
        ),
    })
}

/// The legend box: one row (symbol, label) per labelled series, in the plot
/// corner that hides the least data.
fn draw_legend<DB: DrawingBackend>(
    plot_area: &DrawingArea<DB, Shift>,
    chart: &LineChart,
    lay: &Layout,
    sz: &Sizes,
    scale: f64,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let entries: Vec<(usize, &Series)> = chart
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.trim().is_empty())
        .collect();
    let sym = (30.0 * scale).round() as i32;
    let pad = sz.pad;
    let row_h = (sz.legend * 1.45).round() as i32;
    let mut text_w = 0;
    for (_, s) in &entries {
        text_w = text_w.max(text_size(plot_area, s.label.trim(), sz.legend)?.0);
    }
    let (w, h) = (
        pad + sym + pad + text_w + pad,
        entries.len() as i32 * row_h + pad,
    );
    let (bx, by) = legend_corner(chart, lay, (w, h), pad);
    plot_area
        .draw(&Rectangle::new(
            [(bx, by), (bx + w, by + h)],
            WHITE.mix(0.92).filled(),
        ))
        .map_err(e)?;
    plot_area
        .draw(&Rectangle::new(
            [(bx, by), (bx + w, by + h)],
            RGBColor(110, 110, 110).stroke_width(sz.hair),
        ))
        .map_err(e)?;
    let font = (FONT, sz.legend)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (row, (k, s)) in entries.iter().enumerate() {
        let ci = s.colour.unwrap_or(*k);
        let c = colour(ci);
        let y = by + pad / 2 + row as i32 * row_h + row_h / 2;
        let (x0, x1) = (bx + pad, bx + pad + sym);
        if s.style != SeriesStyle::Points {
            plot_area
                .draw(&PathElement::new(
                    vec![(x0, y), (x1, y)],
                    c.stroke_width(sz.line),
                ))
                .map_err(e)?;
        }
        if s.style != SeriesStyle::Line {
            plot_area
                .draw(
                    &(EmptyElement::at(((x0 + x1) / 2, y))
                        + marker(&marker_shape(ci, sz.marker), c)),
                )
                .map_err(e)?;
        }
        plot_area
            .draw_text(s.label.trim(), &font, (x1 + pad, y))
            .map_err(e)?;
    }
    Ok(())
}

/// A filled marker outline, in pixels relative to the point.
fn marker(shape: &[(i32, i32)], c: RGBColor) -> Polygon<(i32, i32)> {
    Polygon::new(shape.to_vec(), c.filled())
}

fn draw_multi<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    panels: &[LineChart],
    cols: usize,
    k: u32,
) -> Result<Vec<PanelLayout>, String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let cols = cols.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = root.dim_in_pixel();
    let cell = (w / k / cols as u32, h / k / rows as u32);
    let scale = font_scale(cell) * f64::from(k);
    let area = if title.is_empty() {
        root.clone()
    } else {
        let sz = Sizes::new(scale, k);
        root.margin(sz.pad, 0, 0, 0)
            .titled(title, (FONT, sz.title * 1.15).into_font().color(&BLACK))
            .map_err(e)?
    };
    let mut out = Vec::with_capacity(panels.len());
    for (chart, cell) in panels.iter().zip(area.split_evenly((rows, cols))) {
        out.push(draw_panel(&cell, chart, scale, k)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_numbers_with_matching_decimals() {
        let t = nice_ticks((-0.07, 1.03), 5);
        assert_eq!(t.labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let t = nice_ticks((457.3, 478.9), 5);
        assert_eq!(t.labels, ["460", "465", "470", "475"]);
        let t = nice_ticks((-8.6, 8.6), 8);
        assert_eq!(t.major, [-8.0, -6.0, -4.0, -2.0, 0.0, 2.0, 4.0, 6.0, 8.0]);
        assert!(
            t.labels.iter().all(|l| !l.starts_with("-0")),
            "{:?}",
            t.labels
        );
        assert!(t.minor.iter().all(|m| !t.major.contains(m)));
        let t = nice_ticks((0.0, 2e12), 4);
        assert_eq!(t.labels[1], "5.0e11");
        let t = nice_ticks((0.0, 3e-6), 3);
        assert_eq!(t.labels[1], "1e-6");
    }

    #[test]
    fn ranges_widen_and_equalise() {
        assert_eq!(widen((2.0, 1.0)), (1.0, 2.0));
        assert_eq!(widen((0.0, 0.0)), (-1.0, 1.0));
        let (lo, hi) = widen((10.0, 10.0));
        assert!((lo - 9.5).abs() < 1e-12 && (hi - 10.5).abs() < 1e-12);
        let (x, y) = equalise(((0.0, 100.0), (0.0, 10.0)), (500, 500));
        assert_eq!(x, (0.0, 100.0));
        assert_eq!(y, (-45.0, 55.0));
    }

    #[test]
    fn segments_are_clipped_to_the_box() {
        let b = ((0.0, 1.0), (0.0, 1.0));
        assert_eq!(
            clip_segment((-1.0, 0.5), (2.0, 0.5), b.0, b.1),
            Some(((0.0, 0.5), (1.0, 0.5)))
        );
        assert_eq!(clip_segment((2.0, 2.0), (3.0, 3.0), b.0, b.1), None);
        let lines = visible_polylines(
            &[
                (0.1, 0.1),
                (0.2, 0.2),
                (f64::NAN, 0.0),
                (0.3, 0.3),
                (5.0, 0.3),
                (0.4, 0.4),
            ],
            b.0,
            b.1,
        );
        assert_eq!(lines.len(), 3, "{lines:?}");
        assert_eq!(
            isolated_points(&[(0.0, 0.0), (f64::NAN, 1.0), (2.0, 2.0)]).count(),
            2
        );
    }
}
