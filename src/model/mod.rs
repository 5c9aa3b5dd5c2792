//! The physical problem after validation: a clamped beam on [0, l], its bending stiffness
//! EJ(x) (piecewise constant), a linear load and the point obstacles with given friction.
//!
//! This is what the numerics read. It is built only by [`crate::scene::Scene::validate`], so
//! every `Problem` satisfies the rules listed there (positive length and stiffness, obstacles
//! strictly inside and apart, non-negative thresholds, finite values). Units are SI throughout:
//! l [m], EJ [N m²], f [N/m], sliding threshold g1 [N], swivel threshold g2 [N m] — the
//! symbols of the paper's (1)–(6) and (21).

mod method;

pub use method::Method;

/// A stretch of the beam with constant bending stiffness E·J.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StiffnessPiece {
    /// Start of the stretch [m].
    pub from: f64,
    /// End of the stretch [m].
    pub to: f64,
    /// E·J on the stretch [N m²].
    pub bending_stiffness: f64,
}

/// The load f(x) = f0 + (f1 − f0)·x/l [N/m], positive in the direction of positive u.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearLoad {
    /// f at x = 0 [N/m].
    pub f0: f64,
    /// f at x = l [N/m].
    pub f1: f64,
}

impl LinearLoad {
    /// Is the load the same everywhere?
    pub fn is_constant(&self) -> bool {
        self.f0 == self.f1
    }
}

/// A point obstacle with given friction (paper (3)–(6)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obstacle {
    /// Position x̂ [m], strictly inside (0, l).
    pub x: f64,
    /// Sliding threshold g1 [N]: the point moves once the shear jump reaches it.
    pub sliding_threshold: f64,
    /// Swivel threshold g2 [N m]: the point rotates once the moment jump reaches it.
    pub swivel_threshold: f64,
}

/// The validated problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Beam length l [m].
    pub length: f64,
    /// E·J on consecutive stretches covering [0, l] without gaps, ordered by position.
    pub stiffness: Vec<StiffnessPiece>,
    /// The distributed load.
    pub load: LinearLoad,
    /// Obstacles ordered by position.
    pub obstacles: Vec<Obstacle>,
}

impl Problem {
    /// f(x) [N/m], as f0·(l − x)/l + f1·x/l: each end's weight to a few ulps of itself (l − x
    /// is exact near x = l), so next to either support the load is accurate to its own size.
    /// The textbook f0 + (f1 − f0)·x/l loses digits there (f1 = 0 and x = l − 1e-9·l: 2e-7
    /// relative) and overflows when f1 − f0 does.
    pub fn load_at(&self, x: f64) -> f64 {
        let LinearLoad { f0, f1 } = self.load;
        if f0 == f1 {
            f0
        } else {
            f0 * ((self.length - x) / self.length) + f1 * (x / self.length)
        }
    }

    /// df/dx [N/m²].
    pub fn load_slope(&self) -> f64 {
        (self.load.f1 - self.load.f0) / self.length
    }

    /// E·J at x [N m²]; at a boundary between stretches, the stretch to the right.
    pub fn bending_stiffness_at(&self, x: f64) -> f64 {
        let index = self
            .stiffness
            .partition_point(|piece| piece.to <= x)
            .min(self.stiffness.len() - 1);
        self.stiffness[index].bending_stiffness
    }

    /// Is E·J the same along the whole beam?
    pub fn has_uniform_stiffness(&self) -> bool {
        let first = self.stiffness[0].bending_stiffness;
        self.stiffness.iter().all(|p| p.bending_stiffness == first)
    }

    /// Every point the mesh must have as a node: supports, obstacles and the ends of the
    /// stretches of constant E·J, ordered and without repetitions.
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut points = vec![0.0, self.length];
        points.extend(self.obstacles.iter().map(|o| o.x));
        for piece in &self.stiffness {
            points.push(piece.from);
            points.push(piece.to);
        }
        points.retain(|&x| (0.0..=self.length).contains(&x));
        points.sort_by(f64::total_cmp);
        points.dedup();
        points
    }

    /// The friction thresholds in the paper's order g = (g1, g2, g1, g2, …), one pair per
    /// obstacle (45).
    pub fn thresholds(&self) -> Vec<f64> {
        self.obstacles
            .iter()
            .flat_map(|o| [o.sliding_threshold, o.swivel_threshold])
            .collect()
    }
}
