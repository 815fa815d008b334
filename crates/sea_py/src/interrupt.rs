//! Ctrl-C during native work: the work runs on a worker thread with the GIL released while
//! the calling thread wakes every [`SIGNAL_POLL`] to run Python's signal handlers. When one
//! raises (SIGINT: `KeyboardInterrupt`), a cancellation flag is raised; the native loop polls
//! it, stops at its next sample and finishes its outputs (an MCAP log gets its summary
//! section), and the caller gets both what was computed and the exception, so it can attach
//! the partial result to the exception before raising it.
//!
//! SIGTERM (a batch scheduler's stop, `kill`): Python leaves it at the system's default, which
//! ends the process at once and would leave an MCAP log without its summary. While the work
//! runs, a SIGTERM left at that default is handled as Ctrl-C is, its handler raising
//! `SystemExit(143)` (the status the default would give); the previous disposition is put
//! back afterwards. Only on the main thread (Python's signal handlers live there), and never
//! over a handler the program installed itself.

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
    // Put back when dropped, also when the work panics.
    let _terminate = TerminateAsExit::install(py)?;
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

/// SIGTERM handled as `SystemExit(143)` while native work runs (module doc): holds the
/// disposition to put back, `None` when nothing was changed.
struct TerminateAsExit(Option<Py<PyAny>>);

impl TerminateAsExit {
    /// Installs the handler when SIGTERM is at the system's default and this is the main
    /// thread; otherwise changes nothing.
    fn install(py: Python<'_>) -> PyResult<Self> {
        let signal = py.import("signal")?;
        let threading = py.import("threading")?;
        let main = threading.call_method0("main_thread")?;
        if !main.is(&threading.call_method0("current_thread")?) {
            return Ok(Self(None));
        }
        let sigterm = signal.getattr("SIGTERM")?;
        let previous = signal.call_method1("getsignal", (&sigterm,))?;
        if !previous.eq(signal.getattr("SIG_DFL")?)? {
            return Ok(Self(None));
        }
        let handler = pyo3::types::PyCFunction::new_closure(
            py,
            None,
            None,
            |_args, _kwargs| -> PyResult<()> {
                Err(pyo3::exceptions::PySystemExit::new_err(128 + 15))
            },
        )?;
        signal.call_method1("signal", (&sigterm, handler))?;
        Ok(Self(Some(previous.unbind())))
    }
}

impl Drop for TerminateAsExit {
    /// Puts the previous disposition back (a failure to, which Python's `signal.signal` has
    /// no reason for on the thread that installed the handler, is left unreported).
    fn drop(&mut self) {
        if let Some(previous) = self.0.take() {
            Python::attach(|py| {
                let _ = py.import("signal").and_then(|signal| {
                    signal.call_method1("signal", (signal.getattr("SIGTERM")?, previous))
                });
            });
        }
    }
}
