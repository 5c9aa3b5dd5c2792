//! Recording the local explorer's screen as an asciinema v2 cast (`beamfric present --record
//! FILE.cast`): a JSON header line, then one JSON array per event — `[t, "o", text]` for what
//! was written to the terminal, `[t, "m", label]` for a marker (a lesson's step), `[t, "r",
//! "WxH"]` for a new size — with `t` in seconds since the start.
//!
//! The UI thread never waits for the disk: [`Output`] hands each frame's bytes (at its flush)
//! to a recorder thread over a channel. That thread keeps the recording and writes it whole
//! to a temporary file beside FILE, renamed over it ([`FLUSH_EVERY`] after a change, and at
//! the end with fsync), so FILE is always a complete cast: a crash, even SIGKILL, loses at most
//! the last [`FLUSH_EVERY`] — longer only for a cast so large that writing it takes over a
//! fifth of that (tens of MB: `cargo bench --bench record`), when the period stretches to four
//! times the write. A recording over [`MAX_CAST_BYTES`] stops growing, with a note.

use std::io::{self, Stdout, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

use super::feed::Feed;
use super::screen::{MOUSE_OFF, MOUSE_ON};

/// At most this much of the recording is lost if the process dies.
pub const FLUSH_EVERY: Duration = Duration::from_secs(2);
/// Largest recording kept (events beyond it are dropped, and the end says so).
pub const MAX_CAST_BYTES: usize = 256 << 20;
/// The last output of every cast: attributes reset, the cursor shown.
const CAST_END: &str = "\x1b[0m\x1b[?25h";

/// What the recorder thread is told.
enum Record {
    Output(f64, Vec<u8>),
    Marker(f64, String),
    Resize(f64, u16, u16),
    /// Where to tell the user when the file cannot be written, and when it can again.
    TellFailuresTo(Feed),
    Finish,
}

/// What the UI thread holds of a recording: where to send events, and the start.
#[derive(Clone)]
pub struct RecordTap {
    sender: Sender<Record>,
    start: Instant,
}

impl RecordTap {
    fn now(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// A marker (`[t, "m", label]`): where a lesson's step begins.
    pub fn marker(&self, label: &str) {
        let _ = self
            .sender
            .send(Record::Marker(self.now(), label.to_string()));
    }

    /// The terminal has a new size.
    pub fn resize(&self, width: u16, height: u16) {
        let _ = self.sender.send(Record::Resize(self.now(), width, height));
    }
}

/// A recording under way: its thread, and the tap events go in by.
pub struct Recording {
    tap: RecordTap,
    thread: Option<JoinHandle<io::Result<Summary>>>,
}

/// How a recording ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub path: PathBuf,
    pub seconds: f64,
    pub bytes: usize,
    /// Events dropped beyond [`MAX_CAST_BYTES`].
    pub truncated: bool,
    /// The name asked for, when something else took it during the recording.
    pub moved_from: Option<PathBuf>,
}

impl Recording {
    /// Starts recording a terminal of `size` (columns, rows) to `path`, written at once with
    /// its header. A file already there is refused (a recording never replaces one).
    pub fn start(path: &Path, size: (u16, u16), title: &str) -> io::Result<Recording> {
        check_target(path)?;
        let header = header(size, title);
        let mut cast = Cast {
            path: path.to_path_buf(),
            header,
            events: Vec::new(),
            utf8_tail: Vec::new(),
            truncated: false,
            last_time: 0.0,
            written: None,
            moved_from: None,
            told: None,
            failing: false,
        };
        cast.persist(false)?;
        let (sender, receiver) = channel();
        let start = Instant::now();
        let thread = std::thread::Builder::new()
            .name("record".into())
            .spawn(move || cast.run(&receiver))?;
        Ok(Recording {
            tap: RecordTap { sender, start },
            thread: Some(thread),
        })
    }

    /// From now on, a write of the recording that fails (a full disk, say) is told to the
    /// explorer of `feed` at once, as its message, and so is the next one that succeeds.
    pub fn tell_failures_to(&self, feed: Feed) {
        let _ = self.tap.sender.send(Record::TellFailuresTo(feed));
    }

    /// The tap for the UI thread.
    pub fn tap(&self) -> RecordTap {
        self.tap.clone()
    }

    /// Ends the recording: written whole, synced, and renamed over the file.
    pub fn finish(mut self) -> io::Result<Summary> {
        let _ = self.tap.sender.send(Record::Finish);
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            _ => Err(io::Error::other("the recorder thread failed")),
        }
    }
}

