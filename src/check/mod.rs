//! The stability suite behind `beamfric check`: every method on a scene (each preset and each
//! hard case of issue 10 by default, [`HARD_CASES`]), judged from the outside.
//!
//! For each case it checks that no number is NaN or infinite (a stiffness-route result that is
//! not finite must say so and counts as a breakdown); that every method which does not flag
//! itself (a conditioning, indefinite-factorization, non-convergence, inconsistency or
//! `kkt-residual` warning) agrees with the condensed method to its own accuracy (1e-10 for
//! exact methods, an O(ε) bound for the regularised ones) — so a loss of digits is always
//! warned about; that the stiffness route
//! warns at 10⁶ elements; that the condensed method is within 1e-10 of every closed form that
//! applies (paper (50), the plain clamped beam for g = 0, clamped spans when every obstacle is
//! stuck); that scaling l, E and f changes u by the predicted factor; and that a refused method
//! names a method that then works.

mod closed_forms;
pub mod families;
mod hard;
mod many;

use serde::Serialize;

use crate::fem::{Mesh, NodalField};
use crate::format::sci;
use crate::model::Problem;
use crate::scene::{PRESETS, Scene};
use crate::solve::{
    ConditionLevel, Method, Solution, SolveError, SolveErrorKind, SolveOptions, WarningCode, solve,
};

pub use closed_forms::closed_forms;
pub use hard::HARD_CASES;
pub use many::{MANY_SIZES, check_families, check_family};

/// Accuracy an exact method must reach when it raises no flag (the accuracy-loss threshold and
/// the acceptance bound of issue 10).
const EXACT_TOLERANCE: f64 = 1e-10;
/// The condensed method against a closed form.
const CLOSED_FORM_TOLERANCE: f64 = 1e-10;
/// The condensed method against its own scaled problem.
const SCALING_TOLERANCE: f64 = 1e-12;
/// Scaling used for the scaling check: l → αl, E → βE, f → γf (u scales by γα⁴/β). All three
/// are powers of two so that every input scales exactly and the scaled problem is the same
/// problem: an obstacle 2e-9·l from a support must stay exactly that far (10·x moves it by an
/// ulp of x, 5e-8 of that distance), and a threshold equal to its stuck force to the last bit
/// must stay equal to it (× 7 and × 56 round the force and the threshold apart, and such a
/// knife-edge state flips: `presets::the_scaling_check_keeps_thresholds_tied_to_the_last_bit_tied`).
const SCALING: (f64, f64, f64) = (8.0, 4.0, 16.0);

/// How one method fared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodRun {
    pub method: Method,
    /// `solved`, `refused`, `not-applicable` or `breakdown`.
    pub outcome: String,
    /// max relative nodal difference from the condensed method (u and u').
    pub disagreement: Option<f64>,
    pub kkt_residual: Option<f64>,
    /// The method flagged its own result as unreliable.
    pub flagged: bool,
    pub warnings: Vec<WarningCode>,
}

/// The verdict on one case.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseReport {
    pub case: String,
    pub elements: usize,
    pub runs: Vec<MethodRun>,
    /// Largest disagreement among the exact methods that do not flag themselves.
    pub max_disagreement: Option<f64>,
    /// Largest disagreement of the regularised methods (an O(ε) error by design).
    pub regularized_disagreement: Option<f64>,
    /// Condensed against each closed form that applies: (name, relative error).
    pub closed_forms: Vec<(String, f64)>,
    /// Largest KKT residual among the exact methods that do not flag themselves.
    pub kkt_residual: Option<f64>,
    /// Relative error of the scaled problem against the predicted factor.
    pub scaling: Option<f64>,
    /// What went wrong; empty when the case passes.
    pub failures: Vec<String>,
}

impl CaseReport {
    /// Did every check pass?
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }
}

fn options(epsilon: f64) -> SolveOptions {
    SolveOptions {
        epsilon,
        condition: ConditionLevel::Off,
        reference: false,
        ..SolveOptions::default()
    }
}

