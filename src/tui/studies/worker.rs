//! The background thread that computes studies for the interactive explorer. Each request
//! cancels the outdated work of its study; a panic in a study becomes a message in its panel.
//! In a served session each study waits for its turn on the shared cores (`tui::cores`).

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Sender, channel};
use std::thread::JoinHandle;

use super::{STUDIES, StudyRequest, StudyResult, run};
use crate::solve::Cancellation;
use crate::study::Cancelled;
use crate::tui::cores::Share;

/// A background worker for the studies.
pub struct Worker {
    jobs: Option<Sender<(u64, StudyRequest)>>,
    /// The newest request per study; older ones are cancelled, inside the solve of the point in
    /// progress too. Leaked (eight bytes per study and worker) so that a `Cancellation` can
    /// hold it by `'static` reference.
    newest: Vec<Arc<AtomicU64>>,
    counter: u64,
    /// Requests already sent, so the same one is not sent twice.
    sent: Vec<StudyRequest>,
    thread: Option<JoinHandle<()>>,
}

/// The result of a study that panicked: its panel shows the message.
fn failed(request: &StudyRequest, payload: &Box<dyn std::any::Any + Send>) -> StudyResult {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    StudyResult {
        study: request.study,
        inputs: request.inputs.clone(),
        data: Err(format!(
            "internal error in this study ({message}); the explorer goes on"
        )),
    }
}

impl Worker {
    /// Starts the worker thread; `deliver` gets every finished study (on the worker thread).
    /// With `inject_panic`, its first study panics (a test of how a failing study is
    /// reported).
    pub fn start(inject_panic: bool, deliver: impl Fn(StudyResult) + Send + 'static) -> Worker {
        Worker::start_sharing(inject_panic, None, deliver)
    }

    /// As [`Worker::start`]; with a `share`, each study waits for its turn on the shared cores
    /// first (and is skipped if it became outdated meanwhile).
    pub fn start_sharing(
        inject_panic: bool,
        share: Option<Share>,
        deliver: impl Fn(StudyResult) + Send + 'static,
    ) -> Worker {
        let (jobs, inbox) = channel::<(u64, StudyRequest)>();
        let newest: Vec<Arc<AtomicU64>> = STUDIES
            .iter()
            .map(|_| Arc::new(AtomicU64::new(0)))
            .collect();
        let shared = newest.clone();
        let body = move || {
            let mut inject = inject_panic;
            for (id, request) in inbox {
                let study = request.study;
                let cancel = Cancellation::watching(Arc::clone(&shared[study]), id);
                if cancel.is_cancelled() {
                    continue;
                }
                // Our turn on the shared cores; the worker's end (every study cancelled for
                // good) gives up waiting.
                let closed = || shared.iter().all(|n| n.load(Ordering::Relaxed) == u64::MAX);
                let _permit = match &share {
                    Some(share) => match share.acquire(&closed) {
                        Some(permit) => Some(permit),
                        None => return,
                    },
                    None => None,
                };
                if cancel.is_cancelled() {
                    continue;
                }
                // A panic in a study must not take the explorer down: report it instead.
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    if std::mem::take(&mut inject) {
                        panic!("injected panic in a study");
                    }
                    run(&request, cancel)
                }));
                let result = match outcome {
                    Ok(Ok(result)) => result,
                    Ok(Err(Cancelled)) => continue,
                    Err(payload) => failed(&request, &payload),
                };
                deliver(result);
            }
        };
        let thread = std::thread::Builder::new()
            .name("studies".into())
            .spawn(body)
            .expect("a thread can be started");
        Worker {
            jobs: Some(jobs),
            newest,
            counter: 0,
            sent: Vec::new(),
            thread: Some(thread),
        }
    }

    /// Stops the worker (a study in progress is cancelled inside its loops) and returns its
    /// thread, to see when it has ended (a served session that ends).
    pub fn stop(mut self) -> Option<JoinHandle<()>> {
        let thread = self.thread.take();
        drop(self);
        thread
    }

    /// Sends the requests not sent yet; each cancels the outdated work of its study, and a
    /// study with no request (its panel hidden, or its data in) has its work cancelled.
    pub fn request(&mut self, requests: Vec<StudyRequest>) {
        for study in 0..STUDIES.len() {
            let wanted = requests.iter().any(|r| r.study == study);
            if !wanted && self.sent.iter().any(|r| r.study == study) {
                self.cancel(study);
            }
        }
        for request in requests {
            if self.sent.contains(&request) {
                continue;
            }
            self.counter += 1;
            self.newest[request.study].store(self.counter, Ordering::Relaxed);
            self.sent.retain(|r| r.study != request.study);
            self.sent.push(request.clone());
            if let Some(jobs) = &self.jobs {
                let _ = jobs.send((self.counter, request));
            }
        }
    }

    /// Cancels the work on `study` (its panel was hidden).
    pub fn cancel(&mut self, study: usize) {
        self.counter += 1;
        self.newest[study].store(self.counter, Ordering::Relaxed);
        self.sent.retain(|r| r.study != study);
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // Cancel whatever runs and close the queue; never wait: quitting is immediate.
        for slot in self.newest.iter() {
            slot.store(u64::MAX, Ordering::Relaxed);
        }
        self.jobs = None;
    }
}
