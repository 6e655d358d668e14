//! PNG plots of a run: a synthetic two-wheelset run with sinusoidal lateral
//! motion and flange contact at the peaks.

use std::path::{Path, PathBuf};

use preproc::plot::{LineChart, render_line_chart, render_multi_panel};
use railsim::report::run_plots::{
    comparison_chart, contact_force_panels, creepage_panels, lateral_displacement_chart,
    write_comparison_plot, write_run_plots,
};
use runtime::results::{RunResults, WheelSample, WheelsetSample, ZoneSample};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two wheelsets 2.5 m apart hunting with a 16 m wavelength and 6 mm
/// amplitude at `speed_m_s`, 1 kHz for 2 s; the flange touches beyond ±5 mm.
fn synthetic(speed_m_s: f64, amplitude_m: f64) -> RunResults {
    let mut r = RunResults::with_wheelsets(["leading", "trailing"]);
    r.scene_toml = "# synthetic".into();
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        let samples: Vec<WheelsetSample> = (0..2)
            .map(|w| {
                let s = speed_m_s * t + 2.5 * (1 - w) as f64;
                let y = amplitude_m * (std::f64::consts::TAU * s / 16.0).sin();
                let wheel = |side: usize| {
                    // + left: the left flange touches at y > 5 mm, the right at y < −5 mm.
                    let toward = if side == 0 { y } else { -y };
                    let tread = ZoneSample {
                        in_contact: true,
                        normal_n: 60e3,
                        fx_n: 100.0 * y,
                        fy_n: -2e5 * y,
                        mz_nm: 0.0,
                        lateral_force_n: -3e6 * y,
                        vertical_force_n: 60e3,
                        xi: 1e-3 * toward / amplitude_m,
                        eta: -2e-3 * y / amplitude_m,
                        phi_1_m: 0.05 * toward / amplitude_m,
                        y_wheel_m: 0.0,
                        y_rail_m: 0.0,
                        contact_angle_rad: 0.05,
                        lead_m: 0.0,
                        fallback: 0,
                    };
                    let flange = if toward > 0.005 {
                        ZoneSample {
                            in_contact: true,
                            normal_n: 4e7 * (toward - 0.005),
                            lateral_force_n: -3e7 * (y - 0.005 * y.signum()),
                            vertical_force_n: 2e7 * (toward - 0.005),
                            contact_angle_rad: 1.2,
                            ..tread
                        }
                    } else {
                        ZoneSample::NO_CONTACT
                    };
                    WheelSample {
                        travelled_m: s,
                        zones: [tread, flange],
                    }
                };
                WheelsetSample {
                    lateral_m: y,
                    yaw_rad: 0.0,
                    roll_rad: 0.0,
                    distance_m: s,
                    speed_m_s,
                    track_s_m: 5.0 + s,
                    wheels: [wheel(0), wheel(1)],
                }
            })
            .collect();
        r.push(t, &samples).unwrap();
    }
    r
}

/// PNG signature and the IHDR image size.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert!(bytes.len() > 20_000, "{} is too small", path.display());
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is no PNG",
        path.display()
    );
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes(b.try_into().unwrap());
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

/// The same charts with their series emptied (axes, titles, legends stay).
fn without_data(charts: &[LineChart]) -> Vec<LineChart> {
    charts
        .iter()
        .map(|c| {
            let mut c = c.clone();
            c.x_range = Some((0.0, 80.0));
            c.y_range = Some((-1.0, 1.0));
            for s in &mut c.series {
                s.points.clear();
            }
            c
        })
        .collect()
}

/// The data adds clearly visible ink to every panel.
fn assert_panels_drawn(charts: &[LineChart]) {
    for (chart, empty) in charts.iter().zip(without_data(charts)) {
        let size = (900, 500);
        let with = render_line_chart(chart, size).unwrap().non_white_pixels();
        let without = render_line_chart(&empty, size).unwrap().non_white_pixels();
        assert!(
            with > without + 2_000,
            "panel '{}' draws little data: {with} vs {without} non-white pixels",
            chart.title
        );
    }
}

