//! The explorer's input, above its state: bytes decoded into keys, pastes and mouse events
//! ([`decode`]), keys and their names ([`keys`]), what a key means in each mode
//! ([`keymap`], with the help and hints made from the same tables), and the mouse's clicks,
//! drags and wheel ([`pointer`]).

pub mod decode;
pub mod keymap;
pub mod keys;
pub mod pointer;
