//! `beamfric report`: error against run time for every method over mesh sizes, and the
//! regularisation trade-off over ε, as a Markdown report with tables, the explorer's charts as
//! text, CSV files and an SVG figure (plotters) next to it. Where a method is refused, or its
//! result is meaningless (indefinite factorization, non-finite values), the report says so
//! instead of printing numbers; the reference's own row is marked, never shown as error 0.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use crate::format::{duration, sci};
use crate::plot::{Look, StudyChart, buffer_to_text, chart_buffer};
use crate::scene::LoadedScene;
use crate::solve::{Method, WarningCode};
use crate::study::{self, EpsPoint, MeshPoint, Progress};

/// What to measure.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportOptions {
    /// Mesh sizes of the mesh sweep.
    pub sizes: Vec<usize>,
    /// Runs per point (median run time).
    pub repeat: usize,
    /// ε values of the ε sweep (at the scene's n).
    pub epsilons: Vec<f64>,
    /// The command line that produced the report, quoted in it.
    pub command: String,
}

/// A report's files.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    pub markdown: String,
    pub mesh_csv: String,
    pub epsilon_csv: Option<String>,
    pub svg: String,
}

/// The files a report writes into its directory.
pub const FILES: [&str; 4] = [
    "report.md",
    "mesh-sweep.csv",
    "epsilon-sweep.csv",
    "error-vs-time.svg",
];

/// How a point is shown: its numbers, or why there are none.
fn status(point: &MeshPoint) -> Result<bool, String> {
    if let Some(reason) = &point.refused {
        return Err(reason.clone());
    }
    if point.is_reference() {
        return Err("reference".into());
    }
    if point
        .warnings
        .contains(&WarningCode::IndefiniteFactorization)
    {
        return Err("unreliable: A indefinite in floating point".into());
    }
    if point.warnings.contains(&WarningCode::NonFinite) || point.error.is_none() {
        return Err("n/a: non-finite values".into());
    }
    Ok(point.warnings.contains(&WarningCode::StiffnessConditioning))
}

/// The processor and core count, for the record of where run times were measured.
fn machine() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown processor".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{model}, {cores} cores")
}

/// Runs the studies and builds the report.
pub fn build(
    loaded: &LoadedScene,
    options: &ReportOptions,
    progress: Progress,
) -> Result<Report, String> {
    let (problem, settings) = (&loaded.problem, &loaded.settings);
    let never = &|| false;
    let mesh_points = study::mesh_sweep(
        problem,
        &Method::ALL,
        &options.sizes,
        options.repeat,
        settings.epsilon,
        never,
        progress,
    )
    .map_err(|_| "cancelled".to_string())?;
    let eps_points = study::epsilon_sweep(
        problem,
        settings.elements,
        Method::Regularized,
        &options.epsilons,
        never,
        progress,
    )
    .map_err(|_| "cancelled".to_string())?;

    let source = loaded.source.to_string();
    let title = if loaded.scene.title.is_empty() {
        source.as_str()
    } else {
        loaded.scene.title.as_str()
    };
    let mut md = String::new();
    write_introduction(&mut md, loaded, title, options);
    write_mesh_table(&mut md, &mesh_points);
    write_error_time_chart(&mut md, &mesh_points);
    let epsilon_csv = match &eps_points {
        Ok(points) => {
            write_epsilon_section(&mut md, points, settings.elements);
            Some(crate::output::epsilon_sweep_csv(points))
        }
        Err(e) => {
            let _ = writeln!(
                md,
                "## Regularisation against ε\n\nNot computed: {e}. The semismooth Newton method \
                 solves the same ε-problem (`beamfric sweep epsilon --method regularized-newton`).\n"
            );
            None
        }
    };
    let _ = writeln!(
        md,
        "\nFiles: [mesh-sweep.csv](mesh-sweep.csv){}, [error-vs-time.svg](error-vs-time.svg).",
        if epsilon_csv.is_some() {
            ", [epsilon-sweep.csv](epsilon-sweep.csv)"
        } else {
            ""
        }
    );
    Ok(Report {
        markdown: md,
        mesh_csv: crate::output::mesh_sweep_csv(&mesh_points),
        epsilon_csv,
        svg: svg_figure(&mesh_points, title),
    })
}

/// The charts of a report: the explorer's drawing, Unicode, no colour.
const REPORT_LOOK: Look = Look {
    ascii: false,
    color: false,
};

