//! The explorer's one kind of background worker, used for the keystroke's solve and for the
//! sweeps behind the charts: a thread that runs the newest job of each of its lanes (the
//! solve has one lane, the sweeps one per sweep). A job asked for replaces the one waiting in
//! its lane unseen, and cancels the one running there inside its loops (through the
//! [`Cancellation`] it runs with), so ten quick key presses make one solve of the final
//! value. In a served session the worker waits for its turn on the shared cores
//! ([`super::cores`]) before it takes a job — an express turn when its next job is quick
//! ([`Job::is_quick`]). A panic in a job is caught and reported as the
//! job's result. Dropping the worker never waits: a job in progress is cancelled (every method
//! stops within tens of milliseconds, `benches/cancel.rs`) and, should a step still run,
//! the thread runs on detached until it ends, then gives back its memory.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

use crate::solve::Cancellation;
use crate::tui::jobs::solve::{SolveRequest, Solved, solve};
use crate::tui::jobs::sweeps::{SweepRequest, SweepResult, compute};

use super::cores::Share;

/// Work a [`Worker`] runs: a pure function of the job, stopped early by its cancellation.
pub trait Job: Clone + PartialEq + Send + 'static {
    type Output: Send + 'static;
    /// Runs the job; `None` when `cancel` stopped it (such a result answers nothing).
    fn compute(&self, cancel: &Cancellation) -> Option<Self::Output>;
    /// What to deliver when the job panicked with `message`.
    fn failed(&self, message: String) -> Self::Output;
    /// Whether the job takes milliseconds, so that it may run beside heavy ones on an
    /// express permit of the shared cores.
    fn is_quick(&self) -> bool {
        false
    }
}

/// The keystroke's solve: delivered as the solve, or as the message of a panic.
impl Job for SolveRequest {
    type Output = Result<Solved, String>;

    fn compute(&self, cancel: &Cancellation) -> Option<Self::Output> {
        let mut request = self.clone();
        request.options.cancel = cancel.clone();
        let solved = solve(&request);
        // A newer request also cuts the reference's solve short: drop the result.
        (!solved.was_cancelled()).then_some(Ok(solved))
    }

    fn is_quick(&self) -> bool {
        self.takes_milliseconds()
    }

    fn failed(&self, message: String) -> Self::Output {
        Err(format!("internal error in the solver ({message})"))
    }
}

/// A chart's sweep: delivered with its data, or with the panic's message for its panel.
impl Job for SweepRequest {
    type Output = SweepResult;

    fn compute(&self, cancel: &Cancellation) -> Option<Self::Output> {
        compute(self, cancel).ok()
    }

    fn failed(&self, message: String) -> Self::Output {
        SweepResult {
            sweep: self.sweep,
            inputs: self.inputs.clone(),
            data: Err(format!(
                "internal error in this sweep ({message}); the explorer goes on"
            )),
        }
    }
}

/// What the worker and its thread share.
struct Shared<J> {
    queue: Mutex<Queue<J>>,
    ready: Condvar,
    /// The newest generation asked for in each lane: a job of an older one is cancelled.
    newest: Vec<Arc<AtomicU64>>,
}

/// The jobs waiting, one per lane at most.
struct Queue<J> {
    /// Per lane: the job waiting there and its generation.
    waiting: Vec<Option<(u64, J)>>,
    /// The worker is gone: the thread ends.
    closed: bool,
}

