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
//!
//! A bracketed paste is read by the decoder itself, byte by byte up to its end marker, however
//! many reads and pauses it spans: its text is never decoded as keys. A paste of at most
//! [`PASTE_LIMIT`] bytes is one [`Input::Paste`]; a longer one is dropped whole — what came
//! before the limit is freed, what comes after is counted and skipped until the end marker —
//! and said so by [`Input::PasteDropped`]. The memory a paste holds is bounded by the limit
//! whatever its size, also for a paste that never ends.

use std::time::Duration;

use terminput::{Event, KeyCode, KeyEventKind, KeyModifiers};

use super::keys::Key;

/// How long a lone ESC waits for the rest of a sequence.
pub const ESC_TIMEOUT: Duration = Duration::from_millis(30);
/// Longest escape sequence kept while incomplete.
pub const SEQUENCE_LIMIT: usize = 64;
/// Longest bracketed paste kept (a paste is typed into a prompt, which takes far less); a
/// longer one is dropped whole.
pub const PASTE_LIMIT: usize = 64 * 1024;
/// How a bracketed paste starts.
const PASTE_START: &[u8] = b"\x1b[200~";
/// How a bracketed paste ends.
const PASTE_END: &[u8] = b"\x1b[201~";

/// What the terminal said.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    Key(Key),
    /// A mouse event: (column, row, what).
    Mouse(u16, u16, MouseInput),
    /// A bracketed paste: text the terminal marked as pasted, not typed.
    Paste(String),
    /// A bracketed paste over [`PASTE_LIMIT`], dropped whole: nothing of it is typed.
    PasteDropped(DroppedPaste),
}

/// A paste dropped for its size: said once when it passes the limit, and again when it ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DroppedPaste {
    /// The paste's bytes so far (all of them once it ended), end marker not counted.
    pub bytes: usize,
    /// It ended (else it has just passed the limit, and the rest is being skipped).
    pub ended: bool,
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
    /// An escape sequence (or a character) not complete yet: at most [`SEQUENCE_LIMIT`] bytes.
    pending: Vec<u8>,
    /// The bracketed paste being read, from its start marker to its end marker.
    paste: Option<PasteInProgress>,
}

/// A bracketed paste between its start and end markers.
#[derive(Debug, Default)]
struct PasteInProgress {
    /// Its bytes while it is within the limit (the end marker's first bytes included until
    /// they are known to be it); freed once the paste is over the limit.
    kept: Vec<u8>,
    /// Its bytes so far, those of `kept` and the skipped ones alike.
    length: usize,
    /// How many bytes of [`PASTE_END`] the last bytes are.
    end_matched: usize,
    /// Over the limit: dropped whole, its further bytes only counted.
    over: bool,
}

