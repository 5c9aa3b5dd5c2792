//! The interactive explorer's event loop, the same for the local terminal and for a remote one
//! (an SSH channel, see `crate::serve`): it draws on a [`Screen`] and hears everything through
//! one channel of [`Event`]s. The UI thread only reads events, updates the state and draws;
//! everything slow runs on workers:
//!
//! - the terminal's bytes arrive as [`Event::Bytes`] — locally from an input thread (end of
//!   file or a read error is a hangup that ends the explorer: no busy loop on a closed
//!   terminal), remotely from the SSH connection, with window changes as [`Event::Resize`];
//! - locally, a signal thread turns SIGINT, SIGTERM, SIGHUP, SIGWINCH, SIGTSTP and SIGCONT
//!   into events;
//! - the solver worker computes the keystroke's re-solve, the study worker the charts' data.
//!
//! All of them feed one channel, and the loop blocks on it: it draws only when something
//! changed (a key, a result, a resize, or a timer tick a few times a second while work is in
//! flight), so an idle explorer uses no CPU. Every queued event is applied before the next
//! frame and the next request to a worker, so a burst of keys makes one solve of the final
//! state. Quitting never waits for a worker.

use std::io::{self, Read, Write};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::time::{Duration, Instant};

use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

use super::app::{App, Shown};
use super::input::{Decoder, ESC_TIMEOUT, Input};
use super::keymap::{Action, action_for, paste_actions};
use super::mouse::{ClickTracker, MOUSE_OFF, MOUSE_ON};
use super::solver::SolveWorker;
use super::studies::{StudyResult, Worker};
use super::terminal::{SIGNALS, Session};
use super::{Ending, INJECT_PANIC, update, view};

/// How often the frame is redrawn while work is in flight (for the elapsed time).
const TICK: Duration = Duration::from_millis(250);
/// Longest a served session waits for its cancelled workers to end before it lets them go.
const WORKER_GRACE: Duration = Duration::from_millis(500);
/// Most events applied before a frame is drawn (a paste of any size still shows progress).
const EVENTS_PER_FRAME: usize = 4096;

/// What wakes the loop.
pub enum Event {
    /// Bytes from the terminal.
    Bytes(Vec<u8>),
    /// The terminal has a new size (columns, rows): a remote terminal's window change.
    Resize(u16, u16),
    /// The terminal's input is gone.
    Hangup,
    /// A signal (the local terminal only).
    Signal(i32),
    Solved(Box<Result<Shown, String>>),
    Study(StudyResult),
    /// The presenter's new state (follow mode).
    Follow(std::sync::Arc<super::follow::Snapshot>),
    /// Nothing but a new frame (e.g. the number of followers changed).
    Redraw,
}

/// Where the loop draws: the local terminal ([`Session`]) or a remote one (an SSH channel).
/// Nothing here may query the terminal: its answers would arrive on the input the explorer
/// reads itself, and a remote terminal is known only by what its client said.
pub trait Screen {
    type Out: Write;
    fn terminal(&mut self) -> &mut Terminal<CrosstermBackend<Self::Out>>;
    /// The size in cells (columns, rows), as last known.
    fn size(&mut self) -> io::Result<(u16, u16)>;
    /// The terminal now has this size: draw the next frame whole at it.
    fn resize(&mut self, width: u16, height: u16) -> io::Result<()>;
    /// Ctrl-Z or SIGTSTP: give the terminal back until resumed, then redraw it whole. Returns
    /// `false` when this screen cannot be suspended (a remote one).
    fn suspend(&mut self) -> io::Result<bool>;
    /// Forgets what was drawn, so the next frame is drawn whole.
    fn redraw_all(&mut self) -> io::Result<()>;
}

/// Called with the state after every frame (a presenter publishes it).
pub type AfterFrame = Box<dyn FnMut(&App) + Send>;

