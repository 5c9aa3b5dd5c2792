//! Measurement and diagnosis tools on the independent multi-precision reference of
//! `tests/it/reference/` (issue 10): they run for minutes and print what they find, so they are
//! not tests. `harness = false`; the tool is the first argument that is not an option:
//!
//! ```text
//! cargo bench --bench reference -- measure    # every method on the hard scenes
//! cargo bench --bench reference -- silent     # the regularised methods' silent failures
//! cargo bench --bench reference -- scan       # the stable method on many generated scenes
//! cargo bench --bench reference -- write      # keep seeds as regression scenes
//! cargo bench --bench reference -- diagnose   # one generated scene in detail
//! cargo bench --bench reference -- families   # the stable method on the issue-26 families
//! ```
//!
//! Each reads its settings from the environment, as described at its function:
//! `BEAMFRIC_HARD_SCENES`, `BEAMFRIC_HARD_SEED`, `BEAMFRIC_WIDE_SEEDS`, `BEAMFRIC_EPSILON`,
//! `BEAMFRIC_MAX_CASES`, `BEAMFRIC_WRITE_SEEDS`, `BEAMFRIC_DIAGNOSE_SEED`. For example
//! `BEAMFRIC_WIDE_SEEDS=1 BEAMFRIC_HARD_SCENES=10000 BEAMFRIC_HARD_SEED=77 cargo bench --bench
//! reference -- scan`. Without a tool (as in a plain `cargo bench`) it prints its usage and
//! does nothing; an unknown tool is an error.

#[path = "../tests/it/reference/mod.rs"]
mod reference;

use beamfric::fem::Mesh;
use beamfric::scene::Scene;
use beamfric::solve::{Method, SolveOptions};

use reference::*;

const USAGE: &str = "usage: cargo bench --bench reference -- measure|silent|scan|write|diagnose \
                     (settings from BEAMFRIC_* environment variables, see benches/reference.rs)";

fn main() {
    // `cargo bench` passes `--bench`; the tool is the first argument that is not an option.
    let tool = std::env::args().skip(1).find(|arg| !arg.starts_with('-'));
    match tool.as_deref() {
        Some("measure") => measure_every_method_on_hard_scenes(),
        Some("silent") => diagnose_silent_regularized_failures(),
        Some("scan") => scan_stable_method_on_hard_scenes(),
        Some("write") => write_hard_scenes_as_regressions(),
        Some("diagnose") => diagnose_one_hard_scene(),
        Some("families") => scan_stable_method_on_families(),
        None => eprintln!("{USAGE}"),
        Some(other) => {
            eprintln!("unknown tool {other:?}; {USAGE}");
            std::process::exit(2);
        }
    }
}

