//! The status lines and the hint line, built to fit the width: the solution summary drops its
//! least important items rather than cutting a number; the warnings line gives the count, the
//! most serious warning (in full when it fits in two lines, else its short form) and the key
//! that shows them all; the hints keep whole hints, most useful first.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::fit::{Item, fit_items, wrap_words};
use super::warnings::{headline, ordered};
use crate::format::{duration, sci};
use crate::plot::Theme;
use crate::solve::{Reference, Solution};
use crate::tui::input::keymap::help::{
    discard_hints, end_class_question, overwrite_question, picker_hints, prompt_keys, scroll_keys,
};
use crate::tui::input::keymap::{extra_keys, fitted_hint_line_of, up_down, works_now};
use crate::tui::state::prompt::Prompt;
use crate::tui::state::{App, Discard, Mode};

/// "solving …" while the current state's solve runs (with its run time when the clock may
/// show), else `None`.
fn busy_text(app: &App) -> Option<String> {
    if app.exploration.is_current() {
        return None;
    }
    let elapsed = match app.busy_since {
        Some(since) if app.show_timings => format!(" {:.1} s", since.elapsed().as_secs_f64()),
        _ => String::new(),
    };
    Some(format!(
        "solving n = {} with {}…{elapsed}",
        app.exploration.wanted.elements, app.exploration.wanted.method
    ))
}

/// The summary of a solution, most important first by importance number.
fn solution_items(app: &App, solution: &Solution, elements: usize, unknowns: usize) -> Vec<Item> {
    let mut items = vec![
        Item::new(0, solution.method.to_string()),
        Item::new(1, format!("n = {elements} (N = {unknowns})")),
    ];
    if let Some(e) = solution.epsilon {
        items.push(Item::new(2, format!("ε = {}", sci(e, 2))));
    }
    if app.show_timings {
        items.push(Item::new(
            5,
            format!("solve {}", duration(solution.timing.total())),
        ));
    }
    match solution.error {
        Some(e) if e.reference == Reference::ThisSolution => {
            items.push(Item::new(4, "this is the reference"))
        }
        Some(e) => items.push(Item::new(
            2,
            match e.max_rel {
                Some(rel) => format!("error {} vs {}", sci(rel, 2), e.reference.label()),
                None => "error n/a".into(),
            },
        )),
        None => {}
    }
    items.push(Item::new(
        3,
        format!("KKT {}", sci(solution.kkt_residual, 1)),
    ));
    items
}

pub(super) fn draw_status(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let width = area.width as usize;
    // The follow mode is on the title line (`draw_title`): here it would cost a figure at
    // 80 columns (issue 23 item 2).
    let mut items = Vec::new();
    if let Some(busy) = busy_text(app) {
        items.push(Item::new(0, busy));
        if app.exploration.shown.is_some() {
            items.push(Item::new(2, "shown: previous result"));
        }
    }
    let mut detail: Vec<Line> = Vec::new();
    // Warnings or a refusal's reason, which a long message must not hide.
    let mut detail_matters = false;
    match app.exploration.shown.as_ref().map(|s| (s, &s.solution)) {
        None => {}
        Some((shown, Ok(solution))) => {
            items.extend(solution_items(
                app,
                solution,
                shown.mesh.elements(),
                shown.mesh.unknowns(),
            ));
            detail = warning_lines(solution, theme, width, app.message.is_none());
            detail_matters = !solution.warnings.is_empty();
        }
        Some((shown, Err(e))) => {
            items.push(Item::new(0, e.method.to_string()));
            items.push(Item::new(1, format!("n = {}", shown.mesh.elements())));
            let rows = if app.message.is_none() { 2 } else { 1 };
            // What works instead, and the key that shows it all, stay in view however much
            // of the reason is cut (at 80 columns a refusal's reason takes two rows alone).
            let text = theme
                .text(&format!("{} {}: {};", e.method, e.kind.label(), e.reason))
                .into_owned();
            let tail = theme
                .text(&format!(
                    "the {} method works here (w: in full)",
                    e.suggestion
                ))
                .into_owned();
            detail = fitted_lines(&text, &tail, width, rows, theme.error());
            detail_matters = true;
        }
    }
    // In ASCII the words are spelled out before fitting (ε as eps), so nothing is cut later.
    for item in &mut items {
        item.text = theme.text(&item.text).into_owned();
    }
    // The first item (the busy note) gets its own style.
    let summary = fit_items(&items, &theme.text(" · "), width);
    let [first, second, third] = Layout::vertical([Constraint::Length(1); 3]).areas(area);
    let emphasised = items
        .first()
        .filter(|i| i.importance <= 1 && !app.exploration.is_current())
        .filter(|i| summary.starts_with(&i.text));
    let summary_line = match emphasised {
        Some(item) => Line::from(vec![
            Span::styled(item.text.clone(), theme.warning()),
            Span::raw(summary[item.text.len()..].to_string()),
        ]),
        None => Line::from(summary),
    };
    frame.render_widget(Paragraph::new(summary_line), first);
    let mut rows = detail.into_iter();
    // A message longer than the width takes the warnings' row too where it holds only "no
    // warnings", so that a refusal or a path is read whole at 80 columns; warnings and a
    // refusal's reason keep their row, and the message is cut at a word.
    let message = app.message.as_deref().map(|message| {
        let (first, rest) = super::fit::first_row(message, width);
        (first, super::fit::cut_at_word(rest, width))
    });
    let (second_line, third_line) = match message {
        Some((first, rest)) if !rest.is_empty() && !detail_matters => (
            Line::styled(first, theme.warning()),
            Line::styled(rest, theme.warning()),
        ),
        Some(_) => (
            rows.next().unwrap_or_default(),
            // Cut at a word, never in one (issue 25).
            Line::styled(
                super::fit::cut_at_word(app.message.as_deref().unwrap_or_default(), width),
                theme.warning(),
            ),
        ),
        None => (
            rows.next().unwrap_or_default(),
            rows.next().unwrap_or_default(),
        ),
    };
    frame.render_widget(Paragraph::new(second_line), second);
    frame.render_widget(Paragraph::new(third_line), third);
}

