//! The command line (clap): the commands behind the argument types of `cli/args.rs`. `main.rs`
//! parses and calls [`dispatch`]; everything else lives here and in the modules it calls.

use serde_json::json;
use std::process::ExitCode;

use crate::fem::Mesh;
use crate::output::{SolveContext, json_text, refusal_json, solution_json, solution_table};
use crate::scene::{self, LoadedScene};
use crate::solve::{Method, SolveOptions, WarningCode, solve};

mod args;
mod error;
mod history;

pub use args::*;
pub use error::CliError;
use error::write_stdout;

/// A line on stderr. Unlike `eprintln!`, a closed stderr (a terminal that went away) is no
/// reason to panic.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// Text on stderr without a new line (the progress line), failures ignored as by [`say!`].
macro_rules! say_inline {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

pub mod exchange;
mod figure;

/// Exit status for bad input (scene, arguments).
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit status when the method gave no solution (refused, not applicable, broke down).
pub const EXIT_NO_SOLUTION: u8 = 3;
/// Exit status of `solve` when the solution has non-finite values: it is printed (with `null`
/// or `n/a` in their place and the `non-finite` warning) but is no answer a script should use.
pub const EXIT_NOT_FINITE: u8 = 4;

/// Exit status when a check failed.
pub const EXIT_CHECK_FAILED: u8 = 1;

/// Prints a clap error: help and version as clap formats them, anything else as one line.
pub fn report_usage_error(error: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match error.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            // Written as every output is: a full disk is an error, a closed pipe is not.
            match error::write_stdout(&error.render().to_string()) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    say!("beamfric: {e}");
                    ExitCode::from(EXIT_BAD_INPUT)
                }
            }
        }
        _ => {
            let text = error.to_string();
            // The first line, with what it lists on the lines under it (clap puts the missing
            // arguments there: "the following required arguments were not provided:").
            let mut lines = text.lines();
            let mut message = lines.next().unwrap_or("invalid arguments").to_string();
            if message.ends_with(':') {
                for item in lines.take_while(|l| l.starts_with(' ')) {
                    message.push(' ');
                    message.push_str(item.trim());
                }
            } else if let Some(values) = lines.find(|l| l.trim().starts_with("[possible values")) {
                // A value not among the choices: name them.
                message.push(' ');
                message.push_str(values.trim());
            }
            say!("beamfric: {}", message.trim_start_matches("error: "));
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

/// Runs the parsed command line.
pub fn dispatch(cli: Cli) -> ExitCode {
    let result = match cli.command {
        Some(Command::Solve(args)) => solve_command(&args),
        Some(Command::Check(args)) => check_command(&args),
        Some(Command::Render(args)) => render_command(&args),
        Some(Command::Sweep(SweepCommand::Epsilon(args))) => epsilon_sweep_command(&args),
        Some(Command::Sweep(SweepCommand::Elements(args))) => elements_sweep_command(&args),
        Some(Command::Report(args)) => report_command(&args),
        Some(Command::Figure(args)) => figure::figure_command(&args),
        Some(Command::Serve(args)) => serve_command(&args),
        Some(Command::Present(args)) => present_command(&args),
        Some(Command::Export(args)) => exchange::export_command(&args),
        Some(Command::Grade(args)) => exchange::grade_command(&args),
        None => explore(
            cli.scene.as_deref().unwrap_or("benchmark-1"),
            &cli.lesson,
            &cli.display,
        ),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            say!("beamfric: {message}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

/// Loads a scene and applies command-line overrides, checked by the scene's rules for those
/// fields (the physics is validated once, by loading: the overrides do not change it).
pub fn load_with_overrides(
    name: &str,
    method: Option<Method>,
    elements: Option<usize>,
    epsilon: Option<f64>,
) -> Result<LoadedScene, CliError> {
    let mut loaded = scene::load(name)?;
    if let Some(n) = elements {
        scene::check_elements(n)
            .map_err(|rule| CliError::Argument(format!("--elements {rule}")))?;
        loaded.scene.mesh.elements = n;
        loaded.settings.elements = n;
    }
    if let Some(e) = epsilon {
        scene::check_epsilon(e).map_err(|rule| CliError::Argument(format!("--epsilon {rule}")))?;
        loaded.scene.solver.epsilon = e;
        loaded.settings.epsilon = e;
    }
    if let Some(m) = method {
        loaded.scene.solver.method = m;
        loaded.settings.method = m;
    }
    Ok(loaded)
}

/// Colours unless the user or the NO_COLOR convention (any non-empty value) says no.
fn colors_wanted(no_color: bool) -> bool {
    !no_color && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
}

/// The look of an explorer drawn on this process's terminal: ASCII when asked or when the
/// locale is not UTF-8, colours unless refused.
fn local_look(display: &DisplayArgs) -> crate::plot::Look {
    crate::plot::Look {
        ascii: display.ascii
            || !crate::plot::locale_is_utf8(
                |name| std::env::var(name).ok(),
                crate::plot::UnsetLocale::Ascii,
            ),
        color: colors_wanted(display.no_color),
    }
}

/// The scene to open and the lesson place, from a scene name or `--lesson FILE [--step K]`.
fn open_scene(
    name: &str,
    lesson: &LessonArgs,
) -> Result<(LoadedScene, Option<crate::tui::state::LessonPlace>), CliError> {
    let Some(path) = &lesson.lesson else {
        return Ok((scene::load(name)?, None));
    };
    let step = lesson.step.unwrap_or(1);
    let lesson = crate::lesson::read_lesson(path)?;
    let count = lesson.steps.len();
    if step == 0 || step > count {
        return Err(CliError::Argument(format!(
            "--step {step}: {} has {count} step{}, counted from 1 (from 1 to {count})",
            crate::format::printable(&path.display().to_string()),
            if count == 1 { "" } else { "s" }
        )));
    }
    let place = crate::tui::state::LessonPlace {
        lesson: std::sync::Arc::new(lesson),
        step: step - 1,
    };
    Ok((place.current().scene.clone(), Some(place)))
}

fn explore(name: &str, lesson: &LessonArgs, display: &DisplayArgs) -> Result<ExitCode, CliError> {
    use std::io::IsTerminal;
    if !std::io::stdout().is_terminal() {
        return Err(CliError::NotATerminal(
            "the explorer draws on a terminal, and standard output is not one; `beamfric \
             render` prints a frame as text",
        ));
    }
    let (loaded, lesson) = open_scene(name, lesson)?;
    let (palette, markers) = display.palette_and_markers();
    let options = crate::tui::state::Options {
        palette,
        markers,
        mouse: !display.no_mouse,
        show_timings: true,
        lesson,
        ..crate::tui::state::Options::new(local_look(display))
    };
    let ending = crate::tui::explore(loaded, options)?;
    Ok(exit_code(ending))
}

/// The exit status after the explorer ended.
fn exit_code(ending: crate::tui::Ending) -> ExitCode {
    match ending {
        crate::tui::Ending::Quit => ExitCode::SUCCESS,
        // The conventional status of a process ended by a signal.
        crate::tui::Ending::Signal(signal) => ExitCode::from((128 + signal) as u8),
        // As if by SIGHUP: the terminal went away.
        crate::tui::Ending::Hangup => ExitCode::from(128 + 1),
        // Only served sessions have an idle timeout.
        crate::tui::Ending::Idle => ExitCode::SUCCESS,
    }
}

#[cfg(unix)]
fn serve_command(args: &ServeArgs) -> Result<ExitCode, CliError> {
    crate::serve::serve_until_stopped(&serve_options(args))?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(unix)]
fn present_command(args: &PresentArgs) -> Result<ExitCode, CliError> {
    use std::io::IsTerminal;
    if !std::io::stdout().is_terminal() {
        return Err(CliError::NotATerminal(
            "present draws your explorer on this terminal, and standard output is not one; \
             `beamfric serve` serves without it",
        ));
    }
    Ok(exit_code(crate::serve::present(
        &serve_options(&args.serve),
        local_look(&args.serve.display),
        args.record.as_deref(),
    )?))
}

#[cfg(not(unix))]
fn present_command(_args: &PresentArgs) -> Result<ExitCode, CliError> {
    Err(CliError::Unsupported("present needs a Unix system"))
}

#[cfg(unix)]
fn serve_options(args: &ServeArgs) -> crate::serve::ServeOptions {
    crate::serve::ServeOptions {
        listen: args.listen.clone(),
        host_key: args.host_key.clone(),
        authorized_keys: args.authorized_keys.clone(),
        presenter_keys: args.presenter_keys.clone(),
        password_file: args.password_file.clone(),
        open: args.open,
        max_sessions: args.max_sessions,
        memory_budget_mib: args.memory_budget,
        max_elements: args.max_elements,
        idle_timeout: (args.idle_timeout > 0)
            .then(|| std::time::Duration::from_secs(args.idle_timeout)),
        mouse: !args.display.no_mouse,
        ascii: args.display.ascii,
        color: !args.display.no_color,
        palette: args.display.palette_and_markers().0,
        markers: args.display.palette_and_markers().1,
        scene: args.scene.clone(),
        lesson: args.lesson.clone(),
        save_dir: args.save_dir.clone(),
    }
}

#[cfg(not(unix))]
fn serve_command(_args: &ServeArgs) -> Result<ExitCode, CliError> {
    Err(CliError::Unsupported("serve needs a Unix system"))
}

fn render_command(args: &RenderArgs) -> Result<ExitCode, CliError> {
    let keys = crate::tui::input::keys::parse_keys(&args.keys)
        .map_err(|unknown| CliError::Argument(format!("--keys: {unknown}")))?;
    let (loaded, lesson) = open_scene(&args.scene, &args.lesson)?;
    let (palette, markers) = args::chosen_look(args.theme, args.marker, args.projector);
    let options = crate::tui::RenderOptions {
        lesson,
        width: args.size.0,
        height: args.size.1,
        look: crate::plot::Look {
            ascii: args.ascii,
            color: args.color,
        },
        palette,
        markers,
        timings: args.timings,
        allow_save: args.allow_save.clone(),
    };
    let buffer = crate::tui::render(loaded, &keys, options)?;
    let text = crate::plot::buffer_to_text(&buffer, args.color);
    write_stdout(&text)?;
    Ok(ExitCode::SUCCESS)
}

/// A progress line on stderr, only when stderr is a terminal.
struct ProgressLine {
    label: &'static str,
    enabled: bool,
}

impl ProgressLine {
    fn new(label: &'static str) -> ProgressLine {
        use std::io::IsTerminal;
        ProgressLine {
            label,
            enabled: std::io::stderr().is_terminal(),
        }
    }

    fn report(&self, done: usize, total: usize, what: &str) {
        if !self.enabled || total == 0 {
            return;
        }
        let width = 24;
        let filled = done * width / total;
        say_inline!(
            "\r{} [{}{}] {done}/{total} {what:<32}",
            self.label,
            "#".repeat(filled),
            ".".repeat(width - filled)
        );
    }

    fn finish(&self) {
        if self.enabled {
            say_inline!("\r{}\r", " ".repeat(80));
        }
    }
}

fn check_count(
    what: &str,
    value: usize,
    range: std::ops::RangeInclusive<usize>,
) -> Result<(), CliError> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(CliError::Argument(format!(
            "{what} {value}: must be from {} to {}",
            range.start(),
            range.end()
        )))
    }
}

/// The mesh sizes and repeats of a sweep over n, checked: sizes the scene rules allow, from
/// the smaller to the larger, at most 200 of them, at most 100 runs each.
fn check_mesh_sweep(sizes: &MeshSizes, repeat: usize) -> Result<(), CliError> {
    check_elements_range(sizes.from, sizes.to)?;
    check_count("--points", sizes.points, 1..=MAX_MESH_POINTS)?;
    check_count("--repeat", repeat, 1..=MAX_REPEAT)
}

/// The mesh sizes asked for.
fn mesh_sizes(sizes: &MeshSizes) -> Vec<usize> {
    crate::study::mesh_sizes(sizes.from, sizes.to, sizes.points)
}

fn check_elements_range(from: usize, to: usize) -> Result<(), CliError> {
    scene::check_elements(from).map_err(|rule| CliError::Argument(format!("--from {rule}")))?;
    scene::check_elements(to).map_err(|rule| CliError::Argument(format!("--to {rule}")))?;
    if from > to {
        return Err(CliError::Argument(format!(
            "--from {from} is larger than --to {to}"
        )));
    }
    Ok(())
}

/// Prints a sweep as CSV, or as a JSON document.
fn print_table(
    format: TableFormat,
    csv: impl FnOnce() -> String,
    json: impl FnOnce() -> serde_json::Value,
) -> Result<(), CliError> {
    write_stdout(&match format {
        TableFormat::Csv => csv(),
        TableFormat::Json => json_text(&json()),
    })
}

fn epsilon_sweep_command(args: &EpsilonSweepArgs) -> Result<ExitCode, CliError> {
    for (name, value) in [("--from", args.from), ("--to", args.to)] {
        scene::check_epsilon(value).map_err(|rule| CliError::Argument(format!("{name} {rule}")))?;
    }
    if args.from > args.to {
        return Err(CliError::Argument(format!(
            "--from {} is larger than --to {}",
            args.from, args.to
        )));
    }
    check_count("--points", args.points, 1..=MAX_EPSILON_POINTS)?;
    if !args.method.is_regularized() {
        return Err(CliError::Argument(format!(
            "--method {}: the ε sweep needs regularized or regularized-newton",
            args.method
        )));
    }
    let LoadedScene {
        source,
        problem,
        settings,
        ..
    } = load_with_overrides(&args.scene, None, args.elements, None)?;
    let epsilons = crate::study::log_space(args.from, args.to, args.points);
    let progress = ProgressLine::new("sweep epsilon");
    let result = crate::study::epsilon_sweep(
        &problem,
        settings.elements,
        args.method,
        &epsilons,
        &crate::solve::Cancellation::NEVER,
        &|done, total, what| progress.report(done, total, what),
    );
    progress.finish();
    let points = match result.expect("never cancelled") {
        Ok(points) => points,
        Err(e) => {
            say!("beamfric: {}", crate::study::sweep_refusal(&e));
            return Ok(ExitCode::from(EXIT_NO_SOLUTION));
        }
    };
    print_table(
        args.format,
        || crate::output::epsilon_sweep_csv(&points),
        || {
            let ran_with = [
                ("method", json!(args.method.name())),
                ("elements", json!(settings.elements)),
            ];
            crate::output::sweep_json(&source, &ran_with, &points)
        },
    )?;
    Ok(ExitCode::SUCCESS)
}

fn elements_sweep_command(args: &ElementsSweepArgs) -> Result<ExitCode, CliError> {
    check_mesh_sweep(&args.sizes, args.repeat)?;
    let LoadedScene {
        source,
        problem,
        settings,
        ..
    } = load_with_overrides(&args.scene, None, None, args.epsilon)?;
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };
    let sizes = mesh_sizes(&args.sizes);
    let progress = ProgressLine::new("sweep elements");
    let points = crate::study::mesh_sweep(
        &problem,
        &methods,
        &sizes,
        args.repeat,
        settings.epsilon,
        &crate::solve::Cancellation::NEVER,
        &|done, total, what| progress.report(done, total, what),
    )
    .expect("never cancelled");
    progress.finish();
    print_table(
        args.format,
        || crate::output::mesh_sweep_csv(&points),
        || {
            let ran_with = [
                ("repeat", json!(args.repeat)),
                ("epsilon", json!(settings.epsilon)),
            ];
            crate::output::sweep_json(&source, &ran_with, &points)
        },
    )?;
    Ok(ExitCode::SUCCESS)
}

fn report_command(args: &ReportArgs) -> Result<ExitCode, CliError> {
    check_mesh_sweep(&args.sizes, args.repeat)?;
    let loaded = scene::load(&args.scene)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| format!("report-{}", loaded.source.stem()));
    // Checked before measuring, not after.
    let destination = crate::report::prepare(std::path::Path::new(&out), args.force)?;
    let options = crate::report::ReportOptions {
        sizes: mesh_sizes(&args.sizes),
        repeat: args.repeat,
        epsilons: crate::study::log_space(1e-16, 1.0, 33),
        command: format!(
            "beamfric report --scene {} --out {out} --from {} --to {} --points {} --repeat {}",
            args.scene, args.sizes.from, args.sizes.to, args.sizes.points, args.repeat
        ),
    };
    let progress = ProgressLine::new("report");
    let report = crate::report::build(&loaded, &options, &|done, total, what| {
        progress.report(done, total, what)
    });
    progress.finish();
    let written = crate::report::write(&report, &destination)?;
    for path in written {
        say!("wrote {path}");
    }
    Ok(ExitCode::SUCCESS)
}

