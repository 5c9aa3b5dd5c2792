//! Overlays drawn over the frame: the help (every key), the preset picker, and the scene as
//! TOML to copy (saving in a served session).

use ratatui::Frame;
use ratatui::layout::{Constraint, Flex, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph, Wrap};

use crate::plot::Theme;
use crate::scene::{PRESETS, Scene};
use crate::tui::app::{App, Mode};
use crate::tui::keymap::help_lines_with;

fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let [row] = Layout::vertical([Constraint::Length(height.min(area.height))])
        .flex(Flex::Center)
        .areas(area);
    let [cell] = Layout::horizontal([Constraint::Length(width.min(area.width))])
        .flex(Flex::Center)
        .areas(row);
    cell
}

pub(super) fn draw(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    match &app.mode {
        Mode::Help => help(frame, app, theme, area),
        Mode::SceneText => scene_text(frame, app, theme, area),
        Mode::Presets { index } => presets(frame, theme, area, *index),
        _ => {}
    }
}

/// The scene as TOML, without side borders so that it can be copied from the screen as is.
fn scene_text(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let mut lines = vec![
        Line::styled(
            "The scene as TOML (nothing is saved on the server): copy it into a file.",
            theme.dim(),
        ),
        Line::from(""),
    ];
    lines.extend(
        app.scene
            .to_toml()
            .lines()
            .map(|l| Line::from(l.to_string())),
    );
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines), area);
}

fn help(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let mut lines: Vec<Line> = help_lines_with(app.look.ascii, crate::tui::follow::keys(app))
        .iter()
        .map(|(keys, what)| Line::from(format!("{keys:>16}  {what}")))
        .collect();
    lines.push(Line::from(""));
    lines.push(Line::styled(
        "Values: loads, modulus, section, thresholds and ε step by ×10^0.1 (coarse ×10);",
        theme.dim(),
    ));
    lines.push(Line::styled(
        "positions by l/200 (coarse l/20); elements by 10 % (coarse ×10). Units: SI.",
        theme.dim(),
    ));
    if !app.scene.description.is_empty() {
        lines.push(Line::from(""));
        lines.push(Line::from(app.scene.description.clone()));
    }
    let width = 84u16.min(area.width);
    let inner = width.saturating_sub(2).max(1) as usize;
    let rows: usize = lines.iter().map(|l| l.width().div_ceil(inner).max(1)).sum();
    let rect = centered(area, width, rows as u16 + 2);
    frame.render_widget(Clear, rect);
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(Wrap { trim: false })
            .block(theme.block(" Keys (any key closes) ", true)),
        rect,
    );
}

fn presets(frame: &mut Frame, theme: &Theme, area: Rect, index: usize) {
    let lines: Vec<Line> = PRESETS
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let title = Scene::from_toml(p.text, p.name)
                .map(|s| s.title)
                .unwrap_or_default();
            let text = format!("{:<24}{title}", p.name);
            if i == index {
                Line::styled(text, theme.selected())
            } else {
                Line::from(text)
            }
        })
        .collect();
    let height = lines.len() as u16 + 2;
    let rect = centered(area, 72, height);
    frame.render_widget(Clear, rect);
    // Keep the highlighted entry visible when the list is taller than the screen.
    let visible = rect.height.saturating_sub(2) as usize;
    let offset = (index + 1).saturating_sub(visible) as u16;
    frame.render_widget(
        Paragraph::new(lines)
            .scroll((offset, 0))
            .block(theme.block(" Presets (Enter loads, Esc cancels) ", true)),
        rect,
    );
}
