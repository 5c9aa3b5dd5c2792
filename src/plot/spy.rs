//! What the matrices look like: a character "spy" plot of each matrix's nonzero pattern —
//! the stiffness matrix A (banded), the dual's S = B A⁻¹ Bᵀ of (49) (dense 2k × 2k) and the
//! condensed method's system — with its size, nonzeros, bandwidth and cond₂, side by side.
//! A block of the matrix is drawn filled when any entry in it is nonzero (half-block
//! characters give two blocks per cell in Unicode).

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use super::Theme;
use super::chart::{PanelFrame, fitted_title};
use crate::format::sci;
use crate::study::{MatrixStructure, SpyGrid};

/// Is any entry of the grid's blocks under the pixel (`column`, `row`) of a `width` × `height`
/// picture nonzero?
fn filled(grid: &SpyGrid, column: usize, row: usize, width: usize, height: usize) -> bool {
    if grid.width == 0 || grid.height == 0 {
        return false;
    }
    let span = |index: usize, pixels: usize, cells: usize| {
        let from = index * cells / pixels;
        let to = ((index + 1) * cells)
            .div_ceil(pixels)
            .max(from + 1)
            .min(cells);
        from..to
    };
    span(row, height, grid.height)
        .any(|r| span(column, width, grid.width).any(|c| grid.cells[r * grid.width + c] != 0.0))
}

/// The picture of `grid` in `columns` × `rows` cells, square in pixels as far as the cells
/// allow (a cell is about twice as tall as wide).
fn picture(grid: &SpyGrid, columns: u16, rows: u16, ascii: bool) -> Vec<String> {
    let side = usize::from(columns).min(2 * usize::from(rows)).max(1);
    let (width, cell_rows) = (side, side.div_ceil(2));
    let pixel_rows = if ascii { cell_rows } else { 2 * cell_rows };
    (0..cell_rows)
        .map(|line| {
            (0..width)
                .map(|column| {
                    if ascii {
                        if filled(grid, column, line, width, pixel_rows) {
                            '#'
                        } else {
                            '.'
                        }
                    } else {
                        let top = filled(grid, column, 2 * line, width, pixel_rows);
                        let bottom = filled(grid, column, 2 * line + 1, width, pixel_rows);
                        match (top, bottom) {
                            (true, true) => '█',
                            (true, false) => '▀',
                            (false, true) => '▄',
                            (false, false) => '·',
                        }
                    }
                })
                .collect()
        })
        .collect()
}

/// One matrix: its name and numbers, then its picture.
fn matrix_lines(matrix: &MatrixStructure, area: Rect, theme: &Theme) -> Vec<Line<'static>> {
    let ascii = theme.look.ascii;
    let count = |n: usize| {
        if n < 1_000_000 {
            n.to_string()
        } else {
            sci(n as f64, 2)
        }
    };
    let band = matrix
        .bandwidth
        .map_or(String::new(), |b| format!(" band {b}"));
    let mut lines = vec![
        Line::from(Span::styled(
            theme.text(matrix.name).into_owned(),
            theme.current(),
        )),
        Line::from(Span::styled(
            if matrix.rows == matrix.cols {
                format!("{}²{band}", count(matrix.rows))
            } else {
                format!("{}×{}{band}", count(matrix.rows), count(matrix.cols))
            },
            theme.plain(),
        )),
        Line::from(Span::styled(
            format!("nnz {}", count(matrix.nonzeros)),
            theme.dim(),
        )),
        Line::from(Span::styled(
            format!(
                "cond₂ {}",
                matrix.condition.map_or("n/a".to_string(), |c| sci(c, 1))
            ),
            theme.dim(),
        )),
    ];
    let rows = area.height.saturating_sub(lines.len() as u16);
    if matrix.grid.cells.is_empty() {
        lines.push(Line::from(Span::styled(
            theme.text(&matrix.note).into_owned(),
            theme.dim(),
        )));
        return lines;
    }
    for text in picture(&matrix.grid, area.width, rows, ascii) {
        lines.push(Line::from(Span::styled(text, theme.series(0))));
    }
    lines
}

/// The matrices side by side in `panel`, each with its numbers above its picture, and one
/// line under them saying what each is.
pub fn spy_panel(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    matrices: &[MatrixStructure],
) {
    let title = fitted_title(
        &theme.text(&panel.title),
        panel.area.width,
        theme.look.ascii,
    );
    let block = theme.block(title, panel.focused);
    let inner = block.inner(panel.area);
    frame.render_widget(block, panel.area);
    if matrices.is_empty() {
        return;
    }
    let notes: Vec<Line> = matrices
        .iter()
        .map(|m| Line::from(Span::styled(theme.text(&m.note).into_owned(), theme.dim())))
        .collect();
    // The pictures take what they need (square, three lines of numbers above); the notes
    // under them, wrapped, the rest.
    let cell_width = inner.width.saturating_sub(matrices.len() as u16 - 1) / matrices.len() as u16;
    let picture_rows = 4 + cell_width.div_ceil(2);
    let [pictures, legend] = Layout::vertical([
        Constraint::Length(picture_rows.min(inner.height)),
        Constraint::Min(0),
    ])
    .areas(inner);
    let constraints = vec![Constraint::Ratio(1, matrices.len() as u32); matrices.len()];
    let cells = Layout::horizontal(constraints).spacing(1).split(pictures);
    for (matrix, cell) in matrices.iter().zip(cells.iter()) {
        frame.render_widget(Paragraph::new(matrix_lines(matrix, *cell, theme)), *cell);
    }
    frame.render_widget(Paragraph::new(notes).wrap(Wrap { trim: true }), legend);
}
