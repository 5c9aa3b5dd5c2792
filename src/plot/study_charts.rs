//! The charts of the studies (paper Figure 5 and error against run time), drawn from the
//! studies' points: the explorer's panels and the text charts of `beamfric report` are the
//! same drawing.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::widgets::GraphType;

use super::chart::{LogLog, PanelFrame, Series, log_log, log_points};
use super::{Look, Theme, transliterate};
use crate::solve::{Method, Reference};
use crate::study::{EpsPoint, MeshPoint};

/// The regularisation error against ε (paper Figure 5, left).
pub fn eps_error_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[EpsPoint],
    current_epsilon: Option<f64>,
) {
    let error = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.error.and_then(|e| e.max_rel))),
    );
    let series = [(
        ('•', '*'),
        "max rel. error".to_string(),
        error,
        GraphType::Line,
    )];
    let chart = LogLog {
        x_title: "ε",
        series: &series,
        current_epsilon,
        empty: "no error to plot".into(),
    };
    log_log(frame, theme, panel, chart);
}

/// The largest condition number over the cases against ε (paper Figure 5, right), with the
/// Jacobi-scaled one.
pub fn eps_condition_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[EpsPoint],
    current_epsilon: Option<f64>,
) {
    let plain = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.cond_max.map(|c| c.value))),
    );
    let scaled = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.cond_scaled_max.map(|c| c.value))),
    );
    let series = [
        (('•', '*'), "cond2(Â)".to_string(), plain, GraphType::Line),
        (
            ('+', '+'),
            "Jacobi-scaled".to_string(),
            scaled,
            GraphType::Scatter,
        ),
    ];
    let chart = LogLog {
        x_title: "ε",
        series: &series,
        current_epsilon,
        empty: format!(
            "no condition numbers: they are computed for N ≤ {} unknowns",
            crate::study::CONDITION_LIMIT
        ),
    };
    log_log(frame, theme, panel, chart);
}

/// Every method's error against its run time (or against n when `by_time` is false).
pub fn error_time_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[MeshPoint],
    by_time: bool,
) {
    let markers = [
        ('●', 'o'),
        ('■', '#'),
        ('▲', '^'),
        ('◆', '%'),
        ('✚', '+'),
        ('✖', 'x'),
    ];
    let mut series: Vec<Series> = Vec::new();
    for (i, method) in Method::ALL.into_iter().enumerate() {
        let of_method: Vec<_> = points.iter().filter(|p| p.method == method).collect();
        if of_method.is_empty() || of_method.iter().all(|p| p.refused.is_some()) {
            continue;
        }
        let is_reference = of_method.iter().any(|p| p.is_reference());
        let data = log_points(of_method.iter().filter(|p| p.refused.is_none()).map(|p| {
            let x = if by_time {
                p.run_time.as_secs_f64()
            } else {
                p.elements as f64
            };
            (
                x,
                p.error
                    .filter(|e| e.reference != Reference::ThisSolution)
                    .and_then(|e| e.max_rel),
            )
        }));
        let name = if is_reference {
            format!("{method} = reference")
        } else {
            method.name().to_string()
        };
        series.push((markers[i % markers.len()], name, data, GraphType::Scatter));
    }
    let chart = LogLog {
        x_title: if by_time {
            "run time [s]"
        } else {
            "elements n"
        },
        series: &series,
        current_epsilon: None,
        empty: "no error to plot".into(),
    };
    log_log(frame, theme, panel, chart);
}

/// A chart of study data drawn on its own, for reports.
#[derive(Debug, Clone, Copy)]
pub enum StudyChart<'a> {
    /// Regularisation error against ε.
    EpsError(&'a [EpsPoint]),
    /// Largest condition numbers of the cases against ε.
    EpsCondition(&'a [EpsPoint]),
    /// Error against run time (`by_time`) or against n.
    ErrorTime {
        points: &'a [MeshPoint],
        by_time: bool,
    },
}

/// Draws one study chart, with its title, into a fresh buffer of the given size: the same
/// drawing as the explorer's panel.
pub fn chart_buffer(chart: StudyChart, title: &str, width: u16, height: u16, look: Look) -> Buffer {
    let theme = Theme { look };
    let mut terminal = ratatui::Terminal::new(ratatui::backend::TestBackend::new(width, height))
        .expect("an in-memory terminal");
    terminal
        .draw(|frame| {
            let panel = PanelFrame {
                area: frame.area(),
                title: format!(" {title} "),
                focused: false,
            };
            match chart {
                StudyChart::EpsError(points) => eps_error_chart(frame, &theme, panel, points, None),
                StudyChart::EpsCondition(points) => {
                    eps_condition_chart(frame, &theme, panel, points, None)
                }
                StudyChart::ErrorTime { points, by_time } => {
                    error_time_chart(frame, &theme, panel, points, by_time)
                }
            }
            if look.ascii {
                transliterate(frame.buffer_mut());
            }
        })
        .expect("drawing into memory does not fail");
    terminal.backend().buffer().clone()
}
