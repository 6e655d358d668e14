//! The PNG chart module: files, sizes, content, equal aspect, edge cases and
//! errors. Output goes under `CARGO_TARGET_TMPDIR/plot/`.

use std::path::{Path, PathBuf};

use preproc::plot::{
    LineChart, PALETTE, PlotError, Series, SeriesStyle, XBand, render_line_chart,
    render_multi_panel, write_line_chart, write_multi_panel,
};

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("plot")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Checks the signature and returns (width, height) from the IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        bytes.len() > 33,
        "{} is too short for a PNG",
        path.display()
    );
    assert_eq!(bytes[..8], PNG_SIGNATURE, "{} is not a PNG", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

fn file_len(path: &Path) -> u64 {
    std::fs::metadata(path).unwrap().len()
}

/// Rolling radius, contact angle and contact-ellipse semi-axes of a
/// synthetic wheel against lateral displacement y, left and right.
fn contact_panels() -> Vec<LineChart> {
    let ys: Vec<f64> = (0..=160).map(|k| -8.0 + 0.1 * f64::from(k)).collect();
    let r = |side: f64| -> Vec<(f64, f64)> {
        ys.iter()
            .map(|&y| {
                let u = side * y;
                let flange = if u > 5.5 {
                    2.5 * (u - 5.5).powi(2)
                } else {
                    0.0
                };
                (y, 460.0 + 0.15 * u + 0.02 * u * u.abs() + flange)
            })
            .collect()
    };
    let gamma = |side: f64| -> Vec<(f64, f64)> {
        ys.iter()
            .map(|&y| {
                let u = side * y;
                let flange = if u > 5.5 { 30.0 * (u - 5.5) } else { 0.0 };
                (y, (2.0 + 0.3 * u + flange).min(70.0))
            })
            .collect()
    };
    let axis = |scale: f64, side: f64| -> Vec<(f64, f64)> {
        ys.iter()
            .map(|&y| (y, scale * (6.0 - 0.25 * side * y).max(1.5)))
            .collect()
    };
    vec![
        LineChart {
            title: "Rolling radius".into(),
            x_label: "lateral displacement y [mm]".into(),
            y_label: "rolling radius r [mm]".into(),
            series: vec![
                Series::line("left wheel", r(1.0)),
                Series::line("right wheel", r(-1.0)),
            ],
            ..LineChart::default()
        },
        LineChart {
            title: "Contact angle".into(),
            x_label: "lateral displacement y [mm]".into(),
            y_label: "contact angle γ [deg]".into(),
            series: vec![
                Series::line("left wheel", gamma(1.0)),
                Series::line("right wheel", gamma(-1.0)),
            ],
            ..LineChart::default()
        },
        LineChart {
            title: "Contact ellipse semi-axes (left wheel)".into(),
            x_label: "lateral displacement y [mm]".into(),
            y_label: "semi-axis [mm]".into(),
            series: vec![
                Series::line("a (longitudinal)", axis(1.0, 1.0)),
                Series::line("b (lateral)", axis(0.6, 1.0)).with_style(SeriesStyle::LineAndPoints),
            ],
            ..LineChart::default()
        },
    ]
}

/// A wheel-tread-like outline and a rail-head-like outline in mm: the
/// shapes `equal_aspect` is for.
fn profile_chart() -> LineChart {
    let wheel: Vec<(f64, f64)> = (0..=140)
        .map(|k| {
            let y = -70.0 + f64::from(k);
            let flange = if y > 35.0 {
                28.0 * (1.0 - (1.0 - ((y - 35.0) / 32.0).min(1.0)).powi(2)).sqrt()
            } else {
                0.0
            };
            (y, 0.025 * y + flange + 4.0)
        })
        .collect();
    let rail: Vec<(f64, f64)> = (0..=72)
        .map(|k| {
            let a = std::f64::consts::PI * f64::from(k) / 72.0;
            (36.0 * a.cos(), 12.0 * a.sin().powf(0.3) - 12.0)
        })
        .collect();
    LineChart {
        title: "Wheel and rail profiles (equal scales)".into(),
        x_label: "lateral coordinate [mm]".into(),
        y_label: "vertical coordinate [mm]".into(),
        series: vec![
            Series::line("wheel tread and flange", wheel),
            Series::line("rail head", rail),
            Series::points("contact point", vec![(2.0, 0.0)]).with_colour(6),
        ],
        equal_aspect: true,
        ..LineChart::default()
    }
}

#[test]
fn line_chart_png_has_signature_size_and_content() {
    let dir = out_dir("line_chart");
    let chart = contact_panels().remove(0);
    let path = dir.join("rolling_radius.png");
    write_line_chart(&path, &chart, (900, 600)).unwrap();
    assert_eq!(png_size(&path), (900, 600));

    // The same axes without the data: a smaller file and far fewer
    // non-white pixels.
    let full = render_line_chart(&chart, (900, 600)).unwrap();
    let blank = LineChart {
        series: Vec::new(),
        x_range: Some(full.panels[0].x_range),
        y_range: Some(full.panels[0].y_range),
        ..chart.clone()
    };
    let blank_path = dir.join("blank.png");
    write_line_chart(&blank_path, &blank, (900, 600)).unwrap();
    assert_eq!(png_size(&blank_path), (900, 600));
    assert!(
        file_len(&path) > file_len(&blank_path) + 2_000,
        "chart {} B, blank {} B",
        file_len(&path),
        file_len(&blank_path)
    );
    let empty = render_line_chart(&blank, (900, 600)).unwrap();
    assert_eq!(empty.panels[0].x_range, full.panels[0].x_range);
    assert_eq!((full.width, full.height), (900, 600));
    assert_eq!(full.rgb.len(), 900 * 600 * 3);
    assert!(empty.non_white_pixels() > 0, "even a blank chart has axes");
    assert!(
        full.non_white_pixels() > empty.non_white_pixels() + 3_000,
        "{} vs {}",
        full.non_white_pixels(),
        empty.non_white_pixels()
    );
    // Nothing at all (no title, labels or data) is still a chart frame.
    let nothing = render_line_chart(&LineChart::default(), (900, 600)).unwrap();
    assert!(nothing.non_white_pixels() > 1_000);
    for c in &PALETTE[..2] {
        assert!(count_colour(&full.rgb, *c) > 200, "colour {c:?} missing");
    }
}

fn count_colour(rgb: &[u8], (r, g, b): (u8, u8, u8)) -> usize {
    rgb.chunks_exact(3).filter(|p| p == &[r, g, b]).count()
}

#[test]
fn x_bands_shade_their_stretch_behind_the_series() {
    // Red at 30 % on white: (255, 178, 178) give or take the rounding.
    let pink = |rgb: &[u8]| {
        rgb.chunks_exact(3)
            .filter(|p| p[0] == 255 && (170..=186).contains(&p[1]) && p[1] == p[2])
            .count()
    };
    let chart = |bands: Vec<XBand>| LineChart {
        x_range: Some((0.0, 10.0)),
        y_range: Some((0.0, 1.0)),
        x_bands: bands,
        ..LineChart::new("", "x [m]", "y [m]")
            .with_series(Series::line("", vec![(0.0, 0.5), (10.0, 0.5)]))
    };
    let band = |from, to| XBand {
        from,
        to,
        rgb: (255, 0, 0),
    };
    let none = pink(&render_line_chart(&chart(vec![]), (600, 400)).unwrap().rgb);
    let three = pink(
        &render_line_chart(&chart(vec![band(2.0, 5.0)]), (600, 400))
            .unwrap()
            .rgb,
    );
    let six = pink(
        &render_line_chart(&chart(vec![band(2.0, 8.0)]), (600, 400))
            .unwrap()
            .rgb,
    );
    // Clipped to the x range: only 0 … 3 of −5 … 3 shows.
    let clipped = pink(
        &render_line_chart(&chart(vec![band(-5.0, 3.0)]), (600, 400))
            .unwrap()
            .rgb,
    );
    let outside = pink(
        &render_line_chart(&chart(vec![band(12.0, 15.0)]), (600, 400))
            .unwrap()
            .rgb,
    );
    assert_eq!(none, 0);
    assert!(three > 10_000, "{three}");
    let ratio = six as f64 / three as f64;
    assert!((ratio - 2.0).abs() < 0.1, "{six} / {three}");
    assert!(
        (clipped as f64 / three as f64 - 1.0).abs() < 0.1,
        "{clipped}"
    );
    assert_eq!(outside, 0);
}

#[test]
fn colour_index_picks_the_palette_entry() {
    let pts: Vec<(f64, f64)> = (0..50)
        .map(|k| (f64::from(k), f64::from(k).sin()))
        .collect();
    let default = LineChart::new("", "x [m]", "y [m]").with_series(Series::line("", pts.clone()));
    let fixed = LineChart::new("", "x [m]", "y [m]")
        .with_series(Series::line("", pts).with_colour(1 + PALETTE.len()));
    let a = render_line_chart(&default, (600, 400)).unwrap();
    let b = render_line_chart(&fixed, (600, 400)).unwrap();
    assert!(count_colour(&a.rgb, PALETTE[0]) > 300);
    assert_eq!(count_colour(&a.rgb, PALETTE[1]), 0);
    assert!(count_colour(&b.rgb, PALETTE[1]) > 300, "index wraps around");
    assert_eq!(count_colour(&b.rgb, PALETTE[0]), 0);
}

#[test]
fn legend_only_with_several_labelled_series() {
    let a: Vec<(f64, f64)> = (0..20).map(|k| (f64::from(k), f64::from(k))).collect();
    let b: Vec<(f64, f64)> = (0..20)
        .map(|k| (f64::from(k), 20.0 - f64::from(k)))
        .collect();
    let chart = |la: &str, lb: &str| {
        LineChart::new("t", "x [s]", "y [N]")
            .with_series(Series::line(la, a.clone()))
            .with_series(Series::points(lb, b.clone()))
    };
    let none = render_line_chart(&chart("", ""), (700, 500)).unwrap();
    let one = render_line_chart(&chart("a", ""), (700, 500)).unwrap();
    let two = render_line_chart(&chart("a", "b"), (700, 500)).unwrap();
    assert_eq!(none.rgb, one.rgb, "a single labelled series gets no legend");
    assert_ne!(none.rgb, two.rgb, "two labelled series get a legend");
}

#[test]
fn multi_panel_png() {
    let dir = out_dir("multi_panel");
    let panels = contact_panels();
    let path = dir.join("contact_vs_y.png");
    write_multi_panel(
        &path,
        "Wheel–rail contact against lateral displacement",
        &panels,
        3,
        (1800, 560),
    )
    .unwrap();
    assert_eq!(png_size(&path), (1800, 560));

    let img = render_multi_panel("Contact", &panels, 2, (1200, 900)).unwrap();
    assert_eq!(img.panels.len(), 3);
    // 2 columns: panels 0 and 1 side by side, panel 2 below panel 0.
    let p = |i: usize| img.panels[i].plot_px;
    assert!(p(0).2 <= p(1).0, "{:?} {:?}", p(0), p(1));
    assert!(p(0).3 <= p(2).1, "{:?} {:?}", p(0), p(2));
    for l in &img.panels {
        let (x0, y0, x1, y1) = l.plot_px;
        assert!(0.0 <= x0 && x0 < x1 && x1 <= 1200.0 && 0.0 <= y0 && y0 < y1 && y1 <= 900.0);
    }
    assert!(img.non_white_pixels() > 20_000);

    // Degenerate grids do not panic.
    render_multi_panel("", &panels, 0, (900, 900)).unwrap();
    render_multi_panel("", &panels, 10, (1500, 500)).unwrap();
    render_multi_panel("nothing", &[], 3, (600, 400)).unwrap();
}

#[test]
fn equal_aspect_gives_equal_scales() {
    let dir = out_dir("equal_aspect");
    let chart = profile_chart();
    for size in [(1000, 700), (700, 1000), (1200, 500)] {
        let img = render_line_chart(&chart, size).unwrap();
        let l = img.panels[0];
        let (ux, uy) = l.units_per_px();
        assert!(
            ((ux - uy) / ux).abs() < 1e-9,
            "size {size:?}: {ux} vs {uy} mm/px"
        );
        // The data is all inside.
        assert!(
            l.x_range.0 <= -70.0 && l.x_range.1 >= 70.0,
            "{:?}",
            l.x_range
        );
        assert!(
            l.y_range.0 <= -12.0 && l.y_range.1 >= 33.0,
            "{:?}",
            l.y_range
        );
        let path = dir.join(format!("profiles_{}x{}.png", size.0, size.1));
        write_line_chart(&path, &chart, size).unwrap();
        assert_eq!(png_size(&path), size);
    }
    // Given ranges are kept on the axis that sets the scale and widened on
    // the other.
    let fixed = LineChart {
        x_range: Some((-80.0, 80.0)),
        y_range: Some((-20.0, 40.0)),
        ..chart.clone()
    };
    let l = render_line_chart(&fixed, (1000, 700)).unwrap().panels[0];
    assert_eq!(l.x_range, (-80.0, 80.0));
    assert!(l.y_range.0 < -20.0 && l.y_range.1 > 40.0);
    assert!((0.5 * (l.y_range.0 + l.y_range.1) - 10.0).abs() < 1e-9);
    let (ux, uy) = l.units_per_px();
    assert!(((ux - uy) / ux).abs() < 1e-9);

    // Without equal_aspect the ranges are the data's plus a small margin.
    let free = LineChart {
        equal_aspect: false,
        ..chart
    };
    let l = render_line_chart(&free, (1000, 700)).unwrap().panels[0];
    assert!(
        l.x_range.0 < -70.0 && l.x_range.0 > -77.0,
        "{:?}",
        l.x_range
    );
    let (ux, uy) = l.units_per_px();
    assert!((ux - uy).abs() / ux > 0.1);
}

#[test]
fn missing_directory_is_an_error_naming_the_path() {
    let dir = out_dir("missing_dir");
    let path = dir.join("no such dir").join("chart.png");
    let err = write_line_chart(&path, &profile_chart(), (600, 400)).unwrap_err();
    assert!(matches!(err, PlotError::Write { .. }), "{err:?}");
    assert_eq!(err.path(), path);
    let text = err.to_string();
    assert!(text.contains(&path.display().to_string()), "{text}");
    assert!(!path.exists());

    let err = write_multi_panel(&path, "t", &contact_panels(), 3, (900, 300)).unwrap_err();
    assert_eq!(err.path(), path);
}

#[test]
fn bad_sizes_are_errors_not_panics() {
    let dir = out_dir("bad_size");
    let path = dir.join("zero.png");
    let err = write_line_chart(&path, &profile_chart(), (0, 400)).unwrap_err();
    assert!(matches!(err, PlotError::Invalid { .. }), "{err:?}");
    assert_eq!(err.path(), path);
    // Too small to hold axes and labels: an error, and no file left behind.
    let path = dir.join("tiny.png");
    let err = write_line_chart(&path, &profile_chart(), (40, 30)).unwrap_err();
    assert!(matches!(err, PlotError::Draw { .. }), "{err:?}");
    assert_eq!(err.path(), path);
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "left files behind"
    );
    assert!(render_line_chart(&profile_chart(), (100_000, 10)).is_err());
}

