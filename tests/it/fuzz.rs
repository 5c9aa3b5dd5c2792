//! No panic from input (issue 6). The explorer's update function is driven with long random
//! key sequences — typed values good and bad, resizes down to 1×1, preset switches, saves into
//! a temporary directory — and after every key the state must be valid and the frame must
//! draw. Scene files, arbitrary and mutated, must give errors, never panics.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use beamfric::fem::Mesh;
use beamfric::plot::Look;
use beamfric::scene::{LoadedScene, PRESETS, Scene, SceneSource};
use beamfric::solve::{Method, SolveOptions, WarningCode, solve};
use beamfric::tui::input::keys::Key;
use beamfric::tui::input::pointer::Pointer;
use beamfric::tui::state::{App, Mode, Options, SavePolicy};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{draw_to_buffer, settle, settled, view};

/// What the fuzzer feeds the explorer: keys, as from the terminal, and resizes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Input {
    Key(Key),
    Resize(u16, u16),
    /// A mouse event (click, drag, release, wheel) at a cell, on screen or off it.
    Mouse(Pointer),
}

fn apply(app: &mut App, input: Input) {
    match input {
        Input::Key(key) => beamfric::tui::press(app, key),
        Input::Resize(w, h) => update(app, Msg::Resize(w, h)),
        Input::Mouse(pointer) => {
            update(app, Msg::Pointer(pointer));
            settle(app);
        }
    }
}

fn mouse() -> impl Strategy<Value = Input> {
    (0u16..170, 0u16..55, 0u8..5, any::<bool>()).prop_map(|(x, y, kind, flag)| {
        Input::Mouse(match kind {
            0 => Pointer::Click { x, y, double: flag },
            1 | 2 => Pointer::Drag { x, y },
            3 => Pointer::Release { x, y },
            _ => Pointer::Scroll { x, y, up: flag },
        })
    })
}
use proptest::prelude::*;
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::harness::seed;

/// Random sessions, and actions (one or more keys) in each.
const CASES: u32 = 220;
const ACTIONS_PER_CASE: usize = 300;
/// Above this many elements the harness brings the mesh back down, so that 10⁵ keys stay
/// quick; everything the keys do to the mesh size below it is exercised.
const ELEMENT_BUDGET: usize = 1000;

fn typed_text() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_string()),
        Just("-0".to_string()),
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("1e-320".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("99999999999999999999999".to_string()),
        Just("0.5".to_string()),
        Just("dual".to_string()),
        Just("regularized".to_string()),
        Just("".to_string()),
        "[0-9.e+-]{1,12}",
        "\\PC{0,8}",
    ]
}

fn action() -> impl Strategy<Value = Vec<Input>> {
    let key = |k: Key| Just(Input::Key(k));
    let single = prop_oneof![
        6 => key(Key::Up),
        6 => key(Key::Down),
        4 => prop::sample::select(vec![Key::Left, Key::ShiftLeft]).prop_map(Input::Key),
        4 => prop::sample::select(vec![Key::Right, Key::ShiftRight]).prop_map(Input::Key),
        1 => key(Key::Esc),
        1 => key(Key::Backspace),
        1 => prop::sample::select(vec![Key::Tab, Key::BackTab]).prop_map(Input::Key),
        1 => key(Key::Ctrl('c')),
        1 => prop::sample::select(vec!['d', 'z', 'u', 'r']).prop_map(|c| Input::Key(Key::Ctrl(c))),
        2 => (1u16..=160, 1u16..=50).prop_map(|(w, h)| Input::Resize(w, h)),
        6 => mouse(),
        2 => prop::sample::select(vec![Key::Home, Key::End, Key::PageUp, Key::PageDown])
            .prop_map(Input::Key),
        6 => prop::sample::select(vec![
            'a', 'd', 'm', 'p', 's', 'r', 'b', 't', '?', 'q', 'k', 'j', 'h', 'l', '[', ']',
            'y', 'n', 'x', '5', 'é', 'g', 'G', 'z',
        ])
        .prop_map(|c| Input::Key(Key::Char(c))),
    ]
    .prop_map(|a| vec![a]);
    // A typed value: Enter, text, Enter.
    let typed = typed_text().prop_map(|text| {
        let mut inputs = vec![Input::Key(Key::Enter)];
        inputs.extend(text.chars().map(|c| Input::Key(Key::Char(c))));
        inputs.push(Input::Key(Key::Enter));
        inputs
    });
    // A preset switch: p, some moves, Enter.
    let preset = (0usize..PRESETS.len()).prop_map(|i| {
        let mut inputs = vec![Input::Key(Key::Char('p'))];
        inputs.extend(std::iter::repeat_n(Input::Key(Key::Down), i));
        inputs.push(Input::Key(Key::Enter));
        inputs
    });
    prop_oneof![30 => single, 4 => typed, 1 => preset, 1 => Just(vec![Input::Key(Key::Enter)])]
}

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("beamfric-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn fresh(name: &str, dir: &Path) -> App {
    let preset = beamfric::scene::preset(name).unwrap();
    let mut scene = Scene::from_toml(preset.text, name).unwrap();
    scene.mesh.elements = scene.mesh.elements.min(ELEMENT_BUDGET);
    let look = Look {
        ascii: name.len().is_multiple_of(2),
        color: true,
    };
    let loaded = LoadedScene::new(scene, SceneSource::Preset(preset.name)).unwrap();
    settled(App::new(loaded, saving_within(look, dir)).unwrap())
}

