//! One served explorer: its own `App`, workers and UI thread, running the local explorer's
//! event loop on the SSH channel. What it draws goes through a [`ChannelWriter`] to a task
//! that sends it to the client; when the explorer ends (quit, idle, hangup) that task closes
//! the channel, and only then gives back the session's slot (so a slot freed means the
//! explorer, its workers and its connection's output are gone). Its look follows what the
//! client sent: ASCII when its locale is not UTF-8, no colours with `NO_COLOR`. It saves only
//! under the lecturer's `--save-dir`, else `s` shows the TOML to copy.

use std::io::{self, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use russh::ChannelId;
use russh::server::Handle;
use tokio::sync::mpsc;

use crate::plot::{Look, UnsetLocale, locale_is_utf8};
use crate::scene::LoadedScene;
use crate::tui::runtime::remote::{self, AfterFrame, Feed, RemoteOptions};
use crate::tui::state::follow::Follow;
use crate::tui::state::{App, Options, SavePolicy};
use crate::tui::update::{Msg, update};

use super::ServeError;
use super::limits::SessionSlot;
use super::{Shared, lock};

/// Frames waiting for the client. Beyond them, a client that does not read loses frames (the
/// newest is drawn whole once it reads again): the explorer never waits for it, and the
/// server keeps at most these few frames for it.
const OUTPUT_QUEUE: usize = 4;
/// Environment variables a client may set, and the longest value kept.
pub const ACCEPTED_ENV: [&str; 4] = ["LANG", "LC_ALL", "LC_CTYPE", "NO_COLOR"];
pub const ENV_VALUE_LIMIT: usize = 256;
/// Most environment requests kept per session.
pub const ENV_COUNT_LIMIT: usize = 16;

/// What every served explorer shares.
#[derive(Debug, Clone)]
pub struct ExplorerSettings {
    pub scene: LoadedScene,
    /// The lesson every session starts on (its first step is `scene`).
    pub lesson: Option<crate::tui::state::LessonPlace>,
    pub max_elements: usize,
    pub idle_timeout: Option<Duration>,
    /// Ask the client's terminal for mouse reports.
    pub mouse: bool,
    /// ASCII for every session (`--ascii`), whatever the client's locale.
    pub ascii: bool,
    /// Colours allowed (`--no-color`: none).
    pub color: bool,
    /// The colours a session starts with (`--theme`).
    pub palette: crate::plot::Palette,
    /// The chart markers a session starts with (`--marker`).
    pub markers: crate::plot::MarkerSet,
    /// `--save-dir`, resolved: the only directory sessions save to.
    pub save_dir: Option<std::path::PathBuf>,
}

/// The client's terminal as its pty request described it.
#[derive(Debug, Clone, Default)]
pub struct ClientTerminal {
    pub term: String,
    pub width: u32,
    pub height: u32,
    /// Accepted environment variables ([`ACCEPTED_ENV`]), in the order sent.
    pub env: Vec<(String, String)>,
}

impl ClientTerminal {
    fn var(&self, name: &str) -> Option<&str> {
        self.env
            .iter()
            .rev()
            .find(|(n, v)| n == name && !v.is_empty())
            .map(|(_, v)| v.as_str())
    }

    /// ASCII unless the client's locale (LC_ALL, else LC_CTYPE, else LANG) is UTF-8 or
    /// unknown ([`crate::plot::locale_is_utf8`]: an SSH client that sent none is taken as
    /// UTF-8), or its terminal is `dumb`; colours unless `NO_COLOR` or `dumb`.
    pub fn look(&self) -> Look {
        let utf8 = locale_is_utf8(|name| self.var(name).map(String::from), UnsetLocale::Utf8);
        let dumb = self.term == "dumb";
        Look {
            ascii: !utf8 || dumb,
            color: !dumb && self.var("NO_COLOR").is_none(),
        }
    }
}

/// Collects a frame's bytes and hands them on at each flush, or drops them when the client
/// has [`OUTPUT_QUEUE`] frames unread (and says so in `frames_lost`). Never fails or waits: a
/// client that went away is heard of as a hangup, and the explorer must be able to leave its
/// screen anyway.
struct ChannelWriter {
    buffer: Vec<u8>,
    chunks: mpsc::Sender<Vec<u8>>,
    frames_lost: Arc<AtomicBool>,
}

impl Write for ChannelWriter {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.buffer.extend_from_slice(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        if self.buffer.is_empty() {
            return Ok(());
        }
        let chunk = std::mem::take(&mut self.buffer);
        if let Err(mpsc::error::TrySendError::Full(_)) = self.chunks.try_send(chunk) {
            self.frames_lost.store(true, Ordering::Release);
        }
        Ok(())
    }
}

/// How long the explorer's last words (leaving the alternate screen, why it closed) wait for
/// room in the client's queue before they are dropped too.
const LAST_WORDS_PATIENCE: Duration = Duration::from_secs(1);

impl Drop for ChannelWriter {
    fn drop(&mut self) {
        let mut chunk = std::mem::take(&mut self.buffer);
        if chunk.is_empty() {
            return;
        }
        let deadline = std::time::Instant::now() + LAST_WORDS_PATIENCE;
        loop {
            match self.chunks.try_send(chunk) {
                Err(mpsc::error::TrySendError::Full(back))
                    if std::time::Instant::now() < deadline =>
                {
                    chunk = back;
                    std::thread::sleep(Duration::from_millis(10));
                }
                _ => return,
            }
        }
    }
}

/// What a student reads on joining a class whose presenter has not logged in (one status
/// line at 80 columns).
const NO_PRESENTER_YET: &str =
    "no presenter yet: the keys are yours; you follow one once they log in";

/// A session's place in the class (follow mode), where the server has one.
#[derive(Default)]
struct ClassPlace {
    follow: Option<Follow>,
    /// Its id in the hub, to leave it.
    hub_id: Option<u64>,
    /// The class's newest state: a student shows it (following) or keeps it for `F`; a
    /// presenter goes on from it.
    latest: Option<Arc<crate::tui::state::Exploration>>,
    /// A presenter publishes every frame's state.
    after_frame: Option<AfterFrame>,
    /// What the session says first (a student without a presenter).
    greeting: Option<String>,
}

/// Joins the server's class, if it has one: a presenter leads and publishes every frame's
/// state, a student follows (or waits for a presenter).
fn join_class(
    shared: &Arc<Shared>,
    presenter: bool,
    feed: &Feed,
    user: Option<&str>,
) -> ClassPlace {
    let Some(hub) = &shared.hub else {
        return ClassPlace::default();
    };
    if presenter {
        // The class's state so far: the presenter goes on from there.
        let latest = hub.latest();
        let id = hub.join_presenter(feed.clone());
        let publishing = Arc::clone(shared);
        return ClassPlace {
            follow: Some(Follow::presenter(&hub.followers, false)),
            hub_id: Some(id),
            latest,
            after_frame: Some(Box::new(move |app: &App| {
                if let Some(hub) = &publishing.hub {
                    hub.publish(id, &app.exploration);
                }
            })),
            greeting: None,
        };
    }
    let user = user.unwrap_or("(no name)");
    let (id, latest, presenter_here) = hub.join(feed.clone());
    let (follow, greeting) = if presenter_here {
        (Follow::student(&hub.followers, user), None)
    } else {
        (
            Follow::student_without_presenter(&hub.followers, user),
            Some(NO_PRESENTER_YET.to_string()),
        )
    };
    ClassPlace {
        follow: Some(follow),
        hub_id: Some(id),
        latest,
        after_frame: None,
        greeting,
    }
}

/// Starts an explorer on `channel` (called on the server's runtime), presenting or following
/// when the server has presenters. Returns the feed for the client's bytes and window changes.
pub(crate) fn start(
    shared: &Arc<Shared>,
    presenter: bool,
    slot: SessionSlot,
    handle: Handle,
    channel: ChannelId,
    (client, user): (&ClientTerminal, Option<&str>),
) -> Result<Feed, ServeError> {
    let settings = &shared.explorer;
    let (feed, events) = remote::events();
    let ClassPlace {
        follow,
        hub_id,
        latest,
        after_frame,
        greeting,
    } = join_class(shared, presenter, &feed, user);
    // Nothing is written on the server but under --save-dir: otherwise `s` shows the scene's
    // TOML to copy.
    let save_policy = match &settings.save_dir {
        Some(dir) => SavePolicy::Within(dir.clone()),
        None => SavePolicy::ShowText,
    };
    let options = Options {
        show_timings: true,
        mouse: settings.mouse,
        save_policy,
        save_directory: settings.save_dir.clone(),
        max_elements: Some(settings.max_elements),
        follow,
        owner: user.map(str::to_string),
        palette: settings.palette,
        markers: settings.markers,
        lesson: settings.lesson.clone(),
        greeting,
        ..Options::new(Look {
            ascii: client.look().ascii || settings.ascii,
            color: client.look().color && settings.color,
        })
    };
    let mut app = App::new(settings.scene.clone(), options)?;
    if let Some(exploration) = latest {
        update(&mut app, Msg::Follow(exploration));
    }
    let explorer_id = shared.next_explorer.fetch_add(1, Ordering::Relaxed);
    lock(&shared.explorers).push((explorer_id, feed.clone()));
    let (chunks, mut outbox) = mpsc::channel::<Vec<u8>>(OUTPUT_QUEUE);
    let frames_lost = Arc::new(AtomicBool::new(false));
    let (lost, catching_up) = (Arc::clone(&frames_lost), feed.clone());
    tokio::spawn(async move {
        // Held until the explorer, its workers and this output are gone.
        let _slot = slot;
        while let Some(chunk) = outbox.recv().await {
            if handle.data(channel, chunk).await.is_err() {
                return;
            }
            // The client reads again after frames were dropped: send it a whole one.
            if outbox.is_empty() && lost.load(Ordering::Acquire) {
                catching_up.redraw();
            }
        }
        // The explorer ended: so does the channel, and with it the client's `ssh`.
        let _ = handle.exit_status_request(channel, 0).await;
        let _ = handle.eof(channel).await;
        let _ = handle.close(channel).await;
    });
    let writer = ChannelWriter {
        buffer: Vec::new(),
        chunks,
        frames_lost: Arc::clone(&frames_lost),
    };
    let size = (client.width, client.height);
    let logging = Arc::clone(shared);
    let remote_options = RemoteOptions {
        work_not_saved: Some(Box::new(move |note: String| logging.log(&note))),
        idle_timeout: settings.idle_timeout,
        after_frame,
        cores: Some(shared.cores.session()),
        frames_lost: Some(frames_lost),
    };
    let leaving = Arc::clone(shared);
    std::thread::Builder::new()
        .name("session".into())
        .spawn(move || {
            let _ = remote::run_remote(app, writer, size, events, remote_options);
            if let (Some(hub), Some(id)) = (&leaving.hub, hub_id) {
                hub.leave(id);
            }
            lock(&leaving.explorers).retain(|(id, _)| *id != explorer_id);
            // The session's memory is free now (its state, its workers' results): back to the
            // system, not kept in the allocator's arenas.
            crate::memory::give_back_freed_memory();
            // Dropping the writer here ends the output task, which closes the channel.
        })
        .map_err(|e| ServeError::Start(format!("cannot start a session thread: {e}")))?;
    Ok(feed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn client(term: &str, env: &[(&str, &str)]) -> ClientTerminal {
        ClientTerminal {
            term: term.into(),
            width: 80,
            height: 24,
            env: env
                .iter()
                .map(|(n, v)| (n.to_string(), v.to_string()))
                .collect(),
        }
    }

    #[test]
    fn the_look_follows_locale_term_and_no_color() {
        let unicode = Look {
            ascii: false,
            color: true,
        };
        assert_eq!(client("xterm", &[]).look(), unicode);
        assert_eq!(client("xterm", &[("LANG", "en_GB.UTF-8")]).look(), unicode);
        assert!(client("xterm", &[("LANG", "C")]).look().ascii);
        // LC_ALL wins over LANG.
        assert!(
            client("xterm", &[("LANG", "de_DE.utf8"), ("LC_ALL", "POSIX")])
                .look()
                .ascii
        );
        assert!(!client("xterm", &[("NO_COLOR", "1")]).look().color);
        assert!(client("xterm", &[("NO_COLOR", "")]).look().color);
        let dumb = client("dumb", &[]).look();
        assert!(dumb.ascii && !dumb.color);
    }
}