fn check_command(args: &CheckArgs) -> Result<ExitCode, CliError> {
    let reports = match &args.scene {
        Some(name) => {
            let loaded = scene::load(name)?;
            vec![crate::check::check_scene(
                &loaded.source.to_string(),
                &loaded.scene,
            )]
        }
        None => crate::check::check_all(),
    };
    let text = match args.format {
        CheckFormat::Markdown => crate::check::markdown(&reports),
        CheckFormat::Json => json_text(&reports),
    };
    write_stdout(&text)?;
    let failed = reports.iter().filter(|r| !r.passed()).count();
    if failed > 0 {
        say!("beamfric: {failed} of {} cases failed", reports.len());
        return Ok(ExitCode::from(EXIT_CHECK_FAILED));
    }
    Ok(ExitCode::SUCCESS)
}

fn solve_command(args: &SolveArgs) -> Result<ExitCode, CliError> {
    let LoadedScene {
        scene,
        source,
        problem,
        settings,
    } = load_with_overrides(&args.scene, args.method, args.elements, args.epsilon)?;
    let source = source.to_string();
    for &x in &args.at {
        if !(x.is_finite() && (0.0..=problem.length).contains(&x)) {
            return Err(CliError::Argument(format!(
                "--at {x}: positions must lie on the beam, in [0, {}] m",
                problem.length
            )));
        }
    }
    history::check_format(args.format, args.history)?;
    let mesh = Mesh::new(&problem, settings.elements);
    let options = SolveOptions {
        epsilon: settings.epsilon,
        condition: args.condition,
        history: args.history,
        ..SolveOptions::default()
    };
    let context = SolveContext {
        source: &source,
        title: &scene.title,
        mesh: &mesh,
    };
    match solve(&problem, &mesh, settings.method, &options) {
        Ok(solution) => {
            let at: Vec<_> = args
                .at
                .iter()
                .map(|&x| (x, solution.field.at(&mesh, x)))
                .collect();
            let text = match args.format {
                Format::Json => json_text(&solution_json(&context, &solution, !args.no_nodes, &at)),
                Format::Table => solution_table(&context, &solution, &at, true),
                Format::Csv => history::csv_text(&solution),
            };
            write_stdout(&text)?;
            // Exactly when the user is told, by the `non-finite` warning.
            if solution.has_warning(WarningCode::NonFinite) {
                say!(
                    "beamfric: {} gave non-finite values: see the warnings",
                    settings.method
                );
                Ok(ExitCode::from(EXIT_NOT_FINITE))
            } else {
                Ok(ExitCode::SUCCESS)
            }
        }
        Err(error) => {
            if args.format == Format::Json {
                write_stdout(&json_text(&refusal_json(&context, &error)))?;
            }
            say!("beamfric: {error}");
            Ok(ExitCode::from(EXIT_NO_SOLUTION))
        }
    }
}
