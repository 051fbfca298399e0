//! A value computed once and shared between threads whose waiters help instead of blocking.
//!
//! The columns of an exact edit run on rayon's workers and all need the responses to the
//! anchors, lifted once. With a plain `OnceLock`, the column that arrives second blocks in
//! `get_or_init` for the whole lifting (tens of milliseconds on a real mesh), and the lifting's
//! parallel parts (combining each entry's p-adic digits, dividing out the content, checking the
//! solution) find no free worker: half the machine idles. Here a worker that finds the value
//! being computed by another runs pending rayon jobs — the computation's own — until it is
//! there. Threads outside rayon's pool block as with `OnceLock`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::Duration;

/// Consecutive rounds without a job to run after which a helping worker sleeps between checks.
const IDLE_ROUNDS_BEFORE_SLEEP: u32 = 64;

/// How long an idle helper sleeps between checks once it has found nothing to run for a while.
const IDLE_SLEEP: Duration = Duration::from_micros(20);

/// A value initialised once; see the module documentation.
#[derive(Debug)]
pub(crate) struct SharedOnce<T> {
    value: OnceLock<T>,
    /// Set while a rayon worker computes the value.
    claimed: AtomicBool,
}

impl<T> Default for SharedOnce<T> {
    fn default() -> Self {
        SharedOnce {
            value: OnceLock::new(),
            claimed: AtomicBool::new(false),
        }
    }
}

impl<T: Clone> Clone for SharedOnce<T> {
    /// The same value if it is there; an unclaimed empty cell otherwise.
    fn clone(&self) -> Self {
        SharedOnce {
            value: self.value.clone(),
            claimed: AtomicBool::new(false),
        }
    }
}

/// Clears the claim when the computing worker is done, also when it unwinds (then a waiter
/// takes the computation over).
struct Claim<'a>(&'a AtomicBool);

impl Drop for Claim<'_> {
    fn drop(&mut self) {
        self.0.store(false, Ordering::Release);
    }
}

impl<T> SharedOnce<T> {
    /// The value, if it has been computed.
    pub(crate) fn get(&self) -> Option<&T> {
        self.value.get()
    }

    /// The value, computed by `init` if no thread has computed it yet. A rayon worker that
    /// finds another computing it runs rayon jobs meanwhile.
    pub(crate) fn get_or_init(&self, init: impl FnOnce() -> T) -> &T {
        if let Some(value) = self.value.get() {
            return value;
        }
        if rayon::current_thread_index().is_none() {
            return self.value.get_or_init(init);
        }
        if self
            .claimed
            .compare_exchange(false, true, Ordering::AcqRel, Ordering::Acquire)
            .is_ok()
        {
            let _claim = Claim(&self.claimed);
            return self.value.get_or_init(init);
        }
        let mut idle = 0;
        loop {
            if let Some(value) = self.value.get() {
                return value;
            }
            if !self.claimed.load(Ordering::Acquire) {
                // Done (the value is there now) or the computing worker unwound: compute it here.
                return self.get_or_init(init);
            }
            match rayon::yield_now() {
                Some(rayon::Yield::Executed) => idle = 0,
                _ if idle < IDLE_ROUNDS_BEFORE_SLEEP => {
                    idle += 1;
                    std::thread::yield_now();
                }
                _ => std::thread::sleep(IDLE_SLEEP),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::sync::atomic::AtomicUsize;

    /// Many workers asking at once: one computation, every one of them gets its value, and the
    /// computation's own parallel loop runs (also on the waiting workers).
    #[test]
    fn computed_once_for_every_worker() {
        let once = SharedOnce::default();
        let computed = AtomicUsize::new(0);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .expect("a pool");
        let seen: Vec<u64> = pool.install(|| {
            (0..64)
                .into_par_iter()
                .map(|_| {
                    *once.get_or_init(|| {
                        computed.fetch_add(1, Ordering::SeqCst);
                        (0..100_000u64).into_par_iter().map(|x| x % 7).sum::<u64>()
                    })
                })
                .collect()
        });
        let expected: u64 = (0..100_000u64).map(|x| x % 7).sum();
        assert_eq!(computed.load(Ordering::SeqCst), 1);
        assert!(seen.iter().all(|v| *v == expected));
    }

    /// A computation that panics leaves the cell empty and unclaimed: the next caller computes.
    #[test]
    fn a_failed_computation_is_taken_over() {
        let once = SharedOnce::default();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let failed = pool.install(|| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                once.get_or_init(|| -> u32 { panic!("lifting failed") })
            }))
        });
        assert!(failed.is_err());
        assert_eq!(once.get(), None);
        assert_eq!(pool.install(|| *once.get_or_init(|| 7)), 7);
        assert_eq!(*once.get_or_init(|| 8), 7);
    }
}
