//! The regularised method's cases one by one (paper 2.7.1, Table 1 and system (43)), for the
//! explorer's case table: for every friction DOF the region of its value c relative to
//! [−ε, ε], each case's linear system solved as `regularized` solves it (the Schur complement
//! on the friction DOFs, the same arithmetic), whether its solution lies in its own regions,
//! and cond₂ of its whole finite-element matrix Â (A with g/ε added on the diagonal of the
//! middle DOFs), as Figure 5 plots it. Every case is listed for k ≤ 2 obstacles (9 or 81);
//! above, the consistent cases are counted. It also says over which cases the ε-cond chart
//! (the ε sweep, `super::epsilon`) takes its largest condition number.

use serde::Serialize;

use super::condensation::condense;
use super::epsilon::CONDITION_LIMIT;
use super::{Cancel, Cancelled};
use crate::fem::{Mesh, StiffnessMatrix};
use crate::linalg::condition::{ConditionKind, DENSE_LIMIT, block_condition_until};
use crate::linalg::stop::Stopped;
use crate::linalg::{BlockMatrix, BlockTridiagonal};
use crate::model::Problem;
use crate::solve::MAX_CASES;
use crate::solve::internals::{
    EpsilonRegion, case_count, case_regions, case_violation, conditions_every_case,
    middle_additions, solve_case,
};

/// Most obstacles for which every case is listed (9^2 = 81 rows).
pub const LISTED_OBSTACLES: usize = 2;

/// Cases solved between two questions to the caller's cancel.
const CASES_BETWEEN_QUESTIONS: u64 = 1024;

/// Where a friction DOF's value c lies in Table 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Region {
    /// c < −ε: the friction force is −g (the right-hand side gains +g).
    Negative,
    /// |c| ≤ ε: the force is g c/ε (the diagonal gains g/ε).
    Middle,
    /// c > ε: the force is +g (the right-hand side gains −g).
    Positive,
}

impl Region {
    /// `−`, `0` or `+` (a true minus sign).
    pub fn symbol(self) -> char {
        match self {
            Region::Negative => '−',
            Region::Middle => '0',
            Region::Positive => '+',
        }
    }

    /// `-`, `0` or `+`.
    pub fn ascii(self) -> char {
        match self {
            Region::Negative => '-',
            Region::Middle => '0',
            Region::Positive => '+',
        }
    }

    fn of(region: EpsilonRegion) -> Region {
        match region {
            EpsilonRegion::Negative => Region::Negative,
            EpsilonRegion::Middle => Region::Middle,
            EpsilonRegion::Positive => Region::Positive,
        }
    }
}

/// One case of the enumeration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseRow {
    /// Its number in the method's enumeration order (digit q in base 3 is DOF q's region:
    /// 0 middle, 1 positive, 2 negative).
    pub index: u64,
    /// The assumed region of every friction DOF, two per obstacle: deflection, then rotation.
    pub regions: Vec<Region>,
    /// Does the case's own solution lie in its assumed regions (to the last bit, the method's
    /// own test)?
    pub consistent: bool,
    /// How far the case's solution lies outside its assumed regions, in units of ε: 0 when
    /// consistent, infinite when the case's matrix could not be factored or its solution is
    /// not finite.
    pub worst_violation: f64,
    /// cond₂ of the case's whole finite-element matrix Â (Figure 5); `None` above
    /// N = [`DENSE_LIMIT`] unknowns or when it could not be computed.
    pub condition: Option<f64>,
    /// How `condition` was obtained: from all eigenvalues (`Exact`), or, when λ_min is below
    /// what the eigensolver resolves, an estimate or a lower bound.
    pub condition_kind: Option<ConditionKind>,
}

/// The cases, listed or counted.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CaseTable {
    /// k ≤ 2: every case (9 or 81 rows), in the method's enumeration order.
    All {
        rows: Vec<CaseRow>,
        /// The case the regularised method keeps: the first consistent one, else the first
        /// of the smallest violation.
        picked: Option<u64>,
    },
    /// k > 2 (or the enumeration refused): counts only.
    Counted {
        /// 9^k, or `u64::MAX` when it overflows.
        cases: u64,
        /// How many cases the method solves before it stops: up to and including the first
        /// consistent one, all of them when none is; 0 when refused.
        tried: u64,
        /// How many of all the cases are consistent (all were solved for the count).
        consistent: u64,
        /// 9^k is over `max_cases`: nothing was solved.
        refused: bool,
    },
}

