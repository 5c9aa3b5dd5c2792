//! The certificate's check in dimensionless units: every scale (length, stiffness, load) a
//! power of two, so that loads of 1e-300 or 1e300 neither underflow to a zero residual nor
//! overflow, and the solution to be checked read in those units.

use crate::fem::{Mesh, NodalField};
use crate::model::Problem;

/// 2^k·x without intermediate overflow or underflow.
fn scaled(x: f64, k: i32) -> f64 {
    if (-500..=500).contains(&k) {
        // 2^k from its bits: the same exact factor as powi, without a call per value (this
        // runs for every node).
        return x * f64::from_bits(((k + 1023) as u64) << 52);
    }
    let mut value = x;
    let mut k = k;
    while k > 500 {
        value *= 2f64.powi(500);
        k -= 500;
    }
    while k < -500 {
        value *= 2f64.powi(-500);
        k += 500;
    }
    value * 2f64.powi(k)
}

/// The binary exponent of a positive finite x (0 for anything else).
fn exponent(x: f64) -> i32 {
    if x > 0.0 && x.is_finite() {
        x.log2().round() as i32
    } else {
        0
    }
}

/// Nodal values in dimensionless units: 2^exponent times the SI values, read through one exact
/// factor (or, when 2^exponent is not a normal number, a scaled copy).
pub(super) struct Dimensionless<'a> {
    values: std::borrow::Cow<'a, [f64]>,
    factor: f64,
}

impl<'a> Dimensionless<'a> {
    pub(super) fn new(values: &'a [f64], exponent: i32) -> Dimensionless<'a> {
        if (-1000..=1000).contains(&exponent) {
            Dimensionless {
                values: values.into(),
                factor: scaled(1.0, exponent),
            }
        } else {
            Dimensionless {
                values: values.iter().map(|&v| scaled(v, exponent)).collect(),
                factor: 1.0,
            }
        }
    }
    pub(super) fn at(&self, node: usize) -> f64 {
        self.values[node] * self.factor
    }
    /// The largest |value| over `nodes`.
    pub(super) fn largest(&self, nodes: std::ops::RangeInclusive<usize>) -> f64 {
        self.values[nodes]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            * self.factor
    }
    /// The values of `nodes` in SI units and the factor to dimensionless units.
    pub(super) fn raw(&self, nodes: std::ops::Range<usize>) -> (&[f64], f64) {
        (&self.values[nodes], self.factor)
    }
}

/// The problem in dimensionless units: every scale a power of two.
pub(super) struct Units {
    length: i32,
    stiffness: i32,
    load: i32,
}

impl Units {
    pub(super) fn of(problem: &Problem) -> Units {
        let l = problem.length;
        let ej = problem
            .stiffness
            .iter()
            .fold(0.0f64, |m, p| m.max(p.bending_stiffness));
        let f = problem.load.f0.abs().max(problem.load.f1.abs());
        let g = problem.obstacles.iter().fold(0.0f64, |m, o| {
            m.max(o.sliding_threshold / l)
                .max(o.swivel_threshold / (l * l))
        });
        let load = if f > 0.0 { f } else { g };
        Units {
            length: exponent(l),
            stiffness: exponent(ej),
            load: exponent(load),
        }
    }
    pub(super) fn x(&self, x: f64) -> f64 {
        scaled(x, -self.length)
    }
    pub(super) fn ej(&self, ej: f64) -> f64 {
        scaled(ej, -self.stiffness)
    }
    pub(super) fn f(&self, f: f64) -> f64 {
        scaled(f, -self.load)
    }
    pub(super) fn u_exponent(&self) -> i32 {
        self.stiffness - self.load - 4 * self.length
    }
    pub(super) fn slope_exponent(&self) -> i32 {
        self.stiffness - self.load - 3 * self.length
    }
    /// u over F L⁴ / EJ.
    pub(super) fn u(&self, u: f64) -> f64 {
        scaled(u, self.u_exponent())
    }
    /// u' over F L³ / EJ.
    pub(super) fn slope(&self, t: f64) -> f64 {
        scaled(t, self.slope_exponent())
    }
    /// λ1 over F L, λ2 over F L².
    pub(super) fn force(&self, v: f64, kind: usize) -> f64 {
        scaled(v, -self.load - (1 + kind as i32) * self.length)
    }
}

/// A relative residual: |r| / scale, in [0, 1]; 1 when the numbers overflowed.
pub(super) fn relative(r: f64, scale: f64) -> f64 {
    if !r.is_finite() || !scale.is_finite() {
        1.0
    } else if scale > 0.0 {
        (r.abs() / scale).min(1.0)
    } else {
        0.0
    }
}

/// The solution to be checked in dimensionless units, with the problem's thresholds and what
/// the SI values themselves can carry.
pub(super) struct DimensionlessSolution<'a> {
    pub(super) problem: &'a Problem,
    pub(super) mesh: &'a Mesh,
    pub(super) units: Units,
    /// u at the nodes, read through one exact factor (no copies of 10⁶ values: allocating
    /// them cost more than the check).
    pub(super) deflection: Dimensionless<'a>,
    /// u' at the nodes, likewise.
    pub(super) slope: Dimensionless<'a>,
    /// (λ1, λ2) per obstacle.
    pub(super) friction: Vec<[f64; 2]>,
    /// (g1, g2) per obstacle.
    pub(super) thresholds: Vec<[f64; 2]>,
    /// The smallest normal double as a deflection and as a slope: below it an SI value has
    /// fewer than 53 bits, so an absolute 2^-1022 is its rounding.
    pub(super) subnormal: [f64; 2],
    /// The same as a force and as a moment.
    pub(super) subnormal_force: [f64; 2],
}

