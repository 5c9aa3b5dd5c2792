//! The command line's argument types (clap derive) and the value parsers for the crate's own
//! enums: [`Method`] and [`ConditionLevel`] know nothing of clap, so their clap names and help
//! come from their `name()` and `description()` here. Numeric options take negative numbers
//! as values (so `--elements -1` is refused for its value, quoted, not taken for an option)
//! and refuse what cannot be a count or a finite number in words.

use std::path::PathBuf;
use std::sync::LazyLock;

use clap::builder::PossibleValue;
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::figure::FigurePanel;
use crate::plot::{MarkerSet, Palette};
use crate::scene::MAX_ELEMENTS;
use crate::solve::{ConditionLevel, Method};

mod formats;
pub use formats::{CheckFormat, Format, GradeFormat, TableFormat};

/// The methods in declaration order (the order clap has always listed them in).
static METHODS: LazyLock<Vec<Method>> = LazyLock::new(|| {
    let mut methods = Method::ALL.to_vec();
    methods.sort_by_key(|m| *m as u8);
    methods
});

impl ValueEnum for Method {
    fn value_variants<'a>() -> &'a [Self] {
        &METHODS
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

impl ValueEnum for Palette {
    fn value_variants<'a>() -> &'a [Self] {
        &Palette::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

impl ValueEnum for MarkerSet {
    fn value_variants<'a>() -> &'a [Self] {
        &MarkerSet::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

impl ValueEnum for FigurePanel {
    fn value_variants<'a>() -> &'a [Self] {
        &FigurePanel::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

/// The palette and marker set of `--theme`, `--marker` and `--projector`: what is given, else
/// the projector's (high-contrast, half blocks) with `--projector`, else the defaults.
pub fn chosen_look(
    theme: Option<Palette>,
    marker: Option<MarkerSet>,
    projector: bool,
) -> (Palette, MarkerSet) {
    let (palette, markers) = if projector {
        (Palette::HighContrast, MarkerSet::HalfBlock)
    } else {
        (Palette::default(), MarkerSet::default())
    };
    (theme.unwrap_or(palette), marker.unwrap_or(markers))
}

impl DisplayArgs {
    /// The palette and marker set asked for.
    pub fn palette_and_markers(&self) -> (Palette, MarkerSet) {
        chosen_look(self.theme, self.marker, self.projector)
    }
}

impl ValueEnum for ConditionLevel {
    fn value_variants<'a>() -> &'a [Self] {
        &ConditionLevel::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

/// Explore a clamped beam through point obstacles with given sliding and swivel friction.
#[derive(Debug, Parser)]
#[command(
    name = "beamfric",
    version,
    about,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Scene file or preset name to open (default: benchmark-1).
    #[arg(conflicts_with = "lesson")]
    pub scene: Option<String>,
    #[command(flatten)]
    pub lesson: LessonArgs,
    #[command(flatten)]
    pub display: DisplayArgs,
}

/// A lesson to step through (Space / Backspace, `n` / `N`), and the step to start on.
#[derive(Debug, Args)]
pub struct LessonArgs {
    /// A lesson file (TOML: steps with a scene, settings and a caption; see lessons/).
    #[arg(long, value_name = "FILE")]
    pub lesson: Option<std::path::PathBuf>,
    /// The step to start on, counted from 1.
    #[arg(long, value_name = "K", requires = "lesson", value_parser = count_up_to(crate::lesson::MAX_STEPS), allow_negative_numbers = true)]
    pub step: Option<usize>,
}

/// How an explorer draws: the same options for `beamfric`, `serve` (the default of every
/// session) and `present` (the lecturer's explorer and the sessions).
#[derive(Debug, Args, Clone)]
pub struct DisplayArgs {
    /// Draw without Unicode (no Braille, no box drawing) for plain terminals; automatic when
    /// the locale (LC_ALL, LC_CTYPE or LANG; a session's: its client's) is not UTF-8.
    #[arg(long)]
    pub ascii: bool,
    /// No colours (also when NO_COLOR is set; a session's: its client's).
    #[arg(long)]
    pub no_color: bool,
    /// Colours for the terminal's background or a projector (`T` cycles them) [default: dark,
    /// high-contrast with --projector].
    #[arg(long, value_name = "THEME")]
    pub theme: Option<Palette>,
    /// What the charts' curves are drawn with (`M` cycles them) [default: braille, half-block
    /// with --projector; ascii without Unicode].
    #[arg(long, value_name = "SET")]
    pub marker: Option<MarkerSet>,
    /// The look for a projector: thick half-block curves, the high-contrast palette, bold
    /// labels (--theme and --marker still choose).
    #[arg(long)]
    pub projector: bool,
    /// Leave the mouse to the terminal (no clicks, wheel or drags in the explorer).
    #[arg(long)]
    pub no_mouse: bool,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a scene once and print the solution with its certificate.
    Solve(SolveArgs),
    /// Run the stability suite on every preset (or one scene) and print the verdicts.
    Check(CheckArgs),
    /// Print the explorer's frame after some keys, without a terminal.
    Render(RenderArgs),
    /// Sweep ε or the mesh size and print the results as CSV or JSON.
    #[command(subcommand)]
    Sweep(SweepCommand),
    /// Write the error-against-run-time report (Markdown, CSV, SVG) for a scene.
    Report(ReportArgs),
    /// Write a panel's figure as SVG (the explorer's `e`): the same data, slide-sized.
    Figure(FigureArgs),
    /// Serve the explorer over SSH: every connection gets its own explorer.
    Serve(ServeArgs),
    /// Serve as `serve` does, with your own explorer in this terminal presenting: every
    /// student who follows sees its scene and view live. Quitting it stops the server.
    Present(PresentArgs),
    /// Write the discrete problem (A, b, B, g, the mesh) as Matrix Market, JSON and CSV files
    /// with a README of the conventions, for your own method.
    Export(ExportArgs),
    /// Grade an answer computed elsewhere (forces λ or nodal u, u'; JSON or CSV) with the
    /// certificate of the built-in methods.
    Grade(GradeArgs),
}

/// `beamfric export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Number of elements (default: the scene's).
    #[arg(long, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub elements: Option<usize>,
    /// The directory for the files (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Replace the files of an earlier export in DIR.
    #[arg(long)]
    pub force: bool,
}

/// `beamfric grade`.
#[derive(Debug, Args)]
pub struct GradeArgs {
    /// Scene file or preset name (the one the answer was computed for).
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Number of elements (default: the scene's; the one the answer was computed on).
    #[arg(long, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub elements: Option<usize>,
    /// The answer: forces λ and/or nodal u, u' as JSON or CSV (see
    /// docs/bring-your-own-method.md); the JSON of `beamfric solve --format json` is one form.
    #[arg(long, value_name = "FILE")]
    pub answer: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = GradeFormat::Table)]
    pub format: GradeFormat,
}

/// `beamfric serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// Address and port to listen on.
    #[arg(long, default_value = "127.0.0.1:2222", value_name = "ADDR:PORT")]
    pub listen: String,
    /// The server's host key (created with mode 0600 on first start); default under
    /// ~/.config/beamfric.
    #[arg(long, value_name = "PATH")]
    pub host_key: Option<std::path::PathBuf>,
    /// Public keys that may log in (OpenSSH authorized_keys format).
    #[arg(long, value_name = "PATH")]
    pub authorized_keys: Option<std::path::PathBuf>,
    /// Public keys whose sessions present: every other session follows them (f forks, F
    /// rejoins).
    #[arg(long, value_name = "PATH")]
    pub presenter_keys: Option<std::path::PathBuf>,
    /// A file whose first line is the password any user name may log in with.
    #[arg(long, value_name = "PATH")]
    pub password_file: Option<std::path::PathBuf>,
    /// Let anyone log in (needed when neither --authorized-keys nor --password-file is given).
    #[arg(long)]
    pub open: bool,
    /// Most explorers at once; beyond, a polite message.
    #[arg(long, default_value_t = 64, value_name = "N")]
    pub max_sessions: usize,
    /// The server's memory budget in MiB: explorers beyond what it holds (at the largest
    /// window, a full undo history and --max-elements) get a polite message.
    #[arg(long, default_value_t = crate::serve::memory::DEFAULT_MEMORY_BUDGET_MIB, value_name = "MIB")]
    pub memory_budget: usize,
    /// Most elements a served session may ask for.
    #[arg(long, default_value_t = 100_000, value_name = "N")]
    pub max_elements: usize,
    /// End a session after this many seconds without input (0: never).
    #[arg(long, default_value_t = 1800, value_name = "SECS")]
    pub idle_timeout: u64,
    /// The scene every session starts with: a preset name or a scene file.
    #[arg(long, default_value = "benchmark-1", conflicts_with = "lesson")]
    pub scene: String,
    /// A lesson: the presenter steps through it (Space / Backspace) and followers see each
    /// step and its caption; without a presenter, every session steps on its own.
    #[arg(long, value_name = "FILE")]
    pub lesson: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub display: DisplayArgs,
    /// The only directory sessions may save scenes to (file names cannot leave it); without
    /// it, `s` shows the scene's TOML to copy.
    #[arg(long, value_name = "DIR")]
    pub save_dir: Option<std::path::PathBuf>,
}

/// `beamfric present`.
#[derive(Debug, Args)]
pub struct PresentArgs {
    /// Record your screen as an asciinema v2 cast (`asciinema play FILE` replays it), with a
    /// marker at each lesson step; never replaces a file, and at most 2 s are lost in a crash.
    #[arg(long, value_name = "FILE.cast")]
    pub record: Option<std::path::PathBuf>,
    /// The options of `serve`; the display options are also your own explorer's.
    #[command(flatten)]
    pub serve: ServeArgs,
}

/// `beamfric sweep …`.
#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// The regularised method over ε: error, largest condition numbers, run time.
    Epsilon(EpsilonSweepArgs),
    /// Every method over mesh sizes: error, median run time, KKT residual, warnings.
    Elements(ElementsSweepArgs),
}

/// `beamfric sweep epsilon`.
#[derive(Debug, Args)]
pub struct EpsilonSweepArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Smallest ε.
    #[arg(long, default_value_t = 1e-16, value_parser = finite_number, allow_hyphen_values = true)]
    pub from: f64,
    /// Largest ε.
    #[arg(long, default_value_t = 1.0, value_parser = finite_number, allow_hyphen_values = true)]
    pub to: f64,
    /// Number of ε values, log-spaced.
    #[arg(long, default_value_t = 33, value_parser = count_up_to(MAX_EPSILON_POINTS), allow_negative_numbers = true)]
    pub points: usize,
    /// The enumeration of paper 2.7.1, or semismooth Newton on the same ε-problem (which
    /// works with any number of obstacles).
    #[arg(long, value_enum, default_value = "regularized")]
    pub method: Method,
    /// Number of elements (default: the scene's).
    #[arg(long, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub elements: Option<usize>,
    #[arg(long, value_enum, default_value_t = TableFormat::Csv)]
    pub format: TableFormat,
}

/// The mesh sizes of a sweep over n: `--points` sizes from `--from` to `--to` elements,
/// log-spaced.
#[derive(Debug, Args)]
pub struct MeshSizes {
    /// Smallest number of elements.
    #[arg(long, default_value_t = 10, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub from: usize,
    /// Largest number of elements.
    #[arg(long, default_value_t = 1_000_000, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub to: usize,
    /// Number of mesh sizes, log-spaced.
    #[arg(long, default_value_t = 11, value_parser = count_up_to(MAX_MESH_POINTS), allow_negative_numbers = true)]
    pub points: usize,
}

/// `beamfric sweep elements`.
#[derive(Debug, Args)]
pub struct ElementsSweepArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Methods, comma-separated (default: all).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub methods: Vec<Method>,
    #[command(flatten)]
    pub sizes: MeshSizes,
    /// Runs per point; the run time is their median.
    #[arg(long, default_value_t = 3, value_parser = count_up_to(MAX_REPEAT), allow_negative_numbers = true)]
    pub repeat: usize,
    /// ε for the regularised methods (default: the scene's).
    #[arg(long, value_parser = finite_number, allow_hyphen_values = true)]
    pub epsilon: Option<f64>,
    #[arg(long, value_enum, default_value_t = TableFormat::Csv)]
    pub format: TableFormat,
}

/// `beamfric report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Directory for report.md and the CSV and SVG files (default: report-<scene>).
    #[arg(long)]
    pub out: Option<String>,
    #[command(flatten)]
    pub sizes: MeshSizes,
    /// Runs per point; the run time is their median.
    #[arg(long, default_value_t = 5, value_parser = count_up_to(MAX_REPEAT), allow_negative_numbers = true)]
    pub repeat: usize,
    /// Replace the files of an existing report in --out.
    #[arg(long)]
    pub force: bool,
}

/// What the error-time figure puts on its x axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Against {
    /// The median run time [s].
    Time,
    /// The number of elements n.
    Elements,
}

/// `beamfric figure`.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// The panel to draw.
    #[arg(value_enum)]
    pub panel: FigurePanel,
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Method (default: the scene's): the solve of `deflection`, the current run of
    /// `error-time`; for the ε panels regularized or regularized-newton (default: as the
    /// explorer, regularized, and Newton where the enumeration refuses).
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Number of elements (default: the scene's).
    #[arg(long, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub elements: Option<usize>,
    /// Regularisation parameter ε (default: the scene's), the current ε of the ε panels.
    #[arg(long, value_parser = finite_number, allow_hyphen_values = true)]
    pub epsilon: Option<f64>,
    /// The sweep's start: the smallest ε (default 1e-16) or the smallest n (default 10).
    #[arg(long, value_parser = finite_number, allow_hyphen_values = true)]
    pub from: Option<f64>,
    /// The sweep's end: the largest ε (default 1) or the largest n (default 100000).
    #[arg(long, value_parser = finite_number, allow_hyphen_values = true)]
    pub to: Option<f64>,
    /// Values swept, log-spaced, besides the scene's own (default 33 for ε, 9 for n): the
    /// explorer's panels.
    #[arg(long, value_parser = count_up_to(MAX_EPSILON_POINTS), allow_negative_numbers = true)]
    pub points: Option<usize>,
    /// Runs per mesh size of `error-time`; the run time is their median.
    #[arg(long, default_value_t = 3, value_parser = count_up_to(MAX_REPEAT), allow_negative_numbers = true)]
    pub repeat: usize,
    /// The x axis of `error-time`.
    #[arg(long, value_enum, default_value_t = Against::Time)]
    pub against: Against,
    /// The figure's title (default: the scene's title and what the figure shows); a tab, a
    /// newline or another control character in it is drawn as a blank.
    #[arg(long)]
    pub title: Option<String>,
    /// The file to write: SVG (`.svg`, 1280 × 720) or PNG (`.png`, 1920 × 1080).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: std::path::PathBuf,
    /// Replace the file if it exists.
    #[arg(long)]
    pub force: bool,
}

/// `beamfric render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1", conflicts_with = "lesson")]
    pub scene: String,
    /// Render a step of this lesson (the step's scene, settings and caption).
    #[command(flatten)]
    pub lesson: LessonArgs,
    /// Frame size in cells, WIDTHxHEIGHT.
    #[arg(long, default_value = "120x40", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u16, u16),
    /// Keys to apply first, space-separated: Up Down Left Right S-Left S-Right Enter Esc Tab
    /// BackTab Backspace Home End PgUp PgDn Space, C-x (Ctrl and a letter) and single
    /// characters (text one character at a time: Enter 3 e 4 Enter); any other word is an
    /// error.
    #[arg(long, default_value = "", allow_hyphen_values = true)]
    pub keys: String,
    /// Draw without Unicode.
    #[arg(long)]
    pub ascii: bool,
    /// Emit ANSI colours (plain text otherwise).
    #[arg(long)]
    pub color: bool,
    /// The colours of --color (bold labels in high-contrast) [default: dark, high-contrast with
    /// --projector].
    #[arg(long, value_name = "THEME")]
    pub theme: Option<Palette>,
    /// What the charts' curves are drawn with [default: braille, half-block with --projector].
    #[arg(long, value_name = "SET")]
    pub marker: Option<MarkerSet>,
    /// The projector look: half-block curves, high-contrast palette, bold labels.
    #[arg(long)]
    pub projector: bool,
    /// Show run times (the frame then depends on the clock).
    #[arg(long)]
    pub timings: bool,
    /// Let a save in the keys write, but only into DIR (without it, a save is simulated and
    /// nothing on disk changes).
    #[arg(long, value_name = "DIR")]
    pub allow_save: Option<std::path::PathBuf>,
}

/// Most mesh sizes in a sweep over n (`--points` of `sweep elements` and `report`).
pub const MAX_MESH_POINTS: usize = 200;
/// Most ε values in `sweep epsilon`.
pub const MAX_EPSILON_POINTS: usize = 1000;
/// Most runs per point (`--repeat`).
pub const MAX_REPEAT: usize = 100;

/// The value parser of a count option (`--elements`, `--points`, `--repeat`, …) whose rule is
/// a whole number from 1 to `max`: what cannot be a count at all — a negative number, a
/// fraction, an exponent, a word, a number beyond `max` too large to hold — is refused here
/// (clap quotes what was typed and names the option: "invalid value '-1' for '--elements
/// <ELEMENTS>': must be a whole number from 1 to 10000000"); any other number reaches the
/// command, whose check of the range quotes it in the same words as the scene's rules.
pub(super) fn count_up_to(
    max: usize,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync {
    move |text: &str| {
        let digits = text.trim();
        let digits = digits.strip_prefix('+').unwrap_or(digits);
        let rule = || format!("must be a whole number from 1 to {max}");
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(rule());
        }
        digits.parse().map_err(|_| rule())
    }
}

/// The value parser of a real-number option (ε, positions): a number, and a finite one
/// (`1e400` would be infinity); its sign and range are the command's rules. These options take
/// any value starting with `-` (clap's own test for a negative number misses `-1e-3`), so an
/// option in the place of the missing value is named as such.
fn finite_number(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err("must be a finite number (at most 1.8e308 in size)".into()),
        Err(_) if text.starts_with("--") => Err(format!(
            "must be a number; {text} is the next option, so the value is missing"
        )),
        Err(_) => Err("must be a number, e.g. 1e-8 or 0.5".into()),
    }
}

