//! Hard scenes for the reference harness (issue 10): a seeded generator, a proptest strategy
//! over its seeds, and the regression scenes of `tests/scenes/hard/*.toml`.
//!
//! A generated scene mixes, at random: beams of 1 mm to 1 km; 0–3 segments 1e-6 to 1e10 times
//! softer/stiffer than the beam, their ends on obstacles, 1.5e-9·l past them or anywhere;
//! 1–40 obstacles, with gaps between them and to the supports from 1.001e-9·l up; thresholds
//! 0, natural (a fraction of the force the point would carry if stuck), tiny, huge (up to
//! 1e20), and exact switching values (the force of a reference solve with that threshold
//! lifted, rounded to f64, and its neighbours one ulp away); loads of either sign, changing
//! sign along the beam, then scaled by a power of two to 1e-300 … 1e300 (the scaling is exact,
//! so the scene stays the same problem up to units); 1 to 200 elements. Every scene passes
//! `Scene::validate`; the rules it must meet are those of `src/scene/mod.rs`.

use beamfric::model::Problem;
use beamfric::scene::{
    BeamSpec, LoadSpec, MeshSpec, ObstacleSpec, Scene, Section, SegmentSpec, SolverSpec, ViewSpec,
};
use proptest::prelude::*;

use super::mp::to_f64;
use super::solver::solve_reference;

/// SplitMix64: small, seedable, good enough to spread scenes.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5DEE_CE66_D1CE_4E5B)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// 10^U(a, b).
    pub fn decades(&mut self, a: f64, b: f64) -> f64 {
        10f64.powf(self.uniform(a, b))
    }

    /// Uniform integer in [a, b].
    pub fn range(&mut self, a: usize, b: usize) -> usize {
        a + (self.next_u64() % (b - a + 1) as u64) as usize
    }

    /// True with probability p.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.range(0, items.len() - 1)]
    }
}

/// A scene with the physics only (no view, default solver settings).
pub fn scene_from_parts(
    length: f64,
    young: f64,
    section: Section,
    segments: Vec<SegmentSpec>,
    load: (f64, f64),
    obstacles: Vec<ObstacleSpec>,
    elements: usize,
) -> Scene {
    Scene {
        title: String::new(),
        description: String::new(),
        beam: BeamSpec {
            length,
            young,
            section,
            segments,
        },
        load: LoadSpec {
            f0: load.0,
            f1: Some(load.1),
        },
        obstacles,
        mesh: MeshSpec { elements },
        solver: SolverSpec::default(),
        view: ViewSpec::default(),
    }
}

/// The validated problem and the number of elements of a scene.
pub fn problem_of(scene: &Scene) -> (Problem, usize) {
    let (problem, settings) = scene
        .validate("generated scene")
        .unwrap_or_else(|e| panic!("invalid scene: {e}\n{}", scene.to_toml()));
    (problem, settings.elements)
}

/// The hard scene of `seed`, valid and reproducible; `title` names the seed.
pub fn hard_scene(seed: u64) -> Scene {
    for attempt in 0..1000u64 {
        let mut rng = Rng::new(seed.wrapping_mul(1000).wrapping_add(attempt));
        if let Some(mut scene) = try_scene(&mut rng) {
            scene.title = format!("hard scene {seed}");
            return scene;
        }
    }
    panic!("no valid scene for seed {seed}")
}

/// A proptest strategy of hard scenes (over the generator's seed).
pub fn hard_scenes() -> impl Strategy<Value = Scene> {
    any::<u64>().prop_map(hard_scene)
}

fn valid(scene: &Scene) -> bool {
    scene.validate("generated scene").is_ok()
}