/// `text` and then `tail` in at most `rows` lines of `width`; when they need more, the last
/// line ends with `…` at a word boundary, and then `tail` (the key that shows the text whole).
fn fitted_lines(
    text: &str,
    tail: &str,
    width: usize,
    rows: usize,
    style: ratatui::style::Style,
) -> Vec<Line<'static>> {
    let whole = if tail.is_empty() {
        text.to_string()
    } else {
        format!("{text} {tail}")
    };
    let mut lines = wrap_words(&whole, width);
    if lines.len() > rows {
        lines = wrap_words(text, width);
        lines.truncate(rows);
        // The last row ends in "… " and the tail where there is room for it, else in "…".
        let tail = if tail.chars().count() + 2 < width {
            tail
        } else {
            ""
        };
        let tail_width = match tail.chars().count() {
            0 => 0,
            n => n + 1,
        };
        if let Some(last) = lines.last_mut() {
            let room = |last: &String| last.chars().count() + 1 + tail_width;
            while room(last) > width {
                match last.rfind(' ') {
                    Some(cut) => last.truncate(cut),
                    None => {
                        last.clear();
                        break;
                    }
                }
            }
            last.push('…');
            if !tail.is_empty() {
                last.push(' ');
                last.push_str(tail);
            }
        }
    }
    lines.into_iter().map(|l| Line::styled(l, style)).collect()
}

/// The warnings of `solution` in one or two lines: the count and the key that shows them
/// all, then the most serious one in full if it fits (two rows when `two_rows`), else its
/// short form.
fn warning_lines(
    solution: &Solution,
    theme: &Theme,
    width: usize,
    two_rows: bool,
) -> Vec<Line<'static>> {
    let warnings = ordered(solution);
    let Some(first) = warnings.first() else {
        return vec![Line::styled("no warnings", theme.dim())];
    };
    let count = if warnings.len() == 1 {
        "1 warning (w: in full)".to_string()
    } else {
        format!("{} warnings (w: all)", warnings.len())
    };
    let rows = if two_rows { 2 } else { 1 };
    let full = theme
        .text(&format!("⚠ {count}: {}", first.message))
        .into_owned();
    let lines = wrap_words(&full, width);
    if lines.len() <= rows {
        return lines
            .into_iter()
            .map(|l| Line::styled(l, theme.warning()))
            .collect();
    }
    let short = theme
        .text(&format!(
            "⚠ {count}: {}",
            headline(first.code, solution.kkt_residual)
        ))
        .into_owned();
    fitted_lines(&short, "", width, rows, theme.warning())
}

