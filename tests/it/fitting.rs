//! Whole items or nothing (issue 25): at every width from 60 to 200 columns, on every preset
//! with every method, the title line and the status lines hold only whole items and words of
//! what they would say with room to spare — dropped by importance or ended with `…` at a word,
//! never cut in a word or a number.

use beamfric::model::Method;
use beamfric::plot::{Look, buffer_to_text};
use beamfric::scene::{LoadedScene, PRESETS, SceneSource};
use beamfric::tui::state::{App, Options};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::view::warnings::{headline, ordered};
use beamfric::tui::{draw_to_buffer, settled};

use crate::harness::scenes::preset_scene;

/// The title line and the three status lines of `app` drawn `width` columns wide.
fn lines(app: &App, width: u16) -> Vec<String> {
    let text = buffer_to_text(&draw_to_buffer(app, width, 24), false);
    let rows: Vec<String> = text.lines().map(|l| l.trim_end().to_string()).collect();
    vec![
        rows[0].clone(),
        rows[20].clone(),
        rows[21].clone(),
        rows[22].clone(),
    ]
}

/// Every word of `narrow` is a word of `wide` (the last may end in `…`, then it is the start
/// of one, or stands alone).
fn whole_words(narrow: &str, wide: &str) -> Result<(), String> {
    let words: Vec<&str> = wide.split_whitespace().collect();
    for word in narrow.split_whitespace() {
        let whole = match word.strip_suffix('…') {
            Some("") => true,
            Some(start) => words.iter().any(|w| *w == start || w.starts_with(start)),
            None => words.contains(&word),
        };
        if !whole {
            return Err(format!("{word:?} is cut: {narrow:?}\nwith room: {wide:?}"));
        }
    }
    Ok(())
}

#[test]
fn title_and_status_hold_whole_words_at_every_width_on_every_preset_and_method() {
    let methods = [
        Method::Regularized,
        Method::RegularizedNewton,
        Method::DualInverse,
        Method::Dual,
        Method::Flexibility,
        Method::ClosedForm,
        Method::Condensed,
    ];
    let mut checked = 0;
    for preset in PRESETS {
        for method in methods {
            let mut scene = preset_scene(preset.name);
            scene.solver.method = method;
            // Every method quick enough: the lines are what is tested, not the solve.
            let most = if method == Method::DualInverse {
                100
            } else {
                2000
            };
            scene.mesh.elements = scene.mesh.elements.min(most);
            let loaded = LoadedScene::new(scene, SceneSource::Preset(preset.name)).unwrap();
            let options = Options::new(Look {
                ascii: false,
                color: false,
            });
            let mut app = settled(App::new(loaded, options).unwrap());
            update(&mut app, Msg::Resize(400, 24));
            let wide = lines(&app, 400);
            // Where the most serious warning does not fit, its short form stands in.
            let headlines: String = match app.exploration.solution() {
                Some(Ok(solution)) => ordered(solution)
                    .iter()
                    .map(|w| headline(w.code, solution.kkt_residual))
                    .collect::<Vec<_>>()
                    .join(" "),
                _ => String::new(),
            };
            for width in 60..=200 {
                update(&mut app, Msg::Resize(width, 24));
                let narrow = lines(&app, width);
                for (row, (n, w)) in narrow.iter().zip(&wide).enumerate() {
                    // The warning line wraps onto the next at a narrow width: its words come
                    // from the two rows with room.
                    let with_room = if row >= 2 {
                        format!("{} {} {headlines}", wide[2], wide[3])
                    } else {
                        w.clone()
                    };
                    if let Err(e) = whole_words(n, &with_room) {
                        panic!(
                            "{} with {method:?} at {width} columns, row {row}: {e}",
                            preset.name
                        );
                    }
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, PRESETS.len() * 7 * 141);
}