/// How a loop behaves beyond its screen.
#[derive(Default)]
pub struct LoopOptions {
    /// End the session after this long without input.
    pub idle_timeout: Option<Duration>,
    /// `main` or `worker`: panic there after the first frame (tests of the local terminal).
    pub inject_panic: String,
    pub after_frame: Option<AfterFrame>,
    /// The session's turn on cores shared with other explorers (served sessions).
    pub cores: Option<super::cores::Share>,
    /// On return, wait until the workers have ended (a served session: its memory is given
    /// back before its slot), at most [`WORKER_GRACE`]; the local explorer never waits.
    pub wait_for_workers: bool,
}

/// Runs the explorer in the local terminal until it quits, a signal ends it, or the terminal
/// hangs up. `attach` is given a feed into the loop (for events from elsewhere: the hub of a
/// server running in the same process, `beamfric present`) and returns what to call after
/// every frame.
pub fn run(
    mut app: App,
    attach: impl FnOnce(super::remote::Feed) -> Option<AfterFrame>,
) -> Result<Ending, String> {
    let (sender, events) = channel::<Event>();
    start_signal_thread(sender.clone()).map_err(|e| format!("cannot handle signals: {e}"))?;
    let after_frame = attach(super::remote::Feed::new(sender.clone()));
    let mut session = Session::start().map_err(|e| format!("cannot open the terminal: {e}"))?;
    start_input_thread(sender.clone()).map_err(|e| format!("cannot read the terminal: {e}"))?;
    let options = LoopOptions {
        idle_timeout: None,
        inject_panic: std::env::var(INJECT_PANIC).unwrap_or_default(),
        after_frame,
        cores: None,
        wait_for_workers: false,
    };
    let result = event_loop(&mut session, &mut app, &sender, &events, options);
    drop(session);
    result.map_err(|e| format!("terminal error: {e}"))
}

/// Runs the explorer on `screen` with events from `events` (whose sender the workers also
/// use) until it quits, the input hangs up, or it was idle for too long. Mouse reporting is
/// switched on while the app wants it, and off again when the loop ends.
pub fn event_loop<S: Screen>(
    screen: &mut S,
    app: &mut App,
    sender: &Sender<Event>,
    events: &Receiver<Event>,
    options: LoopOptions,
) -> io::Result<Ending> {
    let mut mouse_on = false;
    let ending = run_with_workers(screen, app, sender, events, options, &mut mouse_on);
    if mouse_on {
        // Best effort: the terminal may be gone.
        let out = screen.terminal().backend_mut();
        let _ = out
            .write_all(MOUSE_OFF.as_bytes())
            .and_then(|()| out.flush());
    }
    ending
}

/// Asks the terminal for mouse reports, or tells it to stop, when the app's wish changed
/// (written before the next frame, which flushes it).
fn sync_mouse<S: Screen>(screen: &mut S, app: &App, mouse_on: &mut bool) -> io::Result<()> {
    let wanted = app.wants_mouse();
    if wanted != *mouse_on {
        let sequence = if wanted { MOUSE_ON } else { MOUSE_OFF };
        screen
            .terminal()
            .backend_mut()
            .write_all(sequence.as_bytes())?;
        *mouse_on = wanted;
    }
    Ok(())
}

