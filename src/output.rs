//! What `beamfric solve` prints: the JSON document (schema in the README) and the human table;
//! `history` the convergence history of `--history`.
//! Non-finite numbers become `null` in JSON and `n/a` in tables, always with a warning.

use serde::Serialize;
use serde_json::{Value, json};

use crate::fem::{Mesh, PointValues};
use crate::format::{duration, printable, sci};
use crate::linalg::condition::ConditionNumber;
use crate::solve::{Method, Reference, Solution, SolveError};

mod history;

pub use history::{history_csv, history_json};

/// What the output needs to know besides the solution.
pub struct SolveContext<'a> {
    /// File path or `preset <name>`.
    pub source: &'a str,
    pub title: &'a str,
    pub mesh: &'a Mesh,
}

fn number(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn numbers(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|&x| number(x)).collect())
}

fn to_value<T: Serialize>(v: &T) -> Value {
    serde_json::to_value(v).unwrap_or(Value::Null)
}

/// The JSON document of a solution. `nodes` includes x, u, slope at every node; `at` the
/// values at requested positions.
pub fn solution_json(
    context: &SolveContext,
    solution: &Solution,
    nodes: bool,
    at: &[(f64, PointValues)],
) -> Value {
    let t = &solution.timing;
    let mut document = json!({
        "scene": context.source,
        "title": context.title,
        "method": solution.method.name(),
        "elements": context.mesh.elements(),
        "unknowns": context.mesh.unknowns(),
        "epsilon": solution.epsilon,
        "at": at.iter().map(|(x, p)| json!({
            "x": number(*x),
            "u": number(p.deflection),
            "slope": number(p.slope),
            "moment": number(p.moment),
            "shear": number(p.shear),
        })).collect::<Vec<_>>(),
        "obstacles": solution.obstacles.iter().map(|o| json!({
            "x": number(o.x),
            "u": number(o.u),
            "slope": number(o.slope),
            "force": number(o.force),
            "moment": number(o.moment),
            "sliding": o.sliding,
            "swivel": o.swivel,
            "state": { "sliding": o.sliding_state.name(), "swivel": o.swivel_state.name() },
        })).collect::<Vec<_>>(),
        "kkt_residual": number(solution.kkt_residual),
        "error": solution.error.as_ref().map(to_value),
        "timing": {
            "unit": "s",
            "assembly": t.assembly.as_secs_f64(),
            "factorization": t.factorization.as_secs_f64(),
            "friction_stage": t.friction_stage.as_secs_f64(),
            "reconstruction": t.reconstruction.as_secs_f64(),
            "total": t.total().as_secs_f64(),
        },
        "condition": to_value(&solution.conditioning),
        "details": to_value(&solution.details),
        "warnings": to_value(&solution.warnings),
    });
    if let Some(history) = &solution.history {
        document["history"] = history_json(history);
    }
    if nodes {
        document["nodes"] = json!({
            "x": numbers(&context.mesh.nodes),
            "u": numbers(&solution.field.deflection),
            "slope": numbers(&solution.field.slope),
        });
    }
    document
}

/// The JSON document when the method gave no solution.
pub fn refusal_json(context: &SolveContext, error: &SolveError) -> Value {
    json!({
        "scene": context.source,
        "title": context.title,
        "method": error.method.name(),
        "elements": context.mesh.elements(),
        "refused": {
            "kind": error.kind.name(),
            "reason": error.reason,
            "suggestion": error.suggestion.name(),
        },
    })
}

/// The human-readable summary of a solution: the heading, the obstacles, the requested
/// points, the certificate (max |u|, KKT, error, condition numbers), how the method ran and
/// the warnings.
pub fn solution_table(
    context: &SolveContext,
    solution: &Solution,
    at: &[(f64, PointValues)],
    show_time: bool,
) -> String {
    let mut lines = Vec::new();
    heading_lines(&mut lines, context, solution);
    obstacle_lines(&mut lines, solution);
    point_lines(&mut lines, at);
    certificate_lines(&mut lines, solution);
    condition_line(&mut lines, solution);
    detail_lines(&mut lines, solution, show_time);
    warning_lines(&mut lines, solution);
    lines.iter().map(|l| format!("{l}\n")).collect()
}