impl PasteInProgress {
    /// Takes one byte of the paste: the input it makes (the paste, a note that it is dropped)
    /// and whether it ended with this byte.
    fn take(&mut self, byte: u8) -> (Option<Input>, bool) {
        self.length += 1;
        if !self.over {
            self.kept.push(byte);
        }
        // ESC appears only first in the marker, so a mismatch restarts the match at ESC or 0.
        self.end_matched = if byte == PASTE_END[self.end_matched] {
            self.end_matched + 1
        } else {
            usize::from(byte == PASTE_END[0])
        };
        if self.end_matched == PASTE_END.len() {
            let bytes = self.length - PASTE_END.len();
            let input = if self.over {
                Input::PasteDropped(DroppedPaste { bytes, ended: true })
            } else {
                self.kept.truncate(bytes);
                Input::Paste(String::from_utf8_lossy(&self.kept).into_owned())
            };
            return (Some(input), true);
        }
        // Even if the marker ends with the next bytes, the text is longer than the limit.
        if !self.over && self.length - self.end_matched > PASTE_LIMIT {
            self.over = true;
            self.kept = Vec::new();
            let bytes = self.length - self.end_matched;
            return (
                Some(Input::PasteDropped(DroppedPaste {
                    bytes,
                    ended: false,
                })),
                false,
            );
        }
        (None, false)
    }
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
            if let Some(paste) = &mut self.paste {
                let (input, ended) = paste.take(byte);
                inputs.extend(input);
                if ended {
                    self.paste = None;
                }
                continue;
            }
            self.pending.push(byte);
            if self.pending == [0x1b] {
                // The start of a sequence, or the Esc key: the next byte tells (or, at the end
                // of what arrived, the timeout: see `flush`).
                continue;
            }
            if self.pending == PASTE_START {
                self.pending.clear();
                self.paste = Some(PasteInProgress::default());
                continue;
            }
            // Bytes after a dropped one are decoded again (at most SEQUENCE_LIMIT of them).
            for byte in self.decode_pending(inputs, false).into_iter().rev() {
                queue.push_front(byte);
            }
        }
    }

    /// Is a lone ESC (or an incomplete sequence) waiting? (A paste in progress is not: it
    /// waits for its end marker, however long that takes.)
    pub fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// The bytes the decoder holds (its buffers' capacity): at most about [`PASTE_LIMIT`]
    /// twice, whatever arrives.
    pub fn held_bytes(&self) -> usize {
        self.pending.capacity() + self.paste.as_ref().map_or(0, |p| p.kept.capacity())
    }

    /// After [`ESC_TIMEOUT`] without more bytes: what is pending is taken as typed (a lone
    /// ESC is the Esc key). A paste in progress goes on.
    pub fn flush(&mut self) -> Vec<Input> {
        let mut inputs = Vec::new();
        if self.pending.is_empty() {
            return inputs;
        }
        let rest = self.decode_pending(&mut inputs, true);
        self.pending.clear();
        if !rest.is_empty() {
            self.feed_into(&rest, &mut inputs);
            inputs.extend(self.flush());
        }
        inputs
    }

    /// Decodes what is pending; returns the bytes to decode again after a dropped one.
    fn decode_pending(&mut self, inputs: &mut Vec<Input>, flushing: bool) -> Vec<u8> {
        match Event::parse_from(&self.pending) {
            Ok(Some(event)) => {
                inputs.extend(translate(event));
                self.pending.clear();
                Vec::new()
            }
            Ok(None) if !flushing && self.pending.len() < SEQUENCE_LIMIT => Vec::new(),
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

    /// A paste of `length` bytes of `q`, `a` and Enter, with its markers.
    fn paste_of(length: usize) -> Vec<u8> {
        let mut bytes = PASTE_START.to_vec();
        bytes.extend(b"qa\r".iter().copied().cycle().take(length));
        bytes.extend(PASTE_END);
        bytes
    }

    #[test]
    fn a_paste_over_the_limit_is_dropped_whole_and_nothing_of_it_is_typed() {
        // Issue 22: the text after the cut at 64 KiB was decoded as keys (q quit).
        let mut d = Decoder::default();
        let mut bytes = paste_of(200 * 1024);
        bytes.push(b'j');
        let mut got = Vec::new();
        // In reads of 4 KiB, as a terminal delivers it, with a flush (a pause) between reads.
        for chunk in bytes.chunks(4096) {
            got.extend(d.feed(chunk));
            got.extend(d.flush());
            assert!(d.held_bytes() <= 2 * PASTE_LIMIT, "{}", d.held_bytes());
        }
        let crossed = PASTE_LIMIT + 1;
        assert_eq!(
            got,
            vec![
                Input::PasteDropped(DroppedPaste {
                    bytes: crossed,
                    ended: false
                }),
                Input::PasteDropped(DroppedPaste {
                    bytes: 200 * 1024,
                    ended: true
                }),
                Input::Key(Key::Char('j')),
            ]
        );
        assert!(!d.has_pending());
    }

    #[test]
    fn a_paste_at_the_limit_is_kept_and_one_byte_more_is_dropped() {
        let mut d = Decoder::default();
        let got = d.feed(&paste_of(PASTE_LIMIT));
        assert_eq!(got.len(), 1);
        assert!(matches!(&got[0], Input::Paste(text) if text.len() == PASTE_LIMIT));
        let got = d.feed(&paste_of(PASTE_LIMIT + 1));
        assert_eq!(
            got.last(),
            Some(&Input::PasteDropped(DroppedPaste {
                bytes: PASTE_LIMIT + 1,
                ended: true
            }))
        );
        // The end marker split across reads, after an ESC inside the paste.
        let mut d = Decoder::default();
        assert!(d.feed(b"\x1b[200~ab\x1b[20").is_empty());
        assert!(d.feed(b"0~c\x1b[2").is_empty());
        assert_eq!(d.feed(b"01~"), vec![Input::Paste("ab\x1b[200~c".into())]);
    }

    #[test]
    fn a_paste_that_never_ends_holds_bounded_memory_and_types_nothing() {
        let mut d = Decoder::default();
        assert!(d.feed(PASTE_START).is_empty());
        let chunk = b"qqqqaaaa\r\x1b".repeat(4096);
        let mut got = Vec::new();
        for _ in 0..200 {
            got.extend(d.feed(&chunk));
            got.extend(d.flush());
            assert!(d.held_bytes() <= 2 * PASTE_LIMIT, "{}", d.held_bytes());
        }
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(matches!(
            got[0],
            Input::PasteDropped(DroppedPaste { ended: false, .. })
        ));
        // Once it ends, keys are keys again.
        assert_eq!(
            d.feed(b"\x1b[201~q"),
            vec![
                Input::PasteDropped(DroppedPaste {
                    bytes: 200 * chunk.len(),
                    ended: true
                }),
                Input::Key(Key::Char('q'))
            ]
        );
        assert!(d.held_bytes() <= 2 * SEQUENCE_LIMIT, "{}", d.held_bytes());
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
