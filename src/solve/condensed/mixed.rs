//! The multiple-shooting system of `system` with a mixed condition c_i = D_i λ_i + r_i at
//! every friction DOF in place of a pattern's "c = 0" or "λ = ±g": the linear system of one
//! interior-point step (`interior`). The beam is unloaded: λ here is the change of a force
//! from the held beam (every DOF stuck under the load), and c the motion that change makes.
//! Same band, same unknowns; the DOF's column holds its force where D is small (a DOF close
//! to stuck: c follows from λ) and its motion where D is large (close to moving: λ follows
//! from c), so neither is a small difference of large ones.

use super::CondensedFailure;
use super::system::{BAND_LOWER, BAND_UPPER, JUMPS, Pattern, ShootingSystem};
use crate::linalg::banded_lu::BandedSystem;
use std::cell::Cell;

/// The condition at one friction DOF: c − m = D (λ − λ₀) about a base force λ₀ and motion m
/// (λ = λ₀ with c free where D is infinite). Written about a base point so that the change of
/// a force on the verge of moving (D large, λ₀ at its threshold) is not a small difference
/// of large numbers.
#[derive(Debug, Clone, Copy)]
pub(super) struct Mixed {
    pub(super) weight: f64,
    pub(super) force: f64,
    pub(super) motion: f64,
}

impl Mixed {
    /// The force (change) given as 0 and c free; with `force` set, the force given.
    pub(super) fn free(_dof: usize) -> Mixed {
        Mixed {
            weight: f64::INFINITY,
            force: 0.0,
            motion: 0.0,
        }
    }

    /// c = D λ + this, where the force is the unknown.
    fn offset(&self) -> f64 {
        self.motion - self.weight * self.force
    }

    /// The force change λ − λ₀ from the unknown `value` of the DOF's column, which holds the
    /// force where `force_held`, else the motion.
    fn force_change_from(&self, force_held: bool, value: f64) -> f64 {
        if force_held {
            value - self.force
        } else if self.weight.is_finite() {
            (value - self.motion) / self.weight
        } else {
            0.0
        }
    }

    /// The motion c from the unknown `value` of the DOF's column (see
    /// [`Mixed::force_change_from`]).
    fn motion_from(&self, force_held: bool, value: f64) -> f64 {
        if force_held {
            self.weight * value + self.offset()
        } else {
            value
        }
    }
}

/// What an interior-point step's solves keep ([`ShootingSystem::solve_step`]): per friction
/// DOF whether its column holds its force (set by the factoring solve, for the other), the
/// last solve's unknowns and its force changes (memory reused from step to step).
pub(super) struct StepSolves {
    pub(super) holds_force: Vec<bool>,
    pub(super) unknowns: Vec<f64>,
    pub(super) force_changes: Vec<f64>,
}

impl StepSolves {
    /// After a factoring [`ShootingSystem::solve_mixed`] that set `holds_force`.
    pub(super) fn new(holds_force: Vec<bool>) -> StepSolves {
        StepSolves {
            holds_force,
            unknowns: Vec::new(),
            force_changes: Vec::new(),
        }
    }
}

/// Motions c and the changes of the forces λ − λ₀ per friction DOF.
pub(super) type MotionsAndForces = (Vec<f64>, Vec<f64>);

/// The part of the mixed system every interior-point step shares, assembled once: the moving
/// pattern's matrix without the friction DOFs' columns, and the entries of those columns in
/// the order of assembly (each step scales them by its weights). A step then copies the
/// matrix and goes through a few entries per obstacle instead of assembling every piece
/// again, with the same sums in the same order: the same bits.
pub(super) struct MixedTemplate {
    /// The matrix without the friction DOFs' columns and without the jumps.
    shared: BandedSystem,
    /// The entries in the friction DOFs' columns, in the order of assembly.
    dof_entries: Vec<DofEntry>,
    /// Per friction DOF: its column.
    pub(super) dof_columns: Vec<usize>,
    /// Per friction DOF: its force's entry in its jump row.
    jumps: Vec<JumpEntry>,
}

thread_local! {
    /// The template of the last interior-point guess on this thread ([`MixedTemplate::keep`]):
    /// its matrix (0.9 MB at 4000 obstacles) was allocated and faulted in anew by every solve
    /// (a third of the page faults of a solve on the ties family in a loop of solves).
    static KEPT_TEMPLATE: Cell<Option<MixedTemplate>> = const { Cell::new(None) };
}

impl MixedTemplate {
    /// Keeps this template's memory for the next guess on this thread (its values are stale).
    pub(super) fn keep(self) {
        KEPT_TEMPLATE.set(Some(self));
    }
}

/// Entries a row of the band holds ([`BandedSystem::position`] is row × this + offset).
const BAND_WIDTH: usize = BAND_LOWER + BAND_UPPER + 1;

/// Where the band keeps an entry ([`BandedSystem::position`]), in 32 bits: the template's
/// entries are read twice a step (28 000 of them at 4000 obstacles, where a step's data no
/// longer fits the processor's cache), and at 16 bytes instead of 32 they take half the
/// memory traffic (docs/many-obstacles/step-costs.md, stop 56).
#[derive(Debug, Clone, Copy)]
struct Position(u32);

