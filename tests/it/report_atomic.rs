//! `beamfric report` never leaves a mixed or half-written report (issue 12 item 4): `--force`
//! leaves exactly the new report's files, the destination is checked before anything is
//! measured (an empty name, a file, a missing parent, a read-only or full file system, someone
//! else's files), and a write failure half-way — a real full disk on a tiny tmpfs where the
//! test may mount one, or the writer's injected failure — leaves the old report as it was and
//! no temporary directory. Runs the real binary with small options (well under a second per
//! report).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::harness::process::names;

/// Options that make a report in a fraction of a second.
const SMALL: [&str; 6] = ["--to", "100", "--points", "2", "--repeat", "1"];

/// Options whose measuring would take minutes: a check that is meant to come before measuring
/// and instead came after would show as a test that hangs, not as a flaky time limit.
const HEAVY: [&str; 6] = ["--to", "1000000", "--points", "11", "--repeat", "100"];

fn report(scene: &str, out: &Path, options: &[&str], force: bool, env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_beamfric"));
    command
        .args(["report", "--scene", scene, "--out"])
        .arg(out)
        .args(options);
    if force {
        command.arg("--force");
    }
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("beamfric runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn succeeded(out: &Output) {
    assert!(out.status.success(), "{}", stderr(out));
}

/// Failed with exit status 2 and one line on stderr (no progress, nothing written).
fn refused(out: &Output) -> String {
    let message = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{message}");
    assert_eq!(message.lines().count(), 1, "{message}");
    assert!(!message.contains("wrote"), "{message}");
    message
}

/// Every file of `dir` with its bytes.
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    names(dir)
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(dir.join(&name)).unwrap();
            (name, bytes)
        })
        .collect()
}

/// A tmpfs mounted for one test, unmounted when dropped.
struct Tmpfs {
    dir: tempfile::TempDir,
}

impl Tmpfs {
    /// Mounts a tmpfs with `options`, or says why not and returns `None` (the caller skips).
    fn mount(options: &str) -> Option<Tmpfs> {
        let dir = tempfile::tempdir().unwrap();
        let result = Command::new("mount")
            .args(["-t", "tmpfs", "-o", options, "tmpfs"])
            .arg(dir.path())
            .output();
        match result {
            Ok(out) if out.status.success() => Some(Tmpfs { dir }),
            Ok(out) => {
                eprintln!(
                    "skipped: cannot mount a tmpfs ({options}): {}",
                    String::from_utf8_lossy(&out.stderr).trim()
                );
                None
            }
            Err(e) => {
                eprintln!("skipped: cannot run mount: {e}");
                None
            }
        }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    fn remount(&self, options: &str) {
        let out = Command::new("mount")
            .args(["-o", &format!("remount,{options}")])
            .arg(self.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).output();
    }
}

/// A finished Benchmark 1 report (with its ε sweep) in a directory of its own.
fn benchmark_1_report() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("old");
    succeeded(&report("benchmark-1", &out, &SMALL, false, &[]));
    assert!(out.join("epsilon-sweep.csv").exists());
    (dir, out)
}

/// Copies the files of `from` into a new directory `to`.
fn copy_report(from: &Path, to: &Path) {
    std::fs::create_dir(to).unwrap();
    for name in names(from) {
        std::fs::copy(from.join(&name), to.join(&name)).unwrap();
    }
}

#[test]
fn force_leaves_exactly_the_new_reports_files() {
    // Issue 12 item 4: Benchmark 1's epsilon-sweep.csv survived an eight-obstacles report,
    // whose report.md says the ε sweep was not computed.
    let parent = tempfile::tempdir().unwrap();
    let out = parent.path().join("X");
    succeeded(&report("benchmark-1", &out, &SMALL, false, &[]));
    assert_eq!(
        names(&out),
        [
            "epsilon-sweep.csv",
            "error-vs-time.svg",
            "mesh-sweep.csv",
            "report.md"
        ]
    );
    succeeded(&report("eight-obstacles", &out, &SMALL, true, &[]));
    assert_eq!(
        names(&out),
        ["error-vs-time.svg", "mesh-sweep.csv", "report.md"]
    );
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("Not computed"), "{md}");
    assert!(!md.contains("epsilon-sweep.csv"), "{md}");
    // No temporary directory left next to it.
    assert_eq!(names(parent.path()), ["X"]);
}

