//! `beamfric present`: the server behind the lecturer's own explorer, which presents; the join
//! screen's words (how students log in); and the end of the class — every student's closing
//! screen, then a grace for them to read it before the server stops.

use std::sync::Arc;

use super::{Log, ServeError, ServeOptions, Server, lock, log};

/// `beamfric present`: the server of [`serve_until_stopped`], and the lecturer's own explorer
/// in this terminal, which presents — its scene and view go to every following session, as a
/// session logged in with a presenter key does. Log lines are kept while the explorer has the terminal
/// and printed after it. Quitting the explorer stops the server: every student's explorer
/// leaves its screen and its connection closes. Returns how the lecturer's explorer ended.
pub fn present(
    options: &ServeOptions,
    look: crate::plot::Look,
) -> Result<crate::tui::Ending, ServeError> {
    use crate::tui::runtime::local::run_local;
    use crate::tui::state::follow::Follow;
    use crate::tui::state::{App, JoinInfo, Options};
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
    let publishing = Arc::clone(&shared);
    let mut presenter_id = None;
    let ending = run_local(app, |feed| {
        presenter_id = Some(hub.join_presenter(feed));
        Some(Box::new(move |app: &App| {
            if let Some(hub) = &publishing.hub {
                hub.publish(&app.exploration);
            }
        }))
    })
    .map_err(ServeError::Terminal);
    // The class ends: every student sees their closing screen (their scene saved under
    // --save-dir or shown to copy) and leaves with a key, or the server closes after a grace.
    let told = hub.end_class("the lecturer");
    if told > 0 {
        log(&format!(
            "the class is over: {told} student{} see their closing screen; waiting up to {} s \
             for them to leave (Ctrl-C stops now)",
            if told == 1 { "" } else { "s" },
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
    ending
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