/// Obstacle positions: k + 1 gaps that add up to l, some of them as small as the rules allow.
fn positions(rng: &mut Rng, k: usize, length: f64) -> Vec<f64> {
    let gap = 1e-9 * length;
    let tiny_factors = [1.001, 1.001, 1.5, 2.0, 10.0, 1e3];
    let tiny_share = rng.pick(&[0.0, 0.1, 0.3, 0.6]);
    let mut tiny: Vec<Option<f64>> = (0..=k)
        .map(|_| {
            rng.chance(tiny_share)
                .then(|| gap * rng.pick(&tiny_factors))
        })
        .collect();
    // One ordinary gap at least, so the gaps can fill the length.
    let ordinary = rng.range(0, k);
    tiny[ordinary] = None;
    let weights: Vec<f64> = tiny
        .iter()
        .map(|t| {
            if t.is_none() {
                rng.uniform(0.05, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    let fixed: f64 = tiny.iter().flatten().sum();
    let total_weight: f64 = weights.iter().sum();
    let mut x = 0.0;
    let mut points = Vec::with_capacity(k);
    for i in 0..k {
        x += tiny[i].unwrap_or((length - fixed) * weights[i] / total_weight);
        points.push(x);
    }
    // Exact neighbours of the supports now and then.
    if k >= 1 && rng.chance(0.1) {
        points[k - 1] = length - gap * rng.pick(&tiny_factors);
    }
    points
}

/// Segments with their ends on obstacles, 1.5e-9·l past them, or anywhere.
fn segments(rng: &mut Rng, length: f64, young: f64, points: &[f64]) -> Vec<SegmentSpec> {
    let count = if rng.chance(0.5) { 0 } else { rng.range(1, 3) };
    let gap = 1e-9 * length;
    let mut ends: Vec<f64> = (0..2 * count)
        .map(|_| {
            let near = |rng: &mut Rng| points[rng.range(0, points.len() - 1)];
            match rng.range(0, 5) {
                0 => near(rng),
                1 => near(rng) + 1.5 * gap,
                2 => near(rng) - 1.5 * gap,
                3 => rng.pick(&[0.0, length]),
                _ => rng.uniform(0.0, length),
            }
        })
        .map(|x| x.clamp(0.0, length))
        .collect();
    ends.sort_by(f64::total_cmp);
    ends.dedup();
    ends.chunks_exact(2)
        .filter(|pair| pair[1] > pair[0])
        .map(|pair| SegmentSpec {
            from: pair[0],
            to: pair[1],
            young: Some(young * rng.decades(-6.0, 10.0)),
            section: None,
        })
        .collect()
}

fn try_scene(rng: &mut Rng) -> Option<Scene> {
    let length = if rng.chance(0.5) {
        1.0
    } else {
        rng.decades(-3.0, 3.0)
    };
    let young = rng.decades(5.0, 12.0);
    let section = match rng.range(0, 2) {
        0 => Section::Rectangle {
            width: length * rng.decades(-3.0, -1.0),
            height: length * rng.decades(-3.0, -1.0),
        },
        1 => Section::Circle {
            radius: length * rng.decades(-3.0, -1.0),
        },
        _ => Section::Custom {
            inertia: length.powi(4) * rng.decades(-14.0, -6.0),
        },
    };
    let k = if rng.chance(0.5) {
        rng.range(1, 8)
    } else {
        rng.range(1, 40)
    };
    let points = positions(rng, k, length);
    let segments = segments(rng, length, young, &points);
    let f0 = rng.pick(&[1.0, -1.0]) * rng.decades(-2.0, 2.0);
    let f1 = match rng.range(0, 4) {
        0 => f0,
        1 => -f0,
        2 => 0.0,
        _ => rng.pick(&[1.0, -1.0]) * rng.decades(-2.0, 2.0),
    };
    let f0 = if f1 != 0.0 && rng.chance(0.05) {
        0.0
    } else {
        f0
    };
    let elements = match rng.range(0, 2) {
        0 => rng.range(1, 5),
        1 => rng.range(1, 60),
        _ => rng.range(60, 200),
    };
    // Thresholds, first all lifted to find the forces a stuck point carries.
    let lifted = 1e200;
    let mut obstacles: Vec<ObstacleSpec> = points
        .iter()
        .map(|&x| ObstacleSpec {
            x,
            sliding: lifted,
            swivel: lifted,
        })
        .collect();
    let mut scene = scene_from_parts(
        length,
        young,
        section,
        segments,
        (f0, f1),
        obstacles.clone(),
        elements,
    );
    if !valid(&scene) {
        return None;
    }
    let stuck = {
        let (problem, elements) = problem_of(&scene);
        solve_reference(&problem, elements).lambda_f64()
    };
    let load_scale = f0.abs().max(f1.abs());
    let mut switching = Vec::new();
    for (i, o) in obstacles.iter_mut().enumerate() {
        for kind in 0..2 {
            let natural = stuck[i][kind]
                .abs()
                .max(load_scale * length.powi(kind as i32 + 1) * 1e-3);
            let g = match rng.range(0, 9) {
                0 => 0.0,
                1 => natural * rng.decades(-12.0, -3.0),
                2 => natural * rng.decades(3.0, 20.0),
                3 => 1e20,
                4 => {
                    switching.push((i, kind));
                    lifted
                }
                _ => natural * rng.uniform(0.0, 1.5),
            };
            if kind == 0 {
                o.sliding = g;
            } else {
                o.swivel = g;
            }
        }
    }
    // Exact switching values, one DOF at a time, the others as chosen.
    for &(i, kind) in switching.iter().take(2) {
        scene.obstacles = obstacles.clone();
        let (problem, elements) = problem_of(&scene);
        let force = solve_reference(&problem, elements).lambda_f64()[i][kind].abs();
        let g = match rng.range(0, 3) {
            0 => force.next_down().max(0.0),
            1 => force.next_up(),
            _ => force,
        };
        if kind == 0 {
            obstacles[i].sliding = g;
        } else {
            obstacles[i].swivel = g;
        }
    }
    for &(i, kind) in switching.iter().skip(2) {
        let g = stuck[i][kind].abs() * 0.5;
        if kind == 0 {
            obstacles[i].sliding = g;
        } else {
            obstacles[i].swivel = g;
        }
    }
    scene.obstacles = obstacles;
    scale_by_power_of_two(rng, &mut scene);
    valid(&scene).then_some(scene)
}

/// Scales the load and the thresholds by one power of two (exact in f64 while nothing
/// overflows or goes subnormal, and the reference solution scales by the same factor), so
/// that |f| lands anywhere in 1e-300 … 1e300 with every threshold still a normal number.
fn scale_by_power_of_two(rng: &mut Rng, scene: &mut Scene) {
    if rng.chance(0.4) {
        return;
    }
    let Ok(problem) = scene.problem() else {
        return;
    };
    let l = problem.length;
    let (soft, stiff) = problem
        .stiffness
        .iter()
        .fold((f64::INFINITY, 0f64), |(a, b), p| {
            (a.min(p.bending_stiffness), b.max(p.bending_stiffness))
        });
    let f = scene.load.f0.abs().max(scene.load.f1().abs());
    // Rough sizes of u and u' (they scale with the load too).
    let mut values = vec![
        scene.load.f0,
        scene.load.f1(),
        f * l.powi(4) / soft,
        f * l.powi(4) / stiff,
        f * l.powi(3) / soft,
        f * l.powi(3) / stiff,
    ];
    for o in &scene.obstacles {
        values.push(o.sliding);
        values.push(o.swivel);
    }
    let nonzero: Vec<f64> = values.into_iter().filter(|v| *v != 0.0).collect();
    if nonzero.is_empty() {
        return;
    }
    let largest = nonzero.iter().fold(0f64, |m, v| m.max(v.abs())).log2();
    let smallest = nonzero
        .iter()
        .fold(f64::INFINITY, |m, v| m.min(v.abs()))
        .log2();
    let load = scene.load.f0.abs().max(scene.load.f1().abs()).log2();
    // Room to stay within 2^±900 (answers u ~ f l⁴/EJ need room of their own).
    let (lo, hi) = ((-900.0 - smallest).ceil(), (900.0 - largest).floor());
    if lo > hi {
        return;
    }
    let target = rng.uniform(-300.0, 300.0) * 10f64.log2() - load;
    let shift = target.clamp(lo, hi).round() as i32;
    let factor = |v: f64| v * 2f64.powi(shift);
    scene.load.f0 = factor(scene.load.f0);
    scene.load.f1 = scene.load.f1.map(factor);
    for o in &mut scene.obstacles {
        o.sliding = factor(o.sliding);
        o.swivel = factor(o.swivel);
    }
}

/// The regression scenes of `tests/scenes/hard/`, by file name, sorted.
pub fn regression_scenes() -> Vec<(String, Scene)> {
    let dir = format!("{}/tests/scenes/hard", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&path).expect("readable scene");
            let scene = Scene::from_toml(&text, &name).unwrap_or_else(|e| panic!("{e}"));
            (name, scene)
        })
        .collect()
}

/// Largest |u|, |u'|, |λ| of the reference, to see that a scaled scene stays representable.
pub fn magnitudes(scene: &Scene) -> [f64; 3] {
    let (problem, elements) = problem_of(scene);
    let r = solve_reference(&problem, elements);
    let max = |v: &[super::mp::F]| v.iter().map(|x| to_f64(x).abs()).fold(0f64, f64::max);
    let lambda = r
        .lambda
        .iter()
        .flatten()
        .map(|x| to_f64(x).abs())
        .fold(0f64, f64::max);
    [max(&r.u), max(&r.slope), lambda]
}
