//! The mesh of paper 2.4 on n elements: the supports, every obstacle and every end of a stretch
//! of constant E·J are nodes at their exact positions (no snapping), and the n elements are
//! shared among the pieces between those points in proportion to their length, uniform inside
//! each piece. An obstacle therefore moves continuously, and E·J is constant on every element,
//! which is what makes the nodal values exact (docs/design.md fact 1).

use crate::model::Problem;

/// A stretch between two consecutive special points, meshed uniformly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshPiece {
    /// Index of the first node of the piece.
    pub first_node: usize,
    /// Index of the last node of the piece (the first node of the next one).
    pub last_node: usize,
    /// E·J on the piece [N m²].
    pub bending_stiffness: f64,
}

impl MeshPiece {
    /// Number of elements in the piece.
    pub fn elements(&self) -> usize {
        self.last_node - self.first_node
    }
}

/// The mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Node positions x_0 = 0 < x_1 < … < x_n = l [m].
    pub nodes: Vec<f64>,
    /// The pieces between special points, in order.
    pub pieces: Vec<MeshPiece>,
    /// The node of each obstacle, in the problem's (position) order.
    pub obstacle_nodes: Vec<usize>,
    /// The piece each element belongs to (index into `pieces`).
    pub element_piece: Vec<u32>,
    /// The number of elements asked for; [`Mesh::elements`] is larger when there are more
    /// pieces than that (every piece needs at least one element).
    pub requested_elements: usize,
}

impl Mesh {
    /// Builds the mesh of `problem` on `elements` elements (at least one per piece).
    pub fn new(problem: &Problem, elements: usize) -> Mesh {
        let points = problem.breakpoints();
        let lengths: Vec<f64> = points.windows(2).map(|w| w[1] - w[0]).collect();
        let counts = share_elements(&lengths, problem.length, elements);
        let total: usize = counts.iter().sum();

        let mut nodes = Vec::with_capacity(total + 1);
        let mut pieces = Vec::with_capacity(counts.len());
        nodes.push(points[0]);
        for (p, &count) in counts.iter().enumerate() {
            let (a, b) = (points[p], points[p + 1]);
            let first_node = nodes.len() - 1;
            let step = (b - a) / count as f64;
            for j in 1..count {
                nodes.push(a + step * j as f64);
            }
            nodes.push(b);
            pieces.push(MeshPiece {
                first_node,
                last_node: nodes.len() - 1,
                bending_stiffness: problem.bending_stiffness_at(0.5 * (a + b)),
            });
        }
        let mut element_piece = Vec::with_capacity(total);
        for (p, piece) in pieces.iter().enumerate() {
            element_piece.extend(std::iter::repeat_n(p as u32, piece.elements()));
        }
        let obstacle_nodes = problem
            .obstacles
            .iter()
            .map(|o| {
                let p = points.partition_point(|&x| x < o.x);
                pieces
                    .get(p)
                    .map_or(nodes.len() - 1, |piece| piece.first_node)
            })
            .collect();
        Mesh {
            nodes,
            pieces,
            obstacle_nodes,
            element_piece,
            requested_elements: elements,
        }
    }

    /// Number of elements n.
    pub fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// Number of unknowns N = 2(n − 1) of (38).
    pub fn unknowns(&self) -> usize {
        2 * (self.nodes.len() - 2)
    }

    /// The beam length l [m].
    pub fn length(&self) -> f64 {
        self.nodes[self.nodes.len() - 1]
    }

    /// The element [x_e, x_{e+1}] that contains x (the last one for x = l; clamped to the beam).
    pub fn element_containing(&self, x: f64) -> usize {
        let e = self.nodes.partition_point(|&node| node <= x);
        e.saturating_sub(1).min(self.elements() - 1)
    }

    /// The piece that element `e` belongs to.
    pub fn piece_of_element(&self, e: usize) -> &MeshPiece {
        &self.pieces[self.element_piece[e] as usize]
    }

    /// The element length of a piece (its elements are all equally long) [m].
    pub fn element_length(&self, piece: &MeshPiece) -> f64 {
        (self.nodes[piece.last_node] - self.nodes[piece.first_node]) / piece.elements() as f64
    }

    /// E·J on element `e` [N m²].
    pub fn bending_stiffness_of_element(&self, e: usize) -> f64 {
        self.piece_of_element(e).bending_stiffness
    }
}

/// Shares `total` elements among pieces of the given lengths in proportion to their length,
/// at least one each (largest remainders first, ties to the earlier piece).
fn share_elements(lengths: &[f64], length: f64, total: usize) -> Vec<usize> {
    let pieces = lengths.len();
    if total <= pieces {
        return vec![1; pieces];
    }
    let ideal: Vec<f64> = lengths
        .iter()
        .map(|&len| len / length * total as f64)
        .collect();
    let mut counts: Vec<usize> = ideal.iter().map(|&x| (x.floor() as usize).max(1)).collect();
    let mut sum: usize = counts.iter().sum();
    let mut order: Vec<usize> = (0..pieces).collect();
    // Most under-served first.
    order.sort_by(|&a, &b| {
        let (ra, rb) = (ideal[a] - counts[a] as f64, ideal[b] - counts[b] as f64);
        rb.total_cmp(&ra).then(a.cmp(&b))
    });
    let mut k = 0;
    while sum < total {
        counts[order[k % pieces]] += 1;
        sum += 1;
        k += 1;
    }
    // Too many only when the minimum of one forced extra elements: take from the most
    // over-served pieces that can spare one.
    while sum > total {
        let p = (0..pieces)
            .filter(|&p| counts[p] > 1)
            .min_by(|&a, &b| {
                let (ra, rb) = (ideal[a] - counts[a] as f64, ideal[b] - counts[b] as f64);
                ra.total_cmp(&rb).then(a.cmp(&b))
            })
            .expect("total > pieces leaves a piece with more than one element");
        counts[p] -= 1;
        sum -= 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sharing_is_proportional_and_exact() {
        assert_eq!(share_elements(&[0.8, 0.2], 1.0, 20), vec![16, 4]);
        assert_eq!(share_elements(&[0.2; 5], 1.0, 20), vec![4; 5]);
        assert_eq!(share_elements(&[0.5, 0.5], 1.0, 1), vec![1, 1]);
        let counts = share_elements(&[1e-6, 0.5, 0.5 - 1e-6], 1.0, 10);
        assert_eq!(counts.iter().sum::<usize>(), 10);
        assert!(counts.iter().all(|&c| c >= 1));
        assert_eq!(counts[0], 1);
    }
}
