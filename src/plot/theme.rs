//! Styles for a [`Look`] and a [`Palette`]: colours only when asked for, borders in ASCII when
//! Unicode is off, and three palettes — `dark` (the default, for dark terminals), `light` (for
//! light terminals: no yellow, no cyan text) and `high-contrast` (for projectors: bright colours
//! on an explicit black background, bold). In every palette dark grey is only decoration
//! (axis lines, the u = 0 line, the clamped ends): no information is carried by it alone.

use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::border;
use ratatui::text::Line;
use ratatui::widgets::{Block, Borders};

use super::{Look, MarkerSet};

/// A set of colours for the terminal's background.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Palette {
    /// For dark terminal backgrounds.
    #[default]
    Dark,
    /// For light terminal backgrounds.
    Light,
    /// For projectors: bright, bold colours on black.
    HighContrast,
}

impl Palette {
    /// Every palette, in the order `T` cycles through them.
    pub const ALL: [Palette; 3] = [Palette::Dark, Palette::Light, Palette::HighContrast];

    /// The name on the command line (`--theme`) and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Palette::Dark => "dark",
            Palette::Light => "light",
            Palette::HighContrast => "high-contrast",
        }
    }

    /// What it is for.
    pub fn description(self) -> &'static str {
        match self {
            Palette::Dark => "colours for a dark terminal background (the default)",
            Palette::Light => "colours for a light terminal background (no yellow or cyan text)",
            Palette::HighContrast => "bright, bold colours on black, for projectors",
        }
    }

    /// The palette after this one.
    pub fn next(self) -> Palette {
        let i = Palette::ALL.iter().position(|p| *p == self).unwrap_or(0);
        Palette::ALL[(i + 1) % Palette::ALL.len()]
    }
}

/// The styles of every element of a frame, for one [`Look`] and [`Palette`].
#[derive(Debug, Clone, Copy)]
pub struct Theme {
    pub look: Look,
    pub palette: Palette,
    /// What curves are drawn with (ASCII whatever this says when the look has no Unicode).
    pub markers: MarkerSet,
}

impl Theme {
    pub fn new(look: Look, palette: Palette, markers: MarkerSet) -> Theme {
        Theme {
            look,
            palette,
            markers,
        }
    }

    /// The marker set the curves are drawn with in this look.
    pub fn curve_markers(&self) -> MarkerSet {
        self.markers.for_look(self.look.ascii)
    }

    fn colored(&self, dark: Style, light: Style, high: Style) -> Option<Style> {
        self.look.color.then_some(match self.palette {
            Palette::Dark => dark,
            Palette::Light => light,
            Palette::HighContrast => high,
        })
    }

    fn fg(color: Color) -> Style {
        Style::default().fg(color)
    }

    fn bold(color: Color) -> Style {
        Style::default().fg(color).add_modifier(Modifier::BOLD)
    }

