//! Drawing the explorer, above the layout: reads the [`App`] and draws a frame, changing
//! nothing. One code path for the terminal and for headless rendering.
//!
//! Where things go is `tui::layout`, computed once per frame here; this module draws the
//! title, the parameters and the panels, and hands the results, the status and hint lines,
//! the warnings view and the overlays to their own modules.

mod charts;
pub mod fit;
mod lesson;
mod method_panels;
mod overlays;
mod results;
mod status;
mod students;
pub mod warnings;

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use crate::format::printable;
use crate::plot::{Theme, transliterate};
use crate::tui::layout::{MIN_SIZE, ScreenLayout, screen_layout};
use crate::tui::state::App;
use crate::tui::state::params::Row;
use fit::{Item, cut_at_word, fit_joined};

/// Draws the whole frame.
pub fn draw(frame: &mut Frame, app: &App) {
    let theme = Theme::new(app.look, app.palette, app.markers);
    let area = frame.area();
    // The palette's own background, where it has one (high contrast).
    frame.render_widget(ratatui::widgets::Block::new().style(theme.base()), area);
    match screen_layout(app, area) {
        None => too_small(frame, area),
        Some(layout) => {
            draw_title(frame, app, &theme, layout.title);
            if let Some(area) = layout.description {
                overlays::description_line(frame, app, &theme, area);
            }
            if let Some(area) = layout.caption {
                lesson::draw_caption_strip(frame, app, &theme, area);
            }
            if layout.parameters.area() > 0 {
                draw_parameters(frame, app, &theme, layout.parameters);
            }
            if let Some(results) = layout.results {
                results::draw_results(frame, app, &theme, results);
            }
            draw_panels(frame, app, &theme, &layout);
            status::draw_status(frame, app, &theme, layout.status);
            status::draw_hints(frame, app, &theme, layout.hints);
            overlays::draw(frame, app, &theme, area);
        }
    }
    if app.look.ascii {
        transliterate(frame.buffer_mut());
    }
}

fn too_small(frame: &mut Frame, area: Rect) {
    let text = format!(
        "terminal too small: {}x{}, need at least {}x{}",
        area.width, area.height, MIN_SIZE.0, MIN_SIZE.1
    );
    frame.render_widget(Paragraph::new(text).wrap(Wrap { trim: true }), area);
}

fn draw_title(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let p = &app.exploration.problem;
    let scene = app.scene();
    let obstacles = p.obstacles.len();
    let inertia = scene.beam.section.inertia();
    let segments = if scene.beam.segments.is_empty() {
        String::new()
    } else {
        format!(
            ", {} segment{}",
            scene.beam.segments.len(),
            if scene.beam.segments.len() == 1 {
                ""
            } else {
                "s"
            }
        )
    };
    // Whole items by importance, never one cut in the middle (issue 25): the title first,
    // then the obstacles, the length and J, then where the scene came from.
    let items = [
        Item::new(
            0,
            format!(
                "{}{}",
                if app.modified() { "[modified] " } else { "" },
                printable(&scene.title)
            ),
        ),
        Item::new(
            4,
            format!("({})", printable(&app.exploration.source.to_string())),
        ),
        Item::new(2, format!("l = {} m", crate::format::eng(p.length))),
        Item::new(3, format!("J = {} m^4", crate::format::eng(inertia))),
        Item::new(
            1,
            format!(
                "{obstacles} obstacle{}{segments}",
                if obstacles == 1 { "" } else { "s" }
            ),
        ),
    ];
    let separators = ["", " ", " · ", " · ", " · "];
    let joined: Vec<(&Item, &str)> = items.iter().zip(separators).collect();
    // A follow mode leads the line, where it costs no figure of the status (issue 23 item 2).
    let label = app
        .follow
        .as_ref()
        .map(|follow| format!(" {} ", theme.text(&follow.label())));
    let bar = if app.look.ascii { "|" } else { "│" };
    let used = label
        .as_ref()
        .map_or(0, |l| l.chars().count() + bar.chars().count());
    let room = usize::from(area.width).saturating_sub(used + 1);
    let text = format!(" {}", cut_at_word(&fit_joined(&joined, room), room));
    let line = match label {
        Some(label) => Line::from(vec![
            Span::styled(label, theme.warning()),
            Span::raw(format!("{bar}{text}")),
        ]),
        None => Line::from(text),
    };
    frame.render_widget(Paragraph::new(line).style(theme.title()), area);
}

fn draw_parameters(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let block = theme.block(" Parameters ", false);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let rows = app.exploration.rows();
    let height = inner.height as usize;
    let selected = app.exploration.selected.min(rows.len() - 1);
    // The scroll `update` keeps, moved only as far as needed to show the selected row.
    let offset = app.parameters_offset(height);
    let label_width = 14usize.min(inner.width as usize / 2);
    let lines: Vec<Line> = rows
        .iter()
        .enumerate()
        .skip(offset)
        .take(height)
        .map(|(i, row)| {
            let label = format!("{:<width$}", row.label(), width = label_width);
            let value = row.value(app.scene());
            let text = format!("{label} {value}");
            let style = if i == selected {
                theme.selected()
            } else if row.obstacle().is_some() && !matches!(row, Row::ObstacleX(_)) {
                theme.dim()
            } else {
                theme.plain()
            };
            Line::from(Span::styled(text, style))
        })
        .collect();
    frame.render_widget(Paragraph::new(lines), inner);
}

fn draw_panels(frame: &mut Frame, app: &App, theme: &Theme, layout: &ScreenLayout) {
    let panels = app.exploration.panels();
    if panels.is_empty() {
        return;
    }
    let focus = app.exploration.focus;
    let focused = panels[focus % panels.len()];
    for (panel, area) in &layout.panels {
        let mut title_suffix = if !layout.all_panels && panels.len() > 1 {
            let index = focus % panels.len();
            format!(" [{}/{} Tab]", index + 1, panels.len())
        } else {
            String::new()
        };
        if app.zoom {
            title_suffix.push_str(" [z: back]");
        }
        charts::draw_panel(
            frame,
            app,
            theme,
            *panel,
            *area,
            &title_suffix,
            !layout.all_panels || focused == *panel,
        );
    }
}
