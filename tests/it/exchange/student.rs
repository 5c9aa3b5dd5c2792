//! The student's side of the exchange test, written without the library: a small Matrix
//! Market reader, a dense Cholesky solve of A c = b − Bᵀλ (48), and the dual (49) by
//! enumerating every bound state of every friction DOF.

use std::path::Path;

use serde_json::Value;

/// A matrix read from a Matrix Market file, dense, row-major.
pub struct Dense {
    pub rows: usize,
    pub cols: usize,
    pub values: Vec<f64>,
}

impl Dense {
    fn at(&self, i: usize, j: usize) -> f64 {
        self.values[i * self.cols + j]
    }
}

/// A small Matrix Market reader: `coordinate real general|symmetric` and `array real general`.
pub fn read_mtx(path: &Path) -> Dense {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let banner: Vec<String> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(str::to_lowercase)
        .collect();
    assert_eq!(
        banner[..3],
        ["%%matrixmarket", "matrix", banner[2].as_str()]
    );
    let (layout, field, symmetry) = (&banner[2], &banner[3], &banner[4]);
    assert_eq!(field, "real");
    let mut data = lines.filter(|l| !l.starts_with('%') && !l.trim().is_empty());
    let size: Vec<usize> = data
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    let (rows, cols) = (size[0], size[1]);
    let mut values = vec![0.0; rows * cols];
    if layout == "array" {
        assert_eq!(symmetry, "general");
        // Column-major.
        for (index, line) in data.enumerate() {
            let (i, j) = (index % rows, index / rows);
            values[i * cols + j] = line.trim().parse().unwrap();
        }
    } else {
        let mut count = 0;
        for line in data {
            let parts: Vec<&str> = line.split_whitespace().collect();
            let i: usize = parts[0].parse::<usize>().unwrap() - 1;
            let j: usize = parts[1].parse::<usize>().unwrap() - 1;
            let v: f64 = parts[2].parse().unwrap();
            values[i * cols + j] = v;
            if symmetry == "symmetric" {
                assert!(i >= j, "a symmetric file lists the lower triangle");
                values[j * cols + i] = v;
            }
            count += 1;
        }
        assert_eq!(count, size[2]);
    }
    Dense { rows, cols, values }
}

/// Dense Cholesky factor L (row-major, lower) of an SPD matrix.
fn cholesky(a: &Dense) -> Vec<f64> {
    let n = a.rows;
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut d = a.at(j, j);
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        assert!(d > 0.0, "A is SPD");
        let d = d.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a.at(i, j);
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    l
}

/// Solves L Lᵀ x = b.
fn cholesky_solve(l: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut y = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            y[i] -= l[i * n + k] * y[k];
        }
        y[i] /= l[i * n + i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            y[i] -= l[k * n + i] * y[k];
        }
        y[i] /= l[i * n + i];
    }
    y
}

/// Gaussian elimination with partial pivoting on a small dense system (row-major).
fn small_solve(mut a: Vec<f64>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let pivot =
            (col..n).max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))?;
        if a[pivot * n + col] == 0.0 {
            return None;
        }
        for k in 0..n {
            a.swap(col * n + k, pivot * n + k);
        }
        b.swap(col, pivot);
        for row in col + 1..n {
            let factor = a[row * n + col] / a[col * n + col];
            for k in col..n {
                a[row * n + k] -= factor * a[col * n + k];
            }
            b[row] -= factor * b[col];
        }
    }
    for row in (0..n).rev() {
        for k in row + 1..n {
            b[row] -= a[row * n + k] * b[k];
        }
        b[row] /= a[row * n + row];
    }
    Some(b)
}

/// The exported problem, read back, and its solution by the student's method.
pub struct Student {
    a: Dense,
    b: Vec<f64>,
    /// The column of A each row of B picks.
    friction_columns: Vec<usize>,
    g: Vec<f64>,
    factor: Vec<f64>,
}

impl Student {
    pub fn read(dir: &Path) -> Student {
        let a = read_mtx(&dir.join("stiffness_A.mtx"));
        let b = read_mtx(&dir.join("load_b.mtx"));
        let friction = read_mtx(&dir.join("friction_B.mtx"));
        let g = read_mtx(&dir.join("thresholds_g.mtx"));
        assert_eq!(
            (a.rows, a.cols, b.rows, b.cols),
            (a.rows, a.rows, a.rows, 1)
        );
        assert_eq!(
            (friction.rows, friction.cols, g.rows),
            (g.rows, a.rows, g.rows)
        );
        let friction_columns: Vec<usize> = (0..friction.rows)
            .map(|r| {
                let ones: Vec<usize> = (0..friction.cols)
                    .filter(|&c| friction.at(r, c) != 0.0)
                    .collect();
                assert_eq!(ones.len(), 1);
                assert_eq!(friction.at(r, ones[0]), 1.0);
                ones[0]
            })
            .collect();
        let student = Student {
            factor: cholesky(&a),
            a,
            b: b.values,
            friction_columns,
            g: g.values,
        };
        student.agrees_with_the_json(&dir.join("problem.json"));
        student
    }

