//! The [`Solution`] every method returns and the report types it carries: per-obstacle
//! results (the friction forces λ of (38) and the [`FrictionState`] of every friction DOF),
//! timing, condition numbers, the error against a reference, warnings, and the
//! [`SolveError`] of a method that gives no solution.

use std::fmt;
use std::time::Duration;

use serde::Serialize;

use super::history::History;
use crate::fem::NodalField;
use crate::linalg::condition::ConditionNumber;
use crate::model::Method;

/// Why a method gave no solution, and which method works instead.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveError {
    pub method: Method,
    pub kind: SolveErrorKind,
    /// What went wrong, in words.
    pub reason: String,
    /// A method that works for this problem.
    pub suggestion: Method,
}

/// The kind of [`SolveError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveErrorKind {
    /// The method is outside its range (too many cases, too large for a dense inverse).
    Refused,
    /// The method does not apply to these data (closed form).
    NotApplicable,
    /// The computation broke down (a factorization failed in floating point).
    Breakdown,
    /// A newer request made the solve pointless; it stopped part-way (never shown).
    Cancelled,
}

impl SolveErrorKind {
    /// The code in JSON and in `check`: `refused`, `not-applicable`, `breakdown`.
    pub fn name(self) -> &'static str {
        match self {
            SolveErrorKind::Refused => "refused",
            SolveErrorKind::NotApplicable => "not-applicable",
            SolveErrorKind::Breakdown => "breakdown",
            SolveErrorKind::Cancelled => "cancelled",
        }
    }

    /// The kind in words: `refused`, `not applicable`, `broke down`.
    pub fn label(self) -> &'static str {
        match self {
            SolveErrorKind::Refused => "refused",
            SolveErrorKind::NotApplicable => "not applicable",
            SolveErrorKind::Breakdown => "broke down",
            SolveErrorKind::Cancelled => "cancelled",
        }
    }
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} {}: {}; the {} method works here",
            self.method,
            self.kind.label(),
            self.reason,
            self.suggestion
        )
    }
}

impl std::error::Error for SolveError {}

/// Run time of the stages of a method.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timing {
    pub assembly: Duration,
    pub factorization: Duration,
    /// The work on the friction DOFs: the box QP of the dual methods, the case enumeration or
    /// the Newton iterations of the regularised ones, the friction search of `condensed`, the
    /// closed form's choice of case (50)–(51).
    pub friction_stage: Duration,
    pub reconstruction: Duration,
}

impl Timing {
    /// Sum of the stages.
    pub fn total(&self) -> Duration {
        self.assembly + self.factorization + self.friction_stage + self.reconstruction
    }
}

/// Condition numbers of the matrices a method uses (all optional).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Conditioning {
    /// cond₂(A) of the stiffness matrix.
    pub stiffness: Option<ConditionNumber>,
    /// cond₂ of the Jacobi-scaled stiffness matrix D^{-1/2} A D^{-1/2}.
    pub stiffness_scaled: Option<ConditionNumber>,
    /// Largest cond₂(Â) over the regularised cases (paper Figure 5).
    pub regularized_max: Option<ConditionNumber>,
    /// Largest cond₂ of the Jacobi-scaled Â over the same cases.
    pub regularized_scaled_max: Option<ConditionNumber>,
    /// cond₂(S) of the dual matrix S = B A⁻¹ Bᵀ.
    pub dual: Option<ConditionNumber>,
}

/// What a warning is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarningCode {
    /// More elements than asked for (every piece needs one).
    MeshRaised,
    /// cond(A)·eps says the stiffness route cannot be trusted at this n.
    StiffnessConditioning,
    /// The solution differs visibly from the reference.
    AccuracyLoss,
    /// The QP did not reach its KKT conditions.
    QpNotConverged,
    /// No regularisation case was exactly consistent; the closest was kept.
    RegularizationInconsistent,
    /// The Newton iteration hit its limit.
    NewtonNotConverged,
    /// The stiffness matrix lost positive definiteness to rounding during factorization.
    IndefiniteFactorization,
    /// A value is NaN or infinite.
    NonFinite,
    /// The reference did not certify itself here, so no error is reported.
    UntrustedReference,
    /// The KKT conditions of (38), checked independently of the method, fail by more than
    /// rounding can explain.
    KktResidual,
}

impl WarningCode {
    /// Every code.
    pub const ALL: [WarningCode; 10] = [
        WarningCode::MeshRaised,
        WarningCode::StiffnessConditioning,
        WarningCode::AccuracyLoss,
        WarningCode::QpNotConverged,
        WarningCode::RegularizationInconsistent,
        WarningCode::NewtonNotConverged,
        WarningCode::IndefiniteFactorization,
        WarningCode::NonFinite,
        WarningCode::UntrustedReference,
        WarningCode::KktResidual,
    ];

