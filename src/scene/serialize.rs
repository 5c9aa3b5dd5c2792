//! The scene as TOML text, by serialization: serde turns the [`Scene`] into a `toml::Value`
//! tree (field order kept), and this module lays that tree out as a document. Strings are
//! encoded by the `toml` crate itself, so every title and description round-trips exactly,
//! whatever it contains (newlines, CR, NUL, DEL, ESC, any Unicode); numbers are written in
//! Rust's shortest round-trip form (exponent form outside [1e-3, 1e5)), so every f64 reads
//! back to the same bits, `-0.0` included. Nothing user-supplied ever goes into a comment.

use std::fmt::Write as _;

use toml::Value;

use super::Scene;

/// The only comment a saved scene carries: fixed text, so it cannot change the meaning.
pub const SAVED_HEADER: &str = "# Saved by beamfric (see README, \"Scenes\").\n";

/// The scene as a TOML document: top-level keys, then one `[table]` per section in the
/// order of the model (`beam`, `load`, `obstacle`, `mesh`, `solver`, `view`); sections
/// nested deeper (a cross-section) are inline tables, lists of tables are `[[…]]` blocks.
pub fn scene_to_toml(scene: &Scene) -> String {
    let value = Value::try_from(scene).expect("a scene always serializes");
    let Value::Table(root) = value else {
        unreachable!("a struct serializes to a table")
    };
    let mut out = String::new();
    write_table_body(&mut out, &[], &root);
    out
}

/// Whether a value is written as its own `[…]` / `[[…]]` block rather than `key = value`.
fn is_block(path_len: usize, value: &Value) -> bool {
    match value {
        // Only the top-level sections get headers; deeper tables stay inline (`section`).
        Value::Table(_) => path_len == 0,
        Value::Array(items) => !items.is_empty() && items.iter().all(Value::is_table),
        _ => false,
    }
}

fn write_table_body(out: &mut String, path: &[&str], table: &toml::Table) {
    for (key, value) in table {
        if !is_block(path.len(), value) {
            let _ = writeln!(out, "{} = {}", key_text(key), value_text(value));
        }
    }
    for (key, value) in table {
        if !is_block(path.len(), value) {
            continue;
        }
        let mut child: Vec<&str> = path.to_vec();
        child.push(key);
        let header = child
            .iter()
            .map(|k| key_text(k))
            .collect::<Vec<_>>()
            .join(".");
        match value {
            Value::Table(inner) => {
                let _ = writeln!(out, "\n[{header}]");
                write_table_body(out, &child, inner);
            }
            Value::Array(items) => {
                for item in items {
                    let _ = writeln!(out, "\n[[{header}]]");
                    if let Value::Table(inner) = item {
                        write_table_body(out, &child, inner);
                    }
                }
            }
            _ => unreachable!("blocks are tables or arrays of tables"),
        }
    }
}

/// A key: bare when TOML allows it, else a quoted string encoded by `toml`.
fn key_text(key: &str) -> String {
    let bare = !key.is_empty()
        && key
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
    if bare {
        key.to_string()
    } else {
        Value::String(key.to_string()).to_string()
    }
}

/// A value in `key = value` position (inline tables and arrays included).
fn value_text(value: &Value) -> String {
    match value {
        Value::Float(v) => float_text(*v),
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(value_text).collect();
            format!("[{}]", items.join(", "))
        }
        Value::Table(table) => {
            if table.is_empty() {
                return "{}".to_string();
            }
            let entries: Vec<String> = table
                .iter()
                .map(|(k, v)| format!("{} = {}", key_text(k), value_text(v)))
                .collect();
            format!("{{ {} }}", entries.join(", "))
        }
        // Strings, integers, booleans, datetimes: the `toml` crate's own encoding.
        other => other.to_string(),
    }
}

/// An f64 as TOML that reads back to the same bits: Rust's shortest round-trip digits, plain
/// for magnitudes in [1e-3, 1e5) (`0.02`, `50.0`), exponent form otherwise (`2.15e11`,
/// `1e-6`); `-0.0`, `inf`, `-inf`, `nan` for the special values.
pub fn float_text(v: f64) -> String {
    if v.is_nan() {
        return "nan".to_string();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0.0" } else { "0.0" }.to_string();
    }
    let magnitude = v.abs();
    if (1e-3..1e5).contains(&magnitude) {
        let text = format!("{v}");
        if text.contains('.') {
            text
        } else {
            format!("{text}.0")
        }
    } else {
        // `{:e}` gives the shortest digits that round-trip, e.g. `2.15e11`, `5e-324`; TOML
        // accepts an exponent without a fraction.
        format!("{v:e}")
    }
}
