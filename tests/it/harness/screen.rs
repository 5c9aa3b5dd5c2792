//! Reading a screen as text and talking to it with the mouse, whichever way it was drawn (a
//! test backend's buffer, a `vt100` emulator fed a pty or an SSH channel), and spelling text
//! as the key names of `render --keys`.

/// The cell (column, row), 0-based, where `needle` starts, the first from the top.
pub fn find(rows: &[impl AsRef<str>], needle: &str) -> Option<(u16, u16)> {
    rows.iter().enumerate().find_map(|(y, row)| {
        let row = row.as_ref();
        let at = row.find(needle)?;
        Some((row[..at].chars().count() as u16, y as u16))
    })
}

/// The rows of a `vt100` screen as text.
pub fn rows(screen: &vt100::Screen) -> Vec<String> {
    let (_, width) = screen.size();
    screen.rows(0, width).collect()
}

/// An SGR mouse report of button code `code` at the 0-based cell (x, y): a press (or motion)
/// when `press`, else a release.
pub fn sgr(code: u8, (x, y): (u16, u16), press: bool) -> Vec<u8> {
    let end = if press { 'M' } else { 'm' };
    format!("\x1b[<{code};{};{}{end}", x + 1, y + 1).into_bytes()
}

/// The `render --keys` words that type `text`: one word per character, `Space` for a space
/// (a longer word would be taken for a key name).
pub fn typed(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c == ' ' {
                "Space".into()
            } else {
                c.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}
