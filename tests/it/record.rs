//! `present --record FILE.cast` (issue 23): the lecturer's screen as an asciinema v2 cast,
//! parsed back — the header, every event line, times that never go back, a marker per lesson
//! step, and the last frame equal to the lecturer's screen — and a presenter killed with
//! SIGKILL leaves a cast that still parses; a recording that cannot be written is told to the
//! lecturer at once and makes the status 2.

#![cfg(unix)]

use std::path::Path;

use nix::sys::signal::Signal;

use crate::harness::lecture::{past_the_join_screen, present};
use crate::harness::pty::PtyProcess;
use crate::harness::wait::eventually;

/// A cast parsed: the header, and each event as (time, kind, data).
struct Cast {
    header: serde_json::Value,
    events: Vec<(f64, String, String)>,
}

/// Parses `path` as asciinema v2: a header object, then one `[time, kind, data]` per line.
fn parse(path: &Path) -> Result<Cast, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let mut lines = text.lines();
    let header: serde_json::Value =
        serde_json::from_str(lines.next().ok_or("empty")?).map_err(|e| e.to_string())?;
    let mut events = Vec::new();
    for line in lines {
        let event: (f64, String, String) =
            serde_json::from_str(line).map_err(|e| format!("{e}: {line:?}"))?;
        events.push(event);
    }
    Ok(Cast { header, events })
}

/// What a player shows at the end: every output event fed to a terminal of the header's size
/// (resized where the cast says so).
fn last_screen(cast: &Cast) -> String {
    let width = cast.header["width"].as_u64().unwrap() as u16;
    let height = cast.header["height"].as_u64().unwrap() as u16;
    let mut terminal = vt100::Parser::new(height, width, 0);
    for (_, kind, data) in &cast.events {
        match kind.as_str() {
            "o" => terminal.process(data.as_bytes()),
            "r" => {
                let (w, h) = data.split_once('x').unwrap();
                terminal
                    .screen_mut()
                    .set_size(h.parse().unwrap(), w.parse().unwrap());
            }
            _ => {}
        }
    }
    terminal.screen().contents()
}

fn presenting(dir: &Path, cast: &Path) -> PtyProcess {
    let lesson = ["--lesson", "lessons/regularisation.toml"];
    let record = ["--record", cast.to_str().unwrap()];
    present(dir, &[lesson, record].concat(), (80, 24))
}

#[test]
fn a_recording_plays_back_to_the_lecturers_screen_with_a_marker_per_step() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("class.cast");
    let mut lecturer = presenting(dir.path(), &path);
    past_the_join_screen(&mut lecturer);
    lecturer.wait_for_screen("step 1/7:");
    lecturer.type_bytes(b" ");
    lecturer.wait_for_screen("step 2/7:");
    lecturer.type_bytes(b" ");
    lecturer.wait_for_screen("step 3/7:");
    lecturer.wait_for_screen("error 8.5e-5");
    // Stop 59's lecture pass: a new size was recorded after the frame drawn at it, so a
    // player drew that frame at the old size, then resized: the last screen was garbled.
    lecturer.resize((100, 30));
    lecturer.wait_for_screen("m:method w:warnings");
    lecturer.type_bytes(b"q");
    assert_eq!(lecturer.exit().code(), Some(0));
    assert!(
        lecturer.text().contains("recording saved: "),
        "{}",
        lecturer.text()
    );

    let cast = parse(&path).unwrap();
    assert_eq!(cast.header["version"], 2);
    let resized = cast.events.iter().position(|e| e.1 == "r");
    assert_eq!(resized.map(|i| cast.events[i].2.as_str()), Some("100x30"));
    let resized = resized.unwrap();
    assert!(
        cast.events[..resized]
            .iter()
            .all(|e| !e.2.contains("m:method w:warnings")),
        "a frame at the new size came before the new size"
    );
    // A replay ends with the cursor shown and plain attributes, as the lecturer's did.
    assert!(cast.events.last().unwrap().2.ends_with("\x1b[0m\x1b[?25h"));
    assert_eq!(cast.header["width"], 80);
    assert_eq!(cast.header["height"], 24);
    let times: Vec<f64> = cast.events.iter().map(|e| e.0).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert!(times.iter().all(|t| t.is_finite() && *t >= 0.0));
    let markers: Vec<&str> = cast
        .events
        .iter()
        .filter(|e| e.1 == "m")
        .map(|e| e.2.as_str())
        .collect();
    assert_eq!(markers.len(), 3, "{markers:?}");
    for (i, marker) in markers.iter().enumerate() {
        assert!(
            marker.starts_with(&format!("step {}/7: ", i + 1)),
            "{marker}"
        );
    }
    // The last frame a player shows is the lecturer's last screen.
    assert_eq!(last_screen(&cast), lecturer.last_frame());
    // A second recording to the same file, or into a folder that does not exist, is refused
    // before anything starts: no host key is written, no port opened.
    let fresh = dir.path().join("fresh");
    std::fs::create_dir(&fresh).unwrap();
    for (target, words) in [
        (path.clone(), "exists already"),
        (dir.path().join("nowhere/class.cast"), "cannot be used"),
    ] {
        let mut again = presenting(&fresh, &target);
        let status = again.exit();
        assert_eq!(status.code(), Some(2));
        let text = again.text();
        assert!(text.contains(words), "{text}");
        assert!(!text.contains("listening on"), "{text}");
        assert!(!fresh.join("host_key").exists());
    }
}

