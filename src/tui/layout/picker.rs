//! Where the preset picker's parts are on a screen: its box centred, the search line, the list
//! (scrolling when the screen is short) and the highlighted preset's description. Drawing and
//! mouse hit-testing both use it.

use ratatui::layout::{Constraint, Flex, Layout, Rect};

use crate::scene::PRESETS;

/// A box of `width` × `height` (at most the area's) in the middle of `area`.
pub fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let [row] = Layout::vertical([Constraint::Length(height.min(area.height))])
        .flex(Flex::Center)
        .areas(area);
    let [cell] = Layout::horizontal([Constraint::Length(width.min(area.width))])
        .flex(Flex::Center)
        .areas(row);
    cell
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

/// How many entries the preset picker's list shows on the app's screen now (at least one).
pub fn picker_rows_shown(app: &crate::tui::state::App) -> usize {
    usize::from(picker_layout(super::screen::screen(app)).list.height).max(1)
}