fn relative_difference(a: &NodalField, b: &NodalField) -> f64 {
    let rel = |x: &[f64], y: &[f64]| {
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0f64, |m, d| if d.is_nan() { f64::NAN } else { m.max(d) });
        if scale > 0.0 { diff / scale } else { diff }
    };
    let (u, s) = (rel(&a.deflection, &b.deflection), rel(&a.slope, &b.slope));
    if u.is_nan() || s.is_nan() {
        f64::NAN
    } else {
        u.max(s)
    }
}

/// Did the method flag its own result, from its own computation (not from the comparison
/// with the reference, which `check` makes itself)?
fn is_flagged(solution: &Solution) -> bool {
    solution.warnings.iter().any(|w| {
        matches!(
            w.code,
            WarningCode::StiffnessConditioning
                | WarningCode::IndefiniteFactorization
                | WarningCode::QpNotConverged
                | WarningCode::NewtonNotConverged
                | WarningCode::KktResidual
                | WarningCode::RegularizationInconsistent
        )
    })
}

/// What a regularised solution may differ by: every stuck DOF is held within ε instead of at
/// zero, which moves u by at most a few ε per DOF (times l for a rotation).
fn regularized_tolerance(problem: &Problem, epsilon: f64, largest: f64) -> f64 {
    let dofs = 2.0 * problem.obstacles.len() as f64;
    EXACT_TOLERANCE + 10.0 * dofs * epsilon * problem.length.max(1.0) / largest
}

/// The verdict on one solved method: NaN or infinity anywhere fails; so does a disagreement
/// beyond the method's own accuracy unless the method flagged its result as unreliable.
fn judge(
    method: Method,
    finite: bool,
    disagreement: f64,
    tolerance: f64,
    flagged: bool,
) -> Option<String> {
    if !finite {
        Some(format!("{method}: NaN or infinite values"))
    } else if !flagged && disagreement > tolerance {
        Some(format!(
            "{method}: differs from condensed by {} (tolerance {}) without a warning",
            sci(disagreement, 2),
            sci(tolerance, 2)
        ))
    } else {
        None
    }
}

/// The scene with l → αl, E → βE, f → γf and the thresholds scaled so that every friction
/// state stays the same (g1 like f·l, g2 like f·l²).
pub fn scaled_scene(scene: &Scene, (alpha, beta, gamma): (f64, f64, f64)) -> Scene {
    let mut scaled = scene.clone();
    scaled.beam.length *= alpha;
    scaled.beam.young *= beta;
    for segment in &mut scaled.beam.segments {
        segment.from *= alpha;
        segment.to *= alpha;
        segment.young = segment.young.map(|e| e * beta);
    }
    scaled.load.f0 *= gamma;
    scaled.load.f1 = scaled.load.f1.map(|f| f * gamma);
    for o in &mut scaled.obstacles {
        o.x *= alpha;
        o.sliding *= gamma * alpha;
        o.swivel *= gamma * alpha * alpha;
    }
    scaled
}

impl CaseReport {
    /// The report of `case` before anything has run.
    fn empty(case: &str, elements: usize) -> CaseReport {
        CaseReport {
            case: case.to_string(),
            elements,
            runs: Vec::new(),
            max_disagreement: None,
            regularized_disagreement: None,
            closed_forms: Vec::new(),
            kkt_residual: None,
            scaling: None,
            failures: Vec::new(),
        }
    }
}

/// Runs the suite on one scene: every method against the condensed method, then the closed
/// forms and the scaling law.
pub fn check_scene(case: &str, scene: &Scene) -> CaseReport {
    let mut report = CaseReport::empty(case, scene.mesh.elements);
    let (problem, settings) = match scene.validate(case) {
        Ok(valid) => valid,
        Err(e) => {
            report.failures.push(format!("does not validate: {e}"));
            return report;
        }
    };
    let mesh = Mesh::new(&problem, settings.elements);
    report.elements = mesh.elements();
    let epsilon = settings.epsilon;
    let reference = match solve(&problem, &mesh, Method::Condensed, &options(epsilon)) {
        Ok(s) => s,
        Err(e) => {
            report.failures.push(format!("condensed failed: {e}"));
            return report;
        }
    };
    if !reference.is_finite() {
        report
            .failures
            .push("condensed: NaN or infinite values".into());
        return report;
    }
    let bench = Bench {
        problem: &problem,
        mesh: &mesh,
        epsilon,
        largest: reference.max_deflection().max(f64::MIN_POSITIVE),
        reference: &reference,
    };
    for method in Method::ALL {
        let run = bench.judge(method, &mut report.failures);
        report.runs.push(run);
    }
    summarize(&mut report);
    check_closed_forms(&bench, &mut report);
    report.scaling = Some(check_scaling(
        scene,
        &mesh,
        &reference,
        &mut report.failures,
    ));
    report
}

