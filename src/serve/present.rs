//! `beamfric present`: the server behind the lecturer's own explorer, which presents; the join
//! screen's words (how students log in); and the end of the class — every student's closing
//! screen, then a grace for them to read it before the server stops.

use std::sync::Arc;

use super::{Log, ServeError, ServeOptions, Server, lock, log};
use crate::tui::runtime::record::{RecordTap, Recording, check_target};

/// `beamfric present`: the server of [`serve_until_stopped`], and the lecturer's own explorer
/// in this terminal, which presents — its scene and view go to every following session, as a
/// session logged in with a presenter key does. Log lines are kept while the explorer has the terminal
/// and printed after it. Quitting the explorer stops the server: every student's explorer
/// leaves its screen and its connection closes. Returns how the lecturer's explorer ended.
pub fn present(
    options: &ServeOptions,
    look: crate::plot::Look,
    record: Option<&std::path::Path>,
) -> Result<crate::tui::Ending, ServeError> {
    use crate::tui::runtime::local::run_local;
    use crate::tui::state::follow::Follow;
    use crate::tui::state::{App, JoinInfo, Options};
    // A recording that cannot be made is said before anything starts (no host key written,
    // no port opened).
    if let Some(path) = record {
        check_target(path).map_err(|e| record_error(path, &e))?;
    }
    let server = Server::start_as(options, true)?;
    let listening = format!(
        "listening on {} (host key {}); students connect with: ssh -p {} HOST",
        server.address(),
        server.fingerprint(),
        server.address().port()
    );
    for note in server.notes() {
        log(note);
    }
    log(&listening);
    let shared = Arc::clone(&server.shared);
    let Some(hub) = &shared.hub else {
        return Err(ServeError::Start(
            "internal error: a presenting server without a follow hub".into(),
        ));
    };
    let options = Options {
        show_timings: true,
        mouse: options.mouse,
        palette: options.palette,
        markers: options.markers,
        follow: Some(Follow::presenter(&hub.followers, true)),
        lesson: shared.explorer.lesson.clone(),
        greeting: Some(format!(
            "presenting: students connect with ssh -p {} HOST (J: how they join)",
            server.address().port(),
        )),
        join: Some(JoinInfo {
            address: server.address(),
            fingerprint: server.fingerprint().to_string(),
            login: login_words(options),
        }),
        ..Options::new(look)
    };
    let app = App::new(shared.explorer.scene.clone(), options)?;
    let recording = match record {
        Some(path) => Some(start_recording(path)?),
        None => None,
    };
    let tap = recording.as_ref().map(Recording::tap);
    let publishing = Arc::clone(&shared);
    let mut presenter_id = None;
    let mut marks = tap.clone().map(Marks::new);
    let ending = run_local(
        app,
        |feed| {
            if let Some(recording) = &recording {
                recording.tell_failures_to(feed.clone());
            }
            let id = hub.join_presenter(feed);
            presenter_id = Some(id);
            Some(Box::new(move |app: &App| {
                if let Some(hub) = &publishing.hub {
                    hub.publish(id, &app.exploration);
                }
                if let Some(marks) = &mut marks {
                    marks.after_frame(app);
                }
            }))
        },
        tap,
    )
    .map_err(ServeError::Terminal);
    let recording_failed = recording.and_then(|recording| finish_recording(recording, record));
    // The class ends: every student sees their closing screen (their scene saved under
    // --save-dir or shown to copy) and leaves with a key, or the server closes after a grace.
    let told = hub.end_class("the lecturer");
    if told > 0 {
        log(&format!(
            "the class is over: {told} {} their closing screen; waiting up to {} s for them to \
             leave (Ctrl-C stops now)",
            if told == 1 {
                "student sees"
            } else {
                "students see"
            },
            CLOSING_GRACE.as_secs()
        ));
        wait_for_students(&server);
    }
    if let Some(id) = presenter_id {
        hub.leave(id);
    }
    // The terminal is the lecturer's again: stop serving, then say what happened meanwhile.
    drop(server);
    if let Log::Kept(lines) = &shared.log {
        for line in lock(lines).drain(..) {
            log(&line);
        }
    }
    log("stopped");
    // Said last, and the status is not zero: the recording is not what was asked for.
    if let Some(failure) = recording_failed {
        return Err(ServeError::Recording(failure));
    }
    ending
}