/// `measure`: every method on the regression scenes and `BEAMFRIC_HARD_SCENES` (default 2000)
/// generated scenes from seed `BEAMFRIC_HARD_SEED` (default 0) on; the exact methods against
/// the exact reference, the regularised ones at `BEAMFRIC_EPSILON` (default 1e-10) against the
/// ε-reference, `BEAMFRIC_MAX_CASES` (default 6561) the enumeration's limit. Prints a table of
/// agreement, warnings and silent failures per method, the worst scenes, and writes the two
/// worst of each method as TOML to `target/tmp/hard-scenes/`. Minutes.
fn measure_every_method_on_hard_scenes() {
    let count = env_number("BEAMFRIC_HARD_SCENES", 2000);
    let first_seed = env_number("BEAMFRIC_HARD_SEED", 0);
    let tolerance = 1e-10;
    let options = SolveOptions {
        epsilon: std::env::var("BEAMFRIC_EPSILON")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(1e-10),
        max_cases: env_number("BEAMFRIC_MAX_CASES", 6561),
        ..SolveOptions::default()
    };
    let mut scenes: Vec<(String, Scene)> = regression_scenes();
    scenes.extend((first_seed..first_seed + count).map(|s| (format!("seed {s}"), hard_scene(s))));
    let mut tallies: Vec<(Method, Tally)> =
        Method::ALL.iter().map(|&m| (m, Tally::default())).collect();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("hard-scenes");
    std::fs::create_dir_all(&dir).unwrap();
    let mut ties = 0;
    let mut uncertified = 0;
    let (mut epsilon_ties, mut epsilon_uncertified, mut epsilon_solves) = (0, 0, 0);
    for (name, scene) in &scenes {
        let (p, n) = problem_of(scene);
        let mesh = Mesh::new(&p, n);
        let r = solve_reference_with(&p, &mesh, reference::mp::DEFAULT_PRECISION)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        if !r.certificate.verified {
            uncertified += 1;
            println!("reference not certified on {name}: {:?}", r.certificate);
            continue;
        }
        ties += usize::from(r.has_tie());
        // The regularised methods against the ε-problem they solve.
        let epsilon_reference = match solve_epsilon_reference(
            &p,
            &mesh,
            options.epsilon,
            reference::mp::DEFAULT_PRECISION,
        ) {
            Ok(e) if e.certificate.verified => {
                epsilon_ties += usize::from(e.has_tie());
                epsilon_solves = epsilon_solves.max(e.solves);
                Some(e)
            }
            Ok(e) => {
                epsilon_uncertified += 1;
                println!("ε-reference not certified on {name}: {:?}", e.certificate);
                None
            }
            Err(why) => {
                epsilon_uncertified += 1;
                println!("ε-reference failed on {name}: {why}");
                None
            }
        };
        for (method, tally) in &mut tallies {
            let (r, tolerance) = if method.is_regularized() {
                match &epsilon_reference {
                    Some(e) => (e, REGULARIZED_TOLERANCE),
                    None => continue,
                }
            } else {
                (&r, tolerance)
            };
            tally.scenes += 1;
            let solution = match run_method(&p, &mesh, *method, &options) {
                Ok(s) => s,
                Err(why) if why == "panicked" => {
                    tally.panicked += 1;
                    continue;
                }
                Err(_) => {
                    tally.refused += 1;
                    continue;
                }
            };
            let c = compare(&p, &solution, r);
            let (field, force) = (c.field_error(), c.force_error());
            note(&mut tally.worst_field, field, name);
            note(&mut tally.worst_force, force, name);
            tally.flag_errors += usize::from(!c.flag_errors.is_empty());
            tally.gross_flags += usize::from(c.gross_flag_errors > 0);
            if c.agrees(tolerance, tolerance) {
                tally.agree += 1;
            } else if c.warned() {
                tally.wrong_with_warning += 1;
                for code in &c.warnings {
                    *tally.warning_codes.entry(format!("{code:?}")).or_default() += 1;
                }
            } else {
                tally.wrong_silently += 1;
                tally.silent_values += usize::from(!(field <= tolerance && force <= tolerance));
                note(&mut tally.worst_silent_field, field, name);
                note(&mut tally.worst_silent_force, force, name);
                let badness = if field.is_nan() || force.is_nan() {
                    f64::INFINITY
                } else {
                    field.max(force)
                };
                tally.examples.push((
                    badness,
                    name.clone(),
                    format!(
                        "u {:.1e} slope {:.1e} force {:.1e} moment {:.1e}; {}",
                        c.u,
                        c.slope,
                        c.force,
                        c.moment,
                        c.flag_errors.first().cloned().unwrap_or_default()
                    ),
                ));
            }
        }
    }
    println!(
        "\n{} scenes ({} regression + {count} generated from seed {first_seed}); reference \
         uncertified on {uncertified}, exact ties in {ties}; exact methods are measured against \
         the exact (eps = 0) reference, agreement = 1e-10 in u/slope and forces with right \
         flags; regularised methods at eps = {:e} against the eps-reference (the same \
         eps-problem (40)-(43) in multi-precision, tests/it/reference/epsilon.rs; uncertified or \
         failed on {epsilon_uncertified}, ties in {epsilon_ties}, at most {epsilon_solves} \
         Newton steps), agreement = {REGULARIZED_TOLERANCE:e} (issue 10) with right flags, \
         'moves' meaning |motion| > eps\n",
        scenes.len(),
        scenes.len() - count as usize,
        options.epsilon
    );
    println!(
        "columns: agree = within the tolerance (1e-10 exact, 1e-8 regularised) with right \
         flags; warned = not, but warned; silent = \
         not, without a warning (s.val: of those, values off, not only flags); flags = scenes \
         with a wrong flag (gross: one f64 could resolve, see compare.rs); worst u/F = worst u-or-slope / force-or-moment error over all \
         solved scenes; silent u/F = the same over the silent ones"
    );
    println!(
        "{:<19} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>5} {:>6} {:>6}  {:>9} {:>9}  {:>9} {:>9}",
        "method",
        "scenes",
        "agree",
        "warned",
        "silent",
        "s.val",
        "refuse",
        "panic",
        "flags",
        "gross",
        "worst u",
        "worst F",
        "silent u",
        "silent F"
    );
    for (method, t) in &tallies {
        println!(
            "{:<19} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>5} {:>6} {:>6}  {:>9.2e} {:>9.2e}  {:>9.2e} {:>9.2e}",
            method.name(),
            t.scenes,
            t.agree,
            t.wrong_with_warning,
            t.wrong_silently,
            t.silent_values,
            t.refused,
            t.panicked,
            t.flag_errors,
            t.gross_flags,
            t.worst_field.0,
            t.worst_force.0,
            t.worst_silent_field.0,
            t.worst_silent_force.0,
        );
    }
    for (method, t) in &mut tallies {
        println!(
            "\n{}: worst u/slope on {}, worst force on {}; warnings of the warned: {:?}",
            method.name(),
            t.worst_field.1,
            t.worst_force.1,
            t.warning_codes
        );
        t.examples
            .sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap_or(std::cmp::Ordering::Equal));
        for (_, name, what) in t.examples.iter().take(8) {
            println!("  silent: {name}: {what}");
        }
        for (_, name, _) in t.examples.iter().take(2) {
            let scene = &scenes.iter().find(|(n, _)| n == name).unwrap().1;
            let file = dir.join(format!("{}-{}.toml", method.name(), name.replace(' ', "-")));
            std::fs::write(&file, scene.to_toml()).unwrap();
            println!("  --- {name} ({}):\n{}", file.display(), scene.to_toml());
        }
    }
}

