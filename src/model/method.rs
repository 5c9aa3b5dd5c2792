//! The ways to solve the problem, named here at the bottom of the crate so that scenes,
//! the solver and the front ends share one list (docs/design.md section 3).

use std::fmt;

use serde::{Deserialize, Serialize};

/// A way to solve the problem (docs/design.md section 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Paper 2.7.1: regularise |·| by ω̃_ε (40), enumerate the 9^k cases of Table 1.
    Regularized,
    /// The same ε-problem by semismooth Newton (a few factorizations).
    RegularizedNewton,
    /// Paper 2.7.2 as written: the dual (49) with an explicit inverse of A.
    DualInverse,
    /// The dual (49) with S and z0 from one factorization of A.
    #[default]
    Dual,
    /// The force formulation: same discrete solution without the stiffness matrix.
    Flexibility,
    /// Paper (50)–(51): one obstacle, constant E, J and f.
    ClosedForm,
    /// Exact relations of each piece between special points (multiple shooting), the friction
    /// solved in the primal: stable on every scene, the reference that grades the others.
    Condensed,
}

impl Method {
    /// Every method, in the order the explorer cycles through them.
    pub const ALL: [Method; 7] = [
        Method::Dual,
        Method::Condensed,
        Method::Flexibility,
        Method::Regularized,
        Method::RegularizedNewton,
        Method::DualInverse,
        Method::ClosedForm,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Regularized => "regularized",
            Method::RegularizedNewton => "regularized-newton",
            Method::DualInverse => "dual-inverse",
            Method::Dual => "dual",
            Method::Flexibility => "flexibility",
            Method::ClosedForm => "closed-form",
            Method::Condensed => "condensed",
        }
    }

    /// What the method does, in one line (the command line's help lists it).
    pub fn description(self) -> &'static str {
        match self {
            Method::Regularized => {
                "Paper 2.7.1: regularise |·| by ω̃_ε (40), enumerate the 9^k cases of Table 1"
            }
            Method::RegularizedNewton => {
                "The same ε-problem by semismooth Newton (a few factorizations)"
            }
            Method::DualInverse => {
                "Paper 2.7.2 as written: the dual (49) with an explicit inverse of A"
            }
            Method::Dual => "The dual (49) with S and z0 from one factorization of A",
            Method::Flexibility => {
                "The force formulation: same discrete solution without the stiffness matrix"
            }
            Method::ClosedForm => "Paper (50)–(51): one obstacle, constant E, J and f",
            Method::Condensed => {
                "Exact piece relations (multiple shooting) and the friction in the primal: \
                 the stable reference"
            }
        }
    }

    /// Does the method work through the stiffness matrix A (and so inherit its conditioning)?
    pub fn uses_stiffness_matrix(self) -> bool {
        !matches!(
            self,
            Method::Flexibility | Method::ClosedForm | Method::Condensed
        )
    }

    /// Does the method solve the regularised problem (and so depend on ε)?
    pub fn is_regularized(self) -> bool {
        matches!(self, Method::Regularized | Method::RegularizedNewton)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_name_is_the_serialized_form() {
        for method in Method::ALL {
            let json = serde_json::to_value(method).unwrap();
            assert_eq!(json.as_str(), Some(method.name()));
        }
    }
}