/// What every method of one case is judged against.
struct Bench<'a> {
    problem: &'a Problem,
    mesh: &'a Mesh,
    epsilon: f64,
    /// The condensed method's solution.
    reference: &'a Solution,
    /// Its largest |u| (never zero).
    largest: f64,
}

impl Bench<'_> {
    /// Runs one method and judges it; failures go to `failures`.
    fn judge(&self, method: Method, failures: &mut Vec<String>) -> MethodRun {
        match solve(self.problem, self.mesh, method, &options(self.epsilon)) {
            Ok(solution) => self.solved(method, &solution, failures),
            Err(error) => self.declined(method, &error, failures),
        }
    }

    /// A solution must agree with the reference to the method's accuracy unless flagged, and
    /// the stiffness route must warn at 10⁶ elements. A stiffness-route result that is not
    /// finite counts as a breakdown when it says so (the `non-finite` warning, naming the
    /// condensed method, which works here: it is the reference).
    fn solved(&self, method: Method, solution: &Solution, failures: &mut Vec<String>) -> MethodRun {
        if !solution.is_finite()
            && method.uses_stiffness_matrix()
            && solution.has_warning(WarningCode::NonFinite)
        {
            return MethodRun {
                method,
                outcome: SolveErrorKind::Breakdown.name().into(),
                disagreement: None,
                kkt_residual: None,
                flagged: true,
                warnings: solution.warnings.iter().map(|w| w.code).collect(),
            };
        }
        let disagreement = relative_difference(&solution.field, &self.reference.field);
        let flagged = is_flagged(solution);
        let tolerance = if method.is_regularized() {
            regularized_tolerance(self.problem, self.epsilon, self.largest)
        } else {
            EXACT_TOLERANCE
        };
        let finite = solution.is_finite() && disagreement.is_finite();
        if let Some(failure) = judge(method, finite, disagreement, tolerance, flagged) {
            failures.push(failure);
        }
        if method.uses_stiffness_matrix()
            && self.mesh.elements() >= 1_000_000
            && !solution.has_warning(WarningCode::StiffnessConditioning)
        {
            failures.push(format!(
                "{method}: no conditioning warning at {} elements",
                self.mesh.elements()
            ));
        }
        MethodRun {
            method,
            outcome: "solved".into(),
            disagreement: disagreement.is_finite().then_some(disagreement),
            kkt_residual: Some(solution.kkt_residual),
            flagged,
            warnings: solution.warnings.iter().map(|w| w.code).collect(),
        }
    }

    /// A method that gives no solution must name one that works; only the stiffness route
    /// may break down.
    fn declined(
        &self,
        method: Method,
        error: &SolveError,
        failures: &mut Vec<String>,
    ) -> MethodRun {
        let options = options(self.epsilon);
        if let Err(e) = solve(self.problem, self.mesh, error.suggestion, &options) {
            failures.push(format!(
                "{method} suggests {} which fails too: {e}",
                error.suggestion
            ));
        }
        if error.kind == SolveErrorKind::Breakdown && !method.uses_stiffness_matrix() {
            failures.push(format!("{method} broke down: {error}"));
        }
        MethodRun {
            method,
            outcome: error.kind.name().into(),
            disagreement: None,
            kkt_residual: None,
            flagged: error.kind == SolveErrorKind::Breakdown,
            warnings: Vec::new(),
        }
    }
}