/// Ends the recording and says where it went; or returns why it could not be finished.
fn finish_recording(recording: Recording, path: Option<&std::path::Path>) -> Option<String> {
    match recording.finish() {
        Ok(summary) => log(&format!(
            "recording saved: {}{} ({:.0} s, {} bytes{}); asciinema play {} replays it",
            crate::format::printable(&summary.path.display().to_string()),
            summary
                .moved_from
                .as_ref()
                .map_or_else(String::new, |asked| format!(
                    " (not {}: something else was put there meanwhile)",
                    crate::format::printable(&asked.display().to_string())
                )),
            summary.seconds,
            summary.bytes,
            if summary.truncated {
                ", cut at the size limit"
            } else {
                ""
            },
            crate::format::printable(&summary.path.display().to_string())
        )),
        // A full disk, say: the file keeps its last whole write, a complete cast.
        Err(e) => {
            return Some(format!(
                "the recording could not be finished ({}); {} keeps it as last written, a complete \
             cast up to then",
                e.kind(),
                path.map_or_else(String::new, |p| crate::format::printable(
                    &p.display().to_string()
                )
                .into_owned()),
            ));
        }
    }
    None
}

/// Starts `--record FILE`: the terminal's size now, written at once (a file there is refused).
fn start_recording(path: &std::path::Path) -> Result<Recording, ServeError> {
    let size = crossterm::terminal::size().unwrap_or((80, 24));
    Recording::start(path, size, "beamfric present").map_err(|e| record_error(path, &e))
}

fn record_error(path: &std::path::Path, e: &std::io::Error) -> ServeError {
    ServeError::Option(format!(
        "--record {}: {e}",
        crate::format::printable(&path.display().to_string())
    ))
}

/// What the recording marks after each frame: a lesson's step when it changes (an asciinema
/// marker, `step 2/7: title`). The terminal's new size is noted before the frame drawn at it,
/// by the terminal's own output (`runtime::record::Output::note_resize`).
struct Marks {
    tap: RecordTap,
    step: Option<usize>,
}

impl Marks {
    fn new(tap: RecordTap) -> Marks {
        Marks { tap, step: None }
    }

    fn after_frame(&mut self, app: &crate::tui::state::App) {
        if let Some(place) = &app.exploration.lesson
            && self.step != Some(place.step)
        {
            self.step = Some(place.step);
            self.tap.marker(&format!(
                "step {}/{}: {}",
                place.step + 1,
                place.lesson.steps.len(),
                place.current().title
            ));
        }
    }
}

/// How students log in to a server started with `options`, in words for the join screen.
fn login_words(options: &ServeOptions) -> String {
    let mut ways = Vec::new();
    if options.open {
        ways.push("any user name, no password (the server is open)");
    }
    if options.password_file.is_some() {
        ways.push("any user name and the class password");
    }
    if options.authorized_keys.is_some() {
        ways.push("their SSH key, if the lecturer listed it");
    }
    if ways.is_empty() {
        return "nobody can log in: give --open, --password-file or --authorized-keys".into();
    }
    format!(
        "{}; the user name names their saved files",
        ways.join(", or ")
    )
}

/// How long students may read their closing screen before the server closes.
const CLOSING_GRACE: std::time::Duration = std::time::Duration::from_secs(60);

/// Waits until every student's explorer has ended, [`CLOSING_GRACE`] has passed, or Ctrl-C.
fn wait_for_students(server: &Server) {
    let interrupted = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let hooks: Vec<_> = [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM]
        .into_iter()
        .filter_map(|signal| signal_hook::flag::register(signal, Arc::clone(&interrupted)).ok())
        .collect();
    let deadline = std::time::Instant::now() + CLOSING_GRACE;
    while server.sessions() > 0
        && std::time::Instant::now() < deadline
        && !interrupted.load(std::sync::atomic::Ordering::Relaxed)
    {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    for hook in hooks {
        signal_hook::low_level::unregister(hook);
    }
}
