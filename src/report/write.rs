//! Putting a report on disk without ever leaving a mixed or half-written one: the destination
//! is checked before anything is measured ([`prepare`]), the files are written and synced in a
//! fresh temporary directory next to the target, and that directory replaces the target in one
//! step ([`write`]); a failure leaves the target as it was.

use std::path::{Path, PathBuf};

use super::{FILES, Report, ReportError};

/// Free space the destination's file system must have before anything is measured: a typical
/// report is 100–300 KB, so 1 MiB leaves room to spare.
pub const MIN_FREE_BYTES: u64 = 1 << 20;

/// Test hook: `BEAMFRIC_INJECT_WRITE_FAILURE=after:N` makes the report writer fail as a full
/// disk would when it writes its file number N + 1 (after N complete files);
/// `=swap` makes it fail at the step that puts the new report in place of an old one (taking
/// the two-rename route, so the restore of the old report is exercised). Read only by
/// [`write`]; nothing else looks at it.
pub const INJECT_WRITE_FAILURE: &str = "BEAMFRIC_INJECT_WRITE_FAILURE";

/// Prefix of the temporary directories made next to the target (the new report while it is
/// written, the old one while it is swapped out).
const STAGING_PREFIX: &str = ".beamfric-report-";

/// Where a report goes, checked by [`prepare`] before anything is measured.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Destination {
    /// The directory as the user named it, for messages.
    shown: PathBuf,
    /// The directory to create or replace (a symlink's target when `--out` is a symlink).
    target: PathBuf,
    /// Its parent, where the temporary directories go.
    parent: PathBuf,
    /// Replace an existing report (`--force`).
    overwrite: bool,
}

impl Destination {
    /// The directory as the user named it.
    pub fn path(&self) -> &Path {
        &self.shown
    }
}

/// Checks, before anything is measured, that a report can be written to `dir`: it is named
/// (not empty); it is not a file; it is missing, empty, or holds only report files (and then `overwrite` is needed);
/// its parent exists and a directory can be created there; an existing `dir` is writable (its
/// old files must be removed); and the file system has [`MIN_FREE_BYTES`] free.
pub fn prepare(dir: &Path, overwrite: bool) -> Result<Destination, ReportError> {
    check_destination(dir, overwrite).map_err(ReportError::Destination)
}

/// [`prepare`], its reasons in words.
fn check_destination(dir: &Path, overwrite: bool) -> Result<Destination, String> {
    if dir.as_os_str().is_empty() {
        return Err(
            "--out is empty: name the directory for the report (e.g. --out report), or \
                    leave --out out for report-<scene>"
                .into(),
        );
    }
    let shown = dir.to_path_buf();
    let target = match std::fs::symlink_metadata(dir) {
        // The directory it points to is replaced; the link stays.
        Ok(meta) if meta.file_type().is_symlink() => std::fs::canonicalize(dir).map_err(|e| {
            format!(
                "{} is a symbolic link whose target cannot be resolved: {e}",
                dir.display()
            )
        })?,
        _ => dir.to_path_buf(),
    };
    let exists = inspect(&shown, &target, overwrite)?;
    let target = if exists {
        std::fs::canonicalize(&target).map_err(|e| format!("cannot use {}: {e}", dir.display()))?
    } else {
        target
    };
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match std::fs::metadata(&parent) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => {
            return Err(format!(
                "cannot write the report to {}: {} is not a directory",
                dir.display(),
                parent.display()
            ));
        }
        Err(e) => {
            return Err(format!(
                "cannot write the report to {}: its parent directory {}: {e}",
                dir.display(),
                parent.display()
            ));
        }
    }
    // The same kind of directory the report will be built in; removed again at once, so an
    // interrupted run leaves nothing behind.
    tempfile::Builder::new()
        .prefix(STAGING_PREFIX)
        .tempdir_in(&parent)
        .map_err(|e| {
            format!(
                "cannot write the report to {}: cannot create a directory in {}: {e}",
                dir.display(),
                parent.display()
            )
        })?;
    if exists {
        tempfile::tempfile_in(&target).map_err(|e| {
            format!(
                "cannot replace the report in {}: cannot write there: {e}",
                dir.display()
            )
        })?;
    }
    check_free_space(&parent)?;
    Ok(Destination {
        shown,
        target,
        parent,
        overwrite,
    })
}

