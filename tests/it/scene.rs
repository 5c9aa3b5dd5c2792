//! Scene files: presets load and validate; every kind of mistake is rejected with a message
//! naming the file, the field and the rule.

use beamfric::scene::{PRESETS, Scene, load};

const GOOD: &str = r#"
title = "t"
[beam]
length = 1.0
young = 2.15e11
section = { shape = "rectangle", width = 0.02, height = 0.02 }
[load]
f0 = 5e4
[[obstacle]]
x = 0.8
sliding = 1e2
swivel = 5e4
[mesh]
elements = 20
[solver]
method = "dual"
epsilon = 1e-6
"#;

fn reject(text: &str) -> String {
    let scene = match Scene::from_toml(text, "bad.toml") {
        Ok(scene) => scene,
        Err(e) => return e.to_string(),
    };
    match scene.validate("bad.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn mutate(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from}");
    reject(&GOOD.replacen(from, to, 1))
}

fn assert_mentions(message: &str, parts: &[&str]) {
    assert!(message.starts_with("bad.toml: "), "{message}");
    for part in parts {
        assert!(
            message.contains(part),
            "{message:?} does not mention {part:?}"
        );
    }
}

#[test]
fn the_good_scene_and_every_preset_validate() {
    Scene::from_toml(GOOD, "good")
        .unwrap()
        .validate("good")
        .unwrap();
    for preset in PRESETS {
        let loaded = load(preset.name).unwrap();
        assert_eq!(loaded.source.to_string(), format!("preset {}", preset.name));
        // Loading validated once and kept what validation built.
        let (problem, settings) = loaded.scene.validate("again").unwrap();
        assert_eq!((problem, settings), (loaded.problem, loaded.settings));
        assert!(!loaded.scene.title.is_empty());
    }
}

#[test]
fn each_kind_of_mistake_is_named() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "length = 1.0",
            "length = 0.0",
            &["beam.length", "greater than zero"],
        ),
        (
            "length = 1.0",
            "length = -2.0",
            &["beam.length", "greater than zero"],
        ),
        ("young = 2.15e11", "young = 0", &["beam.young", "= 0 Pa"]),
        (
            "young = 2.15e11",
            "young = -1e9",
            &["beam.young", "greater than zero"],
        ),
        (
            "width = 0.02",
            "width = 0.0",
            &["beam.section.width", "greater than zero"],
        ),
        (
            "{ shape = \"rectangle\", width = 0.02, height = 0.02 }",
            "{ shape = \"custom\", inertia = -1e-8 }",
            &["beam.section.inertia", "greater than zero"],
        ),
        (
            "x = 0.8",
            "x = 1.2",
            &["obstacle[1].x", "strictly inside (0, l)"],
        ),
        ("x = 0.8", "x = 0.0", &["obstacle[1].x", "strictly inside"]),
        (
            "sliding = 1e2",
            "sliding = -1",
            &["obstacle[1].sliding", "zero or positive"],
        ),
        (
            "swivel = 5e4",
            "swivel = -5e4",
            &["obstacle[1].swivel", "zero or positive"],
        ),
        (
            "epsilon = 1e-6",
            "epsilon = 0.0",
            &["solver.epsilon", "greater than zero"],
        ),
        (
            "epsilon = 1e-6",
            "epsilon = -1e-3",
            &["solver.epsilon", "greater than zero"],
        ),
        (
            "elements = 20",
            "elements = 0",
            &["mesh.elements", "between 1 and"],
        ),
        ("f0 = 5e4", "f0 = nan", &["load.f0", "finite"]),
        ("f0 = 5e4", "f0 = inf", &["load.f0", "finite"]),
        ("length = 1.0", "length = inf", &["beam.length", "finite"]),
        (
            "length = 1.0",
            "lenght = 1.0",
            &["unknown field `lenght`", "[beam]"],
        ),
        (
            "method = \"dual\"",
            "method = \"fast\"",
            &["unknown variant `fast`", "dual"],
        ),
        ("elements = 20", "elements = \"many\"", &["line", "[mesh]"]),
        ("shape = \"rectangle\"", "shape = \"hexagon\"", &["hexagon"]),
        ("[mesh]", "[meshes]", &["unknown field `meshes`"]),
    ];
    for (from, to, parts) in cases {
        let message = mutate(from, to);
        assert_mentions(&message, parts);
    }
}

