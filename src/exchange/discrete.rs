//! The discrete problem of a scene as plain numbers ([`DiscreteProblem`]): the stiffness
//! matrix A and load vector b of (36)–(39), the friction matrix B of (46) and the thresholds g
//! of (45), taken from the assembly every method uses (`fem`), and their Matrix Market and
//! JSON texts.
//!
//! DOF order: node i = 1 … n − 1 (the clamped ends 0 and n carry none) has u_i at 0-based
//! index 2(i − 1) and u'_i at 2(i − 1) + 1 — the paper's c_{2i−1}, c_{2i}. Friction DOFs: two
//! per obstacle in position order, deflection then rotation, so row 2j of B picks u and row
//! 2j + 1 picks u' at obstacle j's node (0-based).

use serde_json::{Value, json};

use crate::fem::{Mesh, StiffnessMatrix, load_vector};
use crate::linalg::BlockMatrix;
use crate::model::Problem;

/// One entry of a sparse matrix, 0-based.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    pub row: usize,
    pub col: usize,
    pub value: f64,
}

/// The objects of (38)–(49) for one scene on one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteProblem {
    /// N = 2(n − 1).
    pub unknowns: usize,
    /// A's nonzero entries on and below the diagonal (row ≥ col), by column, then row [N/m,
    /// N, N m: rows and columns of u carry 1/m relative to those of u'].
    pub stiffness_lower: Vec<Entry>,
    /// b (N values): ∫ f φ_i [N for a u row, N m for a u' row].
    pub load: Vec<f64>,
    /// The column of A (0-based DOF) that row r of B picks (2k values).
    pub friction_columns: Vec<usize>,
    /// g (2k values): g1 [N], g2 [N m] per obstacle.
    pub thresholds: Vec<f64>,
    /// Node positions x_0 … x_n [m].
    pub nodes: Vec<f64>,
    /// E·J of every element [N m²].
    pub element_bending_stiffness: Vec<f64>,
    /// The length of every element as A was assembled with it [m]: its piece's length over
    /// its number of elements (node differences may differ from it by rounding).
    pub element_lengths: Vec<f64>,
    /// The node of every obstacle.
    pub obstacle_nodes: Vec<usize>,
}

impl DiscreteProblem {
    /// Assembles A and b as the methods do ([`StiffnessMatrix`], [`load_vector`]).
    pub fn new(problem: &Problem, mesh: &Mesh) -> DiscreteProblem {
        let matrix = StiffnessMatrix::new(mesh);
        let blocks = matrix.blocks();
        let mut stiffness_lower = Vec::with_capacity(7 * blocks);
        let mut push = |row: usize, col: usize, value: f64| {
            if value != 0.0 {
                stiffness_lower.push(Entry { row, col, value });
            }
        };
        for i in 0..blocks {
            let d = matrix.diag(i);
            // Column 2i: the diagonal, the u' row of the same node, then the next node's rows
            // (block (i, i+1) transposed).
            push(2 * i, 2 * i, d[0]);
            push(2 * i + 1, 2 * i, d[1]);
            let upper = (i + 1 < blocks).then(|| matrix.upper(i));
            if let Some(u) = upper {
                push(2 * i + 2, 2 * i, u[0]);
                push(2 * i + 3, 2 * i, u[1]);
            }
            push(2 * i + 1, 2 * i + 1, d[2]);
            if let Some(u) = upper {
                push(2 * i + 2, 2 * i + 1, u[2]);
                push(2 * i + 3, 2 * i + 1, u[3]);
            }
        }
        let (load_u, load_slope) = load_vector(problem, mesh);
        let load = (1..mesh.elements())
            .flat_map(|node| [load_u[node], load_slope[node]])
            .collect();
        let friction_columns = mesh
            .obstacle_nodes
            .iter()
            .flat_map(|&node| [2 * (node - 1), 2 * (node - 1) + 1])
            .collect();
        DiscreteProblem {
            unknowns: mesh.unknowns(),
            stiffness_lower,
            load,
            friction_columns,
            thresholds: problem.thresholds(),
            nodes: mesh.nodes.clone(),
            element_bending_stiffness: (0..mesh.elements())
                .map(|e| mesh.bending_stiffness_of_element(e))
                .collect(),
            element_lengths: (0..mesh.elements())
                .map(|e| mesh.element_length(mesh.piece_of_element(e)))
                .collect(),
            obstacle_nodes: mesh.obstacle_nodes.clone(),
        }
    }

    /// A, both triangles, by column then row.
    pub fn stiffness_full(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self
            .stiffness_lower
            .iter()
            .flat_map(|e| {
                let mirror = (e.row != e.col).then_some(Entry {
                    row: e.col,
                    col: e.row,
                    value: e.value,
                });
                std::iter::once(*e).chain(mirror)
            })
            .collect();
        entries.sort_by_key(|e| (e.col, e.row));
        entries
    }