/// Starts the workers, runs the loop, and stops them (waiting a bounded time when asked).
fn run_with_workers<S: Screen>(
    screen: &mut S,
    app: &mut App,
    sender: &Sender<Event>,
    events: &Receiver<Event>,
    mut options: LoopOptions,
    mouse_on: &mut bool,
) -> io::Result<Ending> {
    let injected = std::mem::take(&mut options.inject_panic);
    let (width, height) = screen.size()?;
    update::update(app, Action::Resize(width, height));
    let solved = sender.clone();
    let mut solver = SolveWorker::start_sharing(options.cores.clone(), move |result| {
        let _ = solved.send(Event::Solved(Box::new(result)));
    });
    let studied = sender.clone();
    let mut studies =
        Worker::start_sharing(injected == "worker", options.cores.clone(), move |result| {
            let _ = studied.send(Event::Study(result));
        });
    let mut workers = Workers {
        solver: &mut solver,
        studies: &mut studies,
    };
    let ending = run_loop(
        screen,
        app,
        events,
        &mut options,
        &injected,
        &mut workers,
        mouse_on,
    );
    if options.wait_for_workers {
        // Cancelled, they end at their next check; a step that cannot be cancelled (a dense
        // inverse) is not waited for beyond WORKER_GRACE: it holds its core until it ends.
        let threads = [solver.stop(), studies.stop()];
        let deadline = Instant::now() + WORKER_GRACE;
        while threads.iter().flatten().any(|t| !t.is_finished()) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    ending
}

/// The session's two workers.
struct Workers<'a> {
    solver: &'a mut SolveWorker,
    studies: &'a mut Worker,
}

/// The loop itself, with its workers.
fn run_loop<S: Screen>(
    screen: &mut S,
    app: &mut App,
    events: &Receiver<Event>,
    options: &mut LoopOptions,
    injected: &str,
    workers: &mut Workers,
    mouse_on: &mut bool,
) -> io::Result<Ending> {
    let Workers { solver, studies } = workers;
    let mut decoder = Decoder::default();
    let mut clicks = ClickTracker::default();
    let mut last_input = Instant::now();
    // When the last bytes came: a pending lone ESC is the Esc key ESC_TIMEOUT after them,
    // however many other events (results, a presenter's states) arrive meanwhile.
    let mut last_bytes = Instant::now();
    loop {
        if let Some(request) = app.pending_solve().cloned() {
            if app.busy_since.is_none() {
                app.busy_since = Some(Instant::now());
            }
            solver.want(&request);
        }
        studies.request(app.pending_studies());
        // Something happened (or this is the first frame): draw. A terminal that cannot be
        // written to any more has gone away.
        if sync_mouse(screen, app, mouse_on).is_err()
            || screen
                .terminal()
                .draw(|frame| view::draw(frame, app))
                .is_err()
        {
            return Ok(Ending::Hangup);
        }
        if let Some(after_frame) = &mut options.after_frame {
            after_frame(app);
        }
        if injected == "main" {
            panic!("injected panic ({INJECT_PANIC}=main)");
        }
        if app.quit {
            return Ok(Ending::Quit);
        }
        // Block until something happens; wake for a pending lone ESC, to tick a timer, or
        // when the session has been idle for too long.
        let idle_left = options
            .idle_timeout
            .map(|limit| limit.saturating_sub(last_input.elapsed()));
        if idle_left == Some(Duration::ZERO) {
            return Ok(Ending::Idle);
        }
        let timeout = if decoder.has_pending() {
            Some(ESC_TIMEOUT.saturating_sub(last_bytes.elapsed()))
        } else if !app.is_current() && app.show_timings {
            Some(TICK)
        } else {
            None
        };
        let timeout = match (timeout, idle_left) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        let first = match timeout {
            None => events.recv().map_err(|_| RecvTimeoutError::Disconnected),
            Some(t) => events.recv_timeout(t),
        };
        let first = match first {
            Ok(event) => Some(event),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => return Ok(Ending::Hangup),
        };
        if decoder.has_pending() && last_bytes.elapsed() >= ESC_TIMEOUT {
            for input in decoder.flush() {
                apply_input(app, input, &mut clicks);
            }
        }
        // This event and every one already queued, then one frame.
        for event in first
            .into_iter()
            .chain(events.try_iter().take(EVENTS_PER_FRAME))
        {
            match event {
                Event::Bytes(bytes) => {
                    last_input = Instant::now();
                    last_bytes = last_input;
                    for input in decoder.feed(&bytes) {
                        apply_input(app, input, &mut clicks);
                    }
                }
                Event::Resize(width, height) => {
                    last_input = Instant::now();
                    // A terminal that cannot be resized any more has gone away (a closed
                    // pty can report a size change just before its reads fail).
                    if screen.resize(width, height).is_err() {
                        return Ok(Ending::Hangup);
                    }
                    update::update(app, Action::Resize(width, height));
                }
                Event::Hangup => return Ok(Ending::Hangup),
                Event::Signal(signal) => match signal {
                    signal_hook::consts::SIGWINCH => {
                        if let Ok((w, h)) = crossterm::terminal::size() {
                            update::update(app, Action::Resize(w, h));
                        }
                    }
                    signal_hook::consts::SIGTSTP => {
                        suspend(screen, app)?;
                        // The terminal was given back: ask for the mouse again.
                        *mouse_on = false;
                    }
                    signal_hook::consts::SIGCONT => screen.redraw_all()?,
                    other => return Ok(Ending::Signal(other)),
                },
                Event::Solved(result) => match *result {
                    Ok(shown) => {
                        app.accept_solution(shown);
                    }
                    Err(message) => app.message = Some(message),
                },
                Event::Study(result) => {
                    app.accept(result);
                }
                Event::Redraw => {}
                Event::Follow(snapshot) => {
                    // A student watching the presenter is not idle.
                    last_input = Instant::now();
                    super::follow::receive(app, snapshot);
                }
            }
            if app.quit {
                return Ok(Ending::Quit);
            }
            if app.suspend_requested {
                app.suspend_requested = false;
                suspend(screen, app)?;
                *mouse_on = false;
            }
        }
    }
}