/// Can a recording be made at `path`? Not over anything there (a recording never replaces a
/// file), and only in a folder that exists and can be written to; the errors say which.
pub fn check_target(path: &Path) -> io::Result<()> {
    if std::fs::symlink_metadata(path).is_ok() {
        return Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            "it exists already (a recording never replaces a file: choose another name)",
        ));
    }
    let folder = folder_of(path);
    match std::fs::metadata(folder) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => {
            return Err(io::Error::other(format!(
                "{} is not a folder",
                folder.display()
            )));
        }
        Err(e) => {
            return Err(io::Error::new(
                e.kind(),
                format!(
                    "its folder {} cannot be used: {}",
                    folder.display(),
                    e.kind()
                ),
            ));
        }
    }
    tempfile::NamedTempFile::new_in(folder)
        .map(drop)
        .map_err(|e| {
            io::Error::new(
                e.kind(),
                format!("cannot write in {}: {}", folder.display(), e.kind()),
            )
        })
}

/// The folder a file goes in (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// The cast's header line: version 2, the size, when, and the terminal's type.
fn header(size: (u16, u16), title: &str) -> String {
    let timestamp = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let term = std::env::var("TERM").unwrap_or_else(|_| "xterm-256color".into());
    serde_json::json!({
        "version": 2,
        "width": size.0,
        "height": size.1,
        "timestamp": timestamp,
        "title": title,
        "env": { "TERM": term },
    })
    .to_string()
}

/// The recording, on the recorder thread.
struct Cast {
    path: PathBuf,
    header: String,
    /// Event lines, each ending in a newline.
    events: Vec<u8>,
    /// The start of a UTF-8 character cut at the end of the last output.
    utf8_tail: Vec<u8>,
    truncated: bool,
    last_time: f64,
    /// The file last written (device and inode): a different one at the path later is not
    /// ours, and is never written over.
    written: Option<Identity>,
    /// Where the recording was meant to go, when something else took that name meanwhile.
    moved_from: Option<PathBuf>,
    /// Who is told when a write fails ([`Recording::tell_failures_to`]).
    told: Option<Feed>,
    /// The last write failed.
    failing: bool,
}

impl Cast {
    fn run(mut self, receiver: &Receiver<Record>) -> io::Result<Summary> {
        let mut changed_at: Option<Instant> = None;
        // A long recording takes longer to write: the period stretches so that writing never
        // takes more than a fifth of this thread's time.
        let mut period = FLUSH_EVERY;
        loop {
            let wait = changed_at.map(|at| period.saturating_sub(at.elapsed()));
            let received = match wait {
                Some(wait) => receiver.recv_timeout(wait),
                None => receiver.recv().map_err(|_| RecvTimeoutError::Disconnected),
            };
            match received {
                Ok(Record::Finish) | Err(RecvTimeoutError::Disconnected) => {
                    // A replay ends with the viewer's terminal as it was: plain text, the cursor
                    // shown (the explorer hid it; its restoring goes to the terminal only).
                    self.add(Record::Output(self.last_time, CAST_END.as_bytes().to_vec()));
                    break;
                }
                Ok(Record::TellFailuresTo(feed)) => self.told = Some(feed),
                Ok(record) => {
                    self.add(record);
                    changed_at.get_or_insert_with(Instant::now);
                }
                Err(RecvTimeoutError::Timeout) => {}
            }
            if changed_at.is_some_and(|at| at.elapsed() >= period) {
                // A failed periodic write is tried again at the next change and at the end;
                // the user hears of the first failure, and of the write that works again.
                let started = Instant::now();
                let written = self.persist(false);
                self.tell(written);
                period = FLUSH_EVERY.max(started.elapsed() * 4);
                changed_at = None;
            }
        }
        self.persist(true)?;
        Ok(Summary {
            moved_from: self.moved_from.clone(),
            path: self.path.clone(),
            seconds: self.last_time,
            bytes: self.header.len() + 1 + self.events.len(),
            truncated: self.truncated,
        })
    }

