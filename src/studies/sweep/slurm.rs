//! A study on a Slurm cluster: a job array whose task I runs shard I of N
//! (`sim sweep STUDY --shard I/N`), and a merge job that waits for every
//! task (`--dependency=afterok`) and runs `sim sweep merge DIR`. Slurm
//! does the scheduling; we only write its scripts and, if asked, submit
//! them with `sbatch` (docs/guide/sweeps.md, "Run a study on a cluster").

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail, ensure};

use super::{Dir, Study};

/// The job settings of `sim sweep slurm`.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmOptions {
    /// Array tasks (shards).
    pub shards: usize,
    pub partition: Option<String>,
    /// Wall-time limit per task, Slurm's syntax (`2:00:00`).
    pub time: Option<String>,
    /// Cores per task: the shard's threads.
    pub cpus_per_task: usize,
    /// The `sim` the tasks run (this one, by its absolute path).
    pub sim: PathBuf,
}

/// The scripts written.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SlurmScripts {
    pub array: PathBuf,
    pub merge: PathBuf,
    /// The shell command that submits both.
    pub command: String,
}

/// `s` quoted for a POSIX shell.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).with_context(|| format!("the absolute path of {}", p.display()))
}

fn check_word(what: &str, s: &str) -> Result<()> {
    ensure!(
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_:.,".contains(c)),
        "--{what} '{s}': letters, digits and - _ : . , only"
    );
    Ok(())
}

/// Writes `DIR/slurm/array.sbatch` and `DIR/slurm/merge.sbatch` for
/// `study` (paths absolute, so the jobs run from any directory).
pub fn write_scripts(study: &Study, dir: &Dir, o: &SlurmOptions) -> Result<SlurmScripts> {
    ensure!(o.shards >= 1, "--shards must be >= 1");
    ensure!(
        o.shards <= study.variants.len().max(1),
        "--shards {} is more than the study's {} variants",
        o.shards,
        study.variants.len()
    );
    ensure!(o.cpus_per_task >= 1, "--cpus-per-task must be >= 1");
    if let Some(p) = &o.partition {
        check_word("partition", p)?;
    }
    if let Some(t) = &o.time {
        check_word("time", t)?;
    }
    dir.prepare(study)?;
    let root = absolute(&dir.root)?;
    let slurm = root.join("slurm");
    std::fs::create_dir_all(&slurm).with_context(|| format!("creating {}", slurm.display()))?;
    let sim = quote(&absolute(&o.sim)?.display().to_string());
    let file = quote(&absolute(&study.file.path)?.display().to_string());
    let out = quote(&root.display().to_string());
    let mut common = String::new();
    if let Some(p) = &o.partition {
        common += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(t) = &o.time {
        common += &format!("#SBATCH --time={t}\n");
    }
    let title = study.file.sweep.title.replace('\n', " ");
    let n = o.shards;
    let array = format!(
        "#!/bin/bash\n\
         # railsim study '{title}': task I of the array runs shard I of {n}.\n\
         # Written by `sim sweep slurm`; submit with the command it printed.\n\
         #SBATCH --job-name=railsim-sweep\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --cpus-per-task={c}\n\
         #SBATCH --output={log}/shard_%a.out\n\
         {common}\
         set -euo pipefail\n\
         exec {sim} sweep {file} --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\" --out {out} --jobs \"${{SLURM_CPUS_PER_TASK:-{c}}}\" --quiet\n",
        last = n - 1,
        c = o.cpus_per_task,
        log = slurm.display(),
    );
    let merge = format!(
        "#!/bin/bash\n\
         # railsim study '{title}': joins the {n} shards once every task ended well.\n\
         #SBATCH --job-name=railsim-merge\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --output={log}/merge.out\n\
         {common}\
         set -euo pipefail\n\
         exec {sim} sweep merge {out}\n",
        log = slurm.display(),
    );
    let array_path = slurm.join("array.sbatch");
    let merge_path = slurm.join("merge.sbatch");
    for (p, text) in [(&array_path, &array), (&merge_path, &merge)] {
        runtime::io::atomic::write_atomically(p, |tmp| std::fs::write(tmp, text))
            .with_context(|| format!("writing {}", p.display()))?;
    }
    let command = format!(
        "jobid=$(sbatch --parsable {}) && sbatch --dependency=afterok:${{jobid%%;*}} {}",
        quote(&array_path.display().to_string()),
        quote(&merge_path.display().to_string())
    );
    Ok(SlurmScripts {
        array: array_path,
        merge: merge_path,
        command,
    })
}

/// The job ids of a submission.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Submitted {
    pub array_job: String,
    pub merge_job: String,
}

fn sbatch(args: &[&str]) -> Result<String> {
    let out = Command::new("sbatch")
        .args(args)
        .output()
        .context("running sbatch (is Slurm installed and SLURM_CONF set?)")?;
    if !out.status.success() {
        bail!(
            "sbatch {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    // `--parsable` prints "id" or "id;cluster".
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text
        .trim()
        .split(';')
        .next()
        .unwrap_or_default()
        .to_string();
    ensure!(
        !id.is_empty() && id.chars().all(|c| c.is_ascii_digit()),
        "sbatch printed '{}', not a job id",
        text.trim()
    );
    Ok(id)
}

/// Submits the array, then the merge job after it.
pub fn submit(scripts: &SlurmScripts) -> Result<Submitted> {
    let array = scripts.array.display().to_string();
    let array_job = sbatch(&["--parsable", &array])?;
    let merge = scripts.merge.display().to_string();
    let dependency = format!("--dependency=afterok:{array_job}");
    let merge_job = sbatch(&["--parsable", &dependency, &merge])?;
    Ok(Submitted {
        array_job,
        merge_job,
    })
}
