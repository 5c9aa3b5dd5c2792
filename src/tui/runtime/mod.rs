//! The explorer's runtimes, the top of its layers: the event loop that turns a terminal's
//! bytes, window changes, signals and the workers' results into the update's messages and
//! draws ([`event_loop`]) on a [`screen::Screen`]: the local terminal ([`local`],
//! [`terminal`]) or a remote one over SSH ([`remote`]), fed through a [`feed`]; the background workers ([`worker`]) and their fair share of a server's
//! cores ([`cores`]); a served session's time budget ([`budget`]); and the headless explorer that runs the same jobs on the spot
//! ([`headless`]).

pub mod budget;
pub mod cores;
pub mod event_loop;
pub mod feed;
pub mod headless;
pub mod local;
pub mod record;
pub mod remote;
pub mod screen;
pub mod terminal;
pub mod worker;