/// Over which cases the ε-cond chart takes its largest cond₂(Â).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConditionedSubset {
    pub cases_conditioned: u64,
    /// 9^k, or `u64::MAX` when it overflows.
    pub cases_total: u64,
    /// Which ones, in words.
    pub description: String,
}

/// The case study of one scene at one ε.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseStudy {
    pub table: CaseTable,
    pub epsilon: f64,
    pub conditioned: ConditionedSubset,
    /// The case the method keeps, for any k (with its condition number when N is small);
    /// `None` when the enumeration refused.
    pub kept: Option<CaseRow>,
}

impl CaseStudy {
    /// The number of the case the method keeps, if any.
    pub fn picked(&self) -> Option<u64> {
        self.kept.as_ref().map(|row| row.index)
    }
}

/// The case study of `problem` on `mesh` at `epsilon`: every case for k ≤
/// [`LISTED_OBSTACLES`], else the counts, refused (nothing solved) when 9^k exceeds
/// `max_cases`. `Ok(Err(why))` for an ε that is not positive and finite or a stiffness
/// matrix that cannot be factored; [`Cancelled`] as soon as `cancel` says so (asked every
/// [`CASES_BETWEEN_QUESTIONS`] cases and inside the factorization and the eigensolver).
pub fn case_study(
    problem: &Problem,
    mesh: &Mesh,
    epsilon: f64,
    max_cases: u64,
    cancel: &Cancel,
) -> Result<Result<CaseStudy, String>, Cancelled> {
    if !(epsilon > 0.0 && epsilon.is_finite()) {
        return Ok(Err(format!("ε must be positive and finite, not {epsilon}")));
    }
    let k = problem.obstacles.len();
    let count = case_count(k);
    let conditioned = conditioned_subset(k, count, mesh.unknowns());
    let Some(cases) = count.filter(|&c| c <= max_cases) else {
        return Ok(Ok(CaseStudy {
            table: CaseTable::Counted {
                cases: count.unwrap_or(u64::MAX),
                tried: 0,
                consistent: 0,
                refused: true,
            },
            epsilon,
            conditioned,
            kept: None,
        }));
    };
    let stop = || cancel.is_cancelled();
    let enumeration = Enumeration {
        mesh,
        epsilon,
        thresholds: problem.thresholds(),
        matrix: (mesh.unknowns() <= DENSE_LIMIT)
            .then(|| StiffnessMatrix::new(mesh).to_block_tridiagonal()),
        stop: &stop,
    };
    let run = || -> Result<Result<CaseStudy, String>, Stopped> {
        let condensation = match condense(problem, mesh, &stop)? {
            Ok(c) => c,
            Err(why) => return Ok(Err(why)),
        };
        let listed = k <= LISTED_OBSTACLES;
        let tally = enumeration.run(&condensation, cases, listed)?;
        let kept = match &tally.kept {
            Some((violation, index, regions)) => {
                Some(enumeration.row(*index, regions, *violation)?)
            }
            None => None,
        };
        let table = if listed {
            CaseTable::All {
                rows: tally.rows,
                picked: kept.as_ref().map(|row| row.index),
            }
        } else {
            CaseTable::Counted {
                cases,
                tried: tally.first_consistent.map_or(cases, |c| c + 1),
                consistent: tally.consistent,
                refused: false,
            }
        };
        Ok(Ok(CaseStudy {
            table,
            epsilon,
            conditioned,
            kept,
        }))
    };
    run().map_err(|Stopped| Cancelled)
}

/// What the enumeration reads.
struct Enumeration<'a> {
    mesh: &'a Mesh,
    epsilon: f64,
    thresholds: Vec<f64>,
    /// A, explicitly, when it is small enough for exact condition numbers.
    matrix: Option<BlockTridiagonal>,
    stop: crate::linalg::stop::Stop<'a>,
}

/// What the enumeration found.
struct Tally {
    /// Every row, when listed.
    rows: Vec<CaseRow>,
    /// (violation, index, regions) of the case the method keeps.
    kept: Option<(f64, u64, Vec<EpsilonRegion>)>,
    first_consistent: Option<u64>,
    consistent: u64,
}

