//! The banded solver's own checks: pivoting, the fixed-size paths against the general ones
//! bit for bit, singular systems, exact scaling by powers of two.

use super::*;

#[test]
fn solves_a_system_that_needs_pivoting() {
    // The first pivot is zero: row exchanges are needed.
    let mut a = BandedSystem::new(3, 1, 1);
    let rows = [[0.0, 1.0, 0.0], [1.0, 0.0, 2.0], [0.0, 3.0, 1.0]];
    let x_true = [1.0, 1.0, 2.0];
    for (r, row) in rows.iter().enumerate() {
        for (c, &v) in row.iter().enumerate() {
            if v != 0.0 {
                a.add(r, c, v);
            }
        }
        let rhs: f64 = row.iter().zip(x_true).map(|(a, x)| a * x).sum();
        a.add_rhs(r, rhs);
    }
    let x = a.solve().unwrap();
    for (x, t) in x.iter().zip(x_true) {
        assert!((x - t).abs() < 1e-15, "{x} vs {t}");
    }
}

#[test]
fn the_fixed_size_path_does_the_general_arithmetic() {
    // The band (3, 3) is eliminated by a fixed-size path away from the last rows; the
    // same matrix in the band (3, 4) goes the general way. Every pivot choice and every
    // operation is the same, so the solutions agree to the last bit.
    let size = 50;
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || uniform(&mut state);
    let mut fixed = BandedSystem::new(size, 3, 3);
    let mut general = BandedSystem::new(size, 3, 4);
    for row in 0..size {
        for column in row.saturating_sub(3)..=(row + 3).min(size - 1) {
            // Small diagonals: the pivots come from other rows.
            let value = if row == column { 1e-3 * next() } else { next() };
            fixed.add(row, column, value);
            general.add(row, column, value);
        }
        let rhs = next();
        fixed.add_rhs(row, rhs);
        general.add_rhs(row, rhs);
    }
    let (x, y) = (
        fixed.solve_unrefined().unwrap(),
        general.solve_unrefined().unwrap(),
    );
    assert_eq!(x, y);
    assert!(x.iter().all(|v| v.is_finite() && *v != 0.0));
    // The substitutions alone, on right-hand sides with zeros (skipped columns) and
    // signed zeros: bit for bit.
    for pattern in 0..4 {
        let b: Vec<f64> = (0..size)
            .map(|i| match (i + pattern) % 4 {
                0 => 0.0,
                1 => -0.0,
                _ => next(),
            })
            .collect();
        let (mut u, mut v) = (b.clone(), b);
        assert!(fixed.apply_inverse(&mut u) && general.apply_inverse(&mut v));
        let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&u), bits(&v), "right-hand side {pattern}");
    }
}

#[test]
fn reports_a_singular_system() {
    let mut a = BandedSystem::new(2, 1, 1);
    a.add(0, 0, 1.0);
    a.add(0, 1, 1.0);
    a.add(1, 0, 2.0);
    a.add(1, 1, 2.0);
    assert_eq!(a.solve().unwrap_err(), SingularColumn { column: 1 });
}

#[test]
fn powers_of_two_scale_exactly_across_the_range() {
    assert_eq!(times_power_of_two(3.0, 2), 12.0);
    assert_eq!(times_power_of_two(1.5, -1073), 3.0 * f64::from_bits(1));
    assert_eq!(
        times_power_of_two(times_power_of_two(0.7, 1020), -1020),
        0.7
    );
    assert_eq!(
        times_power_of_two(times_power_of_two(1e-300, 1900), -1900),
        1e-300
    );
}

/// A band (3, 3) system of `size` rows with small diagonals (the pivots come from other
/// rows), and the same matrix in the band (3, 4), which is eliminated from the top only.
fn condensed_and_general(size: usize, seed: u64) -> (BandedSystem, BandedSystem) {
    let mut state = seed;
    let mut next = || uniform(&mut state);
    let mut fixed = BandedSystem::new(size, 3, 3);
    let mut general = BandedSystem::new(size, 3, 4);
    for row in 0..size {
        for column in row.saturating_sub(3)..=(row + 3).min(size - 1) {
            // Rows of very different units, some entries zero.
            let unit = [1.0, 1e-9, 1e7][row % 3];
            let value = match (row * 7 + column) % 11 {
                0 => 0.0,
                _ if row == column => 1e-3 * next() * unit,
                _ => next() * unit,
            };
            fixed.add(row, column, value);
            general.add(row, column, value);
        }
        let rhs = next();
        fixed.add_rhs(row, rhs);
        general.add_rhs(row, rhs);
    }
    (fixed, general)
}