    /// Tells the user ([`Cast::told`]) of a periodic write that failed after one that worked,
    /// or that worked after one that failed.
    fn tell(&mut self, written: io::Result<()>) {
        let text = match (&written, self.failing) {
            (Err(e), false) => format!(
                "the recording cannot be written ({}): {} keeps its last whole write; every \
                 change is tried again",
                e.kind(),
                crate::format::printable(&self.path.display().to_string())
            ),
            (Ok(()), true) => format!(
                "the recording is written again to {}",
                crate::format::printable(&self.path.display().to_string())
            ),
            _ => return,
        };
        self.failing = written.is_err();
        if let Some(feed) = &self.told {
            feed.notice(text);
        }
    }

    /// Appends one event line.
    fn add(&mut self, record: Record) {
        let time = match &record {
            Record::Output(time, _) | Record::Marker(time, _) | Record::Resize(time, ..) => *time,
            Record::Finish | Record::TellFailuresTo(_) => return,
        };
        // Times never go back.
        let time = self.last_time.max(time);
        let line = match record {
            Record::Output(_, bytes) => {
                let mut bytes = std::mem::take(&mut self.utf8_tail)
                    .into_iter()
                    .chain(bytes)
                    .collect::<Vec<u8>>();
                // Keep an incomplete character for the next output.
                let text = match std::str::from_utf8(&bytes) {
                    Ok(text) => text.to_string(),
                    Err(e) if e.error_len().is_none() => {
                        self.utf8_tail = bytes.split_off(e.valid_up_to());
                        String::from_utf8_lossy(&bytes).into_owned()
                    }
                    Err(_) => String::from_utf8_lossy(&bytes).into_owned(),
                };
                // The viewer's terminal is not asked for mouse reports on replay.
                let text = text.replace(MOUSE_ON, "").replace(MOUSE_OFF, "");
                if text.is_empty() {
                    return;
                }
                serde_json::json!([round(time), "o", text])
            }
            Record::Marker(_, label) => serde_json::json!([round(time), "m", label]),
            Record::Resize(_, width, height) => {
                serde_json::json!([round(time), "r", format!("{width}x{height}")])
            }
            Record::Finish | Record::TellFailuresTo(_) => return,
        };
        let line = line.to_string();
        if self.events.len() + line.len() + 1 > MAX_CAST_BYTES {
            self.truncated = true;
            return;
        }
        self.last_time = time;
        self.events.extend_from_slice(line.as_bytes());
        self.events.push(b'\n');
    }

    /// Writes the whole cast to a temporary file beside the target and renames it over it
    /// (synced first when `sync`).
    fn persist(&mut self, sync: bool) -> io::Result<()> {
        self.keep_off_others();
        let name = self
            .path
            .file_name()
            .map_or_else(|| "cast".into(), |n| n.to_string_lossy().into_owned());
        // A write cut short (the process killed) leaves a `.NAME.…part` beside it, never a
        // broken cast.
        let mut file = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".part")
            .tempfile_in(folder_of(&self.path))?;
        file.write_all(self.header.as_bytes())?;
        file.write_all(b"\n")?;
        file.write_all(&self.events)?;
        file.flush()?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            file.as_file()
                .set_permissions(std::fs::Permissions::from_mode(0o644))?;
        }
        if sync {
            file.as_file().sync_all()?;
        }
        file.persist(&self.path).map_err(|e| e.error)?;
        self.written = identity(&self.path);
        Ok(())
    }

    /// If something other than the last cast written now sits at the path (a file put there
    /// meanwhile, a folder), the recording goes on under the next free name (`NAME-2.cast`…).
    fn keep_off_others(&mut self) {
        let ours = |cast: &Cast| match identity(&cast.path) {
            None => std::fs::symlink_metadata(&cast.path).is_err(),
            found => found == cast.written,
        };
        if ours(self) {
            return;
        }
        let original = self
            .moved_from
            .get_or_insert_with(|| self.path.clone())
            .clone();
        let stem = original
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let extension = original
            .extension()
            .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
        for number in 2.. {
            let candidate = original.with_file_name(format!("{stem}-{number}{extension}"));
            if std::fs::symlink_metadata(&candidate).is_err() {
                self.path = candidate;
                self.written = None;
                return;
            }
        }
    }
}

/// What tells the file at `path` from another put there later (not following a link): its
/// device, inode, size and change time — an inode number freed and reused still differs in
/// the rest.
fn identity(path: &Path) -> Option<Identity> {
    let meta = std::fs::symlink_metadata(path).ok()?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some([
            meta.dev(),
            meta.ino(),
            meta.len(),
            meta.ctime() as u64,
            meta.ctime_nsec() as u64,
        ])
    }
    #[cfg(not(unix))]
    {
        Some([meta.len(), 0, 0, 0, 0])
    }
}

