//! Drawing the explorer: reads the [`App`] and draws a frame, changing nothing. One code path
//! for the terminal and for headless rendering.
//!
//! Layout: title line; parameters on the left; the scene's panels on the right (deflection on
//! top, the others side by side below) when the terminal has at least 100×30 cells, one panel
//! at a time (Tab cycles) from 60×16, and a "terminal too small" notice below that. Then the
//! status (solution summary, warnings, last message) and the key hints.

mod charts;
mod overlays;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use super::app::{App, Discard, Mode};
use super::keymap::hint_line;
use crate::format::{duration, sci};
use crate::plot::{Theme, transliterate};
use crate::scene::Panel;
use crate::solve::Reference;

/// Smallest terminal the explorer draws into.
pub const MIN_SIZE: (u16, u16) = (60, 16);
/// Smallest terminal for every panel at once.
pub const FULL_SIZE: (u16, u16) = (100, 30);

/// Draws the whole frame.
pub fn draw(frame: &mut Frame, app: &App) {
    let theme = Theme::new(app.look, app.palette);
    let area = frame.area();
    // The palette's own background, where it has one (high contrast).
    frame.render_widget(ratatui::widgets::Block::new().style(theme.base()), area);
    if area.width < MIN_SIZE.0 || area.height < MIN_SIZE.1 {
        too_small(frame, area);
    } else {
        let [title, body, status, hints] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Min(8),
            Constraint::Length(3),
            Constraint::Length(1),
        ])
        .areas(area);
        draw_title(frame, app, &theme, title);
        let full = area.width >= FULL_SIZE.0 && area.height >= FULL_SIZE.1;
        let parameters_width = if full { 38 } else { 30 };
        let [left, right] =
            Layout::horizontal([Constraint::Length(parameters_width), Constraint::Min(20)])
                .areas(body);
        if full {
            let rows = app.rows().len() as u16 + 2;
            let [top, bottom] = Layout::vertical([
                Constraint::Length(rows.min(left.height / 2).max(8)),
                Constraint::Min(3),
            ])
            .areas(left);
            let top = if rows + 6 <= left.height {
                let [t, b] =
                    Layout::vertical([Constraint::Length(rows), Constraint::Min(3)]).areas(left);
                draw_results(frame, app, &theme, b);
                t
            } else {
                draw_results(frame, app, &theme, bottom);
                top
            };
            draw_parameters(frame, app, &theme, top);
        } else {
            draw_parameters(frame, app, &theme, left);
        }
        draw_panels(frame, app, &theme, right, full);
        draw_status(frame, app, &theme, status);
        draw_hints(frame, app, &theme, hints);
        overlays::draw(frame, app, &theme, area);
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
    let p = &app.problem;
    let obstacles = p.obstacles.len();
    let inertia = app.scene.beam.section.inertia();
    let segments = if app.scene.beam.segments.is_empty() {
        String::new()
    } else {
        format!(", {} segment(s)", app.scene.beam.segments.len())
    };
    let text = format!(
        " {}{} ({}) · l = {} m · J = {} m^4 · {} obstacle{}{segments}",
        if app.modified() { "[modified] " } else { "" },
        app.scene.title,
        app.source,
        crate::format::eng(p.length),
        crate::format::eng(inertia),
        obstacles,
        if obstacles == 1 { "" } else { "s" },
    );
    frame.render_widget(Paragraph::new(text).style(theme.title()), area);
}

