//! Overlays drawn over the frame: the help (every key), the preset picker, and the scene as
//! TOML to copy (saving in a served session).

use ratatui::Frame;
use ratatui::layout::{Constraint, Flex, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph};

use crate::plot::Theme;
use crate::scene::{PRESETS, Scene};
use crate::tui::app::{App, Mode};
use crate::tui::keymap::help_lines;

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
        Mode::Help { offset } => help(frame, app, theme, area, *offset),
        Mode::SceneText => scene_text(frame, app, theme, area),
        Mode::Warnings { offset } => super::warnings::draw_view(frame, app, theme, area, *offset),
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

/// What the status line's words mean, for the help.
const READING_THE_STATUS: &[&str] = &[
    "error: the largest relative nodal error of u against the reference — the closed form \
     where the scene has one, else the condensed method on the same mesh (shown only when \
     the reference certified itself).",
    "KKT: how far the solution is from satisfying the problem's optimality conditions \
     (equilibrium, |λ1| ≤ g1, |λ2| ≤ g2 and the sign of the motion), relative to the \
     load; about 1e-16 is exact to rounding.",
    "States: stuck (below both thresholds), slides (|λ1| = g1, u ≠ 0), swivels \
     (|λ2| = g2, u' ≠ 0), both; under a regularised method a point below its threshold \
     creeps by about ε·λ inside the ε-band instead of sticking.",
    "λ1, λ2: the friction force [N] and moment [N m] at an obstacle (the paper's names); \
     M in the diagram is the beam's bending moment.",
    "Prompts: ←/→ move the cursor, Ctrl-A/Ctrl-E go to the start/end, Backspace deletes, \
     Ctrl-U erases up to the cursor; the first key typed replaces the value shown.",
    "Values: loads, modulus, section, thresholds and ε step by ×10^0.1 (coarse ×10); \
     positions by l/200 (coarse l/20); elements by 10 % (coarse ×10). Units: SI.",
];

/// The help over the whole frame: every key with what it does (wrapped under its own
/// column), what the status line's words mean, the scene's description; scrolled by
/// `offset` lines when taller than the screen, never cut.
fn help(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, offset: u16) {
    use super::fit::wrap_words;
    let width = 84u16.min(area.width);
    let inner = width.saturating_sub(2).max(1) as usize;
    let bindings = help_lines(app.look.ascii);
    let key_width = bindings
        .iter()
        .map(|(keys, _)| keys.chars().count())
        .max()
        .unwrap_or(0)
        .min(inner / 3);
    let mut lines: Vec<Line> = Vec::new();
    for (keys, what) in &bindings {
        let text_width = inner.saturating_sub(key_width + 2).max(8);
        for (i, part) in wrap_words(what, text_width).into_iter().enumerate() {
            let keys = if i == 0 { keys.as_str() } else { "" };
            lines.push(Line::from(format!("{keys:>key_width$}  {part}")));
        }
    }
    let mut paragraph = |text: &str, style| {
        lines.push(Line::from(""));
        lines.extend(
            wrap_words(text, inner)
                .into_iter()
                .map(|l| Line::styled(l, style)),
        );
    };
    for text in READING_THE_STATUS {
        paragraph(text, theme.dim());
    }
    if !app.scene.description.is_empty() {
        paragraph(
            &format!("This scene: {}", app.scene.description),
            theme.plain(),
        );
    }
    let height = (lines.len() as u16 + 2).min(area.height);
    let rect = centered(area, width, height);
    let visible = rect.height.saturating_sub(2);
    let total = lines.len() as u16;
    let offset = offset.min(total.saturating_sub(visible));
    let mut block = theme.block(" Keys (any key closes) ", true);
    if total > visible {
        block = block.title_bottom(format!(
            " {} lines {}–{} of {total} ",
            crate::tui::keymap::up_down(app.look.ascii),
            offset + 1,
            (offset + visible).min(total)
        ));
    }
    frame.render_widget(Clear, rect);
    frame.render_widget(Paragraph::new(lines).scroll((offset, 0)).block(block), rect);
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