impl Enumeration<'_> {
    /// Solves cases `0..cases` as `regularized` does, keeping the case it keeps (the first
    /// of the smallest violation among those whose matrix factors; it stops at the first
    /// consistent one, which is the same case).
    fn run(
        &self,
        condensation: &super::condensation::Condensation,
        cases: u64,
        listed: bool,
    ) -> Result<Tally, Stopped> {
        let mut tally = Tally {
            rows: Vec::new(),
            kept: None,
            first_consistent: None,
            consistent: 0,
        };
        let mut regions = vec![EpsilonRegion::Middle; condensation.dofs];
        for case in 0..cases {
            if case % CASES_BETWEEN_QUESTIONS == 0 && (self.stop)() {
                return Err(Stopped);
            }
            case_regions(case, &mut regions);
            let solved = solve_case(
                &condensation.stiffness,
                &condensation.load,
                &self.thresholds,
                &regions,
                self.epsilon,
            );
            let violation = solved
                .as_ref()
                .map_or(f64::INFINITY, |c| case_violation(&regions, c, self.epsilon));
            if violation == 0.0 {
                tally.consistent += 1;
                tally.first_consistent.get_or_insert(case);
            }
            if solved.is_some() && tally.kept.as_ref().is_none_or(|(v, _, _)| violation < *v) {
                tally.kept = Some((violation, case, regions.clone()));
            }
            if listed {
                tally.rows.push(self.row(case, &regions, violation)?);
            }
        }
        Ok(tally)
    }

    /// The row of one case, with cond₂ of its Â when A is small.
    fn row(
        &self,
        index: u64,
        regions: &[EpsilonRegion],
        violation: f64,
    ) -> Result<CaseRow, Stopped> {
        let condition = match &self.matrix {
            Some(matrix) => {
                let mut modified = matrix.clone();
                for (dof, add) in middle_additions(regions, &self.thresholds, self.epsilon) {
                    let block = self.mesh.obstacle_nodes[dof / 2] - 1;
                    modified.diag[block][if dof % 2 == 0 { 0 } else { 2 }] += add;
                }
                if modified.blocks() == 0 {
                    None
                } else {
                    block_condition_until(&modified, self.stop)?
                }
            }
            None => None,
        };
        Ok(CaseRow {
            index,
            regions: regions.iter().map(|&r| Region::of(r)).collect(),
            consistent: violation == 0.0,
            worst_violation: violation,
            condition: condition.map(|c| c.value),
            condition_kind: condition.map(|c| c.kind),
        })
    }
}

/// Over which cases the ε sweep (the ε-cond chart) takes its largest cond₂(Â), as
/// `regularized` chooses them (`condition_cases` there) at the sweep's limits: the enumeration
/// up to [`MAX_CASES`] (beyond, `regularized-newton` with its final case and the all-middle
/// one), condition numbers only up to [`CONDITION_LIMIT`] unknowns.
fn conditioned_subset(k: usize, count: Option<u64>, unknowns: usize) -> ConditionedSubset {
    let total = count.unwrap_or(u64::MAX);
    let total_words = count.map_or(format!("9^{k} (more than 1.8e19)"), |c| c.to_string());
    let subset = |cases_conditioned: u64, description: String| ConditionedSubset {
        cases_conditioned,
        cases_total: total,
        description,
    };
    if unknowns > CONDITION_LIMIT {
        return subset(
            0,
            format!(
                "no cond₂: the ε sweep computes condition numbers only up to \
                 N = {CONDITION_LIMIT} unknowns (N = {unknowns} here)"
            ),
        );
    }
    let estimates = if unknowns > DENSE_LIMIT {
        format!("; Lanczos estimates, N = {unknowns} > {DENSE_LIMIT}")
    } else {
        String::new()
    };
    let enumerated = count.is_some_and(|c| c <= MAX_CASES);
    if k == 0 {
        return subset(
            total,
            format!("no obstacles: the one case is A itself{estimates}"),
        );
    }
    if enumerated && conditions_every_case(total, unknowns) {
        return subset(total, format!("cond₂ over all {total} cases of Table 1"));
    }
    let kept = if enumerated {
        "the kept one".to_string()
    } else {
        format!(
            "regularized-newton's final one (the enumeration refuses more than {MAX_CASES} \
             cases)"
        )
    };
    subset(
        2.min(total),
        format!(
            "cond₂ over 2 of {total_words} cases: {kept} and the all-middle one (every g/ε \
             added){estimates}"
        ),
    )
}
