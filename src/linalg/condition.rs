//! 2-norm condition numbers of SPD matrices, as the paper's Figure 5 plots them:
//! exact from all eigenvalues (faer) for small N, Lanczos estimates of the extreme eigenvalues
//! for large N (λ_max from A, λ_min from A⁻¹ through the block-tridiagonal factorization), and
//! the inverse iteration behind the stiffness matrix's cheap lower bound
//! (`fem::stiffness_condition_bounds`, which builds the coarse matrices from the mesh).

use faer::{Mat, Side};
use serde::Serialize;

use super::blocktri::FrictionLastFactor;
use super::stop::{NEVER, Stop, Stopped};
use super::{BlockMatrix, BlockTridiagonal};

/// Largest N for which all eigenvalues are computed.
pub const DENSE_LIMIT: usize = 200;
/// Lanczos steps for each extreme eigenvalue.
const LANCZOS_STEPS: usize = 40;

/// How a condition number was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConditionKind {
    /// From all eigenvalues.
    Exact,
    /// Lanczos estimate of the extreme eigenvalues (from below).
    Estimate,
    /// A rigorous lower bound.
    LowerBound,
}

impl ConditionKind {
    /// The code in JSON and CSV: `exact`, `estimate`, `lower-bound`.
    pub fn name(self) -> &'static str {
        match self {
            ConditionKind::Exact => "exact",
            ConditionKind::Estimate => "estimate",
            ConditionKind::LowerBound => "lower-bound",
        }
    }

    /// How the number relates to the true one: `=`, `≈` or `≥`.
    pub fn symbol(self) -> &'static str {
        match self {
            ConditionKind::Exact => "=",
            ConditionKind::Estimate => "≈",
            ConditionKind::LowerBound => "≥",
        }
    }
}

/// A condition number and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ConditionNumber {
    pub value: f64,
    pub kind: ConditionKind,
}

impl ConditionNumber {
    /// Does the number mean that a backward-stable solve may lose every digit
    /// (cond · eps ≥ 1)?
    pub fn beyond_double_precision(&self) -> bool {
        self.value * f64::EPSILON >= 1.0
    }
}

/// Extreme eigenvalues (min, max) of a dense symmetric row-major matrix.
pub fn dense_extremes(a: &[f64], n: usize) -> Option<(f64, f64)> {
    if a.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let values = m.self_adjoint_eigenvalues(Side::Lower).ok()?;
    Some((*values.first()?, *values.last()?))
}

/// From this size on faer's eigensolver is more than a few milliseconds of work in one call
/// that cannot be interrupted (90 ms at n = 1022, the largest dual matrix).
const EIGENSOLVER_ON_HELPER: usize = 256;

/// [`dense_extremes`], stopping to wait when `stop` says so. From
/// [`EIGENSOLVER_ON_HELPER`] on, faer's eigensolver runs on a helper thread while this one asks
/// `stop` every millisecond: a cancelled caller returns at once, and the helper ends by itself
/// when its one call is done (its answer is dropped). The numbers are faer's either way.
fn dense_extremes_until(a: &[f64], n: usize, stop: Stop) -> Result<Option<(f64, f64)>, Stopped> {
    use std::sync::mpsc::{RecvTimeoutError, channel};
    if n < EIGENSOLVER_ON_HELPER {
        return Ok(dense_extremes(a, n));
    }
    if stop() {
        return Err(Stopped);
    }
    let (matrix, (tell, told)) = (a.to_vec(), channel());
    let helper = std::thread::Builder::new()
        .name("eigenvalues".into())
        .spawn(move || tell.send(dense_extremes(&matrix, n)));
    if helper.is_err() {
        // No thread to be had: the call here, to the end.
        return Ok(dense_extremes(a, n));
    }
    loop {
        match told.recv_timeout(std::time::Duration::from_millis(1)) {
            Ok(extremes) => return Ok(extremes),
            Err(RecvTimeoutError::Timeout) if stop() => return Err(Stopped),
            Err(RecvTimeoutError::Timeout) => {}
            // The helper panicked: as if the eigensolver had failed.
            Err(RecvTimeoutError::Disconnected) => return Ok(None),
        }
    }
}

/// How far above rounding (n·eps·λ_max, the eigensolver's absolute accuracy) λ_min must be for
/// the condition number from the eigenvalues to be called exact (three digits).
const RESOLVED_EIGENVALUE: f64 = 1e3;