type Identity = [u64; 5];

/// Times in microseconds, as asciinema writes them.
fn round(time: f64) -> f64 {
    (time * 1e6).round() / 1e6
}

/// The local terminal's output: standard output, and a recording of it when one is made
/// (each flush — a frame — is one output event).
pub struct Output {
    /// Standard output, or nothing (`Output::sink`: a benchmark of the recording alone).
    out: Option<Stdout>,
    tap: Option<RecordTap>,
    pending: Vec<u8>,
}

impl Output {
    pub fn new(tap: Option<RecordTap>) -> Output {
        Output {
            out: Some(io::stdout()),
            tap,
            pending: Vec::new(),
        }
    }

    /// An output that only records (benchmarks).
    pub fn sink(tap: Option<RecordTap>) -> Output {
        Output {
            out: None,
            tap,
            pending: Vec::new(),
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let written = match &mut self.out {
            Some(out) => out.write(buf)?,
            None => buf.len(),
        };
        if self.tap.is_some() {
            self.pending.extend_from_slice(&buf[..written]);
        }
        Ok(written)
    }

    fn flush(&mut self) -> io::Result<()> {
        let flushed = self.out.as_mut().map_or(Ok(()), Write::flush);
        if let Some(tap) = &self.tap
            && !self.pending.is_empty()
        {
            let bytes = std::mem::take(&mut self.pending);
            let _ = tap.sender.send(Record::Output(tap.now(), bytes));
        }
        flushed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(path: &Path) -> Vec<serde_json::Value> {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    }

    #[test]
    fn a_recording_is_a_cast_from_the_start_with_every_event_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("class.cast");
        let recording = Recording::start(&path, (80, 24), "class").unwrap();
        // The header is there at once.
        let header = &lines(&path)[0];
        assert_eq!(header["version"], 2);
        assert_eq!(header["width"], 80);
        assert_eq!(header["height"], 24);
        let tap = recording.tap();
        let mut output = Output::sink(Some(tap.clone()));
        // A character cut between two frames arrives whole.
        let text = "ε = 1e-2 ⠤".as_bytes();
        output.pending.extend_from_slice(MOUSE_ON.as_bytes());
        output.pending.extend_from_slice(&text[..1]);
        output.flush().unwrap();
        output.pending.extend_from_slice(&text[1..]);
        output.flush().unwrap();
        tap.marker("step 2/7: ε");
        tap.resize(100, 30);
        let summary = recording.finish().unwrap();
        assert!(!summary.truncated);
        let all = lines(&path);
        assert_eq!(all.len(), 5, "{all:?}");
        assert_eq!(all[1][1], "o");
        assert_eq!(all[1][2], "ε = 1e-2 ⠤");
        assert_eq!(all[2][1], "m");
        assert_eq!(all[2][2], "step 2/7: ε");
        assert_eq!(all[3][2], "100x30");
        assert_eq!(all[4][1], "o");
        assert_eq!(all[4][2], CAST_END);
        let times: Vec<f64> = all[1..].iter().map(|e| e[0].as_f64().unwrap()).collect();
        assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
        // A file put at its name meanwhile is never written over: it goes on next to it.
        let replaced = dir.path().join("replaced.cast");
        let recording = Recording::start(&replaced, (80, 24), "class").unwrap();
        std::fs::remove_file(&replaced).unwrap();
        std::fs::write(&replaced, "precious notes").unwrap();
        recording.tap().marker("after");
        let summary = recording.finish().unwrap();
        assert_eq!(
            std::fs::read_to_string(&replaced).unwrap(),
            "precious notes"
        );
        assert_eq!(summary.path, dir.path().join("replaced-2.cast"));
        assert_eq!(summary.moved_from.as_deref(), Some(replaced.as_path()));
        // The header, the marker and the closing output.
        assert_eq!(lines(&summary.path).len(), 3);
        // No part file is left behind.
        let parts = std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .ends_with(".part")
            })
            .count();
        assert_eq!(parts, 0);
        // A file there already is never replaced.
        let again = Recording::start(&path, (80, 24), "class");
        assert_eq!(
            again.err().map(|e| e.kind()),
            Some(io::ErrorKind::AlreadyExists)
        );
    }
}
