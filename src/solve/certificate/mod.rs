//! The certificate [`solve`](crate::solve::solve) attaches to every method's answer, the same
//! way for every method: the relative KKT residual of (38), the friction state of every
//! obstacle, condition numbers when asked, the error against a reference (the closed form (50)
//! where it applies, else the `condensed` method on the same mesh) and warnings in words. The
//! reference of one mesh ([`MeshReference`]) is solved at most once per
//! [`solve`](crate::solve::solve) call, whoever asks for it first.
//!
//! The parts: `certify` (the certificate of one solution), `equilibrium` (the independent
//! check of (38) and the friction states), `reference` (the reference solution of a mesh and
//! the error against it), `warnings` (the warnings in words).

mod certify;
mod equilibrium;
mod reference;
mod warnings;

pub(crate) use certify::friction_data_rounding;
pub(super) use certify::{certified_condensed, certify};
pub(crate) use equilibrium::{FORCE_ULPS, MOTION_ULPS};
pub(super) use reference::MeshReference;
