//! 2D axisymmetric meshes of 4-node quadrilaterals in the `(r, z)` half-plane, `r >= 0`.

use super::Part;
use std::collections::BTreeMap;

/// Geometric grading of a structured direction: element sizes grow by a constant ratio so
/// that the last element is `ratio` times the first (1 = uniform).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grading {
    /// Size of the last element over the size of the first.
    pub ratio: f64,
}

impl Grading {
    /// Uniform spacing.
    pub const UNIFORM: Grading = Grading { ratio: 1.0 };

    /// `count + 1` node coordinates from `start` to `end`.
    pub fn positions(self, start: f64, end: f64, count: usize) -> Vec<f64> {
        let count = count.max(1);
        if (self.ratio - 1.0).abs() < 1e-12 || count == 1 {
            return (0..=count)
                .map(|i| {
                    if i == count {
                        end
                    } else {
                        start + (end - start) * i as f64 / count as f64
                    }
                })
                .collect();
        }
        // Element k has size h0 q^k with q^(count-1) = ratio.
        let q = libm::pow(self.ratio, 1.0 / (count as f64 - 1.0));
        let total: f64 = (0..count).map(|k| q.powi(k as i32)).sum();
        let mut positions = Vec::with_capacity(count + 1);
        let mut x = start;
        positions.push(x);
        for k in 0..count {
            x += (end - start) * q.powi(k as i32) / total;
            positions.push(if k + 1 == count { end } else { x });
        }
        positions
    }
}

/// A 2D axisymmetric mesh. Coordinates are `[r, z]` (m); element connectivity is
/// counter-clockwise in the `(r, z)` plane.
#[derive(Clone, Debug, Default)]
pub struct QuadMesh {
    /// Node coordinates `[r, z]`.
    pub nodes: Vec<[f64; 2]>,
    /// Element connectivity (counter-clockwise node indices).
    pub elements: Vec<[usize; 4]>,
    /// Part index of each element.
    pub element_part: Vec<usize>,
    /// Parts.
    pub parts: Vec<Part>,
    /// Named node sets.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named element sets.
    pub element_sets: BTreeMap<String, Vec<usize>>,
}

impl QuadMesh {
    /// A structured block `[r0, r1] x [z0, z1]` with `nr x nz` elements, as part `part`
    /// (material index `material`). Node sets `<part>.axis` (if `r0 = 0`), `<part>.bottom`,
    /// `<part>.top`, `<part>.outer`, `<part>.inner`; element set `<part>`.
    #[allow(clippy::too_many_arguments)]
    pub fn block(
        part: &str,
        material: usize,
        r: (f64, f64),
        z: (f64, f64),
        nr: usize,
        nz: usize,
        grading_r: Grading,
        grading_z: Grading,
    ) -> Self {
        Self::structured(
            part,
            material,
            &grading_r.positions(r.0, r.1, nr),
            &grading_z.positions(z.0, z.1, nz),
        )
    }

    /// A structured block on the node coordinates `rs` x `zs` (each strictly increasing,
    /// at least two), as part `part`, with the node and element sets of [`QuadMesh::block`].
    pub fn structured(part: &str, material: usize, rs: &[f64], zs: &[f64]) -> Self {
        let nr = rs.len().saturating_sub(1);
        let nz = zs.len().saturating_sub(1);
        let mut mesh = QuadMesh::default();
        for &zv in zs {
            for &rv in rs {
                mesh.nodes.push([rv, zv]);
            }
        }
        let node = |i: usize, j: usize| j * (nr + 1) + i;
        mesh.elements = super::structured_quads(nr, nz, node);
        mesh.element_part = vec![0; mesh.elements.len()];
        mesh.parts.push(Part {
            name: part.into(),
            material,
        });
        let mut set = |name: &str, nodes: Vec<usize>| {
            mesh.node_sets.insert(format!("{part}.{name}"), nodes);
        };
        set("bottom", (0..=nr).map(|i| node(i, 0)).collect());
        set("top", (0..=nr).map(|i| node(i, nz)).collect());
        set("outer", (0..=nz).map(|j| node(nr, j)).collect());
        set("inner", (0..=nz).map(|j| node(0, j)).collect());
        if rs.first() == Some(&0.0) {
            set("axis", (0..=nz).map(|j| node(0, j)).collect());
        }
        mesh.element_sets
            .insert(part.into(), (0..mesh.elements.len()).collect());
        mesh
    }

    /// Append `other` (its nodes are not merged: parts stay separate bodies).
    pub fn append(&mut self, other: QuadMesh) {
        let node_offset = self.nodes.len();
        let element_offset = self.elements.len();
        let part_offset = self.parts.len();
        self.nodes.extend(other.nodes);
        self.elements.extend(
            other
                .elements
                .into_iter()
                .map(|e| e.map(|n| n + node_offset)),
        );
        self.element_part
            .extend(other.element_part.into_iter().map(|p| p + part_offset));
        self.parts.extend(other.parts);
        for (name, nodes) in other.node_sets {
            self.node_sets
                .insert(name, nodes.into_iter().map(|n| n + node_offset).collect());
        }
        for (name, elements) in other.element_sets {
            self.element_sets.insert(
                name,
                elements.into_iter().map(|e| e + element_offset).collect(),
            );
        }
    }

    /// Area of element `e` in the `(r, z)` plane (positive for counter-clockwise).
    pub fn area(&self, e: usize) -> f64 {
        let [a, b, c, d] = self.elements[e].map(|n| self.nodes[n]);
        0.5 * ((c[0] - a[0]) * (d[1] - b[1]) - (d[0] - b[0]) * (c[1] - a[1]))
    }

    /// Shortest element edge of the mesh in the reference configuration (m).
    pub fn smallest_edge(&self) -> f64 {
        self.elements
            .iter()
            .flat_map(|element| {
                (0..4).map(move |k| {
                    let a = self.nodes[element[k]];
                    let b = self.nodes[element[(k + 1) % 4]];
                    libm::hypot(b[0] - a[0], b[1] - a[1])
                })
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// A node set by name.
    pub fn node_set(&self, name: &str) -> Option<&[usize]> {
        self.node_sets.get(name).map(Vec::as_slice)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_positions_span_the_interval_with_the_requested_ratio() {
        // GOAL: grading places nodes from start to end, last/first size = ratio.
        // SETUP: 10 elements on [0, 1], ratio 4. REFERENCE: exact endpoints, ratio 4 to 1e-12.
        let x = Grading { ratio: 4.0 }.positions(0.0, 1.0, 10);
        assert_eq!(x.len(), 11);
        assert_eq!(x[0], 0.0);
        assert_eq!(x[10], 1.0);
        let first = x[1] - x[0];
        let last = x[10] - x[9];
        assert!((last / first - 4.0).abs() < 1e-9);
    }

    #[test]
    fn block_has_positive_areas_and_node_sets() {
        // GOAL: counter-clockwise elements and the boundary sets exist.
        // SETUP: a 4 x 6 rod block. REFERENCE: area sum = r*L exactly (to round-off).
        let mesh = QuadMesh::block(
            "rod",
            0,
            (0.0, 2.0),
            (0.0, 3.0),
            4,
            6,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let total: f64 = (0..mesh.elements.len()).map(|e| mesh.area(e)).sum();
        assert!((total - 6.0).abs() < 1e-12);
        assert!((0..mesh.elements.len()).all(|e| mesh.area(e) > 0.0));
        assert_eq!(mesh.node_set("rod.axis").unwrap().len(), 7);
        assert_eq!(mesh.node_set("rod.bottom").unwrap().len(), 5);
    }
}
