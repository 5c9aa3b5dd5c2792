//! Finite elements (paper 2.4–2.6): the mesh with every obstacle and every end of a stretch of
//! constant E·J as a node, the Hermite cubic element, assembly of the stiffness matrix A and the
//! load vector b of (38), and evaluation of u, u', bending moment and shear at any x.
//!
//! Unknowns are numbered per interior node: node i (1 ≤ i ≤ n − 1) carries (u_i, u'_i), which
//! are the paper's c_{2i−1}, c_{2i}. The clamped ends carry none.

mod assembly;
mod conditioning;
mod element;
mod mesh;

pub use assembly::{StiffnessMatrix, kkt_stationarity, load_vector, load_vector_until};
pub use conditioning::{stiffness_condition_bounds, stiffness_condition_bounds_until};
pub use element::{element_load, element_stiffness, hermite_basis};
pub use mesh::{Mesh, MeshPiece};

/// A discrete solution on a mesh: u and u' at every node, ends included.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalField {
    /// u at the nodes [m].
    pub deflection: Vec<f64>,
    /// u' at the nodes [rad].
    pub slope: Vec<f64>,
}

/// A field of 10⁷ nodes is 160 MB: it is freed off the dropping thread (`linalg::release`),
/// so that a solve cancelled after its field was built returns at once.
impl Drop for NodalField {
    fn drop(&mut self) {
        crate::linalg::release::release(std::mem::take(&mut self.deflection));
        crate::linalg::release::release(std::mem::take(&mut self.slope));
    }
}

/// u, u', bending moment M = −EJ u'' and shear T = M' (the paper's sign convention, Appendix
/// A) of the finite-element solution at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointValues {
    /// u [m].
    pub deflection: f64,
    /// u' [rad].
    pub slope: f64,
    /// M = −EJ u'' [N m].
    pub moment: f64,
    /// T = −(EJ u'')' [N].
    pub shear: f64,
}

impl NodalField {
    /// A field of zeros on `nodes` nodes.
    pub fn zeros(nodes: usize) -> NodalField {
        NodalField {
            deflection: vec![0.0; nodes],
            slope: vec![0.0; nodes],
        }
    }

    /// The finite-element solution (Hermite interpolation of the nodal values) at x. On a node
    /// shared by two elements, moment and shear are taken from the element to the right (the
    /// last element at x = l).
    pub fn at(&self, mesh: &Mesh, x: f64) -> PointValues {
        let element = mesh.element_containing(x);
        let (a, b) = (mesh.nodes[element], mesh.nodes[element + 1]);
        let h = b - a;
        let ej = mesh.bending_stiffness_of_element(element);
        let (n, dn, ddn, dddn) = hermite_basis((x - a) / h, h);
        let dofs = [
            self.deflection[element],
            self.slope[element],
            self.deflection[element + 1],
            self.slope[element + 1],
        ];
        let dot = |w: [f64; 4]| w.iter().zip(dofs).map(|(w, c)| w * c).sum::<f64>();
        PointValues {
            deflection: dot(n),
            slope: dot(dn),
            moment: -ej * dot(ddn),
            shear: -ej * dot(dddn),
        }
    }
}
