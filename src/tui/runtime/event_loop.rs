//! The interactive explorer's event loop, the same for the local terminal and for a remote one
//! (an SSH channel, see `crate::serve`): it draws on a [`Screen`] and hears everything through
//! one channel of [`Event`]s, which it turns into the update's messages. The UI thread only
//! reads events, updates the state (`tui::update`, the only writer) and draws; everything slow
//! runs on workers:
//!
//! - the terminal's bytes arrive as [`Event::Bytes`] — locally from an input thread (end of
//!   file or a read error is a hangup that ends the explorer: no busy loop on a closed
//!   terminal), remotely from the SSH connection, with window changes as [`Event::Resize`];
//! - locally, a signal thread turns SIGINT, SIGTERM, SIGHUP, SIGWINCH, SIGTSTP and SIGCONT
//!   into events;
//! - one worker computes the keystroke's re-solve, another the charts' sweeps
//!   ([`super::worker`]).
//!
//! All of them feed one channel, and the loop blocks on it: it draws only when something
//! changed (a key, a result, a resize, or a timer tick a few times a second while work is in
//! flight), so an idle explorer uses no CPU. Every queued event is applied before the next
//! frame and the next request to a worker, so a burst of keys makes one solve of the final
//! state. Quitting never waits for a worker.

use std::collections::VecDeque;
use std::io::{self, Write};
use std::sync::mpsc::{RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

use crate::tui::input::decode::{Decoder, ESC_TIMEOUT, Input};
use crate::tui::input::pointer::ClickTracker;
use crate::tui::jobs::solve::SolveRequest;
use crate::tui::jobs::sweeps::{SWEEPS, SweepRequest};
use crate::tui::state::{App, Ending, Mode};
use crate::tui::update::{Msg, Suspension, update};
use crate::tui::view;

use super::budget::TimeBudget;
pub use super::feed::Event;
use super::feed::{Events, Signals};
use super::screen::{MOUSE_OFF, MOUSE_ON, Screen};
use super::worker::{Worker, WorkerOptions};

/// Set to `main` or `worker` to make the explorer panic after its first frame (on the main
/// thread or in a sweep), to test that the terminal is restored.
pub const INJECT_PANIC: &str = "BEAMFRIC_INJECT_PANIC";

/// How often the frame is redrawn while work is in flight (for the elapsed time).
const TICK: Duration = Duration::from_millis(250);
/// How often the presenter's list of students is redrawn while open (its idle times).
const STUDENTS_TICK: Duration = Duration::from_secs(1);
/// How long before the idle timeout the user is warned (at most half the timeout).
const IDLE_WARNING: Duration = Duration::from_secs(60);
/// Longest a served session waits for its cancelled workers to end before it lets them go.
const WORKER_GRACE: Duration = Duration::from_millis(500);
/// Most events taken from the queue before a frame is drawn.
const EVENTS_PER_FRAME: usize = 4096;
/// Most keys, pastes and mouse events applied before a frame is drawn, and the longest time
/// spent applying them: a burst shows progress, and a hang-up or a result is heard between.
const INPUTS_PER_FRAME: usize = 256;
const INPUT_SLICE: Duration = Duration::from_millis(50);
/// How often a session resting on its time budget looks for a hang-up.
const REST_STEP: Duration = Duration::from_millis(10);

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
    /// The share of one core the loop's own thread may use on average, with bursts of up to
    /// a second (served sessions: a flood of keys or window changes is slowed to it, never
    /// queued beyond it); `None`: no limit (the local explorer).
    pub ui_share: Option<f64>,
}

/// The session's two workers.
struct Workers {
    solver: Worker<SolveRequest>,
    sweeps: Worker<SweepRequest>,
}

