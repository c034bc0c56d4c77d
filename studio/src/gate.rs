//! The bound on heavy requests: rendered frames, Lottie documents, rebuilds after an edit
//! and exports take a pass from a [`Gate`], so at most a few run at once whatever the
//! number of clients, and the light ones (`/api/status`, `/api/state`, the page) never
//! wait for a pass.
//!
//! Why: no lock that polling needs is held while a build or an export runs (they work on
//! an `Arc` of the last good animation, taken under a short lock), but with a thread per
//! connection fifty clients asking for frames at once ran fifty renders on two cores, and
//! the page's polling waited its turn for a core behind all of them. A gate rather than a
//! pool of worker threads: the connection's own thread does the work once it has a pass, so
//! nothing is handed between threads and a client that goes away frees its pass as it
//! unwinds.

use std::sync::{Condvar, Mutex};

/// A counting semaphore: at most `width` passes out at once.
#[derive(Debug)]
pub(crate) struct Gate {
    out: Mutex<usize>,
    freed: Condvar,
    width: usize,
}

/// A pass through a [`Gate`], given back when dropped.
#[derive(Debug)]
pub(crate) struct Pass<'a>(&'a Gate);

impl Gate {
    /// A gate letting `width` (at least one) heavy requests run at once.
    pub(crate) fn new(width: usize) -> Gate {
        Gate {
            out: Mutex::new(0),
            freed: Condvar::new(),
            width: width.max(1),
        }
    }

    /// A gate as wide as the machine's cores less one (at least one), which leaves a core
    /// for the light requests; the frame writer's own threads still use every core while
    /// a pass is out.
    pub(crate) fn cores_less_one() -> Gate {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Gate::new(cores.saturating_sub(1))
    }

    /// Waits for a pass.
    pub(crate) fn enter(&self) -> Pass<'_> {
        let mut out = self.out.lock().unwrap_or_else(|p| p.into_inner());
        while *out >= self.width {
            out = self.freed.wait(out).unwrap_or_else(|p| p.into_inner());
        }
        *out += 1;
        Pass(self)
    }
}

impl Drop for Pass<'_> {
    fn drop(&mut self) {
        let mut out = self.0.out.lock().unwrap_or_else(|p| p.into_inner());
        *out -= 1;
        self.0.freed.notify_one();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn no_more_passes_than_its_width_are_out_at_once() {
        let gate = Gate::new(2);
        let (inside, most) = (AtomicUsize::new(0), AtomicUsize::new(0));
        std::thread::scope(|s| {
            for _ in 0..8 {
                s.spawn(|| {
                    for _ in 0..50 {
                        let _pass = gate.enter();
                        let now = inside.fetch_add(1, Ordering::SeqCst) + 1;
                        most.fetch_max(now, Ordering::SeqCst);
                        std::thread::yield_now();
                        inside.fetch_sub(1, Ordering::SeqCst);
                    }
                });
            }
        });
        assert!(most.load(Ordering::SeqCst) <= 2, "{most:?} at once");
        assert_eq!(*gate.out.lock().unwrap(), 0, "every pass came back");
    }
}
