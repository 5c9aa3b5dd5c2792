//! `beamfric report`: error against run time for every method over mesh sizes, and the
//! regularisation trade-off over ε, as a Markdown report with tables, the explorer's charts as
//! text, CSV files and an SVG figure ([`crate::figure`], the explorer's `e`) next to it. Where a method is refused, or its
//! result is meaningless (indefinite factorization, non-finite values), the report says so
//! instead of printing numbers; the reference's own row is marked, never shown as error 0.

use std::fmt::Write;

use crate::format::{duration, printable, sci};
use crate::plot::{Look, StudyChart, buffer_to_text, chart_buffer};
use crate::scene::LoadedScene;
use crate::solve::{Method, WarningCode};
use crate::study::{self, EpsPoint, MeshPoint, Progress};

mod write;

pub use write::{Destination, INJECT_WRITE_FAILURE, MIN_FREE_BYTES, prepare, write};

/// Why a report could not be written; each says in words which file and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReportError {
    /// The destination cannot take a report (found before anything is measured).
    Destination(String),
    /// Writing the report failed; the destination is as it was.
    Write(String),
}

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReportError::Destination(text) | ReportError::Write(text) => f.write_str(text),
        }
    }
}

impl std::error::Error for ReportError {}

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
pub(crate) fn status(point: &MeshPoint) -> Result<bool, String> {
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
pub fn build(loaded: &LoadedScene, options: &ReportOptions, progress: Progress) -> Report {
    let (problem, settings) = (&loaded.problem, &loaded.settings);
    let never = crate::solve::Cancellation::NEVER;
    let mesh_points = study::mesh_sweep(
        problem,
        &Method::ALL,
        &options.sizes,
        options.repeat,
        settings.epsilon,
        &never,
        progress,
    )
    .expect("a sweep that is never cancelled finishes");
    let eps_points = study::epsilon_sweep(
        problem,
        settings.elements,
        Method::Regularized,
        &options.epsilons,
        &never,
        progress,
    )
    .expect("a sweep that is never cancelled finishes");

    let source = loaded.source.to_string();
    // Control characters escaped in every file (Markdown, and SVG, where they are not XML).
    let title = printable(if loaded.scene.title.is_empty() {
        source.as_str()
    } else {
        loaded.scene.title.as_str()
    });
    let mut md = String::new();
    write_introduction(&mut md, loaded, &title, options);
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
    Report {
        markdown: md,
        mesh_csv: crate::output::mesh_sweep_csv(&mesh_points),
        epsilon_csv,
        svg: error_time_svg(&mesh_points, &title),
    }
}

/// The figure of error against run time, one line per method, of the results the table
/// shows numbers for (as the text chart).
fn error_time_svg(mesh_points: &[MeshPoint], title: &str) -> String {
    let shown: Vec<MeshPoint> = mesh_points
        .iter()
        .filter(|p| status(p).is_ok())
        .cloned()
        .collect();
    let title = format!("{title}: error against run time");
    crate::figure::error_time_figure(&shown, crate::figure::ErrorAxis::RunTime, None, &title)
}

/// The charts of a report: the explorer's drawing, Unicode, no colour.
const REPORT_LOOK: Look = Look {
    ascii: false,
    color: false,
};

/// Text from the scene in Markdown: `&`, `<` and `>` as HTML entities, so that a title such
/// as `<img src=x onerror=…>` is read as text, not as HTML a viewer would run.
fn markdown_text(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Title, description, and how the figures were produced.
fn write_introduction(md: &mut String, loaded: &LoadedScene, title: &str, options: &ReportOptions) {
    let _ = writeln!(md, "# Error against run time: {}\n", markdown_text(title));
    if !loaded.scene.description.is_empty() {
        let description = printable(&loaded.scene.description);
        let _ = writeln!(md, "{}\n", markdown_text(&description));
    }
    let _ = writeln!(
        md,
        "Produced by `{}`. Run times are medians of {} run(s) of each method's stages \
         (assembly, factorization, dual solve, reconstruction) on this machine: {}. Errors are \
         the largest nodal |u − u_ref| over max |u_ref|, against {}.\n",
        printable(&options.command),
        options.repeat,
        machine(),
        if crate::solve::closed_form(&loaded.problem).is_ok() {
            "the closed form (50)"
        } else {
            "the condensed method on the same mesh (whose own rows read \"reference\")"
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