impl Workers {
    fn start(sender: &Sender<Event>, options: &LoopOptions, inject_panic: bool) -> Workers {
        let solved = sender.clone();
        let solver = Worker::start(
            "solver",
            1,
            WorkerOptions {
                share: options.cores.clone(),
                inject_panic: false,
            },
            move |result| {
                let _ = solved.send(Event::Solved(Box::new(result)));
            },
        );
        let swept = sender.clone();
        let sweeps = Worker::start(
            "sweeps",
            SWEEPS.len(),
            WorkerOptions {
                share: options.cores.clone(),
                inject_panic,
            },
            move |result| {
                let _ = swept.send(Event::Swept(result));
            },
        );
        Workers { solver, sweeps }
    }

    /// Hands the workers what the state wants now (an outdated job is cancelled), and tells
    /// the state when its solve started.
    fn hand_out(&mut self, app: &mut App) {
        let pending = app.exploration.pending_solve().cloned();
        if pending.is_some() {
            update(app, Msg::SolveStarted(Instant::now()));
        }
        self.solver.want(0, pending.as_ref());
        let sweeps = app.exploration.pending_sweeps();
        for lane in 0..SWEEPS.len() {
            self.sweeps
                .want(lane, sweeps.iter().find(|request| request.sweep == lane));
        }
    }