/// Title, description, and how the figures were produced.
fn write_introduction(md: &mut String, loaded: &LoadedScene, title: &str, options: &ReportOptions) {
    let _ = writeln!(md, "# Error against run time: {title}\n");
    if !loaded.scene.description.is_empty() {
        let _ = writeln!(md, "{}\n", loaded.scene.description);
    }
    let _ = writeln!(
        md,
        "Produced by `{}`. Run times are medians of {} run(s) of each method's stages \
         (assembly, factorization, dual solve, reconstruction) on this machine: {}. Errors are \
         the largest nodal |u − u_ref| over max |u_ref|, against {}.\n",
        options.command,
        options.repeat,
        machine(),
        if crate::solve::closed_form(&loaded.problem).is_ok() {
            "the closed form (50)"
        } else {
            "the flexibility method on the same mesh (whose own rows read \"reference\")"
        }
    );
}

/// Methods over mesh sizes: one row per n, one column per method, and the notes the cells
/// refer to.
fn write_mesh_table(md: &mut String, mesh_points: &[MeshPoint]) {
    let methods: Vec<Method> = Method::ALL
        .into_iter()
        .filter(|m| mesh_points.iter().any(|p| p.method == *m))
        .collect();
    let _ = writeln!(md, "## Every method over mesh sizes\n");
    let _ = writeln!(
        md,
        "Each cell: relative error · run time. † marks a result the method itself flagged \
         (the stiffness route's conditioning warning: expect rounding errors near \
         0.02·cond·eps).\n"
    );
    let _ = write!(md, "| n |");
    for m in &methods {
        let _ = write!(md, " {m} |");
    }
    let _ = write!(md, "\n|---|");
    for _ in &methods {
        let _ = write!(md, "---|");
    }
    md.push('\n');
    let mut notes: Vec<String> = Vec::new();
    let mut sizes: Vec<usize> = mesh_points.iter().map(|p| p.elements).collect();
    sizes.dedup();
    for elements in sizes {
        let _ = write!(md, "| {elements} |");
        for m in &methods {
            let point = mesh_points
                .iter()
                .find(|p| p.elements == elements && p.method == *m);
            let _ = write!(md, " {} |", mesh_cell(point, &mut notes));
        }
        md.push('\n');
    }
    if !notes.is_empty() {
        md.push('\n');
        for (i, note) in notes.iter().enumerate() {
            let _ = writeln!(md, "[{}] {note}  ", i + 1);
        }
    }
}

/// One cell of the mesh table: error and run time, `reference`, or a short reason with the
/// number of its note (added to `notes` when new).
fn mesh_cell(point: Option<&MeshPoint>, notes: &mut Vec<String>) -> String {
    let Some(p) = point else {
        return "—".to_string();
    };
    match status(p) {
        Ok(flagged) => format!(
            "{}{} · {}",
            sci(p.error.and_then(|e| e.max_rel).unwrap_or(f64::NAN), 2),
            if flagged { "†" } else { "" },
            duration(p.run_time)
        ),
        Err(why) if why == "reference" => format!("reference · {}", duration(p.run_time)),
        Err(why) => {
            if !notes.contains(&why) {
                notes.push(why.clone());
            }
            let index = notes.iter().position(|n| *n == why).unwrap_or(0) + 1;
            let short = why.split(':').next().unwrap_or("").to_string();
            format!("{short} [{index}]")
        }
    }
}

/// The chart, as the explorer draws it, of the results the table shows numbers for.
fn write_error_time_chart(md: &mut String, mesh_points: &[MeshPoint]) {
    let shown: Vec<MeshPoint> = mesh_points
        .iter()
        .filter(|p| status(p).is_ok() || p.is_reference())
        .cloned()
        .collect();
    let chart = StudyChart::ErrorTime {
        points: &shown,
        by_time: true,
    };
    let chart = chart_buffer(chart, "Error vs run time", 100, 30, REPORT_LOOK);
    let _ = writeln!(
        md,
        "\n```\n{}```\n\n![Error against run time](error-vs-time.svg)\n",
        buffer_to_text(&chart, false)
    );
}

