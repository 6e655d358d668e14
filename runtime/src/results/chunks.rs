//! A run's record in pieces, for results that are written while the run
//! goes on (docs/guide/run-a-scene.md, "What is written when"): the samples
//! recorded since the last write are taken out as one chunk
//! ([`RunResults::take_samples`]) and handed to a [`ResultsSink`] (the
//! results file's writer appends them to its extendable datasets), while
//! the run keeps a bounded view of every `stride`-th sample for its summary
//! and plots ([`DecimatedView`]). Nothing here touches a file.

use super::{RunResults, Values, WHEEL_COLUMNS, WHEELSET_COLUMNS, WheelsetSeries, ZONE_COLUMNS};

/// Where the chunks of a run go (the results file's writer, with the `io`
/// feature: `crate::io::schema::ResultsWriter`).
pub trait ResultsSink {
    /// Append the samples of `chunk` (same wheelsets as every other chunk,
    /// times continuing the previous chunk's).
    fn append(&mut self, chunk: &RunResults) -> Result<(), SinkError>;
    /// Forget every sample appended so far (a run repeated from its start,
    /// e.g. when its flange guard tripped).
    fn restart(&mut self) -> Result<(), SinkError>;
    /// Samples appended so far.
    fn len(&self) -> usize;
    /// No sample appended yet.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A sink that could not take a chunk (the message names the file).
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct SinkError {
    pub message: String,
}

/// Apply `f64s` to every `f64` series and `flags` to every `u8` series
/// of `ws` (wheelset, wheel and zone columns, in column order).
fn for_each_series(
    ws: &mut WheelsetSeries,
    f64s: &mut dyn FnMut(&mut Vec<f64>),
    flags: &mut dyn FnMut(&mut Vec<u8>),
) {
    for c in &WHEELSET_COLUMNS {
        match &c.values {
            Values::F64(a) => f64s((a.series_mut)(ws)),
            Values::Flags { access, .. } => flags((access.series_mut)(ws)),
        }
    }
    for wheel in &mut ws.wheels {
        for c in &WHEEL_COLUMNS {
            match &c.values {
                Values::F64(a) => f64s((a.series_mut)(wheel)),
                Values::Flags { access, .. } => flags((access.series_mut)(wheel)),
            }
        }
        for zone in &mut wheel.zones {
            for c in &ZONE_COLUMNS {
                match &c.values {
                    Values::F64(a) => f64s((a.series_mut)(zone)),
                    Values::Flags { access, .. } => flags((access.series_mut)(zone)),
                }
            }
        }
    }
}

/// Keep the elements of `v` at indices `offset`, `offset + stride`, …
fn keep_strided<T: Copy>(v: &mut Vec<T>, offset: usize, stride: usize) {
    let kept: Vec<T> = v.iter().skip(offset).step_by(stride).copied().collect();
    *v = kept;
}

impl RunResults {
    /// Reserve room for `additional` more samples in every series (a run
    /// that knows how many samples it will record grows its ~200 series
    /// once instead of a dozen times each).
    pub fn reserve(&mut self, additional: usize) {
        self.time_s.reserve(additional);
        for ws in &mut self.wheelsets {
            for_each_series(ws, &mut |v| v.reserve(additional), &mut |v| {
                v.reserve(additional)
            });
        }
        for b in &mut self.bodies {
            b.for_each_series(&mut |v| v.reserve(additional));
        }
    }

    /// Move every sample out into a new record with the same wheelsets
    /// (names, Nadal limits), scene and attributes; `self` keeps its
    /// wheelsets with empty series, ready for the next samples.
    pub fn take_samples(&mut self) -> RunResults {
        let mut chunk = RunResults {
            time_s: std::mem::take(&mut self.time_s),
            wheelsets: Vec::with_capacity(self.wheelsets.len()),
            scene_toml: self.scene_toml.clone(),
            attributes: self.attributes.clone(),
            bodies: Vec::with_capacity(self.bodies.len()),
            car_body: self.car_body.clone(),
        };
        for b in &mut self.bodies {
            let empty = b.empty_like();
            chunk.bodies.push(std::mem::replace(b, empty));
        }
        for ws in &mut self.wheelsets {
            let taken = std::mem::take(ws);
            ws.name = taken.name.clone();
            for (w, t) in ws.wheels.iter_mut().zip(&taken.wheels) {
                w.nadal = t.nadal;
            }
            chunk.wheelsets.push(taken);
        }
        chunk
    }

