//! The interactive explorer's event loop. The UI thread only reads events, updates the state
//! and draws; everything slow runs on workers:
//!
//! - an input thread reads the terminal's bytes (end of file or a read error: [`Event::Bytes`]
//!   stops and a hangup ends the explorer — no busy loop on a closed terminal);
//! - a signal thread turns SIGINT, SIGTERM, SIGHUP, SIGWINCH, SIGTSTP and SIGCONT into events;
//! - the solver worker computes the keystroke's re-solve, the study worker the charts' data.
//!
//! All of them feed one channel, and the loop blocks on it: it draws only when something
//! changed (a key, a result, a resize, or a timer tick a few times a second while work is in
//! flight), so an idle explorer uses no CPU. Every queued event is applied before the next
//! frame and the next request to a worker, so a burst of keys makes one solve of the final
//! state. Quitting never waits for a worker.

use std::io::{self, Read};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::time::{Duration, Instant};

use super::app::{App, Shown};
use super::input::{Decoder, ESC_TIMEOUT, Input};
use super::keymap::{Action, action_for, paste_actions};
use super::solver::SolveWorker;
use super::studies::{StudyResult, Worker};
use super::terminal::{SIGNALS, Session};
use super::{Ending, INJECT_PANIC, update, view};

/// How often the frame is redrawn while work is in flight (for the elapsed time).
const TICK: Duration = Duration::from_millis(250);
/// Most events applied before a frame is drawn (a paste of any size still shows progress).
const EVENTS_PER_FRAME: usize = 4096;

/// What wakes the loop.
enum Event {
    /// Bytes from the terminal.
    Bytes(Vec<u8>),
    /// The terminal's input is gone.
    Hangup,
    Signal(i32),
    Solved(Box<Result<Shown, String>>),
    Study(StudyResult),
}

/// Runs the explorer until it quits, a signal ends it, or the terminal hangs up.
pub fn run(mut app: App) -> Result<Ending, String> {
    let (sender, events) = channel::<Event>();
    start_signal_thread(sender.clone()).map_err(|e| format!("cannot handle signals: {e}"))?;
    let mut session = Session::start().map_err(|e| format!("cannot open the terminal: {e}"))?;
    start_input_thread(sender.clone()).map_err(|e| format!("cannot read the terminal: {e}"))?;
    let result = event_loop(&mut session, &mut app, &sender, &events);
    drop(session);
    result.map_err(|e| format!("terminal error: {e}"))
}

fn event_loop(
    session: &mut Session,
    app: &mut App,
    sender: &Sender<Event>,
    events: &Receiver<Event>,
) -> io::Result<Ending> {
    let injected = std::env::var(INJECT_PANIC).unwrap_or_default();
    let size = session.terminal.size()?;
    update::update(app, Action::Resize(size.width, size.height));
    let solved = sender.clone();
    let mut solver = SolveWorker::start(move |result| {
        let _ = solved.send(Event::Solved(Box::new(result)));
    });
    let studied = sender.clone();
    let mut studies = Worker::start(injected == "worker", move |result| {
        let _ = studied.send(Event::Study(result));
    });
    let mut decoder = Decoder::default();
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
        if session
            .terminal
            .draw(|frame| view::draw(frame, app))
            .is_err()
        {
            return Ok(Ending::Hangup);
        }
        if injected == "main" {
            panic!("injected panic ({INJECT_PANIC}=main)");
        }
        if app.quit {
            return Ok(Ending::Quit);
        }
        // Block until something happens; wake for a pending lone ESC, or to tick a timer.
        let timeout = if decoder.has_pending() {
            Some(ESC_TIMEOUT)
        } else if !app.is_current() && app.show_timings {
            Some(TICK)
        } else {
            None
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
        if first.is_none() {
            for input in decoder.flush() {
                apply_input(app, input);
            }
        }
        // This event and every one already queued, then one frame.
        for event in first
            .into_iter()
            .chain(events.try_iter().take(EVENTS_PER_FRAME))
        {
            match event {
                Event::Bytes(bytes) => {
                    for input in decoder.feed(&bytes) {
                        apply_input(app, input);
                    }
                }
                Event::Hangup => return Ok(Ending::Hangup),
                Event::Signal(signal) => match signal {
                    signal_hook::consts::SIGWINCH => {
                        if let Ok((w, h)) = crossterm::terminal::size() {
                            update::update(app, Action::Resize(w, h));
                        }
                    }
                    signal_hook::consts::SIGTSTP => suspend(session, app)?,
                    signal_hook::consts::SIGCONT => session.redraw_all()?,
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
            }
            if app.quit {
                return Ok(Ending::Quit);
            }
            if app.suspend_requested {
                app.suspend_requested = false;
                suspend(session, app)?;
            }
        }
    }
}

fn apply_input(app: &mut App, input: Input) {
    match input {
        Input::Key(key) => {
            if let Some(action) = action_for(&app.mode, key) {
                update::update(app, action);
            }
        }
        Input::Paste(text) => {
            for action in paste_actions(&app.mode, &text) {
                update::update(app, action);
            }
        }
        Input::Mouse(..) => {}
        Input::Hangup => app.quit = true,
    }
}

/// Ctrl-Z or SIGTSTP: leave the terminal, stop, and on SIGCONT take it back at its new size.
fn suspend(session: &mut Session, app: &mut App) -> io::Result<()> {
    session.suspend()?;
    if let Ok((w, h)) = crossterm::terminal::size() {
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
