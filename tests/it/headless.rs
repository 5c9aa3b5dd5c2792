//! Headless sweeps and reports (issue 4): CSV and JSON parse and have one row per requested
//! point; the ε sweep reproduces the paper's Figure 5; the report marks refusals and the
//! reference instead of printing numbers that mean nothing.

use std::process::Output;

use serde_json::Value;

use crate::harness::process::beamfric;

fn csv_rows(out: &Output) -> Vec<csv::StringRecord> {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Not a terminal: no progress bar, nothing on stderr.
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    csv::Reader::from_reader(out.stdout.as_slice())
        .records()
        .map(|r| r.expect("valid CSV"))
        .collect()
}

fn column(rows: &[csv::StringRecord], headers: &csv::StringRecord, name: &str) -> Vec<String> {
    let i = headers.iter().position(|h| h == name).expect(name);
    rows.iter().map(|r| r[i].to_string()).collect()
}

fn headers(out: &Output) -> csv::StringRecord {
    csv::Reader::from_reader(out.stdout.as_slice())
        .headers()
        .unwrap()
        .clone()
}

#[test]
fn epsilon_sweep_csv_and_json_have_one_row_per_point() {
    let out = beamfric(&[
        "sweep",
        "epsilon",
        "--scene",
        "benchmark-1",
        "--points",
        "9",
    ]);
    let rows = csv_rows(&out);
    assert_eq!(rows.len(), 9);
    let h = headers(&out);
    for name in [
        "epsilon",
        "max_rel",
        "mean_abs_m",
        "cond_max",
        "cond_scaled_max",
        "run_time_s",
    ] {
        assert!(h.iter().any(|x| x == name), "{name}");
    }
    let json = beamfric(&["sweep", "epsilon", "--points", "5", "--format", "json"]);
    let doc: Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(doc["points"].as_array().unwrap().len(), 5);
    assert_eq!(doc["method"], "regularized");
    assert!(doc["points"][0]["cond_max"]["value"].as_f64().unwrap() > 1e16);
}

