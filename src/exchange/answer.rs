//! Reading a student's answer for `beamfric grade`: friction forces λ of (45)/(48), nodal
//! values u and u', or both, as JSON or CSV (formats in `docs/bring-your-own-method.md` and
//! the README of an export). Every rule broken is an [`AnswerError`] that names the field and
//! the rule; nothing here panics on any input.
//!
//! JSON: an object with `lambda` (2k numbers, B's row order) or `obstacles` (k objects with
//! `force` [N] and `moment` [N m], the form `beamfric solve --format json` prints), and/or `c`
//! (N numbers, the DOF order of the export) or `nodes` (`u` [m] and `slope` [rad], n + 1 values
//! each, ends included and 0). `elements`, and `x` in `obstacles` and `nodes`, are checked
//! against the mesh when present; other fields are ignored.
//!
//! CSV, with a header line: `force,moment` (k rows) or `u,slope` (n + 1 rows), an optional
//! `x` column checked against the obstacles or the nodes.

use serde_json::{Map, Value};

use crate::fem::{Mesh, NodalField};
use crate::model::Problem;
use crate::solve::GivenAnswer;

/// A rule the answer breaks: the field (`lambda[3]`, `nodes.u`, `row 4, column moment`, …)
/// and the rule in words. The file is named by the caller.
#[derive(Debug, Clone, PartialEq)]
pub struct AnswerError {
    pub field: String,
    pub rule: String,
}

impl std::fmt::Display for AnswerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.rule)
    }
}

fn broken(field: impl Into<String>, rule: impl Into<String>) -> AnswerError {
    AnswerError {
        field: field.into(),
        rule: rule.into(),
    }
}

/// How an answer file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnswerFormat {
    Json,
    Csv,
}

impl AnswerFormat {
    /// By the file's extension (`.json`, `.csv`, any case), else by its first character that
    /// is not blank: `{` is JSON, anything else CSV.
    pub fn guess(path: &std::path::Path, text: &str) -> AnswerFormat {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => AnswerFormat::Json,
            Some(e) if e.eq_ignore_ascii_case("csv") => AnswerFormat::Csv,
            _ if text.trim_start().starts_with('{') => AnswerFormat::Json,
            _ => AnswerFormat::Csv,
        }
    }
}

/// What an answer must fit: the obstacle positions and the mesh's nodes [m].
#[derive(Debug, Clone, PartialEq)]
pub struct AnswerShape {
    pub obstacles: Vec<f64>,
    pub nodes: Vec<f64>,
}

impl AnswerShape {
    pub fn new(problem: &Problem, mesh: &Mesh) -> AnswerShape {
        AnswerShape {
            obstacles: problem.obstacles.iter().map(|o| o.x).collect(),
            nodes: mesh.nodes.clone(),
        }
    }

    fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// The largest answer file read for this scene: 1 MiB, and 64 bytes for every number
    /// the largest answer holds (x, u and u' of every node, force and moment of every
    /// obstacle) — an answer printed with 17 digits and indented, several times over.
    pub fn most_bytes(&self) -> u64 {
        let numbers = 3 * self.nodes.len() + 2 * self.obstacles.len();
        (1 << 20) + 64 * numbers as u64
    }

    /// Positions given in an answer must match to this [m] (1e-9 of the beam's length).
    fn position_tolerance(&self) -> f64 {
        1e-9 * self.nodes.last().copied().unwrap_or(1.0).abs()
    }
}

/// Parses an answer written as `format`.
pub fn parse_answer(
    text: &str,
    format: AnswerFormat,
    shape: &AnswerShape,
) -> Result<GivenAnswer, AnswerError> {
    match format {
        AnswerFormat::Json => parse_json(text, shape),
        AnswerFormat::Csv => parse_csv(text, shape),
    }
}