fn draw_parameters(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let block = theme.block(" Parameters ", false);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let rows = app.rows();
    let height = inner.height as usize;
    let selected = app.selected.min(rows.len() - 1);
    // Scroll so that the selected row stays visible (a pure function of the selection).
    let offset = (selected + 1).saturating_sub(height);
    let label_width = 14usize.min(inner.width as usize / 2);
    let lines: Vec<Line> = rows
        .iter()
        .enumerate()
        .skip(offset)
        .take(height)
        .map(|(i, row)| {
            let label = format!("{:<width$}", row.label(), width = label_width);
            let value = row.value(&app.scene);
            let text = format!("{label} {value}");
            let style = if i == selected {
                theme.selected()
            } else if row.obstacle().is_some() && !matches!(row, super::params::Row::ObstacleX(_)) {
                theme.dim()
            } else {
                theme.plain()
            };
            Line::from(Span::styled(text, style))
        })
        .collect();
    frame.render_widget(Paragraph::new(lines), inner);
}

/// The solution at the obstacles, under the parameters when there is room.
fn draw_results(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let block = theme.block(" Results ", false);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let (Some(Ok(solution)), Some(shown)) = (app.solution(), &app.shown) else {
        let text = if app.shown.is_none() {
            "solving…"
        } else {
            "no solution"
        };
        frame.render_widget(Paragraph::new(text).style(theme.error()), inner);
        return;
    };
    let eng = crate::format::eng;
    let mut lines = vec![Line::from(format!(
        "max |u| {} m",
        eng(shown.max_deflection)
    ))];
    for (i, o) in solution.obstacles.iter().enumerate() {
        lines.push(Line::from(format!(
            "#{} at {} m: {}",
            i + 1,
            eng(o.x),
            o.state()
        )));
        lines.push(Line::styled(
            format!("  u {} m, u' {} rad", eng(o.u), eng(o.slope)),
            theme.dim(),
        ));
        lines.push(Line::styled(
            format!("  F {} N, M {} N m", eng(o.force), eng(o.moment)),
            theme.dim(),
        ));
    }
    frame.render_widget(Paragraph::new(lines), inner);
}

fn draw_panels(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, full: bool) {
    let panels = app.panels();
    if panels.is_empty() {
        return;
    }
    if !full {
        let index = app.focus % panels.len();
        let title_suffix = if panels.len() > 1 {
            format!(" [{}/{} Tab]", index + 1, panels.len())
        } else {
            String::new()
        };
        charts::draw_panel(frame, app, theme, panels[index], area, &title_suffix, true);
        return;
    }
    let has_deflection = panels.contains(&Panel::Deflection);
    let others: Vec<Panel> = panels
        .iter()
        .copied()
        .filter(|p| *p != Panel::Deflection)
        .collect();
    let focused = panels[app.focus % panels.len()];
    let (top, bottom) = match (has_deflection, others.is_empty()) {
        (true, true) => (Some(area), None),
        (true, false) => {
            let [t, b] = Layout::vertical([Constraint::Percentage(55), Constraint::Percentage(45)])
                .areas(area);
            (Some(t), Some(b))
        }
        (false, _) => (None, Some(area)),
    };
    if let Some(top) = top {
        charts::draw_panel(
            frame,
            app,
            theme,
            Panel::Deflection,
            top,
            "",
            focused == Panel::Deflection,
        );
    }
    if let Some(bottom) = bottom {
        let constraints = vec![Constraint::Ratio(1, others.len() as u32); others.len()];
        let cells = Layout::horizontal(constraints).split(bottom);
        for (panel, cell) in others.iter().zip(cells.iter()) {
            charts::draw_panel(frame, app, theme, *panel, *cell, "", focused == *panel);
        }
    }
}

/// "solving …" while the current state's solve runs (with its run time when the clock may
/// show), else empty.
fn busy_text(app: &App) -> Option<String> {
    if app.is_current() {
        return None;
    }
    let elapsed = match app.busy_since {
        Some(since) if app.show_timings => format!(" {:.1} s", since.elapsed().as_secs_f64()),
        _ => String::new(),
    };
    Some(format!(
        "solving n = {} with {}…{elapsed}",
        app.wanted.elements, app.wanted.method
    ))
}

