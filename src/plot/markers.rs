//! How the charts draw their curves: a [`MarkerSet`] for every room — Braille dots (the finest,
//! for a laptop), half blocks, quadrants and sextants (thicker lines that read from the back of
//! a room and draw in fonts without Braille), whole blocks (the thickest), and ASCII (`*`,
//! for terminals without Unicode). The `--projector` look uses half blocks.

use ratatui::symbols::Marker;

/// The characters a chart's curves are drawn with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MarkerSet {
    /// Braille dots, 2×4 to a cell: the finest lines.
    #[default]
    Braille,
    /// Half blocks, 1×2 to a cell: thick lines with square pixels.
    HalfBlock,
    /// Quadrants, 2×2 to a cell.
    Quadrant,
    /// Sextants, 2×3 to a cell (Unicode 13: not in every font).
    Sextant,
    /// Whole blocks, one to a cell: the thickest lines.
    Block,
    /// `*`, one to a cell: for terminals without Unicode.
    Ascii,
}

impl MarkerSet {
    /// Every set, in the order `M` cycles through them.
    pub const ALL: [MarkerSet; 6] = [
        MarkerSet::Braille,
        MarkerSet::HalfBlock,
        MarkerSet::Quadrant,
        MarkerSet::Sextant,
        MarkerSet::Block,
        MarkerSet::Ascii,
    ];

    /// The name on the command line (`--marker`) and in messages.
    pub fn name(self) -> &'static str {
        match self {
            MarkerSet::Braille => "braille",
            MarkerSet::HalfBlock => "half-block",
            MarkerSet::Quadrant => "quadrant",
            MarkerSet::Sextant => "sextant",
            MarkerSet::Block => "block",
            MarkerSet::Ascii => "ascii",
        }
    }

    /// What it is for.
    pub fn description(self) -> &'static str {
        match self {
            MarkerSet::Braille => "Braille dots: the finest lines (the default)",
            MarkerSet::HalfBlock => "half blocks: thick lines for a projector (--projector)",
            MarkerSet::Quadrant => "quadrants: thick lines, twice as fine across",
            MarkerSet::Sextant => "sextants: thick and fine, in newer fonts only",
            MarkerSet::Block => "whole blocks: the thickest lines, one cell each",
            MarkerSet::Ascii => "asterisks: for terminals without Unicode",
        }
    }

    /// The set after this one.
    pub fn next(self) -> MarkerSet {
        let i = MarkerSet::ALL.iter().position(|m| *m == self).unwrap_or(0);
        MarkerSet::ALL[(i + 1) % MarkerSet::ALL.len()]
    }

    /// The set a look can draw: ASCII when the look has no Unicode.
    pub fn for_look(self, ascii: bool) -> MarkerSet {
        if ascii { MarkerSet::Ascii } else { self }
    }

    /// ratatui's marker for a curve.
    pub fn curve(self) -> Marker {
        match self {
            MarkerSet::Braille => Marker::Braille,
            MarkerSet::HalfBlock => Marker::HalfBlock,
            MarkerSet::Quadrant => Marker::Quadrant,
            MarkerSet::Sextant => Marker::Sextant,
            MarkerSet::Block => Marker::Block,
            MarkerSet::Ascii => Marker::Custom('*'),
        }
    }

    /// The key's character for a curve: what a short level stretch of it looks like.
    pub fn curve_key(self) -> char {
        match self {
            MarkerSet::Braille => '⠤',
            MarkerSet::HalfBlock | MarkerSet::Quadrant => '▄',
            MarkerSet::Sextant => '🬋',
            MarkerSet::Block => '█',
            MarkerSet::Ascii => '*',
        }
    }
}

#[cfg(test)]
mod tests {
    use super::MarkerSet;

    #[test]
    fn the_cycle_visits_every_set_once() {
        let mut seen = vec![MarkerSet::Braille];
        let mut set = MarkerSet::Braille.next();
        while set != MarkerSet::Braille {
            assert!(!seen.contains(&set), "{set:?} twice");
            seen.push(set);
            set = set.next();
        }
        assert_eq!(seen.len(), MarkerSet::ALL.len());
    }

    #[test]
    fn ascii_looks_draw_ascii_and_keys_are_one_column() {
        for set in MarkerSet::ALL {
            assert_eq!(set.for_look(true), MarkerSet::Ascii);
            assert_eq!(set.for_look(false), set);
            let key = set.curve_key().to_string();
            assert_eq!(
                unicode_width::UnicodeWidthStr::width(key.as_str()),
                1,
                "{set:?}"
            );
        }
        assert!(MarkerSet::Ascii.curve_key().is_ascii());
    }
}
