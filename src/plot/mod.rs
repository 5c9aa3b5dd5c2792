//! Drawing that the explorer and `beamfric report` share: the [`Look`] of a frame (Unicode or
//! ASCII, colour or not), its [`Theme`] of styles in one of three [`Palette`]s, ASCII spelled
//! out so that nothing changes meaning, axes whose labels sit at their values (log decades and
//! nice linear ticks, [`PlotArea`]), the study charts built on them, and a buffer turned into
//! text. Nothing here knows the explorer's state: every chart takes its data as arguments.

mod ascii;
mod axes;
mod cases_table;
mod chart;
mod dual_box;
mod figure5;
mod iterations_chart;
mod markers;
mod plot_area;
mod spy;
mod study_charts;
mod text;
mod theme;

pub use ascii::{ascii_char, spell_ascii, transliterate};
pub use axes::{Scale, cell, linear_scale, log_scale, tick_label, to_unit};
pub use cases_table::cases_table;
pub use chart::{
    KeyEntry, PanelFrame, Piece, bounds_of, curve_key, curve_marker, key_layout, log_points,
    marker_char, notice, pack, panel_with_key, point_marker,
};
pub use dual_box::{DualBoxView, dual_box_chart, position_words};
pub use figure5::figure5_chart;
pub use iterations_chart::{iterations_chart, iterations_plot};
pub use markers::MarkerSet;
pub use plot_area::{AxisKind, AxisSpec, Markers, PlotArea};
pub use spy::spy_panel;
pub use study_charts::{
    CurrentRun, StudyChart, chart_buffer, eps_condition_chart, eps_error_chart, error_time_chart,
};
pub use text::buffer_to_text;
pub use theme::{Palette, Theme};

/// What no locale at all means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnsetLocale {
    /// The C locale, which is ASCII: a local process's own environment says nothing.
    Ascii,
    /// UTF-8: an SSH client that sent no locale (most send none) has a terminal that, nearly
    /// always, draws UTF-8.
    Utf8,
}

/// Does the locale ask for UTF-8? The first of `LC_ALL`, `LC_CTYPE` and `LANG` that is set and
/// not empty decides, as in tmux and other terminal programs: UTF-8 when it names `UTF-8` or
/// `utf8` (any case); none set means what `unset` says. `var` reads a variable.
pub fn locale_is_utf8(var: impl Fn(&str) -> Option<String>, unset: UnsetLocale) -> bool {
    ["LC_ALL", "LC_CTYPE", "LANG"]
        .iter()
        .find_map(|name| var(name).filter(|v| !v.is_empty()))
        .map_or(unset == UnsetLocale::Utf8, |locale| {
            let locale = locale.to_ascii_lowercase();
            locale.contains("utf-8") || locale.contains("utf8")
        })
}

/// How a frame is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Look {
    /// No Unicode: ASCII borders, markers and text.
    pub ascii: bool,
    /// Colours (off with NO_COLOR).
    pub color: bool,
}

#[cfg(test)]
mod tests {
    use super::{UnsetLocale, locale_is_utf8};

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| {
            vars.iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| v.to_string())
        }
    }

    /// The local rule: no locale is the C locale.
    fn local(vars: &[(&str, &str)]) -> bool {
        locale_is_utf8(env(vars), UnsetLocale::Ascii)
    }

    #[test]
    fn the_locale_decides_like_tmux() {
        assert!(local(&[("LANG", "en_GB.UTF-8")]));
        assert!(local(&[("LANG", "C.utf8")]));
        assert!(!local(&[("LANG", "C")]));
        assert!(!local(&[]), "no locale is the C locale");
        // LC_ALL over LC_CTYPE over LANG; empty values do not count.
        assert!(!local(&[("LC_ALL", "POSIX"), ("LANG", "C.UTF-8")]));
        assert!(local(&[
            ("LC_ALL", ""),
            ("LC_CTYPE", "de_DE.UTF-8"),
            ("LANG", "C")
        ]));
        assert!(!local(&[
            ("LC_CTYPE", "de_DE.ISO-8859-1"),
            ("LANG", "C.UTF-8")
        ]));
    }
}