    /// The style under everything: the high-contrast palette sets its own background.
    pub fn base(&self) -> Style {
        self.colored(
            Style::default(),
            Style::default(),
            Style::default().fg(Color::White).bg(Color::Black),
        )
        .unwrap_or_default()
    }
    /// Ordinary text (axis labels among it): bold in the high-contrast palette, with or without
    /// colours, so that it reads from the back of a room.
    pub fn plain(&self) -> Style {
        if self.palette == Palette::HighContrast {
            Style::default().add_modifier(Modifier::BOLD)
        } else {
            Style::default()
        }
    }
    pub fn title(&self) -> Style {
        self.colored(
            Theme::bold(Color::Cyan),
            Theme::bold(Color::Blue),
            Theme::bold(Color::White),
        )
        .unwrap_or(Style::default().add_modifier(Modifier::BOLD))
    }
    pub fn selected(&self) -> Style {
        self.colored(
            Style::default().fg(Color::Black).bg(Color::Cyan),
            Style::default().fg(Color::White).bg(Color::Blue),
            Style::default()
                .fg(Color::Black)
                .bg(Color::White)
                .add_modifier(Modifier::BOLD),
        )
        .unwrap_or(Style::default().add_modifier(Modifier::REVERSED))
    }
    /// Secondary text (details, hints): readable in every palette, never dark grey.
    pub fn dim(&self) -> Style {
        self.colored(
            Theme::fg(Color::Gray),
            Style::default(),
            Theme::fg(Color::White),
        )
        .unwrap_or_default()
    }
    /// Decoration that carries no information of its own (axis lines, the u = 0 line, the
    /// clamped ends): the one use of dark grey.
    pub fn faint(&self) -> Style {
        self.colored(
            Theme::fg(Color::DarkGray),
            Theme::fg(Color::DarkGray),
            Theme::fg(Color::Gray),
        )
        .unwrap_or_default()
    }
    /// The current point of a study chart (the ε or n the scene has): it must stand out.
    pub fn current(&self) -> Style {
        self.colored(
            Theme::bold(Color::White),
            Theme::bold(Color::Black),
            Theme::bold(Color::LightYellow),
        )
        .unwrap_or(Style::default().add_modifier(Modifier::BOLD))
    }
    pub fn warning(&self) -> Style {
        self.colored(
            Theme::fg(Color::Yellow),
            Theme::bold(Color::Magenta),
            Theme::bold(Color::LightYellow),
        )
        .unwrap_or(Style::default().add_modifier(Modifier::BOLD))
    }
    pub fn error(&self) -> Style {
        self.colored(
            Theme::bold(Color::Red),
            Theme::bold(Color::Red),
            Theme::bold(Color::LightRed),
        )
        .unwrap_or(Style::default().add_modifier(Modifier::BOLD))
    }
    /// The style of a chart's series number `index`.
    pub fn series(&self, index: usize) -> Style {
        const DARK: [Color; 7] = [
            Color::Cyan,
            Color::Yellow,
            Color::Magenta,
            Color::Green,
            Color::Red,
            Color::Blue,
            Color::White,
        ];
        // Dark enough on white: no yellow, cyan or grey (256-colour teal and brown).
        const LIGHT: [Color; 7] = [
            Color::Blue,
            Color::Red,
            Color::Magenta,
            Color::Green,
            Color::Black,
            Color::Indexed(30),
            Color::Indexed(94),
        ];
        const HIGH: [Color; 7] = [
            Color::LightCyan,
            Color::LightYellow,
            Color::LightMagenta,
            Color::LightGreen,
            Color::LightRed,
            Color::LightBlue,
            Color::White,
        ];
        let i = index % DARK.len();
        self.colored(
            Theme::fg(DARK[i]),
            Theme::fg(LIGHT[i]),
            Theme::bold(HIGH[i]),
        )
        .unwrap_or_default()
    }
    /// A bordered block with a title.
    pub fn block<'a>(&self, title: impl Into<Line<'a>>, focused: bool) -> Block<'a> {
        let set = if self.look.ascii {
            border::Set {
                top_left: "+",
                top_right: "+",
                bottom_left: "+",
                bottom_right: "+",
                vertical_left: "|",
                vertical_right: "|",
                horizontal_top: "-",
                horizontal_bottom: "-",
            }
        } else if focused {
            border::THICK
        } else {
            border::PLAIN
        };
        Block::default()
            .borders(Borders::ALL)
            .border_set(set)
            .style(self.base())
            .title(title)
            .title_style(self.title())
    }

    /// `text` as this look spells it: in ASCII, `eps` for ε, `cond2(A^)` for cond₂(Â), `x` for
    /// ×, `|` for a separating ·, `*` for a multiplying one (see [`super::spell_ascii`]).
    pub fn text<'a>(&self, text: &'a str) -> std::borrow::Cow<'a, str> {
        if self.look.ascii {
            std::borrow::Cow::Owned(super::spell_ascii(text))
        } else {
            std::borrow::Cow::Borrowed(text)
        }
    }
}