    /// Append every sample of `other` (same wheelsets and bodies, in
    /// order) for which `keep(i)` holds, `i` its index in `other`.
    pub fn append_where(&mut self, other: &RunResults, keep: impl Fn(usize) -> bool) {
        let picked: Vec<usize> = (0..other.len()).filter(|&i| keep(i)).collect();
        self.time_s.extend(picked.iter().map(|&i| other.time_s[i]));
        for (b, o) in self.bodies.iter_mut().zip(&other.bodies) {
            let mut src = Vec::new();
            o.clone()
                .for_each_series(&mut |v| src.push(std::mem::take(v)));
            let mut k = src.iter();
            b.for_each_series(&mut |v| {
                let s = k.next().expect("same columns");
                v.extend(picked.iter().map(|&i| s[i]));
            });
        }
        for (ws, o) in self.wheelsets.iter_mut().zip(&other.wheelsets) {
            // Pair the series of both records in the same column order.
            let mut src_f = Vec::new();
            let mut src_u = Vec::new();
            let mut o = o.clone();
            for_each_series(&mut o, &mut |v| src_f.push(std::mem::take(v)), &mut |v| {
                src_u.push(std::mem::take(v))
            });
            let (mut kf, mut ku) = (src_f.iter(), src_u.iter());
            for_each_series(
                ws,
                &mut |v| {
                    let s = kf.next().expect("same columns");
                    v.extend(picked.iter().map(|&i| s[i]));
                },
                &mut |v| {
                    let s = ku.next().expect("same columns");
                    v.extend(picked.iter().map(|&i| s[i]));
                },
            );
        }
    }

    /// Keep every `stride`-th sample, starting with the first.
    pub fn keep_every(&mut self, stride: usize) {
        let stride = stride.max(1);
        keep_strided(&mut self.time_s, 0, stride);
        for b in &mut self.bodies {
            b.for_each_series(&mut |v| keep_strided(v, 0, stride));
        }
        for ws in &mut self.wheelsets {
            for_each_series(ws, &mut |v| keep_strided(v, 0, stride), &mut |v| {
                keep_strided(v, 0, stride)
            });
        }
    }
}

/// A bounded view of a long run: every `stride`-th sample, the stride
/// doubling whenever the view would hold more than `max_samples`, so that
/// the memory of the view does not grow with the run's length. The full
/// record is in the sink; the view feeds the summary and the plots, which
/// say when they come from a thinned view.
#[derive(Debug, Clone, PartialEq)]
pub struct DecimatedView {
    /// The samples kept (every `stride`-th of those seen).
    pub results: RunResults,
    /// Keep one sample in `stride`.
    pub stride: usize,
    /// Samples seen (appended to the sink) so far.
    pub seen: usize,
    max_samples: usize,
}

impl DecimatedView {
    /// An empty view shaped like `template` (its wheelsets, without
    /// samples), holding at most `max_samples` (at least 2).
    pub fn new(template: &RunResults, max_samples: usize) -> Self {
        let mut results = template.clone();
        let _ = results.take_samples();
        Self {
            results,
            stride: 1,
            seen: 0,
            max_samples: max_samples.max(2),
        }
    }

    /// A view whose first samples are `chunk`'s, taken without a copy:
    /// the same view as [`Self::new`] on `chunk` followed by
    /// [`Self::add`] of it (a short run's record is one chunk, and copying
    /// it cost 1.5 % of a bogie run).
    pub fn from_first(chunk: RunResults, max_samples: usize) -> Self {
        let mut view = Self {
            seen: chunk.len(),
            results: chunk,
            stride: 1,
            max_samples: max_samples.max(2),
        };
        view.decimate();
        view
    }

