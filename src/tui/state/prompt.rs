//! A one-line text prompt (typing a value, a file name): a cursor that moves (←/→, Home/End
//! or Ctrl-A/Ctrl-E), Backspace before the cursor, Ctrl-U to erase up to it, a length limit,
//! and an optional pre-filled value that the first typed character replaces (as a selected
//! field does), so `Enter 0.5 Enter` still sets 0.5 while the current value stays in view.

/// The text of a prompt and where its cursor is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Prompt {
    pub text: String,
    /// Cursor position in characters (0 ..= number of characters).
    pub cursor: usize,
    /// The text is the pre-filled value, all of it selected: typing replaces it.
    pub selected: bool,
    /// Characters typed or pasted past the limit, not inserted: the text is not what was
    /// typed, so Enter refuses it until the prompt is emptied (Ctrl-U, Backspace).
    pub refused: usize,
}

/// What typing a character did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Typed {
    Inserted,
    /// The prompt is full: nothing was inserted.
    Full,
}

impl Prompt {
    /// A prompt holding `text`, the cursor at its end; `selected` when typing should replace it.
    pub fn new(text: impl Into<String>, selected: bool) -> Prompt {
        let text = text.into();
        Prompt {
            cursor: text.chars().count(),
            text,
            selected,
            refused: 0,
        }
    }

    fn byte_index(&self, chars: usize) -> usize {
        self.text
            .char_indices()
            .nth(chars)
            .map_or(self.text.len(), |(i, _)| i)
    }

    /// Types `c` at the cursor (replacing a selected pre-filled value), unless `limit`
    /// characters are there already.
    pub fn insert(&mut self, c: char, limit: usize) -> Typed {
        if self.selected {
            self.text.clear();
            self.cursor = 0;
            self.selected = false;
        }
        if self.text.chars().count() >= limit {
            self.refused += 1;
            return Typed::Full;
        }
        let at = self.byte_index(self.cursor);
        self.text.insert(at, c);
        self.cursor += 1;
        Typed::Inserted
    }

    /// Backspace: the character before the cursor (or the whole selected value).
    pub fn delete_before(&mut self) {
        if self.selected {
            *self = Prompt::new("", false);
            return;
        }
        if self.cursor > 0 {
            let at = self.byte_index(self.cursor - 1);
            self.text.remove(at);
            self.cursor -= 1;
        }
        self.forget_refused_when_empty();
    }

    /// An emptied prompt starts afresh: nothing typed into it was refused.
    fn forget_refused_when_empty(&mut self) {
        if self.text.is_empty() {
            self.refused = 0;
        }
    }

    /// Ctrl-U: everything before the cursor.
    pub fn erase_to_start(&mut self) {
        let at = self.byte_index(self.cursor);
        self.text.replace_range(..at, "");
        self.cursor = 0;
        self.selected = false;
        self.forget_refused_when_empty();
    }

    /// Moves the cursor by `step` characters (negative: left), within the text.
    pub fn move_by(&mut self, step: isize) {
        self.selected = false;
        let len = self.text.chars().count() as isize;
        self.cursor = (self.cursor as isize + step).clamp(0, len) as usize;
    }

    pub fn home(&mut self) {
        self.selected = false;
        self.cursor = 0;
    }

    pub fn end(&mut self) {
        self.selected = false;
        self.cursor = self.text.chars().count();
    }

    /// The text split at the cursor, for drawing: before, the character under the cursor
    /// (a space at the end), after.
    pub fn split(&self) -> (String, String, String) {
        let before: String = self.text.chars().take(self.cursor).collect();
        let mut rest = self.text.chars().skip(self.cursor);
        let under = rest.next().map_or(" ".to_string(), String::from);
        (before, under, rest.collect())
    }
}

/// The text a value is pre-filled with: plain decimals from 1e-3 to 1e6, else scientific
/// notation; both read back to the same number (Rust prints the shortest such form).
pub fn editable_number(value: f64) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typing_replaces_a_selected_value_and_edits_at_the_cursor() {
        let mut p = Prompt::new("0.8", true);
        assert_eq!(p.insert('5', 10), Typed::Inserted);
        assert_eq!(p.text, "5");
        let mut p = Prompt::new("0.8", true);
        p.move_by(-1);
        p.insert('5', 10);
        assert_eq!((p.text.as_str(), p.cursor), ("0.58", 3));
        p.home();
        p.insert('1', 10);
        assert_eq!(p.text, "10.58");
        p.end();
        p.delete_before();
        assert_eq!(p.text, "10.5");
        p.move_by(-2);
        p.erase_to_start();
        assert_eq!((p.text.as_str(), p.cursor), (".5", 0));
        p.move_by(-5);
        assert_eq!(p.cursor, 0);
        p.move_by(50);
        assert_eq!(p.cursor, 2);
        assert_eq!(p.insert('x', 2), Typed::Full);
        assert_eq!(p.split(), (".5".into(), " ".into(), String::new()));
        // Multi-byte characters move as one.
        let mut p = Prompt::new("ε=1", false);
        p.home();
        p.move_by(1);
        p.delete_before();
        assert_eq!(p.text, "=1");
        // Backspace on a selected value clears it.
        let mut p = Prompt::new("dual", true);
        p.delete_before();
        assert_eq!(p.text, "");
    }

    #[test]
    fn pre_filled_numbers_read_back_exactly() {
        for value in [
            0.8,
            5e4,
            2.15e11,
            1e-6,
            1.0 / 3.0,
            1e300,
            5e-324,
            0.0,
            -1.5e5,
            123456.0,
        ] {
            let text = editable_number(value);
            assert_eq!(text.parse::<f64>().unwrap(), value, "{text}");
        }
        assert_eq!(editable_number(0.8), "0.8");
        assert_eq!(editable_number(2.15e11), "2.15e11");
        assert_eq!(editable_number(1e-6), "1e-6");
    }
}