/// Whatever the keys do to the file name (cursor moves, Ctrl-U, pastes), a save lands in the
/// temporary directory or nowhere: a fuzz run once saved scenes into the repository.
fn saving_within(look: Look, dir: &Path) -> Options {
    Options {
        save_policy: SavePolicy::Within(dir.to_path_buf()),
        save_directory: Some(dir.to_path_buf()),
        ..Options::new(look)
    }
}

/// Everything that must hold after any key.
fn check(app: &App) -> Result<(), TestCaseError> {
    let scene = app.scene();
    let (problem, settings) = scene
        .validate("state")
        .map_err(|e| TestCaseError::fail(format!("invalid state: {e}")))?;
    prop_assert_eq!(&problem, &app.exploration.problem);
    prop_assert_eq!(settings.elements, scene.mesh.elements);
    let l = scene.beam.length;
    let xs: Vec<f64> = scene.obstacles.iter().map(|o| o.x).collect();
    prop_assert!(xs.windows(2).all(|w| w[0] < w[1]), "unordered {:?}", xs);
    prop_assert!(xs.iter().all(|&x| x > 0.0 && x < l), "outside {:?}", xs);
    for o in &scene.obstacles {
        prop_assert!(o.sliding.is_finite() && o.sliding >= 0.0);
        prop_assert!(o.swivel.is_finite() && o.swivel >= 0.0);
    }
    prop_assert!(scene.load.f0.is_finite() && scene.load.f1().is_finite());
    prop_assert!(scene.beam.young.is_finite() && scene.beam.young > 0.0);
    prop_assert!(scene.solver.epsilon.is_finite() && scene.solver.epsilon > 0.0);
    prop_assert!(app.exploration.selected < app.exploration.rows().len());
    if let Some(Ok(solution)) = app.exploration.solution() {
        // A non-finite number is only ever there with its warning.
        prop_assert!(
            solution.is_finite()
                || solution
                    .warnings
                    .iter()
                    .any(|w| w.code == WarningCode::NonFinite)
        );
    }
    Ok(())
}

/// Applies one script of actions to a fresh explorer; returns the keys applied.
fn run_script(start: usize, script: Vec<Vec<Input>>) -> Result<usize, TestCaseError> {
    let dir = temp_dir();
    let mut app = fresh(PRESETS[start].name, &dir);
    let prefix = dir.display().to_string();
    let mut applied = 0;
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    for action in script.into_iter().flatten() {
        // Saves stay inside the temporary directory: never erase into its path.
        if let Mode::Save { prompt: buffer } = &app.mode
            && action == Input::Key(Key::Backspace)
            && buffer.text.len() <= prefix.len() + 1
        {
            continue;
        }
        apply(&mut app, action);
        applied += 1;
        if app.ending.is_some() {
            let known = match app.exploration.source {
                SceneSource::Preset(name) => name,
                SceneSource::File(_) => "benchmark-1",
            };
            app = fresh(known, &dir);
        }
        if app.scene().mesh.elements > ELEMENT_BUDGET {
            let mut scene = app.scene().clone();
            scene.mesh.elements = 200;
            let (source, look) = (app.exploration.source.clone(), app.look);
            let loaded = LoadedScene::new(scene, source).unwrap();
            app = App::new(loaded, saving_within(look, &dir)).unwrap();
        }
        check(&app)?;
        // Draw at the size the app was told, as the terminal would.
        let (w, h) = (app.size.0.max(1), app.size.1.max(1));
        if terminal.size().map(|s| (s.width, s.height)).ok() != Some((w, h)) {
            terminal
                .resize(ratatui::layout::Rect::new(0, 0, w, h))
                .unwrap();
        }
        let drawn = terminal.draw(|frame| view::draw(frame, &app));
        prop_assert!(drawn.is_ok());
        if app.look.ascii {
            let buffer = terminal.backend().buffer();
            prop_assert!(
                buffer.content.iter().all(|c| c.symbol().is_ascii()),
                "non-ASCII in ASCII mode at {}x{}",
                w,
                h
            );
        }
    }
    Ok(applied)
}

#[test]
fn random_keys_never_break_the_explorer() {
    use proptest::test_runner::{Config, TestRunner};
    let keys = AtomicUsize::new(0);
    // Two runners on the two cores, with different random streams of the run's seed.
    seed::seed();
    std::thread::scope(|scope| {
        for stream in [1, 2] {
            let keys = &keys;
            scope.spawn(move || {
                let config = Config {
                    cases: CASES / 2,
                    max_shrink_iters: 50,
                    failure_persistence: None,
                    ..Config::default()
                };
                let rng = seed::rng(stream);
                let mut runner = TestRunner::new_with_rng(config, rng);
                let strategy = (
                    0usize..PRESETS.len(),
                    prop::collection::vec(action(), ACTIONS_PER_CASE),
                );
                runner
                    .run(&strategy, |(start, script)| {
                        keys.fetch_add(run_script(start, script)?, Ordering::Relaxed);
                        Ok(())
                    })
                    .unwrap();
            });
        }
    });
    let keys = keys.load(Ordering::Relaxed);
    assert!(keys >= 100_000, "only {keys} keys were applied");
    println!("{keys} keys applied over {CASES} random sessions");
    let _ = std::fs::remove_dir_all(temp_dir());
}

