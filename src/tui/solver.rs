//! The keystroke's own solve, off the UI thread: one worker thread that always takes the
//! newest request (older ones are dropped unseen, so ten quick key presses make one solve of
//! the final value), and hands back the mesh and solution tagged with what they were computed
//! for, with the reference solution (`condensed` on the same mesh, solved once for both the
//! certificate and the chart) the deflection panel draws under it. The app keeps a result only
//! if it is still the one wanted. In a served session the worker waits for its turn on the
//! shared cores ([`super::cores`]) before each solve.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

use crate::fem::Mesh;
use crate::solve::{Cancellation, SolveErrorKind, solve_with_condensed};

use super::app::{Shown, SolveRequest};
use super::cores::Share;

/// Computes a request on the spot (headless rendering, tests, and the worker itself).
pub fn run_solve(request: &SolveRequest) -> Shown {
    let mesh = Mesh::new(&request.problem, request.elements);
    // With the reference curve of the deflection panel: the stable method on the same mesh,
    // the same solve the certificate graded with (none when the method is condensed).
    let (solution, reference) =
        solve_with_condensed(&request.problem, &mesh, request.method, &request.options);
    let max_deflection = solution.as_ref().map_or(f64::NAN, |s| s.max_deflection());
    Shown {
        request: request.clone(),
        mesh,
        solution,
        max_deflection,
        reference,
    }
}

/// The newest request (with its generation), and whether the worker should stop.
#[derive(Default)]
struct Slot {
    request: Option<(u64, SolveRequest)>,
    closed: bool,
}

/// A background solver: `want` a request, receive its result through the callback.
pub struct SolveWorker {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    /// The newest generation: a solve of an older one stops inside its loops. Leaked (eight
    /// bytes per worker) so that a `Cancellation` can hold it by `'static` reference.
    newest: Arc<AtomicU64>,
    /// The last request handed over, so the same one is not solved twice.
    last: Option<SolveRequest>,
    thread: Option<JoinHandle<()>>,
}

impl SolveWorker {
    /// Starts the worker; `deliver` gets every finished result (on the worker thread).
    pub fn start(deliver: impl Fn(Result<Shown, String>) + Send + 'static) -> SolveWorker {
        SolveWorker::start_sharing(None, deliver)
    }

    /// As [`SolveWorker::start`]; with a `share`, each solve waits for its turn on the shared
    /// cores first, and then takes the newest request.
    pub fn start_sharing(
        share: Option<Share>,
        deliver: impl Fn(Result<Shown, String>) + Send + 'static,
    ) -> SolveWorker {
        let slot: Arc<(Mutex<Slot>, Condvar)> = Arc::default();
        let shared = Arc::clone(&slot);
        let newest = Arc::new(AtomicU64::new(0));
        let watched = Arc::clone(&newest);
        let thread = std::thread::Builder::new()
            .name("solver".into())
            .spawn(move || {
                let (lock, ready) = &*shared;
                let closed = || lock.lock().unwrap_or_else(|e| e.into_inner()).closed;
                loop {
                    {
                        let mut slot = lock.lock().unwrap_or_else(|e| e.into_inner());
                        while slot.request.is_none() && !slot.closed {
                            slot = ready.wait(slot).unwrap_or_else(|e| e.into_inner());
                        }
                        if slot.closed {
                            return;
                        }
                    }
                    // Our turn on the shared cores (served sessions), then the newest request:
                    // whatever was asked for while waiting replaced the older one unseen.
                    let _permit = match &share {
                        Some(share) => match share.acquire(&closed) {
                            Some(permit) => Some(permit),
                            None => return,
                        },
                        None => None,
                    };
                    let request = lock
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .request
                        .take();
                    let Some((generation, mut request)) = request else {
                        continue;
                    };
                    request.options.cancel = Cancellation::watching(Arc::clone(&watched), generation);
                    // A panic in a method must not take the explorer down.
                    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        run_solve(&request)
                    }))
                    .map_err(|payload| {
                        let message = payload
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| payload.downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "unknown".into());
                        format!("internal error in the solver ({message})")
                    });
                    // A newer request also cuts the reference's solve short: drop the result.
                    let cancelled = request.options.cancel.is_cancelled()
                        || matches!(
                            &outcome,
                            Ok(Shown { solution: Err(e), .. }) if e.kind == SolveErrorKind::Cancelled
                        );
                    if !cancelled {
                        deliver(outcome);
                    }
                }
            })
            .expect("a thread can be started");
        SolveWorker {
            slot,
            newest,
            last: None,
            thread: Some(thread),
        }
    }

    /// Stops the worker (a solve in progress is cancelled inside its loops) and returns its
    /// thread, to see when it has ended (a served session that ends).
    pub fn stop(mut self) -> Option<JoinHandle<()>> {
        let thread = self.thread.take();
        drop(self);
        thread
    }

    /// Asks for `request` unless it was the last one asked for; replaces a request the worker
    /// has not started yet.
    pub fn want(&mut self, request: &SolveRequest) {
        if self.last.as_ref() == Some(request) {
            return;
        }
        self.last = Some(request.clone());
        // Whatever runs now is outdated: it stops inside its loops.
        let generation = self.newest.fetch_add(1, Ordering::Relaxed) + 1;
        let (lock, ready) = &*self.slot;
        lock.lock().unwrap_or_else(|e| e.into_inner()).request =
            Some((generation, request.clone()));
        ready.notify_one();
    }
}

impl Drop for SolveWorker {
    fn drop(&mut self) {
        // Never waits for a solve in progress: quitting is immediate.
        self.newest.fetch_add(1, Ordering::Relaxed);
        let (lock, ready) = &*self.slot;
        lock.lock().unwrap_or_else(|e| e.into_inner()).closed = true;
        ready.notify_one();
    }
}
