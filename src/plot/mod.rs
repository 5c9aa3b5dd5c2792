//! Drawing that the explorer and `beamfric report` share: the [`Look`] of a frame (Unicode or
//! ASCII, colour or not), its [`Theme`] of styles, the ASCII stand-ins for every symbol, log–log
//! charts of plain data with decade axes, the study charts built on them, and a buffer turned
//! into text. Nothing here knows the explorer's state: every chart takes its data as arguments.

mod ascii;
mod axes;
mod chart;
mod study_charts;
mod text;
mod theme;

pub use ascii::{ascii_char, transliterate};
pub use axes::{decade_axis, linear_axis, to_unit};
pub use chart::{
    KeyEntry, LogLog, PanelFrame, Series, chart_with_key, curve_marker, log_log, log_points,
    marker_char, notice, point_marker,
};
pub use study_charts::{
    StudyChart, chart_buffer, eps_condition_chart, eps_error_chart, error_time_chart,
};
pub use text::buffer_to_text;
pub use theme::Theme;

/// How a frame is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Look {
    /// No Unicode: ASCII borders, markers and text.
    pub ascii: bool,
    /// Colours (off with NO_COLOR).
    pub color: bool,
}
