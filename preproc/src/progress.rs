//! Progress reporting behind a callback, so the library never prints; the
//! CLI turns the events into an indicatif bar.

/// A progress event of a long build.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Progress {
    /// A stage starts, with the number of rows it will produce.
    Stage { name: &'static str, rows: u64 },
    /// More rows of the current stage are done.
    Rows(u64),
    /// The build is complete.
    Done,
}

/// Receives [`Progress`] events; may be called from several threads.
pub trait ProgressSink: Sync {
    fn event(&self, e: Progress);
}

impl<F: Fn(Progress) + Sync> ProgressSink for F {
    fn event(&self, e: Progress) {
        self(e)
    }
}

/// A sink that ignores everything.
pub struct NoProgress;

impl ProgressSink for NoProgress {
    fn event(&self, _: Progress) {}
}