fn parse_json(text: &str, shape: &AnswerShape) -> Result<GivenAnswer, AnswerError> {
    let value: Value = serde_json::from_str(text)
        .map_err(|e| broken("(document)", format!("not valid JSON: {e}")))?;
    let Value::Object(object) = value else {
        return Err(broken(
            "(document)",
            "must be a JSON object with `lambda` or `obstacles`, and/or `c` or `nodes`",
        ));
    };
    if let Some(elements) = object.get("elements") {
        let given = elements.as_u64();
        if given != Some(shape.elements() as u64) {
            return Err(broken(
                "elements",
                format!(
                    "the answer is on {elements} elements, the scene's mesh has {}: grade with \
                     the same --elements the answer was computed on",
                    shape.elements()
                ),
            ));
        }
    }
    let forces = json_forces(&object, shape)?;
    let field = json_field(&object, shape)?;
    if forces.is_none() && field.is_none() {
        return Err(broken(
            "(document)",
            "gives no answer: expected `lambda` or `obstacles` (friction forces), and/or `c` \
             or `nodes` (nodal values)",
        ));
    }
    Ok(GivenAnswer { forces, field })
}

/// One of two alternative fields, not both.
fn one_of<'a>(
    object: &'a Map<String, Value>,
    names: [&'static str; 2],
) -> Result<Option<(&'static str, &'a Value)>, AnswerError> {
    match (object.get(names[0]), object.get(names[1])) {
        (Some(_), Some(_)) => Err(broken(
            names[1],
            format!("give either `{}` or `{}`, not both", names[0], names[1]),
        )),
        (Some(v), None) => Ok(Some((names[0], v))),
        (None, Some(v)) => Ok(Some((names[1], v))),
        (None, None) => Ok(None),
    }
}

/// A finite number.
fn number(value: &Value, field: &str) -> Result<f64, AnswerError> {
    match value {
        Value::Number(n) => n
            .as_f64()
            .filter(|v| v.is_finite())
            .ok_or_else(|| broken(field, "must be a finite number")),
        Value::Null => Err(broken(
            field,
            "is null: must be a finite number (null is how JSON writes a NaN or infinity)",
        )),
        other => Err(broken(
            field,
            format!("must be a finite number, not {}", kind(other)),
        )),
    }
}

/// A number in a message: plain from 1e-3 to 1e6, else in scientific notation (never the
/// 301 digits of 1e300 in plain decimals).
fn shown(value: f64) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Longest text of the answer a message quotes whole.
const QUOTED_CHARS: usize = 40;

/// Text from the answer in a message: at most [`QUOTED_CHARS`] characters, then how long it
/// was (a 20 MB line is not echoed back).
fn quoted(text: &str) -> String {
    let length = text.chars().count();
    if length <= QUOTED_CHARS {
        return text.to_string();
    }
    let start: String = text.chars().take(QUOTED_CHARS).collect();
    format!("{start}… ({length} characters)")
}

fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "true or false",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// An array of exactly `length` finite numbers.
fn numbers(value: &Value, field: &str, length: usize, what: &str) -> Result<Vec<f64>, AnswerError> {
    let Value::Array(items) = value else {
        return Err(broken(
            field,
            format!(
                "must be an array of {length} numbers ({what}), not {}",
                kind(value)
            ),
        ));
    };
    if items.len() != length {
        return Err(broken(
            field,
            format!("has {} values; it must have {length} ({what})", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, v)| number(v, &format!("{field}[{i}]")))
        .collect()
}

/// A position given in the answer matches the scene's.
fn check_position(
    given: f64,
    expected: f64,
    field: &str,
    tolerance: f64,
) -> Result<(), AnswerError> {
    if (given - expected).abs() <= tolerance {
        Ok(())
    } else {
        Err(broken(
            field,
            format!(
                "is {} m, but this scene has {} m there: the answer is for another scene or \
                 mesh",
                shown(given),
                shown(expected)
            ),
        ))
    }
}

fn json_forces(
    object: &Map<String, Value>,
    shape: &AnswerShape,
) -> Result<Option<Vec<[f64; 2]>>, AnswerError> {
    let k = shape.obstacles.len();
    match one_of(object, ["lambda", "obstacles"])? {
        None => Ok(None),
        Some(("lambda", value)) => {
            let what = format!("force and moment of each of the {k} obstacles");
            let flat = numbers(value, "lambda", 2 * k, &what)?;
            Ok(Some(flat.chunks(2).map(|c| [c[0], c[1]]).collect()))
        }
        Some((_, value)) => {
            let Value::Array(items) = value else {
                return Err(broken(
                    "obstacles",
                    format!("must be an array of {k} objects, not {}", kind(value)),
                ));
            };
            if items.len() != k {
                return Err(broken(
                    "obstacles",
                    format!("has {} entries; the scene has {k} obstacles", items.len()),
                ));
            }
            items
                .iter()
                .enumerate()
                .map(|(j, item)| obstacle_forces(item, j, shape))
                .collect::<Result<Vec<_>, _>>()
                .map(Some)
        }
    }
}

/// `{"force": λ1, "moment": λ2}` of obstacle `j` (`x` checked when present).
fn obstacle_forces(item: &Value, j: usize, shape: &AnswerShape) -> Result<[f64; 2], AnswerError> {
    let field = format!("obstacles[{j}]");
    let Value::Object(entry) = item else {
        return Err(broken(
            field,
            format!(
                "must be an object with `force` and `moment`, not {}",
                kind(item)
            ),
        ));
    };
    let get = |name: &str, unit: &str| {
        let path = format!("{field}.{name}");
        match entry.get(name) {
            Some(v) => number(v, &path),
            None => Err(broken(path, format!("is missing ({unit})"))),
        }
    };
    if let Some(x) = entry.get("x") {
        let path = format!("{field}.x");
        check_position(
            number(x, &path)?,
            shape.obstacles[j],
            &path,
            shape.position_tolerance(),
        )?;
    }
    Ok([
        get("force", "the friction force λ1 [N]")?,
        get("moment", "the friction moment λ2 [N m]")?,
    ])
}

fn json_field(
    object: &Map<String, Value>,
    shape: &AnswerShape,
) -> Result<Option<NodalField>, AnswerError> {
    let nodes = shape.nodes.len();
    match one_of(object, ["c", "nodes"])? {
        None => Ok(None),
        Some(("c", value)) => {
            let unknowns = 2 * (nodes - 2);
            let what = "u, u' of every interior node, the export's DOF order";
            let flat = numbers(value, "c", unknowns, what)?;
            let mut field = NodalField::zeros(nodes);
            for (i, pair) in flat.chunks(2).enumerate() {
                field.deflection[i + 1] = pair[0];
                field.slope[i + 1] = pair[1];
            }
            Ok(Some(field))
        }
        Some((_, value)) => {
            let Value::Object(entry) = value else {
                return Err(broken(
                    "nodes",
                    format!(
                        "must be an object with `u` and `slope`, not {}",
                        kind(value)
                    ),
                ));
            };
            let what = "one per node, ends included";
            let get = |name: &str| match entry.get(name) {
                Some(v) => numbers(v, &format!("nodes.{name}"), nodes, what),
                None => Err(broken(format!("nodes.{name}"), "is missing")),
            };
            if entry.contains_key("x") {
                let x = get("x")?;
                check_nodes(&x, shape, |i| format!("nodes.x[{i}]"))?;
            }
            let field = NodalField {
                deflection: get("u")?,
                slope: get("slope")?,
            };
            check_clamped(&field, |name, i| format!("nodes.{name}[{i}]"))?;
            Ok(Some(field))
        }
    }
}

/// Node positions given in the answer match the mesh.
fn check_nodes(
    x: &[f64],
    shape: &AnswerShape,
    field: impl Fn(usize) -> String,
) -> Result<(), AnswerError> {
    for (i, (&given, &expected)) in x.iter().zip(&shape.nodes).enumerate() {
        check_position(given, expected, &field(i), shape.position_tolerance())?;
    }
    Ok(())
}

/// u and u' are 0 at both clamped ends.
fn check_clamped(
    field: &NodalField,
    name: impl Fn(&str, usize) -> String,
) -> Result<(), AnswerError> {
    let last = field.deflection.len() - 1;
    for (label, values) in [("u", &field.deflection), ("slope", &field.slope)] {
        for i in [0, last] {
            if values[i] != 0.0 {
                return Err(broken(
                    name(label, i),
                    format!(
                        "is {}: must be 0, the end is clamped (u = u' = 0 at x = 0 and x = l)",
                        shown(values[i])
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn parse_csv(text: &str, shape: &AnswerShape) -> Result<GivenAnswer, AnswerError> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| broken("header", format!("not readable as CSV: {e}")))?
        .iter()
        .map(str::to_string)
        .collect();
    let column = |name: &str| header.iter().position(|h| h == name);
    let forces = column("force").is_some() || column("moment").is_some();
    let nodal = column("u").is_some() || column("slope").is_some();
    let (names, rows_wanted, what) = match (forces, nodal) {
        (true, false) => (
            ["force", "moment"],
            shape.obstacles.len(),
            "one per obstacle",
        ),
        (false, true) => (
            ["u", "slope"],
            shape.nodes.len(),
            "one per node, ends included",
        ),
        (true, true) => {
            return Err(broken(
                "header",
                "has both force/moment and u/slope columns: write forces and nodal values in \
                 two files, or both in one JSON answer",
            ));
        }
        (false, false) => {
            return Err(broken(
                "header",
                format!(
                    "is `{}`: the columns must be `force,moment` (friction forces) or \
                     `u,slope` (nodal values), optionally with `x`",
                    quoted(&header.join(","))
                ),
            ));
        }
    };
    let [first, second] = names.map(column);
    let (Some(first), Some(second)) = (first, second) else {
        return Err(broken(
            "header",
            format!("needs both `{}` and `{}` columns", names[0], names[1]),
        ));
    };
    let x_column = column("x");
    let mut values: Vec<[f64; 2]> = Vec::new();
    let mut positions = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let row = i + 1;
        let record =
            record.map_err(|e| broken(format!("row {row}"), format!("not readable: {e}")))?;
        let cell = |index: usize, name: &str| -> Result<f64, AnswerError> {
            let field = format!("row {row}, column {name}");
            let text = record
                .get(index)
                .ok_or_else(|| broken(field.clone(), "is missing"))?;
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                Ok(_) => Err(broken(
                    field,
                    format!("is {}: must be a finite number", quoted(text)),
                )),
                Err(_) => Err(broken(
                    field,
                    format!("is `{}`: must be a number", quoted(text)),
                )),
            }
        };
        values.push([cell(first, names[0])?, cell(second, names[1])?]);
        if let Some(x) = x_column {
            positions.push(cell(x, "x")?);
        }
    }
    if values.len() != rows_wanted {
        return Err(broken(
            "rows",
            format!(
                "{} rows under the header; there must be {rows_wanted} ({what})",
                values.len()
            ),
        ));
    }
    if forces {
        for (j, &x) in positions.iter().enumerate() {
            let field = format!("row {}, column x", j + 1);
            check_position(x, shape.obstacles[j], &field, shape.position_tolerance())?;
        }
        return Ok(GivenAnswer {
            forces: Some(values),
            field: None,
        });
    }
    check_nodes(&positions, shape, |i| format!("row {}, column x", i + 1))?;
    let field = NodalField {
        deflection: values.iter().map(|v| v[0]).collect(),
        slope: values.iter().map(|v| v[1]).collect(),
    };
    check_clamped(&field, |name, i| format!("row {}, column {name}", i + 1))?;
    Ok(GivenAnswer {
        forces: None,
        field: Some(field),
    })
}
