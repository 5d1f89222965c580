//! 3D meshes of 8-node hexahedra.

use super::Part;
use std::collections::BTreeMap;

/// A 3D hexahedral mesh. Coordinates `[x, y, z]` (m); connectivity in the usual order (bottom
/// face counter-clockwise seen from +z, then the top face).
#[derive(Clone, Debug, Default)]
pub struct HexMesh {
    /// Node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Element connectivity.
    pub elements: Vec<[usize; 8]>,
    /// Part index of each element.
    pub element_part: Vec<usize>,
    /// Parts.
    pub parts: Vec<Part>,
    /// Named node sets.
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

impl HexMesh {
    /// Quarter-symmetric circular rod of radius `radius` and length `length` along `z`,
    /// starting at `z = 0`: an O-grid of `core` x `core` elements in the square core and
    /// `rings` rings outside it in each quadrant, `axial` elements along `z`. Node sets
    /// `<part>.x0` (plane x = 0), `<part>.y0` (plane y = 0), `<part>.bottom`, `<part>.top`,
    /// `<part>.outer`.
    pub fn quarter_rod(
        part: &str,
        material: usize,
        radius: f64,
        length: f64,
        core: usize,
        rings: usize,
        axial: usize,
    ) -> Self {
        // Cross-section nodes of the quarter disc.
        let mut section: Vec<[f64; 2]> = Vec::new();
        let core_half = 0.5 * radius;
        let index_core = |i: usize, j: usize| j * (core + 1) + i;
        for j in 0..=core {
            for i in 0..=core {
                section.push([
                    core_half * i as f64 / core as f64,
                    core_half * j as f64 / core as f64,
                ]);
            }
        }
        // Boundary of the core square from (core_half, 0) up to the corner and over to
        // (0, core_half): 2*core + 1 points, matched to points on the circle.
        let mut core_boundary = Vec::new();
        for j in 0..=core {
            core_boundary.push(index_core(core, j));
        }
        for i in (0..core).rev() {
            core_boundary.push(index_core(i, core));
        }
        let boundary_count = core_boundary.len();
        let mut ring_nodes: Vec<Vec<usize>> = vec![core_boundary.clone()];
        for ring in 1..=rings {
            let fraction = ring as f64 / rings as f64;
            let mut layer = Vec::with_capacity(boundary_count);
            for (k, &inner) in core_boundary.iter().enumerate() {
                let angle = std::f64::consts::FRAC_PI_2 * k as f64 / (boundary_count - 1) as f64;
                let on_circle = [radius * libm::cos(angle), radius * libm::sin(angle)];
                let start = section[inner];
                let point = [
                    start[0] + (on_circle[0] - start[0]) * fraction,
                    start[1] + (on_circle[1] - start[1]) * fraction,
                ];
                section.push(point);
                layer.push(section.len() - 1);
            }
            ring_nodes.push(layer);
        }
        let mut quads = super::structured_quads(core, core, index_core);
        for ring in 0..rings {
            for k in 0..boundary_count - 1 {
                let inner = &ring_nodes[ring];
                let outer = &ring_nodes[ring + 1];
                quads.push([inner[k], outer[k], outer[k + 1], inner[k + 1]]);
            }
        }
        let per_layer = section.len();
        let mut mesh = HexMesh::default();
        for layer in 0..=axial {
            let z = if layer == axial {
                length
            } else {
                length * layer as f64 / axial as f64
            };
            for p in &section {
                mesh.nodes.push([p[0], p[1], z]);
            }
        }
        for layer in 0..axial {
            for q in &quads {
                let bottom = q.map(|n| n + layer * per_layer);
                let top = q.map(|n| n + (layer + 1) * per_layer);
                mesh.elements.push([
                    bottom[0], bottom[1], bottom[2], bottom[3], top[0], top[1], top[2], top[3],
                ]);
                mesh.element_part.push(0);
            }
        }
        mesh.parts.push(Part {
            name: part.into(),
            material,
        });
        let tolerance = 1e-9 * radius;
        let select = |mesh: &HexMesh, test: &dyn Fn(&[f64; 3]) -> bool| -> Vec<usize> {
            (0..mesh.nodes.len())
                .filter(|&n| test(&mesh.nodes[n]))
                .collect()
        };
        let x0 = select(&mesh, &|p| p[0].abs() < tolerance);
        let y0 = select(&mesh, &|p| p[1].abs() < tolerance);
        let bottom = select(&mesh, &|p| p[2].abs() < tolerance);
        let top = select(&mesh, &|p| (p[2] - length).abs() < tolerance);
        let outer = select(&mesh, &|p| {
            ((p[0] * p[0] + p[1] * p[1]).sqrt() - radius).abs() < 1e-6 * radius
        });
        for (name, set) in [
            ("x0", x0),
            ("y0", y0),
            ("bottom", bottom),
            ("top", top),
            ("outer", outer),
        ] {
            mesh.node_sets.insert(format!("{part}.{name}"), set);
        }
        mesh
    }

