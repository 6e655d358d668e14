//! A run's samples handed to its results file while the run goes on
//! (docs/guide/run-a-scene.md, "What is written when"): every
//! [`FLUSH_SAMPLES`] samples the recorder's record is taken out and
//! appended to the sink (`runtime::io::schema::ResultsWriter`: chunked,
//! extendable datasets), so that the memory a run needs does not grow
//! with its length. The summary, the guard and the plots use a bounded
//! view ([`DecimatedView`], at most [`VIEW_MAX_SAMPLES`] samples: every
//! sample of a run up to that length, every 2nd, 4th, … of a longer one,
//! which the summary then states).

use runtime::multibody::DynamicsError;
use runtime::results::{DecimatedView, ResultsSink, RunResults};

/// Samples recorded between two appends to the sink: four of the results
/// file's chunks, so that each chunk is written once, whole (the file
/// keeps no chunk cache, `runtime::io::schema::ResultsWriter`).
pub const FLUSH_SAMPLES: usize = 4 * runtime::io::schema::RESULTS_CHUNK_SAMPLES;

/// Most samples the view of a streamed run keeps in memory: 200 000
/// samples are 200 s at 1 kHz, about 110 MB per wheelset (the summary of
/// every shipped scene is computed from all its samples).
pub const VIEW_MAX_SAMPLES: usize = 200_000;

/// The sink of a run and the view it keeps.
pub struct Stream<'a> {
    sink: &'a mut dyn ResultsSink,
    view: Option<DecimatedView>,
    /// Time of the last sample handed over (s).
    last_time_s: f64,
}

impl<'a> Stream<'a> {
    pub fn new(sink: &'a mut dyn ResultsSink) -> Self {
        Self {
            sink,
            view: None,
            last_time_s: 0.0,
        }
    }

    /// Hand the samples of `record` (the recorder's) to the sink, leaving
    /// it empty, once it holds `at_least` samples.
    pub fn flush(
        &mut self,
        record: &mut RunResults,
        at_least: usize,
        t_s: f64,
    ) -> Result<(), DynamicsError> {
        if record.len() < at_least.max(1) {
            return Ok(());
        }
        let chunk = record.take_samples();
        self.last_time_s = chunk.time_s.last().copied().unwrap_or(self.last_time_s);
        self.sink
            .append(&chunk)
            .map_err(|e| DynamicsError::Output {
                t_s,
                message: e.message,
            })?;
        match &mut self.view {
            Some(view) => view.add(&chunk),
            None => self.view = Some(DecimatedView::from_first(chunk, VIEW_MAX_SAMPLES)),
        }
        Ok(())
    }

    /// Forget every sample (the run is repeated from its start).
    pub fn restart(&mut self) -> anyhow::Result<()> {
        self.view = None;
        self.last_time_s = 0.0;
        self.sink.restart().map_err(|e| anyhow::anyhow!(e.message))
    }

    /// Time of the last sample handed over (s).
    pub fn last_time_s(&self) -> f64 {
        self.last_time_s
    }

    /// The samples handed over so far.
    pub fn samples(&self) -> usize {
        self.sink.len()
    }

    /// The view (every `stride`-th sample) in place of `record` (emptied
    /// by the flushes), and the stride.
    pub fn view_into(&mut self, record: &mut RunResults) -> usize {
        match self.view.take() {
            Some(v) => {
                *record = v.results;
                v.stride
            }
            None => 1,
        }
    }
}