/// cond₂ of a dense SPD matrix. From its eigenvalues when λ_min is resolved (`Exact`); else
/// λ_max(A)·λ_max(A⁻¹) with A⁻¹ from a Cholesky factorization, which is accurate when the
/// ill-conditioning comes from a diagonal scaling such as the regularised g/ε (`Estimate`);
/// else, when A is not positive definite in floating point, the rigorous
/// λ_max / (max(λ_min, 0) + n·eps·λ_max) (`LowerBound`). `None` if an entry is not finite (the
/// eigensolver would spin on it for seconds) or the eigensolver fails.
pub fn dense_condition(a: &[f64], n: usize) -> Option<ConditionNumber> {
    dense_condition_until(a, n, NEVER).expect("never stopped")
}

/// [`dense_condition`], giving up when `stop` says so: between the eigensolver's calls and
/// inside the Cholesky factorization and inverse (a second each at n = 1022; faer's
/// eigensolver itself is one call, tens of milliseconds at that size).
pub fn dense_condition_until(
    a: &[f64],
    n: usize,
    stop: Stop,
) -> Result<Option<ConditionNumber>, Stopped> {
    let Some((min, max)) = dense_extremes_until(a, n, stop)? else {
        return Ok(None);
    };
    if !(max > 0.0 && max.is_finite()) {
        return Ok(None);
    }
    let rounding = n as f64 * f64::EPSILON * max;
    if min > RESOLVED_EIGENVALUE * rounding {
        return Ok(condition_from(min, max, ConditionKind::Exact));
    }
    let bound = ConditionNumber {
        value: max / (min.max(0.0) + rounding),
        kind: ConditionKind::LowerBound,
    };
    let inverse = match crate::linalg::dense::Cholesky::factor_until(a, n, stop)? {
        Some(c) => Some(c.inverse_until(stop)?),
        None => None,
    };
    let inverse_extremes = match inverse {
        Some(inverse) => dense_extremes_until(&inverse, n, stop)?,
        None => None,
    };
    let estimate = inverse_extremes
        .map(|(_, inverse_max)| max * inverse_max)
        .filter(|v| v.is_finite() && *v >= bound.value);
    Ok(Some(estimate.map_or(bound, |value| ConditionNumber {
        value,
        kind: ConditionKind::Estimate,
    })))
}

fn condition_from(min: f64, max: f64, kind: ConditionKind) -> Option<ConditionNumber> {
    let value = max / min;
    (min > 0.0 && value.is_finite()).then_some(ConditionNumber { value, kind })
}

/// The matrix D^{-1/2} A D^{-1/2} with D = diag(A): unit diagonal.
pub fn jacobi_scaled(a: &BlockTridiagonal) -> BlockTridiagonal {
    let s: Vec<[f64; 2]> = a
        .diag
        .iter()
        .map(|d| [1.0 / d[0].sqrt(), 1.0 / d[2].sqrt()])
        .collect();
    BlockTridiagonal {
        diag: a
            .diag
            .iter()
            .zip(&s)
            .map(|(d, s)| [d[0] * s[0] * s[0], d[1] * s[0] * s[1], d[2] * s[1] * s[1]])
            .collect(),
        upper: a
            .upper
            .iter()
            .enumerate()
            .map(|(i, u)| {
                let (l, r) = (s[i], s[i + 1]);
                [
                    u[0] * l[0] * r[0],
                    u[1] * l[0] * r[1],
                    u[2] * l[1] * r[0],
                    u[3] * l[1] * r[1],
                ]
            })
            .collect(),
    }
}

/// cond₂ of a block-tridiagonal SPD matrix: [`dense_condition`] for N ≤ [`DENSE_LIMIT`], else
/// a Lanczos estimate, or a lower bound when the matrix is not positive definite to working
/// precision.
pub fn block_condition(a: &BlockTridiagonal) -> Option<ConditionNumber> {
    block_condition_until(a, NEVER).expect("never stopped")
}

/// [`block_condition`], giving up when `stop` says so, asked before every Lanczos step and
/// around the factorization (each O(n)).
pub fn block_condition_until(
    a: &BlockTridiagonal,
    stop: Stop,
) -> Result<Option<ConditionNumber>, Stopped> {
    let n = 2 * a.blocks();
    if n <= DENSE_LIMIT {
        return dense_condition_until(&a.to_dense(), n, stop);
    }
    let max = lanczos_largest(n, |v| flat_apply(a, v), stop)?;
    // A is not positive definite in floating point: λ_min is below the factorization's
    // rounding, a few ulps of λ_max for a banded matrix, so cond(A) ≥ 1/(64 eps).
    let indefinite = Some(ConditionNumber {
        value: 1.0 / (64.0 * f64::EPSILON),
        kind: ConditionKind::LowerBound,
    });
    if stop() {
        return Err(Stopped);
    }
    let Ok(factor) = FrictionLastFactor::new(a.clone(), &[]) else {
        return Ok(indefinite);
    };
    if factor.first_indefinite.is_some() {
        return Ok(indefinite);
    }
    let inverse_max = lanczos_largest(
        n,
        |v| {
            let mut u: Vec<f64> = v.iter().step_by(2).copied().collect();
            let mut t: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
            factor.solve(&mut u, &mut t, |_| Vec::new());
            u.iter().zip(&t).flat_map(|(a, b)| [*a, *b]).collect()
        },
        stop,
    )?;
    Ok(condition_from(
        1.0 / inverse_max,
        max,
        ConditionKind::Estimate,
    ))
}