/// What one method did over the scenes of `measure`.
#[derive(Default)]
struct Tally {
    scenes: usize,
    agree: usize,
    wrong_with_warning: usize,
    wrong_silently: usize,
    silent_values: usize,
    refused: usize,
    panicked: usize,
    flag_errors: usize,
    gross_flags: usize,
    worst_field: (f64, String),
    worst_force: (f64, String),
    worst_silent_field: (f64, String),
    worst_silent_force: (f64, String),
    examples: Vec<(f64, String, String)>,
    /// Of the scenes counted as warned: how many carried each warning code.
    warning_codes: std::collections::BTreeMap<String, usize>,
}

/// Keeps the larger of `slot` and `value` (a NaN wins), with the scene's name.
fn note(slot: &mut (f64, String), value: f64, name: &str) {
    if value > slot.0 || (value.is_nan() && !slot.0.is_nan()) {
        *slot = (value, name.to_string());
    }
}

/// `silent`: every silent failure of the regularised methods against the ε-reference, flag by
/// flag, on the regression scenes and `BEAMFRIC_HARD_SCENES` (default 2000) generated scenes
/// from seed 0, at `BEAMFRIC_EPSILON` (default 1e-10): for each wrong flag the reference's
/// |c|/ε − 1 and λ/g next to the program's, and whether f64 could resolve it (gross).
fn diagnose_silent_regularized_failures() {
    let count = env_number("BEAMFRIC_HARD_SCENES", 2000);
    let epsilon: f64 = std::env::var("BEAMFRIC_EPSILON")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1e-10);
    let options = SolveOptions {
        epsilon,
        max_cases: env_number("BEAMFRIC_MAX_CASES", 6561),
        ..SolveOptions::default()
    };
    let mut scenes: Vec<(String, Scene)> = regression_scenes();
    scenes.extend((0..count).map(|s| (format!("seed {s}"), hard_scene(s))));
    for (name, scene) in &scenes {
        let (p, n) = problem_of(scene);
        let mesh = Mesh::new(&p, n);
        let Ok(r) = solve_epsilon_reference(&p, &mesh, epsilon, reference::mp::DEFAULT_PRECISION)
        else {
            println!("{name}: no ε-reference");
            continue;
        };
        for method in [Method::Regularized, Method::RegularizedNewton] {
            let Ok(solution) = run_method(&p, &mesh, method, &options) else {
                continue;
            };
            let c = compare(&p, &solution, &r);
            if c.agrees(REGULARIZED_TOLERANCE, REGULARIZED_TOLERANCE) || c.warned() {
                continue;
            }
            println!(
                "{name} {method}: u {:.1e} slope {:.1e} force {:.1e} moment {:.1e}, gross flags {}, kkt {:.1e}, k = {}",
                c.u,
                c.slope,
                c.force,
                c.moment,
                c.gross_flag_errors,
                solution.kkt_residual,
                p.obstacles.len()
            );
            let motion = r.motion_f64();
            let lambda = r.lambda_f64();
            for (j, o) in solution.obstacles.iter().enumerate() {
                let node = mesh.obstacle_nodes[j];
                let mine = [solution.field.deflection[node], solution.field.slope[node]];
                let forces = [o.force, o.moment];
                let states = [o.sliding_state, o.swivel_state];
                let g = [
                    p.obstacles[j].sliding_threshold,
                    p.obstacles[j].swivel_threshold,
                ];
                for k in 0..2 {
                    let flag = [o.sliding, o.swivel][k];
                    if r.states[j][k].accepts(flag) {
                        continue;
                    }
                    println!(
                        "    obstacle {} {}: reference {} |c|/ε−1 {:.3e} λ/g {:.17} | program {:?} |c|/ε−1 {:.3e} λ/g {:.17}",
                        j + 1,
                        ["sliding", "swivel"][k],
                        r.states[j][k].word(),
                        motion[j][k].abs() / epsilon - 1.0,
                        lambda[j][k] / g[k],
                        states[k],
                        mine[k].abs() / epsilon - 1.0,
                        forces[k] / g[k]
                    );
                }
            }
        }
    }
}