#[test]
fn run_plots_are_written_and_show_the_data() {
    let dir = scratch("run_plots");
    let r = synthetic(36.0, 0.006);
    let files = write_run_plots(&r, &dir.join("plots"), "synthetic bogie, 36 m/s").unwrap();
    let names: Vec<_> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "lateral_displacement.png",
            "contact_forces.png",
            "creepages.png"
        ]
    );
    for f in &files {
        let (w, h) = png_size(f);
        assert!(w >= 800 && h >= 400, "{}: {w}×{h}", f.display());
    }
    // One row of panels per wheelset.
    let (_, h1) = png_size(&files[1]);
    let one = RunResults {
        wheelsets: r.wheelsets[..1].to_vec(),
        ..r.clone()
    };
    let files1 = write_run_plots(&one, &dir.join("one"), "one wheelset").unwrap();
    assert!(png_size(&files1[1]).1 < h1);

    // The lateral chart: mm against the wheelset's distance, one series per wheelset.
    let chart = lateral_displacement_chart(&r, "t");
    assert_eq!(chart.series.len(), 2);
    let (x, y) = chart.series[1].points[500];
    assert_eq!(x, r.wheelsets[1].distance_m[500]);
    assert!((y - 1e3 * r.wheelsets[1].lateral_m[500]).abs() < 1e-9);
    assert_ne!(chart.series[0].colour, chart.series[1].colour);
    assert_panels_drawn(&[chart]);

    // Y sums tread and flange, + towards the track centre (−n for the left
    // wheel), as the results file's y_n and the Y/Q summary; out of flange
    // contact the flange counts 0.
    let forces = contact_force_panels(&r);
    assert_eq!(forces.len(), 6);
    let left = &r.wheelsets[0].wheels[0];
    let k = (0..r.len())
        .find(|&k| left.flange_contact[k] == 1)
        .expect("the synthetic run touches the flange");
    let expected_kn = -1e-3 * (left.zones[0].lateral_force_n[k] + left.zones[1].lateral_force_n[k]);
    assert!((forces[0].series[0].points[k].1 - expected_kn).abs() < 1e-9);
    let free = (0..r.len()).find(|&k| left.flange_contact[k] == 0).unwrap();
    assert_eq!(
        forces[0].series[0].points[free].1,
        -1e-3 * left.zones[0].lateral_force_n[free]
    );
    assert!(forces[0].y_label.contains("+ towards the track centre"));
    // The right wheel's Y is + towards the centre too: +n.
    let right = &r.wheelsets[0].wheels[1];
    let kr = (0..r.len())
        .find(|&k| right.flange_contact[k] == 1)
        .expect("the right flange touches too");
    let expected_right_kn =
        1e-3 * (right.zones[0].lateral_force_n[kr] + right.zones[1].lateral_force_n[kr]);
    assert!((forces[0].series[1].points[kr].1 - expected_right_kn).abs() < 1e-9);
    assert_eq!(forces[2].series[0].points[free].1, 0.0, "no flange force");
    assert!(forces[2].series[0].points[k].1 > 0.0);
    // Left and right wheels keep their colours in every panel.
    for p in forces.iter().chain(&creepage_panels(&r)) {
        assert_eq!(p.series[0].colour, Some(0), "{}", p.title);
        assert_eq!(p.series[1].colour, Some(1), "{}", p.title);
        assert!(
            p.x_label.contains("[m]") && p.y_label.contains('['),
            "{}",
            p.title
        );
    }
    assert_panels_drawn(&forces);

    let creep = creepage_panels(&r);
    assert_eq!(creep.len(), 6);
    assert_panels_drawn(&creep);

    // The multi-panel image in memory has ink in every panel.
    let img = render_multi_panel("t", &forces, 3, (1900, 1120)).unwrap();
    assert_eq!(img.panels.len(), 6);
    assert!(img.non_white_pixels() > 50_000);
}

#[test]
fn comparison_plot_of_a_speed_sweep() {
    let dir = scratch("run_plots_comparison");
    let slow = synthetic(30.0, 0.002);
    let fast = synthetic(40.0, 0.006);
    let runs = vec![
        ("30 m/s, Polach".to_string(), &slow),
        ("40 m/s, Polach".to_string(), &fast),
    ];
    let path = dir.join("sweep.png");
    write_comparison_plot(&runs, 1, &path, "trailing wheelset, speed sweep").unwrap();
    let (w, h) = png_size(&path);
    assert!(w >= 800 && h >= 400);

    let chart = comparison_chart(&runs, 1, "t").unwrap();
    assert_eq!(chart.series.len(), 2);
    assert_eq!(chart.series[0].label, "30 m/s, Polach");
    assert_eq!(chart.series[0].colour, Some(0));
    assert_eq!(chart.series[1].colour, Some(1));
    let peak = |i: usize| {
        chart.series[i]
            .points
            .iter()
            .map(|p| p.1.abs())
            .fold(0.0, f64::max)
    };
    assert!((peak(0) - 2.0).abs() < 0.01 && (peak(1) - 6.0).abs() < 0.01);
    assert_panels_drawn(&[chart]);

    let e = write_comparison_plot(&runs, 2, &dir.join("none.png"), "t").unwrap_err();
    assert!(e.to_string().contains("no wheelset 2"), "{e}");
    assert!(!dir.join("none.png").exists());
}

#[test]
fn inconsistent_results_are_not_plotted() {
    let dir = scratch("run_plots_bad");
    let mut r = synthetic(36.0, 0.006);
    r.wheelsets[0].wheels[1].zones[0].xi.pop();
    let e = write_run_plots(&r, &dir, "bad").unwrap_err();
    assert!(
        format!("{e:#}").contains("wheelset_0/right/tread/xi"),
        "{e:#}"
    );
    assert!(std::fs::read_dir(&dir).unwrap().next().is_none());
}

/// `sim compare` prints each later run's lateral difference from the first,
/// per wheelset: zero for the same run, the amplitude difference for two
/// sine runs in phase (6 mm against 5 mm: 1 mm at the peaks).
#[test]
fn sim_compare_prints_the_lateral_difference_per_wheelset() {
    let dir = scratch("sim_compare_difference");
    let (a, b) = (dir.join("a.h5"), dir.join("b.h5"));
    runtime::io::schema::write_results(&a, &synthetic(10.0, 6e-3)).unwrap();
    runtime::io::schema::write_results(&b, &synthetic(10.0, 5e-3)).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_sim"))
        .arg("compare")
        .args([&a, &a, &b])
        .arg("--out")
        .arg(dir.join("cmp.png"))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let max_um: Vec<f64> = out
        .lines()
        .filter(|l| l.contains("lateral difference"))
        .map(|l| {
            let after = l.split("max ").nth(1).unwrap();
            after.split(' ').next().unwrap().parse().unwrap()
        })
        .collect();
    // a vs a (two wheelsets), b vs a (two wheelsets).
    assert_eq!(max_um.len(), 4, "{out}");
    assert_eq!(&max_um[..2], &[0.0, 0.0], "{out}");
    for m in &max_um[2..] {
        assert!((m - 1000.0).abs() < 1.0, "expected ≈ 1000 µm: {out}");
    }
    assert!(out.contains("wheelset 1 (trailing)"), "{out}");
}
