//! A lesson's caption strip, under the title: the lesson, the step (`step 2/6`) and its title
//! on the first line, the step's caption wrapped under it (the lesson's rules keep it within
//! three lines at 80 columns, so at 80×24 it is never cut). A following student reads, in
//! place of the lesson's title, that the keys a caption names work once they fork.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::format::printable;
use crate::lesson::{columns, prefix_in_columns, wrap};
use crate::plot::Theme;
use crate::tui::layout::caption_width;
use crate::tui::state::App;

pub(super) fn draw_caption_strip(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let Some(place) = &app.exploration.lesson else {
        return;
    };
    let step = place.current();
    let count = place.lesson.steps.len();
    let separator = if app.look.ascii { "|" } else { "·" };
    let step_line = format!(
        " step {}/{count}: {} ",
        place.step + 1,
        printable(&step.title)
    );
    // A follower's keys only watch: the keys a caption names work once they fork (stop 59's
    // lecture pass), said where the lesson's title would be.
    let following = app.follow.as_ref().is_some_and(|f| f.is_following());
    let lesson_line = if following {
        format!(" {separator} f: try the keys yourself")
    } else {
        format!(" {separator} {}", printable(&place.lesson.title))
    };
    // The lesson's title only where it fits whole: the step's comes first.
    let fits = columns(&step_line) + columns(&lesson_line) <= usize::from(area.width);
    let mut first = vec![Span::styled(step_line, theme.selected())];
    if fits {
        first.push(Span::styled(lesson_line, theme.dim()));
    }
    let mut lines = vec![Line::from(first)];
    let mut caption = wrap(&step.caption, caption_width(area));
    let room = usize::from(area.height.saturating_sub(1));
    if caption.len() > room && room > 0 {
        caption.truncate(room);
        if let Some(last) = caption.last_mut() {
            // More follows: the last line shown always ends in `…`.
            let keep = caption_width(area).saturating_sub(1);
            *last = format!("{}…", prefix_in_columns(last, keep));
        }
    }
    lines.extend(
        caption
            .iter()
            .map(|l| Line::styled(format!(" {}", printable(l)), theme.plain())),
    );
    frame.render_widget(Paragraph::new(lines), area);
}