/// Whether `target` exists, after checking it may be replaced: a directory holding nothing but
/// report files (any of them, with `overwrite`) or nothing at all. Anything else in it — the
/// user's notes, a subdirectory — makes it off limits, even with `overwrite`.
fn inspect(shown: &Path, target: &Path, overwrite: bool) -> Result<bool, String> {
    let meta = match std::fs::metadata(target) {
        Ok(meta) => meta,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(format!("cannot use {}: {e}", shown.display())),
    };
    if !meta.is_dir() {
        return Err(format!(
            "{} is a file, not a directory: choose another --out",
            shown.display()
        ));
    }
    let entries =
        std::fs::read_dir(target).map_err(|e| format!("cannot read {}: {e}", shown.display()))?;
    let (mut ours, mut foreign) = (Vec::new(), Vec::new());
    for entry in entries {
        let entry = entry.map_err(|e| format!("cannot read {}: {e}", shown.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let regular = entry.file_type().is_ok_and(|t| t.is_file());
        if regular && FILES.contains(&name.as_str()) {
            ours.push(name);
        } else {
            foreign.push(name);
        }
    }
    if !foreign.is_empty() {
        foreign.sort();
        let more = if foreign.len() > 3 { ", …" } else { "" };
        foreign.truncate(3);
        return Err(format!(
            "{} holds files that are not part of a report ({}{more}): a report replaces only a \
             directory of report files, even with --force; choose another --out or move them",
            shown.display(),
            foreign.join(", ")
        ));
    }
    if !overwrite && let Some(first) = FILES.iter().find(|f| ours.iter().any(|o| o == *f)) {
        return Err(format!(
            "{} exists: pass --force to replace the report, or choose another --out",
            shown.join(first).display()
        ));
    }
    Ok(true)
}

/// Refuses a file system with less than [`MIN_FREE_BYTES`] available.
#[cfg(unix)]
fn check_free_space(dir: &Path) -> Result<(), String> {
    let stats = nix::sys::statvfs::statvfs(dir)
        .map_err(|e| format!("cannot tell the free space in {}: {e}", dir.display()))?;
    let free = (stats.blocks_available() as u64).saturating_mul(stats.fragment_size() as u64);
    if free < MIN_FREE_BYTES {
        return Err(format!(
            "not enough room for a report in {}: {} KiB free, a report needs up to {} KiB",
            dir.display(),
            free / 1024,
            MIN_FREE_BYTES / 1024
        ));
    }
    Ok(())
}

#[cfg(not(unix))]
fn check_free_space(_dir: &Path) -> Result<(), String> {
    Ok(())
}

/// What [`INJECT_WRITE_FAILURE`] asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Injected {
    None,
    /// Fail on the file after this many.
    After(usize),
    /// Fail when the new report goes in place of the old one.
    Swap,
}

fn injected() -> Injected {
    match std::env::var(INJECT_WRITE_FAILURE).ok().as_deref() {
        Some("swap") => Injected::Swap,
        Some(v) => v
            .strip_prefix("after:")
            .and_then(|n| n.parse().ok())
            .map_or(Injected::None, Injected::After),
        None => Injected::None,
    }
}

fn injected_error() -> std::io::Error {
    std::io::Error::other(format!("injected failure ({INJECT_WRITE_FAILURE})"))
}

/// Writes the report into `destination` as one step: every file is written and synced in a
/// fresh temporary directory next to it, then that directory takes the target's place (an
/// atomic exchange where the file system offers one, else the old report is renamed aside
/// until the new one is in place, and put back if that fails) and the old report is removed.
/// The result holds exactly the new report's files. On any failure the target is as it was —
/// the old report, or nothing — no temporary directory is left, and the error names the file
/// and the reason. Returns the paths written.
pub fn write(report: &Report, destination: &Destination) -> Result<Vec<String>, ReportError> {
    write_in_one_step(report, destination).map_err(ReportError::Write)
}

/// [`write`], its reasons in words.
fn write_in_one_step(report: &Report, destination: &Destination) -> Result<Vec<String>, String> {
    let Destination {
        shown,
        target,
        parent,
        overwrite,
    } = destination;
    let mut files = vec![(FILES[0], &report.markdown), (FILES[1], &report.mesh_csv)];
    if let Some(csv) = &report.epsilon_csv {
        files.push((FILES[2], csv));
    }
    files.push((FILES[3], &report.svg));
    let inject = injected();
    // The target may have changed while the studies ran.
    let exists = inspect(shown, target, *overwrite)?;
    let unchanged = if exists {
        format!("{} is as it was", shown.display())
    } else {
        format!("{} was not created", shown.display())
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(STAGING_PREFIX);
    #[cfg(unix)]
    {
        // 0777 less the umask, as `create_dir` would; an old report's directory keeps its mode.
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(target)
            .ok()
            .filter(|_| exists)
            .map_or(0o777, |m| m.permissions().mode() & 0o7777);
        builder.permissions(std::fs::Permissions::from_mode(mode));
    }
    let staging = builder.tempdir_in(parent).map_err(|e| {
        format!(
            "cannot write the report to {}: cannot create a directory in {}: {e}",
            shown.display(),
            parent.display()
        )
    })?;
    for (index, (name, text)) in files.iter().enumerate() {
        let written = if inject == Injected::After(index) {
            Err(injected_error())
        } else {
            write_synced(&staging.path().join(name), text.as_bytes())
        };
        // Dropping `staging` removes it with what was written so far.
        written.map_err(|e| {
            format!(
                "cannot write {}: {e}; {unchanged}",
                shown.join(name).display()
            )
        })?;
    }
    sync_dir(staging.path()).map_err(|e| {
        format!(
            "cannot write the report to {}: {e}; {unchanged}",
            shown.display()
        )
    })?;
    let staging = staging.keep();
    let placed = if exists {
        replace(&staging, target, parent, inject == Injected::Swap)
    } else {
        std::fs::rename(&staging, target).map(|()| None)
    };
    let leftover = match placed {
        Ok(old) => old,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&staging);
            return Err(format!(
                "cannot put the report in place at {}: {e}; {unchanged}",
                shown.display()
            ));
        }
    };
    let _ = sync_dir(parent);
    if let Some(old) = leftover
        && let Err(e) = std::fs::remove_dir_all(&old)
    {
        let _ = std::io::Write::write_fmt(
            &mut std::io::stderr(),
            format_args!(
                "beamfric: the new report is in place, but the old one could not be removed from {}: {e}\n",
                old.display()
            ),
        );
    }
    Ok(files
        .iter()
        .map(|(name, _)| shown.join(name).display().to_string())
        .collect())
}

