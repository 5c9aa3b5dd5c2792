//! The server's memory budget (`--memory-budget`, issue 22): what one explorer may hold at
//! most, what the solves and sweeps running at once may hold at most — both at the server's
//! own limits (the largest window, the fullest undo history, `--max-elements`) — and so how
//! many explorers fit. The session cap is the smaller of `--max-sessions` and that number; a
//! student beyond it is told so politely. The figures are upper bounds over measurements
//! (`cargo bench --bench attacks -- memory`: at most 25.6 MiB per session at 500 × 200,
//! 4000 obstacles, n = 10⁵ and a full undo history, where this reserves 45 MiB; the peak RSS
//! of `beamfric solve`: 374 MiB for `dual-inverse` at N = 3998, 66 MiB for `dual` at 511
//! obstacles and n = 10⁵; docs/classroom.md).

use ratatui::buffer::Cell;

use crate::tui::runtime::feed::MAX_SIZE;
use crate::tui::state::history::UNDO_BYTES;

const MIB: usize = 1 << 20;

/// The budget when `--memory-budget` is not given, in MiB.
pub const DEFAULT_MEMORY_BUDGET_MIB: usize = 4096;
/// The largest budget that may be asked for, in MiB (1 TiB: no overflow, no typo of units).
pub const MAX_MEMORY_BUDGET_MIB: usize = 1 << 20;

/// An explorer's own memory apart from its undo history, screens and results: its thread
/// stacks, its state with a 4096-obstacle scene, the SSH channel's buffers (measured: under
/// 3 MiB at 80 × 24 with 4000 obstacles).
const SESSION_BASE: usize = 8 * MIB;
/// What an explorer keeps per element of its mesh: the solution's fields and the charts'
/// samples of the current and the previous result, a sweep's results (measured: about 40).
const SESSION_BYTES_PER_ELEMENT: usize = 128;
/// Frames queued for a client ([`crate::serve::explorer`] keeps at most 4) and the one being
/// drawn: a full redraw is at most this many bytes per cell (a colour change and a character).
const FRAMES_HELD: usize = 5;
const FRAME_BYTES_PER_CELL: usize = 16;
/// A solve's peak apart from its mesh: the dense methods' matrices at their limits
/// (`dual-inverse`'s explicit inverse of A at N = 4000, three 4000 × 4000 matrices).
const SOLVE_DENSE_PEAK: usize = 400 * MIB;
/// A quick solve's peak (`SolveRequest::takes_milliseconds`: at most 2000 elements and 4
/// obstacles; measured: under 5 MiB over the process's own): one may run per core beside the
/// others, on an express permit.
const QUICK_SOLVE_PEAK: usize = 16 * MIB;
/// A solve's memory per element (the sparse factorizations, the fields, the certificate;
/// measured: about 30 for the closed form at n = 10⁶, 170 for `dual` at 511 obstacles).
const SOLVE_BYTES_PER_ELEMENT: usize = 512;

/// How the budget is shared out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryPlan {
    /// The whole budget, bytes.
    pub budget: usize,
    /// At most what one explorer holds, bytes.
    pub per_session: usize,
    /// At most what the solves and sweeps running at once hold (one per core, and a quick
    /// one per core beside them), bytes.
    pub solves: usize,
    /// The explorers that fit: never more than `--max-sessions`, at least 1 (or the start is
    /// refused).
    pub sessions: usize,
    /// True when the budget, not `--max-sessions`, sets the cap.
    pub limited_by_budget: bool,
}

/// At most what one explorer holds at the server's limits.
pub fn per_session(max_elements: usize) -> usize {
    let cells = usize::from(MAX_SIZE.0) * usize::from(MAX_SIZE.1);
    // The terminal's two buffers (the frame drawn and the one before it).
    let screens = 2 * cells * std::mem::size_of::<Cell>();
    let output = FRAMES_HELD * cells * FRAME_BYTES_PER_CELL;
    (SESSION_BASE + UNDO_BYTES + screens + output)
        .saturating_add(max_elements.saturating_mul(SESSION_BYTES_PER_ELEMENT))
}

/// At most what one solve or sweep holds at `max_elements`.
pub fn per_solve(max_elements: usize) -> usize {
    SOLVE_DENSE_PEAK.saturating_add(max_elements.saturating_mul(SOLVE_BYTES_PER_ELEMENT))
}

/// At most what the solves running at once hold with `cores` permits: one of each kind per
/// core.
pub fn solves_at_once(max_elements: usize, cores: usize) -> usize {
    per_solve(max_elements)
        .saturating_add(QUICK_SOLVE_PEAK)
        .saturating_mul(cores)
}

/// The plan for `budget_mib`, `max_sessions`, `max_elements` and `cores` solves at once;
/// an error in words when not even one explorer fits.
pub fn plan(
    budget_mib: usize,
    max_sessions: usize,
    max_elements: usize,
    cores: usize,
) -> Result<MemoryPlan, String> {
    let budget = budget_mib.saturating_mul(MIB);
    let per_session = per_session(max_elements);
    let solves = solves_at_once(max_elements, cores);
    let fitting = budget.saturating_sub(solves) / per_session;
    if fitting == 0 {
        return Err(format!(
            "--memory-budget {budget_mib}: too small for one explorer: the solves running at \
             once (one per core, {cores} here) take up to {} MiB at --max-elements \
             {max_elements}, and an explorer up to {} MiB; give at least {} MiB",
            solves.div_ceil(MIB),
            per_session.div_ceil(MIB),
            solves.saturating_add(per_session).div_ceil(MIB)
        ));
    }
    Ok(MemoryPlan {
        budget,
        per_session,
        solves,
        sessions: fitting.min(max_sessions),
        limited_by_budget: fitting < max_sessions,
    })
}

impl MemoryPlan {
    /// One line for the log and the lecturer.
    pub fn describe(&self) -> String {
        format!(
            "memory budget {} MiB: {} explorer{} of at most {} MiB each, solves at most {} MiB \
             together{}",
            self.budget / MIB,
            self.sessions,
            if self.sessions == 1 { "" } else { "s" },
            self.per_session.div_ceil(MIB),
            self.solves.div_ceil(MIB),
            if self.limited_by_budget {
                " (the budget, not --max-sessions, sets the number of explorers)"
            } else {
                ""
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_budget_holds_the_default_sessions() {
        let plan = plan(DEFAULT_MEMORY_BUDGET_MIB, 64, 100_000, 2).unwrap();
        assert_eq!(plan.sessions, 64);
        assert!(!plan.limited_by_budget);
        assert!(plan.sessions * plan.per_session + plan.solves <= plan.budget);
    }

    #[test]
    fn a_small_budget_lowers_the_cap_and_a_tiny_one_is_refused() {
        let one = (solves_at_once(100_000, 2) + per_session(100_000)).div_ceil(MIB);
        let plan = plan(one, 64, 100_000, 2).unwrap();
        assert_eq!(plan.sessions, 1);
        assert!(plan.limited_by_budget);
        assert!(plan.describe().contains("the budget, not --max-sessions"));
        let error = super::plan(one - 1, 64, 100_000, 2).unwrap_err();
        assert!(
            error.contains(&format!("give at least {one} MiB")),
            "{error}"
        );
    }

    #[test]
    fn huge_inputs_do_not_overflow() {
        let error = plan(1, 64, usize::MAX, usize::MAX).unwrap_err();
        assert!(error.contains("too small"), "{error}");
        assert!(plan(MAX_MEMORY_BUDGET_MIB, 4096, 100_000, 64).is_ok());
    }
}