#[test]
fn writes_atomically_and_overwrites() {
    let dir = out_dir("atomic");
    let path = dir.join("chart.png");
    std::fs::write(&path, b"old").unwrap();
    write_line_chart(&path, &profile_chart(), (640, 480)).unwrap();
    assert_eq!(png_size(&path), (640, 480));
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["chart.png"], "temporary files left behind");

    // A relative path without a directory part goes to the current directory;
    // a path without a file name is refused.
    let err = write_line_chart(Path::new("/"), &profile_chart(), (640, 480)).unwrap_err();
    assert!(matches!(err, PlotError::Invalid { .. }), "{err:?}");
}

#[test]
fn awkward_data_does_not_panic() {
    let dir = out_dir("edge_cases");
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let cases: Vec<(&str, LineChart)> = vec![
        ("no_series", LineChart::new("nothing", "x [m]", "y [m]")),
        (
            "empty_series",
            LineChart::new("empty", "x [m]", "y [m]")
                .with_series(Series::line("a", vec![]))
                .with_series(Series::points("b", vec![])),
        ),
        (
            "only_nan",
            LineChart::new("NaN", "x", "y")
                .with_series(Series::line("a", vec![(nan, nan), (inf, 1.0), (1.0, -inf)]))
                .with_series(Series::points("b", vec![(nan, 0.0)])),
        ),
        (
            "nan_breaks_line",
            LineChart::new("gap", "x", "y").with_series(
                Series::line(
                    "a",
                    vec![(0.0, 0.0), (1.0, 1.0), (2.0, nan), (3.0, 3.0), (4.0, 2.0)],
                )
                .with_style(SeriesStyle::LineAndPoints),
            ),
        ),
        (
            "single_point",
            LineChart::new("one", "x", "y").with_series(Series::line("a", vec![(3.0, 4.0)])),
        ),
        (
            "single_point_at_origin",
            LineChart::new("one", "x", "y")
                .with_series(Series::points("a", vec![(0.0, 0.0)]))
                .with_series(Series::points("b", vec![(0.0, 0.0)])),
        ),
        (
            "vertical_line",
            LineChart::new("x constant", "x", "y")
                .with_series(Series::line("a", vec![(2.0, 0.0), (2.0, 5.0)])),
        ),
        (
            "zero_width_given_ranges",
            LineChart {
                x_range: Some((5.0, 5.0)),
                y_range: Some((1.0, -1.0)),
                ..LineChart::new("given", "x", "y")
                    .with_series(Series::line("a", vec![(0.0, 0.0), (10.0, 1.0)]))
            },
        ),
        (
            "nan_given_range",
            LineChart {
                x_range: Some((nan, 1.0)),
                y_range: Some((0.0, inf)),
                ..LineChart::new("given", "x", "y")
                    .with_series(Series::line("a", vec![(0.0, 0.0), (10.0, 1.0)]))
            },
        ),
        (
            "data_far_outside_given_range",
            LineChart {
                x_range: Some((0.0, 1.0)),
                y_range: Some((0.0, 1.0)),
                ..LineChart::new("clipped", "x", "y").with_series(
                    Series::line("a", vec![(-1e9, -1e9), (0.5, 0.5), (1e9, -1e12)])
                        .with_style(SeriesStyle::LineAndPoints),
                )
            },
        ),
        (
            "huge_and_tiny_values",
            LineChart::new("scales", "x", "y")
                .with_series(Series::line(
                    "a",
                    vec![(0.0, 1e300), (1.0, -1e300), (2.0, 1e-300)],
                ))
                .with_series(Series::line("b", vec![(1e12, 1e-9), (1e12 + 1.0, 2e-9)])),
        ),
        (
            "equal_aspect_degenerate",
            LineChart {
                equal_aspect: true,
                ..LineChart::new("eq", "y [mm]", "z [mm]")
                    .with_series(Series::line("a", vec![(0.0, 0.0), (100.0, 0.0)]))
            },
        ),
        (
            "many_points",
            LineChart::new("dense", "t [s]", "F [kN]").with_series(
                Series::line(
                    "a",
                    (0..200_000)
                        .map(|k| (f64::from(k) * 1e-4, (f64::from(k) * 1e-3).sin()))
                        .collect(),
                )
                .with_style(SeriesStyle::Line),
            ),
        ),
    ];
    for (name, chart) in &cases {
        let path = dir.join(format!("{name}.png"));
        write_line_chart(&path, chart, (640, 480)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(png_size(&path), (640, 480), "{name}");
        let img = render_line_chart(chart, (640, 480)).unwrap();
        let l = img.panels[0];
        for v in [l.x_range.0, l.x_range.1, l.y_range.0, l.y_range.1] {
            assert!(v.is_finite(), "{name}: {l:?}");
        }
        assert!(
            l.x_range.0 < l.x_range.1 && l.y_range.0 < l.y_range.1,
            "{name}: {l:?}"
        );
    }
    write_multi_panel(
        &dir.join("all.png"),
        "edge cases",
        &cases.into_iter().map(|(_, c)| c).collect::<Vec<_>>(),
        4,
        (2000, 1500),
    )
    .unwrap();
}

#[test]
fn concurrent_first_use_is_safe() {
    let dir = out_dir("threads");
    std::thread::scope(|s| {
        for k in 0..4 {
            let dir = &dir;
            s.spawn(move || {
                let path = dir.join(format!("c{k}.png"));
                write_line_chart(&path, &profile_chart(), (500, 400)).unwrap();
                assert_eq!(png_size(&path), (500, 400));
            });
        }
    });
}