#[test]
fn coincident_and_overlapping_things_are_rejected() {
    let two = GOOD.replace(
        "[mesh]",
        "[[obstacle]]\nx = 0.8\nsliding = 1\nswivel = 1\n[mesh]",
    );
    assert_mentions(
        &reject(&two),
        &["obstacle[2].x", "same position as obstacle[1]"],
    );
    let close = GOOD.replace(
        "[mesh]",
        "[[obstacle]]\nx = 0.8000000000001\nsliding = 1\nswivel = 1\n[mesh]",
    );
    assert_mentions(&reject(&close), &["obstacle[2].x", "closer than"]);
    let overlap = GOOD.replace(
        "[load]",
        "[[beam.segment]]\nfrom = 0.1\nto = 0.5\nyoung = 1e9\n[[beam.segment]]\nfrom = 0.4\nto = 0.6\n[load]",
    );
    assert_mentions(
        &reject(&overlap),
        &["beam.segment[2]", "overlaps beam.segment[1]"],
    );
    let backwards = GOOD.replace("[load]", "[[beam.segment]]\nfrom = 0.5\nto = 0.2\n[load]");
    assert_mentions(&reject(&backwards), &["beam.segment[1].to", "(from, l]"]);
}

#[test]
fn a_missing_file_names_the_presets() {
    let error = load("no-such-scene").unwrap_err().to_string();
    assert!(error.contains("no-such-scene"));
    assert!(error.contains("benchmark-1"), "{error}");
}

#[test]
fn scenes_survive_a_round_trip_through_toml() {
    for preset in PRESETS {
        let scene = Scene::from_toml(preset.text, preset.name).unwrap();
        let again = Scene::from_toml(&scene.to_toml(), "again").unwrap();
        assert_eq!(scene, again, "{}", preset.name);
    }
}

#[test]
fn whole_file_mistakes_are_named() {
    // An empty file: the first required table is named.
    assert_mentions(&reject(""), &["missing field `beam`"]);
    // Not TOML at all: the line is given.
    assert_mentions(&reject("this is not a scene\n"), &["line 1"]);
    // A required field left out.
    assert_mentions(
        &reject(&GOOD.replace("young = 2.15e11\n", "")),
        &["missing field `young`", "[beam]"],
    );
    // A field given twice.
    assert_mentions(
        &reject(&GOOD.replace("f0 = 5e4", "f0 = 5e4\nf0 = 1e4")),
        &["duplicate key", "f0"],
    );
    // Too many obstacles for the solvers' limits.
    let mut crowded = GOOD.replace("[[obstacle]]\nx = 0.8\nsliding = 1e2\nswivel = 5e4\n", "");
    for i in 1..=beamfric::scene::MAX_OBSTACLES + 1 {
        let x = i as f64 / (beamfric::scene::MAX_OBSTACLES + 2) as f64;
        crowded.push_str(&format!("[[obstacle]]\nx = {x}\nsliding = 1\nswivel = 1\n"));
    }
    assert_mentions(
        &reject(&crowded),
        &[
            &format!("{} obstacles", beamfric::scene::MAX_OBSTACLES + 1),
            &format!("at most {}", beamfric::scene::MAX_OBSTACLES),
        ],
    );
    // The explorer's panels: an unknown name lists the known ones, none at all is refused.
    assert_mentions(
        &reject(&format!(
            "{GOOD}[view]\npanels = [\"deflection\", \"spectrum\"]\n"
        )),
        &["unknown variant `spectrum`", "deflection"],
    );
    assert_mentions(
        &reject(&format!("{GOOD}[view]\npanels = []\n")),
        &["view.panels"],
    );
    // Non-finite numbers inside an obstacle are named by index.
    assert_mentions(
        &mutate("sliding = 1e2", "sliding = nan"),
        &["obstacle[1].sliding", "finite"],
    );
    assert_mentions(
        &mutate("swivel = 5e4", "swivel = inf"),
        &["obstacle[1].swivel", "finite"],
    );
}
