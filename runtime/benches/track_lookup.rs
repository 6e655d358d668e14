//! Criterion bench: O(1) rail table look-up (position and frame by linear
//! interpolation at an arbitrary arc length), and the s → L → rail chain.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::fixtures::tracks::straight_centerline;
use runtime::geometry::track::{CenterlineTable, RailRow, RailTable, Side};

/// A 10 km rail on a 1000 m radius arc, rows every 0.1 m.
fn arc_rail(step: f64, length: f64, radius: f64) -> RailTable {
    let n = (length / step) as usize;
    let rows = (0..=n)
        .map(|k| {
            let l = k as f64 * step;
            let th = l / radius;
            RailRow {
                l_m: l,
                position: [radius * th.sin(), radius * (1.0 - th.cos()), 0.0],
                t: [th.cos(), th.sin(), 0.0],
                n: [-th.sin(), th.cos(), 0.0],
                b: [0.0, 0.0, 1.0],
            }
        })
        .collect();
    RailTable::new(Side::Left, rows).expect("valid table")
}

fn centerline(step: f64, length: f64) -> CenterlineTable {
    straight_centerline(step, (length / step) as usize, |s| (s, s))
}

fn bench(c: &mut Criterion) {
    let rail = arc_rail(0.1, 10_000.0, 1000.0);
    let cl = centerline(0.1, 10_000.0);
    // Pseudo-random arc lengths (a fixed LCG), so the look-ups are not all in cache.
    let mut x = 12345u64;
    let ls: Vec<f64> = (0..4096)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 * 9_999.0
        })
        .collect();
    let mut i = 0;
    c.bench_function("rail_table_lookup", |b| {
        b.iter(|| {
            i = (i + 1) & 4095;
            black_box(rail.at(black_box(ls[i])).expect("in range"))
        })
    });
    let mut j = 0;
    c.bench_function("centerline_s_to_rail_l", |b| {
        b.iter(|| {
            j = (j + 1) & 4095;
            black_box(cl.rail_l(Side::Left, black_box(ls[j])).expect("in range"))
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
