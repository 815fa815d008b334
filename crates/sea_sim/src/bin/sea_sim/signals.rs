//! Stop signals (SIGINT, SIGTERM, SIGHUP): the first stops the run at the next tick with its
//! log finished; a second exits at once.

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The signals that stop a run cleanly.
pub(crate) const STOP_SIGNALS: [i32; 3] = [SIGINT, SIGTERM, SIGHUP];

/// Records the first stop signal: `stop` is the closed loop's cancellation flag, `signal` the
/// signal number for the exit status.
pub(crate) struct Interrupts {
    /// Raised by the first stop signal: the closed loop's cancellation flag.
    pub(crate) stop: Arc<AtomicBool>,
    signal: Arc<AtomicUsize>,
}

impl Interrupts {
    /// Installs the handlers: the first signal sets the flags, a second exits at once with
    /// 128 + signal (partial files stay; earlier targets are untouched). A signal ignored when
    /// the process started (`nohup`, a background job of a script) stays ignored.
    pub(crate) fn install() -> std::io::Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let signal = Arc::new(AtomicUsize::new(0));
        for sig in STOP_SIGNALS {
            if ignored_at_start(sig) {
                continue;
            }
            // Registered first, so it sees the flag as the previous signal left it.
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, stop.clone())?;
            signal_hook::flag::register_usize(sig, signal.clone(), sig as usize)?;
            signal_hook::flag::register(sig, stop.clone())?;
        }
        Ok(Self { stop, signal })
    }

    /// The signal that stopped the run, if any.
    pub(crate) fn received(&self) -> Option<i32> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            sig => Some(sig as i32),
        }
    }
}

/// Whether `sig` was ignored when the process started (read from the `SigIgn` mask of
/// `/proc/self/status`, which needs no unsafe code; elsewhere than Linux: never).
pub(crate) fn ignored_at_start(sig: i32) -> bool {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        return false;
    };
    status
        .lines()
        .find_map(|line| line.strip_prefix("SigIgn:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| (mask >> (sig - 1)) & 1 == 1)
}

/// The conventional name of a stop signal.
pub(crate) fn signal_name(sig: i32) -> &'static str {
    match sig {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}