    /// Rectangular block `[0, lx] x [0, ly] x [0, lz]` of `nx x ny x nz` equal elements
    /// (`extent` = `[lx, ly, lz]`, `divisions` = `[nx, ny, nz]`); see [`HexMesh::block_on_planes`].
    pub fn block(part: &str, material: usize, extent: [f64; 3], divisions: [usize; 3]) -> Self {
        let planes = |axis: usize| -> Vec<f64> {
            let count = divisions[axis];
            (0..=count)
                .map(|i| extent[axis] * i as f64 / count as f64)
                .collect()
        };
        Self::block_on_planes(part, material, [&planes(0), &planes(1), &planes(2)])
    }

    /// The structured block between the given node planes (`planes[axis]` increasing, at
    /// least two per axis), nodes numbered x fastest, then y, then z. Node sets `<part>.x0`,
    /// `<part>.x1`, `<part>.y0`, `<part>.y1`, `<part>.z0`, `<part>.z1` (the six faces).
    pub fn block_on_planes(part: &str, material: usize, planes: [&[f64]; 3]) -> Self {
        let [xs, ys, zs] = planes;
        let (nx, ny, nz) = (
            xs.len().saturating_sub(1),
            ys.len().saturating_sub(1),
            zs.len().saturating_sub(1),
        );
        let node = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
        let mut mesh = HexMesh {
            parts: vec![Part {
                name: part.to_string(),
                material,
            }],
            ..HexMesh::default()
        };
        for &z in zs {
            for &y in ys {
                for &x in xs {
                    mesh.nodes.push([x, y, z]);
                }
            }
        }
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    mesh.elements.push([
                        node(i, j, k),
                        node(i + 1, j, k),
                        node(i + 1, j + 1, k),
                        node(i, j + 1, k),
                        node(i, j, k + 1),
                        node(i + 1, j, k + 1),
                        node(i + 1, j + 1, k + 1),
                        node(i, j + 1, k + 1),
                    ]);
                    mesh.element_part.push(0);
                }
            }
        }
        let divisions = [nx, ny, nz];
        for (axis, count) in divisions.iter().enumerate() {
            let name = ["x", "y", "z"][axis];
            for (end, index) in [("0", 0), ("1", *count)] {
                let set = (0..=nz)
                    .flat_map(|k| (0..=ny).flat_map(move |j| (0..=nx).map(move |i| [i, j, k])))
                    .filter(|ijk| ijk[axis] == index)
                    .map(|[i, j, k]| node(i, j, k))
                    .collect();
                mesh.node_sets.insert(format!("{part}.{name}{end}"), set);
            }
        }
        mesh
    }

    /// Join `other` to this mesh, merging each of its nodes that lies within `tolerance` of
    /// one of this mesh's nodes (the merged-node coupling of a tied interface, LS-DYNA's
    /// coincident nodes): its parts, elements and node sets are renumbered after this mesh's;
    /// its parts' materials are kept. Returns the number of merged nodes.
    pub fn merge(&mut self, other: HexMesh, tolerance: f64) -> usize {
        self.join(other, Some(tolerance))
    }

    /// Join `other` to this mesh without merging any node (two bodies that may touch but are
    /// not tied): as [`HexMesh::merge`], every node of `other` a new one.
    pub fn append(&mut self, other: HexMesh) {
        self.join(other, None);
    }

    fn join(&mut self, other: HexMesh, tolerance: Option<f64>) -> usize {
        let tolerance = tolerance.unwrap_or(-1.0);
        let cell = |p: &[f64; 3]| {
            if tolerance > 0.0 {
                p.map(|c| libm::floor(c / tolerance) as i64)
            } else {
                [0; 3]
            }
        };
        let mut grid: BTreeMap<[i64; 3], Vec<usize>> = BTreeMap::new();
        if tolerance >= 0.0 {
            for (n, p) in self.nodes.iter().enumerate() {
                grid.entry(cell(p)).or_default().push(n);
            }
        }
        let close = |a: &[f64; 3], b: &[f64; 3]| (0..3).all(|d| (a[d] - b[d]).abs() <= tolerance);
        let mut merged = 0;
        let mut renumber = Vec::with_capacity(other.nodes.len());
        for p in &other.nodes {
            let home = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = [home[0] + dx, home[1] + dy, home[2] + dz];
                        if let Some(candidates) = grid.get(&key) {
                            if let Some(&n) = candidates.iter().find(|&&n| close(&self.nodes[n], p))
                            {
                                found = Some(n);
                                break 'search;
                            }
                        }
                    }
                }
            }
            renumber.push(match found {
                Some(n) => {
                    merged += 1;
                    n
                }
                None => {
                    self.nodes.push(*p);
                    self.nodes.len() - 1
                }
            });
        }
        let part_offset = self.parts.len();
        self.parts.extend(other.parts);
        self.elements.extend(
            other
                .elements
                .iter()
                .map(|element| element.map(|n| renumber[n])),
        );
        self.element_part
            .extend(other.element_part.iter().map(|p| p + part_offset));
        for (name, set) in other.node_sets {
            self.node_sets
                .insert(name, set.iter().map(|&n| renumber[n]).collect());
        }
        merged
    }

    /// The element sizes of a structured direction: planes through every coordinate of
    /// `fixed` (sorted, duplicates within `1e-9` of the span dropped; the first and last are
    /// the direction's ends), each interval between two of them cut into the fewest equal
    /// elements no longer than `size_at` its midpoint.
    pub fn planes_through(fixed: &[f64], size_at: impl Fn(f64) -> f64) -> Vec<f64> {
        let mut fixed: Vec<f64> = fixed.to_vec();
        fixed.sort_by(f64::total_cmp);
        let span = fixed.last().copied().unwrap_or(0.0) - fixed.first().copied().unwrap_or(0.0);
        fixed.dedup_by(|b, a| (*b - *a).abs() <= 1e-9 * span);
        let mut planes = Vec::new();
        for pair in fixed.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let size = size_at(0.5 * (a + b));
            let count = libm::ceil((b - a) / size - 1e-9).max(1.0) as usize;
            for i in 0..count {
                planes.push(a + (b - a) * i as f64 / count as f64);
            }
        }
        if let Some(&last) = fixed.last() {
            planes.push(last);
        }
        planes
    }

    /// Volume of element `e` (one-point: 8 times the Jacobian determinant at the centre,
    /// exact for parallelepipeds).
    pub fn volume(&self, e: usize) -> f64 {
        let x = self.elements[e].map(|n| self.nodes[n]);
        let mut jacobian = [[0.0; 3]; 3];
        const SIGNS: [[f64; 3]; 8] = [
            [-1.0, -1.0, -1.0],
            [1.0, -1.0, -1.0],
            [1.0, 1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
            [1.0, -1.0, 1.0],
            [1.0, 1.0, 1.0],
            [-1.0, 1.0, 1.0],
        ];
        for (a, sign) in SIGNS.iter().enumerate() {
            for (i, row) in jacobian.iter_mut().enumerate() {
                for (j, entry) in row.iter_mut().enumerate() {
                    *entry += 0.125 * sign[j] * x[a][i];
                }
            }
        }
        let j = jacobian;
        8.0 * (j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
            - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
            + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_rod_volume_approaches_the_cylinder() {
        // GOAL: the O-grid quarter rod fills a quarter cylinder.
        // SETUP: radius 1, length 2, core 4, rings 4, axial 5.
        // REFERENCE: pi r^2 L / 4 = 1.5708; the polygonal boundary loses < 1 %.
        let mesh = HexMesh::quarter_rod("rod", 0, 1.0, 2.0, 4, 4, 5);
        let total: f64 = (0..mesh.elements.len()).map(|e| mesh.volume(e)).sum();
        let exact = std::f64::consts::PI * 2.0 / 4.0;
        assert!((0..mesh.elements.len()).all(|e| mesh.volume(e) > 0.0));
        assert!((total / exact - 1.0).abs() < 0.01, "{total} vs {exact}");
        assert!(!mesh.node_sets["rod.x0"].is_empty());
    }

    #[test]
    fn a_block_is_filled_by_positive_elements_and_its_faces_are_named() {
        // GOAL: the box mesher's elements are right-handed and tile the block.
        // SETUP: 2 x 0.5 x 0.25 m in 8 x 3 x 2 elements.
        // REFERENCE: every volume lx ly lz / (nx ny nz), their sum the block's; each face set
        //            holds (n_a + 1)(n_b + 1) nodes on its plane.
        let mesh = HexMesh::block("beam", 0, [2.0, 0.5, 0.25], [8, 3, 2]);
        assert_eq!(mesh.elements.len(), 48);
        assert_eq!(mesh.nodes.len(), 9 * 4 * 3);
        for e in 0..mesh.elements.len() {
            assert!((mesh.volume(e) - 0.25 / 48.0).abs() < 1e-15, "{e}");
        }
        let x1 = &mesh.node_sets["beam.x1"];
        assert_eq!(x1.len(), 4 * 3);
        assert!(x1.iter().all(|&n| mesh.nodes[n][0] == 2.0));
        assert_eq!(mesh.node_sets["beam.z0"].len(), 9 * 4);
        assert!(mesh.node_sets["beam.y1"]
            .iter()
            .all(|&n| mesh.nodes[n][1] == 0.5));
    }

    #[test]
    fn planes_pass_through_the_fixed_coordinates_at_the_local_size() {
        // GOAL: a graded direction keeps every required plane (a bar, a support) and no
        //       element exceeds the local target size.
        // SETUP: fixed 0, 0.031, 0.34 (unsorted, one duplicate), size 0.01 below 0.1 m and
        //        0.05 beyond.
        // REFERENCE: 0..0.031 in 4 elements of 7.75 mm, 0.031..0.34 (midpoint 0.1855) in 7 of
        //            44.1 mm; 12 planes.
        let planes = HexMesh::planes_through(&[0.34, 0.0, 0.031, 0.031], |x| {
            if x < 0.1 {
                0.01
            } else {
                0.05
            }
        });
        assert_eq!(planes.len(), 12);
        assert!(planes.contains(&0.031) && planes[0] == 0.0 && planes[11] == 0.34);
        assert!(planes.windows(2).all(|w| w[1] > w[0]));
        assert!((planes[1] - 0.00775).abs() < 1e-15);
    }

    #[test]
    fn merging_a_block_onto_another_shares_the_coincident_face() {
        // GOAL: a pad meshed separately is tied to the beam through its coincident nodes.
        // SETUP: a 2 x 2 x 2 block of 1 m, and a 1 x 1 x 1 block of 1 m on its top at
        //        (0..1, 0..1, 2..3), its material 1.
        // REFERENCE: the pad's bottom face (4 nodes) merges; 27 + 8 - 4 nodes; the second part
        //            renumbered 1 with its material, its node sets renamed onto merged nodes.
        let mut beam = HexMesh::block("beam", 0, [2.0, 2.0, 2.0], [2, 2, 2]);
        let mut pad = HexMesh::block("pad", 1, [1.0, 1.0, 1.0], [1, 1, 1]);
        for p in &mut pad.nodes {
            p[2] += 2.0;
        }
        let merged = beam.merge(pad, 1e-9);
        assert_eq!(merged, 4);
        assert_eq!(beam.nodes.len(), 31);
        assert_eq!(beam.element_part, vec![0, 0, 0, 0, 0, 0, 0, 0, 1]);
        assert_eq!(beam.parts[1].material, 1);
        let bottom = &beam.node_sets["pad.z0"];
        assert!(bottom
            .iter()
            .all(|&n| beam.node_sets["beam.z1"].contains(&n)));
        assert!((0..beam.elements.len()).all(|e| beam.volume(e) > 0.0));
    }
}