/// The regularisation trade-off at the scene's n: the table and the two charts.
fn write_epsilon_section(md: &mut String, points: &[EpsPoint], elements: usize) {
    let _ = writeln!(
        md,
        "## Regularisation: error and conditioning against ε (n = {elements})\n"
    );
    let _ = writeln!(
        md,
        "| ε | max rel. error | mean abs. error [m] | largest cond₂(Â) | Jacobi-scaled | run time |\n|---|---|---|---|---|---|"
    );
    for p in points {
        let e = p.error;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            sci(p.epsilon, 2),
            sci(e.and_then(|e| e.max_rel).unwrap_or(f64::NAN), 2),
            sci(e.and_then(|e| e.mean_abs).unwrap_or(f64::NAN), 2),
            p.cond_max.map_or("—".into(), |c| sci(c.value, 2)),
            p.cond_scaled_max.map_or("—".into(), |c| sci(c.value, 2)),
            duration(p.run_time)
        );
    }
    for (chart, name) in [
        (StudyChart::EpsError(points), "Regularisation error vs ε"),
        (
            StudyChart::EpsCondition(points),
            "Largest cond2 of the cases vs ε",
        ),
    ] {
        let buffer = chart_buffer(chart, name, 100, 22, REPORT_LOOK);
        let _ = writeln!(md, "\n```\n{}```", buffer_to_text(&buffer, false));
    }
}

/// Error against run time, log–log, one series per method (plotters' SVG backend).
fn svg_figure(points: &[MeshPoint], title: &str) -> String {
    use plotters::prelude::*;
    let series: Vec<(Method, Vec<(f64, f64)>)> = Method::ALL
        .into_iter()
        .map(|m| {
            let data = points
                .iter()
                .filter(|p| p.method == m && status(p).is_ok())
                .filter_map(|p| {
                    let e = p.error?.max_rel?;
                    let t = p.run_time.as_secs_f64();
                    (e > 0.0 && t > 0.0).then_some((t, e))
                })
                .collect();
            (m, data)
        })
        .filter(|(_, d): &(Method, Vec<(f64, f64)>)| !d.is_empty())
        .collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, d)| d.iter().copied()).collect();
    let bound = |f: fn(&(f64, f64)) -> f64| {
        let values: Vec<f64> = all.iter().map(f).collect();
        let low = values.iter().copied().fold(f64::INFINITY, f64::min);
        let high = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if low.is_finite() && high.is_finite() {
            (
                10f64.powf(low.log10().floor()),
                10f64.powf(high.log10().ceil()),
            )
        } else {
            (1e-6, 1.0)
        }
    };
    let (x, y) = (bound(|p| p.0), bound(|p| p.1));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        let _ = root.fill(&WHITE);
        let built = ChartBuilder::on(&root)
            .caption(
                format!("{title}: error against run time"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale());
        if let Ok(mut chart) = built {
            let decade = |v: &f64| format!("1e{}", v.log10().round() as i32);
            let _ = chart
                .configure_mesh()
                .x_desc("run time [s]")
                .y_desc("max relative nodal error")
                .x_label_formatter(&decade)
                .y_label_formatter(&decade)
                .draw();
            const COLORS: [RGBColor; 6] = [
                RGBColor(0, 114, 178),
                RGBColor(0, 158, 115),
                RGBColor(213, 94, 0),
                RGBColor(204, 121, 167),
                RGBColor(86, 64, 0),
                RGBColor(90, 90, 90),
            ];
            for (method, data) in &series {
                let index = Method::ALL.iter().position(|m| m == method).unwrap_or(0);
                let color = COLORS[index % COLORS.len()].to_rgba();
                if let Ok(drawn) = chart.draw_series(
                    data.iter()
                        .map(move |&(t, e)| Circle::new((t, e), 4, color.filled())),
                ) {
                    drawn
                        .label(method.name())
                        .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
                }
            }
            let _ = chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw();
        }
        let _ = root.present();
    }
    svg
}

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

/// Checks, before anything is measured, that a report can be written to `dir`: it is not a
/// file; it is missing, empty, or holds only report files (and then `overwrite` is needed);
/// its parent exists and a directory can be created there; an existing `dir` is writable (its
/// old files must be removed); and the file system has [`MIN_FREE_BYTES`] free.
pub fn prepare(dir: &Path, overwrite: bool) -> Result<Destination, String> {
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
pub fn write(report: &Report, destination: &Destination) -> Result<Vec<String>, String> {
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
        eprintln!(
            "beamfric: the new report is in place, but the old one could not be removed from {}: {e}",
            old.display()
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