pub(super) fn draw_hints(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let width = area.width as usize;
    let ascii = app.look.ascii;
    let fit = |hints: Vec<(u8, String)>| {
        let items: Vec<Item> = hints
            .into_iter()
            .map(|(importance, text)| Item::new(importance, text))
            .collect();
        fit_items(&items, " · ", width)
    };
    let text = match &app.mode {
        Mode::Editing { row, prompt } => {
            let label = format!(
                "new {} [{}]: ",
                row.label().trim(),
                if row.unit().is_empty() {
                    "-"
                } else {
                    row.unit()
                }
            );
            let keys = prompt_keys("sets", ascii);
            return draw_prompt(frame, theme, area, &label, prompt, &keys);
        }
        Mode::Save { prompt } => {
            let keys = prompt_keys("saves", ascii);
            return draw_prompt(frame, theme, area, "save the scene to: ", prompt, &keys);
        }
        Mode::Broadcast { prompt } => {
            let keys = prompt_keys("sends", ascii);
            return draw_prompt(frame, theme, area, "to every student: ", prompt, &keys);
        }
        Mode::Students { .. } => format!(
            "{} scroll · b: bring everyone back · m: a message to all · any other key closes",
            up_down(ascii)
        ),
        Mode::ConfirmOverwrite { path } => overwrite_question(path, ascii),
        Mode::ConfirmDiscard { then } => {
            let changed_steps: Vec<String> = app
                .changed_steps()
                .iter()
                .map(|step| (step + 1).to_string())
                .collect();
            let with_steps = |what: &str| {
                if changed_steps.is_empty() {
                    what.to_string()
                } else {
                    format!("{what} (step {} changed too)", changed_steps.join(", "))
                }
            };
            let (quit_too, follow_too) = (with_steps("quit"), with_steps("follow the presenter"));
            let what = match then {
                Discard::Quit => quit_too.as_str(),
                Discard::Reset => "reset to the scene as loaded",
                Discard::Preset(_) => "load the preset",
                Discard::Rejoin => follow_too.as_str(),
            };
            fit(discard_hints(what, ascii))
        }
        Mode::Presets(_) => fit(picker_hints(ascii)),
        Mode::Help { .. } => format!("{} · any other key closes the help", scroll_keys(ascii)),
        Mode::Warnings { .. } => format!("{} · any other key closes", scroll_keys(ascii)),
        Mode::SceneText => "select the text with the mouse to copy it; any key closes".into(),
        Mode::ConfirmEndClass => {
            let (students, unsaved) = app
                .follow
                .as_ref()
                .and_then(|f| f.class_to_end())
                .unwrap_or((0, 0));
            end_class_question(students, unsaved, ascii)
        }
        Mode::ClassEnded { .. } => {
            "select the text with the mouse to copy it; any key leaves".into()
        }
        Mode::Join => "any key closes; J shows it again".into(),
        Mode::Normal => fitted_hint_line_of(ascii, &extra_keys(app), width, &|a| works_now(app, a)),
    };
    frame.render_widget(Paragraph::new(text).style(theme.dim()), area);
}

/// A prompt line: the label, the text with its cursor (a reversed cell) and what Enter/Esc do,
/// scrolled so that the cursor stays on screen; a selected pre-filled value is highlighted.
fn draw_prompt(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    label: &str,
    prompt: &Prompt,
    keys: &str,
) {
    let (before, under, after) = prompt.split();
    let width = area.width as usize;
    let label_width = label.chars().count();
    // Keep the cursor visible: drop characters from the start of the text if needed.
    let room = width.saturating_sub(label_width + 1);
    let skip = before.chars().count().saturating_sub(room);
    let before: String = before.chars().skip(skip).collect();
    let text_style = if prompt.selected {
        theme.selected()
    } else {
        theme.plain()
    };
    let cursor_style =
        ratatui::style::Style::default().add_modifier(ratatui::style::Modifier::REVERSED);
    let line = Line::from(vec![
        Span::styled(label.to_string(), theme.dim()),
        Span::styled(before, text_style),
        Span::styled(under, cursor_style),
        Span::styled(after, text_style),
        Span::styled(format!("   {keys}"), theme.dim()),
    ]);
    frame.render_widget(Paragraph::new(line), area);
}
