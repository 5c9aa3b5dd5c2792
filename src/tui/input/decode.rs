//! Terminal input as bytes: the explorer reads its terminal (or an SSH channel) itself and
//! decodes the bytes with `terminput`'s parser (crossterm's escape-sequence parser, public).
//! Reading ourselves is what makes a closed terminal end the program (end of file or an error
//! is a hangup for the runtime, not a busy loop) and what makes a burst of pasted keys arrive
//! whole (every byte read is decoded at once, so no key waits in a buffer for new input).
//!
//! A lone ESC at the end of what has arrived may be the start of a sequence split across two
//! reads; the decoder keeps it pending and the caller flushes it after [`ESC_TIMEOUT`] without
//! more bytes. Garbage is dropped, and a sequence that never ends is cut at [`SEQUENCE_LIMIT`]
//! bytes: input from a network is hostile.

use std::time::Duration;

use terminput::{Event, KeyCode, KeyEventKind, KeyModifiers};

use super::keys::Key;

/// How long a lone ESC waits for the rest of a sequence.
pub const ESC_TIMEOUT: Duration = Duration::from_millis(30);
/// Longest escape sequence kept while incomplete.
pub const SEQUENCE_LIMIT: usize = 64;
/// Longest bracketed paste kept (a paste is typed into a prompt, which takes far less).
pub const PASTE_LIMIT: usize = 64 * 1024;
/// How a bracketed paste starts.
const PASTE_START: &[u8] = b"\x1b[200~";

/// What the terminal said.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    Key(Key),
    /// A mouse event: (column, row, what).
    Mouse(u16, u16, MouseInput),
    /// A bracketed paste: text the terminal marked as pasted, not typed.
    Paste(String),
}

/// The mouse events the explorer uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MouseInput {
    Press,
    Drag,
    Release,
    ScrollUp,
    ScrollDown,
}

/// Bytes in, inputs out.
#[derive(Debug, Default)]
pub struct Decoder {
    pending: Vec<u8>,
}

impl Decoder {
    /// Decodes `bytes` (appended to what was pending). A lone ESC at the end stays pending.
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<Input> {
        let mut inputs = Vec::new();
        self.feed_into(bytes, &mut inputs);
        inputs
    }

    fn feed_into(&mut self, bytes: &[u8], inputs: &mut Vec<Input>) {
        let mut queue: std::collections::VecDeque<u8> = bytes.iter().copied().collect();
        while let Some(byte) = queue.pop_front() {
            self.pending.push(byte);
            if self.pending == [0x1b] {
                // The start of a sequence, or the Esc key: the next byte tells (or, at the end
                // of what arrived, the timeout: see `flush`).
                continue;
            }
            // Bytes after a dropped one are decoded again (at most SEQUENCE_LIMIT of them).
            for byte in self.decode_pending(inputs, false).into_iter().rev() {
                queue.push_front(byte);
            }
        }
    }

    /// Is a lone ESC (or an incomplete sequence) waiting?
    pub fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// After [`ESC_TIMEOUT`] without more bytes: what is pending is taken as typed (a lone
    /// ESC is the Esc key).
    pub fn flush(&mut self) -> Vec<Input> {
        let mut inputs = Vec::new();
        let rest = self.decode_pending(&mut inputs, true);
        self.pending.clear();
        if !rest.is_empty() {
            self.feed_into(&rest, &mut inputs);
            inputs.extend(self.flush());
        }
        inputs
    }

    /// How long the pending bytes may grow before they are dropped as never-ending.
    fn limit(&self) -> usize {
        if self.pending.starts_with(PASTE_START) {
            PASTE_LIMIT
        } else {
            SEQUENCE_LIMIT
        }
    }

    /// Decodes what is pending; returns the bytes to decode again after a dropped one.
    fn decode_pending(&mut self, inputs: &mut Vec<Input>, flushing: bool) -> Vec<u8> {
        match Event::parse_from(&self.pending) {
            Ok(Some(event)) => {
                inputs.extend(translate(event));
                self.pending.clear();
                Vec::new()
            }
            Ok(None) if !flushing && self.pending.len() < self.limit() => Vec::new(),
            // A sequence that never ends: dropped.
            Ok(None) => {
                self.pending.clear();
                Vec::new()
            }
            // Garbage: only its first byte is dropped, and what follows is decoded again, so a
            // stray byte (an 8-bit Alt, half a UTF-8 character) cannot turn the escape
            // sequence after it into keystrokes.
            Err(_) => {
                let rest = self.pending.split_off(1);
                self.pending.clear();
                rest
            }
        }
    }
}