/// The largest disagreements and KKT residual over the methods that do not flag themselves.
fn summarize(report: &mut CaseReport) {
    let unflagged = |regularized: bool| {
        report
            .runs
            .iter()
            .filter(move |r| !r.flagged && r.method.is_regularized() == regularized)
    };
    // The condensed method is the yardstick: its own "disagreement" says nothing.
    let max_disagreement = unflagged(false)
        .filter(|r| r.method != Method::Condensed)
        .filter_map(|r| r.disagreement)
        .reduce(f64::max);
    let regularized_disagreement = unflagged(true)
        .filter_map(|r| r.disagreement)
        .reduce(f64::max);
    let kkt_residual = unflagged(false)
        .filter_map(|r| r.kkt_residual)
        .reduce(f64::max);
    report.max_disagreement = max_disagreement;
    report.regularized_disagreement = regularized_disagreement;
    report.kkt_residual = kkt_residual;
}

/// The condensed method against every closed form that applies.
fn check_closed_forms(bench: &Bench, report: &mut CaseReport) {
    let all_stuck = bench
        .reference
        .obstacles
        .iter()
        .all(|o| !o.sliding && !o.swivel);
    for (name, exact) in closed_forms(bench.problem, bench.mesh, all_stuck) {
        let error = relative_difference(&bench.reference.field, &exact);
        if error.is_nan() || error > CLOSED_FORM_TOLERANCE {
            report.failures.push(format!(
                "condensed differs from the {name} closed form by {}",
                sci(error, 2)
            ));
        }
        report.closed_forms.push((name.to_string(), error));
    }
}

/// Solves the scaled scene and compares with the predicted factors γα⁴/β (u) and γα³/β (u') at
/// the special points (supports, obstacles, segment ends). Only there: the two meshes may share
/// the elements among equally long pieces differently (a tie broken by rounding), and the
/// nodal values at the special points do not depend on the mesh (docs/design.md fact 1).
fn check_scaling(
    scene: &Scene,
    mesh: &Mesh,
    reference: &Solution,
    failures: &mut Vec<String>,
) -> f64 {
    let (alpha, beta, gamma) = SCALING;
    let scaled = scaled_scene(scene, SCALING);
    let result = scaled
        .validate("scaled")
        .map_err(|e| e.to_string())
        .and_then(|(p, s)| {
            let mesh = Mesh::new(&p, s.elements);
            solve(&p, &mesh, Method::Condensed, &options(s.epsilon))
                .map(|solution| (mesh, solution))
                .map_err(|e| e.to_string())
        });
    let (scaled_mesh, solution) = match result {
        Ok(s) => s,
        Err(e) => {
            failures.push(format!("scaled scene: {e}"));
            return f64::NAN;
        }
    };
    let special = |mesh: &Mesh| -> Vec<usize> {
        let mut nodes: Vec<usize> = mesh.pieces.iter().map(|p| p.first_node).collect();
        nodes.push(mesh.elements());
        nodes
    };
    let (nodes, scaled_nodes) = (special(mesh), special(&scaled_mesh));
    if nodes.len() != scaled_nodes.len() {
        failures.push("the scaled scene has different special points".into());
        return f64::NAN;
    }
    let pick = |field: &NodalField, nodes: &[usize], factors: (f64, f64)| NodalField {
        deflection: nodes
            .iter()
            .map(|&i| field.deflection[i] * factors.0)
            .collect(),
        slope: nodes.iter().map(|&i| field.slope[i] * factors.1).collect(),
    };
    let factors = (gamma * alpha.powi(4) / beta, gamma * alpha.powi(3) / beta);
    let predicted = pick(&reference.field, &nodes, factors);
    let obtained = pick(&solution.field, &scaled_nodes, (1.0, 1.0));
    let error = relative_difference(&obtained, &predicted);
    if error.is_nan() || error > SCALING_TOLERANCE {
        failures.push(format!(
            "scaling l, E, f by {alpha}, {beta}, {gamma} changes u by a factor off the predicted γα⁴/β by {}",
            sci(error, 2)
        ));
    }
    error
}

/// Runs the suite on every preset.
pub fn check_presets() -> Vec<CaseReport> {
    PRESETS
        .iter()
        .map(|preset| check_text(preset.name, preset.text))
        .collect()
}

/// Runs the suite on every preset, every hard case ([`HARD_CASES`]) and the many-obstacle
/// families ([`check_families`]).
pub fn check_all() -> Vec<CaseReport> {
    let mut reports = check_presets();
    reports.extend(HARD_CASES.iter().map(|(name, text)| check_text(name, text)));
    reports.extend(check_families());
    reports
}