    /// The code in JSON and CSV, e.g. `stiffness-conditioning`.
    pub fn name(self) -> &'static str {
        match self {
            WarningCode::MeshRaised => "mesh-raised",
            WarningCode::StiffnessConditioning => "stiffness-conditioning",
            WarningCode::AccuracyLoss => "accuracy-loss",
            WarningCode::QpNotConverged => "qp-not-converged",
            WarningCode::RegularizationInconsistent => "regularization-inconsistent",
            WarningCode::NewtonNotConverged => "newton-not-converged",
            WarningCode::IndefiniteFactorization => "indefinite-factorization",
            WarningCode::NonFinite => "non-finite",
            WarningCode::UntrustedReference => "untrusted-reference",
            WarningCode::KktResidual => "kkt-residual",
        }
    }

    /// A short tag for tables (`check`'s Markdown), e.g. `cond`.
    pub fn label(self) -> &'static str {
        match self {
            WarningCode::MeshRaised => "mesh",
            WarningCode::StiffnessConditioning => "cond",
            WarningCode::AccuracyLoss => "accuracy",
            WarningCode::QpNotConverged => "qp",
            WarningCode::RegularizationInconsistent => "inconsistent",
            WarningCode::NewtonNotConverged => "newton",
            WarningCode::IndefiniteFactorization => "indefinite",
            WarningCode::NonFinite => "non-finite",
            WarningCode::UntrustedReference => "no-reference",
            WarningCode::KktResidual => "kkt",
        }
    }
}

/// A warning in words.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warning {
    pub code: WarningCode,
    pub message: String,
}

impl Warning {
    pub(crate) fn new(code: WarningCode, message: impl Into<String>) -> Warning {
        Warning {
            code,
            message: message.into(),
        }
    }
}

/// How far from a solution a KKT residual (relative) puts an answer, in three grades: the
/// words of the warning and of its headline follow it, so that a residual of 1e-9 does not
/// read like one of 1e-1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KktGrade {
    /// Above rounding, at most 1e-6: a solution to about that accuracy.
    Close,
    /// Above 1e-6, at most 1e-2: an approximate solution.
    Approximate,
    /// Above 1e-2 (or not finite): not a solution.
    NotASolution,
}

impl KktGrade {
    /// The grade of a relative KKT residual.
    pub fn of(residual: f64) -> KktGrade {
        if residual <= 1e-6 {
            KktGrade::Close
        } else if residual <= 1e-2 {
            KktGrade::Approximate
        } else {
            KktGrade::NotASolution
        }
    }

    /// What the grade means for the answer, after "the answer is".
    pub fn meaning(self) -> &'static str {
        match self {
            KktGrade::Close => "a solution to about that accuracy, not to rounding",
            KktGrade::Approximate => "an approximate solution, good to about that",
            KktGrade::NotASolution => "not a solution of the discrete problem",
        }
    }

    /// The status line's few words, with the residual.
    pub fn headline(self, residual: f64) -> String {
        let residual = crate::format::sci(residual, 2);
        match self {
            KktGrade::Close => format!("KKT check off by {residual}: accurate to about that"),
            KktGrade::Approximate => format!("KKT check off by {residual}: approximate only"),
            KktGrade::NotASolution => {
                format!("the independent KKT check fails by {residual}: not a solution")
            }
        }
    }
}

/// The friction state of one DOF (value or slope) of an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrictionState {
    /// c = 0 and |λ| < g by more than rounding.
    Stuck,
    /// c ≠ 0 by more than rounding, λ = g·sign c.
    Moves,
    /// c = 0 within rounding and |λ| = g within rounding: both descriptions fit.
    AtThreshold,
}

impl FrictionState {
    /// The code in JSON: `stuck`, `moves`, `at-threshold`.
    pub fn name(self) -> &'static str {
        match self {
            FrictionState::Stuck => "stuck",
            FrictionState::Moves => "moves",
            FrictionState::AtThreshold => "at-threshold",
        }
    }
}

/// Serialized as its [`name`](FrictionState::name).
impl Serialize for FrictionState {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// The result at one obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObstacleResult {
    /// Position [m].
    pub x: f64,
    /// u(x̂) [m].
    pub u: f64,
    /// u'(x̂) [rad].
    pub slope: f64,
    /// Friction force λ1 [N] (A c = b − Bᵀλ; |λ1| ≤ g1).
    pub force: f64,
    /// Friction moment λ2 [N m] (|λ2| ≤ g2).
    pub moment: f64,
    /// The value DOF: stuck, moving (sliding) or at its threshold (both fit within
    /// rounding), decided by the certificate from the force and the motion.
    pub sliding_state: FrictionState,
    /// The slope DOF: stuck, moving (swivelling) or at its threshold.
    pub swivel_state: FrictionState,
    /// The sliding friction is fully mobilised: `sliding_state` is not
    /// [`FrictionState::Stuck`] (it moves, or sits at its threshold with a motion rounding
    /// cannot resolve, which is how a real but tiny slide looks in double precision).
    pub sliding: bool,
    /// The swivel friction is fully mobilised: `swivel_state` is not stuck.
    pub swivel: bool,
}

