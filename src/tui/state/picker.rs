//! The preset picker's state: what has been typed into its search, which of the matching
//! presets is highlighted, and how far its list is scrolled. Typing filters the presets by
//! name, title and description (every word typed must occur, in any case); the highlight and
//! the scroll are positions in the filtered list.

use std::sync::OnceLock;

use crate::scene::{PRESETS, Scene};

/// Longest search text kept.
pub const QUERY_LIMIT: usize = 60;

/// What the picker shows of a preset: its name, and the title and description of its scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PresetInfo {
    pub name: &'static str,
    pub title: String,
    pub description: String,
    /// The scene's mesh size: a served student's picker marks presets beyond its limit.
    pub elements: usize,
}

/// Every preset's name, title and description, in the order of [`PRESETS`] (read once).
pub fn preset_infos() -> &'static [PresetInfo] {
    static INFOS: OnceLock<Vec<PresetInfo>> = OnceLock::new();
    INFOS.get_or_init(|| {
        PRESETS
            .iter()
            .map(|p| {
                let scene = Scene::from_toml(p.text, p.name).ok();
                PresetInfo {
                    name: p.name,
                    title: scene.as_ref().map(|s| s.title.clone()).unwrap_or_default(),
                    elements: scene.as_ref().map_or(0, |s| s.mesh.elements),
                    description: scene.map(|s| s.description).unwrap_or_default(),
                }
            })
            .collect()
    })
}

/// The picker: search text, highlighted entry and scroll, both counted in the filtered list.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PresetPicker {
    pub query: String,
    /// The highlighted entry, an index into [`PresetPicker::matches`].
    pub index: usize,
    /// The first entry shown.
    pub offset: usize,
}

impl PresetPicker {
    /// The picker with `preset` (an index into [`PRESETS`]) highlighted and no search.
    pub fn at(preset: usize) -> PresetPicker {
        PresetPicker {
            query: String::new(),
            index: preset.min(PRESETS.len().saturating_sub(1)),
            offset: 0,
        }
    }

    /// The presets that match the search, as indices into [`PRESETS`], in their order.
    pub fn matches(&self) -> Vec<usize> {
        let words: Vec<String> = self
            .query
            .split_whitespace()
            .map(str::to_lowercase)
            .collect();
        preset_infos()
            .iter()
            .enumerate()
            .filter(|(_, info)| {
                let text =
                    format!("{} {} {}", info.name, info.title, info.description).to_lowercase();
                words.iter().all(|w| text.contains(w.as_str()))
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// The highlighted preset (an index into [`PRESETS`]), if any matches.
    pub fn highlighted(&self) -> Option<usize> {
        let matches = self.matches();
        matches
            .get(self.index.min(matches.len().saturating_sub(1)))
            .copied()
    }

    /// Moves the highlight to entry `index` of the filtered list (clamped), scrolling so that
    /// it stays among the `visible` entries shown.
    pub fn select(&mut self, index: isize, visible: usize) {
        let count = self.matches().len();
        let last = count.saturating_sub(1) as isize;
        self.index = index.clamp(0, last.max(0)) as usize;
        self.scroll_to_highlight(visible);
    }

    /// Keeps the highlighted entry among the `visible` entries shown from `offset`.
    pub fn scroll_to_highlight(&mut self, visible: usize) {
        let visible = visible.max(1);
        let count = self.matches().len();
        self.index = self.index.min(count.saturating_sub(1));
        self.offset = self
            .offset
            .min(self.index)
            .max((self.index + 1).saturating_sub(visible))
            .min(count.saturating_sub(visible));
    }

    /// Types `c` into the search (the highlight goes back to the first match).
    pub fn type_char(&mut self, c: char, visible: usize) {
        if self.query.chars().count() < QUERY_LIMIT && !c.is_control() {
            self.query.push(c);
        }
        self.index = 0;
        self.offset = 0;
        self.scroll_to_highlight(visible);
    }

    /// Deletes the last character of the search.
    pub fn delete_char(&mut self, visible: usize) {
        self.query.pop();
        self.index = 0;
        self.offset = 0;
        self.scroll_to_highlight(visible);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The presets whose TOML text mentions `word` in their name, title or description lines,
    /// read from the files themselves (independently of the parsed scenes).
    fn mentioning(word: &str) -> Vec<&'static str> {
        PRESETS
            .iter()
            .filter(|p| {
                p.name.contains(word)
                    || p.text.lines().any(|l| {
                        (l.starts_with("title") || l.starts_with("description"))
                            && l.to_lowercase().contains(word)
                    })
            })
            .map(|p| p.name)
            .collect()
    }

    fn names(picker: &PresetPicker) -> Vec<&'static str> {
        picker.matches().iter().map(|&i| PRESETS[i].name).collect()
    }

    #[test]
    fn every_preset_has_a_title_and_a_description() {
        for info in preset_infos() {
            assert!(!info.title.is_empty(), "{}", info.name);
            assert!(!info.description.is_empty(), "{}", info.name);
        }
    }

    #[test]
    fn typing_filters_by_name_and_description_in_any_case() {
        let mut picker = PresetPicker::at(3);
        assert_eq!(picker.matches().len(), PRESETS.len());
        assert_eq!(picker.highlighted(), Some(3));
        for c in "Closed".chars() {
            picker.type_char(c, 5);
        }
        let expected = mentioning("closed");
        assert!(!expected.is_empty());
        assert_eq!(names(&picker), expected);
        assert_eq!(picker.index, 0, "the highlight goes to the first match");
        // Two words: both must occur.
        let mut picker = PresetPicker::default();
        for c in "bench obstacles".chars() {
            picker.type_char(c, 5);
        }
        let both: Vec<&str> = mentioning("bench")
            .into_iter()
            .filter(|n| mentioning("obstacles").contains(n))
            .collect();
        assert_eq!(names(&picker), both);
        // Nothing matches: nothing is highlighted, and Backspace brings the list back.
        let mut picker = PresetPicker::default();
        for c in "zzzq".chars() {
            picker.type_char(c, 5);
        }
        assert_eq!(picker.highlighted(), None);
        for _ in 0..4 {
            picker.delete_char(5);
        }
        assert_eq!(picker.matches().len(), PRESETS.len());
    }

    #[test]
    fn the_highlight_stays_in_the_list_and_in_view() {
        let mut picker = PresetPicker::default();
        let count = PRESETS.len();
        picker.select(count as isize + 5, 4);
        assert_eq!(picker.index, count - 1);
        assert_eq!(picker.offset, count - 4);
        picker.select(-3, 4);
        assert_eq!((picker.index, picker.offset), (0, 0));
        picker.select(5, 4);
        assert_eq!((picker.index, picker.offset), (5, 2));
        // Moving up inside the view does not scroll.
        picker.select(3, 4);
        assert_eq!((picker.index, picker.offset), (3, 2));
        // A long search text is cut at the limit.
        for _ in 0..200 {
            picker.type_char('x', 4);
        }
        assert_eq!(picker.query.chars().count(), QUERY_LIMIT);
    }
}