impl Position {
    fn new(position: usize) -> Position {
        Position(u32::try_from(position).expect("a band of fewer than 2^32 entries"))
    }
    fn index(self) -> usize {
        self.0 as usize
    }
    /// The row of the entry.
    fn row(self) -> usize {
        self.index() / BAND_WIDTH
    }
}

/// An entry of the template in a friction DOF's column (16 bytes).
#[derive(Debug, Clone, Copy)]
struct DofEntry {
    position: Position,
    /// The friction DOF whose column it is in.
    dof: u32,
    value: f64,
}

/// A friction DOF's force in its jump row ([`JUMPS`]): m'⁺ = m'⁻ − λ1, m⁺ = m⁻ + λ2.
#[derive(Debug, Clone, Copy)]
struct JumpEntry {
    position: Position,
    sign: f64,
}

impl ShootingSystem {
    /// The part of the mixed system shared by every interior-point step, in the memory of
    /// the template kept on this thread, if any.
    pub(super) fn mixed_template(&self) -> MixedTemplate {
        let size = self.unknowns();
        let dofs = 2 * self.point_of_obstacle.len();
        // Obstacles are at distinct points: one column per friction DOF.
        let mut dof_of_column = vec![None; size];
        for i in 0..dofs {
            dof_of_column[self.dof_column(i)] = Some(i);
        }
        let MixedTemplate {
            mut shared,
            mut dof_entries,
            mut dof_columns,
            mut jumps,
        } = KEPT_TEMPLATE.take().unwrap_or_else(|| MixedTemplate {
            shared: BandedSystem::new(0, BAND_LOWER, BAND_UPPER),
            dof_entries: Vec::new(),
            dof_columns: Vec::new(),
            jumps: Vec::new(),
        });
        shared.reset(size);
        dof_entries.clear();
        self.assemble_matrix(
            &vec![Pattern::Positive; dofs],
            |p| self.pieces[p].transfer_matrix(),
            |v| v,
            |row, column, value| match dof_of_column[column] {
                Some(dof) => dof_entries.push(DofEntry {
                    position: Position::new(shared.position(row, column)),
                    dof: u32::try_from(dof).expect("fewer than 2^32 DOFs"),
                    value,
                }),
                None => shared.add(row, column, value),
            },
        );
        dof_columns.clear();
        dof_columns.extend((0..dofs).map(|i| self.dof_column(i)));
        jumps.clear();
        jumps.extend((0..dofs).map(|i| {
            let (row, column, sign) = self.jump_entry(i);
            JumpEntry {
                position: Position::new(shared.position(row, column)),
                sign,
            }
        }));
        MixedTemplate {
            shared,
            dof_entries,
            dof_columns,
            jumps,
        }
    }

    /// Does DOF i's column hold its force (D small against its compliance)?
    fn force_unknown(&self, i: usize, mixed: &Mixed) -> bool {
        mixed.weight * self.diagonal_stiffness(i) < 1.0
    }

    /// Solves the system with the conditions `mixed` (one per friction DOF), factoring it in
    /// `banded`, with whether each DOF's column holds its force written to `holds_force` (for
    /// [`ShootingSystem::resolve_mixed`] with the same factors). The beam is unloaded: what it
    /// solves is the change from the held beam (every DOF stuck under the load), which the
    /// interior-point guess works on.
    pub(super) fn solve_mixed(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &mut BandedSystem,
        holds_force: &mut Vec<bool>,
    ) -> Result<MotionsAndForces, CondensedFailure> {
        let x = self.solve_mixed_unknowns(template, mixed, banded, holds_force)?;
        Ok(mixed_values(template, mixed, holds_force, &x))
    }

    /// An interior-point step's solve ([`ShootingSystem::solve_mixed`] when `factor`, else
    /// [`ShootingSystem::resolve_mixed`] with the factors of the last) for the force changes
    /// alone, into `solves`: no motions computed, and the force changes (and the second
    /// solve's unknowns) written into the vectors kept there, refined with the exact
    /// relations where `refine` (`mixed_refinement`); false where the system is singular.
    pub(super) fn solve_step(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &mut BandedSystem,
        (factor, refine): (bool, bool),
        solves: &mut StepSolves,
    ) -> bool {
        let StepSolves {
            holds_force,
            unknowns,
            force_changes,
        } = solves;
        if factor {
            let Ok(x) = self.solve_mixed_unknowns(template, mixed, banded, holds_force) else {
                return false;
            };
            *unknowns = x;
        } else if self
            .resolve_mixed_unknowns(template, mixed, banded, holds_force, unknowns)
            .is_none()
        {
            return false;
        }
        force_changes_into(template, mixed, holds_force, unknowns, force_changes);
        if refine {
            self.refine_step(template, mixed, banded, solves);
        }
        true
    }

