//! The regularised method's cases (paper Table 1, systems (43)) as a table: for k ≤ 2 every
//! one of the 9^k cases — the ε-region each friction DOF is assumed in, whether the case's own
//! solution lies in those regions (consistent), cond₂ of its matrix Â — with the case the
//! method kept highlighted; for more obstacles how many cases there are, were tried and were
//! consistent. It also says over which cases the condition numbers of the ε chart are taken.

use ratatui::Frame;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::Theme;
use super::chart::{PanelFrame, Piece, fitted_title, pack};
use crate::format::sci;
use crate::study::{CaseRow, CaseStudy, CaseTable};

/// Cells of one row of the table: `  # regions consistent cond₂`.
fn row_text(row: &CaseRow, ascii: bool, picked: bool, obstacles: usize) -> String {
    let mut regions = String::new();
    for (i, region) in row.regions.iter().enumerate() {
        if i > 0 && i % 2 == 0 {
            regions.push(' ');
        }
        regions.push(if ascii {
            region.ascii()
        } else {
            region.symbol()
        });
    }
    let width = 3 * obstacles.max(1) - 1;
    let consistent = if row.consistent {
        "yes".to_string()
    } else {
        format!("no ({}ε)", sci(row.worst_violation, 1))
    };
    let condition = row.condition.map_or("–".to_string(), |c| sci(c, 2));
    let mark = match (picked, ascii) {
        (true, true) => ">",
        (true, false) => "▶",
        _ => " ",
    };
    format!(
        "{mark}{:>2} {regions:<width$} {consistent:<11} {condition}",
        row.index
    )
}

/// `text` as words wrapped to `width`, in `style`, spelled for the look.
fn wrapped(text: &str, style: Style, width: usize, theme: &Theme) -> Vec<Line<'static>> {
    let words: Vec<Piece> = theme
        .text(text)
        .split(' ')
        .filter(|w| !w.is_empty())
        .map(|w| (w.to_string(), style))
        .collect();
    pack(&words, width.max(1), 1, theme.look.ascii)
}

/// The summary lines above the table, wrapped to `width`.
fn summary(study: &CaseStudy, theme: &Theme, width: usize) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    match &study.table {
        CaseTable::All { rows, picked } => {
            let consistent = rows.iter().filter(|r| r.consistent).count();
            let picked = picked.map_or("none kept".to_string(), |p| format!("#{p} kept"));
            lines.extend(wrapped(
                &format!(
                    "{} cases at ε = {}: {consistent} consistent, {picked}",
                    rows.len(),
                    sci(study.epsilon, 1)
                ),
                theme.current(),
                width,
                theme,
            ));
            if rows.iter().all(|r| r.condition.is_none()) {
                lines.extend(wrapped(
                    &format!(
                        "cond₂(Â) of a case is computed for at most {} unknowns",
                        crate::linalg::condition::DENSE_LIMIT
                    ),
                    theme.dim(),
                    width,
                    theme,
                ));
            }
        }
        CaseTable::Counted {
            cases,
            tried,
            consistent,
            refused,
        } => {
            let total = if *cases == u64::MAX {
                "more than 1.8e19".to_string()
            } else {
                cases.to_string()
            };
            let text = if *refused {
                format!("{total} cases: over the enumeration's limit, none tried")
            } else {
                format!("{total} cases: {tried} tried, {consistent} consistent")
            };
            lines.extend(wrapped(&text, theme.current(), width, theme));
            lines.extend(wrapped(
                "the table of every case is drawn for at most 2 obstacles (81 cases)",
                theme.dim(),
                width,
                theme,
            ));
        }
    }
    lines.extend(wrapped(
        &study.conditioned.description,
        theme.dim(),
        width,
        theme,
    ));
    lines
}

/// The table of cases in `panel`: summary, legend, then as many rows as fit (in columns when
/// the panel is wide), the window of rows holding the kept case.
pub fn cases_table(frame: &mut Frame, theme: &Theme, panel: PanelFrame, study: &CaseStudy) {
    let ascii = theme.look.ascii;
    let title = fitted_title(&theme.text(&panel.title), panel.area.width, ascii);
    let block = theme.block(title, panel.focused);
    let inner = block.inner(panel.area);
    frame.render_widget(block, panel.area);
    let mut lines = summary(study, theme, usize::from(inner.width));
    let CaseTable::All { rows, picked } = &study.table else {
        frame.render_widget(Paragraph::new(lines), inner);
        return;
    };
    let minus = if ascii { '-' } else { '−' };
    lines.extend(wrapped(
        &format!("{minus}: c < −ε, 0: |c| ≤ ε, +: c > ε (u then u' per obstacle)"),
        theme.dim(),
        usize::from(inner.width),
        theme,
    ));
    let obstacles = rows.first().map_or(1, |r| r.regions.len() / 2);
    let header = format!(
        " {:>2} {:<width$} {:<11} cond₂(Â)",
        "#",
        "case",
        "consistent",
        width = 3 * obstacles.max(1) - 1
    );
    let cell_width = header.chars().count() + 2;
    let columns = (usize::from(inner.width) / cell_width).clamp(1, 4);
    let used = lines.len() as u16 + 1;
    let height = usize::from(inner.height.saturating_sub(used + 1));
    let capacity = (height * columns).max(1);
    let picked_at = picked
        .and_then(|p| rows.iter().position(|r| r.index == p))
        .unwrap_or(0);
    let start = if rows.len() <= capacity {
        0
    } else {
        picked_at
            .saturating_sub(capacity / 2)
            .min(rows.len() - capacity)
    };
    let shown = &rows[start..rows.len().min(start + capacity)];
    let mut header_line = String::new();
    for column in 0..columns.min(shown.len().div_ceil(height.max(1)).max(1)) {
        if column > 0 {
            header_line.push_str("  ");
        }
        header_line.push_str(&format!("{header:<w$}", w = cell_width - 2));
    }
    lines.push(Line::from(Span::styled(
        theme.text(&header_line).into_owned(),
        theme.dim().add_modifier(Modifier::BOLD),
    )));
    let body_rows = height.max(1).min(shown.len());
    for line in 0..body_rows {
        let mut spans = Vec::new();
        for column in 0..columns {
            let Some(row) = shown.get(column * body_rows + line) else {
                continue;
            };
            if column > 0 {
                spans.push(Span::raw("  "));
            }
            let is_picked = Some(row.index) == *picked;
            let style = if is_picked {
                theme.current().add_modifier(Modifier::REVERSED)
            } else if row.consistent {
                theme.series(0)
            } else {
                Style::default()
            };
            let text = row_text(row, ascii, is_picked, obstacles);
            spans.push(Span::styled(
                format!("{:<w$}", theme.text(&text), w = cell_width - 2),
                style,
            ));
        }
        lines.push(Line::from(spans));
    }
    if shown.len() < rows.len() {
        lines.push(Line::from(Span::styled(
            format!(
                "rows {}–{} of {} shown (the kept case among them)",
                start + 1,
                start + shown.len(),
                rows.len()
            ),
            theme.dim(),
        )));
    }
    frame.render_widget(Paragraph::new(spelled(lines, theme)), inner);
}

/// The lines with every text spelled for the look (ASCII where it has no Unicode).
fn spelled(lines: Vec<Line<'static>>, theme: &Theme) -> Vec<Line<'static>> {
    lines
        .into_iter()
        .map(|line| {
            let spans: Vec<Span<'static>> = line
                .spans
                .into_iter()
                .map(|span| Span::styled(theme.text(&span.content).into_owned(), span.style))
                .collect();
            Line::from(spans)
        })
        .collect()
}