impl ObstacleResult {
    /// The friction state in words: `stuck`, `slides`, `swivels`, `slides and swivels`, with
    /// `at the sliding threshold` (`swivel`, `both thresholds`) for a DOF that rounding cannot
    /// place on either side; `unknown` when the numbers it rests on are not finite.
    pub fn state(&self) -> &'static str {
        if ![self.u, self.slope, self.force, self.moment]
            .iter()
            .all(|v| v.is_finite())
        {
            return "unknown";
        }
        use FrictionState::{AtThreshold as T, Moves as M, Stuck as S};
        match (self.sliding_state, self.swivel_state) {
            (S, S) => "stuck",
            (M, S) => "slides",
            (S, M) => "swivels",
            (M, M) => "slides and swivels",
            (T, S) => "at the sliding threshold",
            (S, T) => "at the swivel threshold",
            (T, T) => "at both thresholds",
            (M, T) => "slides, at the swivel threshold",
            (T, M) => "swivels, at the sliding threshold",
        }
    }
}

/// Which solution the error is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reference {
    /// The closed form (50)–(51).
    ClosedForm,
    /// The condensed method on the same mesh.
    Condensed,
    /// This solution is itself the reference; no error is reported.
    ThisSolution,
}

impl Reference {
    /// The code in JSON and CSV: `closed-form`, `condensed`, `self`.
    pub fn name(self) -> &'static str {
        match self {
            Reference::ClosedForm => "closed-form",
            Reference::Condensed => "condensed",
            Reference::ThisSolution => "self",
        }
    }

    /// The reference in words on screen: `closed form`, `condensed`, `itself`.
    pub fn label(self) -> &'static str {
        match self {
            Reference::ClosedForm => "closed form",
            Reference::Condensed => "condensed",
            Reference::ThisSolution => "itself",
        }
    }
}

/// Nodal error against the reference. The numbers are `None` when this solution is the
/// reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorReport {
    pub reference: Reference,
    /// max |u − u_ref| over the nodes [m].
    pub max_abs: Option<f64>,
    /// max |u − u_ref| / max |u_ref| (see `compare` in the certificate's `reference` for the
    /// guard when u is nearly zero at every node).
    pub max_rel: Option<f64>,
    /// mean |u − u_ref| over the nodes [m] (the paper's err of section 2.8).
    pub mean_abs: Option<f64>,
    /// mean |u − u_ref| / max |u_ref|.
    pub mean_rel: Option<f64>,
    /// max |u' − u'_ref| / max |u'_ref| (guarded likewise when u' is nearly zero at every
    /// node).
    pub slope_max_rel: Option<f64>,
}

/// Extra facts about how a method ran.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct MethodDetails {
    /// Regularised cases enumerated (9^k).
    pub cases: Option<u64>,
    /// Newton iterations of `regularized-newton` (each one Cholesky factorization of a case
    /// matrix K + D on the friction DOFs).
    pub newton_iterations: Option<usize>,
    /// Pattern solves of the `condensed` method's friction search, each one banded
    /// factorisation and solve of the multiple-shooting system.
    pub linear_solves: Option<usize>,
    /// Iterations of the box QP.
    pub qp_iterations: Option<usize>,
    /// How many case matrices the reported largest condition number was taken over.
    pub conditioned_cases: Option<usize>,
}

/// A solution with its certificate.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub method: Method,
    /// ε used (regularised methods only).
    pub epsilon: Option<f64>,
    /// Nodal u and u'.
    pub field: NodalField,
    pub obstacles: Vec<ObstacleResult>,
    /// Relative KKT residual of (38).
    pub kkt_residual: f64,
    pub timing: Timing,
    pub conditioning: Conditioning,
    pub error: Option<ErrorReport>,
    pub warnings: Vec<Warning>,
    pub details: MethodDetails,
    /// The convergence history, when [`super::SolveOptions::history`] asked for it and the
    /// method iterates (`None` for `regularized` and `closed-form`).
    pub history: Option<History>,
    /// `condensed`: its final friction pattern, to start the next solve's search from after a
    /// small change ([`super::WarmStart`]).
    pub friction_pattern: Option<std::sync::Arc<super::condensed::pattern::FrictionPattern>>,
}

impl Solution {
    /// The largest |u| over the nodes [m]; NaN when any is not finite (never a quiet 0).
    pub fn max_deflection(&self) -> f64 {
        let u = &self.field.deflection;
        if u.iter().all(|v| v.is_finite()) {
            u.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        } else {
            f64::NAN
        }
    }

    /// Does the certification carry a warning of this kind?
    pub fn has_warning(&self, code: WarningCode) -> bool {
        self.warnings.iter().any(|w| w.code == code)
    }

    /// Is every reported number finite?
    pub fn is_finite(&self) -> bool {
        self.field
            .deflection
            .iter()
            .chain(&self.field.slope)
            .all(|v| v.is_finite())
            && self
                .obstacles
                .iter()
                .all(|o| o.force.is_finite() && o.moment.is_finite())
    }
}

/// Serialized as its [`name`](SolveErrorKind::name).
impl Serialize for SolveErrorKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// Serialized as its [`name`](WarningCode::name).
impl Serialize for WarningCode {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// Serialized as its [`name`](Reference::name).
impl Serialize for Reference {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}
