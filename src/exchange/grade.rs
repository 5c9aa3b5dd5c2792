//! `beamfric grade`: a student's answer file read (`answer`), certified by
//! [`crate::solve::grade`] — the certificate of the built-in methods: KKT residual of (38),
//! friction states, condition numbers, error against the reference (closed form (50)–(51) or
//! `condensed`) and warnings in words — and summed up in a [`Verdict`], as text or JSON.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use super::ExchangeError;
use super::answer::{AnswerFormat, AnswerShape, parse_answer};
use crate::fem::Mesh;
use crate::model::Problem;
use crate::output::{
    SolveContext, certificate_lines, condition_line, obstacle_lines, solution_json, warning_lines,
};
use crate::scene::{Refusal, read_regular_file};
use crate::solve::{KktGrade, Solution, SolveOptions, WarningCode, grade};

/// The grade in one word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Every check passed as for an exact built-in method: KKT conditions met to rounding,
    /// error against the reference at most 1e-10 (relative), forces and states agreeing.
    Exact,
    /// Close to a solution, with warnings that say how far and why.
    Approximate,
    /// The KKT check fails by more than 1e-2, or values are not finite.
    NotASolution,
}

impl Verdict {
    /// The verdict of a graded answer. Warnings about the scene rather than the answer (a
    /// raised mesh, A's conditioning) do not count against it.
    pub fn of(solution: &Solution) -> Verdict {
        if !solution.is_finite() || KktGrade::of(solution.kkt_residual) == KktGrade::NotASolution {
            return Verdict::NotASolution;
        }
        let about_the_answer = |code: WarningCode| {
            !matches!(
                code,
                WarningCode::MeshRaised | WarningCode::StiffnessConditioning
            )
        };
        if solution.warnings.iter().any(|w| about_the_answer(w.code)) {
            Verdict::Approximate
        } else {
            Verdict::Exact
        }
    }

    /// The code in JSON: `exact`, `approximate`, `not-a-solution`.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Exact => "exact",
            Verdict::Approximate => "approximate",
            Verdict::NotASolution => "not-a-solution",
        }
    }

    /// What it means, in words.
    pub fn meaning(self) -> &'static str {
        match self {
            Verdict::Exact => {
                "exact to rounding: the KKT conditions of (38) hold and the answer agrees with \
                 the reference as the built-in exact methods do"
            }
            Verdict::Approximate => "approximate: see the warnings for how far and why",
            Verdict::NotASolution => "not a solution of the discrete problem (38)",
        }
    }
}

/// A graded answer.
#[derive(Debug, Clone)]
pub struct Grade {
    /// The answer file.
    pub file: PathBuf,
    pub format: AnswerFormat,
    /// What the answer gave: `forces`, `nodal values` or `forces and nodal values`.
    pub given: &'static str,
    /// The answer with its certificate (forces and field completed from (48)).
    pub solution: Solution,
    pub verdict: Verdict,
}

/// What names the scene in a grade.
pub type GradeContext<'a> = SolveContext<'a>;

/// Reads and grades the answer in `file` for `problem` on `mesh`.
pub fn grade_file(problem: &Problem, mesh: &Mesh, file: &Path) -> Result<Grade, ExchangeError> {
    let shape = AnswerShape::new(problem, mesh);
    let answer_error = |error| ExchangeError::Answer {
        file: file.to_path_buf(),
        error,
    };
    // Read only as far as the largest answer for this scene can go: a file of 200 MB held
    // a gigabyte before its row count was refused.
    let limit = shape.most_bytes();
    let bytes = read_regular_file(file, limit).map_err(|refusal| match refusal {
        Refusal::Unreadable(e) => ExchangeError::Io {
            path: file.to_path_buf(),
            action: "read",
            reason: e.to_string(),
        },
        Refusal::NotRegular(kind) => ExchangeError::Io {
            path: file.to_path_buf(),
            action: "read",
            reason: format!("{kind}; an answer is read only from a regular file"),
        },
        Refusal::TooLarge => answer_error(super::AnswerError {
            field: "(document)".into(),
            rule: format!(
                "is larger than {limit} bytes, more than any answer for this scene needs \
                 ({} nodes, {} obstacles); not read",
                shape.nodes.len(),
                shape.obstacles.len()
            ),
        }),
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        answer_error(super::AnswerError {
            field: "(document)".into(),
            rule: format!("is not UTF-8 text ({e})"),
        })
    })?;
    let format = AnswerFormat::guess(file, &text);
    let answer = parse_answer(&text, format, &shape).map_err(answer_error)?;
    let given = match (&answer.forces, &answer.field) {
        (Some(_), Some(_)) => "forces and nodal values",
        (Some(_), None) => "forces",
        _ => "nodal values",
    };
    let solution = grade(problem, mesh, answer, &SolveOptions::default()).map_err(|error| {
        ExchangeError::Grade {
            file: file.to_path_buf(),
            error,
        }
    })?;
    Ok(Grade {
        file: file.to_path_buf(),
        format,
        given,
        verdict: Verdict::of(&solution),
        solution,
    })
}

impl Grade {
    /// What the answer gave and what was rebuilt, in words.
    fn given_in_words(&self) -> String {
        match self.given {
            "forces" => "friction forces λ; u, u' rebuilt from (48) on the exported A".into(),
            "nodal values" => "nodal u, u'; λ = (b − A c) on the friction rows of (48)".into(),
            other => format!("{other}, graded as given"),
        }
    }

    /// The grade as text: heading, obstacles, verdict, the certificate, warnings.
    pub fn text(&self, context: &GradeContext) -> String {
        let solution = &self.solution;
        let mut lines = vec![
            format!(
                "Grade of {} — {} ({}), {} elements, N = {} unknowns",
                crate::format::printable(&self.file.display().to_string()),
                crate::format::printable(context.title),
                crate::format::printable(context.source),
                context.mesh.elements(),
                context.mesh.unknowns()
            ),
            format!("given            {}", self.given_in_words()),
            String::new(),
        ];
        obstacle_lines(&mut lines, solution);
        lines.push(format!("grade            {}", self.verdict.meaning()));
        certificate_lines(&mut lines, solution);
        condition_line(&mut lines, solution);
        warning_lines(&mut lines, solution);
        lines.iter().map(|l| format!("{l}\n")).collect()
    }

    /// The grade as JSON: the document of `beamfric solve --format json` without what only a
    /// method has (method, ε, timing, details, `at`), with `answer` and `grade` added.
    pub fn json(&self, context: &GradeContext) -> Value {
        let mut document = solution_json(context, &self.solution, true, &[]);
        if let Value::Object(map) = &mut document {
            for key in ["method", "epsilon", "timing", "details", "at"] {
                map.remove(key);
            }
            map.insert(
                "answer".into(),
                json!({
                    "file": self.file.display().to_string(),
                    "format": match self.format {
                        AnswerFormat::Json => "json",
                        AnswerFormat::Csv => "csv",
                    },
                    "given": self.given,
                }),
            );
            map.insert(
                "grade".into(),
                json!({
                    "verdict": self.verdict.name(),
                    "meaning": self.verdict.meaning(),
                    "kkt": match KktGrade::of(self.solution.kkt_residual) {
                        _ if self.solution.kkt_residual.is_nan() => "not-finite",
                        KktGrade::Close => "close",
                        KktGrade::Approximate => "approximate",
                        KktGrade::NotASolution => "not-a-solution",
                    },
                }),
            );
        }
        document
    }
}
