//! The answer parsers and the export texts on a small problem (Benchmark 1 on 4 elements).

use super::*;
use crate::fem::Mesh;
use crate::scene;

fn shape() -> (AnswerShape, crate::model::Problem, Mesh) {
    let loaded = scene::load("benchmark-1").unwrap();
    let mesh = Mesh::new(&loaded.problem, 5);
    (
        AnswerShape::new(&loaded.problem, &mesh),
        loaded.problem,
        mesh,
    )
}

fn json_error(text: &str) -> String {
    parse_answer(text, AnswerFormat::Json, &shape().0)
        .unwrap_err()
        .to_string()
}

fn csv_error(text: &str) -> String {
    parse_answer(text, AnswerFormat::Csv, &shape().0)
        .unwrap_err()
        .to_string()
}

#[test]
fn json_forms_of_the_forces_agree() {
    let (shape, ..) = shape();
    let flat = parse_answer(r#"{"lambda": [100, -4798.5]}"#, AnswerFormat::Json, &shape).unwrap();
    let objects = parse_answer(
        r#"{"obstacles": [{"x": 0.8, "force": 100, "moment": -4798.5, "state": "x"}], "elements": 5}"#,
        AnswerFormat::Json,
        &shape,
    )
    .unwrap();
    assert_eq!(flat, objects);
    assert_eq!(flat.forces, Some(vec![[100.0, -4798.5]]));
    assert!(flat.field.is_none());
}

#[test]
fn json_forms_of_the_nodal_values_agree() {
    let (shape, ..) = shape();
    assert_eq!(shape.nodes.len(), 6);
    let c: Vec<f64> = (1..=8).map(f64::from).collect();
    let flat = parse_answer(
        &serde_json::json!({ "c": c }).to_string(),
        AnswerFormat::Json,
        &shape,
    )
    .unwrap();
    let u = [0.0, 1.0, 3.0, 5.0, 7.0, 0.0];
    let slope = [0.0, 2.0, 4.0, 6.0, 8.0, 0.0];
    let nodes = parse_answer(
        &serde_json::json!({ "nodes": { "x": shape.nodes, "u": u, "slope": slope } }).to_string(),
        AnswerFormat::Json,
        &shape,
    )
    .unwrap();
    assert_eq!(flat, nodes);
    assert_eq!(flat.field.unwrap().deflection, u);
}

#[test]
fn malformed_json_names_the_field_and_the_rule() {
    let cases = [
        ("{", "(document): not valid JSON"),
        ("[1, 2]", "(document): must be a JSON object"),
        ("{}", "(document): gives no answer"),
        (r#"{"lambda": [1]}"#, "lambda: has 1 values; it must have 2"),
        (
            r#"{"lambda": [1, null]}"#,
            "lambda[1]: is null: must be a finite number",
        ),
        (
            r#"{"lambda": [1, "2"]}"#,
            "lambda[1]: must be a finite number, not a string",
        ),
        (
            r#"{"lambda": [1, 2], "obstacles": []}"#,
            "obstacles: give either `lambda` or `obstacles`",
        ),
        (
            r#"{"obstacles": []}"#,
            "obstacles: has 0 entries; the scene has 1 obstacles",
        ),
        (
            r#"{"obstacles": [{"force": 1}]}"#,
            "obstacles[0].moment: is missing",
        ),
        (
            r#"{"obstacles": [{"x": 0.5, "force": 1, "moment": 2}]}"#,
            "obstacles[0].x: is 0.5 m, but this scene has 0.8 m",
        ),
        (
            r#"{"elements": 20, "lambda": [1, 2]}"#,
            "elements: the answer is on 20 elements, the scene's mesh has 5",
        ),
        (r#"{"c": [1, 2, 3]}"#, "c: has 3 values; it must have 8"),
        (
            r#"{"nodes": {"u": [0, 1, 1, 1, 1, 0]}}"#,
            "nodes.slope: is missing",
        ),
        (
            r#"{"nodes": {"u": [1, 1, 1, 1, 1, 0], "slope": [0, 0, 0, 0, 0, 0]}}"#,
            "nodes.u[0]: is 1: must be 0, the end is clamped",
        ),
        (r#"{"lambda": [1, 1e999]}"#, "(document): not valid JSON"),
    ];
    for (text, expected) in cases {
        let message = json_error(text);
        assert!(message.starts_with(expected), "{text}: {message}");
    }
}

#[test]
fn csv_forms() {
    let (shape, ..) = shape();
    let forces = parse_answer(
        "x,force,moment\n0.8, 100, -4798.5\n",
        AnswerFormat::Csv,
        &shape,
    )
    .unwrap();
    assert_eq!(forces.forces, Some(vec![[100.0, -4798.5]]));
    let nodal = parse_answer(
        "u,slope\n0,0\n1,2\n3,4\n5,6\n7,8\n0,0\n",
        AnswerFormat::Csv,
        &shape,
    )
    .unwrap();
    assert_eq!(nodal.field.unwrap().slope, [0.0, 2.0, 4.0, 6.0, 8.0, 0.0]);
}

#[test]
fn malformed_csv_names_the_field_and_the_rule() {
    let cases = [
        (
            "a,b\n1,2\n",
            "header: is `a,b`: the columns must be `force,moment`",
        ),
        (
            "force\n1\n",
            "header: needs both `force` and `moment` columns",
        ),
        ("force,moment,u,slope\n1,2,3,4\n", "header: has both"),
        (
            "force,moment\n1,2\n3,4\n",
            "rows: 2 rows under the header; there must be 1",
        ),
        (
            "force,moment\n1,NaN\n",
            "row 1, column moment: is NaN: must be a finite number",
        ),
        (
            "force,moment\n1,abc\n",
            "row 1, column moment: is `abc`: must be a number",
        ),
        ("force,moment\n1\n", "row 1: not readable"),
        ("x,force,moment\n0.7,1,2\n", "row 1, column x: is 0.7 m"),
    ];
    for (text, expected) in cases {
        let message = csv_error(text);
        assert!(message.starts_with(expected), "{text:?}: {message}");
    }
}

#[test]
fn the_format_is_guessed_from_the_name_then_the_text() {
    use std::path::Path;
    assert_eq!(
        AnswerFormat::guess(Path::new("a.JSON"), "x"),
        AnswerFormat::Json
    );
    assert_eq!(
        AnswerFormat::guess(Path::new("a.csv"), "{"),
        AnswerFormat::Csv
    );
    assert_eq!(
        AnswerFormat::guess(Path::new("a"), " {"),
        AnswerFormat::Json
    );
    assert_eq!(
        AnswerFormat::guess(Path::new("a.txt"), "force"),
        AnswerFormat::Csv
    );
}

#[test]
fn the_matrix_market_texts_hold_the_assembled_matrix() {
    let (_, problem, mesh) = shape();
    let discrete = DiscreteProblem::new(&problem, &mesh);
    assert_eq!(discrete.unknowns, 8);
    let a = discrete.stiffness_mtx("t");
    let mut lines = a.lines();
    assert_eq!(
        lines.next(),
        Some("%%MatrixMarket matrix coordinate real symmetric")
    );
    let size = lines.find(|l| !l.starts_with('%')).unwrap();
    assert_eq!(size, format!("8 8 {}", discrete.stiffness_lower.len()));
    // Every entry reads back exactly and lies in the lower triangle.
    for (line, entry) in lines.zip(&discrete.stiffness_lower) {
        let parts: Vec<&str> = line.split(' ').collect();
        assert_eq!(parts[0].parse::<usize>().unwrap(), entry.row + 1);
        assert_eq!(parts[1].parse::<usize>().unwrap(), entry.col + 1);
        assert_eq!(parts[2].parse::<f64>().unwrap(), entry.value);
        assert!(entry.row >= entry.col);
    }
    // The obstacle at 0.8 is node 4 of 5 (uniform 0.2 m elements): DOFs 6 and 7.
    assert_eq!(discrete.friction_columns, [6, 7]);
    let b = discrete.friction_mtx("t");
    assert!(b.ends_with("2 8 2\n1 7 1\n2 8 1\n"), "{b}");
}
