//! Running the studies behind the chart panels: on a worker thread for the interactive
//! explorer (a keystroke never waits for them), or to completion on the spot for headless
//! rendering. A result carries the inputs it was computed for; the app keeps it only if they
//! are still current, and a newer request cancels the work on an outdated one.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use super::app::{EpsInputs, MeshInputs, StudyRequest, StudyResult};
use crate::solve::Method;
use crate::study::{self, Cancel, Cancelled};

/// Points of the ε sweep drawn in the panels: ε = 1e-16 … 1, two per decade.
pub const EPS_POINTS: usize = 33;

/// The largest mesh in the error-vs-run-time panel.
pub const MESH_MAX: usize = 100_000;
/// The largest mesh for `dual-inverse` there: its O(N³) cost shows well before.
pub const DENSE_MAX: usize = 400;

fn run_epsilon(inputs: &EpsInputs, cancel: Cancel) -> Result<StudyResult, Cancelled> {
    let epsilons = study::log_space(1e-16, 1.0, EPS_POINTS);
    let result = study::epsilon_sweep(
        &inputs.problem,
        inputs.elements,
        Method::Regularized,
        &epsilons,
        cancel,
        &study::silent,
    )?;
    Ok(StudyResult::Epsilon(
        inputs.clone(),
        result.map_err(|e| format!("the ε sweep needs the regularised method: {e}")),
    ))
}

fn run_mesh(inputs: &MeshInputs, cancel: Cancel) -> Result<StudyResult, Cancelled> {
    let mut sizes = study::mesh_sizes(10, MESH_MAX, 9);
    sizes.push(inputs.elements);
    sizes.sort();
    sizes.dedup();
    let (dense, others): (Vec<Method>, Vec<Method>) = Method::ALL
        .into_iter()
        .partition(|m| *m == Method::DualInverse);
    let small: Vec<usize> = sizes.iter().copied().filter(|&n| n <= DENSE_MAX).collect();
    let (problem, repeat, epsilon) = (&inputs.problem, inputs.repeat, inputs.epsilon);
    let silent = &study::silent;
    let mut points = study::mesh_sweep(problem, &others, &sizes, repeat, epsilon, cancel, silent)?;
    points.extend(study::mesh_sweep(
        problem, &dense, &small, repeat, epsilon, cancel, silent,
    )?);
    Ok(StudyResult::Mesh(inputs.clone(), Ok(points)))
}

/// Runs one request to completion.
pub fn run_now(request: &StudyRequest) -> StudyResult {
    let never: Cancel = &|| false;
    let result = match request {
        StudyRequest::Epsilon(inputs) => run_epsilon(inputs, never),
        StudyRequest::Mesh(inputs) => run_mesh(inputs, never),
    };
    result.expect("a study that is never cancelled finishes")
}

/// A background worker for the studies.
pub struct Worker {
    jobs: Option<Sender<(u64, StudyRequest)>>,
    results: Receiver<StudyResult>,
    /// The newest request per kind (epsilon, mesh); older ones are cancelled.
    newest: Arc<[AtomicU64; 2]>,
    counter: u64,
    thread: Option<JoinHandle<()>>,
    /// Requests already sent, so the same one is not sent twice.
    sent: Vec<StudyRequest>,
}

/// The result of a study that panicked: its panel shows the message.
fn failed(request: &StudyRequest, payload: &Box<dyn std::any::Any + Send>) -> StudyResult {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    let text = format!("internal error in this study ({message}); the explorer goes on");
    match request {
        StudyRequest::Epsilon(inputs) => StudyResult::Epsilon(inputs.clone(), Err(text)),
        StudyRequest::Mesh(inputs) => StudyResult::Mesh(inputs.clone(), Err(text)),
    }
}

fn kind(request: &StudyRequest) -> usize {
    match request {
        StudyRequest::Epsilon(_) => 0,
        StudyRequest::Mesh(_) => 1,
    }
}

impl Worker {
    /// Starts the worker thread. With `inject_panic`, its first study panics (a test of how a
    /// failing study is reported).
    pub fn start(inject_panic: bool) -> Worker {
        let (jobs, inbox) = channel::<(u64, StudyRequest)>();
        let (outbox, results) = channel();
        let newest: Arc<[AtomicU64; 2]> = Arc::new([AtomicU64::new(0), AtomicU64::new(0)]);
        let shared = Arc::clone(&newest);
        let body = move || {
            let mut inject = inject_panic;
            for (id, request) in inbox {
                let k = kind(&request);
                let cancel = || shared[k].load(Ordering::Relaxed) != id;
                if cancel() {
                    continue;
                }
                // A panic in a study must not take the explorer down: report it instead.
                let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    if std::mem::take(&mut inject) {
                        panic!("injected panic in a study");
                    }
                    match &request {
                        StudyRequest::Epsilon(inputs) => run_epsilon(inputs, &cancel),
                        StudyRequest::Mesh(inputs) => run_mesh(inputs, &cancel),
                    }
                }));
                let result = match run {
                    Ok(Ok(result)) => result,
                    Ok(Err(Cancelled)) => continue,
                    Err(payload) => failed(&request, &payload),
                };
                if outbox.send(result).is_err() {
                    return;
                }
            }
        };
        let thread = std::thread::Builder::new()
            .name("studies".into())
            .spawn(body)
            .expect("a thread can be started");
        Worker {
            jobs: Some(jobs),
            results,
            newest,
            counter: 0,
            thread: Some(thread),
            sent: Vec::new(),
        }
    }

    /// Sends the requests not sent yet; each cancels the outdated work of its kind.
    pub fn request(&mut self, requests: Vec<StudyRequest>) {
        for request in requests {
            if self.sent.contains(&request) {
                continue;
            }
            self.counter += 1;
            self.newest[kind(&request)].store(self.counter, Ordering::Relaxed);
            self.sent.retain(|r| kind(r) != kind(&request));
            self.sent.push(request.clone());
            if let Some(jobs) = &self.jobs {
                let _ = jobs.send((self.counter, request));
            }
        }
    }

    /// The results that have arrived.
    pub fn poll(&mut self) -> Vec<StudyResult> {
        self.results.try_iter().collect()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // Cancel whatever runs, close the queue, and wait for the thread to see it.
        for slot in self.newest.iter() {
            slot.store(u64::MAX, Ordering::Relaxed);
        }
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