/// `scan`: the stable method alone on `BEAMFRIC_HARD_SCENES` (default 2000) generated scenes,
/// one line per scene it fails, the scene written to `target/tmp/scan/seed-N.toml`. The seeds
/// are `BEAMFRIC_HARD_SEED` (default 0) and the ones after it or, when `BEAMFRIC_WIDE_SEEDS` is
/// set, random 64-bit seeds (the property test's kind) drawn from `BEAMFRIC_HARD_SEED`.
fn scan_stable_method_on_hard_scenes() {
    let count = env_number("BEAMFRIC_HARD_SCENES", 2000);
    let first_seed = env_number("BEAMFRIC_HARD_SEED", 0);
    let wide = std::env::var("BEAMFRIC_WIDE_SEEDS").is_ok();
    let mut rng = reference::scenes::Rng::new(first_seed);
    let mut failures = 0;
    for i in 0..count {
        let seed = if wide { rng.next_u64() } else { first_seed + i };
        let scene = hard_scene(seed);
        if let Err(why) = check_stable(&format!("seed {seed}"), &scene) {
            failures += 1;
            println!("{}", why.lines().next().unwrap_or_default());
            let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("scan");
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join(format!("seed-{seed}.toml")), scene.to_toml()).unwrap();
        }
    }
    println!("{failures} of {count} scenes fail");
}