/// The explorer's input for a parsed event, if it uses it.
fn translate(event: Event) -> Option<Input> {
    match event {
        Event::Key(key) => {
            if key.kind == KeyEventKind::Release {
                return None;
            }
            let shift = key.modifiers.contains(KeyModifiers::SHIFT);
            let ctrl = key.modifiers.contains(KeyModifiers::CTRL);
            let key = match key.code {
                KeyCode::Char(c) if ctrl => Key::Ctrl(c.to_ascii_lowercase()),
                KeyCode::Up => Key::Up,
                KeyCode::Down => Key::Down,
                KeyCode::Left if shift => Key::ShiftLeft,
                KeyCode::Right if shift => Key::ShiftRight,
                KeyCode::Left => Key::Left,
                KeyCode::Right => Key::Right,
                KeyCode::Enter => Key::Enter,
                KeyCode::Esc => Key::Esc,
                KeyCode::Backspace => Key::Backspace,
                KeyCode::Home => Key::Home,
                KeyCode::End => Key::End,
                KeyCode::PageUp => Key::PageUp,
                KeyCode::PageDown => Key::PageDown,
                KeyCode::Tab if shift => Key::BackTab,
                KeyCode::Tab => Key::Tab,
                KeyCode::Char(c) => Key::Char(c),
                _ => return None,
            };
            Some(Input::Key(key))
        }
        Event::Mouse(mouse) => {
            use terminput::{MouseEventKind, ScrollDirection};
            let what = match mouse.kind {
                MouseEventKind::Down(_) => MouseInput::Press,
                MouseEventKind::Drag(_) => MouseInput::Drag,
                MouseEventKind::Up(_) => MouseInput::Release,
                MouseEventKind::Scroll(ScrollDirection::Up) => MouseInput::ScrollUp,
                MouseEventKind::Scroll(ScrollDirection::Down) => MouseInput::ScrollDown,
                _ => return None,
            };
            Some(Input::Mouse(mouse.column, mouse.row, what))
        }
        Event::Paste(text) => Some(Input::Paste(text)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(inputs: &[Input]) -> Vec<Key> {
        inputs
            .iter()
            .filter_map(|i| match i {
                Input::Key(k) => Some(*k),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn keys_and_sequences() {
        let mut d = Decoder::default();
        let got = d.feed(
            b"jk\x1b[A\x1b[1;2C\r\x7f\x03\x04q\xc3\xa9\t\x1b[Z\x1b[H\x1b[F\x1b[1~\x1b[4~\x1b[5~\x1b[6~",
        );
        assert_eq!(
            keys(&got),
            vec![
                Key::Char('j'),
                Key::Char('k'),
                Key::Up,
                Key::ShiftRight,
                Key::Enter,
                Key::Backspace,
                Key::Ctrl('c'),
                Key::Ctrl('d'),
                Key::Char('q'),
                Key::Char('é'),
                Key::Tab,
                Key::BackTab,
                Key::Home,
                Key::End,
                Key::Home,
                Key::End,
                Key::PageUp,
                Key::PageDown,
            ]
        );
        assert!(!d.has_pending());
    }

    #[test]
    fn a_sequence_split_across_reads_is_one_key_and_a_lone_esc_waits() {
        let mut d = Decoder::default();
        assert!(d.feed(b"\x1b").is_empty());
        assert!(d.has_pending());
        assert_eq!(keys(&d.feed(b"[B")), vec![Key::Down]);
        assert!(d.feed(b"\x1b").is_empty());
        assert_eq!(keys(&d.flush()), vec![Key::Esc]);
        assert!(!d.has_pending());
        // Half a UTF-8 character, then the rest.
        assert!(d.feed(&[0xc3]).is_empty());
        assert_eq!(keys(&d.feed(&[0xa9])), vec![Key::Char('é')]);
    }

    #[test]
    fn a_burst_is_decoded_whole() {
        let mut d = Decoder::default();
        let mut bytes = b"jk".repeat(5000);
        bytes.push(b'q');
        let got = keys(&d.feed(&bytes));
        assert_eq!(got.len(), 10_001);
        assert_eq!(got.last(), Some(&Key::Char('q')));
    }

    #[test]
    fn garbage_and_endless_sequences_are_dropped() {
        let mut d = Decoder::default();
        let mut bytes = b"\x1b[".to_vec();
        bytes.extend(std::iter::repeat_n(b'1', 10_000));
        bytes.push(b'q');
        let got = keys(&d.feed(&bytes));
        assert_eq!(
            got.last(),
            Some(&Key::Char('q')),
            "input goes on after garbage"
        );
        // Random bytes never panic.
        let mut state = 12345u64;
        let random: Vec<u8> = (0..100_000)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                (state >> 56) as u8
            })
            .collect();
        let _ = d.feed(&random);
        let _ = d.flush();
        // A long run of stray bytes is dropped one by one, without recursion.
        let mut stray = vec![0xc3u8; 200_000];
        stray.push(b'j');
        assert_eq!(keys(&d.feed(&stray)), vec![Key::Char('j')]);
    }

    #[test]
    fn a_stray_byte_does_not_leak_the_sequence_after_it() {
        // Found by a hostile test pass: half a UTF-8 character, then an arrow key.
        let mut d = Decoder::default();
        assert_eq!(keys(&d.feed(b"\xc3\x1b[A")), vec![Key::Up]);
        let got = d.feed(b"\xc3\x1b[<0;10;5M");
        assert_eq!(got, vec![Input::Mouse(9, 4, MouseInput::Press)]);
        assert_eq!(keys(&d.feed(b"\xff\xfeq")), vec![Key::Char('q')]);
    }

    #[test]
    fn a_bracketed_paste_is_one_input_of_text() {
        let mut d = Decoder::default();
        let mut bytes = b"\x1b[200~".to_vec();
        bytes.extend(b"q\rq".repeat(200));
        bytes.extend(b"\x1b[201~j");
        let got = d.feed(&bytes);
        assert_eq!(got.len(), 2);
        assert_eq!(got[0], Input::Paste("q\rq".repeat(200)));
        assert_eq!(got[1], Input::Key(Key::Char('j')));
    }

    #[test]
    fn sgr_mouse_events() {
        let mut d = Decoder::default();
        let got = d.feed(b"\x1b[<0;10;5M\x1b[<32;11;5M\x1b[<0;11;5m\x1b[<64;3;4M");
        assert_eq!(
            got,
            vec![
                Input::Mouse(9, 4, MouseInput::Press),
                Input::Mouse(10, 4, MouseInput::Drag),
                Input::Mouse(10, 4, MouseInput::Release),
                Input::Mouse(2, 3, MouseInput::ScrollUp),
            ]
        );
    }
}