#[test]
fn a_presenter_killed_with_sigkill_leaves_a_cast_that_parses() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("killed.cast");
    let mut lecturer = presenting(dir.path(), &path);
    past_the_join_screen(&mut lecturer);
    lecturer.wait_for_screen("step 1/7:");
    lecturer.type_bytes(b" ");
    lecturer.wait_for_screen("step 2/7:");
    // Within the flush period the step's marker is on disk.
    eventually("the cast holds step 2's marker", || {
        parse(&path).is_ok_and(|cast| {
            cast.events
                .iter()
                .any(|e| e.1 == "m" && e.2.starts_with("step 2/7"))
        })
    });
    lecturer.signal(Signal::SIGKILL);
    lecturer.exit();
    let cast = parse(&path).unwrap();
    assert_eq!(cast.header["version"], 2);
    assert!(cast.events.iter().any(|e| e.1 == "o"));
    assert!(last_screen(&cast).contains("step 2/7:"));
}

#[test]
fn a_recording_that_cannot_be_written_is_told_at_once_and_the_status_says_so() {
    // Stop 58's hostile pass: on a full disk the periodic writes failed in silence for the
    // whole class, and `present` still ended with status 0. A folder taken away makes every
    // write fail, as root too.
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("recordings");
    std::fs::create_dir(&folder).unwrap();
    let path = folder.join("class.cast");
    let mut lecturer = presenting(dir.path(), &path);
    past_the_join_screen(&mut lecturer);
    lecturer.wait_for_screen("step 1/7:");
    std::fs::remove_dir_all(&folder).unwrap();
    lecturer.type_bytes(b" ");
    lecturer.wait_for_screen("the recording cannot be written");
    // Back, and the next change is written again, and said to be.
    std::fs::create_dir(&folder).unwrap();
    lecturer.type_bytes(b" ");
    lecturer.wait_for_screen("the recording is written again");
    eventually("the cast is back, with step 3's marker", || {
        parse(&path).is_ok_and(|cast| {
            cast.events
                .iter()
                .any(|e| e.1 == "m" && e.2.starts_with("step 3/7"))
        })
    });
    // Gone again at the end: the last write fails, and so does the command.
    std::fs::remove_dir_all(&folder).unwrap();
    lecturer.type_bytes(b"q");
    assert_eq!(lecturer.exit().code(), Some(2));
    let text = lecturer.text();
    assert!(
        text.contains("the recording could not be finished"),
        "{text}"
    );
}
