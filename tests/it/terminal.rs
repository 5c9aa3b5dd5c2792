//! The explorer in a real pseudo-terminal (issue 6): whatever ends it — `q`, Ctrl-C typed,
//! SIGINT, SIGTERM, SIGHUP or a panic on the main thread — the terminal comes back out of the
//! alternate screen and raw mode, and the exit status says what happened. A panic in a study
//! worker leaves the explorer running with the failure shown in its panel.
//!
//! Each test starts the real binary on a pty of its own ([`PtyProcess`]: the session leader, so
//! crossterm talks to that pty and nothing else), reads everything it writes, and after it
//! exits reads the pty's line discipline back: canonical mode and echo must be on again.

#![cfg(unix)]

use std::os::unix::process::ExitStatusExt;
use std::time::Duration;

use nix::sys::signal::Signal;
use nix::sys::termios::LocalFlags;

use crate::harness::cpu;
use crate::harness::pty::{ENTER_ALTERNATE, LEAVE_ALTERNATE, PtyProcess};
use crate::harness::scenes;
use crate::harness::screen::{find, sgr};
use crate::harness::wait::{eventually, eventually_or, until};

/// The pty's size: (columns, rows).
const SIZE: (u16, u16) = (100, 30);

/// The explorer on the default scene, on a 100×30 pty.
fn start(env: &[(&str, &str)]) -> PtyProcess {
    PtyProcess::start(&[], env, SIZE)
}

/// `beamfric ARGS` on a 100×30 pty.
fn start_with(args: &[&str], env: &[(&str, &str)]) -> PtyProcess {
    PtyProcess::start(args, env, SIZE)
}

#[test]
fn quitting_by_key_restores_the_terminal_and_exits_zero() {
    // `q`, and Ctrl-C, which in raw mode arrives as a key, not as SIGINT.
    for key in [&b"q"[..], b"\x03"] {
        let mut explorer = start(&[]);
        explorer.wait_for("Parameters");
        explorer.type_bytes(key);
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(0), "{key:?}");
    }
}

#[test]
fn signals_restore_the_terminal_and_exit_with_128_plus_the_signal() {
    for (signal, code) in [
        (Signal::SIGINT, 130),
        (Signal::SIGTERM, 143),
        (Signal::SIGHUP, 129),
    ] {
        let mut explorer = start(&[]);
        explorer.wait_for("Parameters");
        explorer.signal(signal);
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(code), "{signal}: {status:?}");
        assert_eq!(status.signal(), None, "{signal} was handled, not fatal");
    }
}

#[test]
fn a_panic_restores_the_terminal_first_then_reports() {
    let mut explorer = start(&[(beamfric::tui::INJECT_PANIC, "main")]);
    explorer.wait_for("Parameters");
    let (status, after) = explorer.finish();
    assert_eq!(status.code(), Some(101), "{status:?}");
    // The report comes after the restoration, on the normal screen where it stays readable.
    assert!(after.contains("injected panic"), "{after:?}");
}

#[test]
fn a_panic_in_a_study_is_shown_and_the_explorer_goes_on() {
    let mut explorer = start(&[(beamfric::tui::INJECT_PANIC, "worker")]);
    explorer.wait_for("internal error");
    // Still alive and answering keys.
    explorer.type_bytes(b"?");
    explorer.wait_for("Keys");
    // Any key closes the help; then quit.
    explorer.type_bytes(b"?q");
    let (status, after) = explorer.finish();
    assert_eq!(status.code(), Some(0));
    assert!(!after.contains("panicked"), "{after:?}");
}

