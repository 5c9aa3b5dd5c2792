//! The state of the sweeps behind the chart panels: one slot per sweep of
//! `tui::jobs::sweeps::SWEEPS`, holding the inputs its data belongs to and the data — pending
//! while it is computed (the data of the state before kept, to be drawn as out of date),
//! ready, failed, or idle while no visible panel needs it.

use super::super::jobs::sweeps::{SweepData, SweepInputs};

/// A sweep's data for the state it was computed for.
#[derive(Debug, Clone)]
pub enum SweepState {
    /// Not needed: no visible panel shows it.
    Idle,
    /// Being computed for the current state; the data of the state before, if any, is kept to
    /// be drawn (marked as out of date) until the new data arrives.
    Pending(Option<SweepData>),
    /// Done, for the current state.
    Ready(SweepData),
    /// The sweep cannot run for this state (e.g. the enumeration refuses).
    Failed(String),
}

/// A sweep's slot in the state: the inputs its data belongs to and the data.
#[derive(Debug, Clone)]
pub struct SweepSlot {
    pub inputs: Option<SweepInputs>,
    pub state: SweepState,
}

impl Default for SweepSlot {
    fn default() -> Self {
        SweepSlot {
            inputs: None,
            state: SweepState::Idle,
        }
    }
}

impl SweepSlot {
    /// Marks the slot pending for new `inputs` when `needed` (its older data is dropped: it is
    /// never drawn as current), or idle when no visible panel needs it.
    pub fn refresh(&mut self, needed: bool, inputs: SweepInputs) {
        if !needed {
            *self = SweepSlot::default();
        } else if self.inputs.as_ref() != Some(&inputs) {
            let previous = match std::mem::replace(&mut self.state, SweepState::Idle) {
                SweepState::Ready(data) | SweepState::Pending(Some(data)) => Some(data),
                _ => None,
            };
            *self = SweepSlot {
                inputs: Some(inputs),
                state: SweepState::Pending(previous),
            };
        }
    }

    /// Takes a finished result if it belongs to the slot's current inputs.
    pub fn accept(&mut self, inputs: &SweepInputs, data: Result<SweepData, String>) -> bool {
        if self.inputs.as_ref() != Some(inputs) || !matches!(self.state, SweepState::Pending(_)) {
            return false;
        }
        self.state = match data {
            Ok(d) => SweepState::Ready(d),
            Err(e) => SweepState::Failed(e),
        };
        true
    }
}

/// What a panel draws of its sweep: the data, the data of the state before while the new one
/// is computed, or a notice in its place.
pub enum SweepView<'a, T> {
    Ready(&'a T),
    Outdated(&'a T),
    Notice(String),
}
