//! The presenter's list of students (`S`): each session's user, whether it follows or explores
//! on its own, how long since its last key, and whether it holds unsaved work; the keys to
//! bring everyone back and to write to all are on the hint line. Idle times are as of this
//! frame (it is redrawn every second while the list is open).

use std::time::{Duration, Instant};

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph};

use crate::format::printable;
use crate::lesson::{columns, fit_columns};
use crate::plot::Theme;
use crate::tui::state::App;
use crate::tui::state::follow::StudentView;

/// Longest user name shown (longer ones end in `…`).
const USER_WIDTH: usize = 16;

pub(super) fn draw_students(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, offset: u16) {
    let Some(follow) = &app.follow else {
        return;
    };
    // The status and hint lines stay visible under the list.
    let area = Rect {
        height: area.height.saturating_sub(4),
        ..area
    };
    let roster = follow.followers.roster(Instant::now());
    let following = roster.iter().filter(|s| s.following).count();
    let unsaved = roster.iter().filter(|s| s.unsaved).count();
    let block = theme.block(
        format!(
            " Students: {} connected · {following} following · {unsaved} with unsaved work ",
            roster.len()
        ),
        true,
    );
    let inner = block.inner(area);
    let rows = usize::from(inner.height);
    let mut lines: Vec<Line> = Vec::new();
    if roster.is_empty() {
        lines.push(Line::styled("no student is connected", theme.dim()));
    }
    // Scrolled (↑ ↓, PgUp PgDn), never past the last screenful.
    let first = usize::from(offset).min(roster.len().saturating_sub(rows.max(1)));
    let below = roster.len().saturating_sub(first + rows);
    let shown = if below > 0 {
        rows.saturating_sub(1)
    } else {
        rows
    };
    for student in roster.iter().skip(first).take(shown) {
        lines.push(Line::styled(row(student), row_style(theme, student)));
    }
    let more = roster.len().saturating_sub(first + shown);
    if more > 0 {
        lines.push(Line::styled(
            format!("… and {more} more (↓ scrolls)"),
            theme.dim(),
        ));
    }
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

fn row_style(theme: &Theme, student: &StudentView) -> ratatui::style::Style {
    if student.unsaved {
        theme.warning()
    } else {
        theme.plain()
    }
}

/// `alice            following        idle 3 s    unsaved`.
fn row(student: &StudentView) -> String {
    let user = printable(&student.user);
    // Cut and padded in terminal columns (a CJK name takes two a character).
    let name = fit_columns(&user, USER_WIDTH);
    let pad = " ".repeat(USER_WIDTH.saturating_sub(columns(&name)));
    format!(
        "{name}{pad}  {:<15}  idle {:<7}  {}",
        if student.following {
            "following"
        } else {
            "own exploration"
        },
        idle(student.idle),
        if student.unsaved { "unsaved" } else { "" }
    )
}

/// An idle time in the largest whole unit: `12 s`, `4 min`, `2 h`.
fn idle(duration: Duration) -> String {
    let seconds = duration.as_secs();
    if seconds < 60 {
        format!("{seconds} s")
    } else if seconds < 3600 {
        format!("{} min", seconds / 60)
    } else {
        format!("{} h", seconds / 3600)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_says_who_what_how_long_and_unsaved_and_cuts_long_names() {
        let student = StudentView {
            user: "a-very-long-user-name-indeed".into(),
            following: false,
            unsaved: true,
            idle: Duration::from_secs(125),
        };
        let text = row(&student);
        assert!(text.starts_with("a-very-long-use… "), "{text}");
        assert!(text.contains("own exploration  idle 2 min"), "{text}");
        assert!(text.trim_end().ends_with("unsaved"), "{text}");
        assert_eq!(idle(Duration::from_secs(59)), "59 s");
        assert_eq!(idle(Duration::from_secs(7300)), "2 h");
    }
}
