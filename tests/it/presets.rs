//! Every preset loads, validates and solves (issue 5), and the stability suite passes on it.

use beamfric::check::families::{Family, family_scene, stuck_forces};
use beamfric::check::{check_scene, markdown, scaled_scene};
use beamfric::fem::Mesh;
use beamfric::scene::{PRESETS, Scene, SegmentSpec};
use beamfric::solve::{Method, Reference, SolveErrorKind, WarningCode, solve};

use crate::harness::scenes::*;

#[test]
fn every_preset_loads_validates_and_solves_with_its_own_method() {
    assert!(PRESETS.len() >= 16);
    for preset in PRESETS {
        let scene = Scene::from_toml(preset.text, preset.name).unwrap();
        assert!(
            !scene.description.is_empty(),
            "{}: no description",
            preset.name
        );
        assert!(
            preset.text.trim_start().starts_with('#'),
            "{}: the file must open with a comment saying what it teaches",
            preset.name
        );
        let (problem, settings) = scene.validate(preset.name).unwrap();
        let mesh = Mesh::new(&problem, settings.elements);
        let solution = solve(&problem, &mesh, settings.method, &options(settings.epsilon))
            .unwrap_or_else(|e| panic!("{}: {e}", preset.name));
        assert!(solution.is_finite(), "{}", preset.name);
    }
}

#[test]
fn the_scaled_beams_reproduce_benchmark_1() {
    let reference = solve_with(
        &problem(&preset_scene("benchmark-1")),
        20,
        Method::Flexibility,
        1e-6,
    );
    for name in ["tiny-beam", "huge-beam"] {
        let solution = solve_with(&problem(&preset_scene(name)), 20, Method::Flexibility, 1e-6);
        let diff = relative_difference(&solution.field.deflection, &reference.field.deflection);
        assert!(diff < 1e-12, "{name}: {diff:e}");
        assert_eq!(solution.error.unwrap().reference, Reference::ClosedForm);
    }
}

#[test]
fn the_presets_show_what_their_comments_promise() {
    // Eight obstacles: the enumeration refuses, the others work.
    let eight = problem(&preset_scene("eight-obstacles"));
    let mesh = Mesh::new(&eight, 80);
    let refused = solve(&eight, &mesh, Method::Regularized, &options(1e-6)).unwrap_err();
    assert_eq!(refused.kind, SolveErrorKind::Refused);
    for method in [Method::Dual, Method::Flexibility, Method::RegularizedNewton] {
        assert!(
            solve(&eight, &mesh, method, &options(1e-9)).is_ok(),
            "{method}"
        );
    }
    // Zero thresholds: no friction force; huge thresholds: stuck.
    let free = solve_with(
        &problem(&preset_scene("zero-thresholds")),
        20,
        Method::Dual,
        1e-6,
    );
    assert!(free.obstacles[0].force == 0.0 && free.obstacles[0].moment == 0.0);
    let clamped = solve_with(
        &problem(&preset_scene("huge-thresholds")),
        20,
        Method::Dual,
        1e-6,
    );
    assert!(!clamped.obstacles[0].sliding && !clamped.obstacles[0].swivel);
    // The modulus contrast costs the stiffness route digits even at n = 200, and it says so.
    let contrast = solve_with(
        &problem(&preset_scene("modulus-contrast")),
        200,
        Method::Dual,
        1e-6,
    );
    assert!(contrast.error.unwrap().max_rel.unwrap() > 1e-6);
    assert!(
        contrast
            .warnings
            .iter()
            .any(|w| w.code == WarningCode::StiffnessConditioning)
    );
    let stable = solve_with(
        &problem(&preset_scene("modulus-contrast")),
        200,
        Method::Flexibility,
        1e-6,
    );
    assert!(stable.warnings.is_empty());
    // ε = 1e-16 is still accurate with a direct solve.
    let tiny_eps = solve_with(
        &problem(&preset_scene("epsilon-1e-16")),
        20,
        Method::Regularized,
        1e-16,
    );
    assert!(tiny_eps.error.unwrap().max_rel.unwrap() < 1e-12);
    // The lessons show only the panels their lesson needs.
    use beamfric::scene::Panel;
    assert_eq!(
        preset_scene("lesson-epsilon").view.panels,
        vec![Panel::Figure5]
    );
    // Figure 5's lesson opens with ε selected.
    assert_eq!(
        preset_scene("lesson-epsilon").view.select.as_deref(),
        Some("solver.epsilon")
    );
    assert_eq!(
        preset_scene("lesson-mesh").view.panels,
        vec![Panel::Deflection, Panel::ErrorTime]
    );
}

