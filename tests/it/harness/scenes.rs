//! Scenes and problems: presets as scenes and validated problems, solve options without the
//! condition numbers, the reference values of `tests/data/`, the crowded scene whose solve
//! takes seconds.
#![allow(dead_code)]

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::plot::Look;
use beamfric::scene::{self, LoadedScene, Scene};
use beamfric::solve::{
    CondensedSolution, ConditionLevel, Method, Solution, SolveOptions, solve, solve_condensed,
};

/// A preset's scene.
pub fn preset_scene(name: &str) -> Scene {
    let preset = scene::preset(name).expect("preset exists");
    Scene::from_toml(preset.text, name).expect("preset parses")
}

/// A validated problem from a scene.
pub fn problem(scene: &Scene) -> Problem {
    scene.validate("test").expect("valid scene").0
}

/// u(x̂) of Benchmark 1 (docs/design.md section 6), 0.0057016100178890876565 m, rounded to
/// double precision.
pub const BENCHMARK_1_U: f64 = 0.005_701_610_017_889_088;
/// The moment at the obstacle of Benchmark 1, N·m.
pub const BENCHMARK_1_MOMENT: f64 = -4_798.461_538_461_538;

/// Options without condition numbers (fast) and with the reference error.
pub fn options(epsilon: f64) -> SolveOptions {
    SolveOptions {
        epsilon,
        condition: ConditionLevel::Off,
        ..SolveOptions::default()
    }
}

/// Solves a problem on `elements` elements.
pub fn solve_with(problem: &Problem, elements: usize, method: Method, epsilon: f64) -> Solution {
    let mesh = Mesh::new(problem, elements);
    solve(problem, &mesh, method, &options(epsilon))
        .unwrap_or_else(|e| panic!("{method} failed: {e}"))
}

/// `condensed` on `scene` with `elements`, which must converge.
pub fn converged_condensed(scene: &Scene, elements: usize) -> CondensedSolution {
    let problem = scene.problem().expect("a generated scene is valid");
    let mesh = Mesh::new(&problem, elements);
    let solution = solve_condensed(&problem, &mesh).expect("the scene solves");
    assert!(solution.converged, "{}: not converged", scene.title);
    solution
}

/// max |a − b| / max |b|.
pub fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    if scale == 0.0 { diff } else { diff / scale }
}

/// The reference values in `tests/data` (docs/design.md, section 6): nodal x, u,
/// slope and the (force, moment) pairs.
pub struct ReferenceValues {
    pub x: Vec<f64>,
    pub u: Vec<f64>,
    pub slope: Vec<f64>,
    pub friction: Vec<[f64; 2]>,
}

pub fn reference_values(name: &str) -> ReferenceValues {
    let path = format!("{}/tests/data/{name}-n20.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("reference file");
    let mut values = ReferenceValues {
        x: vec![],
        u: vec![],
        slope: vec![],
        friction: vec![],
    };
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("# obstacle") {
            let number = |key: &str| -> f64 {
                let start = rest.find(key).unwrap() + key.len();
                rest[start..]
                    .split_whitespace()
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap()
            };
            values.friction.push([number("force="), number("moment=")]);
        } else if !line.starts_with('#') && !line.starts_with('x') && !line.is_empty() {
            let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
            values.x.push(v[0]);
            values.u.push(v[1]);
            values.slope.push(v[2]);
        }
    }
    values
}

/// 256 obstacles on 1000 elements with thresholds spread over four decades (a fixed sequence),
/// method `dual`, only the deflection panel: its solve takes seconds (5.5 s in a release
/// build on the 2-core test machine), long work to interrupt.
pub fn crowded_scene_text() -> String {
    crowded_scene_text_of(256, 1000)
}

/// The crowded scene with `obstacles` evenly spaced obstacles on `elements` elements (the same
/// sequence of thresholds, the first ones for fewer obstacles).
pub fn crowded_scene_text_of(obstacles: usize, elements: usize) -> String {
    let mut text = format!(
        "title = \"{obstacles} obstacles\"\n[beam]\nlength = 1.0\nyoung = 2.15e11\n\
         section = {{ shape = \"rectangle\", width = 0.02, height = 0.02 }}\n\
         [load]\nf0 = 5e4\nf1 = -3e4\n",
    );
    let mut state = 7u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..obstacles {
        let x = (i + 1) as f64 / (obstacles + 1) as f64;
        let sliding = 10f64.powf(4.0 * uniform());
        let swivel = 10f64.powf(4.0 * uniform());
        text.push_str(&format!(
            "[[obstacle]]\nx = {x:?}\nsliding = {sliding:?}\nswivel = {swivel:?}\n"
        ));
    }
    text.push_str(&format!(
        "[mesh]\nelements = {elements}\n[solver]\nmethod = \"dual\"\n\
         [view]\npanels = [\"deflection\"]\n"
    ));
    text
}

/// The crowded scene's problem with `obstacles` obstacles.
pub fn crowded_problem(obstacles: usize) -> Problem {
    let text = crowded_scene_text_of(obstacles, 1000);
    problem(&Scene::from_toml(&text, "crowded").expect("the crowded scene parses"))
}

/// A preset as the explorer loads it.
pub fn loaded_preset(name: &str) -> LoadedScene {
    LoadedScene::preset(scene::preset(name).expect("preset exists")).expect("preset loads")
}

/// How the in-process explorer is drawn in tests: Unicode, no colours.
pub const PLAIN: Look = Look {
    ascii: false,
    color: false,
};

/// A plain render's options at `width` × `height`: no colours (ASCII where `ascii`), the
/// default palette and markers, no timings, no saves, no lesson.
pub fn plain_render(width: u16, height: u16, ascii: bool) -> beamfric::tui::RenderOptions {
    beamfric::tui::RenderOptions {
        width,
        height,
        look: Look {
            ascii,
            color: false,
        },
        palette: Default::default(),
        markers: Default::default(),
        timings: false,
        allow_save: None,
        lesson: None,
    }
}