#[test]
fn unsaved_changes_make_q_ask_and_esc_in_the_save_prompt_goes_back() {
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    // An edit: the load one step up.
    explorer.type_bytes(b"l");
    explorer.wait_for_screen("[modified]");
    explorer.type_bytes(b"q");
    explorer.wait_for_screen("quit and lose them?");
    // No: back to the explorer with the edit.
    explorer.type_bytes(b"n");
    explorer.wait_for_screen("kept the unsaved changes");
    // Esc in the save prompt, then Esc again in normal mode: still running.
    explorer.type_bytes(b"s");
    explorer.wait_for_screen("save the scene to");
    explorer.type_bytes(b"\x1b");
    explorer.wait_for_screen("not saved");
    // Still running: a key typed after the Esc is answered (had the Esc quit, it would not be).
    explorer.type_bytes(b"x");
    eventually("x is answered, or the explorer has ended", || {
        !explorer.is_running() || explorer.screen().contains("no command on 'x'")
    });
    assert!(explorer.is_running(), "Esc quit");
    // Then quit for real: q, y.
    explorer.type_bytes(b"qy");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

// ---- Issue 11: never blocks, never orphans itself, quits at once. ----

/// The crowded scene of the harness, written to a file: its `dual` solve takes seconds.
fn slow_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("slow.toml");
    std::fs::write(&path, scenes::crowded_scene_text()).unwrap();
    path
}

#[test]
fn a_closed_terminal_ends_the_explorer() {
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    explorer.hang_up();
    let status = explorer.exit();
    // Ended by its own hand (SIGHUP handled, or end of input), not killed.
    assert_eq!(status.signal(), None, "{status:?}");
    assert_eq!(status.code(), Some(129), "{status:?}");
}

#[test]
fn a_paste_of_ten_thousand_keys_is_read_to_the_end() {
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    // Selection moves, arrows and Tab (none changes the scene), then q: 10 000 bytes.
    let mut keys = Vec::new();
    while keys.len() < 9_990 {
        keys.extend_from_slice(b"jk\x1b[A\x1b[B\t");
    }
    keys.truncate(9_990);
    // End on whole keys.
    while keys.last() == Some(&0x1b) || keys.ends_with(b"\x1b[") {
        keys.pop();
    }
    keys.extend(std::iter::repeat_n(b'j', 9_999 - keys.len()));
    keys.push(b'q');
    assert_eq!(keys.len(), 10_000);
    explorer.type_bytes(&keys);
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0), "{status:?}");
}

/// Quitting during a solve of seconds does not wait for it: the explorer is gone before its
/// solve thread has worked one more second of CPU (the whole solve takes several), a bound in
/// CPU time, not on the clock, so a busy machine cannot make it pass or fail.
#[test]
fn quitting_or_sigterm_during_a_long_solve_does_not_wait_for_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    for (how, code) in [("q", 0), ("SIGTERM", 143)] {
        let mut explorer = start_with(&[scene.to_str().unwrap()], &[]);
        explorer.wait_for_screen("solving n = 1000 with dual");
        // The frame is up while the solve runs: the UI thread does not wait for it.
        assert!(explorer.screen().contains("Parameters"));
        let pid = explorer.pid().as_raw() as u32;
        let (solver, worked) = until(
            &format!("{how}: the solve works for 200 ms of CPU"),
            || {
                cpu::threads_named_in(pid, "solver")
                    .into_iter()
                    .find_map(|tid| {
                        let worked = cpu::thread_time_in(pid, tid)?;
                        (worked >= Duration::from_millis(200)).then_some((tid, worked))
                    })
            },
            || format!("solver threads: {:?}", cpu::threads_named_in(pid, "solver")),
        );
        if how == "q" {
            explorer.type_bytes(b"q");
        } else {
            explorer.signal(Signal::SIGTERM);
        }
        // The solve thread is gone (the process has ended) before it worked a second more.
        eventually(
            &format!("{how}: the explorer ends"),
            || match cpu::thread_time_in(pid, solver) {
                None => true,
                Some(now) => {
                    assert!(
                        now < worked + Duration::from_secs(1),
                        "{how}: the explorer waited for its solve ({now:?} of CPU)"
                    );
                    false
                }
            },
        );
        let status = explorer.exit();
        assert!(
            explorer.last_frame().contains("solving"),
            "{how}: the solve had finished"
        );
        let (status_again, _) = explorer.finish();
        assert_eq!(status.code(), Some(code), "{how}: {status:?}");
        assert_eq!(status_again.code(), Some(code));
    }
}

