//! `beamfric export` and `beamfric grade` (bring your own method, issue 24): the thin commands
//! over [`crate::exchange`], which does the work (their arguments are in `args`).

use std::process::ExitCode;

use super::args::{ExportArgs, GradeArgs, GradeFormat};
use super::{CliError, EXIT_CHECK_FAILED, load_with_overrides};
use crate::exchange::{ExportedScene, GradeContext, Verdict, export, grade_file};
use crate::fem::Mesh;
use crate::output::json_text;

/// Runs `beamfric export`.
pub(super) fn export_command(args: &ExportArgs) -> Result<ExitCode, CliError> {
    let elements = args.elements;
    let loaded = load_with_overrides(&args.scene, None, elements, None)?;
    let mesh = Mesh::new(&loaded.problem, loaded.settings.elements);
    let source = loaded.source.to_string();
    let command_scene = match elements {
        Some(n) => format!("--scene {} --elements {n}", args.scene),
        None => format!("--scene {}", args.scene),
    };
    let scene = ExportedScene {
        title: &loaded.scene.title,
        source: &source,
        command_scene: &command_scene,
    };
    let written =
        export(&loaded.problem, &mesh, scene, &args.out, args.force).map_err(CliError::Exchange)?;
    for path in written {
        say!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// Runs `beamfric grade`: exit 0 for an exact answer, 1 for one graded otherwise.
pub(super) fn grade_command(args: &GradeArgs) -> Result<ExitCode, CliError> {
    let elements = args.elements;
    let loaded = load_with_overrides(&args.scene, None, elements, None)?;
    let mesh = Mesh::new(&loaded.problem, loaded.settings.elements);
    let graded = grade_file(&loaded.problem, &mesh, &args.answer).map_err(CliError::Exchange)?;
    let source = loaded.source.to_string();
    let context = GradeContext {
        source: &source,
        title: &loaded.scene.title,
        mesh: &mesh,
    };
    let text = match args.format {
        GradeFormat::Json => json_text(&graded.json(&context)),
        GradeFormat::Table => graded.text(&context),
    };
    super::error::write_stdout(&text)?;
    Ok(if graded.verdict == Verdict::Exact {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_CHECK_FAILED)
    })
}