#[test]
fn the_stability_suite_passes_on_the_small_presets_and_reports_them() {
    // The 10⁶-element preset runs in the release-mode `.ci/run` (`beamfric check`).
    let mut reports = Vec::new();
    for preset in PRESETS.iter().filter(|p| p.name != "fine-mesh") {
        let scene = Scene::from_toml(preset.text, preset.name).unwrap();
        let report = check_scene(preset.name, &scene);
        assert!(report.passed(), "{}: {:?}", preset.name, report.failures);
        reports.push(report);
    }
    let table = markdown(&reports);
    assert!(table.contains("| benchmark-1 | 20 | 7 of 7 |"), "{table}");
    assert!(table.contains("regularized refused"), "{table}");
    assert!(!table.contains("FAIL"));
}

#[test]
fn the_suite_fails_what_is_wrong() {
    // Scaling l, E and f predicts u exactly, and a wrong factor would be caught.
    let scene = preset_scene("benchmark-3");
    let scaled = scaled_scene(&scene, (10.0, 3.0, 7.0));
    let a = solve_with(&problem(&scene), 20, Method::Flexibility, 1e-6);
    let b = solve_with(&problem(&scaled), 20, Method::Flexibility, 1e-6);
    let factor = 7.0 * 1e4 / 3.0;
    let predicted: Vec<f64> = a.field.deflection.iter().map(|u| u * factor).collect();
    assert!(relative_difference(&b.field.deflection, &predicted) < 1e-12);
    let wrong: Vec<f64> = predicted.iter().map(|u| u * 1.001).collect();
    assert!(relative_difference(&b.field.deflection, &wrong) > 1e-4);
    // A broken scene is a failed case, not a crash.
    let mut broken = preset_scene("benchmark-1");
    broken.beam.length = -1.0;
    let report = check_scene("broken", &broken);
    assert!(!report.passed());
    assert!(report.failures[0].contains("beam.length"));
}

#[test]
fn the_scaling_check_keeps_thresholds_tied_to_the_last_bit_tied() {
    // Every threshold equal to its stuck force, on a beam with a stiff and a soft stretch: about
    // half the DOFs move by a force excess of an ulp of their threshold. Scaling f by 7 and the
    // thresholds by 56 and 448 (the check's factors up to stop 44) rounds them apart and flips
    // such states: u changed by 5.0e-10 of itself here, by 0.9–2.9 times itself on such scenes
    // at k = 128, n = 10⁴ — right answers to another problem. The check now scales by powers of
    // two, so every input scales exactly and the scaled problem is the same one.
    let mut scene = family_scene(Family::Ties, 40, 1, 2000);
    let young = scene.beam.young;
    let stretch = |from: f64, to: f64, factor: f64| SegmentSpec {
        from,
        to,
        young: Some(young * factor),
        section: None,
    };
    scene.beam.segments = vec![stretch(0.085, 0.32, 1e8), stretch(0.47, 0.7, 1e-6)];
    let stuck = stuck_forces(&scene, 2000);
    for (o, [force, moment]) in scene.obstacles.iter_mut().zip(stuck) {
        o.sliding = force;
        o.swivel = moment;
    }
    let report = check_scene("ties with stretches", &scene);
    assert!(report.passed(), "{:?}", report.failures);
}
