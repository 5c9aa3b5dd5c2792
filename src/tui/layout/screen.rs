//! Where everything goes on the screen: one pure function of the state and the terminal size,
//! used by drawing and by mouse hit-testing alike, so a click lands on what is drawn there.
//!
//! Title line on top, the scene's description under it when there is room (from
//! [`DESCRIPTION_MIN_HEIGHT`] rows); parameters on the left with the results under them when there is room;
//! the scene's panels on the right (from [`FULL_SIZE`] on all of them, the deflection on top
//! and the others side by side below; under it one at a time, Tab cycling; a zoomed panel
//! takes the whole body); then the status (solution summary, warnings, last message) and the
//! key hints. Below [`MIN_SIZE`] nothing but a "terminal too small" notice.

use ratatui::layout::{Constraint, Layout, Rect};

use super::super::state::App;
use crate::scene::Panel;

/// Smallest terminal the explorer draws into.
pub const MIN_SIZE: (u16, u16) = (60, 16);
/// Smallest terminal for every panel at once.
pub const FULL_SIZE: (u16, u16) = (100, 30);
/// Fewest rows with the scene's description under the title.
pub const DESCRIPTION_MIN_HEIGHT: u16 = 30;

/// The rectangles of one frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScreenLayout {
    pub title: Rect,
    /// The scene's description, one line, when it has one and there is room (not with a
    /// lesson: its caption strip says more).
    pub description: Option<Rect>,
    /// A lesson's strip: the step line, then the caption (see [`caption_strip_height`]).
    pub caption: Option<Rect>,
    /// The parameters box (borders included).
    pub parameters: Rect,
    /// The results box, when there is room for it.
    pub results: Option<Rect>,
    /// The panels drawn, each with its box, in drawing order.
    pub panels: Vec<(Panel, Rect)>,
    /// Is every panel of the scene on screen (otherwise the focused one alone)?
    pub all_panels: bool,
    /// Status: the summary line, then the warnings, then the last message.
    pub status: Rect,
    pub hints: Rect,
}

/// Is the terminal big enough to draw into?
pub fn fits(area: Rect) -> bool {
    area.width >= MIN_SIZE.0 && area.height >= MIN_SIZE.1
}

/// The layout of a frame of `area` for `app`, or `None` when the terminal is too small.
pub fn screen_layout(app: &App, area: Rect) -> Option<ScreenLayout> {
    if !fits(area) {
        return None;
    }
    let strip = caption_strip_height(app, area);
    let described = strip == 0
        && area.height >= DESCRIPTION_MIN_HEIGHT
        && !app.scene().description.trim().is_empty();
    let [title, description, caption, body, status, hints] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Length(u16::from(described)),
        Constraint::Length(strip),
        Constraint::Min(8),
        Constraint::Length(3),
        Constraint::Length(1),
    ])
    .areas(area);
    let description = described.then_some(description);
    let caption = (strip > 0).then_some(caption);
    let full = area.width >= FULL_SIZE.0 && area.height >= FULL_SIZE.1;
    let panels = app.exploration.panels();
    let focused = (!panels.is_empty()).then(|| panels[app.exploration.focus % panels.len()]);
    if let (true, Some(panel)) = (app.zoom, focused) {
        return Some(ScreenLayout {
            title,
            description,
            caption,
            parameters: Rect::new(body.x, body.y, 0, 0),
            results: None,
            panels: vec![(panel, body)],
            all_panels: false,
            status,
            hints,
        });
    }
    let parameters_width = if full { 38 } else { 30 };
    let [left, right] =
        Layout::horizontal([Constraint::Length(parameters_width), Constraint::Min(20)]).areas(body);
    let (parameters, results) = split_left(app, left);
    let panels = if full {
        full_panels(&panels, right)
    } else {
        focused.map(|p| vec![(p, right)]).unwrap_or_default()
    };
    Some(ScreenLayout {
        title,
        description,
        caption,
        parameters,
        results,
        panels,
        all_panels: full,
        status,
        hints,
    })
}

/// Rows of a lesson's caption strip in a frame of `area` (0 without a lesson): the step line
/// and the caption wrapped to the width less a column each side, as many lines as it needs
/// (a lesson's captions fit 3 at 80 columns) while the body keeps its rows; a caption cut
/// short of that ends in `…`.
pub fn caption_strip_height(app: &App, area: Rect) -> u16 {
    let Some(place) = &app.exploration.lesson else {
        return 0;
    };
    let needed = crate::lesson::wrap(&place.current().caption, caption_width(area)).len();
    // Title, body (8), status (3) and hints keep theirs; the step line is always there.
    let room = usize::from(area.height.saturating_sub(1 + 8 + 3 + 1 + 1));
    1 + needed.min(room.max(1)) as u16
}

