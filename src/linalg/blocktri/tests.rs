//! The block-tridiagonal factorization with the friction DOFs last, against dense solves.

use super::*;
use crate::linalg::BlockTridiagonal;

fn random_spd(blocks: usize, seed: u64) -> BlockTridiagonal {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let upper: Vec<[f64; 4]> = (0..blocks.saturating_sub(1))
        .map(|_| [next(), next(), next(), next()])
        .collect();
    let diag = (0..blocks)
        .map(|_| [4.0 + next(), 0.3 * next(), 4.0 + next()])
        .collect();
    BlockTridiagonal { diag, upper }
}

fn dense_solve(a: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut m: Vec<Vec<f64>> = a.chunks(n).map(|r| r.to_vec()).collect();
    let mut x = b.to_vec();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| m[i][k].abs().total_cmp(&m[j][k].abs()))
            .unwrap();
        m.swap(k, p);
        x.swap(k, p);
        for i in k + 1..n {
            let f = m[i][k] / m[k][k];
            for j in k..n {
                m[i][j] -= f * m[k][j];
            }
            x[i] -= f * x[k];
        }
    }
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| m[k][j] * x[j]).sum();
        x[k] = (x[k] - s) / m[k][k];
    }
    x
}

fn check(blocks: usize, boundary: &[usize]) {
    let a = random_spd(blocks, 7 + blocks as u64);
    let dense = a.to_dense();
    let n = 2 * blocks;
    let flat: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).sin()).collect();
    let expected = dense_solve(&dense, &flat);
    let factor = FrictionLastFactor::new(a.clone(), boundary).unwrap();
    assert_eq!(factor.first_indefinite, None);
    // The Schur complement must equal (B A⁻¹ Bᵀ)⁻¹: check K · (B A⁻¹ e_j) = e_j.
    let dim = 2 * boundary.len();
    for j in 0..dim {
        let mut e = vec![0.0; n];
        e[2 * boundary[j / 2] + j % 2] = 1.0;
        let column = dense_solve(&dense, &e);
        for i in 0..dim {
            let v: f64 = (0..dim)
                .map(|c| factor.schur[i * dim + c] * column[2 * boundary[c / 2] + c % 2])
                .sum();
            let target = if i == j { 1.0 } else { 0.0 };
            assert!((v - target).abs() < 1e-12, "K S != I at ({i},{j}): {v}");
        }
    }
    let mut u: Vec<f64> = flat.iter().step_by(2).copied().collect();
    let mut t: Vec<f64> = flat.iter().skip(1).step_by(2).copied().collect();
    factor.solve(&mut u, &mut t, |g| dense_solve(&factor.schur, g));
    for i in 0..blocks {
        for (v, e) in [(u[i], expected[2 * i]), (t[i], expected[2 * i + 1])] {
            assert!(
                (v - e).abs() < 1e-12 * (1.0 + e.abs()),
                "block {i}: {v} vs {e}"
            );
        }
    }
}

#[test]
fn matches_dense_elimination() {
    check(9, &[]);
    check(9, &[4]);
    check(9, &[0, 8]);
    check(9, &[2, 3, 6]);
    check(12, &[1, 5, 6, 7, 11]);
    check(1, &[0]);
    check(2, &[]);
}