proptest! {
    #![proptest_config(seed::config(ProptestConfig::default()))]

    #[test]
    fn frames_with_every_panel_ready_draw_at_any_size(
        width in 1u16..=200,
        height in 1u16..=60,
        ascii in any::<bool>(),
        diagram in 0usize..3,
    ) {
        let mut app = ready_app().clone();
        app.look.ascii = ascii;
        for _ in 0..diagram {
            beamfric::tui::press(&mut app, Key::Char('b'));
        }
        let text = beamfric::plot::buffer_to_text(&draw_to_buffer(&app, width, height), false);
        prop_assert_eq!(text.lines().count(), height as usize);
        if ascii {
            prop_assert!(text.is_ascii());
        }
    }
}

/// Benchmark 3 with every study done (computed once).
fn ready_app() -> &'static App {
    static READY: std::sync::OnceLock<App> = std::sync::OnceLock::new();
    READY.get_or_init(|| {
        let preset = beamfric::scene::preset("benchmark-3").unwrap();
        let loaded = LoadedScene::preset(preset).unwrap();
        let look = Look {
            ascii: false,
            color: false,
        };
        beamfric::tui::prepare(
            loaded,
            &[],
            beamfric::tui::RenderOptions {
                width: 120,
                height: 40,
                look,
                timings: false,
                palette: Default::default(),
                markers: Default::default(),
                allow_save: None,
                lesson: None,
            },
        )
        .unwrap()
    })
}

/// One random edit of a scene file.
fn mutate(text: &str, seed: u64, edits: usize) -> String {
    let weird = [
        "0",
        "-1",
        "1e308",
        "-1e308",
        "1e-320",
        "nan",
        "inf",
        "-inf",
        "\"x\"",
        "[]",
        "{}",
        "99999999999999999999",
        "0.0",
        "1e400",
        "true",
    ];
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut state = seed | 1;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    for _ in 0..edits {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let i = next(lines.len());
        match next(6) {
            0 => {
                lines.remove(i);
            }
            1 => {
                let copy = lines[i].clone();
                lines.insert(next(lines.len() + 1), copy);
            }
            2 => {
                // Replace a value.
                if let Some((key, _)) = lines[i].split_once(" = ") {
                    lines[i] = format!("{key} = {}", weird[next(weird.len())]);
                }
            }
            3 => {
                let j = next(lines.len());
                lines.swap(i, j);
            }
            4 => {
                let line = &mut lines[i];
                let at = next(line.len() + 1);
                if line.is_char_boundary(at) {
                    line.insert(at, ['=', '[', '"', '#', '\n', 'x', '.'][next(7)]);
                }
            }
            _ => {
                let line = &mut lines[i];
                if !line.is_empty() {
                    let at = next(line.len());
                    if line.is_char_boundary(at) && line.is_char_boundary(at + 1) {
                        line.remove(at);
                    }
                }
            }
        }
    }
    lines.join("\n")
}

proptest! {
    #![proptest_config(seed::config(ProptestConfig::with_cases(3000)))]

    #[test]
    fn arbitrary_text_is_an_error_never_a_panic(text in "\\PC{0,400}") {
        if let Ok(scene) = Scene::from_toml(&text, "fuzz.toml") {
            let _ = scene.validate("fuzz.toml");
        }
    }

    #[test]
    fn mutated_scenes_are_errors_or_solve_honestly(preset in 0usize..PRESETS.len(), seed in any::<u64>(), edits in 1usize..6) {
        let text = mutate(PRESETS[preset].text, seed, edits);
        let scene = match Scene::from_toml(&text, "mutated.toml") {
            Ok(scene) => scene,
            Err(e) => {
                // An error names the file.
                prop_assert!(e.to_string().starts_with("mutated.toml"), "{}", e);
                return Ok(());
            }
        };
        let (problem, settings) = match scene.validate("mutated.toml") {
            Ok(valid) => valid,
            Err(e) => {
                prop_assert!(e.to_string().starts_with("mutated.toml: "));
                prop_assert!(!e.field.is_empty() && !e.rule.is_empty());
                return Ok(());
            }
        };
        if settings.elements > 20_000 {
            return Ok(());
        }
        let mesh = Mesh::new(&problem, settings.elements);
        for method in [Method::Flexibility, Method::Dual, Method::RegularizedNewton] {
            if let Ok(s) = solve(&problem, &mesh, method, &SolveOptions::default()) {
                prop_assert!(
                    s.is_finite() || s.warnings.iter().any(|w| w.code == WarningCode::NonFinite),
                    "{method}: a non-finite result without its warning"
                );
            }
        }
    }
}