#[test]
fn the_epsilon_sweep_reproduces_figure_5() {
    // Benchmark 1, n = 20, ε from 1e-12 to 1e-3.
    let out = beamfric(&[
        "sweep",
        "epsilon",
        "--scene",
        "benchmark-1",
        "--from",
        "1e-12",
        "--to",
        "1e-3",
        "--points",
        "10",
    ]);
    let rows = csv_rows(&out);
    let h = headers(&out);
    let number = |name: &str| -> Vec<f64> {
        column(&rows, &h, name)
            .iter()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let (eps, error, cond) = (number("epsilon"), number("mean_abs_m"), number("cond_max"));
    let at = |target: f64| {
        eps.iter()
            .position(|e| (e / target - 1.0).abs() < 1e-9)
            .unwrap()
    };
    let slope = |y: &[f64], from: f64, to: f64| -> f64 {
        (y[at(to)].log10() - y[at(from)].log10()) / (to.log10() - from.log10())
    };
    // Error falls linearly with ε over the whole range.
    let s = slope(&error, 1e-12, 1e-3);
    assert!((s - 1.0).abs() < 0.02, "error slope {s}");
    // The largest condition number rises like 1/ε while g/ε dominates cond(A) = 2.1e5.
    let s = slope(&cond, 1e-12, 1e-6);
    assert!((s + 1.0).abs() < 0.01, "cond slope {s}");
    // And the values of docs/design.md fact 4.
    assert!((cond[at(1e-12)] / 6.0e12 - 1.0).abs() < 0.02);
    assert!((cond[at(1e-5)] / 6.0e5 - 1.0).abs() < 0.02);
    assert!((error[at(1e-9)] / 1e-9 - 0.00879).abs() < 0.0003);
    // Every one of the nine case matrices was used.
    assert!(
        column(&rows, &h, "conditioned_cases")
            .iter()
            .all(|c| c == "9")
    );
}

#[test]
fn elements_sweep_has_one_row_per_method_and_size_and_marks_the_reference() {
    let out = beamfric(&[
        "sweep",
        "elements",
        "--scene",
        "benchmark-3",
        "--methods",
        "dual,flexibility,dual-inverse,closed-form",
        "--from",
        "10",
        "--to",
        "3000",
        "--points",
        "4",
        "--repeat",
        "1",
    ]);
    let rows = csv_rows(&out);
    assert_eq!(rows.len(), 4 * 4);
    let h = headers(&out);
    let (methods, status, max_rel) = (
        column(&rows, &h, "method"),
        column(&rows, &h, "status"),
        column(&rows, &h, "max_rel"),
    );
    for i in 0..rows.len() {
        match methods[i].as_str() {
            // No closed form for four obstacles: every row says why, with no numbers.
            "closed-form" => {
                assert!(status[i].starts_with("not applicable"), "{}", status[i]);
                assert!(max_rel[i].is_empty());
            }
            // The condensed method is the reference: marked, never an error of zero.
            "condensed" => {
                assert_eq!(status[i], "reference");
                assert!(max_rel[i].is_empty());
            }
            _ => {}
        }
    }
    // The dense inverse refuses at n = 3000 (N = 5998 > 4000), with a reason.
    let last_inverse = (0..rows.len())
        .rev()
        .find(|&i| methods[i] == "dual-inverse")
        .unwrap();
    assert!(
        status[last_inverse].starts_with("refused"),
        "{}",
        status[last_inverse]
    );
    let json = beamfric(&[
        "sweep",
        "elements",
        "--methods",
        "flexibility",
        "--points",
        "3",
        "--to",
        "1000",
        "--format",
        "json",
    ]);
    let doc: Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(doc["points"].as_array().unwrap().len(), 3);
}

#[test]
fn bad_sweep_arguments_are_one_line() {
    for (args, expected) in [
        (vec!["sweep", "epsilon", "--from", "0"], "--from = 0"),
        (
            vec!["sweep", "epsilon", "--from", "1", "--to", "1e-3"],
            "larger than --to",
        ),
        (
            vec!["sweep", "epsilon", "--method", "dual"],
            "needs regularized",
        ),
        (vec!["sweep", "elements", "--from", "0"], "--from = 0"),
        (vec!["sweep", "elements", "--repeat", "0"], "--repeat 0"),
        (
            vec!["sweep", "elements", "--methods", "fast"],
            "invalid value 'fast'",
        ),
    ] {
        let out = beamfric(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
    // Eight obstacles: the enumeration refuses the ε sweep and says what works.
    let out = beamfric(&[
        "sweep",
        "epsilon",
        "--scene",
        "eight-obstacles",
        "--points",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(3));
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("regularized-newton")
    );
    let newton = beamfric(&[
        "sweep",
        "epsilon",
        "--scene",
        "eight-obstacles",
        "--points",
        "3",
        "--method",
        "regularized-newton",
    ]);
    assert_eq!(csv_rows(&newton).len(), 3);
}

#[test]
fn the_report_writes_markdown_csv_and_svg_and_is_honest() {
    let dir = std::env::temp_dir().join(format!("beamfric-report-{}", std::process::id()));
    let out = beamfric(&[
        "report",
        "--scene",
        "benchmark-1",
        "--out",
        dir.to_str().unwrap(),
        "--to",
        "3000",
        "--points",
        "4",
        "--repeat",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for file in beamfric::report::FILES {
        assert!(dir.join(file).exists(), "{file}");
    }
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        md.contains("| n | dual | condensed | flexibility |"),
        "{md}"
    );
    // The closed form is the reference: its column says so (with its run time), with no
    // error of zero.
    assert!(md.contains("| reference · "), "{md}");
    assert!(!md.contains("| 0 · ") && !md.contains("| 0† · "), "{md}");
    // dual-inverse is refused at n = 3000 and the report says why instead of numbers.
    assert!(
        md.contains("refused [1]") && md.contains("[1] refused: the dense inverse"),
        "{md}"
    );
    // The chart as text and the figure.
    assert!(md.contains("Error vs run time") && md.contains("error-vs-time.svg"));
    let svg = std::fs::read_to_string(dir.join("error-vs-time.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("<circle"));
    let rows = csv::Reader::from_path(dir.join("mesh-sweep.csv"))
        .unwrap()
        .records()
        .count();
    assert_eq!(rows, beamfric::solve::Method::ALL.len() * 4);
    let rows = csv::Reader::from_path(dir.join("epsilon-sweep.csv"))
        .unwrap()
        .records()
        .count();
    assert_eq!(rows, 33);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_report_never_replaces_files_without_force() {
    let dir = std::env::temp_dir().join(format!("beamfric-report-force-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("report.md"), "mine").unwrap();
    let args = |force: bool| {
        let mut args = vec![
            "report",
            "--scene",
            "benchmark-1",
            "--out",
            dir.to_str().unwrap(),
            "--to",
            "100",
            "--points",
            "2",
            "--repeat",
            "1",
        ];
        if force {
            args.push("--force");
        }
        args
    };
    let out = beamfric(&args(false));
    assert!(!out.status.success());
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("report.md exists") && message.contains("--force"),
        "{message}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("report.md")).unwrap(),
        "mine"
    );
    let out = beamfric(&args(true));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::read_to_string(dir.join("report.md"))
            .unwrap()
            .starts_with("# ")
    );
    // Only the report's files: no temporary ones left.
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut expected: Vec<_> = beamfric::report::FILES
        .iter()
        .map(|f| f.to_string())
        .collect();
    expected.sort();
    assert_eq!(names, expected);
    std::fs::remove_dir_all(&dir).unwrap();
}
