//! Overlays drawn over the frame: the help (every key, and the scene's description in full),
//! the preset picker (search, each preset's description, the highlighted one's in full), and
//! the scene as TOML to copy (saving in a served session). Also the scene's description as a
//! line under the title.

use ratatui::Frame;
use ratatui::layout::{Constraint, Flex, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph, Wrap};

use crate::plot::Theme;
use crate::scene::PRESETS;
use crate::tui::app::{App, Mode};
use crate::tui::keymap::help_lines;
use crate::tui::picker::{PresetPicker, preset_infos};

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
        Mode::Warnings { offset } => super::warnings::draw_view(frame, app, theme, area, *offset),
        Mode::Presets(picker) => presets(frame, theme, area, picker),
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
    // The scene's description first, in full: what this scene is for.
    let mut lines: Vec<Line> = Vec::new();
    if !app.scene.description.trim().is_empty() {
        lines.push(Line::styled(
            format!("{}: {}", app.scene.title, app.scene.description.trim()),
            theme.title(),
        ));
        lines.push(Line::from(""));
    }
    lines.extend(
        help_lines(app.look.ascii)
            .iter()
            .map(|(keys, what)| Line::from(format!("{keys:>16}  {what}"))),
    );
    lines.push(Line::from(""));
    lines.push(Line::styled(
        "Values: loads, modulus, section, thresholds and ε step by ×10^0.1 (coarse ×10);",
        theme.dim(),
    ));
    lines.push(Line::styled(
        "positions by l/200 (coarse l/20); elements by 10 % (coarse ×10). Units: SI.",
        theme.dim(),
    ));
    if app.mouse {
        lines.push(Line::styled(
            "Mouse: click a row (twice to type), wheel steps it, drag an obstacle on the chart, \
             click a panel's title to zoom; Shift+drag selects text.",
            theme.dim(),
        ));
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

/// `text` cut to `width` characters, with `…` where it was cut.
fn truncated(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut out: String = text.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}

/// The scene's description on one line under the title (in full in the help).
pub(super) fn description_line(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let text = format!(" {}", app.scene.description.trim());
    frame.render_widget(
        Paragraph::new(truncated(&text, area.width as usize)).style(theme.dim()),
        area,
    );
}

/// Where the preset picker's parts are on a screen of `area`: drawing and mouse hit-testing
/// both use it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PickerLayout {
    /// The whole box, borders included.
    pub outer: Rect,
    /// The search line.
    pub search: Rect,
    /// The list: one preset a row.
    pub list: Rect,
    /// The highlighted preset's title and description, in full (empty when there is no room).
    pub detail: Rect,
}

/// Rows of the highlighted preset's description under the list.
const PICKER_DETAIL_ROWS: u16 = 3;

/// The preset picker's layout on a screen of `area`: as wide as the screen up to 100 columns,
/// every preset listed when there is room, else the list scrolls.
pub fn picker_layout(area: Rect) -> PickerLayout {
    let width = area.width.min(100);
    let wanted = PRESETS.len() as u16 + 2 + PICKER_DETAIL_ROWS + 2;
    let outer = centered(area, width, wanted);
    let inner = Rect::new(
        outer.x.saturating_add(1),
        outer.y.saturating_add(1),
        outer.width.saturating_sub(2),
        outer.height.saturating_sub(2),
    );
    // The search line, the list, a rule and the detail; the detail goes first when short.
    let detail_rows = if inner.height >= 2 + 2 + PICKER_DETAIL_ROWS {
        PICKER_DETAIL_ROWS
    } else {
        0
    };
    let rule = u16::from(detail_rows > 0);
    let list_rows = inner.height.saturating_sub(1 + rule + detail_rows);
    let row = |y: u16, height: u16| Rect::new(inner.x, y, inner.width, height);
    PickerLayout {
        outer,
        search: row(inner.y, inner.height.min(1)),
        list: row(inner.y.saturating_add(1), list_rows),
        detail: row(inner.y.saturating_add(1 + list_rows + rule), detail_rows),
    }
}

fn presets(frame: &mut Frame, theme: &Theme, area: Rect, picker: &PresetPicker) {
    let layout = picker_layout(area);
    let infos = preset_infos();
    let matches = picker.matches();
    let highlighted = picker.index.min(matches.len().saturating_sub(1));
    frame.render_widget(Clear, layout.outer);
    frame.render_widget(
        theme.block(" Presets (type to search, Enter loads, Esc cancels) ", true),
        layout.outer,
    );
    let search = if picker.query.is_empty() {
        Line::styled(
            "search: type a word of a name or a description",
            theme.dim(),
        )
    } else {
        Line::from(format!("search: {}_", picker.query))
    };
    frame.render_widget(Paragraph::new(search), layout.search);
    let width = layout.list.width as usize;
    let name_width = infos.iter().map(|i| i.name.len()).max().unwrap_or(0) + 2;
    let mut lines: Vec<Line> = matches
        .iter()
        .enumerate()
        .skip(picker.offset)
        .take(layout.list.height as usize)
        .map(|(i, &preset)| {
            let info = &infos[preset];
            // The highlight is marked in the text too, for terminals without colours.
            let mark = if i == highlighted { "> " } else { "  " };
            let text = format!("{mark}{:<name_width$}{}", info.name, info.description);
            let text = truncated(&text, width);
            if i == highlighted {
                Line::styled(format!("{text:<width$}"), theme.selected())
            } else {
                Line::from(text)
            }
        })
        .collect();
    if matches.is_empty() {
        lines.push(Line::styled(
            format!("no preset matches \"{}\" (Backspace edits)", picker.query),
            theme.warning(),
        ));
    }
    frame.render_widget(Paragraph::new(lines), layout.list);
    if layout.detail.height > 0 {
        let rule = Rect::new(layout.list.x, layout.detail.y - 1, layout.list.width, 1);
        frame.render_widget(
            Paragraph::new("─".repeat(rule.width as usize)).style(theme.dim()),
            rule,
        );
        if let Some(&preset) = matches.get(highlighted) {
            let info = &infos[preset];
            let detail = Line::from(vec![
                ratatui::text::Span::styled(format!("{}: ", info.title), theme.title()),
                ratatui::text::Span::raw(info.description.clone()),
            ]);
            frame.render_widget(
                Paragraph::new(detail).wrap(Wrap { trim: true }),
                layout.detail,
            );
        }
    }
}
