//! A drawn buffer as text: what `beamfric render` prints, the charts in reports, and snapshots.

use ratatui::buffer::Buffer;
use ratatui::style::{Color, Modifier};

/// The buffer as text: one line per row, each exactly as wide as the buffer; with `color`,
/// ANSI escapes for the styles.
pub fn buffer_to_text(buffer: &Buffer, color: bool) -> String {
    let area = buffer.area;
    let mut out = String::with_capacity((area.width as usize + 8) * area.height as usize);
    for y in 0..area.height {
        let mut current: Option<(Color, Color, Modifier)> = None;
        for x in 0..area.width {
            let cell = &buffer[(x, y)];
            if color {
                let style = (cell.fg, cell.bg, cell.modifier);
                if current != Some(style) {
                    out.push_str(&sgr(style));
                    current = Some(style);
                }
            }
            out.push_str(cell.symbol());
        }
        if color {
            out.push_str("\x1b[0m");
        }
        out.push('\n');
    }
    out
}

fn sgr((fg, bg, modifier): (Color, Color, Modifier)) -> String {
    let mut codes = vec!["0".to_string()];
    if modifier.contains(Modifier::BOLD) {
        codes.push("1".into());
    }
    if modifier.contains(Modifier::REVERSED) {
        codes.push("7".into());
    }
    let color_code = |c: Color, base: u8| -> Option<String> {
        let (index, bright) = match c {
            Color::Black => (0, false),
            Color::Red => (1, false),
            Color::Green => (2, false),
            Color::Yellow => (3, false),
            Color::Blue => (4, false),
            Color::Magenta => (5, false),
            Color::Cyan => (6, false),
            Color::Gray => (7, false),
            Color::DarkGray => (0, true),
            Color::LightRed => (1, true),
            Color::LightGreen => (2, true),
            Color::LightYellow => (3, true),
            Color::LightBlue => (4, true),
            Color::LightMagenta => (5, true),
            Color::LightCyan => (6, true),
            Color::White => (7, true),
            Color::Indexed(n) => return Some(format!("{};5;{n}", base + 8)),
            _ => return None,
        };
        Some(format!("{}", base + index + if bright { 60 } else { 0 }))
    };
    codes.extend(color_code(fg, 30));
    codes.extend(color_code(bg, 40));
    format!("\x1b[{}m", codes.join(";"))
}
