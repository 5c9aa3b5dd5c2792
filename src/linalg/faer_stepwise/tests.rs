//! faer_stepwise against faer's own calls, bit for bit, for many sizes and cuts.

use super::*;
use crate::linalg::stop::NEVER;
use faer::Side;
use faer::linalg::solvers::DenseSolveCore;

/// A random SPD matrix (a fixed sequence), far from singular.
fn spd(n: usize, seed: u64) -> Mat<f64> {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let m = Mat::from_fn(n, n, |_, _| next());
    let mut a = &m * m.transpose();
    for i in 0..n {
        a[(i, i)] += n as f64;
    }
    a
}

/// The lower triangle of `a` in a matrix made as `dual-inverse` makes it.
fn lower_of(a: &Mat<f64>) -> Mat<f64> {
    let n = a.nrows();
    let mut lower = zeros_until(n, NEVER).unwrap();
    for j in 0..n {
        for i in j..n {
            lower[(i, j)] = a[(i, j)];
        }
    }
    lower
}

fn same_bits(a: MatRef<'_, f64>, b: MatRef<'_, f64>, what: &str) {
    assert_eq!(a.shape(), b.shape());
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            assert_eq!(
                a[(i, j)].to_bits(),
                b[(i, j)].to_bits(),
                "{what}: ({i}, {j}) differs: {} vs {}",
                a[(i, j)],
                b[(i, j)]
            );
        }
    }
}

/// The factor and the inverse with `cuts` against faer's own calls.
fn check(n: usize, cuts: Cuts) {
    let a = spd(n, n as u64);
    let faer_factor = a.llt(Side::Lower).unwrap();
    let mut factor = lower_of(&a);
    llt_with_cuts(factor.as_mut(), NEVER, cuts)
        .unwrap()
        .unwrap();
    same_bits(
        lower_of(&factor).as_ref(),
        faer_factor.L(),
        &format!("factor n = {n}"),
    );
    let inverse = llt_inverse_with_cuts(factor.as_ref(), NEVER, cuts).unwrap();
    same_bits(
        inverse.as_ref(),
        faer_factor.inverse().as_ref(),
        &format!("inverse n = {n}"),
    );
    let x = faer::Col::from_fn(n, |i| (i as f64).sin());
    let y = mat_vec_until(inverse.as_ref(), x.as_ref(), NEVER).unwrap();
    let expected = &inverse * &x;
    same_bits(y.as_mat(), expected.as_mat(), &format!("product n = {n}"));
}

#[test]
fn cut_up_it_is_faer_bit_for_bit() {
    // Small pieces, so that small matrices are cut at every level.
    let fine = Cuts {
        direct: 16,
        work: 1 << 12,
        memory: 1 << 10,
        piece: 24,
    };
    for n in [1, 2, 3, 17, 40, 65, 97, 130, 200, 257, 300, 411] {
        check(n, fine);
    }
    for n in [300, 700, 1500] {
        check(n, CUTS);
    }
}

/// The LU inverse with `cuts` against faer's own call, on a general matrix.
fn check_lu(n: usize, cuts: Cuts) {
    let a = spd(n, 3 * n as u64);
    let skew = Mat::from_fn(n, n, |i, j| (i as f64 - 2.0 * j as f64).sin());
    let a = &a + &skew;
    let lu = a.partial_piv_lu();
    let inverse = lu_inverse_with_cuts((lu.L(), lu.U(), lu.P()), NEVER, cuts).unwrap();
    same_bits(
        inverse.as_ref(),
        lu.inverse().as_ref(),
        &format!("LU inverse n = {n}"),
    );
}

#[test]
fn the_lu_inverse_cut_up_is_faer_bit_for_bit() {
    let fine = Cuts {
        direct: 16,
        work: 1 << 12,
        memory: 1 << 10,
        piece: 24,
    };
    for n in [1, 2, 3, 17, 40, 65, 97, 130, 200, 257, 411] {
        check_lu(n, fine);
    }
    for n in [300, 1022] {
        check_lu(n, CUTS);
    }
}

#[test]
fn not_positive_definite_and_stopped() {
    let mut a = lower_of(&spd(300, 1));
    a[(200, 200)] = -1.0;
    assert_eq!(
        llt_in_place_until(a.as_mut(), NEVER),
        Ok(Err(NotPositiveDefinite))
    );
    let mut a = lower_of(&spd(300, 1));
    assert_eq!(llt_in_place_until(a.as_mut(), &|| true), Err(Stopped));
    assert!(llt_inverse_until(a.as_ref(), &|| true).is_err());
}

/// The stepwise LU against faer's: P A = L U to rounding, the same permutation convention (its
/// inverse through `lu_inverse_until` agrees with faer's LU inverse), the same pivots on a
/// matrix that needs them, and a stop heard.
#[test]
fn the_stepwise_lu_factors_as_faer_does_and_stops() {
    for n in [1, 2, 3, 17, 64, 65, 130, 300, 1022] {
        let a = spd(n, 5 * n as u64);
        // Large entries below the diagonal: partial pivoting must interchange rows.
        let a = Mat::from_fn(n, n, |i, j| {
            a[(i, j)] + if i > j { 3.0 * n as f64 } else { 0.0 }
        });
        let (lu, p) = partial_piv_lu_until(a.as_ref(), NEVER).unwrap();
        let faer_lu = a.partial_piv_lu();
        let (forward, _) = p.as_ref().arrays();
        let (faer_forward, _) = faer_lu.P().arrays();
        assert_eq!(forward, faer_forward, "the pivots, n = {n}");
        // P A = L U, row by row.
        let scale = a.norm_max();
        for i in 0..n {
            for j in 0..n {
                let sum: f64 = (0..=i.min(j))
                    .map(|m| if m == i { 1.0 } else { lu[(i, m)] } * lu[(m, j)])
                    .sum();
                let diff = (sum - a[(forward[i], j)]).abs();
                assert!(
                    diff <= 1e-12 * scale,
                    "P A = L U at ({i}, {j}), n = {n}: {diff:e}"
                );
            }
        }
        let inverse = lu_inverse_until((lu.as_ref(), lu.as_ref(), p.as_ref()), NEVER).unwrap();
        let faer_inverse = faer_lu.inverse();
        let diff = (&inverse - &faer_inverse).norm_max() / faer_inverse.norm_max();
        assert!(
            diff < 1e-10,
            "inverse differs from faer's by {diff:e}, n = {n}"
        );
    }
    let a = spd(300, 9);
    assert!(partial_piv_lu_until(a.as_ref(), &|| true).is_err());
}
