//! Bring your own method (issue 24) from the outside: `beamfric export` writes the discrete
//! problem, this test reads it back with its own Matrix Market parser, solves it as a student
//! would — a dense Cholesky solve of A c = b − Bᵀλ (48) and the forces of the dual (49) by an
//! exhaustive enumeration of the bound states of every friction DOF — without any of the
//! library's solvers, and `beamfric grade` must call that answer exact; a perturbed answer
//! is graded with the error it has; malformed answers get errors that name the file, the
//! field and the rule.

mod student;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{Value, json};
use student::{Student, read_mtx};

use crate::harness::process::{NO_COLOR, beamfric_with};

fn beamfric(args: &[&str]) -> Output {
    beamfric_with(args, NO_COLOR)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).trim_end().to_string()
}

fn export(scene: &str, dir: &Path) {
    let out = beamfric(&["export", "--scene", scene, "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
}

fn grade(scene: &str, answer: &Path) -> (Output, Value) {
    let out = beamfric(&[
        "grade",
        "--scene",
        scene,
        "--answer",
        answer.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert!(
        out.status.code().is_some_and(|c| c <= 1),
        "{}",
        stderr(&out)
    );
    let doc = serde_json::from_slice(&out.stdout).expect("JSON grade");
    (out, doc)
}

/// Exports `scene`, solves it as a student, writes the answer and returns the grade.
fn student_grade(scene: &str, dir: &Path) -> (Student, Vec<f64>, Vec<f64>, Value) {
    export(scene, dir);
    let student = Student::read(dir);
    let lambda = student.forces();
    let c = student.primal(&lambda);
    let answer = dir.join("answer.json");
    std::fs::write(&answer, json!({ "lambda": lambda, "c": c }).to_string()).unwrap();
    let (out, doc) = grade(scene, &answer);
    assert_eq!(
        out.status.code(),
        Some(if doc["grade"]["verdict"] == "exact" {
            0
        } else {
            1
        })
    );
    (student, lambda, c, doc)
}

fn number(doc: &Value, path: &[&str]) -> f64 {
    path.iter()
        .fold(doc, |v, key| &v[key])
        .as_f64()
        .unwrap_or_else(|| panic!("{path:?} in {doc}"))
}

fn assert_exact(doc: &Value, reference: &str) {
    assert_eq!(doc["grade"]["verdict"], "exact", "{doc}");
    assert_eq!(doc["warnings"], json!([]), "{doc}");
    assert_eq!(doc["error"]["reference"], reference);
    assert!(number(doc, &["error", "max_rel"]) < 1e-11, "{doc}");
    assert!(number(doc, &["error", "slope_max_rel"]) < 1e-11, "{doc}");
    assert!(number(doc, &["kkt_residual"]) < 1e-12, "{doc}");
}

#[test]
fn benchmark_1_solved_outside_is_graded_exact_and_a_perturbation_by_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let (student, lambda, c, doc) = student_grade("benchmark-1", dir.path());
    assert_exact(&doc, "closed-form");
    // The paper's numbers: λ = (100, −4798.46…), u(x̂) = 5.70161e-3 m (slides, does not swivel).
    assert!((lambda[0] - 100.0).abs() < 1e-9 && (lambda[1] + 4798.461538461538).abs() < 1e-6);
    assert_eq!(doc["obstacles"][0]["state"]["sliding"], "moves");
    assert_eq!(doc["obstacles"][0]["state"]["swivel"], "stuck");
    let readme = std::fs::read_to_string(dir.path().join("README.md")).unwrap();
    for needle in ["DOF order", "(48)", "(49)", "(46)", "Sign of λ", "[N m]"] {
        assert!(readme.contains(needle), "README lacks {needle}");
    }

    // The nodal values moved by δ (a smooth bump, clamped ends kept): the error reported is δ.
    let n = c.len() / 2;
    let bump: Vec<f64> = (0..n)
        .map(|i| 1e-7 * ((i + 1) as f64 * std::f64::consts::PI / (n + 1) as f64).sin())
        .collect();
    let mut moved = c.clone();
    for (i, d) in bump.iter().enumerate() {
        moved[2 * i] += d;
    }
    let answer = dir.path().join("moved.json");
    std::fs::write(&answer, json!({ "c": moved }).to_string()).unwrap();
    let (out, doc) = grade("benchmark-1", &answer);
    assert_eq!(out.status.code(), Some(1));
    let largest = bump.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let reported = number(&doc, &["error", "max_abs"]);
    assert!(
        (reported - largest).abs() < 1e-3 * largest,
        "{reported:e} against {largest:e}"
    );
    assert_eq!(doc["grade"]["verdict"], "approximate");
    assert!(
        doc["warnings"].to_string().contains("accuracy-loss"),
        "{doc}"
    );

    // The stuck moment off by 10 N m, forces only: u is rebuilt from (48), and the error is
    // the effect of that force, A⁻¹ Bᵀ δλ, computed here.
    let mut pushed = lambda.clone();
    pushed[1] += 10.0;
    let effect = student.primal(&pushed);
    let expected = effect
        .iter()
        .zip(&c)
        .step_by(2)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let answer = dir.path().join("pushed.csv");
    std::fs::write(
        &answer,
        format!("force,moment\n{},{}\n", pushed[0], pushed[1]),
    )
    .unwrap();
    let (_, doc) = grade("benchmark-1", &answer);
    let reported = number(&doc, &["error", "max_abs"]);
    assert!(
        (reported - expected).abs() < 1e-6 * expected,
        "{reported:e} against {expected:e}"
    );
    assert_eq!(doc["answer"]["given"], "forces");
    assert!(
        number(&doc, &["kkt_residual"]) > 1e-6,
        "the swivel moves while stuck: {doc}"
    );
}

#[test]
fn benchmark_3_and_a_tiny_stiff_beam_solved_outside_are_graded_exact() {
    for (scene, reference) in [("benchmark-3", "condensed"), ("tiny-beam", "closed-form")] {
        let dir = tempfile::tempdir().unwrap();
        let (_, lambda, _, doc) = student_grade(scene, dir.path());
        assert_exact(&doc, reference);
        let obstacles = doc["obstacles"].as_array().unwrap();
        assert_eq!(obstacles.len() * 2, lambda.len());
        for (o, l) in obstacles.iter().zip(lambda.chunks(2)) {
            assert_eq!(o["force"].as_f64().unwrap(), l[0]);
            assert_eq!(o["moment"].as_f64().unwrap(), l[1]);
        }
    }
}

/// A segment 10⁶ times stiffer: A itself is rounded beyond what any solve of it can repair
/// (cond(D^-1/2 A D^-1/2) ≥ 4e13), so the student's dense solve is as good as the built-in
/// stiffness route and no better: graded approximate, with the conditioning named as the
/// cause and an error inside what the certificate predicts for it (0.1·cond·eps).
#[test]
fn a_stiff_insert_is_graded_with_the_rounding_of_the_exported_matrix() {
    let dir = tempfile::tempdir().unwrap();
    let (_, _, _, doc) = student_grade("modulus-contrast", dir.path());
    assert_eq!(doc["grade"]["verdict"], "approximate", "{doc}");
    let codes: Vec<&str> = doc["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["code"].as_str().unwrap())
        .collect();
    assert!(codes.contains(&"stiffness-conditioning"), "{codes:?}");
    for code in &codes {
        assert!(
            ["stiffness-conditioning", "kkt-residual", "accuracy-loss"].contains(code),
            "{codes:?}"
        );
    }
    let scaled = number(&doc, &["condition", "stiffness_scaled", "value"]);
    let error = number(&doc, &["error", "max_rel"]);
    assert!(
        error < 0.1 * scaled * f64::EPSILON,
        "{error:e} against cond {scaled:e}"
    );
    assert!(error > 1e-9, "rounding of A shows: {error:e}");
}

#[test]
fn the_json_that_solve_prints_is_graded_with_the_certificate_solve_printed() {
    let dir = tempfile::tempdir().unwrap();
    for scene in ["benchmark-1", "benchmark-3"] {
        let out = beamfric(&["solve", "--scene", scene, "--format", "json"]);
        assert!(out.status.success());
        let solved: Value = serde_json::from_slice(&out.stdout).unwrap();
        let answer = dir.path().join(format!("{scene}.json"));
        std::fs::write(&answer, &out.stdout).unwrap();
        let (out, graded) = grade(scene, &answer);
        assert_eq!(out.status.code(), Some(0));
        assert_eq!(graded["answer"]["given"], "forces and nodal values");
        for key in ["kkt_residual", "error", "obstacles", "warnings"] {
            assert_eq!(graded[key], solved[key], "{scene}: {key}");
        }
    }
}

fn refused(scene: &str, answer: &Path) -> String {
    let out = beamfric(&[
        "grade",
        "--scene",
        scene,
        "--answer",
        answer.to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(out.stdout.is_empty());
    let message = stderr(&out);
    assert_eq!(message.lines().count(), 1, "{message}");
    message
}

#[test]
fn malformed_answers_are_refused_naming_the_file_the_field_and_the_rule() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &str); 9] = [
        (
            "short.json",
            r#"{"lambda": [100]}"#,
            "lambda: has 1 values; it must have 2",
        ),
        (
            "nan.csv",
            "force,moment\n100,NaN\n",
            "row 1, column moment: is NaN: must be a finite number",
        ),
        (
            "null.json",
            r#"{"obstacles": [{"force": null, "moment": 1}]}"#,
            "obstacles[0].force: is null",
        ),
        (
            "missing.json",
            r#"{"obstacles": [{"force": 1}]}"#,
            "obstacles[0].moment: is missing",
        ),
        (
            "count.json",
            r#"{"obstacles": [{"force": 1, "moment": 2}, {"force": 1, "moment": 2}]}"#,
            "obstacles: has 2 entries; the scene has 1 obstacles",
        ),
        (
            "broken.json",
            r#"{"lambda": [1, 2"#,
            "(document): not valid JSON",
        ),
        (
            "mesh.json",
            r#"{"elements": 40, "lambda": [1, 2]}"#,
            "elements: the answer is on 40 elements, the scene's mesh has 20",
        ),
        (
            "nodes.csv",
            "u,slope\n0,0\n1,1\n",
            "rows: 2 rows under the header; there must be 21",
        ),
        (
            "header.csv",
            "lambda1,lambda2\n1,2\n",
            "header: is `lambda1,lambda2`",
        ),
    ];
    for (name, text, rule) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let message = refused("benchmark-1", &path);
        assert!(message.starts_with("beamfric: "), "{message}");
        assert!(
            message.contains(&format!("{}: {rule}", path.display())),
            "{name}: {message}"
        );
    }
    let absent = dir.path().join("absent.json");
    assert!(refused("benchmark-1", &absent).contains(&format!("cannot read {}", absent.display())));
    // Its help lists only the formats it takes (it listed solve's csv, then refused it).
    let help = beamfric(&["grade", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(!help.contains("csv:"), "{help}");
    let out = beamfric(&["grade", "--format", "csv", "--answer", "x.json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("[possible values: table, json]"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn an_answer_larger_than_the_scene_can_need_is_not_read_and_nothing_is_echoed_whole() {
    // Stop 58's hostile pass: a 200 MB CSV took 983 MB and 14.6 s before its row count was
    // refused, a 20 MB header came back in a 20 MB message, and 1e300 as 301 digits.
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.csv");
    let mut text = String::from("force,moment\n");
    text.push_str(&"1,2\n".repeat(1 << 19));
    std::fs::write(&big, &text).unwrap();
    let message = refused("benchmark-1", &big);
    assert!(
        message.contains(
            "(document): is larger than 1052736 bytes, more than any answer for \
             this scene needs (21 nodes, 1 obstacles); not read"
        ),
        "{message}"
    );
    let long = dir.path().join("long.csv");
    std::fs::write(&long, "1".repeat(200_000) + "\n1,2\n").unwrap();
    let message = refused("benchmark-1", &long);
    assert!(
        message.contains(&format!(
            "header: is `{}… (200000 characters)`",
            "1".repeat(40)
        )),
        "{message}"
    );
    assert!(message.len() < 400, "{message}");
    let clamped = dir.path().join("clamped.csv");
    std::fs::write(
        &clamped,
        "u,slope\n1e300,0\n".to_string() + &"0,0\n".repeat(20),
    )
    .unwrap();
    let message = refused("benchmark-1", &clamped);
    assert!(
        message.contains("row 1, column u: is 1e300: must be 0"),
        "{message}"
    );
    // Only a regular file is read (a FIFO would wait for a writer).
    #[cfg(unix)]
    {
        let fifo = dir.path().join("fifo.csv");
        nix::unistd::mkfifo(&fifo, nix::sys::stat::Mode::S_IRWXU).unwrap();
        let message = refused("benchmark-1", &fifo);
        assert!(message.contains("not a regular file"), "{message}");
    }
}

#[test]
fn export_refuses_to_replace_files_unless_forced_and_names_the_path_it_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir: PathBuf = dir.path().join("problem");
    export("benchmark-1", &out_dir);
    let again = beamfric(&[
        "export",
        "--scene",
        "benchmark-1",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(again.status.code(), Some(2));
    let message = stderr(&again);
    assert!(
        message.contains(&out_dir.join("stiffness_A.mtx").display().to_string()),
        "{message}"
    );
    assert!(message.contains("--force"), "{message}");
    let forced = beamfric(&[
        "export",
        "--scene",
        "benchmark-3",
        "--out",
        out_dir.to_str().unwrap(),
        "--force",
    ]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert_eq!(read_mtx(&out_dir.join("thresholds_g.mtx")).rows, 8);
    // No temporary file is left behind.
    let names = crate::harness::process::names(&out_dir);
    assert_eq!(names.len(), 8, "{names:?}");
    // A file where the directory should be.
    let blocked = dir.path().join("file");
    std::fs::write(&blocked, "x").unwrap();
    let inside = blocked.join("out");
    let out = beamfric(&["export", "--out", inside.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains(&format!("cannot write {}", inside.display())),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_failed_export_removes_the_files_it_wrote() {
    // A write that fails half-way (here the last file's place is taken by a directory; in
    // use, a disk that fills) leaves what was there before: none of the seven files written
    // before the failure stays behind, and the message names the file it could not write.
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("problem");
    std::fs::create_dir_all(out_dir.join("README.md").join("keep")).unwrap();
    let failed = beamfric(&[
        "export",
        "--scene",
        "benchmark-1",
        "--out",
        out_dir.to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(failed.status.code(), Some(2), "{}", stderr(&failed));
    assert!(
        stderr(&failed).contains(&out_dir.join("README.md").display().to_string()),
        "{}",
        stderr(&failed)
    );
    let names = crate::harness::process::names(&out_dir);
    assert_eq!(names, vec!["README.md".to_string()], "{names:?}");
    assert!(out_dir.join("README.md").join("keep").is_dir());
}