impl<J> Shared<J> {
    fn lock(&self) -> MutexGuard<'_, Queue<J>> {
        self.queue.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A background worker: [`Worker::want`] a job in a lane, receive its output through the
/// callback given at the start.
pub struct Worker<J: Job> {
    shared: Arc<Shared<J>>,
    /// The last job asked for in each lane, so the same one is not run twice.
    sent: Vec<Option<J>>,
    /// Generations handed out so far.
    generation: u64,
    thread: Option<JoinHandle<()>>,
}

/// How a worker runs besides its jobs.
#[derive(Default)]
pub struct WorkerOptions {
    /// The session's turn on cores shared with other explorers (served sessions).
    pub share: Option<Share>,
    /// The first job panics (a test of how a failing job is reported).
    pub inject_panic: bool,
}

impl<J: Job> Worker<J> {
    /// Starts a worker thread called `name` with `lanes` lanes; `deliver` gets every output
    /// (on the worker thread).
    pub fn start(
        name: &str,
        lanes: usize,
        options: WorkerOptions,
        deliver: impl Fn(J::Output) + Send + 'static,
    ) -> Worker<J> {
        let shared = Arc::new(Shared {
            queue: Mutex::new(Queue {
                waiting: (0..lanes).map(|_| None).collect(),
                closed: false,
            }),
            ready: Condvar::new(),
            newest: (0..lanes).map(|_| Arc::new(AtomicU64::new(0))).collect(),
        });
        let working = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || work(&working, options, deliver))
            .expect("a thread can be started");
        Worker {
            shared,
            sent: vec![None; lanes],
            generation: 0,
            thread: Some(thread),
        }
    }

    /// Wants `job` in `lane` (`None`: nothing there). Unless it is the job last wanted there,
    /// it replaces the one waiting and cancels the one running in that lane.
    pub fn want(&mut self, lane: usize, job: Option<&J>) {
        if self.sent[lane].as_ref() == job {
            return;
        }
        self.sent[lane] = job.cloned();
        self.generation += 1;
        // Whatever runs in this lane now is outdated: it stops inside its loops.
        self.shared.newest[lane].store(self.generation, Ordering::Relaxed);
        self.shared.lock().waiting[lane] = job.map(|job| (self.generation, job.clone()));
        self.shared.ready.notify_one();
    }

    /// Stops the worker (a job in progress is cancelled inside its loops) and returns its
    /// thread, to see when it has ended (a served session that ends).
    pub fn stop(mut self) -> Option<JoinHandle<()>> {
        let thread = self.thread.take();
        drop(self);
        thread
    }
}

impl<J: Job> Drop for Worker<J> {
    fn drop(&mut self) {
        // Never waits for a job in progress: quitting is immediate.
        for newest in &self.shared.newest {
            newest.store(u64::MAX, Ordering::Relaxed);
        }
        let mut queue = self.shared.lock();
        queue.closed = true;
        queue.waiting.iter_mut().for_each(|w| *w = None);
        drop(queue);
        self.shared.ready.notify_one();
    }
}

/// The worker thread: waits for a job, for its turn on the cores, then runs the oldest job
/// waiting, until the worker is dropped.
fn work<J: Job>(shared: &Shared<J>, options: WorkerOptions, deliver: impl Fn(J::Output)) {
    let mut inject = options.inject_panic;
    let closed = || shared.lock().closed;
    loop {
        {
            let mut queue = shared.lock();
            while queue.waiting.iter().all(Option::is_none) && !queue.closed {
                queue = shared.ready.wait(queue).unwrap_or_else(|e| e.into_inner());
            }
            if queue.closed {
                return;
            }
        }
        // Our turn on the shared cores (served sessions), then the oldest job waiting:
        // whatever was asked for meanwhile replaced the older one of its lane unseen.
        let quick = peek_oldest(&shared.lock()).is_some_and(J::is_quick);
        let permit = match &options.share {
            Some(share) => match share.acquire(quick, &closed) {
                Some(permit) => Some(permit),
                None => return,
            },
            None => None,
        };
        let mut queue = shared.lock();
        // An express permit is for a quick job only: one asked for while waiting goes back.
        let express = permit.as_ref().is_some_and(|p| p.is_express());
        if express && !peek_oldest(&queue).is_some_and(J::is_quick) {
            continue;
        }
        let Some((lane, generation, job)) = oldest(&mut queue) else {
            continue;
        };
        drop(queue);
        let cancel = Cancellation::watching(Arc::clone(&shared.newest[lane]), generation);
        if cancel.is_cancelled() {
            continue;
        }
        // A panic in a job must not take the explorer down: report it instead.
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            if std::mem::take(&mut inject) {
                panic!("injected panic in a job");
            }
            job.compute(&cancel)
        }));
        match outcome {
            Ok(Some(output)) => deliver(output),
            Ok(None) => {}
            Err(payload) => deliver(job.failed(panic_message(payload.as_ref()))),
        }
    }
}

