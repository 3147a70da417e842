//! Long work off the GIL, interruptible with Ctrl-C.
//!
//! Python runs signal handlers only on its main thread, so a check from a
//! Rust worker thread never sees Ctrl-C. The work therefore runs on a scoped
//! worker thread while the calling (main) thread waits without the GIL in
//! short slices, checking signals between them; on Ctrl-C it raises the
//! `cancel` flag, which the work reads at its own granularity (a rolling run:
//! between steps), waits for the worker to stop, and re-raises
//! `KeyboardInterrupt`. Work with no cancellation point (one multipoint or
//! BEM solve, a static run) still runs to its end before the interrupt is
//! raised.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::prelude::*;

/// How long the main thread waits without the GIL between signal checks.
const POLL: Duration = Duration::from_millis(50);

/// Runs `work(cancel)` on a worker thread; returns its value, or the
/// signal's exception (`KeyboardInterrupt`) if one arrived meanwhile.
pub fn run<T: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> T + Send) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    let mut signal: Option<PyErr> = None;
    // The worker wakes the waiting thread when it is done, so a short job
    // does not wait out the rest of a polling slice.
    let waiter = std::thread::current();
    let value = std::thread::scope(|scope| {
        let handle = scope.spawn(|| {
            let value = work(&cancel);
            waiter.unpark();
            value
        });
        while !handle.is_finished() {
            py.detach(|| std::thread::park_timeout(POLL));
            if signal.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                signal = Some(e);
            }
        }
        handle.join()
    });
    // A signal that arrived after the last check, while the work was
    // finishing, is still the user's Ctrl-C: raise it here, not at some
    // later, unrelated line of their script.
    if signal.is_none()
        && let Err(e) = py.check_signals()
    {
        signal = Some(e);
    }
    if let Some(e) = signal {
        return Err(e);
    }
    value.map_err(|_| crate::errors::Error::new_err("a tyreroad worker thread panicked"))
}