#[test]
fn an_out_that_is_a_file_is_refused_before_measuring() {
    let parent = tempfile::tempdir().unwrap();
    let file = parent.path().join("notes.txt");
    std::fs::write(&file, "mine").unwrap();
    let message = refused(&report("benchmark-1", &file, &HEAVY, true, &[]));
    assert!(
        message.contains("notes.txt is a file, not a directory"),
        "{message}"
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    assert_eq!(names(parent.path()), ["notes.txt"]);
}

#[test]
fn an_empty_out_is_refused_in_words_before_measuring() {
    // Issue 22: `--out ''` measured, then failed with "cannot put the report in place at : …".
    // HEAVY: had it measured first, this would hang instead of failing.
    let cwd = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_beamfric"))
        .current_dir(cwd.path())
        .args(["report", "--scene", "benchmark-1", "--out", ""])
        .args(HEAVY)
        .output()
        .unwrap();
    let message = refused(&out);
    assert!(
        message.contains("--out is empty: name the directory for the report"),
        "{message}"
    );
    assert!(names(cwd.path()).is_empty());
}

#[test]
fn a_missing_parent_is_refused_before_measuring() {
    let parent = tempfile::tempdir().unwrap();
    let out = parent.path().join("missing").join("X");
    let message = refused(&report("benchmark-1", &out, &HEAVY, false, &[]));
    assert!(
        message.contains("parent directory") && message.contains("No such file or directory"),
        "{message}"
    );
    assert!(names(parent.path()).is_empty());
}

#[test]
fn a_directory_with_other_files_is_never_replaced() {
    // Decision: a report replaces only a directory of report files, even with --force, so the
    // user's notes cannot be swept away with an old report.
    let (_keep, old) = benchmark_1_report();
    std::fs::write(old.join("notes.txt"), "mine").unwrap();
    let before = contents(&old);
    for force in [false, true] {
        let message = refused(&report("eight-obstacles", &old, &HEAVY, force, &[]));
        assert!(
            message.contains("not part of a report (notes.txt)")
                && message.contains("even with --force"),
            "{message}"
        );
        assert_eq!(contents(&old), before);
    }
    // Without --force, a directory of report files is refused as before.
    std::fs::remove_file(old.join("notes.txt")).unwrap();
    let message = refused(&report("eight-obstacles", &old, &HEAVY, false, &[]));
    assert!(
        message.contains("report.md exists") && message.contains("--force"),
        "{message}"
    );
}

#[test]
fn a_read_only_destination_is_refused_before_measuring() {
    let is_root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    let (_keep, old) = benchmark_1_report();
    // Root writes through permissions: a file system mounted read-only stops it.
    let (_mount, _plain, parent) = if is_root {
        let Some(tmpfs) = Tmpfs::mount("size=4m") else {
            return;
        };
        let parent = tmpfs.path().to_path_buf();
        copy_report(&old, &parent.join("X"));
        tmpfs.remount("ro");
        (Some(tmpfs), None, parent)
    } else {
        use std::os::unix::fs::PermissionsExt;
        let plain = tempfile::tempdir().unwrap();
        let parent = plain.path().to_path_buf();
        copy_report(&old, &parent.join("X"));
        for dir in [parent.join("X"), parent.clone()] {
            std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).unwrap();
        }
        (None, Some(plain), parent)
    };
    let before = contents(&parent.join("X"));
    let message = refused(&report(
        "benchmark-1",
        &parent.join("Y"),
        &HEAVY,
        false,
        &[],
    ));
    assert!(
        message.contains("cannot write the report to")
            && (message.contains("Read-only file system") || message.contains("Permission denied")),
        "{message}"
    );
    let message = refused(&report("benchmark-1", &parent.join("X"), &HEAVY, true, &[]));
    assert!(
        message.contains("Read-only file system") || message.contains("Permission denied"),
        "{message}"
    );
    assert_eq!(names(&parent), ["X"]);
    assert_eq!(contents(&parent.join("X")), before);
    if !is_root {
        use std::os::unix::fs::PermissionsExt;
        for dir in [parent.clone(), parent.join("X")] {
            std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
    }
}

#[test]
fn a_nearly_full_disk_is_refused_before_measuring() {
    let Some(tmpfs) = Tmpfs::mount("size=256k") else {
        return;
    };
    let (_keep, old) = benchmark_1_report();
    let out = tmpfs.path().join("X");
    copy_report(&old, &out);
    let before = contents(&out);
    let message = refused(&report("eight-obstacles", &out, &HEAVY, true, &[]));
    assert!(
        message.contains(&format!(
            "not enough room for a report in {}",
            tmpfs.path().display()
        )) && message.contains("KiB free")
            && message.contains("needs up to 1024 KiB"),
        "{message}"
    );
    assert_eq!(names(tmpfs.path()), ["X"]);
    assert_eq!(contents(&out), before);
}

#[test]
fn a_disk_that_fills_half_way_leaves_the_old_report_as_it_was() {
    // Issue 12 item 4: with the disk full, report.md and the CSVs of the new run ended up next
    // to the old run's SVG. Space is plentiful but the tmpfs runs out of inodes: room for the
    // old report (1 + 4), the root, the new report's directory and two of its files, so the
    // third file fails with ENOSPC.
    let Some(tmpfs) = Tmpfs::mount("size=4m,nr_inodes=9") else {
        return;
    };
    let (_keep, old) = benchmark_1_report();
    let out = tmpfs.path().join("X");
    copy_report(&old, &out);
    let before = contents(&out);
    let out_put = report("eight-obstacles", &out, &SMALL, true, &[]);
    let message = stderr(&out_put);
    assert_eq!(out_put.status.code(), Some(2), "{message}");
    assert!(
        message.contains("No space left on device")
            && message.contains(&format!("cannot write {}", out.join("").display()))
            && message.contains("is as it was"),
        "{message}"
    );
    assert_eq!(names(tmpfs.path()), ["X"]);
    assert_eq!(contents(&out), before);
    // And with no old report, nothing at all is left.
    let fresh = tmpfs.path().join("Y");
    let out_put = report("eight-obstacles", &fresh, &SMALL, true, &[]);
    assert_eq!(out_put.status.code(), Some(2), "{}", stderr(&out_put));
    assert!(stderr(&out_put).contains("No space left on device"));
    assert_eq!(names(tmpfs.path()), ["X"]);
}

#[test]
fn an_injected_write_failure_leaves_the_old_report_or_nothing() {
    // The writer's test hook, where no tmpfs can be mounted: fail on every file in turn.
    let (keep, old) = benchmark_1_report();
    let before = contents(&old);
    for after in 0..4 {
        let value = format!("after:{after}");
        let env = [(beamfric::report::INJECT_WRITE_FAILURE, value.as_str())];
        let out = report("benchmark-1", &old, &SMALL, true, &env);
        let message = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{message}");
        let file = beamfric::report::FILES[after];
        assert!(
            message.contains(&format!("cannot write {}", old.join(file).display()))
                && message.contains("injected failure")
                && message.contains("is as it was"),
            "{message}"
        );
        assert_eq!(contents(&old), before);
        assert_eq!(names(keep.path()), ["old"]);
        let fresh = keep.path().join("new");
        let out = report("benchmark-1", &fresh, &SMALL, false, &env);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("was not created"), "{}", stderr(&out));
        assert_eq!(names(keep.path()), ["old"]);
    }
}

#[test]
fn a_failed_swap_puts_the_old_report_back() {
    // The two-rename route: the old report is moved aside, the new one fails to take its
    // place, and the old one comes back.
    let (keep, old) = benchmark_1_report();
    let before = contents(&old);
    let env = [(beamfric::report::INJECT_WRITE_FAILURE, "swap")];
    let out = report("eight-obstacles", &old, &SMALL, true, &env);
    let message = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{message}");
    assert!(
        message.contains("cannot put the report in place") && message.contains("is as it was"),
        "{message}"
    );
    assert_eq!(contents(&old), before);
    assert_eq!(names(keep.path()), ["old"]);
}

#[test]
fn a_symlinked_out_replaces_the_directory_it_points_to() {
    let (keep, old) = benchmark_1_report();
    let link = keep.path().join("link");
    std::os::unix::fs::symlink(&old, &link).unwrap();
    succeeded(&report("eight-obstacles", &link, &SMALL, true, &[]));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        names(&old),
        ["error-vs-time.svg", "mesh-sweep.csv", "report.md"]
    );
    assert_eq!(names(keep.path()), ["link", "old"]);
}