/// Creates `path` (which must not exist), writes `bytes` and syncs it.
fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut file = std::fs::File::create_new(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// Makes renames and new entries in `dir` durable.
fn sync_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::File::open(dir)?.sync_all()
}

/// Puts the complete report at `staging` in place of the existing directory `target`. Returns
/// where the old report now is, to be removed. On failure the target is as it was.
fn replace(
    staging: &Path,
    target: &Path,
    parent: &Path,
    fail_swap: bool,
) -> std::io::Result<Option<PathBuf>> {
    // One step: the two directories trade places.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    if !fail_swap {
        use nix::errno::Errno;
        use nix::fcntl::{RenameFlags, renameat2};
        match renameat2(None, staging, None, target, RenameFlags::RENAME_EXCHANGE) {
            Ok(()) => return Ok(Some(staging.to_path_buf())),
            // Not offered by this file system: two renames below.
            Err(Errno::EINVAL | Errno::ENOSYS | Errno::EOPNOTSUPP) => {}
            Err(e) => return Err(e.into()),
        }
    }
    // The old report moves aside onto a fresh empty directory's name (a rename may replace an
    // empty directory), the new one takes its place, and the old one comes back on failure.
    let aside = tempfile::Builder::new()
        .prefix(STAGING_PREFIX)
        .tempdir_in(parent)?
        .keep();
    if let Err(e) = std::fs::rename(target, &aside) {
        let _ = std::fs::remove_dir(&aside);
        return Err(e);
    }
    let moved = if fail_swap {
        Err(injected_error())
    } else {
        std::fs::rename(staging, target)
    };
    match moved {
        Ok(()) => Ok(Some(aside)),
        Err(e) => match std::fs::rename(&aside, target) {
            Ok(()) => Err(e),
            Err(back) => Err(std::io::Error::new(
                e.kind(),
                format!(
                    "{e}, and the old report could not be moved back from {}: {back}",
                    aside.display()
                ),
            )),
        },
    }
}
