//! The multi-precision number of the reference solver: a binary `dashu_float::FBig` with a
//! working precision chosen per solve, and the few helpers the solver needs (exact conversion
//! from f64, rounding back, absolute value, sign).
//!
//! dashu keeps the precision of a result as the larger of its operands' precisions, so every
//! input is converted with [`Mp::num`], which carries the working precision; constants made
//! any other way (an f64 converted bare has 53 bits) would silently lower it.

use dashu_float::FBig;
use dashu_float::round::mode::HalfEven;

/// A binary multi-precision float, rounded half to even.
pub type F = FBig<HalfEven, 2>;

/// Default working precision [bits]: 384 bits ≈ 115 decimal digits, enough for condition
/// numbers up to 1e60 with more than 50 digits to spare.
pub const DEFAULT_PRECISION: usize = 384;

/// The working precision of one solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mp {
    pub precision: usize,
}

impl Mp {
    /// An f64, converted exactly, carrying the working precision.
    pub fn num(&self, x: f64) -> F {
        assert!(
            x.is_finite(),
            "the reference takes finite inputs only, got {x}"
        );
        F::try_from(x)
            .expect("finite f64 converts")
            .with_precision(self.precision)
            .value()
    }

    /// Zero at the working precision.
    pub fn zero(&self) -> F {
        self.num(0.0)
    }

    /// The relative tolerance for "exactly zero" and "exactly at the bound": 2^(−precision/2),
    /// far above rounding (2^−precision times any reasonable condition number) and far below
    /// anything an f64 input can produce (2^−53 relative).
    pub fn tie_tolerance(&self) -> F {
        let half = i32::try_from(self.precision / 2).expect("precision fits i32");
        self.num(2f64.powi(-half))
    }
}

/// |x|.
pub fn abs(x: &F) -> F {
    if is_negative(x) {
        -x.clone()
    } else {
        x.clone()
    }
}

/// Is x < 0?
pub fn is_negative(x: &F) -> bool {
    *x < F::ZERO
}

/// Is x = 0?
pub fn is_zero(x: &F) -> bool {
    x.repr().significand().is_zero()
}

/// The nearest f64.
pub fn to_f64(x: &F) -> f64 {
    x.to_f64().value()
}

/// max |x_i| (zero for an empty slice).
pub fn max_abs<'a>(values: impl IntoIterator<Item = &'a F>, mp: &Mp) -> F {
    values
        .into_iter()
        .map(abs)
        .fold(mp.zero(), |a, b| if b > a { b } else { a })
}

impl Mp {
    /// A decimal literal, rounded once to the working precision.
    pub fn decimal(&self, text: &str) -> F {
        let value: FBig<HalfEven, 10> = text.parse().expect("a decimal number");
        value.with_base_and_precision::<2>(self.precision).value()
    }
}
