//! `beamfric figure PANEL --scene S --out FILE.svg`: the explorer's panel as a slide-quality
//! SVG figure ([`crate::figure`]), from the same data — the scene's solve and its reference
//! for the deflection, the explorer's sweeps (ε = 1e-16 … 1 with the scene's ε; every method
//! over n = 10 … 10⁵ with the scene's n, `dual-inverse` up to n = 400) for the others —
//! written atomically, never over an existing file without `--force`.

use std::path::Path;
use std::process::ExitCode;

use super::{
    Against, CliError, EXIT_NO_SOLUTION, FigureArgs, ProgressLine, check_count, load_with_overrides,
};
use crate::fem::Mesh;
use crate::figure::{self, DeflectionInput, ErrorAxis, FigurePanel};
use crate::plot::CurrentRun;
use crate::scene::{self, LoadedScene, SaveError};
use crate::solve::{Cancellation, ConditionLevel, Method, SolveOptions, solve};
use crate::study;
use crate::tui::jobs::sweeps::{EPS_POINTS, MESH_MAX, MESH_POINTS};

/// A figure made: its SVG, and why it has no data if it has none.
struct Drawn {
    svg: String,
    refusal: Option<String>,
}

/// Runs `beamfric figure`.
pub(super) fn figure_command(args: &FigureArgs) -> Result<ExitCode, CliError> {
    check_destination(&args.out, args.force)?;
    let loaded = load_with_overrides(&args.scene, args.method, args.elements, args.epsilon)?;
    // A control character (a tab, a newline) is a blank on a slide; an empty title is none.
    let title = args
        .title
        .as_deref()
        .map(|t| t.replace(char::is_control, " ").trim().to_string())
        .filter(|t| !t.is_empty())
        .unwrap_or_else(|| default_title(&loaded, args));
    let drawn = match args.panel {
        FigurePanel::Deflection => deflection(&loaded, &title),
        FigurePanel::EpsError | FigurePanel::EpsCond => epsilon_panel(&loaded, args, &title)?,
        FigurePanel::ErrorTime => error_time(&loaded, args, &title)?,
    };
    if is_png(&args.out) {
        let png = crate::figure::svg_to_png(&drawn.svg)
            .map_err(|why| CliError::Figure(format!("{}: {why}", args.out.display())))?;
        write_figure(&args.out, &png, args.force)?;
    } else {
        write_figure(&args.out, drawn.svg.as_bytes(), args.force)?;
    }
    say!("wrote {}", args.out.display());
    match drawn.refusal {
        Some(why) => {
            say!("beamfric: the figure has no data: {why}");
            Ok(ExitCode::from(EXIT_NO_SOLUTION))
        }
        None => Ok(ExitCode::SUCCESS),
    }
}

