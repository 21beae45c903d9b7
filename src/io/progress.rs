//! Progress observers: how a long computation (a run, an ensemble, a sweep, a study) says how
//! far it got, as an optimiser tells its observers in argmin. Every computation takes a
//! `&dyn Progress`; a terminal progress bar, a closure or [`Silent`] can observe it, and
//! observing never changes a result.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::atomic::{AtomicU64, Ordering};

/// An observer of a long computation. `Sync` because parallel loops report from their
/// worker threads.
pub trait Progress: Sync {
    /// `done` of `total` units of work are finished; `total` is `None` while it is not known
    /// (a run still settling to its steady state).
    fn observe(&self, done: u64, total: Option<u64>);

    /// The unit of work now starting, named for people (a study's case and setting).
    fn stage(&self, _name: &str) {}

    /// Whether the caller wants the computation to stop. Runs ask between rotations and
    /// stop with [`crate::Error::Cancelled`] (the Python bindings on Ctrl-C); observers that
    /// only watch never cancel.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Passes on only the cancellation of the observer it wraps: for the inner runs of a parallel
/// loop, whose own rotation counts would garble the loop's count.
pub struct Cancellation<'a>(pub &'a dyn Progress);

impl Progress for Cancellation<'_> {
    fn observe(&self, _: u64, _: Option<u64>) {}

    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// Observes nothing.
pub struct Silent;

impl Progress for Silent {
    fn observe(&self, _: u64, _: Option<u64>) {}
}

/// A closure observes the counts only.
impl<F: Fn(u64, Option<u64>) + Sync> Progress for F {
    fn observe(&self, done: u64, total: Option<u64>) {
        self(done, total)
    }
}

impl Progress for ProgressBar {
    fn observe(&self, done: u64, total: Option<u64>) {
        if let Some(total) = total {
            self.set_length(total);
        }
        self.set_position(done);
    }

    fn stage(&self, name: &str) {
        self.set_message(name.to_owned());
    }
}

/// Counts the finished units of a parallel loop of `total` units for an observer.
pub struct Counter<'a> {
    progress: &'a dyn Progress,
    done: AtomicU64,
    total: u64,
}

impl<'a> Counter<'a> {
    /// A count of nothing finished out of `total`.
    pub fn new(progress: &'a dyn Progress, total: usize) -> Self {
        Counter {
            progress,
            done: AtomicU64::new(0),
            total: total as u64,
        }
    }

    /// One more unit finished.
    pub fn finish_one(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        self.progress.observe(done, Some(self.total));
    }
}

/// A progress bar of `len` `unit`s on stderr (hidden when stderr is not a terminal), with the
/// stage under way after the counts.
pub fn progress_bar(len: u64, unit: &str) -> ProgressBar {
    let style = ProgressStyle::with_template(&format!(
        "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {unit} (eta {{eta}}) {{msg}}"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr()).with_style(style)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn a_counter_reports_every_unit_once_with_the_total() {
        let seen = Mutex::new(Vec::new());
        let observer = |done, total| seen.lock().unwrap().push((done, total));
        let counter = Counter::new(&observer, 3);
        std::thread::scope(|s| {
            for _ in 0..3 {
                s.spawn(|| counter.finish_one());
            }
        });
        let mut seen = seen.into_inner().unwrap();
        seen.sort_unstable();
        assert_eq!(seen, [(1, Some(3)), (2, Some(3)), (3, Some(3))]);
    }
}