fn parse_size(text: &str) -> Result<(u16, u16), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}': write the size as WIDTHxHEIGHT, e.g. 120x40"))?;
    let parse = |v: &str, what: &str| -> Result<u16, String> {
        let n: u16 = v
            .trim()
            .parse()
            .map_err(|_| format!("'{text}': the {what} must be a whole number from 1 to 1000"))?;
        if (1..=1000).contains(&n) {
            Ok(n)
        } else {
            Err(format!("'{text}': the {what} must be from 1 to 1000"))
        }
    };
    Ok((parse(w, "width")?, parse(h, "height")?))
}

/// `beamfric check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// One scene file or preset name (default: every preset).
    #[arg(long)]
    pub scene: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = CheckFormat::Markdown)]
    pub format: CheckFormat,
}

/// `beamfric solve`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Scene file or preset name.
    #[arg(long, default_value = "benchmark-1")]
    pub scene: String,
    /// Method (default: the scene's).
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Number of elements (default: the scene's).
    #[arg(long, value_parser = count_up_to(MAX_ELEMENTS), allow_negative_numbers = true)]
    pub elements: Option<usize>,
    /// Regularisation parameter ε (default: the scene's).
    #[arg(long, value_parser = finite_number, allow_hyphen_values = true)]
    pub epsilon: Option<f64>,
    /// Positions [m] where u and u' are reported, comma-separated.
    #[arg(long, value_delimiter = ',', value_parser = finite_number, allow_hyphen_values = true)]
    pub at: Vec<f64>,
    /// Leave the nodal values out of the JSON output.
    #[arg(long)]
    pub no_nodes: bool,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Record the method's convergence history: under "history" in JSON, one row per
    /// iterate with --format csv.
    #[arg(long)]
    pub history: bool,
    /// Condition numbers: exact for N ≤ 200 and a cheap lower bound above (auto), Lanczos
    /// estimates at any size (full), or none (off).
    #[arg(long, value_enum, default_value_t = ConditionLevel::Auto)]
    pub condition: ConditionLevel,
}
