//! Double-double arithmetic: a number carried as an unevaluated sum hi + lo of two doubles
//! (about 106 bits), with the error-free transformations TwoSum and TwoProd (by fused
//! multiply–add). The `condensed` method uses it for the residual of its multiple-shooting
//! system, so that iterative refinement converges to the solution of the *exact* piece
//! relations of (1) on the given f64 data, not of their rounded coefficients (issue 10: a stuck
//! force 1e-8 of the shear around it, or a threshold met to one ulp, is decided right).
//!
//! Written here rather than taken from a crate: the few operations needed (sum, product,
//! quotient, comparison) are a page of textbook code (Dekker 1971; Hida, Li and Bailey's QD),
//! checked by the tests below against exact rational identities.

use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// hi + lo with |lo| ≤ ulp(hi)/2.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DoubleDouble {
    pub hi: f64,
    pub lo: f64,
}

/// a + b = s + e exactly (TwoSum, any order of magnitude).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let v = s - a;
    (s, (a - (s - v)) + (b - v))
}

/// a + b = s + e exactly when |a| ≥ |b| (FastTwoSum).
#[inline]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// a·b = p + e exactly (unless it underflows).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl From<f64> for DoubleDouble {
    #[inline]
    fn from(v: f64) -> DoubleDouble {
        DoubleDouble { hi: v, lo: 0.0 }
    }
}

impl DoubleDouble {
    pub const ZERO: DoubleDouble = DoubleDouble { hi: 0.0, lo: 0.0 };

    /// a − b exactly.
    #[inline]
    pub fn difference(a: f64, b: f64) -> DoubleDouble {
        let (hi, lo) = two_sum(a, -b);
        DoubleDouble { hi, lo }
    }

    /// a·b exactly.
    #[inline]
    pub fn product(a: f64, b: f64) -> DoubleDouble {
        let (hi, lo) = two_product(a, b);
        DoubleDouble { hi, lo }
    }

    /// Exactly zero (hi and lo; a normalised number with hi = 0 has lo = 0).
    #[inline]
    pub fn is_zero(self) -> bool {
        self.hi == 0.0 && self.lo == 0.0
    }

    /// The nearest double.
    #[inline]
    pub fn value(self) -> f64 {
        self.hi + self.lo
    }

    #[inline]
    pub fn abs(self) -> DoubleDouble {
        if self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0) {
            -self
        } else {
            self
        }
    }

    /// −1, 0 or +1.
    #[inline]
    pub fn signum(self) -> f64 {
        match self.cmp_zero() {
            Ordering::Less => -1.0,
            Ordering::Equal => 0.0,
            Ordering::Greater => 1.0,
        }
    }

    #[inline]
    fn cmp_zero(self) -> Ordering {
        let lead = if self.hi != 0.0 { self.hi } else { self.lo };
        lead.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }

    /// self + d for a double d.
    #[inline]
    pub fn plus(self, d: f64) -> DoubleDouble {
        let (s, e) = two_sum(self.hi, d);
        let (hi, lo) = fast_two_sum(s, e + self.lo);
        DoubleDouble { hi, lo }
    }

    /// self·d for a double d.
    #[inline]
    pub fn times(self, d: f64) -> DoubleDouble {
        let (p, e) = two_product(self.hi, d);
        let (hi, lo) = fast_two_sum(p, e + self.lo * d);
        DoubleDouble { hi, lo }
    }

    /// self·2^k-style exact scaling by a power of two `factor`.
    #[inline]
    pub fn scaled(self, factor: f64) -> DoubleDouble {
        DoubleDouble {
            hi: self.hi * factor,
            lo: self.lo * factor,
        }
    }
}

impl Neg for DoubleDouble {
    type Output = DoubleDouble;
    #[inline]
    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    /// The accurate ("IEEE") double-double sum.
    #[inline]
    fn add(self, other: DoubleDouble) -> DoubleDouble {
        let (s, e) = two_sum(self.hi, other.hi);
        let (t, f) = two_sum(self.lo, other.lo);
        let (s, e) = fast_two_sum(s, e + t);
        let (hi, lo) = fast_two_sum(s, e + f);
        DoubleDouble { hi, lo }
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    #[inline]
    fn sub(self, other: DoubleDouble) -> DoubleDouble {
        self + (-other)
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    #[inline]
    fn mul(self, other: DoubleDouble) -> DoubleDouble {
        let (p, e) = two_product(self.hi, other.hi);
        let e = e + (self.hi * other.lo + self.lo * other.hi);
        let (hi, lo) = fast_two_sum(p, e);
        DoubleDouble { hi, lo }
    }
}

impl Div for DoubleDouble {
    type Output = DoubleDouble;
    /// Long division: a first quotient, then one correction from the exact remainder.
    #[inline]
    fn div(self, other: DoubleDouble) -> DoubleDouble {
        let q1 = self.hi / other.hi;
        let remainder = self - other * DoubleDouble::from(q1);
        let q2 = remainder.hi / other.hi;
        let remainder = remainder - other * DoubleDouble::from(q2);
        let q3 = remainder.hi / other.hi;
        let (hi, lo) = fast_two_sum(q1, q2);
        DoubleDouble { hi, lo }.plus(q3)
    }
}

impl PartialOrd for DoubleDouble {
    #[inline]
    fn partial_cmp(&self, other: &DoubleDouble) -> Option<Ordering> {
        Some((*self - *other).cmp_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dd(v: f64) -> DoubleDouble {
        DoubleDouble::from(v)
    }

    #[test]
    fn sums_and_products_are_exact_where_doubles_round() {
        // 1 + 2⁻⁸⁰ is not a double; its difference with 1 is recovered exactly.
        let tiny = 2f64.powi(-80);
        let s = dd(1.0).plus(tiny);
        assert_eq!((s.hi, s.lo), (1.0, tiny));
        assert_eq!((s - dd(1.0)).value(), tiny);
        // (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ + 2⁻⁶⁰.
        let a = 1.0 + 2f64.powi(-30);
        let p = DoubleDouble::product(a, a);
        assert_eq!((p - dd(1.0) - dd(2f64.powi(-29))).value(), 2f64.powi(-60));
        assert_eq!(DoubleDouble::difference(0.3, 0.1).hi, 0.3 - 0.1);
        let d = DoubleDouble::difference(1e16, 1.0);
        assert_eq!((d.hi, d.lo), (1e16, -1.0));
    }

    #[test]
    fn one_third_times_three_is_one_to_106_bits() {
        let third = dd(1.0) / dd(3.0);
        let back = third * dd(3.0) - dd(1.0);
        assert!(back.value().abs() < 2f64.powi(-104), "{back:?}");
        // A quotient of double-doubles: (1 + 2⁻⁷⁰)/(1 + 2⁻⁷⁰) = 1.
        let x = dd(1.0).plus(2f64.powi(-70));
        let q = x / x;
        assert!((q - dd(1.0)).value().abs() < 2f64.powi(-104), "{q:?}");
    }

    #[test]
    fn comparison_and_sign_see_the_low_part() {
        let a = dd(1.0).plus(2f64.powi(-90));
        assert!(a > dd(1.0));
        assert!(-a < dd(-1.0));
        assert_eq!((a - dd(1.0)).signum(), 1.0);
        assert_eq!((dd(1.0) - a).signum(), -1.0);
        assert_eq!(DoubleDouble::ZERO.signum(), 0.0);
        assert_eq!((dd(-2.0).abs()).value(), 2.0);
        assert_eq!(dd(3.0).times(0.5).scaled(4.0).value(), 6.0);
    }
}