fn draw_status(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let Some(shown) = &app.shown else {
        let text = busy_text(app).unwrap_or_default();
        frame.render_widget(Paragraph::new(Line::styled(text, theme.warning())), area);
        return;
    };
    let (mut summary, detail) = match &shown.solution {
        Ok(s) => {
            let mesh = &shown.mesh;
            let mut parts = vec![
                format!("{}", s.method),
                format!("n = {} (N = {})", mesh.elements(), mesh.unknowns()),
            ];
            if let Some(e) = s.epsilon {
                parts.push(format!("ε = {}", sci(e, 2)));
            }
            if app.show_timings {
                parts.push(format!("solve {}", duration(s.timing.total())));
            }
            match s.error {
                Some(e) if e.reference == Reference::ThisSolution => {
                    parts.push("this is the reference".into())
                }
                Some(e) => parts.push(match e.max_rel {
                    Some(rel) => {
                        format!("error {} vs {}", sci(rel, 2), e.reference.label())
                    }
                    None => "error n/a".into(),
                }),
                None => {}
            }
            parts.push(format!("KKT {}", sci(s.kkt_residual, 1)));
            let detail = match s.warnings.as_slice() {
                [] => Line::styled("no warnings", theme.dim()),
                [w] => Line::styled(format!("warning: {}", w.message), theme.warning()),
                [w, rest @ ..] => Line::styled(
                    format!("warning (+{} more): {}", rest.len(), w.message),
                    theme.warning(),
                ),
            };
            (Line::from(parts.join(" · ")), detail)
        }
        Err(e) => (
            Line::from(format!("{} · n = {}", e.method, shown.mesh.elements())),
            Line::styled(format!("{e}"), theme.error()),
        ),
    };
    if let Some(follow) = &app.follow {
        let mut spans = vec![
            Span::styled(follow.label(), theme.warning()),
            Span::raw(" · "),
        ];
        spans.extend(summary.spans);
        summary = Line::from(spans);
    }
    if let Some(busy) = busy_text(app) {
        // The previous result stays, marked as such.
        let mut spans = vec![
            Span::styled(busy, theme.warning()),
            Span::raw(" · shown: previous result · "),
        ];
        spans.extend(summary.spans);
        summary = Line::from(spans);
    }
    let [first, rest] = Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(area);
    frame.render_widget(Paragraph::new(summary), first);
    match &app.message {
        // The detail may take both remaining rows when there is no message.
        None => frame.render_widget(Paragraph::new(detail).wrap(Wrap { trim: true }), rest),
        Some(message) => {
            let [second, third] =
                Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(rest);
            frame.render_widget(Paragraph::new(detail), second);
            frame.render_widget(
                Paragraph::new(Line::styled(message.clone(), theme.warning())),
                third,
            );
        }
    }
}

fn draw_hints(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let text = match &app.mode {
        Mode::Editing { row, buffer } => format!(
            "new {} [{}]: {buffer}_   Enter sets, Esc cancels",
            row.label().trim(),
            if row.unit().is_empty() {
                "-"
            } else {
                row.unit()
            }
        ),
        Mode::Save { buffer } => format!("save the scene to: {buffer}_   Enter saves, Esc cancels"),
        Mode::ConfirmOverwrite { path } => format!("{path} exists: overwrite it? y / n"),
        Mode::ConfirmDiscard { then } => {
            let what = match then {
                Discard::Quit => "quit",
                Discard::Reset => "reset to the scene as loaded",
                Discard::Preset(_) => "load the preset",
            };
            format!(
                "the scene has unsaved changes: {what} and lose them? \
                 y: yes · s: save, then {what} · n or Esc: no"
            )
        }
        Mode::Presets { .. } => "↑↓ choose a preset, Enter loads it, Esc cancels".into(),
        Mode::Help => "any key closes the help".into(),
        Mode::SceneText => "select the text with the mouse to copy it; any key closes".into(),
        Mode::Normal => hint_line(app.look.ascii),
    };
    frame.render_widget(Paragraph::new(text).style(theme.dim()), area);
}