#[test]
fn elimination_from_both_ends_agrees_with_elimination_from_the_top() {
    // Long systems of the band (3, 3) may be eliminated from both ends (`twisted`): another
    // order of the same partial pivoting, so the solutions agree to rounding.
    for (size, seed) in [(64, 1), (65, 2), (66, 3), (67, 4), (200, 5), (1001, 6)] {
        let (mut twisted, mut general) = condensed_and_general(size, 0x9E37_79B9 + seed);
        let (x, y) = (
            twisted.solve_from_both_ends().unwrap(),
            general.solve_unrefined().unwrap(),
        );
        let largest = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, (a, b)) in x.iter().zip(&y).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * largest,
                "size {size}, row {i}: {a} against {b}"
            );
        }
        // The substitutions alone, with the last factors (from both ends).
        let b: Vec<f64> = (0..size).map(|i| ((i * 37) % 17) as f64 - 8.0).collect();
        let (mut u, mut v) = (b.clone(), b);
        assert!(twisted.apply_inverse(&mut u) && general.apply_inverse(&mut v));
        let largest = v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in u.iter().zip(&v) {
            assert!(
                (a - b).abs() <= 1e-9 * largest,
                "size {size}: {a} against {b}"
            );
        }
        // Every other solve keeps the one-ended order: the same bits as the band (3, 4).
        assert_eq!(
            twisted.solve_unrefined().unwrap(),
            general.solve_unrefined().unwrap()
        );
    }
}

#[test]
fn a_singular_column_is_found_from_either_end_and_in_the_middle() {
    // A zero column anywhere: at the top, in the bottom half, in the block both halves
    // meet in. Each is reported, at its own column.
    let size = 100;
    for zero in [2usize, 30, 50, 51, 52, 97] {
        let (mut system, _) = condensed_and_general(size, 7);
        for row in zero.saturating_sub(3)..=(zero + 3).min(size - 1) {
            let at = row * 7 + zero + 3 - row;
            system.entries[at] = 0.0;
        }
        assert_eq!(
            system.solve_from_both_ends().unwrap_err(),
            SingularColumn { column: zero },
            "column {zero} is zero"
        );
    }
}

/// The next of a xorshift sequence, as a number in [−0.5, 0.5).
fn uniform(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

#[test]
fn the_copy_for_avx_and_fma_gives_the_portable_bits() {
    // Where the processor has AVX and FMA, the twisted factorisation runs a copy compiled
    // for them (`linalg::has_avx_and_fma`); every answer must keep the bits of the portable code,
    // which processors without them run. Both copies on the same systems, with small
    // diagonals so that rows are exchanged; skipped on a processor without the features.
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::has_avx_and_fma() {
        for (size, seed) in [(64, 11), (67, 12), (1001, 13), (16_002, 14)] {
            let (system, _) = condensed_and_general(size, 0x51_u64 << 20 | seed);
            let portable =
                TwistedFactors::portable(&system.entries, size, FactorStorage::default()).unwrap();
            let dispatched =
                TwistedFactors::new(&system.entries, size, FactorStorage::default()).unwrap();
            let b: Vec<f64> = (0..size).map(|i| ((i * 37) % 17) as f64 - 8.0).collect();
            let (mut u, mut v) = (b.clone(), b);
            portable.solve_in_place(&mut u);
            dispatched.solve_in_place(&mut v);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&u), bits(&v), "size {size}");
            assert!(u.iter().all(|v| v.is_finite()), "size {size}");
            let storage = |f: TwistedFactors| {
                let s = f.into_storage();
                [s.entries, s.bottom_entries, s.row_scale, s.inverse_diagonal].map(|v| bits(&v))
            };
            assert_eq!(storage(portable), storage(dispatched), "size {size}");
        }
    }
}

#[test]
fn the_first_solve_is_kept_until_the_system_changes() {
    // A one-ended solve keeps A⁻¹ r before refinement: the bits a substitution with its
    // factors gives again. Gone after a reset or a factorisation from both ends, whose
    // solves are not the one-ended order's.
    let (mut system, _) = condensed_and_general(200, 21);
    assert!(system.first_solve().is_none(), "nothing solved yet");
    let refined = system.solve().unwrap();
    let mut again = system.rhs().to_vec();
    assert!(system.apply_inverse(&mut again));
    assert_eq!(system.first_solve(), Some(&again[..]));
    assert!(refined.iter().all(|v| v.is_finite()));
    let unrefined = system.solve_unrefined().unwrap();
    assert_eq!(system.first_solve(), Some(&unrefined[..]));
    system.solve_from_both_ends().unwrap();
    assert!(system.first_solve().is_none(), "factored from both ends");
    system.solve_unrefined().unwrap();
    let copy = system.clone();
    system.reset_to(&copy);
    assert!(system.first_solve().is_none(), "reset");
}