/// `families`: the stable method against the reference on `BEAMFRIC_HARD_SCENES` (default
/// 200) seeds of every family of `check::families` and of its partial ties
/// (`half_ties_scene`, `sliding_ties_scene`), with k drawn from 2..=200 per seed, on 400
/// elements. Minutes.
fn scan_stable_method_on_families() {
    use beamfric::check::families::{Family, family_scene, half_ties_scene, sliding_ties_scene};
    use beamfric::scene::Scene;
    let count = env_number("BEAMFRIC_HARD_SCENES", 200);
    type SceneOf = Box<dyn Fn(usize, u64) -> Scene>;
    let mut arrangements: Vec<(&str, SceneOf)> = Family::ALL
        .into_iter()
        .map(|family| {
            let scene_of: SceneOf = Box::new(move |k, seed| family_scene(family, k, seed, 400));
            (family.name(), scene_of)
        })
        .collect();
    // Stop 53's hostile arrangements: some thresholds at the stuck forces, the others not.
    arrangements.push((
        "half ties",
        Box::new(|k, seed| half_ties_scene(k, seed, 400)),
    ));
    arrangements.push((
        "sliding ties",
        Box::new(|k, seed| sliding_ties_scene(k, seed, 400)),
    ));
    for (name, scene_of) in arrangements {
        let mut rng = reference::scenes::Rng::new(17);
        let mut failures = 0;
        for seed in 0..count {
            let k = rng.range(2, 200);
            let scene = scene_of(k, seed);
            if let Err(why) = check_stable(&scene.title, &scene) {
                failures += 1;
                println!("{}", why.lines().next().unwrap_or_default());
            }
        }
        println!("{name}: {failures} of {count} scenes fail");
    }
}

/// `write`: writes the hard scene of every seed in `BEAMFRIC_WRITE_SEEDS` (comma separated) to
/// `tests/scenes/hard/seed-N.toml`, to keep a failing seed as a regression scene.
fn write_hard_scenes_as_regressions() {
    let seeds = std::env::var("BEAMFRIC_WRITE_SEEDS").unwrap_or_default();
    for seed in seeds
        .split(',')
        .filter_map(|s| s.trim().parse::<u64>().ok())
    {
        let mut scene = hard_scene(seed);
        scene.title = format!("hard scene {seed}");
        let path = format!(
            "{}/tests/scenes/hard/seed-{seed}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        std::fs::write(&path, scene.to_toml()).unwrap();
    }
}

/// `diagnose`: one generated scene in detail, the one of seed `BEAMFRIC_DIAGNOSE_SEED` (default
/// 0): every node and every obstacle, the stable method next to the reference.
fn diagnose_one_hard_scene() {
    let seed = env_number("BEAMFRIC_DIAGNOSE_SEED", 0);
    let scene = hard_scene(seed);
    let (p, n) = problem_of(&scene);
    let mesh = Mesh::new(&p, n);
    let r = solve_reference(&p, n);
    let solution = run_method(&p, &mesh, STABLE_METHOD, &SolveOptions::default()).unwrap();
    let (u, slope) = (r.u_f64(), r.slope_f64());
    println!("{}", scene.to_toml());
    for (i, x) in r.nodes.iter().enumerate() {
        println!(
            "node {i:3} x {x:<24e} u {:<24e} ref {:<24e} | u' {:<24e} ref {:<24e}",
            solution.field.deflection[i], u[i], solution.field.slope[i], slope[i]
        );
    }
    for (j, (o, l)) in solution.obstacles.iter().zip(r.lambda_f64()).enumerate() {
        println!(
            "obstacle {} x {:e}: force {:e} ref {:e} ({:?}), moment {:e} ref {:e} ({:?}); flags {} {}",
            j + 1,
            o.x,
            o.force,
            l[0],
            r.states[j][0],
            o.moment,
            l[1],
            r.states[j][1],
            o.sliding,
            o.swivel
        );
    }
    println!("{:?}", compare(&p, &solution, &r));
    for w in &solution.warnings {
        println!("warning {:?}: {}", w.code, w.message);
    }
}