    /// Every unknown of the mixed system (see [`ShootingSystem::solve_mixed`]).
    fn solve_mixed_unknowns(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &mut BandedSystem,
        holds_force: &mut Vec<bool>,
    ) -> Result<Vec<f64>, CondensedFailure> {
        banded.reset_to(&template.shared);
        self.fill_holds_force(mixed, holds_force);
        // Into the system's own (zero) right-hand side and matrix.
        let (matrix, rhs) = banded.matrix_and_rhs_mut();
        self.assemble_mixed(template, mixed, holds_force, Some(matrix), rhs);
        banded
            .solve_from_both_ends()
            .map_err(|e| CondensedFailure::Singular { column: e.column })
    }

    /// The same system (the same weights, so the same factors in `banded` and the same
    /// `holds_force` as the last [`ShootingSystem::solve_mixed`]) with other offsets: one
    /// back substitution. `None` without factors.
    pub(super) fn resolve_mixed(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &BandedSystem,
        holds_force: &[bool],
    ) -> Option<MotionsAndForces> {
        let mut x = Vec::new();
        self.resolve_mixed_unknowns(template, mixed, banded, holds_force, &mut x)?;
        Some(mixed_values(template, mixed, holds_force, &x))
    }

    /// Every unknown of [`ShootingSystem::resolve_mixed`]'s system, into `x`.
    fn resolve_mixed_unknowns(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &BandedSystem,
        holds_force: &[bool],
        x: &mut Vec<f64>,
    ) -> Option<()> {
        x.clear();
        x.resize(self.unknowns(), 0.0);
        self.assemble_mixed(template, mixed, holds_force, None, x);
        banded.apply_inverse(x).then_some(())
    }

    /// Per friction DOF: does its column hold its force? Into `holds_force`.
    fn fill_holds_force(&self, mixed: &[Mixed], holds_force: &mut Vec<bool>) {
        holds_force.clear();
        holds_force.extend(
            mixed
                .iter()
                .enumerate()
                .map(|(i, m)| self.force_unknown(i, m)),
        );
    }

    /// The right-hand side of the mixed system added to `rhs` (zero), and its matrix into
    /// `matrix` when given (the entries of a system holding the template's shared part): the
    /// moving pattern's matrix with c = D λ + r substituted where a force is the unknown, and
    /// λ = (c − r)/D in the jump where the motion is.
    fn assemble_mixed(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        holds_force: &[bool],
        mut matrix: Option<&mut [f64]>,
        rhs: &mut [f64],
    ) {
        for &DofEntry {
            position,
            dof,
            value,
        } in &template.dof_entries
        {
            let (row, dof) = (position.row(), dof as usize);
            let entry = if holds_force[dof] {
                rhs[row] -= value * mixed[dof].offset();
                mixed[dof].weight * value
            } else {
                value
            };
            if let Some(m) = matrix.as_deref_mut() {
                m[position.index()] += entry;
            }
        }
        for ((m, &force_held), jump) in mixed.iter().zip(holds_force).zip(&template.jumps) {
            let JumpEntry { position, sign } = *jump;
            let row = position.row();
            let entry = if force_held {
                sign
            } else if m.weight.is_finite() {
                // λ = λ₀ + (c − m)/D in the jump.
                rhs[row] += sign * (m.motion / m.weight) - sign * m.force;
                sign / m.weight
            } else {
                rhs[row] -= sign * m.force;
                continue;
            };
            if let Some(matrix) = matrix.as_deref_mut() {
                matrix[position.index()] += entry;
            }
        }
    }

    /// The column of friction DOF i (its motion, or its force).
    fn dof_column(&self, i: usize) -> usize {
        Self::column(self.point_of_obstacle[i / 2], i % 2)
    }

    /// (row, column, sign) of DOF i's force in its jump row.
    fn jump_entry(&self, i: usize) -> (usize, usize, f64) {
        let p = self.point_of_obstacle[i / 2];
        let (_, jump_row, sign) = JUMPS[i % 2];
        (4 * (p - 1) + jump_row, self.dof_column(i), sign)
    }
}

/// The force changes alone of [`mixed_values`], into `forces`.
fn force_changes_into(
    template: &MixedTemplate,
    mixed: &[Mixed],
    holds_force: &[bool],
    x: &[f64],
    forces: &mut Vec<f64>,
) {
    forces.clear();
    forces.extend(
        mixed
            .iter()
            .zip(holds_force)
            .zip(&template.dof_columns)
            .map(|((m, &force_held), &column)| m.force_change_from(force_held, x[column])),
    );
}

/// Motions and forces from a solution `x`.
fn mixed_values(
    template: &MixedTemplate,
    mixed: &[Mixed],
    holds_force: &[bool],
    x: &[f64],
) -> MotionsAndForces {
    mixed
        .iter()
        .zip(holds_force)
        .zip(&template.dof_columns)
        .map(|((m, &force_held), &column)| {
            let value = x[column];
            (
                m.motion_from(force_held, value),
                m.force_change_from(force_held, value),
            )
        })
        .unzip()
}
