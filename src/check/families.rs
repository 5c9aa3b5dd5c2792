//! Scenes with many obstacles in the four arrangements of issue 26, generated from fixed seeds
//! so that a benchmark, `beamfric check` and the reference tests see the same beams: random
//! positions and thresholds; tight clusters whose thresholds are well below the stuck forces
//! (every DOF moves); the same clusters with thresholds around the stuck forces (mixed
//! states); equally spaced obstacles with thresholds exactly at the stuck forces (ties).
//!
//! The beam and load are Benchmark 3's (l = 1 m, E J of a 1 cm round steel bar, f from 1e5 to
//! 1.5e5 N/m). "Stuck forces" are the reactions (38) gives when every DOF is held: the
//! condensed solution with thresholds too large to be reached.

use crate::fem::Mesh;
use crate::model::Problem;
use crate::scene::{ObstacleSpec, Scene, preset};
use crate::solve::solve_condensed;

/// An arrangement of many obstacles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Uniformly random positions; thresholds uniformly random between 0 and twice the stuck
    /// force of each DOF.
    Random,
    /// Three clusters, at 0.25, 0.5 and 0.75 l, each ±0.02 l wide; thresholds 5–50 % of the
    /// stuck forces, so every DOF moves.
    Clustered,
    /// The same clusters with thresholds 50–150 % of the stuck forces: mixed states.
    ClusteredMixed,
    /// Equally spaced obstacles with thresholds equal to the stuck forces (rounded to f64):
    /// every DOF at its threshold, about half of them by a motion of rounding size.
    Ties,
}

impl Family {
    /// Every family, in the order of issue 26's table.
    pub const ALL: [Family; 4] = [
        Family::Random,
        Family::Clustered,
        Family::ClusteredMixed,
        Family::Ties,
    ];

    /// The family's name in tables and case names.
    pub fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::Clustered => "clustered",
            Family::ClusteredMixed => "clustered-mixed",
            Family::Ties => "ties",
        }
    }
}

/// A fixed sequence of uniform numbers in [0, 1) (SplitMix64).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Benchmark 3's beam and load, without its description, on a mesh of `elements`.
fn base_scene(elements: usize) -> Scene {
    let preset = preset("benchmark-3").expect("the benchmark-3 preset exists");
    let mut scene = Scene::from_toml(preset.text, preset.name).expect("the preset is valid");
    scene.description = String::new();
    scene.mesh.elements = elements;
    scene
}

/// Obstacle positions [m] of `family` (sorted, distinct) for `k` obstacles.
fn positions(family: Family, k: usize, random: &mut Uniform, length: f64) -> Vec<f64> {
    let mut xs: Vec<f64> = match family {
        Family::Ties => (1..=k)
            .map(|j| j as f64 / (k + 1) as f64 * length)
            .collect(),
        Family::Random => (0..k)
            .map(|_| (0.01 + 0.98 * random.next()) * length)
            .collect(),
        Family::Clustered | Family::ClusteredMixed => (0..k)
            .map(|j| {
                let centre = [0.25, 0.5, 0.75][j % 3];
                (centre + 0.04 * (random.next() - 0.5)) * length
            })
            .collect(),
    };
    xs.sort_by(f64::total_cmp);
    // Random draws that land within 1e-6·l of each other are spread to that distance (the
    // scene's own minimum separation is far below it).
    for i in 1..xs.len() {
        xs[i] = xs[i].max(xs[i - 1] + 1e-6 * length);
    }
    xs
}

/// (|λ1|, |λ2|) per obstacle with every DOF held (thresholds out of reach), on `elements`.
pub fn stuck_forces(scene: &Scene, elements: usize) -> Vec<[f64; 2]> {
    let mut held = scene.clone();
    for o in &mut held.obstacles {
        o.sliding = 1e300;
        o.swivel = 1e300;
    }
    let problem = held.problem().expect("a generated scene is valid");
    let mesh = Mesh::new(&problem, elements);
    let solution = solve_condensed(&problem, &mesh).expect("the held beam has a solution");
    solution
        .friction
        .iter()
        .map(|[force, moment]| [force.abs(), moment.abs()])
        .collect()
}