/// The lane of the job that has waited longest (the smallest generation).
fn oldest_lane<J>(queue: &Queue<J>) -> Option<usize> {
    Some(
        queue
            .waiting
            .iter()
            .enumerate()
            .filter_map(|(lane, waiting)| {
                waiting.as_ref().map(|(generation, _)| (*generation, lane))
            })
            .min()?
            .1,
    )
}

/// The job that has waited longest, left in the queue.
fn peek_oldest<J>(queue: &Queue<J>) -> Option<&J> {
    let lane = oldest_lane(queue)?;
    queue.waiting[lane].as_ref().map(|(_, job)| job)
}

/// Takes the job that has waited longest out of the queue.
fn oldest<J>(queue: &mut Queue<J>) -> Option<(usize, u64, J)> {
    let lane = oldest_lane(queue)?;
    let (generation, job) = queue.waiting[lane].take()?;
    Some((lane, generation, job))
}

/// The text of a panic's payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;
    use std::time::Duration;

    /// A job that counts down until cancelled (or done) and says how far it got.
    #[derive(Debug, Clone, PartialEq)]
    struct Countdown {
        lane: usize,
        steps: u64,
    }

    impl Job for Countdown {
        type Output = (usize, u64);

        fn compute(&self, cancel: &Cancellation) -> Option<Self::Output> {
            for _ in 0..self.steps {
                if cancel.is_cancelled() {
                    return None;
                }
                std::thread::sleep(Duration::from_millis(1));
            }
            Some((self.lane, self.steps))
        }

        fn failed(&self, _message: String) -> Self::Output {
            (self.lane, 0)
        }
    }

    /// Waits for the next output, with a generous deadline.
    fn next<T>(outputs: &std::sync::mpsc::Receiver<T>) -> T {
        outputs
            .recv_timeout(Duration::from_secs(60))
            .expect("an output within a minute")
    }

    #[test]
    fn the_newest_job_of_a_lane_wins_and_other_lanes_go_on() {
        let (sender, outputs) = channel();
        let mut worker = Worker::start("test", 2, WorkerOptions::default(), move |output| {
            let _ = sender.send(output);
        });
        // A long job, replaced by a short one before it can end: only the short one answers.
        worker.want(
            0,
            Some(&Countdown {
                lane: 0,
                steps: 1_000_000,
            }),
        );
        worker.want(1, Some(&Countdown { lane: 1, steps: 3 }));
        worker.want(0, Some(&Countdown { lane: 0, steps: 2 }));
        let mut got = vec![next(&outputs), next(&outputs)];
        got.sort();
        assert_eq!(got, vec![(0, 2), (1, 3)]);
        // The same job again is not run twice; a lane emptied cancels its job.
        worker.want(1, Some(&Countdown { lane: 1, steps: 3 }));
        worker.want(
            0,
            Some(&Countdown {
                lane: 0,
                steps: 1_000_000,
            }),
        );
        worker.want(0, None);
        worker.want(1, Some(&Countdown { lane: 1, steps: 4 }));
        assert_eq!(next(&outputs), (1, 4));
        let thread = worker.stop().expect("a thread");
        let deadline = std::time::Instant::now() + Duration::from_secs(60);
        while !thread.is_finished() {
            assert!(
                std::time::Instant::now() < deadline,
                "the worker never ended"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        assert!(outputs.try_recv().is_err(), "a cancelled job answered");
    }

    #[test]
    fn a_panicking_job_is_reported_and_the_worker_goes_on() {
        let (sender, outputs) = channel();
        let options = WorkerOptions {
            share: None,
            inject_panic: true,
        };
        let mut worker = Worker::start("test", 1, options, move |output| {
            let _ = sender.send(output);
        });
        worker.want(0, Some(&Countdown { lane: 0, steps: 1 }));
        assert_eq!(next(&outputs), (0, 0));
        worker.want(0, Some(&Countdown { lane: 0, steps: 2 }));
        assert_eq!(next(&outputs), (0, 2));
    }
}