/// A JSON document as the commands print it: pretty, with a final new line, and every control
/// character escaped — serde_json escapes those below U+0020 in strings, and this the rest
/// (DEL and the C1 controls, which it leaves raw and a terminal may act on) as `\u00XX`.
/// Outside strings pretty JSON has no control character but its new lines.
pub fn json_text(value: &impl Serialize) -> String {
    let text = serde_json::to_string_pretty(value).expect("JSON values serialize");
    let mut out = String::with_capacity(text.len() + 1);
    for c in text.chars() {
        if c.is_control() && c != '\n' {
            out.push_str(&format!("\\u{:04x}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    out.push('\n');
    out
}

fn heading_lines(lines: &mut Vec<String>, context: &SolveContext, solution: &Solution) {
    let eps = solution
        .epsilon
        .map(|e| format!(", ε = {}", sci(e, 2)))
        .unwrap_or_default();
    lines.push(format!(
        "{} ({}) — method {}, {} elements, N = {} unknowns{eps}",
        printable(context.title),
        printable(context.source),
        solution.method,
        context.mesh.elements(),
        context.mesh.unknowns()
    ));
    lines.push(String::new());
}

pub(crate) fn obstacle_lines(lines: &mut Vec<String>, solution: &Solution) {
    if solution.obstacles.is_empty() {
        return;
    }
    lines.push(format!(
        "{:>3}  {:>10}  {:>12}  {:>12}  {:>12}  {:>12}  state",
        "#", "x [m]", "u [m]", "u' [rad]", "force [N]", "moment [N m]"
    ));
    for (i, o) in solution.obstacles.iter().enumerate() {
        lines.push(format!(
            "{:>3}  {:>10}  {:>12}  {:>12}  {:>12}  {:>12}  {}",
            i + 1,
            sci(o.x, 4),
            sci(o.u, 6),
            sci(o.slope, 6),
            sci(o.force, 6),
            sci(o.moment, 6),
            o.state()
        ));
    }
    lines.push(String::new());
}

fn point_lines(lines: &mut Vec<String>, at: &[(f64, PointValues)]) {
    for (x, p) in at {
        lines.push(format!(
            "at x = {} m: u = {} m, u' = {} rad, M = {} N m, T = {} N",
            sci(*x, 6),
            sci(p.deflection, 8),
            sci(p.slope, 8),
            sci(p.moment, 6),
            sci(p.shear, 6)
        ));
    }
    if !at.is_empty() {
        lines.push(String::new());
    }
}

pub(crate) fn certificate_lines(lines: &mut Vec<String>, solution: &Solution) {
    lines.push(format!(
        "max |u|          {} m",
        sci(solution.max_deflection(), 8)
    ));
    lines.push(format!(
        "KKT residual     {} (relative)",
        sci(solution.kkt_residual, 2)
    ));
    lines.push(match &solution.error {
        Some(e) => match (e.max_abs, e.max_rel, e.mean_abs) {
            (Some(max), Some(rel), Some(mean)) => format!(
                "error vs {:<11} max {} m ({} relative), mean {} m",
                e.reference.name(),
                sci(max, 2),
                sci(rel, 2),
                sci(mean, 2)
            ),
            _ if e.reference == Reference::ThisSolution => {
                "error            this solution is the reference".to_string()
            }
            _ => "error            n/a (non-finite values)".to_string(),
        },
        None => "error            not computed".to_string(),
    });
}

pub(crate) fn condition_line(lines: &mut Vec<String>, solution: &Solution) {
    let c = &solution.conditioning;
    let mut conds = Vec::new();
    let mut push = |name: &str, v: &Option<ConditionNumber>| {
        if let Some(v) = v {
            conds.push(format!("{name} {} {}", v.kind.symbol(), sci(v.value, 2)));
        }
    };
    push("cond(A)", &c.stiffness);
    push("cond(D^-1/2 A D^-1/2)", &c.stiffness_scaled);
    let over = match (solution.details.conditioned_cases, solution.details.cases) {
        (Some(used), Some(all)) if (used as u64) < all => format!(" (over {used} of {all} cases)"),
        _ => String::new(),
    };
    push(&format!("max cond(Â){over}"), &c.regularized_max);
    push(
        &format!("max cond(scaled Â){over}"),
        &c.regularized_scaled_max,
    );
    push("cond(S)", &c.dual);
    if !conds.is_empty() {
        lines.push(format!("condition        {}", conds.join(", ")));
    }
}

fn detail_lines(lines: &mut Vec<String>, solution: &Solution, show_time: bool) {
    let d = &solution.details;
    if let Some(cases) = d.cases {
        lines.push(format!("cases            {cases} enumerated"));
    }
    if let Some(it) = d.newton_iterations {
        lines.push(format!("Newton           {it} iterations"));
    }
    if let Some(solves) = d.linear_solves {
        lines.push(format!("friction search  {solves} linear solves"));
    }
    if show_time {
        let t = &solution.timing;
        // The stage on the friction DOFs by what the method does there; stages a method does
        // not have (0 s) are left out rather than shown as 0.0 µs.
        let friction_stage_name = match solution.method {
            Method::Condensed => "friction search",
            Method::Regularized | Method::RegularizedNewton => "friction DOFs",
            _ => "dual solve",
        };
        let stages: Vec<String> = [
            ("assembly", t.assembly),
            ("factorization", t.factorization),
            (friction_stage_name, t.friction_stage),
            ("reconstruction", t.reconstruction),
        ]
        .iter()
        .filter(|(_, d)| !d.is_zero())
        .map(|(name, d)| format!("{name} {}", duration(*d)))
        .collect();
        lines.push(if stages.is_empty() {
            format!("time             {}", duration(t.total()))
        } else {
            format!(
                "time             {} ({})",
                duration(t.total()),
                stages.join(", ")
            )
        });
    }
}

pub(crate) fn warning_lines(lines: &mut Vec<String>, solution: &Solution) {
    if solution.warnings.is_empty() {
        lines.push("warnings         none".to_string());
    } else {
        for w in &solution.warnings {
            lines.push(format!("warning          {}", w.message));
        }
    }
}

fn csv_number(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or(String::new(), |v| format!("{v:e}"))
}

fn warning_names(codes: impl Iterator<Item = crate::solve::WarningCode>) -> String {
    codes.map(|c| c.name()).collect::<Vec<_>>().join(";")
}

/// The mesh sweep as CSV: one row per method and mesh size. Numbers are empty where they
/// would mean nothing (a refused method, the reference itself), and `status` says why.
pub fn mesh_sweep_csv(points: &[crate::study::MeshPoint]) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    let _ = writer.write_record([
        "method",
        "elements",
        "epsilon",
        "status",
        "reference",
        "max_abs_m",
        "max_rel",
        "mean_abs_m",
        "mean_rel",
        "run_time_s",
        "kkt_residual",
        "warnings",
    ]);
    for p in points {
        let reference = p.error.map(|e| e.reference.name());
        let status = match &p.refused {
            Some(reason) => reason.clone(),
            None if p.is_reference() => "reference".into(),
            None if p.warnings.is_empty() => "ok".into(),
            None => "warned".into(),
        };
        let solved = p.refused.is_none();
        let e = p.error.filter(|_| solved);
        let _ = writer.write_record([
            p.method.name().to_string(),
            p.elements.to_string(),
            csv_number(p.epsilon),
            status,
            reference.unwrap_or_default().to_string(),
            csv_number(e.and_then(|e| e.max_abs)),
            csv_number(e.and_then(|e| e.max_rel)),
            csv_number(e.and_then(|e| e.mean_abs)),
            csv_number(e.and_then(|e| e.mean_rel)),
            csv_number(solved.then_some(p.run_time.as_secs_f64())),
            csv_number(p.kkt_residual),
            warning_names(p.warnings.iter().copied()),
        ]);
    }
    String::from_utf8(writer.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// The ε sweep as CSV: one row per ε.
pub fn epsilon_sweep_csv(points: &[crate::study::EpsPoint]) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    let _ = writer.write_record([
        "epsilon",
        "reference",
        "max_abs_m",
        "max_rel",
        "mean_abs_m",
        "mean_rel",
        "cond_max",
        "cond_max_kind",
        "cond_scaled_max",
        "cond_scaled_kind",
        "conditioned_cases",
        "run_time_s",
        "warnings",
    ]);
    let kind = |c: Option<ConditionNumber>| c.map_or("", |c| c.kind.name()).to_string();
    for p in points {
        let e = p.error;
        let reference = e.map_or("", |e| e.reference.name()).to_string();
        let _ = writer.write_record([
            format!("{:e}", p.epsilon),
            reference,
            csv_number(e.and_then(|e| e.max_abs)),
            csv_number(e.and_then(|e| e.max_rel)),
            csv_number(e.and_then(|e| e.mean_abs)),
            csv_number(e.and_then(|e| e.mean_rel)),
            csv_number(p.cond_max.map(|c| c.value)),
            kind(p.cond_max),
            csv_number(p.cond_scaled_max.map(|c| c.value)),
            kind(p.cond_scaled_max),
            p.conditioned_cases.map_or(String::new(), |c| c.to_string()),
            format!("{:e}", p.run_time.as_secs_f64()),
            warning_names(p.warnings.iter().map(|w| w.code)),
        ]);
    }
    String::from_utf8(writer.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// A sweep as one JSON document (`beamfric sweep … --format json`): the scene, what the sweep
/// ran with (`settings`: name and value pairs), and its points.
pub fn sweep_json(
    scene: &crate::scene::SceneSource,
    settings: &[(&str, Value)],
    points: &impl Serialize,
) -> Value {
    let mut document = serde_json::Map::new();
    document.insert("scene".into(), Value::String(scene.to_string()));
    for (name, value) in settings {
        document.insert((*name).into(), value.clone());
    }
    document.insert("points".into(), to_value(points));
    Value::Object(document)
}
