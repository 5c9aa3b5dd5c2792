//! Dense Cholesky for the small SPD systems on the friction DOFs (size 2k ≤ 512): the
//! Schur complement K, the cases of the regularised method and the subproblems of the QP.
//! Row-major storage, no allocation beyond the factor; faer is used where matrices are large
//! (the explicit inverse of `dual-inverse`, eigenvalues for condition numbers). At 2k = 1022
//! a factorization or an inverse is a second of work: the `_until` variants give up between
//! columns when their `stop` says so (`linalg::stop`).

use super::stop::{NEVER, Stop, StopCheck, Stopped};

/// L with A = L Lᵀ, row-major lower triangle.
#[derive(Debug, Clone)]
pub struct Cholesky {
    n: usize,
    l: Vec<f64>,
}

impl Cholesky {
    /// Factors the n×n row-major SPD matrix `a`; `None` if a pivot is not positive (not SPD to
    /// working precision) or not finite.
    pub fn new(a: &[f64], n: usize) -> Option<Cholesky> {
        Self::factor_until(a, n, NEVER).unwrap_or(None)
    }

    /// [`new`](Self::new), giving up between columns when `stop` says so.
    pub fn factor_until(a: &[f64], n: usize, stop: Stop) -> Result<Option<Cholesky>, Stopped> {
        let mut check = StopCheck::new(stop);
        let mut l = vec![0.0; n * n];
        for j in 0..n {
            check.after((n - j) * (j + 1))?;
            let mut d = a[j * n + j];
            for k in 0..j {
                d -= l[j * n + k] * l[j * n + k];
            }
            if !(d > 0.0 && d.is_finite()) {
                return Ok(None);
            }
            let d = d.sqrt();
            l[j * n + j] = d;
            for i in j + 1..n {
                let mut s = a[i * n + j];
                for k in 0..j {
                    s -= l[i * n + k] * l[j * n + k];
                }
                l[i * n + j] = s / d;
            }
        }
        Ok(Some(Cholesky { n, l }))
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solves A x = b in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let mut s = b[i];
            for k in 0..i {
                s -= self.l[i * n + k] * b[k];
            }
            b[i] = s / self.l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for k in i + 1..n {
                s -= self.l[k * n + i] * b[k];
            }
            b[i] = s / self.l[i * n + i];
        }
    }

    /// Solves A x = b.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x);
        x
    }

    /// A⁻¹, row-major, exactly symmetric.
    pub fn inverse(&self) -> Vec<f64> {
        self.inverse_until(NEVER)
            .expect("never stopped: the inverse is computed to the end")
    }

    /// [`inverse`](Self::inverse), giving up between columns when `stop` says so.
    pub fn inverse_until(&self, stop: Stop) -> Result<Vec<f64>, Stopped> {
        let n = self.n;
        let mut check = StopCheck::new(stop);
        let mut inv = vec![0.0; n * n];
        let mut e = vec![0.0; n];
        for j in 0..n {
            check.after(n * n)?;
            e.iter_mut().for_each(|v| *v = 0.0);
            e[j] = 1.0;
            self.solve_in_place(&mut e);
            for i in 0..n {
                inv[i * n + j] = e[i];
            }
        }
        for i in 0..n {
            for j in 0..i {
                let v = 0.5 * (inv[i * n + j] + inv[j * n + i]);
                inv[i * n + j] = v;
                inv[j * n + i] = v;
            }
        }
        Ok(inv)
    }
}

/// y = A x for a row-major n×n matrix.
pub fn mat_vec(a: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            a[i * n..(i + 1) * n]
                .iter()
                .zip(x)
                .map(|(a, x)| a * x)
                .sum()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_inverts() {
        let a = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0];
        let c = Cholesky::new(&a, 3).unwrap();
        let x = c.solve(&[1.0, 2.0, 3.0]);
        let back = mat_vec(&a, &x);
        for (b, e) in back.iter().zip([1.0, 2.0, 3.0]) {
            assert!((b - e).abs() < 1e-14);
        }
        let inv = c.inverse();
        for i in 0..3 {
            for j in 0..3 {
                let v: f64 = (0..3).map(|k| a[i * 3 + k] * inv[k * 3 + j]).sum();
                assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        assert!(Cholesky::new(&[1.0, 2.0, 2.0, 1.0], 2).is_none());
    }
}
