//! The matrices' structure (A, S, the condensed system) against dense matrices assembled here.

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::study::{Cancelled, MatrixKind, MatrixStructure, SpyGrid, matrix_structures};

use super::{
    cancelled, dense_system, eigen_condition, friction_index, gaussian_solve, relative, steel_beam,
};
use crate::harness::scenes::{preset_scene, problem};

fn structures(problem: &Problem, mesh: &Mesh, grid: (usize, usize)) -> Vec<MatrixStructure> {
    let found = matrix_structures(problem, mesh, grid, &Default::default()).unwrap();
    let kinds: Vec<MatrixKind> = found.iter().map(|s| s.kind).collect();
    assert_eq!(
        kinds,
        [
            MatrixKind::Stiffness,
            MatrixKind::Dual,
            MatrixKind::Condensed
        ]
    );
    found
}

/// The largest |entry| of each block of a dense matrix, cells mapped as the grid's doc says.
fn expected_grid(a: &[f64], rows: usize, cols: usize, grid: &SpyGrid) -> Vec<f64> {
    let mut cells = vec![0.0f64; grid.width * grid.height];
    for r in 0..rows {
        for c in 0..cols {
            let y = r * grid.height / rows;
            let x = c * grid.width / cols;
            cells[y * grid.width + x] = cells[y * grid.width + x].max(a[r * cols + c].abs());
        }
    }
    cells
}

#[test]
fn stiffness_structure_matches_the_dense_hermite_matrix() {
    for (problem, elements) in [
        (problem(&preset_scene("benchmark-1")), 5),
        (steel_beam(&[(0.3, 50.0, 20.0), (0.75, 3e4, 5e4)], true), 9),
    ] {
        let mesh = Mesh::new(&problem, elements);
        let (a, _, n) = dense_system(&problem, &mesh);
        let nonzeros = a.iter().filter(|v| **v != 0.0).count();
        let bandwidth = (0..n * n)
            .filter(|&ij| a[ij] != 0.0)
            .map(|ij| (ij / n).abs_diff(ij % n))
            .max()
            .unwrap();
        // One cell per entry: nonzero exactly where A is.
        let found = structures(&problem, &mesh, (n, n));
        let stiffness = &found[0];
        assert_eq!((stiffness.rows, stiffness.cols), (n, n));
        assert_eq!(stiffness.nonzeros, nonzeros);
        assert_eq!(stiffness.bandwidth, Some(bandwidth));
        assert_eq!(bandwidth, 3, "Hermite cubics couple u_i with u'_(i+1)");
        assert_eq!((stiffness.grid.width, stiffness.grid.height), (n, n));
        for r in 0..n {
            for c in 0..n {
                assert_eq!(stiffness.grid.at(c, r), a[r * n + c].abs(), "({r}, {c})");
            }
        }
        let condition = stiffness.condition.unwrap();
        assert!(relative(condition, eigen_condition(&a, n)) < 1e-10);
        // Coarser grids: the largest entry of each block.
        for cells in [(3, 3), (7, 4), (1, 1), (n + 10, 2)] {
            let found = structures(&problem, &mesh, cells);
            let grid = &found[0].grid;
            assert_eq!(grid.width, cells.0.min(n));
            assert_eq!(grid.cells, expected_grid(&a, n, n, grid), "{cells:?}");
        }
    }
}

