//! Criterion bench: one warm-started tread contact solve (Newton from the
//! previous step's surface parameters), the same solve as time stepping
//! makes it (the patch followed from its solve at the previous pose: the
//! start from the predictor, the lookups from the last pieces), a whole
//! wheelset step (alternating between two poses, and along a smooth path) (both wheels,
//! time stepping: patches followed by warm start), a cold solve (coarse
//! search + Newton) and a quasi-static wheelset solve (every piece searched
//! afresh), for S1002 on UIC60 and the ML95-like wheel on UIC60 1:20 (the
//! shared `runtime::fixtures` wheelsets).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::contact::{ContactOptions, FollowedPatch, SurfaceParams, WheelsetPose};
use runtime::fixtures::wheelsets::{self, SettledTread};
use runtime::geometry::track::Side;

fn bench(c: &mut Criterion) {
    for (name, m) in [
        (
            "s1002_uic60",
            wheelsets::s1002_uic60().expect("S1002/UIC60"),
        ),
        (
            "ml95_uic60_1in20",
            wheelsets::ml95_uic60_1in20().expect("ML95-like/UIC60"),
        ),
    ] {
        let set_up = SettledTread::new(&m).expect("settled");
        let (track, solver) = (&set_up.track, &set_up.solver);
        let options = ContactOptions::default();
        let tread = set_up.left_tread().expect("tread contact").params;
        // The next step: the wheelset 2 cm further on, slightly moved.
        let pose = set_up.pose(track, 10.02, 0.00201).expect("pose");
        let guess = SurfaceParams {
            s_rail_m: tread.s_rail_m + 0.02,
            ..tread
        };
        c.bench_function(&format!("contact_warm_tread_solve/{name}"), |b| {
            b.iter(|| {
                m.solve_pair(
                    track,
                    black_box(&pose),
                    Side::Left,
                    0,
                    Some(black_box(guess)),
                    &options,
                )
                .expect("solves")
            })
        });
        // The same move as time stepping makes it: the patch followed from
        // its solve at the other pose (the two alternate: 2 cm on, 10 µm
        // sideways), so every solve is a warm one from the previous pose.
        let pose_prev = set_up.pose(track, 10.0, 0.002).expect("pose");
        let c0 = m
            .solve_pair(track, &pose_prev, Side::Left, 0, Some(tread), &options)
            .expect("solves")
            .expect("tread contact");
        let mut patch = FollowedPatch::new(track, &pose_prev, &c0).expect("on the track");
        patch
            .solve(&m, track, &pose_prev, &options)
            .expect("solves")
            .expect("followed");
        let mut flip = false;
        c.bench_function(&format!("contact_follow_tread_solve/{name}"), |b| {
            b.iter(|| {
                flip = !flip;
                let p = if flip { &pose } else { &pose_prev };
                patch
                    .solve(&m, track, black_box(p), &options)
                    .expect("solves")
                    .expect("followed")
                    .params
            })
        });
        c.bench_function(&format!("contact_cold_tread_solve/{name}"), |b| {
            b.iter(|| {
                m.solve_pair(track, black_box(&pose), Side::Left, 0, None, &options)
                    .expect("solves")
            })
        });
        // Time stepping, as runs solve (multibody assembly): patches followed
        // by warm start, pieces searched again only after the wheel has moved.
        let mut step_solver = solver.clone();
        step_solver.options.reuse_clear_pieces = true;
        let pose_b = set_up.pose(track, 10.0, 0.002).expect("pose");
        let mut flip = false;
        c.bench_function(&format!("contact_wheelset_step_tread/{name}"), |b| {
            b.iter(|| {
                flip = !flip;
                let p = if flip { &pose } else { &pose_b };
                step_solver.solve(&m, track, black_box(p)).expect("solves")
            })
        });
        // Time stepping along a smooth path (a lateral sine of 1 mm
        // amplitude and 12.6 m wavelength, 2 cm per solve: at most 10 µm
        // sideways per solve, as the alternating step above), which no
        // solve repeats: 628 poses, one wavelength, then round again.
        let path_track = wheelsets::straight_track_for(&m, 40.0);
        let path: Vec<WheelsetPose> = (0..628)
            .map(|k| {
                let s = 10.0 + 0.02 * k as f64;
                let y = 0.002 + 0.001 * (2.0 * std::f64::consts::PI * (s - 10.0) / 12.56).sin();
                set_up.pose(&path_track, s, y).expect("pose")
            })
            .collect();
        let mut path_solver = solver.clone();
        path_solver.options.reuse_clear_pieces = true;
        let mut at = 0;
        c.bench_function(&format!("contact_wheelset_path_tread/{name}"), |b| {
            b.iter(|| {
                at = (at + 1) % path.len();
                path_solver
                    .solve(&m, &path_track, black_box(&path[at]))
                    .expect("solves")
            })
        });
        // Quasi-static (the default options): every piece searched afresh.
        let mut static_solver = solver.clone();
        c.bench_function(
            &format!("contact_wheelset_quasi_static_tread/{name}"),
            |b| {
                b.iter(|| {
                    static_solver
                        .solve(&m, track, black_box(&pose))
                        .expect("solves")
                })
            },
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