    /// Stops both; with `wait`, waits (a bounded time) until their threads have ended.
    fn stop(self, wait: bool) {
        let threads = [self.solver.stop(), self.sweeps.stop()];
        if !wait {
            return;
        }
        // Cancelled, they end at their next check (within tens of milliseconds in every
        // method); whatever still runs is not waited for beyond WORKER_GRACE.
        let deadline = Instant::now() + WORKER_GRACE;
        while threads.iter().flatten().any(|t| !t.is_finished()) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

/// Runs the explorer on `screen` with events from `events` (whose sender the workers also
/// use) until it ends: it quits, the input hangs up, a signal, or it was idle for too long.
/// Mouse reporting is switched on while the app wants it, and off again when the loop ends.
pub fn event_loop<S: Screen>(
    screen: &mut S,
    app: &mut App,
    events: &Events,
    mut options: LoopOptions,
) -> io::Result<Ending> {
    let injected = std::mem::take(&mut options.inject_panic);
    let (width, height) = screen.size()?;
    update(app, Msg::Resize(width, height));
    let mut workers = Workers::start(&events.sender, &options, injected == "worker");
    let mut state = LoopState {
        decoder: Decoder::default(),
        clicks: ClickTracker::default(),
        inputs: VecDeque::new(),
        last_input: Instant::now(),
        idle_warned: false,
        in_lecture: false,
        last_bytes: Instant::now(),
        mouse_on: false,
        text_shown: None,
        budget: options
            .ui_share
            .map(|share| TimeBudget::new(share, Duration::from_secs(1))),
    };
    let ending = run_loop(
        screen,
        app,
        events,
        &mut options,
        &injected,
        &mut workers,
        &mut state,
    );
    workers.stop(options.wait_for_workers);
    if state.mouse_on {
        // Best effort: the terminal may be gone.
        let out = screen.terminal().backend_mut();
        let _ = out
            .write_all(MOUSE_OFF.as_bytes())
            .and_then(|()| out.flush());
    }
    ending
}

/// What the loop keeps between events besides the state.
struct LoopState {
    decoder: Decoder,
    clicks: ClickTracker,
    /// Decoded input not applied yet (a burst is applied a slice per frame).
    inputs: VecDeque<Input>,
    /// The loop's own time, when limited ([`LoopOptions::ui_share`]).
    budget: Option<TimeBudget>,
    /// When the user last did something (or the presenter did, for a follower).
    last_input: Instant,
    /// The idle warning was shown since [`LoopState::last_input`].
    idle_warned: bool,
    /// The last wait was in a lecture ([`in_a_lecture`]): no idle time counted.
    in_lecture: bool,
    /// When the last bytes came: a pending lone ESC is the Esc key ESC_TIMEOUT after them,
    /// however many other events (results, a presenter's states) arrive meanwhile.
    last_bytes: Instant,
    /// Mouse reports are on in the terminal.
    mouse_on: bool,
    /// The scene whose text the screen shows, outside the explorer's ([`Screen::show_text`]).
    text_shown: Option<crate::scene::Scene>,
}

impl LoopState {
    /// The user did something (or the presenter did, for a follower): idle from now.
    fn note_input(&mut self) {
        self.last_input = Instant::now();
        self.idle_warned = false;
    }
}

/// The loop itself: hand out work, draw, wait, apply what arrived; until the state ends. A
/// hang-up is heard before every event and every key: nothing queued behind it is applied.
fn run_loop<S: Screen>(
    screen: &mut S,
    app: &mut App,
    events: &Events,
    options: &mut LoopOptions,
    injected: &str,
    workers: &mut Workers,
    state: &mut LoopState,
) -> io::Result<Ending> {
    loop {
        let frame_started = Instant::now();
        workers.hand_out(app);
        // Something happened (or this is the first frame): draw. A terminal that cannot be
        // written to any more has gone away.
        if draw(screen, app, state).is_err() {
            update(app, Msg::End(Ending::Hangup));
            return Ok(Ending::Hangup);
        }
        if let Some(after_frame) = &mut options.after_frame {
            after_frame(app);
        }
        if injected == "main" {
            panic!("injected panic ({INJECT_PANIC}=main)");
        }
        if let Some(ending) = app.ending {
            return Ok(ending);
        }
        if let Some(budget) = &mut state.budget {
            budget.spend(frame_started.elapsed());
            rest(budget, &events.signals);
        }
        let first = if events.signals.hung_up() {
            Some(Event::Hangup)
        } else if state.inputs.is_empty() {
            wait(app, events, options, state)
        } else {
            events.receiver.try_recv().ok()
        };
        if let Some(ending) = app.ending {
            return Ok(ending);
        }
        let working = Instant::now();
        if state.decoder.has_pending() && state.last_bytes.elapsed() >= ESC_TIMEOUT {
            state.inputs.extend(state.decoder.flush());
        }
        // This event and every one already queued, then the input they brought, one slice.
        for event in first
            .into_iter()
            .chain(events.receiver.try_iter().take(EVENTS_PER_FRAME))
        {
            let event = if events.signals.hung_up() {
                Event::Hangup
            } else {
                event
            };
            apply_event(screen, app, event, state)?;
            if let Some(ending) = app.ending {
                return Ok(ending);
            }
        }
        // The frame drawn next shows whatever a redraw was asked for until now.
        events.signals.take_redraw();
        apply_inputs(screen, app, state, &events.signals)?;
        if let Some(ending) = app.ending {
            return Ok(ending);
        }
        // However many window changes came, one resize, to the newest size.
        if let Some((width, height)) = events.signals.take_size() {
            state.note_input();
            // A terminal that cannot be resized any more has gone away.
            if screen.resize(width, height).is_err() {
                update(app, Msg::End(Ending::Hangup));
                return Ok(Ending::Hangup);
            }
            update(app, Msg::Resize(width, height));
        }
        if let Some(budget) = &mut state.budget {
            budget.spend(working.elapsed());
        }
    }
}

/// Applies queued input, at most [`INPUTS_PER_FRAME`] items or [`INPUT_SLICE`] of time; stops
/// at a hang-up or an ending.
fn apply_inputs<S: Screen>(
    screen: &mut S,
    app: &mut App,
    state: &mut LoopState,
    signals: &Signals,
) -> io::Result<()> {
    let started = Instant::now();
    let mut applied = 0;
    while applied < INPUTS_PER_FRAME && started.elapsed() < INPUT_SLICE {
        if signals.hung_up() {
            update(app, Msg::End(Ending::Hangup));
            return Ok(());
        }
        let Some(input) = state.inputs.pop_front() else {
            break;
        };
        apply_input(app, input, &mut state.clicks);
        applied += 1;
        if app.ending.is_some() {
            return Ok(());
        }
        if app.suspend_requested {
            suspend(screen, app)?;
            // The terminal was given back: ask for the mouse again.
            state.mouse_on = false;
        }
    }
    Ok(())
}

/// Waits until the loop's time budget has credit again, looking for a hang-up meanwhile.
fn rest(budget: &mut TimeBudget, signals: &Signals) {
    loop {
        let left = budget.rest();
        if left.is_zero() || signals.hung_up() {
            return;
        }
        std::thread::sleep(left.min(REST_STEP));
    }
}

/// Draws a frame, asking the terminal for mouse reports first (or telling it to stop) when
/// the app's wish changed.
fn draw<S: Screen>(screen: &mut S, app: &App, state: &mut LoopState) -> io::Result<()> {
    if screen.before_frame()? {
        // The client may have missed the mouse switch too: say it again.
        state.mouse_on = false;
    }
    // The scene as TOML to copy: outside the explorer's screen where this screen can show it
    // so (whole, unwrapped), and nothing drawn over it until a key brings the explorer back
    // (the mouse is switched off before it is shown, and on again after it). A burst of keys
    // can close it, change the scene and open it again between two frames: then the text
    // shown is another scene's, and it is shown anew.
    let text_wanted = app.mode == Mode::SceneText;
    let stale = |shown: &crate::scene::Scene| !text_wanted || shown != app.scene();
    if state.text_shown.as_ref().is_some_and(stale) {
        screen.end_text()?;
        state.text_shown = None;
    }
    let wanted = app.wants_mouse();
    if wanted != state.mouse_on {
        let sequence = if wanted { MOUSE_ON } else { MOUSE_OFF };
        screen
            .terminal()
            .backend_mut()
            .write_all(sequence.as_bytes())?;
        state.mouse_on = wanted;
    }
    if text_wanted && state.text_shown.is_none() {
        let lines: Vec<String> = app
            .scene()
            .to_toml()
            .lines()
            .map(|line| crate::format::printable(line).into_owned())
            .collect();
        if screen.show_text(&lines)? {
            state.text_shown = Some(app.scene().clone());
        }
    }
    if state.text_shown.is_some() {
        return Ok(());
    }
    screen.terminal().draw(|frame| view::draw(frame, app))?;
    Ok(())
}

/// How long before an idle session ends its user is told: a minute, or half the timeout
/// where that is shorter.
fn idle_warning_before(limit: Duration) -> Duration {
    IDLE_WARNING.min(limit / 2)
}

/// Blocks until something happens: an event, or a wake-up for a pending lone ESC or a timer
/// tick while work is in flight (`None`, after a tick message); ends the state when the
/// session was idle for too long or the channel is gone.
fn wait(
    app: &mut App,
    events: &Events,
    options: &LoopOptions,
    state: &mut LoopState,
) -> Option<Event> {
    // In a lecture there is no idle timer at all (stop 59's pass: a presenter silent for the
    // idle timeout closed every follower), and idle counts from the moment it stops being
    // one. No timer either: a presenter woken by one would draw, and its frame would reach
    // every student.
    let lecture = in_a_lecture(app);
    // Also on the first wait after it stopped being one (stop 60's pass: the presenter who
    // left, or the last follower forking, ended the session at once, idle since long before).
    if lecture || state.in_lecture {
        state.note_input();
    }
    state.in_lecture = lecture;
    let idle_timeout = options.idle_timeout.filter(|_| !lecture);
    let idle_left = idle_timeout.map(|limit| limit.saturating_sub(state.last_input.elapsed()));
    if idle_left == Some(Duration::ZERO) {
        update(app, Msg::End(Ending::Idle));
        return None;
    }
    // How long until the idle warning is due (it is shown once per idle stretch).
    let warning_in = match (idle_timeout, idle_left) {
        (Some(limit), Some(left)) if !state.idle_warned => {
            Some(left.saturating_sub(idle_warning_before(limit)))
        }
        _ => None,
    };
    if let (Some(Duration::ZERO), Some(left)) = (warning_in, idle_left) {
        state.idle_warned = true;
        update(app, Msg::IdleWarning(left));
        return None;
    }
    let idle_left = match (idle_left, warning_in) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, _) => a,
    };
    let timeout = if state.decoder.has_pending() {
        Some(ESC_TIMEOUT.saturating_sub(state.last_bytes.elapsed()))
    } else if !app.exploration.is_current() && app.show_timings {
        Some(TICK)
    } else if matches!(app.mode, Mode::Students { .. }) {
        // The list's idle times move on.
        Some(STUDENTS_TICK)
    } else {
        None
    };
    let timeout = match (timeout, idle_left) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let received = match timeout {
        None => events
            .receiver
            .recv()
            .map_err(|_| RecvTimeoutError::Disconnected),
        Some(t) => events.receiver.recv_timeout(t),
    };
    match received {
        Ok(event) => Some(event),
        Err(RecvTimeoutError::Timeout) => {
            update(app, Msg::Tick);
            None
        }
        Err(RecvTimeoutError::Disconnected) => {
            update(app, Msg::End(Ending::Hangup));
            None
        }
    }
}