impl<'a> DimensionlessSolution<'a> {
    /// The first stage of the check: `field` and `lambda` of `problem` on `mesh` in
    /// dimensionless units.
    pub(super) fn new(
        problem: &'a Problem,
        mesh: &'a Mesh,
        field: &'a NodalField,
        lambda: &[[f64; 2]],
    ) -> DimensionlessSolution<'a> {
        let units = Units::of(problem);
        let deflection = Dimensionless::new(&field.deflection, units.u_exponent());
        let slope = Dimensionless::new(&field.slope, units.slope_exponent());
        let friction: Vec<[f64; 2]> = lambda
            .iter()
            .map(|l| [units.force(l[0], 0), units.force(l[1], 1)])
            .collect();
        let thresholds: Vec<[f64; 2]> = problem
            .obstacles
            .iter()
            .map(|o| {
                [
                    units.force(o.sliding_threshold, 0),
                    units.force(o.swivel_threshold, 1),
                ]
                // A threshold past the largest double in these units (1e20 N against loads of
                // 1e-300) is one no force reaches: the largest double says the same without an
                // infinity that would make every scale infinite.
                .map(|g| g.min(f64::MAX))
            })
            .collect();
        // What the SI values themselves can carry: below the smallest normal double (2^-1022 m,
        // rad, N, N m) a value has fewer than 53 bits, so an absolute 2^-1022 is its rounding.
        let subnormal = [units.u(f64::MIN_POSITIVE), units.slope(f64::MIN_POSITIVE)];
        let subnormal_force = [
            units.force(f64::MIN_POSITIVE, 0),
            units.force(f64::MIN_POSITIVE, 1),
        ];
        DimensionlessSolution {
            problem,
            mesh,
            units,
            deflection,
            slope,
            friction,
            thresholds,
            subnormal,
            subnormal_force,
        }
    }

    /// The position of `node`.
    pub(super) fn x(&self, node: usize) -> f64 {
        self.units.x(self.mesh.nodes[node])
    }

    /// The load at `node`.
    pub(super) fn load_at(&self, node: usize) -> f64 {
        self.units.f(self.problem.load_at(self.mesh.nodes[node]))
    }
}