/// The caption's text width in a frame of `area`.
pub fn caption_width(area: Rect) -> usize {
    usize::from(area.width.saturating_sub(2)).max(1)
}

/// Parameters on top, results below: the parameters get their rows when the results still
/// have room, else the results get theirs up to half the column (the answer before the
/// paging: the parameters scroll to the selection anyway); a column too short for both has
/// the parameters alone.
fn split_left(app: &App, left: Rect) -> (Rect, Option<Rect>) {
    const RESULTS_MIN: u16 = 5;
    const PARAMETERS_MIN: u16 = 7;
    if left.height < RESULTS_MIN + PARAMETERS_MIN {
        return (left, None);
    }
    let parameters_wanted = app.exploration.rows().len() as u16 + 2;
    // The results want borders, a header, max |u| and a line per obstacle.
    let results_wanted = (app.scene().obstacles.len() as u16).saturating_add(5);
    let parameters = if parameters_wanted.saturating_add(RESULTS_MIN) <= left.height {
        // The parameters fit: the results take the rest (scrolling when they need more).
        parameters_wanted
    } else {
        // The results get up to half the column, the parameters at least their minimum.
        let results = results_wanted
            .min(left.height / 2)
            .max(RESULTS_MIN)
            .min(left.height - PARAMETERS_MIN);
        left.height - results
    };
    let [top, bottom] =
        Layout::vertical([Constraint::Length(parameters), Constraint::Min(RESULTS_MIN)])
            .areas(left);
    (top, Some(bottom))
}

/// Every panel: the deflection on top, the others side by side below it.
fn full_panels(panels: &[Panel], area: Rect) -> Vec<(Panel, Rect)> {
    let has_deflection = panels.contains(&Panel::Deflection);
    let others: Vec<Panel> = panels
        .iter()
        .copied()
        .filter(|p| *p != Panel::Deflection)
        .collect();
    let (top, bottom) = match (has_deflection, others.is_empty()) {
        (true, true) => (Some(area), None),
        (true, false) => {
            let [t, b] = Layout::vertical([Constraint::Percentage(55), Constraint::Percentage(45)])
                .areas(area);
            (Some(t), Some(b))
        }
        (false, _) => (None, Some(area)),
    };
    let mut out = Vec::new();
    if let Some(top) = top {
        out.push((Panel::Deflection, top));
    }
    if let Some(bottom) = bottom.filter(|_| !others.is_empty()) {
        let constraints = vec![Constraint::Ratio(1, others.len() as u32); others.len()];
        let cells = Layout::horizontal(constraints).split(bottom);
        out.extend(others.iter().copied().zip(cells.iter().copied()));
    }
    out
}

/// The screen position of a cell: which part of the layout is at column `x`, row `y`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    Title,
    Parameters,
    Results,
    Panel(Panel),
    Status,
    Hints,
}

impl ScreenLayout {
    /// What is drawn at column `x`, row `y`.
    pub fn region_at(&self, x: u16, y: u16) -> Option<Region> {
        let position = ratatui::layout::Position { x, y };
        let inside = |r: Rect| r.contains(position);
        if inside(self.title)
            || self.description.is_some_and(inside)
            || self.caption.is_some_and(inside)
        {
            Some(Region::Title)
        } else if inside(self.parameters) {
            Some(Region::Parameters)
        } else if self.results.is_some_and(inside) {
            Some(Region::Results)
        } else if let Some((panel, _)) = self.panels.iter().find(|(_, r)| inside(*r)) {
            Some(Region::Panel(*panel))
        } else if inside(self.status) {
            Some(Region::Status)
        } else if inside(self.hints) {
            Some(Region::Hints)
        } else {
            None
        }
    }
}

/// The whole screen of the app's last known size.
pub fn screen(app: &App) -> Rect {
    Rect::new(0, 0, app.size.0, app.size.1)
}

/// The panels on screen, as [`screen_layout`] places them: none when the terminal is too
/// small.
pub fn visible_panels(app: &App) -> Vec<Panel> {
    screen_layout(app, screen(app))
        .map(|layout| layout.panels.into_iter().map(|(panel, _)| panel).collect())
        .unwrap_or_default()
}

/// How many parameter rows the frame shows now (at least one).
pub fn parameter_rows_shown(app: &App) -> usize {
    screen_layout(app, screen(app))
        .map_or(1, |layout| {
            usize::from(layout.parameters.height.saturating_sub(2))
        })
        .max(1)
}
