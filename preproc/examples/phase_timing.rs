//! Time the phases of a build: `cargo run --release -p preproc --example phase_timing -- CENTERLINE.csv OUT.h5`.

use std::path::Path;
use std::time::Instant;

use preproc::inputs::CenterlineInput;
use preproc::{BuildConfig, NoProgress, TrackInputs, TrackModel};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (input, out) = (Path::new(&args[1]), Path::new(&args[2]));
    let t0 = Instant::now();
    let text = std::fs::read_to_string(input)?;
    let inputs = TrackInputs {
        centerline: CenterlineInput::parse(input, &text)?,
        cant: None,
        irregularities: None,
    };
    let t1 = Instant::now();
    let model = TrackModel::build(&inputs, &BuildConfig::default())?;
    let t2 = Instant::now();
    let tables = model.tabulate(&NoProgress)?;
    let t3 = Instant::now();
    runtime::io::schema::write_track_file(out, &tables, &Default::default())?;
    let t4 = Instant::now();
    println!(
        "parse {:.3} s, model {:.3} s, tabulate {:.3} s, write {:.3} s, total {:.3} s",
        (t1 - t0).as_secs_f64(),
        (t2 - t1).as_secs_f64(),
        (t3 - t2).as_secs_f64(),
        (t4 - t3).as_secs_f64(),
        (t4 - t0).as_secs_f64()
    );
    Ok(())
}
