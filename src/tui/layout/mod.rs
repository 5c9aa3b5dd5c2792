//! Where everything goes on the screen, above the state and the input: the frame's regions
//! ([`screen`]), the preset picker's box ([`picker`]), the deflection chart's data and plot
//! ([`deflection`]), and what is under a cell ([`hit`]). Pure functions of the state and the
//! terminal size: drawing computes them once per frame, and the mouse is hit-tested with the
//! same functions, so a click lands on what is drawn there.

pub mod deflection;
pub mod hit;
pub mod picker;
pub mod screen;

pub use screen::{
    DESCRIPTION_MIN_HEIGHT, FULL_SIZE, MIN_SIZE, Region, ScreenLayout, caption_strip_height,
    caption_width, parameter_rows_shown, screen_layout, visible_panels,
};