fn flat_apply(a: &BlockTridiagonal, v: &[f64]) -> Vec<f64> {
    let blocks: Vec<[f64; 2]> = v.chunks(2).map(|c| [c[0], c[1]]).collect();
    a.apply(&blocks).into_iter().flatten().collect()
}

/// Largest eigenvalue of a symmetric operator by Lanczos without reorthogonalisation (the
/// extreme Ritz value converges from below), deterministic start vector; `stop` is asked
/// before every step.
fn lanczos_largest(
    n: usize,
    apply: impl Fn(&[f64]) -> Vec<f64>,
    stop: Stop,
) -> Result<f64, Stopped> {
    let steps = LANCZOS_STEPS.min(n);
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * ((i as f64) * 0.618_033_988_75).fract())
        .collect();
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    let mut previous = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta = 0.0;
    for _ in 0..steps {
        if stop() {
            return Err(Stopped);
        }
        let mut w = apply(&v);
        let alpha: f64 = w.iter().zip(&v).map(|(a, b)| a * b).sum();
        for i in 0..n {
            w[i] -= alpha * v[i] + beta * previous[i];
        }
        alphas.push(alpha);
        beta = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        if beta <= 1e-14 * alpha.abs() || !beta.is_finite() {
            break;
        }
        betas.push(beta);
        previous = std::mem::replace(&mut v, w.into_iter().map(|x| x / beta).collect());
    }
    let m = alphas.len();
    let t = Mat::from_fn(m, m, |i, j| {
        if i == j {
            alphas[i]
        } else if i + 1 == j || j + 1 == i {
            betas[i.min(j)]
        } else {
            0.0
        }
    });
    Ok(t.self_adjoint_eigenvalues(Side::Lower)
        .ok()
        .and_then(|v| v.last().copied())
        .unwrap_or(f64::NAN))
}

/// Inverse-iteration steps of [`smallest_rayleigh_quotient`].
const COARSE_ITERATIONS: usize = 30;

/// The Rayleigh quotient vᵀGv / vᵀMv after inverse iteration v ← G⁻¹Mv: an upper bound on the
/// smallest eigenvalue of the pencil (G, M), close to it after a few dozen steps.
pub fn smallest_rayleigh_quotient(g: &BlockTridiagonal, m: &BlockTridiagonal) -> f64 {
    let blocks = g.blocks();
    if blocks == 0 {
        return f64::NAN;
    }
    let Ok(factor) = FrictionLastFactor::new(g.clone(), &[]) else {
        return f64::NAN;
    };
    let dot = |x: &[[f64; 2]], y: &[[f64; 2]]| -> f64 {
        x.iter()
            .zip(y)
            .map(|(a, b)| a[0] * b[0] + a[1] * b[1])
            .sum()
    };
    let mut v: Vec<[f64; 2]> = vec![[1.0, 0.0]; blocks];
    let mut quotient = f64::INFINITY;
    for _ in 0..COARSE_ITERATIONS {
        let mv = m.apply(&v);
        let mut u: Vec<f64> = mv.iter().map(|x| x[0]).collect();
        let mut t: Vec<f64> = mv.iter().map(|x| x[1]).collect();
        factor.solve(&mut u, &mut t, |_| Vec::new());
        let norm = u.iter().chain(&t).fold(0.0f64, |s, x| s.max(x.abs()));
        if !(norm > 0.0 && norm.is_finite()) {
            return f64::NAN;
        }
        v = u
            .iter()
            .zip(&t)
            .map(|(a, b)| [a / norm, b / norm])
            .collect();
        // Every quotient is an upper bound on λ_min; stop once it has settled.
        let next = dot(&v, &g.apply(&v)) / dot(&v, &m.apply(&v));
        let settled = (quotient - next).abs() <= 1e-4 * next;
        quotient = quotient.min(next);
        if settled {
            break;
        }
    }
    quotient
}

/// Serialized as its [`name`](ConditionKind::name).
impl Serialize for ConditionKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}