#[test]
fn ctrl_z_and_sigtstp_suspend_and_sigcont_resumes_with_a_redraw() {
    use nix::sys::wait::{WaitPidFlag, WaitStatus, waitpid};
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    let pid = explorer.pid();
    for how in ["Ctrl-Z", "SIGTSTP"] {
        let mark = explorer.written();
        if how == "Ctrl-Z" {
            explorer.type_bytes(b"\x1a");
        } else {
            explorer.signal(Signal::SIGTSTP);
        }
        match waitpid(pid, Some(WaitPidFlag::WUNTRACED)).unwrap() {
            WaitStatus::Stopped(_, _) => {}
            other => panic!("{how}: not stopped: {other:?}"),
        }
        // While stopped, the terminal is the shell's: line mode (set before it stopped, so
        // no wait), and the normal screen (once the reader has caught up with the output).
        assert!(
            explorer
                .local_flags()
                .contains(LocalFlags::ICANON | LocalFlags::ECHO),
            "{how}: raw mode left on while stopped"
        );
        eventually_or(
            &format!("{how}: the alternate screen is left while stopped"),
            || explorer.text_since(mark).contains(LEAVE_ALTERNATE),
            || format!("{:?}", explorer.text_since(mark)),
        );
        explorer.signal(Signal::SIGCONT);
        // Back: raw mode, the alternate screen, and a full frame.
        eventually_or(
            &format!("{how}: resumed"),
            || {
                let since = explorer.text_since(mark);
                let back = since
                    .rfind(ENTER_ALTERNATE)
                    .is_some_and(|at| since[at..].contains("Parameters"));
                back && !explorer.local_flags().contains(LocalFlags::ICANON)
            },
            || format!("{:?}", explorer.text_since(mark)),
        );
    }
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn a_bracketed_paste_is_never_run_as_commands() {
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    // A paste of commands in normal mode: noted, not run.
    explorer.type_bytes(b"\x1b[200~dq\rq\x1b[201~");
    explorer.wait_for_screen("a paste is typed only into a prompt");
    assert!(explorer.is_running(), "the paste quit");
    assert!(!explorer.screen().contains("[modified]"));
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn a_paste_over_the_limit_is_dropped_whole_and_never_typed() {
    // Issue 22: past 64 KiB the rest of a paste was decoded as keys: its `q` quit the
    // explorer, its `a`s added obstacles.
    let mut explorer = start(&[]);
    explorer.wait_for_screen("Parameters");
    let mut paste = b"\x1b[200~".to_vec();
    paste.extend(b"qaaa\r".iter().copied().cycle().take(200 * 1024));
    paste.extend(b"\x1b[201~");
    explorer.type_bytes(&paste);
    explorer.wait_for_screen("paste of 200 KiB dropped");
    assert!(explorer.is_running(), "the paste quit");
    let screen = explorer.screen();
    assert!(!screen.contains("[modified]"), "{screen}");
    assert!(screen.contains("1 obstacle "), "{screen}");
    // Keys after it are keys again: q quits.
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

/// The screen as cells: `cells[row][column]` is what that cell shows, and whether it is in
/// reverse video (the selected row without colours).
fn cells(explorer: &PtyProcess) -> Vec<Vec<(String, bool)>> {
    let parser = explorer.terminal();
    let screen = parser.screen();
    (0..SIZE.1)
        .map(|row| {
            (0..SIZE.0)
                .map(|column| {
                    screen
                        .cell(row, column)
                        .map_or((" ".into(), false), |cell| {
                            (cell.contents().to_string(), cell.inverse())
                        })
                })
                .collect()
        })
        .collect()
}

/// The text of one row of cells.
fn row_text(row: &[(String, bool)]) -> String {
    row.iter()
        .map(|(c, _)| if c.is_empty() { " " } else { c.as_str() })
        .collect()
}

/// The cell (column, row) where `needle` starts, the first from the top.
fn cell_of(cells: &[Vec<(String, bool)>], needle: &str) -> Option<(u16, u16)> {
    let rows: Vec<String> = cells.iter().map(|row| row_text(row)).collect();
    find(&rows, needle)
}

/// The number after `label` on its row, e.g. `2.15e11` after `modulus E`.
fn value_after(cells: &[Vec<(String, bool)>], label: &str) -> Option<f64> {
    let (x, y) = cell_of(cells, label)?;
    let text = row_text(&cells[y as usize]);
    let rest: String = text
        .chars()
        .skip(x as usize + label.chars().count())
        .collect();
    rest.split_whitespace().next()?.parse().ok()
}

/// Waits until `condition` holds for the screen's cells.
fn wait_until(
    explorer: &PtyProcess,
    what: &str,
    condition: impl Fn(&[Vec<(String, bool)>]) -> bool,
) {
    eventually_or(
        what,
        || condition(&cells(explorer)),
        || format!("the screen:\n{}", explorer.screen()),
    );
}

#[test]
fn mouse_clicks_the_wheel_and_an_obstacle_drag_change_the_state() {
    let mut explorer = start(&[("NO_COLOR", "1")]);
    explorer.wait_for_screen("Parameters");
    explorer.wait_for_screen("slides");
    {
        // The explorer asked for presses, drags and releases, SGR-encoded.
        let parser = explorer.terminal();
        assert_eq!(
            parser.screen().mouse_protocol_mode(),
            vt100::MouseProtocolMode::ButtonMotion
        );
        assert_eq!(
            parser.screen().mouse_protocol_encoding(),
            vt100::MouseProtocolEncoding::Sgr
        );
    }
    // A click on the "modulus E" row selects it (drawn in reverse video).
    let screen = cells(&explorer);
    let (x, y) = cell_of(&screen, "modulus E").expect("the row is drawn");
    assert!(!screen[y as usize][x as usize].1, "not selected yet");
    let young = value_after(&screen, "modulus E").unwrap();
    explorer.type_bytes(&[sgr(0, (x + 2, y), true), sgr(0, (x + 2, y), false)].concat());
    wait_until(&explorer, "the row selected", |cells| {
        cells[y as usize][x as usize].1
    });
    // The wheel over the parameters steps the selected value: one fine step, ×10^0.1.
    explorer.type_bytes(&sgr(64, (x + 2, y + 1), true));
    wait_until(&explorer, "the modulus stepped up", |cells| {
        value_after(cells, "modulus E").is_some_and(|v| (v / young - 10f64.powf(0.1)).abs() < 0.01)
    });
    explorer.type_bytes(&sgr(65, (x + 2, y + 1), true));
    wait_until(&explorer, "the modulus stepped back", |cells| {
        value_after(cells, "modulus E").is_some_and(|v| (v / young - 1.0).abs() < 0.01)
    });
    // Drag the sliding obstacle's marker (↕, on the deflection chart) ten columns left, once
    // the chart of the last step is drawn (under load it can still be on its way: the marker
    // was not there yet once in a CI run beside other work).
    let marker = |screen: &[Vec<(String, bool)>]| {
        screen
            .iter()
            .enumerate()
            .take(SIZE.1 as usize - 8)
            .find_map(|(y, row)| {
                let column = row.iter().position(|(c, _)| c == "↕")?;
                Some((column as u16, y as u16))
            })
    };
    wait_until(&explorer, "the marker is drawn", |cells| {
        marker(cells).is_some()
    });
    let screen = cells(&explorer);
    let x0 = value_after(&screen, "obstacle 1 x").unwrap();
    let (mx, my) = marker(&screen).expect("the marker is drawn");
    let mut drag = sgr(0, (mx, my), true);
    for dx in 1..=10 {
        drag.extend(sgr(32, (mx - dx, my), true));
    }
    drag.extend(sgr(0, (mx - 10, my), false));
    explorer.type_bytes(&drag);
    wait_until(&explorer, "the obstacle moved left", |cells| {
        value_after(cells, "obstacle 1 x").is_some_and(|x| x < x0 - 0.05)
    });
    // ... and its marker is drawn where the pointer let go, once the new solution is in.
    wait_until(&explorer, "the marker redrawn", |cells| {
        cells[..SIZE.1 as usize - 8].iter().any(|row| {
            row.get(mx as usize - 10)
                .is_some_and(|(c, _)| "↕●↻✱".contains(c.as_str()) && !c.is_empty())
        })
    });
    explorer.type_bytes(b"u");
    wait_until(&explorer, "the drag undone", |cells| {
        value_after(cells, "obstacle 1 x") == Some(x0)
    });
    explorer.type_bytes(b"q");
    explorer.type_bytes(b"y");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
    // The mouse is given back to the terminal.
    let text = explorer.text();
    let on = text.rfind("\x1b[?1000h").expect("asked for the mouse");
    assert!(
        text.rfind("\x1b[?1000l") > Some(on),
        "never gave the mouse back"
    );
}

#[test]
fn no_mouse_leaves_the_mouse_to_the_terminal() {
    let mut explorer = start_with(&["--no-mouse"], &[("NO_COLOR", "1")]);
    explorer.wait_for_screen("Parameters");
    let screen = cells(&explorer);
    let (x, y) = cell_of(&screen, "modulus E").expect("the row is drawn");
    // A client that sends mouse reports anyway changes nothing.
    explorer.type_bytes(&[sgr(0, (x + 2, y), true), sgr(0, (x + 2, y), false)].concat());
    explorer.type_bytes(b"?");
    explorer.wait_for_screen("Keys (any key closes)");
    assert!(
        !cells(&explorer)[y as usize][x as usize].1,
        "selected by a click"
    );
    assert!(
        !explorer.text().contains("\x1b[?1000h"),
        "asked for the mouse"
    );
    explorer.type_bytes(b"q");
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

/// Issue 13: a locale that is not UTF-8 gets ASCII by itself (LC_ALL, then LC_CTYPE, then
/// LANG, as tmux decides), a UTF-8 one Unicode; `--ascii` forces ASCII; `T` cycles the theme.
#[test]
fn the_locale_decides_ascii_and_t_cycles_the_theme() {
    for (env, ascii) in [
        (&[("LC_ALL", ""), ("LC_CTYPE", ""), ("LANG", "C")][..], true),
        (&[("LC_ALL", "POSIX"), ("LANG", "en_US.UTF-8")][..], true),
        (
            &[("LC_ALL", ""), ("LC_CTYPE", ""), ("LANG", "en_US.UTF-8")][..],
            false,
        ),
    ] {
        let mut explorer = start(env);
        // Waits for the whole parameter panel: the first frame may arrive in pieces.
        if ascii {
            explorer.wait_for_screen("+ Parameters -");
            explorer.wait_for_screen("epsilon eps");
            let screen = explorer.screen();
            assert!(!screen.contains('┌'), "{env:?}\n{screen}");
        } else {
            explorer.wait_for_screen("┌ Parameters ─");
            explorer.wait_for_screen("epsilon ε");
        }
        explorer.type_bytes(b"T");
        explorer.wait_for_screen("theme light");
        explorer.type_bytes(b"q");
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(0), "{env:?}");
    }
    let mut explorer = start_with(&["--ascii"], &[("LANG", "en_US.UTF-8")]);
    explorer.wait_for_screen("+ Parameters -");
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}
