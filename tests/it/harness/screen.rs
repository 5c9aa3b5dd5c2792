//! Reading a screen as text and talking to it with the mouse, whichever way it was drawn (a
//! test backend's buffer, a `vt100` emulator fed a pty or an SSH channel).

/// The cell (column, row), 0-based, where `needle` starts, the first from the top.
pub fn find(rows: &[impl AsRef<str>], needle: &str) -> Option<(u16, u16)> {
    rows.iter().enumerate().find_map(|(y, row)| {
        let row = row.as_ref();
        let at = row.find(needle)?;
        Some((row[..at].chars().count() as u16, y as u16))
    })
}
