//! Ctrl-C during native work: the work runs on a worker thread with the GIL released while
//! the calling thread wakes every [`SIGNAL_POLL`] to run Python's signal handlers. When one
//! raises (SIGINT: `KeyboardInterrupt`), a cancellation flag is raised; the native loop polls
//! it, stops at its next sample and finishes its outputs (an MCAP log gets its summary
//! section), and the caller gets both what was computed and the exception, so it can attach
//! the partial result to the exception before raising it.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How often the waiting thread runs Python's signal handlers: Ctrl-C is acted on within
/// this (plus one sample of the native loop).
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Stack of the worker thread: the main thread's usual size, so work that runs on the
/// calling thread elsewhere runs here too.
const WORKER_STACK_BYTES: usize = 8 << 20;

/// Runs `work(cancel)` on a worker thread with the GIL released and returns its result with
/// the exception a signal handler raised meanwhile (`None` when none did). `cancel` is set
/// when a handler raises; `work` should poll it and return early. A thread that cannot be
/// started is an `OSError`; a panic in `work` is resumed on the calling thread (PyO3 turns it
/// into a `PanicException`).
pub fn run_interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<(T, Option<PyErr>)> {
    let cancel = AtomicBool::new(false);
    py.detach(|| {
        let caller = std::thread::current();
        std::thread::scope(|scope| {
            let worker = std::thread::Builder::new()
                .name("sea-native-work".into())
                .stack_size(WORKER_STACK_BYTES)
                .spawn_scoped(scope, || {
                    let value = work(&cancel);
                    // Wake the caller at once rather than at its next poll.
                    caller.unpark();
                    value
                })
                .map_err(PyErr::from)?;
            let mut raised = None;
            while !worker.is_finished() {
                std::thread::park_timeout(SIGNAL_POLL);
                if raised.is_none() && !worker.is_finished() {
                    if let Err(error) = Python::attach(|py| py.check_signals()) {
                        cancel.store(true, Ordering::Relaxed);
                        raised = Some(error);
                    }
                }
            }
            match worker.join() {
                Ok(value) => Ok((value, raised)),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        })
    })
}