    /// A in Matrix Market: `coordinate real symmetric`, the lower triangle, 1-based.
    pub fn stiffness_mtx(&self, title: &str) -> String {
        let mut text = header(
            "coordinate real symmetric",
            title,
            "A of (38)-(39): a_ij = a(phi_i, phi_j), SPD",
        );
        text.push_str(&format!(
            "{} {} {}\n",
            self.unknowns,
            self.unknowns,
            self.stiffness_lower.len()
        ));
        for e in &self.stiffness_lower {
            text.push_str(&format!("{} {} {}\n", e.row + 1, e.col + 1, g17(e.value)));
        }
        text
    }

    /// B in Matrix Market: `coordinate real general`, 2k × N, one 1 per row.
    pub fn friction_mtx(&self, title: &str) -> String {
        let rows = self.friction_columns.len();
        let mut text = header(
            "coordinate real general",
            title,
            "B of (46): row 2j-1 picks u, row 2j picks u' at obstacle j (1-based)",
        );
        text.push_str(&format!("{rows} {} {rows}\n", self.unknowns));
        for (row, col) in self.friction_columns.iter().enumerate() {
            text.push_str(&format!("{} {} 1\n", row + 1, col + 1));
        }
        text
    }

    /// A column vector in Matrix Market: `array real general`, one value per line.
    pub fn vector_mtx(values: &[f64], title: &str, what: &str) -> String {
        let mut text = header("array real general", title, what);
        text.push_str(&format!("{} 1\n", values.len()));
        for v in values {
            text.push_str(&g17(*v));
            text.push('\n');
        }
        text
    }

    /// Everything in one JSON document (0-based indices; A with both triangles).
    pub fn to_json(&self, title: &str, source: &str) -> Value {
        let full = self.stiffness_full();
        let k = self.obstacle_nodes.len();
        json!({
            "format": "beamfric discrete problem",
            "version": 1,
            "scene": source,
            "title": title,
            "units": "SI: x [m], u [m], u' [rad], A [N/m, N, N m by row and column kind], \
                      b [N, N m], g and lambda [N, N m]",
            "elements": self.nodes.len() - 1,
            "unknowns": self.unknowns,
            "obstacles": k,
            "dof_order": "node i = 1..n-1: u_i at 2(i-1), u'_i at 2(i-1)+1 (0-based); \
                          clamped ends removed",
            "A": {
                "equation": "(38)-(39)",
                "rows": self.unknowns,
                "cols": self.unknowns,
                "row": full.iter().map(|e| e.row).collect::<Vec<_>>(),
                "col": full.iter().map(|e| e.col).collect::<Vec<_>>(),
                "value": full.iter().map(|e| e.value).collect::<Vec<_>>(),
            },
            "b": self.load,
            "B": {
                "equation": "(46)",
                "rows": 2 * k,
                "cols": self.unknowns,
                "col_of_row": self.friction_columns,
            },
            "g": self.thresholds,
            "mesh": {
                "nodes": self.nodes,
                "elements": (0..self.nodes.len() - 1).map(|e| [e, e + 1]).collect::<Vec<_>>(),
                "element_length": self.element_lengths,
                "bending_stiffness": self.element_bending_stiffness,
                "obstacle_nodes": self.obstacle_nodes,
            },
        })
    }
}

/// The header of a Matrix Market file with two comment lines.
fn header(kind: &str, title: &str, what: &str) -> String {
    let title: String = title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    format!("%%MatrixMarket matrix {kind}\n% beamfric export: {title}\n% {what}\n")
}

/// `v` as C's `printf("%.17g", v)`: 17 significant digits (every double reads back exactly),
/// fixed notation for decimal exponents −4 … 16, scientific otherwise, trailing zeros removed.
pub fn g17(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            "nan".into()
        } else if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0" } else { "0" }.into();
    }
    let scientific = format!("{v:.16e}");
    let (mantissa, exponent) = scientific
        .split_once('e')
        .expect("Rust's {:e} has an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    if (-4..17).contains(&exponent) {
        let decimals = (16 - exponent) as usize;
        strip_zeros(&format!("{v:.decimals$}"))
    } else {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!(
            "{}e{sign}{:02}",
            strip_zeros(mantissa),
            exponent.unsigned_abs()
        )
    }
}

/// Removes the trailing zeros of a decimal fraction, and its point if nothing follows it.
fn strip_zeros(text: &str) -> String {
    if !text.contains('.') {
        return text.to_string();
    }
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g17_prints_as_c_does() {
        // The strings of Python's '%.17g' % v (C's printf).
        let cases = [
            (0.1, "0.10000000000000001"),
            (100.0, "100"),
            (1e-5, "1.0000000000000001e-05"),
            (2.15e11, "215000000000"),
            (-4798.461538461539, "-4798.461538461539"),
            (1e17, "1e+17"),
            (1e16, "10000000000000000"),
            (0.0001, "0.0001"),
            (1.0 / 3.0, "0.33333333333333331"),
            (-2.5e-300, "-2.5e-300"),
            (5e4, "50000"),
            (123456.789, "123456.789"),
            (9.999999999999998e16, "99999999999999984"),
        ];
        for (v, c) in cases {
            assert_eq!(g17(v), c, "{v:e}");
            assert_eq!(g17(v).parse::<f64>().unwrap(), v);
        }
    }
}