/// The scene of `family` with `k` obstacles from `seed`, its thresholds set from the stuck
/// forces on a mesh of `elements`.
pub fn family_scene(family: Family, k: usize, seed: u64, elements: usize) -> Scene {
    let mut scene = generated_scene((family, family), k, seed, elements);
    scene.title = format!("{} k={k} seed={seed}", family.name());
    scene
}

/// The obstacles of `positions`' family with the thresholds of `thresholds`' (fractions of
/// the stuck forces on a mesh of `elements`), from `seed`.
fn generated_scene(
    (positions_of, thresholds_of): (Family, Family),
    k: usize,
    seed: u64,
    elements: usize,
) -> Scene {
    let mut scene = base_scene(elements);
    let mut random = Uniform(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ k as u64);
    let xs = positions(positions_of, k, &mut random, scene.beam.length);
    let fractions = match thresholds_of {
        Family::Random => (0.0, 2.0),
        Family::Clustered => (0.05, 0.5),
        Family::ClusteredMixed => (0.5, 1.5),
        Family::Ties => (1.0, 1.0),
    };
    place_with_stuck_thresholds(&mut scene, xs, fractions, &mut random, elements);
    scene
}

/// `scene`'s obstacles at `xs` [m], each threshold a fraction in [low, high) of its stuck
/// force on a mesh of `elements`, drawn from `random` (sliding, then swivel, per obstacle).
fn place_with_stuck_thresholds(
    scene: &mut Scene,
    xs: Vec<f64>,
    (low, high): (f64, f64),
    random: &mut Uniform,
    elements: usize,
) {
    scene.obstacles = xs
        .into_iter()
        .map(|x| ObstacleSpec {
            x,
            sliding: 0.0,
            swivel: 0.0,
        })
        .collect();
    let stuck = stuck_forces(scene, elements);
    for (o, [force, moment]) in scene.obstacles.iter_mut().zip(stuck) {
        let mut fraction = || low + (high - low) * random.next();
        o.sliding = force * fraction();
        o.swivel = moment * fraction();
    }
}

/// One notch of the explorer's fine threshold step (×10^0.1).
pub const NOTCH: f64 = 1.258_925_411_794_167_2;

/// The ties scene (seed 14) with the first obstacle's sliding threshold `notches` notches
/// down: every other force at its threshold while that obstacle slides, an arrangement slow
/// for the pattern search (docs/many-obstacles/guess-and-warm-starts.md, "An arrangement still
/// slow").
pub fn lowered_ties_scene(k: usize, notches: i32, elements: usize) -> Scene {
    lowered_ties_scene_at(k, (0, false), notches, elements)
}

/// [`lowered_ties_scene`] with another threshold lowered: obstacle `obstacle`'s sliding
/// threshold, or its swivel threshold where `swivel` is true.
pub fn lowered_ties_scene_at(
    k: usize,
    (obstacle, swivel): (usize, bool),
    notches: i32,
    elements: usize,
) -> Scene {
    let mut scene = family_scene(Family::Ties, k, 14, elements);
    let lowered = &mut scene.obstacles[obstacle];
    if swivel {
        lowered.swivel /= NOTCH.powi(notches);
    } else {
        lowered.sliding /= NOTCH.powi(notches);
    }
    scene
}

/// The clustered family's obstacles (three clusters ±0.02 l wide, from `seed`) with every
/// threshold equal to its stuck force, and the swivel threshold of obstacle
/// (7919 · seed) mod k lowered by `notches` notches: the arrangement of issue 26's slowest
/// reports (clusters at exact ties), on which the monotone search took up to thousands of
/// solves (docs/many-obstacles/monotone-search.md, "Clusters at ties with one threshold lowered").
pub fn lowered_clustered_ties_scene(k: usize, seed: u64, notches: i32, elements: usize) -> Scene {
    let mut scene = generated_scene((Family::Clustered, Family::Ties), k, seed, elements);
    scene.title = format!("clustered ties k={k} seed={seed} notches={notches}");
    let lowered = (7919 * seed as usize) % k;
    scene.obstacles[lowered].swivel /= NOTCH.powi(notches);
    scene
}