/// Runs the suite on a scene given as TOML text.
fn check_text(name: &str, text: &str) -> CaseReport {
    match Scene::from_toml(text, name) {
        Ok(scene) => check_scene(name, &scene),
        Err(e) => CaseReport {
            failures: vec![e.to_string()],
            ..CaseReport::empty(name, 0)
        },
    }
}

fn warning_summary(run: &MethodRun) -> Option<String> {
    let short: Vec<&str> = run.warnings.iter().map(|w| w.label()).collect();
    (!short.is_empty()).then(|| format!("{}: {}", run.method, short.join("+")))
}

/// The reports as a Markdown table, then the failures.
pub fn markdown(reports: &[CaseReport]) -> String {
    let mut out = String::from(
        "| case | n | methods run | max disagreement (exact) | regularised (ε) | closed form | KKT | scaling | warnings raised | verdict |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in reports {
        let solved: Vec<&str> = r
            .runs
            .iter()
            .filter(|run| run.outcome == "solved")
            .map(|run| run.method.name())
            .collect();
        let declined: Vec<String> = r
            .runs
            .iter()
            .filter(|run| run.outcome != "solved")
            .map(|run| format!("{} {}", run.method, run.outcome))
            .collect();
        let mut methods = format!("{} of {}", solved.len(), Method::ALL.len());
        if !declined.is_empty() {
            methods.push_str(&format!(" ({})", declined.join(", ")));
        }
        let flagged: Vec<String> = r
            .runs
            .iter()
            .filter(|run| run.flagged && run.outcome == "solved")
            .map(|run| {
                format!(
                    "{} {}",
                    run.method,
                    run.disagreement.map_or("n/a".into(), |d| sci(d, 1))
                )
            })
            .collect();
        let mut disagreement = r.max_disagreement.map_or("—".into(), |d| sci(d, 1));
        if !flagged.is_empty() {
            disagreement.push_str(&format!("; flagged: {}", flagged.join(", ")));
        }
        let closed = if r.closed_forms.is_empty() {
            "—".to_string()
        } else {
            r.closed_forms
                .iter()
                .map(|(name, e)| format!("{name} {}", sci(*e, 1)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let warnings: Vec<String> = r.runs.iter().filter_map(warning_summary).collect();
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.case,
            r.elements,
            methods,
            disagreement,
            r.regularized_disagreement.map_or("—".into(), |d| sci(d, 1)),
            closed,
            r.kkt_residual.map_or("—".into(), |k| sci(k, 1)),
            r.scaling.map_or("—".into(), |s| sci(s, 1)),
            if warnings.is_empty() {
                "none".to_string()
            } else {
                warnings.join("; ")
            },
            if r.passed() { "pass" } else { "**FAIL**" }
        ));
    }
    let failures: Vec<String> = reports
        .iter()
        .flat_map(|r| r.failures.iter().map(move |f| format!("- {}: {f}", r.case)))
        .collect();
    if !failures.is_empty() {
        out.push_str("\nFailures:\n\n");
        out.push_str(&failures.join("\n"));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_silent_disagreement_or_a_nan_fails_a_flagged_one_does_not() {
        assert!(judge(Method::Dual, true, 1e-12, 1e-8, false).is_none());
        let silent = judge(Method::Dual, true, 1e-3, 1e-8, false).unwrap();
        assert!(silent.contains("without a warning"), "{silent}");
        assert!(judge(Method::Dual, true, 1.0, 1e-8, true).is_none());
        assert!(
            judge(Method::Dual, false, 0.0, 1e-8, true)
                .unwrap()
                .contains("NaN")
        );
    }

    #[test]
    fn the_regularisation_tolerance_follows_epsilon() {
        let scene =
            Scene::from_toml(crate::scene::preset("benchmark-1").unwrap().text, "b1").unwrap();
        let problem = scene.problem().unwrap();
        let loose = regularized_tolerance(&problem, 1e-3, 0.02);
        let tight = regularized_tolerance(&problem, 1e-9, 0.02);
        assert!(loose > 1e-3 && tight < 1e-5, "{loose:e} {tight:e}");
    }
}
