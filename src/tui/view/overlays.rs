//! Overlays drawn over the frame: the help (every key, and the scene's description in full),
//! the preset picker (search, each preset's description, the highlighted one's in full), and
//! the scene as TOML to copy (saving in a served session). Also the scene's description as a
//! line under the title.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph, Wrap};

use super::super::input::keymap::{extra_keys, help_lines_with, up_down};
use super::super::layout::picker::{centered, picker_layout};
use super::super::state::picker::{PresetPicker, preset_infos};
use super::super::state::{App, Mode};
use crate::format::printable;
use crate::plot::Theme;

pub(super) fn draw(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    match &app.mode {
        Mode::Help { offset } => help(frame, app, theme, area, *offset),
        Mode::SceneText => scene_text(frame, app, theme, area),
        Mode::Join => join(frame, app, theme, area),
        Mode::Students { offset } => {
            super::students::draw_students(frame, app, theme, area, *offset)
        }
        Mode::ClassEnded { by, saved } => {
            class_ended(frame, app, theme, area, by, saved.as_deref())
        }
        Mode::Warnings { offset } => super::warnings::draw_view(frame, app, theme, area, *offset),
        Mode::Presets(picker) => presets(frame, theme, area, (picker, app.max_elements)),
        _ => {}
    }
}

/// The scene's TOML, a line per line, as the screen shows it to copy.
fn scene_toml_lines(app: &App) -> Vec<Line<'static>> {
    let toml = app.scene().to_toml();
    toml.lines().map(|l| Line::from(l.to_string())).collect()
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
    lines.extend(scene_toml_lines(app));
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines), area);
}

/// How students join (the lecturer's explorer, at start and on `J`): the command, the host
/// key's whole fingerprint (wrapped, never cut: students check it when ssh asks) and how they
/// log in, with the students connected now.
fn join(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let Some(info) = &app.join else {
        return;
    };
    let width = usize::from(area.width.saturating_sub(4)).max(8);
    let address = info.address;
    let host = if address.ip().is_unspecified() {
        "HOST (this machine's name or address)".to_string()
    } else {
        address.ip().to_string()
    };
    let students = app.follow.as_ref().map_or(0, |f| f.followers.students());
    let mut lines = vec![
        Line::styled("Students join the class with", theme.title()),
        Line::from(""),
        Line::from(format!("  ssh -p {} {host}", address.port())),
        Line::styled(format!("  (the server listens on {address})"), theme.dim()),
        Line::from(""),
        Line::styled(
            "The server's host key (ssh shows it at the first login):",
            theme.title(),
        ),
    ];
    let fingerprint: Vec<char> = info.fingerprint.chars().collect();
    for piece in fingerprint.chunks(width) {
        lines.push(Line::from(format!(
            "  {}",
            piece.iter().collect::<String>()
        )));
    }
    lines.push(Line::from(""));
    lines.push(Line::styled("Logging in:", theme.title()));
    lines.push(Line::from(format!("  {}", info.login)));
    lines.push(Line::from(""));
    lines.push(Line::from(format!(
        "{students} student{} connected now · J shows this again · any key closes",
        if students == 1 { "" } else { "s" }
    )));
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}

/// A student's closing screen: who ended the class and where their work goes. Changes not
/// saved on the server are printed as TOML on the client's own screen once the explorer has
/// left it (`runtime::remote`): whole, unwrapped and in its scrollback, where a screen of this
/// size would cut them.
fn class_ended(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    area: Rect,
    by: &str,
    saved: Option<&str>,
) {
    let kept = match saved {
        Some(name) if !app.has_unsaved_work() => format!(
            "Your changes are saved as {} (in the class's save directory).",
            printable(name)
        ),
        None if !app.has_unsaved_work() => "You have no unsaved changes.".into(),
        _ => "Your changes are not saved on the server: when this \
                                   closes, your scene is printed on your terminal as TOML, \
                                   to copy into a file."
            .into(),
    };
    let lines = vec![
        Line::styled(
            format!("The class was ended by {}.", printable(by)),
            theme.warning(),
        ),
        Line::from(kept),
        Line::styled(
            "Any key leaves; the connection closes soon anyway.",
            theme.dim(),
        ),
    ];
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
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

/// What the mouse does, for the help (when the mouse is on).
const MOUSE_HELP: &str = "Mouse: click a row to select it (double-click to type its value), the \
     wheel over the parameters steps the selected value; drag an obstacle's marker along the \
     deflection chart; click a panel to focus it, its title (or a double click) to zoom it; \
     click the warnings in the status line to read them all. Shift+drag selects text.";

/// The help over the whole frame: every key with what it does (wrapped under its own
/// column), what the status line's words mean, the scene's description; scrolled by
/// `offset` lines when taller than the screen, never cut.
fn help(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, offset: u16) {
    use super::fit::wrap_words;
    let width = 84u16.min(area.width);
    let inner = width.saturating_sub(2).max(1) as usize;
    let bindings = help_lines_with(app.look.ascii, &extra_keys(app));
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
    if app.mouse {
        paragraph(MOUSE_HELP, theme.dim());
    }
    if !app.scene().description.is_empty() {
        paragraph(
            &format!("This scene: {}", printable(&app.scene().description)),
            theme.plain(),
        );
    }
    if let Some(place) = &app.exploration.lesson {
        let lesson = &place.lesson;
        let steps: Vec<String> = lesson
            .steps
            .iter()
            .enumerate()
            .map(|(i, step)| {
                let here = if i == place.step { " (here)" } else { "" };
                format!("{}. {}{here}", i + 1, printable(&step.title))
            })
            .collect();
        paragraph(
            &format!(
                "This lesson: {}{}{} Its steps: {}.",
                printable(&lesson.title),
                if lesson.description.is_empty() {
                    "."
                } else {
                    ": "
                },
                printable(&lesson.description),
                steps.join("; ")
            ),
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
            " {} PgUp PgDn: lines {}–{} of {total} ",
            up_down(app.look.ascii),
            offset + 1,
            (offset + visible).min(total)
        ));
    }
    frame.render_widget(Clear, rect);
    frame.render_widget(Paragraph::new(lines).scroll((offset, 0)).block(block), rect);
}

/// The scene's description on one line under the title (in full in the help).
pub(super) fn description_line(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let text = format!(" {}", printable(app.scene().description.trim()));
    frame.render_widget(
        Paragraph::new(super::fit::cut_at_word(&text, area.width as usize)).style(theme.dim()),
        area,
    );
}

/// The preset picker; under a limit on the mesh (`max_elements`, a served session) a preset
/// beyond it is marked with the reason, before its description.
fn presets(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    (picker, max_elements): (&PresetPicker, Option<usize>),
) {
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
            let beyond = match max_elements {
                Some(max) if info.elements > max => {
                    format!(
                        "[n = {} is over this server's {max}: not here] ",
                        info.elements
                    )
                }
                _ => String::new(),
            };
            let text = format!(
                "{mark}{:<name_width$}{beyond}{}",
                info.name,
                printable(&info.description)
            );
            let text = super::fit::cut_at_word(&text, width);
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
                ratatui::text::Span::styled(format!("{}: ", printable(&info.title)), theme.title()),
                ratatui::text::Span::raw(printable(&info.description).into_owned()),
            ]);
            frame.render_widget(
                Paragraph::new(detail).wrap(Wrap { trim: true }),
                layout.detail,
            );
        }
    }
}
