//! What the explorer's workers compute, as pure functions of a request: the keystroke's solve
//! ([`solve`]) and the sweeps behind the chart panels ([`sweeps`]). The interactive explorer
//! runs them on background workers (`tui::runtime::worker`), headless rendering on the spot;
//! either way a result carries the request it answers, and `tui::update` keeps it only while
//! it is still the one wanted. The bottom layer of the explorer: it knows nothing of the
//! state, the screen or the keys.

pub mod solve;
pub mod sweeps;