/// Half of `k` obstacles evenly in a stretch 1e-4·l wide (spacing 2e-4·l / k, jittered by a
/// tenth of it) starting at a random place between 0.2 and 0.8 l, the other half at random
/// positions (any two at least 1e-8·l apart, within the scene's own 1e-9 m); thresholds
/// 1–1000 N and 1e-4–1 N·m, log-uniform. Obstacles 1e-7·l apart move together
/// to within what an f64 solve resolves of their motion, and the interior-point guess cannot
/// tell which of them is stuck: found in the hostile pass of stop 48 (up to 1191 pattern
/// solves at k = 3000), the worst arrangement of issue 26 measured since
/// (docs/many-obstacles/close-obstacles-and-near-ties.md, "Still slow: obstacles nearly on top of
/// each other" and "The guess with its unclear DOFs held, tried first").
pub fn dense_stretch_scene(k: usize, seed: u64, elements: usize) -> Scene {
    let mut scene = base_scene(elements);
    scene.title = format!("dense stretch k={k} seed={seed}");
    let mut random = Uniform(seed.wrapping_mul(0x9E6C_63D0_676A_9A99) ^ k as u64);
    let length = scene.beam.length;
    let (dense, start) = (k / 2, 0.2 + 0.6 * random.next());
    let spacing = 1e-4 / dense.max(1) as f64;
    let mut xs: Vec<f64> = (0..k)
        .map(|j| {
            let x = if j < dense {
                start + spacing * (j as f64 + 0.1 * (random.next() - 0.5))
            } else {
                0.01 + 0.98 * random.next()
            };
            x * length
        })
        .collect();
    xs.sort_by(f64::total_cmp);
    for i in 1..xs.len() {
        xs[i] = xs[i].max(xs[i - 1] + 1e-8 * length);
    }
    scene.obstacles = xs
        .into_iter()
        .map(|x| ObstacleSpec {
            x,
            sliding: 10f64.powf(3.0 * random.next()),
            swivel: 10f64.powf(-4.0 + 4.0 * random.next()),
        })
        .collect();
    scene
}

/// Obstacles in pairs: `k / 2` positions of the random family (from `seed`), each with a
/// second obstacle 1e-9·l to 1e-5·l after it (log-uniform), any two at least 1e-9·l apart;
/// thresholds 0–2 × the stuck forces on a mesh of `elements`. Two obstacles that close move
/// together to within what an f64 solve resolves, and which of them is stuck is decided by
/// motions of 1e-27 of the common one: found in the hostile pass of stop 48 (194–579 pattern
/// solves), settled from the guess since stop 52
/// (docs/many-obstacles/close-obstacles-and-near-ties.md, "The monotone search from a close
/// guess").
pub fn pairs_scene(k: usize, seed: u64, elements: usize) -> Scene {
    let mut scene = family_scene(Family::Random, k / 2, seed, elements);
    scene.title = format!("pairs k={k} seed={seed}");
    let mut random = Uniform(seed.wrapping_mul(0xD1B5_4A32_D192_ED03) ^ k as u64);
    let length = scene.beam.length;
    let mut xs: Vec<f64> = scene
        .obstacles
        .iter()
        .flat_map(|o| [o.x, o.x + 10f64.powf(-9.0 + 4.0 * random.next()) * length])
        .collect();
    xs.sort_by(f64::total_cmp);
    for i in 1..xs.len() {
        xs[i] = xs[i].max(xs[i - 1] + 1e-9 * length);
    }
    place_with_stuck_thresholds(&mut scene, xs, (0.0, 2.0), &mut random, elements);
    scene
}