    /// Add the samples of `chunk`, the next ones of the run.
    pub fn add(&mut self, chunk: &RunResults) {
        let (seen, stride) = (self.seen, self.stride);
        self.results
            .append_where(chunk, |i| (seen + i) % stride == 0);
        self.seen += chunk.len();
        self.decimate();
    }

    /// Halve the samples kept until at most `max_samples` remain.
    fn decimate(&mut self) {
        while self.results.len() > self.max_samples {
            // Samples kept are at multiples of `stride`; keeping every
            // other one leaves the multiples of `2 stride`.
            self.results.keep_every(2);
            self.stride *= 2;
        }
    }

    /// Forget every sample (the run restarts).
    pub fn clear(&mut self) {
        let _ = self.results.take_samples();
        self.stride = 1;
        self.seen = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{WheelSample, WheelsetSample, ZoneSample};

    fn sample(x: f64) -> WheelsetSample {
        let mut zone = ZoneSample::NO_CONTACT;
        zone.in_contact = true;
        zone.normal_n = x;
        WheelsetSample {
            lateral_m: x,
            wheels: [WheelSample {
                travelled_m: x,
                zones: [zone, ZoneSample::NO_CONTACT],
            }; 2],
            ..WheelsetSample::default()
        }
    }

    /// Equal field by field, NaN equal to NaN (the zones hold NaN).
    fn same(a: &RunResults, b: &RunResults) -> bool {
        format!("{a:?}") == format!("{b:?}")
    }

    fn record(n: usize) -> RunResults {
        let mut r = RunResults::with_wheelsets(["front", "rear"]);
        for i in 0..n {
            r.push(i as f64, &[sample(i as f64), sample(-(i as f64))])
                .unwrap();
        }
        r
    }

    #[test]
    fn taking_the_samples_leaves_an_empty_record_of_the_same_shape() {
        let mut r = record(5);
        let chunk = r.take_samples();
        assert!(same(&chunk, &record(5)));
        assert!(r.is_empty());
        assert_eq!(r.wheelsets.len(), 2);
        assert_eq!(r.wheelsets[1].name, "rear");
        r.validate().unwrap();
        assert!(r.wheelsets[0].wheels[1].zones[0].normal_n.is_empty());
    }

    #[test]
    fn a_view_keeps_every_stride_th_sample_within_its_bound() {
        let full = record(1000);
        let mut view = DecimatedView::new(&full, 100);
        let mut rest = full.clone();
        // Chunks of 37 samples, as a sink would receive them.
        let mut start = 0;
        while start < 1000 {
            let end = (start + 37).min(1000);
            let mut chunk = RunResults::with_wheelsets(["front", "rear"]);
            chunk.append_where(&rest, |i| (start..end).contains(&i));
            view.add(&chunk);
            start = end;
        }
        rest.keep_every(view.stride);
        assert_eq!(view.seen, 1000);
        assert!(view.results.len() <= 100, "{}", view.results.len());
        assert_eq!(view.stride, 16);
        assert!(same(&view.results, &rest));
        view.results.validate().unwrap();
        assert_eq!(
            view.results.wheelsets[1].wheels[0].zones[0].normal_n[2],
            -32.0
        );
    }

    #[test]
    fn reserving_room_changes_no_sample() {
        let mut r = record(7);
        r.reserve(100);
        assert!(same(&r, &record(7)));
        assert!(r.time_s.capacity() >= 107);
        assert!(r.wheelsets[1].wheels[0].zones[1].normal_n.capacity() >= 107);
    }

    #[test]
    fn a_view_taken_from_its_first_chunk_is_the_view_built_from_a_copy() {
        let (first, second) = (record(300), record(50));
        for max in [1000, 100] {
            let mut copied = DecimatedView::new(&first, max);
            copied.add(&first);
            copied.add(&second);
            let mut moved = DecimatedView::from_first(first.clone(), max);
            moved.add(&second);
            assert_eq!((moved.seen, moved.stride), (copied.seen, copied.stride));
            assert!(same(&moved.results, &copied.results), "max {max}");
        }
    }
}
