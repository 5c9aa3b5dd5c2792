//! `beamfric solve` from the outside: the JSON document, the table, and errors as one line.

use std::process::Output;

use serde_json::Value;

use crate::harness::process::{NO_COLOR, beamfric_with};

fn beamfric(args: &[&str]) -> Output {
    beamfric_with(args, NO_COLOR)
}

fn json(args: &[&str]) -> Value {
    let out = beamfric(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn stderr_line(out: &Output) -> String {
    let text = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(text.trim_end().lines().count(), 1, "not one line: {text:?}");
    text.trim_end().to_string()
}

#[test]
fn json_has_every_documented_field() {
    let doc = json(&[
        "solve",
        "--scene",
        "benchmark-1",
        "--format",
        "json",
        "--at",
        "0.4,0.8",
    ]);
    for key in [
        "method",
        "elements",
        "nodes",
        "at",
        "obstacles",
        "kkt_residual",
        "error",
        "timing",
        "condition",
        "warnings",
    ] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["method"], "dual");
    assert_eq!(doc["elements"], 20);
    let nodes = &doc["nodes"];
    assert_eq!(nodes["x"].as_array().unwrap().len(), 21);
    assert_eq!(nodes["u"].as_array().unwrap().len(), 21);
    assert_eq!(nodes["slope"].as_array().unwrap().len(), 21);
    let at = doc["at"].as_array().unwrap();
    assert_eq!(at.len(), 2);
    let u_at = at[1]["u"].as_f64().unwrap();
    assert!((u_at - 0.005_701_610_017_889_088).abs() < 1e-15);
    let o = &doc["obstacles"][0];
    assert!((o["force"].as_f64().unwrap() - 100.0).abs() < 1e-9);
    assert!((o["moment"].as_f64().unwrap() + 4_798.461_538_461_5).abs() < 1e-6);
    assert_eq!(o["sliding"], true);
    assert_eq!(o["swivel"], false);
    assert_eq!(doc["error"]["reference"], "closed-form");
    assert!(doc["error"]["max_rel"].as_f64().unwrap() < 1e-12);
    assert!(doc["kkt_residual"].as_f64().unwrap() < 1e-12);
    assert_eq!(doc["timing"]["unit"], "s");
    for stage in [
        "assembly",
        "factorization",
        "friction_stage",
        "reconstruction",
        "total",
    ] {
        assert!(doc["timing"][stage].as_f64().unwrap() >= 0.0, "{stage}");
    }
    assert_eq!(doc["condition"]["stiffness"]["kind"], "exact");
    assert!(doc["warnings"].as_array().unwrap().is_empty());
}

#[test]
fn overrides_and_no_nodes() {
    let doc = json(&[
        "solve",
        "--scene",
        "benchmark-3",
        "--method",
        "condensed",
        "--elements",
        "40",
        "--format",
        "json",
        "--no-nodes",
    ]);
    assert!(doc.get("nodes").is_none());
    assert_eq!(doc["elements"], 40);
    assert_eq!(doc["method"], "condensed");
    // No closed form for four obstacles: condensed is its own reference, not "error 0".
    assert_eq!(doc["error"]["reference"], "self");
    assert!(doc["error"]["max_rel"].is_null());
    assert_eq!(doc["obstacles"].as_array().unwrap().len(), 4);
}

#[test]
fn the_table_is_for_people() {
    let out = beamfric(&["solve", "--scene", "benchmark-1"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("Benchmark 1"));
    assert!(text.contains("slides"));
    assert!(text.contains("u [m]"));
    assert!(text.contains("error vs closed-form"));
}

#[test]
fn bad_input_is_one_clear_line_and_a_failure() {
    let cases: &[(&[&str], &str)] = &[
        (&["solve", "--scene", "nope"], "not a preset name"),
        (
            &["solve", "--elements", "0"],
            "--elements = 0: must be between 1 and",
        ),
        (&["solve", "--epsilon", "-1"], "--epsilon = -1"),
        (&["solve", "--elements", "many"], "invalid value 'many'"),
        (&["solve", "--method", "fast"], "invalid value 'fast'"),
        (
            &["solve", "--at", "2"],
            "--at 2: positions must lie on the beam",
        ),
        (&["solve", "--format", "xml"], "invalid value 'xml'"),
    ];
    for (args, expected) in cases {
        let out = beamfric(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let line = stderr_line(&out);
        assert!(line.contains(expected), "{args:?}: {line}");
        assert!(out.stdout.is_empty());
    }
    let dir = std::env::temp_dir().join(format!("beamfric-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("broken.toml");
    std::fs::write(&path, "[beam]\nlength = -1\n").unwrap();
    let out = beamfric(&["solve", "--scene", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let line = stderr_line(&out);
    assert!(line.contains("broken.toml"), "{line}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn negative_and_out_of_range_numbers_are_refused_quoting_what_was_typed() {
    // Issue 22: `--elements -1` said "unexpected argument '-1'" (taken for an option).
    let count = "must be a whole number from 1 to 10000000";
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["solve", "--elements", "-1"],
            &["invalid value '-1' for '--elements", count],
        ),
        (
            &["solve", "--elements", "1e300"],
            &["invalid value '1e300' for '--elements", count],
        ),
        (
            &["solve", "--elements", "99999999999999999999999"],
            &[
                "invalid value '99999999999999999999999' for '--elements",
                count,
            ],
        ),
        (
            &["solve", "--elements", "20000000"],
            &["--elements = 20000000: must be between 1 and 10000000"],
        ),
        (
            &["solve", "--epsilon", "1e400"],
            &[
                "invalid value '1e400' for '--epsilon",
                "must be a finite number",
            ],
        ),
        (
            &["solve", "--at", "-0.5"],
            &["--at -0.5: positions must lie on the beam"],
        ),
        (
            &["sweep", "epsilon", "--elements", "-3"],
            &["invalid value '-3' for '--elements", count],
        ),
        (
            &["sweep", "epsilon", "--from", "-1e-3"],
            &["--from = -0.001: ε must be a finite number greater than zero"],
        ),
        (
            &["sweep", "epsilon", "--points", "-2"],
            &["invalid value '-2' for '--points", "from 1 to 1000"],
        ),
        (
            &["sweep", "elements", "--epsilon", "-1"],
            &["--epsilon = -1: ε must be a finite number greater than zero"],
        ),
        (
            &["sweep", "elements", "--to", "-10"],
            &["invalid value '-10' for '--to", count],
        ),
        (
            &["report", "--repeat", "-1"],
            &["invalid value '-1' for '--repeat", "from 1 to 100"],
        ),
        (
            &["report", "--points", "2.5"],
            &["invalid value '2.5' for '--points", "from 1 to 200"],
        ),
        (
            &[
                "render",
                "--lesson",
                "lessons/regularisation.toml",
                "--step",
                "-1",
            ],
            &["invalid value '-1' for '--step", "from 1 to"],
        ),
        (
            &["render", "--size", "-1x5"],
            &["'-1x5': the width must be a whole number from 1 to 1000"],
        ),
    ];
    for (args, expected) in cases {
        let out = beamfric(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let line = stderr_line(&out);
        for part in *expected {
            assert!(line.contains(part), "{args:?}: {line}");
        }
        assert!(!line.contains("unexpected argument"), "{args:?}: {line}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn a_refused_method_says_which_one_works() {
    let out = beamfric(&[
        "solve",
        "--scene",
        "benchmark-3",
        "--method",
        "closed-form",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(3));
    let line = stderr_line(&out);
    assert!(line.contains("closed-form not applicable"), "{line}");
    assert!(line.contains("condensed"), "{line}");
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["refused"]["kind"], "not-applicable");
    assert_eq!(doc["refused"]["suggestion"], "condensed");
}

#[test]
fn an_epsilon_sweep_that_cannot_run_does_not_send_you_to_a_method_without_epsilon() {
    // Stop 58's hostile pass: `sweep epsilon` on a scene where the regularised method breaks
    // down said "the condensed method works here", a method the sweep cannot take.
    let dir = tempfile::tempdir().unwrap();
    let mut scene = beamfric::scene::load("benchmark-1").unwrap().scene;
    scene.beam.young = 1e308;
    let path = dir.path().join("stiff.toml");
    std::fs::write(&path, scene.to_toml()).unwrap();
    let out = beamfric(&["sweep", "epsilon", "--scene", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(3));
    let line = stderr_line(&out);
    assert!(
        line.contains("the ε sweep needs the regularised method: regularized broke down"),
        "{line}"
    );
    assert!(
        line.ends_with("so this scene has no ε sweep (the condensed method solves it, without ε)"),
        "{line}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn a_non_finite_solution_is_reported_not_shown() {
    let dir = std::env::temp_dir().join(format!("beamfric-nonfinite-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge.toml");
    let scene = beamfric::scene::load("benchmark-1").unwrap().scene;
    let mut scene = scene;
    // Valid numbers each, but f1 − f0 overflows.
    scene.load.f0 = 1.7e308;
    scene.load.f1 = Some(-1.7e308);
    std::fs::write(&path, scene.to_toml()).unwrap();
    let path = path.to_str().unwrap();

    let out = beamfric(&["solve", "--scene", path, "--format", "json"]);
    assert_eq!(out.status.code(), Some(4));
    assert!(stderr_line(&out).contains("non-finite"));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["warnings"][0]["code"], "non-finite", "{doc}");
    assert!(doc["kkt_residual"].is_null(), "{}", doc["kkt_residual"]);
    assert!(doc["obstacles"][0]["force"].is_null());
    assert!(doc["nodes"]["u"][1].is_null());
    for field in ["max_abs", "max_rel", "mean_abs", "mean_rel"] {
        assert!(
            doc["error"][field].is_null(),
            "{field}: {}",
            doc["error"][field]
        );
    }

    let out = beamfric(&["solve", "--scene", path]);
    assert_eq!(out.status.code(), Some(4));
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("KKT residual     n/a"), "{table}");
    assert!(table.contains("max |u|          n/a"), "{table}");
    assert!(table.contains("unknown"), "{table}");

    // The explorer's frame: n/a and the warning, never NaN, inf or a made-up 0.
    let out = beamfric(&["render", "--scene", path, "--size", "120x40"]);
    assert!(out.status.success());
    let frame = String::from_utf8_lossy(&out.stdout);
    // Everything above the warning line (which says "NaN or infinite" in words).
    let (numbers, _) = frame.split_once("\n⚠").expect("a warning line");
    for bad in ["NaN", "nan", "inf", "error 0 "] {
        assert!(!numbers.contains(bad), "{bad:?} in\n{frame}");
    }
    assert!(
        frame.contains("KKT n/a") && frame.contains("NaN or infinite"),
        "{frame}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_time_line_names_the_stages_a_method_has() {
    let time_line = |method: &str| {
        let out = beamfric(&["solve", "--scene", "benchmark-1", "--method", method]);
        assert!(out.status.success(), "{method}");
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .find(|l| l.starts_with("time "))
            .unwrap_or_else(|| panic!("{method}: no time line"))
            .to_string()
    };
    // The condensed method has no assembly, factorization or reconstruction stage of its own:
    // its time is the friction search (which solves and refines every pattern).
    let condensed = time_line("condensed");
    assert!(condensed.contains("(friction search "), "{condensed}");
    for absent in ["assembly", "factorization", "dual solve", "reconstruction"] {
        assert!(!condensed.contains(absent), "{condensed}");
    }
    let dual = time_line("dual");
    for stage in ["assembly", "factorization", "dual solve", "reconstruction"] {
        assert!(dual.contains(stage), "{dual}");
    }
    assert!(time_line("regularized").contains("friction DOFs"));
}

/// Issue 25: a refusal in `sweep elements` names its own n (the 10⁵ row said 10⁴'s figures).
#[test]
fn a_sweeps_refusals_name_their_own_size() {
    let out = crate::harness::process::beamfric(&[
        "sweep",
        "elements",
        "--scene",
        "benchmark-1",
        "--from",
        "10000",
        "--to",
        "1000000",
        "--points",
        "3",
        "--methods",
        "dual-inverse",
    ]);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    for n in ["10000", "100000", "1000000"] {
        let row = text
            .lines()
            .find(|l| l.starts_with(&format!("dual-inverse,{n},")))
            .unwrap_or_else(|| panic!("no row for n = {n}:\n{text}"));
        assert!(row.contains(&format!("for n = {n} elements")), "{row}");
    }
}

/// Standard output that cannot be written (a full disk behind `> file`, here /dev/full) is an
/// error with exit status 2 and one line on stderr, not a cut answer with status 0; a reader
/// that stops reading (`beamfric solve | head`) is no error. Before stop 55 every command
/// ignored the write's error and ended with 0.
#[cfg(target_os = "linux")]
#[test]
fn output_that_cannot_be_written_is_an_error_and_a_closed_pipe_is_not() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let binary = env!("CARGO_BIN_EXE_beamfric");
    for args in [
        &["solve", "--scene", "benchmark-1", "--format", "json"][..],
        &["sweep", "epsilon", "--scene", "benchmark-1"][..],
        &["check", "--scene", "benchmark-1"][..],
        // Help and version too (stop 58's hostile pass: `--help > /dev/full` ended with 0).
        &["--help"][..],
        &["solve", "--help"][..],
        &["--version"][..],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full opens");
        let out = Command::new(binary)
            .args(args)
            .env("NO_COLOR", "1")
            .stdout(full)
            .output()
            .expect("the binary runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("cannot write to standard output"),
            "{args:?}: {stderr}"
        );
    }
    // A reader that takes one byte and closes the pipe, of an answer far larger than the
    // pipe's buffer (4000 obstacles' values as JSON).
    let scene = std::env::temp_dir().join(format!("beamfric-pipe-{}.toml", std::process::id()));
    std::fs::write(
        &scene,
        crate::harness::scenes::crowded_scene_text_of(4000, 10_000),
    )
    .expect("the scene is written");
    let mut child = Command::new(binary)
        .args([
            "solve",
            "--method",
            "condensed",
            "--format",
            "json",
            "--scene",
        ])
        .arg(&scene)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut byte = [0u8; 1];
    child
        .stdout
        .take()
        .unwrap()
        .read_exact(&mut byte)
        .expect("a first byte");
    let out = child.wait_with_output().expect("it ends");
    let _ = std::fs::remove_file(&scene);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
    assert!(stderr.is_empty(), "{stderr}");
}
