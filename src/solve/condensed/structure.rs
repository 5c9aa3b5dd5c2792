//! The matrix of the multiple-shooting system of one friction pattern, entry by entry: what
//! `system` factors for that pattern (each piece's exact transfer, the jumps (3)–(6) at the
//! obstacles, the clamped ends), for the explorer's view of what the matrices look like
//! (`study::structure`).

use super::scaling::Scales;
use super::search::NEWTON_REVERSAL_FRACTIONS;
use super::system::{Pattern, ShootingSystem};
use crate::fem::Mesh;
use crate::model::Problem;

/// The multiple-shooting matrix of the pattern with friction DOF i stuck where `stuck[i]`
/// (moving elsewhere; a moving DOF's sign changes only the right-hand side), in the method's
/// dimensionless units and before its row equilibration: its size and every entry as
/// (row, column, value), entries of one position summed. `stuck` shorter than 2k counts the
/// missing DOFs as stuck.
pub(crate) fn shooting_matrix(
    problem: &Problem,
    mesh: &Mesh,
    stuck: &[bool],
) -> (usize, Vec<(usize, usize, f64)>) {
    let scales = Scales::of(problem);
    let system = ShootingSystem::new(problem, mesh, &scales, NEWTON_REVERSAL_FRACTIONS[0]);
    let pattern: Vec<Pattern> = (0..2 * problem.obstacles.len())
        .map(|i| {
            if stuck.get(i).copied().unwrap_or(true) {
                Pattern::Stuck
            } else {
                Pattern::Positive
            }
        })
        .collect();
    let size = system.unknowns();
    let mut entries: Vec<(usize, usize, f64)> = Vec::new();
    system.assemble_matrix(
        &pattern,
        |p| system.pieces[p].transfer_matrix(),
        |v| v,
        |row, column, value| entries.push((row, column, value)),
    );
    entries.sort_by_key(|&(row, column, _)| (row, column));
    let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(entries.len());
    for (row, column, value) in entries {
        match merged.last_mut() {
            Some(last) if last.0 == row && last.1 == column => last.2 += value,
            _ => merged.push((row, column, value)),
        }
    }
    (size, merged)
}