/// Does the name ask for a PNG (`.png`, any case)?
fn is_png(out: &Path) -> bool {
    out.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// The file must be an `.svg` or a `.png`, and not be there already unless `--force`
/// (checked before anything is computed).
fn check_destination(out: &Path, force: bool) -> Result<(), CliError> {
    let shown = out.display();
    let is_svg = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if !is_svg && !is_png(out) {
        return Err(CliError::Argument(format!(
            "--out {shown}: figures are written as SVG (.svg) or PNG (.png, 1920 × 1080), so \
             the file name must end in one of those"
        )));
    }
    if !force && std::fs::symlink_metadata(out).is_ok() {
        return Err(CliError::Figure(exists(out)));
    }
    Ok(())
}

fn exists(out: &Path) -> String {
    format!(
        "{} exists and was not replaced: pass --force to replace it, or choose another name",
        out.display()
    )
}

/// Writes the figure atomically (a temporary file in the same directory, renamed).
fn write_figure(out: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    match scene::write_atomic(out, bytes, force) {
        Ok(_) => Ok(()),
        Err(SaveError::Exists(_)) => Err(CliError::Figure(exists(out))),
        Err(SaveError::Io(_, e)) => Err(CliError::Figure(format!(
            "cannot write the figure {}: {e}",
            out.display()
        ))),
        Err(e) => Err(CliError::Figure(format!("cannot write the figure: {e}"))),
    }
}

/// "Benchmark 1: regularisation error against ε".
fn default_title(loaded: &LoadedScene, args: &FigureArgs) -> String {
    let scene = if loaded.scene.title.is_empty() {
        loaded.source.stem()
    } else {
        loaded.scene.title.clone()
    };
    let against = match args.against {
        Against::Time => ErrorAxis::RunTime,
        Against::Elements => ErrorAxis::Elements,
    };
    crate::figure::figure_title(&scene, args.panel, against)
}

/// The scene's solve and, for another method, the reference (`condensed` on the same mesh).
fn deflection(loaded: &LoadedScene, title: &str) -> Drawn {
    let (problem, settings) = (&loaded.problem, &loaded.settings);
    let mesh = Mesh::new(problem, settings.elements);
    let options = SolveOptions {
        epsilon: settings.epsilon,
        condition: ConditionLevel::Off,
        ..SolveOptions::default()
    };
    let solution = match solve(problem, &mesh, settings.method, &options) {
        Ok(solution) => solution,
        Err(e) => {
            let why = format!("{} gave no solution: {e}", settings.method);
            return Drawn {
                svg: figure::notice_figure(FigurePanel::Deflection, title, &why),
                refusal: Some(why),
            };
        }
    };
    let reference = (settings.method != Method::Condensed)
        .then(|| solve(problem, &mesh, Method::Condensed, &options).ok())
        .flatten();
    let input = DeflectionInput {
        problem,
        mesh: &mesh,
        solution: &solution,
        reference: reference.as_ref(),
    };
    Drawn {
        svg: figure::deflection_figure(&input, title),
        refusal: None,
    }
}

/// The sweep's range, from the options or the explorer's defaults.
fn range(args: &FigureArgs, defaults: (f64, f64, usize)) -> (f64, f64, usize) {
    (
        args.from.unwrap_or(defaults.0),
        args.to.unwrap_or(defaults.1),
        args.points.unwrap_or(defaults.2),
    )
}

fn check_order(from: f64, to: f64) -> Result<(), CliError> {
    if from > to {
        return Err(CliError::Argument(format!(
            "--from {from} is larger than --to {to}"
        )));
    }
    Ok(())
}

/// The explorer's ε sweep at the scene's n: the range asked for and the scene's ε.
fn epsilon_panel(loaded: &LoadedScene, args: &FigureArgs, title: &str) -> Result<Drawn, CliError> {
    let (from, to, points) = range(args, (1e-16, 1.0, EPS_POINTS));
    for (name, value) in [("--from", from), ("--to", to)] {
        scene::check_epsilon(value).map_err(|rule| CliError::Argument(format!("{name} {rule}")))?;
    }
    check_order(from, to)?;
    check_count("--points", points, 1..=super::MAX_EPSILON_POINTS)?;
    if let Some(method) = args.method.filter(|m| !m.is_regularized()) {
        return Err(CliError::Argument(format!(
            "--method {method}: the ε panels need regularized or regularized-newton"
        )));
    }
    let settings = &loaded.settings;
    let mut epsilons = study::log_space(from, to, points);
    epsilons.push(settings.epsilon);
    epsilons.sort_by(f64::total_cmp);
    epsilons.dedup();
    let progress = ProgressLine::new("figure");
    let sweep = |method| {
        study::epsilon_sweep(
            &loaded.problem,
            settings.elements,
            method,
            &epsilons,
            &Cancellation::NEVER,
            &|done, total, what| progress.report(done, total, what),
        )
        .expect("never cancelled")
    };
    let result = match args.method {
        Some(method) => sweep(method),
        None => sweep(Method::Regularized).or_else(|_| sweep(Method::RegularizedNewton)),
    };
    progress.finish();
    let points = match result {
        Ok(points) => points,
        Err(e) => {
            let why = crate::study::sweep_refusal(&e);
            return Ok(Drawn {
                svg: figure::notice_figure(args.panel, title, &why),
                refusal: Some(why),
            });
        }
    };
    let current = Some(settings.epsilon);
    let svg = match args.panel {
        FigurePanel::EpsCond => figure::eps_cond_figure(&points, current, title),
        _ => figure::eps_error_figure(&points, current, title),
    };
    Ok(Drawn { svg, refusal: None })
}

/// The explorer's mesh sweep: every method over the sizes asked for and the scene's n,
/// `dual-inverse` only up to [`study::DENSE_MAX`].
fn error_time(loaded: &LoadedScene, args: &FigureArgs, title: &str) -> Result<Drawn, CliError> {
    let (from, to, points) = range(args, (10.0, MESH_MAX as f64, MESH_POINTS));
    let mut ends = [0usize; 2];
    for (end, (name, value)) in ends.iter_mut().zip([("--from", from), ("--to", to)]) {
        if value.fract() != 0.0 || value < 1.0 {
            return Err(CliError::Argument(format!(
                "{name} {value}: for error-time, a number of elements (a whole number)"
            )));
        }
        *end = value as usize;
        scene::check_elements(*end).map_err(|rule| CliError::Argument(format!("{name} {rule}")))?;
    }
    check_order(from, to)?;
    check_count("--points", points, 1..=super::MAX_MESH_POINTS)?;
    // As `report` and `sweep mesh` refuse it: no run has no median.
    check_count("--repeat", args.repeat, 1..=super::MAX_REPEAT)?;
    let settings = &loaded.settings;
    let progress = ProgressLine::new("figure");
    let report = |done, total, what: &str| progress.report(done, total, what);
    let mesh_points = study::error_study(
        &loaded.problem,
        &study::mesh_sizes(ends[0], ends[1], points),
        settings.elements,
        args.repeat,
        settings.epsilon,
        &Cancellation::NEVER,
        &report,
    )
    .expect("never cancelled");
    progress.finish();
    let against = match args.against {
        Against::Time => ErrorAxis::RunTime,
        Against::Elements => ErrorAxis::Elements,
    };
    let current = CurrentRun {
        elements: settings.elements,
        method: settings.method,
    };
    let svg = figure::error_time_figure(&mesh_points, against, Some(current), title);
    let refusal = figure::method_series(&mesh_points, against)
        .is_empty()
        .then(|| "no method gave a positive finite error against the reference".to_string());
    Ok(Drawn { svg, refusal })
}