    /// problem.json holds the same numbers, bit for bit.
    fn agrees_with_the_json(&self, path: &Path) {
        let doc: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
        let n = self.a.rows;
        assert_eq!(doc["unknowns"], n);
        let floats = |v: &Value| -> Vec<f64> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        assert_eq!(floats(&doc["b"]), self.b);
        assert_eq!(floats(&doc["g"]), self.g);
        let cols: Vec<usize> = doc["B"]["col_of_row"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(cols, self.friction_columns);
        let mut dense = vec![0.0; n * n];
        let a = &doc["A"];
        for ((r, c), v) in a["row"]
            .as_array()
            .unwrap()
            .iter()
            .zip(a["col"].as_array().unwrap())
            .zip(floats(&a["value"]))
        {
            dense[r.as_u64().unwrap() as usize * n + c.as_u64().unwrap() as usize] = v;
        }
        assert_eq!(dense, self.a.values);
    }

    /// c = A⁻¹ (b − Bᵀλ) (48).
    pub fn primal(&self, lambda: &[f64]) -> Vec<f64> {
        let mut rhs = self.b.clone();
        for (&col, l) in self.friction_columns.iter().zip(lambda) {
            rhs[col] -= l;
        }
        cholesky_solve(&self.factor, &rhs)
    }

    /// S = B A⁻¹ Bᵀ and z0 = B A⁻¹ b of (49).
    fn dual(&self) -> (Vec<f64>, Vec<f64>) {
        let m = self.friction_columns.len();
        let n = self.a.rows;
        let mut s = vec![0.0; m * m];
        for (j, &col) in self.friction_columns.iter().enumerate() {
            let mut e = vec![0.0; n];
            e[col] = 1.0;
            let x = cholesky_solve(&self.factor, &e);
            for (i, &row) in self.friction_columns.iter().enumerate() {
                s[i * m + j] = x[row];
            }
        }
        let x = cholesky_solve(&self.factor, &self.b);
        let z0 = self.friction_columns.iter().map(|&r| x[r]).collect();
        (s, z0)
    }

    /// The box QP (49) by enumerating every state of every friction DOF (free, at +g, at −g):
    /// the pattern whose solution violates its conditions least (relative to the scales of
    /// λ and of the motions c_F = z0 − Sλ) is the solution.
    pub fn forces(&self) -> Vec<f64> {
        let (s, z0) = self.dual();
        let m = z0.len();
        let motion_scale = z0
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let mut best: Option<(f64, Vec<f64>)> = None;
        for pattern in 0..3usize.pow(m as u32) {
            let state: Vec<usize> = (0..m).map(|r| pattern / 3usize.pow(r as u32) % 3).collect();
            let mut lambda: Vec<f64> = (0..m)
                .map(|r| match state[r] {
                    1 => self.g[r],
                    2 => -self.g[r],
                    _ => 0.0,
                })
                .collect();
            let free: Vec<usize> = (0..m).filter(|&r| state[r] == 0).collect();
            if !free.is_empty() {
                let sub: Vec<f64> = free
                    .iter()
                    .flat_map(|&i| free.iter().map(move |&j| (i, j)))
                    .map(|(i, j)| s[i * m + j])
                    .collect();
                let rhs: Vec<f64> = free
                    .iter()
                    .map(|&i| {
                        z0[i]
                            - (0..m)
                                .filter(|j| state[*j] != 0)
                                .map(|j| s[i * m + j] * lambda[j])
                                .sum::<f64>()
                    })
                    .collect();
                let Some(values) = small_solve(sub, rhs) else {
                    continue;
                };
                for (&r, v) in free.iter().zip(values) {
                    lambda[r] = v;
                }
            }
            let motion: Vec<f64> = (0..m)
                .map(|i| z0[i] - (0..m).map(|j| s[i * m + j] * lambda[j]).sum::<f64>())
                .collect();
            let violation = (0..m)
                .map(|r| match state[r] {
                    0 => ((lambda[r].abs() - self.g[r]).max(0.0)
                        / self.g[r].max(f64::MIN_POSITIVE))
                    .max(0.0),
                    1 => (-motion[r]).max(0.0) / motion_scale,
                    _ => motion[r].max(0.0) / motion_scale,
                })
                .fold(0.0f64, f64::max);
            if best.as_ref().is_none_or(|(v, _)| violation < *v) {
                best = Some((violation, lambda));
            }
        }
        let (violation, lambda) = best.unwrap();
        assert!(violation < 1e-9, "no consistent pattern: {violation:e}");
        lambda
    }
}