/// The random family's obstacles (from `seed`) with every other obstacle's thresholds equal
/// to its stuck forces on a mesh of `elements` (the first, the third, …) and the others' 0–2 ×
/// them. The others that move load the tied ones past their thresholds, and the
/// interior-point guess stalled on bounds 1e-18 wide while the answer moved away from them:
/// found in the hostile pass of stop 53 (up to 1277 pattern solves at k = 3000, 2.2 s),
/// settled by a second guess with those ties widened since
/// (docs/many-obstacles/close-obstacles-and-near-ties.md, "Near ties that the answer moves away
/// from").
pub fn half_ties_scene(k: usize, seed: u64, elements: usize) -> Scene {
    partial_ties_scene((k, seed, elements), "half ties", |obstacle, _| {
        obstacle % 2 == 0
    })
}

/// [`half_ties_scene`] with every sliding threshold at its stuck force instead, the swivel
/// thresholds 0–2 × the stuck moments: the slowest arrangement of stop 53's hostile pass
/// (up to 1310 pattern solves at k = 3000 before the second guess).
pub fn sliding_ties_scene(k: usize, seed: u64, elements: usize) -> Scene {
    partial_ties_scene((k, seed, elements), "sliding ties", |_, kind| kind == 0)
}

/// The random family's obstacles (`k`, from `seed`) with the thresholds `tied(obstacle, kind)`
/// (kind 0 sliding, 1 swivel) equal to the stuck forces on a mesh of `elements`, the others
/// 0–2 × them (drawn in order: sliding, then swivel, per obstacle).
fn partial_ties_scene(
    (k, seed, elements): (usize, u64, usize),
    name: &str,
    tied: impl Fn(usize, usize) -> bool,
) -> Scene {
    let mut scene = family_scene(Family::Random, k, seed, elements);
    scene.title = format!("{name} k={k} seed={seed}");
    let mut random = Uniform(seed.wrapping_mul(0x8CB9_2BA7_2F3D_8DD7) ^ k as u64);
    let stuck = stuck_forces(&scene, elements);
    for (i, (o, [force, moment])) in scene.obstacles.iter_mut().zip(stuck).enumerate() {
        let mut threshold = |kind: usize, stuck: f64| {
            if tied(i, kind) {
                stuck
            } else {
                stuck * 2.0 * random.next()
            }
        };
        o.sliding = threshold(0, force);
        o.swivel = threshold(1, moment);
    }
    scene
}

/// Tight clusters at ties: `k / 10` clusters of ten obstacles 1e-7·l apart (the last
/// `k % 10` obstacles in one more), centred at random in [0.05, 0.95]·l (from `seed`), every
/// threshold equal to its stuck force on a mesh of `elements`. Inside a cluster the beam is
/// nearly a mechanism, the inner obstacles' swivel thresholds 1e-19–1e-11 of the first's; the
/// interior-point iteration can stall there, and its second guess, with the ties widened,
/// was then often the worse one: found in the hostile pass of stop 54 (up to 1545 pattern
/// solves, 9.5 s at k = 3000). Weighing both guesses settles most of those since, not all
/// (docs/many-obstacles/step-costs.md, "Two guesses where the first stalled").
pub fn tight_clusters_ties_scene(k: usize, seed: u64, elements: usize) -> Scene {
    let mut scene = base_scene(elements);
    scene.title = format!("tight clusters at ties k={k} seed={seed}");
    let mut random = Uniform(seed.wrapping_mul(0x94D0_49BB_1331_11EB) ^ k as u64);
    let length = scene.beam.length;
    let mut xs = Vec::with_capacity(k);
    while xs.len() < k {
        let centre = 0.05 + 0.9 * random.next();
        let members = (k - xs.len()).min(10);
        xs.extend((0..members).map(|j| (centre + j as f64 * 1e-7) * length));
    }
    xs.sort_by(f64::total_cmp);
    for i in 1..xs.len() {
        xs[i] = xs[i].max(xs[i - 1] + 1e-8 * length);
    }
    place_with_stuck_thresholds(&mut scene, xs, (1.0, 1.0), &mut random, elements);
    scene
}

/// [`family_scene`] validated, with its mesh.
pub fn family_problem(family: Family, k: usize, seed: u64, elements: usize) -> (Problem, Mesh) {
    let scene = family_scene(family, k, seed, elements);
    let problem = scene.problem().expect("a generated scene is valid");
    let mesh = Mesh::new(&problem, elements);
    (problem, mesh)
}