fn apply_input(app: &mut App, input: Input, clicks: &mut ClickTracker) {
    match input {
        Input::Key(key) => {
            if super::follow::intercept(app, key) {
                return;
            }
            if let Some(action) = action_for(&app.mode, key) {
                update::update(app, action);
            }
        }
        Input::Paste(text) => {
            for action in paste_actions(&app.mode, &text) {
                update::update(app, action);
            }
        }
        // Without mouse capture (`--no-mouse`) the mouse means nothing, even if a client sends
        // its sequences.
        Input::Mouse(x, y, what) => {
            if app.mouse {
                let action = super::mouse::action(x, y, what, clicks, Instant::now());
                update::update(app, action);
            }
        }
        Input::Hangup => app.quit = true,
    }
}

/// Ctrl-Z or SIGTSTP: leave the terminal, stop, and on SIGCONT take it back at its new size
/// (a remote terminal cannot be left: it says so).
fn suspend<S: Screen>(screen: &mut S, app: &mut App) -> io::Result<()> {
    if !screen.suspend()? {
        app.message = Some("Ctrl-Z does nothing here: q quits".into());
        return Ok(());
    }
    if let Ok((w, h)) = screen.size() {
        update::update(app, Action::Resize(w, h));
    }
    Ok(())
}

/// Reads the terminal's bytes until end of file or an error, which is a hangup.
fn start_input_thread(sender: Sender<Event>) -> io::Result<()> {
    use std::io::IsTerminal;
    let mut input: Box<dyn Read + Send> = if io::stdin().is_terminal() {
        Box::new(io::stdin())
    } else {
        Box::new(std::fs::File::open("/dev/tty")?)
    };
    std::thread::Builder::new()
        .name("input".into())
        .spawn(move || {
            let mut buffer = [0u8; 4096];
            loop {
                match input.read(&mut buffer) {
                    Ok(0) => break,
                    Ok(n) => {
                        if sender.send(Event::Bytes(buffer[..n].to_vec())).is_err() {
                            return;
                        }
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(_) => break,
                }
            }
            let _ = sender.send(Event::Hangup);
        })?;
    Ok(())
}

fn start_signal_thread(sender: Sender<Event>) -> io::Result<()> {
    let mut signals = signal_hook::iterator::Signals::new(SIGNALS)?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                if sender.send(Event::Signal(signal)).is_err() {
                    return;
                }
            }
        })?;
    Ok(())
}
