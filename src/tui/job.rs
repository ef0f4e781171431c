//! One background-job type for everything the workbench computes off the UI thread (run-time
//! calibration, sweeps, single scenes), after gitui's `AsyncSingleJob`: at most one job runs
//! and one waits; a newer request replaces the waiting one, and the running one's output is
//! then stale: it is asked to stop and what it returns is dropped (latest wins). The job talks
//! to the UI only through a channel that [`AsyncSingleJob::poll`] drains on each tick.
//!
//! Plain threads and `std::sync::mpsc` rather than an async runtime: jobs are few, long and
//! CPU-bound (a sweep fans out on rayon inside its job).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};

/// Hands a running job's progress to the UI thread. Shareable across the job's own worker
/// threads (a sweep reports from every rayon worker).
pub struct Reporter<P> {
    tx: Sender<Message<P>>,
}

impl<P: Send> Reporter<P> {
    pub fn report(&self, progress: P) {
        // The UI may have stopped listening (abandoned job): nothing to do then.
        let _ = self.tx.send(Message::Progress(progress));
    }
}

/// The work itself: given where to report progress and a stop request to honour when it can.
pub type Task<P, O> = Box<dyn FnOnce(&Reporter<P>, &AtomicBool) -> O + Send>;

enum Message<P> {
    Progress(P),
    // The output travels on its own channel so that `Reporter` does not depend on its type.
    Finished,
}

struct Running<P, O> {
    progress: Receiver<Message<P>>,
    output: Receiver<O>,
    cancel: Arc<AtomicBool>,
}

/// What a poll found.
#[derive(Debug, PartialEq)]
pub enum JobEvent<P, O> {
    Progress(P),
    Done(O),
    /// The job ended without output (it panicked).
    Lost,
}

pub struct AsyncSingleJob<P, O> {
    running: Option<Running<P, O>>,
    queued: Option<Task<P, O>>,
}

impl<P, O> Default for AsyncSingleJob<P, O> {
    fn default() -> Self {
        AsyncSingleJob {
            running: None,
            queued: None,
        }
    }
}

impl<P: Send + 'static, O: Send + 'static> AsyncSingleJob<P, O> {
    /// Start `task` now if nothing runs; otherwise queue it in place of any queued task and
    /// ask the running one to stop, its output now being stale.
    pub fn spawn(&mut self, task: impl FnOnce(&Reporter<P>, &AtomicBool) -> O + Send + 'static) {
        match &self.running {
            None => self.start(Box::new(task)),
            Some(running) => {
                running.cancel.store(true, Ordering::Relaxed);
                self.queued = Some(Box::new(task));
            }
        }
    }

    fn start(&mut self, task: Task<P, O>) {
        let (tx, progress) = channel();
        let (out_tx, output) = channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let flag = cancel.clone();
        std::thread::spawn(move || {
            let reporter = Reporter { tx };
            let out = task(&reporter, &flag);
            let _ = out_tx.send(out);
            let _ = reporter.tx.send(Message::Finished);
        });
        self.running = Some(Running {
            progress,
            output,
            cancel,
        });
    }

    /// A job runs or waits.
    pub fn is_busy(&self) -> bool {
        self.running.is_some() || self.queued.is_some()
    }

    /// The running job's stop flag (for a stop requested from outside the UI thread).
    pub fn cancel_flag(&self) -> Option<Arc<AtomicBool>> {
        self.running.as_ref().map(|r| r.cancel.clone())
    }

    /// Ask the running job to stop early; what it returns is still delivered.
    pub fn cancel(&self) {
        if let Some(running) = &self.running {
            running.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Forget both jobs: the queued one never starts, the running one is asked to stop and
    /// its output is dropped.
    pub fn abandon(&mut self) {
        self.cancel();
        self.running = None;
        self.queued = None;
    }

    /// Everything the running job reported since the last poll, in order. When it finishes,
    /// the queued job (if any) starts, and the finished one's output is dropped as stale.
    pub fn poll(&mut self) -> Vec<JobEvent<P, O>> {
        let mut events = Vec::new();
        let Some(running) = &self.running else {
            return events;
        };
        let stale = self.queued.is_some();
        let ended = loop {
            match running.progress.try_recv() {
                Ok(Message::Progress(p)) => {
                    if !stale {
                        events.push(JobEvent::Progress(p));
                    }
                }
                Ok(Message::Finished) | Err(TryRecvError::Disconnected) => {
                    break Some(running.output.try_recv().ok());
                }
                Err(TryRecvError::Empty) => break None,
            }
        };
        if let Some(output) = ended {
            self.running = None;
            if let Some(next) = self.queued.take() {
                self.start(next);
            } else {
                events.push(output.map_or(JobEvent::Lost, JobEvent::Done));
            }
        }
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::sync_channel;
    use std::time::{Duration, Instant};

    fn poll_until_done<P: Send + 'static, O: Send + 'static>(
        job: &mut AsyncSingleJob<P, O>,
    ) -> Vec<JobEvent<P, O>> {
        let until = Instant::now() + Duration::from_secs(10);
        let mut all = Vec::new();
        while job.is_busy() && Instant::now() < until {
            all.extend(job.poll());
            std::thread::sleep(Duration::from_millis(1));
        }
        assert!(!job.is_busy(), "the job did not finish");
        all
    }

    #[test]
    fn progress_then_output_arrive_in_order() {
        let mut job = AsyncSingleJob::default();
        job.spawn(|r: &Reporter<usize>, _: &AtomicBool| {
            (1..=3).for_each(|i| r.report(i));
            "done"
        });
        let events = poll_until_done(&mut job);
        assert_eq!(
            events,
            vec![
                JobEvent::Progress(1),
                JobEvent::Progress(2),
                JobEvent::Progress(3),
                JobEvent::Done("done")
            ]
        );
    }

    #[test]
    fn the_latest_request_wins_and_the_superseded_one_is_asked_to_stop() {
        let mut job: AsyncSingleJob<(), &str> = AsyncSingleJob::default();
        // The first job waits until it is told to stop (by the newer request).
        let (started_tx, started) = sync_channel(0);
        job.spawn(move |_, cancel| {
            started_tx.send(()).unwrap();
            while !cancel.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(1));
            }
            "first"
        });
        started.recv().unwrap();
        job.spawn(|_, _| "second");
        job.spawn(|_, _| "third");
        // Only the last request runs after the first; the first's output is stale.
        assert_eq!(poll_until_done(&mut job), vec![JobEvent::Done("third")]);
    }

    #[test]
    fn a_cancelled_job_still_delivers_and_a_panicking_one_is_reported_lost() {
        let mut job: AsyncSingleJob<(), bool> = AsyncSingleJob::default();
        let (go_tx, go) = sync_channel::<()>(0);
        job.spawn(move |_, cancel| {
            go.recv().unwrap();
            cancel.load(Ordering::Relaxed)
        });
        job.cancel();
        go_tx.send(()).unwrap();
        assert_eq!(poll_until_done(&mut job), vec![JobEvent::Done(true)]);
        job.spawn(|_, _| panic!("job panics (expected in this test)"));
        assert_eq!(poll_until_done(&mut job), vec![JobEvent::Lost]);
        // Abandoned, nothing is reported.
        job.spawn(|_, _| true);
        job.abandon();
        assert!(!job.is_busy());
        assert!(job.poll().is_empty());
    }
}
