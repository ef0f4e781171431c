//! Ending the workbench on a signal when its event loop may never run again. crossterm 0.29
//! spins for ever inside `event::poll` once its terminal is gone (its tty read loop retries on
//! EOF and EIO), so after a lost SSH session the loop cannot take up the SIGHUP, and the sweep
//! it would stop went on computing until the process was ended from outside the loop (2 s
//! later, 3–4 s under load). Here a watcher thread stops the sweep itself the moment a signal
//! arrives (running scenes are abandoned at once, as `rocklab run` abandons them), lets it
//! write its results files (finished scenes are in its journal already), and ends the process
//! if the event loop has not taken the signal up by then.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The sweep the workbench runs: its stop flag, and whether it has returned (results written).
struct Sweep {
    cancel: Arc<AtomicBool>,
    returned: Arc<AtomicBool>,
}

/// At most one sweep runs per workbench (process).
static SWEEP: Mutex<Option<Sweep>> = Mutex::new(None);

/// Register the sweep now running: `cancel` stops it, `returned` is set once it has returned.
pub fn sweep_started(cancel: Arc<AtomicBool>, returned: Arc<AtomicBool>) {
    if let Ok(mut sweep) = SWEEP.lock() {
        *sweep = Some(Sweep { cancel, returned });
    }
}

/// Stop the registered sweep; true once it has returned (or if there is none).
fn stop_sweep() -> bool {
    let Ok(sweep) = SWEEP.lock() else {
        return true;
    };
    match sweep.as_ref() {
        Some(s) => {
            s.cancel.store(true, Ordering::Relaxed);
            s.returned.load(Ordering::Relaxed)
        }
        None => true,
    }
}

/// How long the event loop has to take up a signal before the process ends without it (it
/// polls every tick, 100 ms).
const GRACE: Duration = Duration::from_millis(500);

/// Longest wait for a stopped sweep to write its results files before the process ends
/// anyway (its finished scenes are in the journal: the next run resumes from them).
const WRITE_LIMIT: Duration = Duration::from_secs(10);

/// Watch `interrupted` (set by the signal handlers). When it is set: stop the sweep at once,
/// then end the process with status 129 unless `shutting_down` (the event loop took the signal
/// up) is set within [`GRACE`]; never before the stopped sweep has returned (at most
/// [`WRITE_LIMIT`]).
pub fn watch(interrupted: Arc<AtomicBool>, shutting_down: Arc<AtomicBool>) {
    std::thread::spawn(move || {
        while !interrupted.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let since = Instant::now();
        loop {
            let returned = stop_sweep();
            if shutting_down.load(Ordering::Relaxed) {
                return;
            }
            let waited = since.elapsed();
            if (returned && waited >= GRACE) || waited >= WRITE_LIMIT {
                std::process::exit(129);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    });
}