/// A student following a presenter, or the leading presenter while students follow: in a
/// lecture, and not idle however long the presenter talks without a key (the class's end, or
/// the presenter leaving, ends that; the session limit, not the idle timeout, bounds who may
/// stay).
fn in_a_lecture(app: &App) -> bool {
    app.follow.as_ref().is_some_and(|follow| {
        follow.is_following()
            || (!follow.is_student() && follow.leads && follow.followers.count() > 0)
    })
}

/// One event, as the update's messages.
fn apply_event<S: Screen>(
    screen: &mut S,
    app: &mut App,
    event: Event,
    state: &mut LoopState,
) -> io::Result<()> {
    match event {
        Event::Bytes(bytes) => {
            state.note_input();
            state.last_bytes = state.last_input;
            state.inputs.extend(state.decoder.feed(&bytes));
        }
        // Applied once after the queue is read, at the newest size.
        Event::Resize => state.note_input(),
        Event::Hangup => update(app, Msg::End(Ending::Hangup)),
        Event::Signal(signal) => match signal {
            signal_hook::consts::SIGWINCH => {
                if let Ok((w, h)) = crossterm::terminal::size() {
                    screen.resize(w, h)?;
                    update(app, Msg::Resize(w, h));
                }
            }
            signal_hook::consts::SIGTSTP => {
                suspend(screen, app)?;
                // The terminal was given back: ask for the mouse again.
                state.mouse_on = false;
            }
            signal_hook::consts::SIGCONT => screen.redraw_all()?,
            other => update(app, Msg::End(Ending::Signal(other))),
        },
        Event::Solved(result) => match *result {
            Ok(solved) => update(app, Msg::Solved(Box::new(solved))),
            Err(message) => update(app, Msg::SolveFailed(message)),
        },
        Event::Swept(result) => update(app, Msg::Swept(result)),
        Event::Redraw => update(app, Msg::Tick),
        Event::Notice(text) => update(app, Msg::Notice(text)),
        // A student following is not idle ([`in_a_lecture`]); one who forked is, however
        // busy the presenter whose states it keeps for `F`.
        Event::Follow(exploration) => update(app, Msg::Follow(exploration)),
        Event::Class(news) => update(app, Msg::Class(news)),
    }
    Ok(())
}

/// A decoded input as the update's message (a mouse event with its double click told).
fn apply_input(app: &mut App, input: Input, clicks: &mut ClickTracker) {
    let msg = match input {
        Input::Key(key) => Msg::Key(key),
        Input::Paste(text) => Msg::Paste(text),
        Input::PasteDropped(dropped) => Msg::PasteDropped(dropped),
        Input::Mouse(x, y, what) => Msg::Pointer(clicks.pointer(x, y, what, Instant::now())),
    };
    update(app, msg);
}

/// Ctrl-Z or SIGTSTP: leave the terminal, stop, and on SIGCONT take it back at its new size
/// (a remote terminal cannot be left: the state says so).
fn suspend<S: Screen>(screen: &mut S, app: &mut App) -> io::Result<()> {
    let suspension = if !screen.suspend()? {
        Suspension::Refused
    } else {
        let (width, height) = screen.size().unwrap_or(app.size);
        Suspension::Resumed(width, height)
    };
    update(app, Msg::Suspension(suspension));
    Ok(())
}
