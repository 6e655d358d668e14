//! Criterion bench: building 10 km of track at a 0.1 m table step (fit,
//! arc-length re-parameterisation, rails, tabulation of the three tables),
//! and the same plus writing the HDF5 file.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use preproc::inputs::CenterlineInput;
use preproc::{BuildConfig, NoProgress, TrackInputs, TrackModel};
use runtime::geometry::track::Provenance;

/// Control points every 5 m of a track alternating 500 m straights and
/// 500 m arcs of radius 1000 m (left and right), `length_m` long, with a
/// 1 % grade on every other kilometre.
pub fn synthetic_centerline(length_m: f64) -> String {
    let mut s = String::from("x,y,z\n");
    let (mut x, mut y, mut z, mut heading) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    let h = 5.0;
    let n = (length_m / h) as usize;
    for k in 0..=n {
        s += &format!("{x:.9},{y:.9},{z:.9}\n");
        let dist = k as f64 * h;
        let element = (dist / 500.0) as usize;
        let curvature = match element % 4 {
            1 => 1.0 / 1000.0,
            3 => -1.0 / 1000.0,
            _ => 0.0,
        };
        let grade = if (dist / 1000.0) as usize % 2 == 1 {
            0.01
        } else {
            0.0
        };
        let mid = heading + 0.5 * curvature * h;
        x += h * mid.cos();
        y += h * mid.sin();
        z += h * grade;
        heading += curvature * h;
    }
    s
}

fn bench(c: &mut Criterion) {
    let text = synthetic_centerline(10_000.0);
    let inputs = TrackInputs {
        centerline: CenterlineInput::parse(Path::new("synthetic.csv"), &text).expect("valid"),
        cant: None,
        irregularities: None,
    };
    let config = BuildConfig::default();
    let mut group = c.benchmark_group("build_10km_step_0.1m");
    group.sample_size(10);
    group.bench_function("model_and_tables", |b| {
        b.iter(|| {
            let m = TrackModel::build(&inputs, &config).expect("builds");
            m.tabulate(&NoProgress).expect("tabulates")
        })
    });
    let dir = std::env::temp_dir().join(format!("build-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = dir.join("bench.h5");
    group.bench_function("model_tables_and_hdf5", |b| {
        b.iter(|| {
            let m = TrackModel::build(&inputs, &config).expect("builds");
            let t = m.tabulate(&NoProgress).expect("tabulates");
            runtime::io::schema::write_track_file(&out, &t, &Provenance::default()).expect("writes")
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