#[test]
fn dual_structure_is_s_symmetric_with_a_positive_diagonal() {
    let problem = steel_beam(&[(0.3, 50.0, 20.0), (0.75, 3e4, 5e4)], true);
    let mesh = Mesh::new(&problem, 12);
    let (a, _, n) = dense_system(&problem, &mesh);
    // S = B A⁻¹ Bᵀ: column q of A⁻¹ Bᵀ solves A x = e_(friction DOF q).
    let dim = 2 * problem.obstacles.len();
    let dofs: Vec<usize> = (0..dim)
        .map(|q| friction_index(&mesh, q / 2, q % 2))
        .collect();
    let mut s = vec![0.0; dim * dim];
    for (q, &i) in dofs.iter().enumerate() {
        let mut e = vec![0.0; n];
        e[i] = 1.0;
        let x = gaussian_solve(&a, &e, n).unwrap();
        for (p, &j) in dofs.iter().enumerate() {
            s[p * dim + q] = x[j];
        }
    }
    let found = structures(&problem, &mesh, (dim, dim));
    let dual = &found[1];
    assert_eq!((dual.rows, dual.cols, dual.nonzeros), (dim, dim, dim * dim));
    assert_eq!(dual.bandwidth, None);
    for p in 0..dim {
        assert!(dual.grid.at(p, p) > 0.0);
        for q in 0..dim {
            assert_eq!(dual.grid.at(p, q), dual.grid.at(q, p), "symmetric");
            assert!(relative(dual.grid.at(q, p), s[p * dim + q].abs()) < 1e-9);
        }
    }
    assert!(
        s.iter()
            .enumerate()
            .all(|(pq, v)| pq % (dim + 1) != 0 || *v > 0.0)
    );
    let condition = dual.condition.unwrap();
    assert!(relative(condition, eigen_condition(&s, dim)) < 1e-6);
}

#[test]
fn condensed_structure_is_the_banded_shooting_system() {
    let problem = problem(&preset_scene("benchmark-3"));
    let mesh = Mesh::new(&problem, 20);
    let size = 4 * mesh.pieces.len() - 2;
    let found = structures(&problem, &mesh, (size, size));
    let condensed = &found[2];
    assert_eq!((condensed.rows, condensed.cols), (size, size));
    assert!(condensed.bandwidth.unwrap() <= 3);
    let marked = condensed.grid.cells.iter().filter(|v| **v != 0.0).count();
    assert_eq!(marked, condensed.nonzeros);
    assert!(
        condensed
            .condition
            .is_some_and(|c| c.is_finite() && c >= 1.0)
    );
    assert!(condensed.note.contains("8 DOFs"), "{}", condensed.note);
}

#[test]
fn a_fine_mesh_is_never_dense() {
    let problem = problem(&preset_scene("benchmark-3"));
    let mesh = Mesh::new(&problem, 200_000);
    let started = std::time::Instant::now();
    let found = structures(&problem, &mesh, (80, 40));
    let stiffness = &found[0];
    assert_eq!(stiffness.rows, mesh.unknowns());
    assert_eq!(stiffness.condition, None);
    assert_eq!((stiffness.grid.width, stiffness.grid.height), (80, 40));
    // Only the cells along the diagonal (row block y meets column blocks 2y and 2y + 1, and
    // the band reaches one block further on each side).
    for y in 0..40usize {
        for x in 0..80usize {
            let near = x + 1 >= 2 * y && x <= 2 * y + 2;
            assert_eq!(stiffness.grid.at(x, y) != 0.0, near, "({x}, {y})");
        }
    }
    assert!(started.elapsed().as_secs_f64() < 30.0);
    assert_eq!(
        matrix_structures(&problem, &mesh, (80, 40), &cancelled()),
        Err(Cancelled)
    );
}

#[test]
fn matrix_structures_survive_every_preset_and_odd_grids() {
    for preset in beamfric::scene::PRESETS {
        let loaded = crate::harness::scenes::loaded_preset(preset.name);
        let mesh = Mesh::new(&loaded.problem, loaded.settings.elements.min(2000));
        for grid in [(0, 0), (1, 1), (80, 24), (usize::MAX, usize::MAX)] {
            let found = structures(&loaded.problem, &mesh, grid);
            for s in &found {
                assert_eq!(s.grid.cells.len(), s.grid.width * s.grid.height);
                assert!(!s.note.is_empty());
            }
        }
    }
}
