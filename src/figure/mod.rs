//! Slide-quality SVG figures of the explorer's panels (issue 25): the deflection, the
//! regularisation error and the condition numbers against ε, and the error against run time
//! or n. Each is a pure function of the data the panel draws, returning the SVG text; the
//! explorer's `e` key, `beamfric figure` and `beamfric report` share them.
//!
//! Every figure has a 1280 × 720 view box (16:9, pixels at 96 dpi), a white background,
//! text of 20 px and more (≥ 14 pt on a 16:9 slide), one polyline per series with a marker
//! at each point (colour-blind-safe colours, a distinct shape per method; the data values in
//! each marker's `data-x` / `data-y`), log axes over whole decades labelled exactly at their
//! decades, axis names with units at the axes' ends, the current point marked by a dashed
//! rule and a ring, and the legend in a column right of the data. Where there is nothing to
//! plot, the figure says why in the plot area. The output is deterministic (fixed precision,
//! no dates), so figures can be snapshot-tested.
//!
//! The SVG is written here rather than with plotters: plotters puts its legend inside the
//! data, labels log axes at values that are not decades, and cannot say that nothing lies
//! outside the view box; this writer keeps every element inside it (text cut with "…" where
//! it would not fit, its width estimated conservatively).

mod axes;
mod deflection;
mod panels;
mod png;
mod series;
mod svg;

pub use axes::{Axes, Axis, PLOT, PlotFrame, Scale, superscript};
pub use deflection::{DeflectionInput, SAMPLES, deflection_figure, sample_deflection};
pub use panels::{ErrorAxis, eps_cond_figure, eps_error_figure, error_time_figure, method_series};
pub use png::{PNG_SCALE, svg_to_png};
pub use svg::{HEIGHT, LABEL_SIZE, NOTE_SIZE, TITLE_SIZE, WIDTH, escape};

use crate::scene::Panel;

/// A panel a figure can be made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FigurePanel {
    Deflection,
    EpsError,
    EpsCond,
    ErrorTime,
}

impl FigurePanel {
    /// Every panel, in the explorer's order.
    pub const ALL: [FigurePanel; 4] = [
        FigurePanel::Deflection,
        FigurePanel::EpsError,
        FigurePanel::EpsCond,
        FigurePanel::ErrorTime,
    ];

    /// The name, as in scene files: `deflection`, `eps-error`, `eps-cond`, `error-time`.
    pub fn name(self) -> &'static str {
        Panel::from(self).name()
    }

    /// What the figure shows, in words.
    pub fn description(self) -> &'static str {
        match self {
            FigurePanel::Deflection => "the deflection u(x) with the obstacles",
            FigurePanel::EpsError => "the regularisation error against ε",
            FigurePanel::EpsCond => "the largest condition number of the cases against ε",
            FigurePanel::ErrorTime => "every method's error against its run time (or n)",
        }
    }

    /// The names of the axes, with their units.
    fn axis_names(self) -> (&'static str, &'static str) {
        match self {
            FigurePanel::Deflection => ("x [m]", "deflection u [m]"),
            FigurePanel::EpsError => ("ε [m, rad]", "max relative nodal error [1]"),
            FigurePanel::EpsCond => ("ε [m, rad]", "largest cond₂ over the cases [1]"),
            FigurePanel::ErrorTime => ("run time t [s]", "max relative nodal error [1]"),
        }
    }
}

impl From<FigurePanel> for Panel {
    fn from(panel: FigurePanel) -> Panel {
        match panel {
            FigurePanel::Deflection => Panel::Deflection,
            FigurePanel::EpsError => Panel::EpsError,
            FigurePanel::EpsCond => Panel::EpsCond,
            FigurePanel::ErrorTime => Panel::ErrorTime,
        }
    }
}

impl FigurePanel {
    /// The figure of an explorer panel, for the panels that have one (the panels that show how
    /// a method works are for the screen only).
    pub fn of(panel: Panel) -> Option<FigurePanel> {
        match panel {
            Panel::Deflection => Some(FigurePanel::Deflection),
            Panel::EpsError => Some(FigurePanel::EpsError),
            Panel::EpsCond => Some(FigurePanel::EpsCond),
            Panel::ErrorTime => Some(FigurePanel::ErrorTime),
            Panel::Figure5
            | Panel::Iterations
            | Panel::DualBox
            | Panel::Cases
            | Panel::Matrices => None,
        }
    }
}

impl std::str::FromStr for FigurePanel {
    type Err = String;

    /// A panel by its name; an unknown name is refused with the names there are.
    fn from_str(name: &str) -> Result<FigurePanel, String> {
        FigurePanel::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = FigurePanel::ALL.iter().map(|p| p.name()).collect();
                format!(
                    "unknown panel '{}': the panels are {}",
                    crate::format::printable(name),
                    names.join(", ")
                )
            })
    }
}

/// A figure's title: the scene's and what the panel shows (`Benchmark 1: error against n`),
/// the same from `beamfric figure` and the explorer's `e`.
pub fn figure_title(scene_title: &str, panel: FigurePanel, against: ErrorAxis) -> String {
    let what = match (panel, against) {
        (FigurePanel::Deflection, _) => "deflection u(x)",
        (FigurePanel::EpsError, _) => "regularisation error against ε",
        (FigurePanel::EpsCond, _) => "condition numbers against ε",
        (FigurePanel::ErrorTime, ErrorAxis::RunTime) => "error against run time",
        (FigurePanel::ErrorTime, ErrorAxis::Elements) => "error against n",
    };
    format!("{scene_title}: {what}")
}

/// A figure of `panel` that has no data, only `text` saying why (a method that refused, a
/// sweep that could not run): valid SVG with the panel's title and axis names.
pub fn notice_figure(panel: FigurePanel, title: &str, text: &str) -> String {
    let mut svg = series::page(title, panel.description(), panel.axis_names(), "");
    series::draw_notice(&mut svg, text);
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_parse_by_name() {
        for panel in FigurePanel::ALL {
            assert_eq!(panel.name().parse::<FigurePanel>(), Ok(panel));
            assert_eq!(FigurePanel::of(Panel::from(panel)), Some(panel));
        }
        let refused = "plot".parse::<FigurePanel>().unwrap_err();
        assert!(refused.contains("eps-cond"), "{refused}");
    }

    #[test]
    fn a_notice_is_a_whole_document() {
        let svg = notice_figure(FigurePanel::EpsError, "A & B", "the method <refused>");
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        assert!(svg.contains("A &amp; B") && svg.contains("&lt;refused&gt;"));
    }
}
