//! A rod with a pointed (ogive or hemispherical) nose, meshed as an O-grid: a ring of layers
//! that follows the nose's surface around a structured core.
//!
//! Mapping a structured grid onto a pointed nose row by row (each row's radii scaled to the
//! profile) squeezes every column into the tip: at a 0.1 mm element size, the 20 columns of a
//! 4 mm core share a 0.4 mm meplat, elements 0.02 mm wide that set the time step and invert
//! first. The O-grid keeps the elements near the surface about the nominal size everywhere,
//! as hand-made penetrator meshes in LS-DYNA or Autodyn do:
//!
//! - **Ring:** `m` layers along the outer boundary, from the tip on the axis across the
//!   meplat and up the profile to the shoulder, `N` elements long.
//! - **Core:** `c = n_r - m` columns by `n_y` rows, bounded by the axis, the shoulder line and
//!   the ring's inner side (its first `c` segments are the core's bottom, the next `n_y` its
//!   right side), so `N = c + n_y`.
//! - **Shank:** the structured `n_r`-column block from the shoulder to the tail; its first row
//!   of nodes is the core's top and the ring's end.
//!
//! The outer boundary's nodes are spaced evenly in arc length on the meplat and on the
//! profile (the meplat's corner is a node); the shoulder line's nodes are the shank's columns.
//! The other nodes (the axis nodes sliding along the axis) are placed by Laplacian smoothing
//! from a transfinite first guess, Gauss-Seidel sweeps in a fixed order until no node moves more
//! than a billionth of the element size: the mesh depends only on the inputs. For a convex nose region the smoothed grid does not fold;
//! [`pointed_rod`] checks that every element has a positive area and a bounded shape.

use super::{structured_quads, Part, QuadMesh};

/// Largest number of Gauss-Seidel sweeps of the Laplacian smoothing.
const MAXIMUM_SWEEPS: usize = 20_000;

/// Largest number of node moves (sweeps times nodes) of one smoothing: a very fine nose stops
/// smoothing there and is accepted or refused by its shape check, never left to run for
/// hours (the experiments' noses, up to about 3 000 nodes, converge well inside it).
const MAXIMUM_NODE_MOVES: usize = 200_000_000;

/// The smoothing stops when no node moved more than this fraction of the element size.
const SMOOTHING_TOLERANCE: f64 = 1e-9;

/// Samples of the profile for its arc length.
const ARC_SAMPLES: usize = 4000;

/// Smallest interior angle (degrees) [`pointed_rod`] accepts in the nose.
pub const MINIMUM_NOSE_ANGLE: f64 = 25.0;

/// Largest ratio of an element's longest to its shortest edge [`pointed_rod`] accepts in the
/// nose.
pub const MAXIMUM_NOSE_EDGE_RATIO: f64 = 5.0;

/// The rod's geometry for [`pointed_rod`].
#[derive(Clone, Copy)]
pub struct PointedRod<'a> {
    /// Shank radius `a` (m).
    pub radius: f64,
    /// Total length, nose included (m).
    pub length: f64,
    /// Nose length `L_n` (m), `0 < L_n < length`.
    pub nose_length: f64,
    /// Outer radius `r(y)` at distance `y` behind the tip, `0 <= y <= L_n`: `r(0)` is the
    /// meplat's radius (`> 0`), `r(L_n) = a`, non-decreasing and concave (a convex nose).
    pub profile: &'a dyn Fn(f64) -> f64,
    /// Nominal element size (m).
    pub element_size: f64,
    /// Axial position of the tip (m); the rod extends to `tip + length`.
    pub tip: f64,
}

/// The O-grid mesh of a pointed rod as part `part` (material index `material`), with node sets
/// `<part>.axis` (every node on the axis), `<part>.top` (the tail) and `<part>.outer` (the
/// outer surface from the meplat to the tail), and element set `<part>`. Elements are ordered
/// nose first, tail row last. `Err` names what is wrong with the geometry, or the element whose
/// shape the smoothing could not keep.
pub fn pointed_rod(part: &str, material: usize, rod: &PointedRod<'_>) -> Result<QuadMesh, String> {
    let a = rod.radius;
    let nose = rod.nose_length;
    let h = rod.element_size;
    let tip_radius = (rod.profile)(0.0);
    if !(a > 0.0 && h > 0.0 && nose > 0.0 && nose < rod.length) {
        return Err(format!(
            "a pointed rod needs radius, element size > 0 and 0 < nose length ({nose}) < \
             length ({})",
            rod.length
        ));
    }
    if !(tip_radius > 0.0 && tip_radius < a) {
        return Err(format!(
            "the meplat radius {tip_radius} must lie between 0 and the radius {a}"
        ));
    }
    let columns = ((a / h).round() as usize).max(2);

    // Arc length along the profile, sampled.
    let mut arc = vec![0.0; ARC_SAMPLES + 1];
    let mut previous = [tip_radius, 0.0];
    for (k, length) in arc.iter_mut().enumerate().skip(1) {
        let y = nose * k as f64 / ARC_SAMPLES as f64;
        let point = [(rod.profile)(y), y];
        *length = libm::hypot(point[0] - previous[0], point[1] - previous[1]);
        previous = point;
    }
    for k in 1..=ARC_SAMPLES {
        arc[k] += arc[k - 1];
    }
    let profile_length = arc[ARC_SAMPLES];
    // The point of the profile at arc length `s` (linear between samples).
    let on_profile = |s: f64| -> [f64; 2] {
        let k = arc.partition_point(|&l| l < s).clamp(1, ARC_SAMPLES);
        let span = arc[k] - arc[k - 1];
        let t = if span > 0.0 {
            ((s - arc[k - 1]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let y = nose * (k as f64 - 1.0 + t) / ARC_SAMPLES as f64;
        [(rod.profile)(y), y]
    };
    let face_segments = ((tip_radius / h).round() as usize).max(1);
    let profile_segments = ((profile_length / h).round() as usize).max(columns + 1);
    let boundary_segments = face_segments + profile_segments;

    // Outer boundary, from the tip on the axis to the shoulder.
    let mut outer = Vec::with_capacity(boundary_segments + 1);
    for k in 0..=face_segments {
        outer.push([tip_radius * k as f64 / face_segments as f64, 0.0]);
    }
    for k in 1..=profile_segments {
        let point = if k == profile_segments {
            [a, nose]
        } else {
            on_profile(profile_length * k as f64 / profile_segments as f64)
        };
        outer.push(point);
    }

    // A third of the columns in the ring; half as many, and so on down to one, where that
    // leaves a slender nose's tip elements too skewed (a few attempts, not one per layer).
    let mut refusal = String::new();
    let mut region = None;
    let first_layers = (columns / 3).max(1);
    let attempts = core::iter::successors(Some(first_layers), |&m| (m > 1).then_some(m / 2));
    for ring_layers in attempts {
        match nose_region(&outer, columns, ring_layers, nose, h) {
            Ok(built) => {
                region = Some(built);
                break;
            }
            Err(why) => refusal = why,
        }
    }
    let Some(NoseRegion {
        nodes,
        elements,
        shoulder,
        surface,
    }) = region
    else {
        return Err(refusal);
    };
    let mut mesh = QuadMesh {
        nodes,
        elements,
        ..QuadMesh::default()
    };

    // Shank: the structured block from the shoulder to the tail; its first row is the
    // shoulder line (the core's top, then the ring's end).
    let shank_rows = (((rod.length - nose) / h).round() as usize).max(1);
    let mut row_nodes = shoulder;
    let mut tail = Vec::new();
    let mut outer_side = Vec::new();
    for j in 1..=shank_rows {
        let z = if j == shank_rows {
            rod.length
        } else {
            nose + (rod.length - nose) * j as f64 / shank_rows as f64
        };
        let first = mesh.nodes.len();
        for i in 0..=columns {
            mesh.nodes.push([a * i as f64 / columns as f64, z]);
        }
        let next: Vec<usize> = (first..=first + columns).collect();
        for i in 0..columns {
            mesh.elements
                .push([row_nodes[i], row_nodes[i + 1], next[i + 1], next[i]]);
        }
        outer_side.push(next[columns]);
        if j == shank_rows {
            tail = next.clone();
        }
        row_nodes = next;
    }
    for node in &mut mesh.nodes {
        node[1] += rod.tip;
    }

    let mut axis: Vec<usize> = (0..mesh.nodes.len())
        .filter(|&n| mesh.nodes[n][0] == 0.0)
        .collect();
    axis.sort_by(|&p, &q| mesh.nodes[p][1].total_cmp(&mesh.nodes[q][1]));
    let mut outer_surface = surface;
    outer_surface.extend(outer_side);
    mesh.element_part = vec![0; mesh.elements.len()];
    mesh.parts.push(Part {
        name: part.into(),
        material,
    });
    mesh.node_sets.insert(format!("{part}.axis"), axis);
    mesh.node_sets.insert(format!("{part}.top"), tail);
    mesh.node_sets
        .insert(format!("{part}.outer"), outer_surface);
    mesh.element_sets
        .insert(part.into(), (0..mesh.elements.len()).collect());
    Ok(mesh)
}

/// The nose region's grid: nodes, counter-clockwise elements, the shoulder line's nodes from
/// the axis out and the outer surface's nodes from the tip.
struct NoseRegion {
    nodes: Vec<[f64; 2]>,
    elements: Vec<[usize; 4]>,
    shoulder: Vec<usize>,
    surface: Vec<usize>,
}

/// The O-grid of the nose region bounded by the axis, the shoulder line `z = nose` (`columns`
/// elements) and `outer` (the surface from the tip on the axis to the shoulder), with
/// `ring_layers` layers in the ring; `Err` if an element's shape is out of bounds.
fn nose_region(
    outer: &[[f64; 2]],
    columns: usize,
    ring_layers: usize,
    nose: f64,
    h: f64,
) -> Result<NoseRegion, String> {
    let a = outer[outer.len() - 1][0];
    let core_columns = columns - ring_layers;
    let boundary_segments = outer.len() - 1;
    if boundary_segments <= core_columns {
        return Err("the nose is too short for its element size".into());
    }
    let rows = boundary_segments - core_columns;

    // Node numbering: the ring (boundary index k, layer l), then the core nodes not shared
    // with the ring (i < c, j >= 1: the core's bottom row and right column are the ring's
    // inner side).
    let ring_index = |k: usize, l: usize| k * (ring_layers + 1) + l;
    let ring_count = (boundary_segments + 1) * (ring_layers + 1);
    let core_index = |i: usize, j: usize| -> usize {
        if j == 0 {
            ring_index(i, ring_layers)
        } else if i == core_columns {
            ring_index(core_columns + j, ring_layers)
        } else {
            ring_count + (j - 1) * core_columns + i
        }
    };
    let node_count = ring_count + rows * core_columns;
    let mut nodes = vec![[0.0; 2]; node_count];
    // Which nodes move: 0 fixed, 1 free, 2 on the axis (z only).
    let mut kind = vec![1u8; node_count];
    let axis_free = |kind: &mut Vec<u8>, n: usize| {
        if kind[n] != 0 {
            kind[n] = 2;
        }
    };

    // First guess. Ring: the outer boundary, its inner side a homothety of it towards the
    // point of the axis at the shoulder's height less the radius, layers between.
    let shrink = 1.0 - ring_layers as f64 / columns as f64;
    let centre = [0.0, (nose - a).max(0.5 * nose)];
    for (k, point) in outer.iter().enumerate() {
        let inner = [
            centre[0] + shrink * (point[0] - centre[0]),
            centre[1] + shrink * (point[1] - centre[1]),
        ];
        for l in 0..=ring_layers {
            let t = l as f64 / ring_layers as f64;
            nodes[ring_index(k, l)] = [
                point[0] + t * (inner[0] - point[0]),
                point[1] + t * (inner[1] - point[1]),
            ];
        }
        kind[ring_index(k, 0)] = 0;
    }
    // The ring's end on the shoulder line: the shank's outer columns.
    for l in 0..=ring_layers {
        let n = ring_index(boundary_segments, l);
        nodes[n] = [a * (columns - l) as f64 / columns as f64, nose];
        kind[n] = 0;
    }
    // The ring's end on the axis.
    for l in 0..=ring_layers {
        let n = ring_index(0, l);
        nodes[n][0] = 0.0;
        axis_free(&mut kind, n);
    }
    // Core: transfinite interpolation of its four sides.
    let bottom = |i: usize| nodes[ring_index(i, ring_layers)];
    let right = |j: usize| nodes[ring_index(core_columns + j, ring_layers)];
    let left_bottom = bottom(0);
    let mut core = Vec::new();
    for j in 1..=rows {
        for i in 0..core_columns {
            let u = i as f64 / core_columns as f64;
            let v = j as f64 / rows as f64;
            let left = [0.0, left_bottom[1] + v * (nose - left_bottom[1])];
            let top = [a * i as f64 / columns as f64, nose];
            let (b, r) = (bottom(i), right(j));
            let (b_right, r_top) = (bottom(core_columns), right(rows));
            let mut p = [0.0; 2];
            for d in 0..2 {
                p[d] = (1.0 - u) * left[d] + u * r[d] + (1.0 - v) * b[d] + v * top[d]
                    - ((1.0 - u) * (1.0 - v) * left_bottom[d]
                        + u * (1.0 - v) * b_right[d]
                        + (1.0 - u) * v * [0.0, nose][d]
                        + u * v * r_top[d]);
            }
            core.push((core_index(i, j), p, i, j));
        }
    }
    for (n, p, i, j) in core {
        nodes[n] = p;
        if j == rows {
            kind[n] = 0;
            nodes[n] = [a * i as f64 / columns as f64, nose];
        } else if i == 0 {
            nodes[n][0] = 0.0;
            axis_free(&mut kind, n);
        }
    }

    // Elements (counter-clockwise): the ring (the region lies to the left of the boundary's
    // direction, inwards as l grows), then the core.
    // Ring quads boundary segment by boundary segment (k outer, l inner), each
    // `[(k, l), (k + 1, l), (k + 1, l + 1), (k, l + 1)]`: (l, k) is left-handed in the
    // plane, so each quad of the (l, k) patch is reversed and rotated to that order.
    let mut elements = structured_quads(ring_layers, boundary_segments, |l, k| ring_index(k, l));
    for quad in &mut elements {
        quad.reverse();
        quad.rotate_right(1);
    }
    elements.extend(structured_quads(core_columns, rows, core_index));

    // Smoothing: each movable node to the mean of the centroids of its elements (the
    // element-centroid form of Laplacian smoothing, which keeps the three elements around the
    // core's corner, the grid's one irregular node, as large as their neighbours).
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); node_count];
    for (e, element) in elements.iter().enumerate() {
        for &n in element {
            around[n].push(e);
        }
    }
    for _ in 0..MAXIMUM_SWEEPS.min(MAXIMUM_NODE_MOVES / node_count.max(1)) {
        let mut largest_move = 0.0_f64;
        for n in 0..node_count {
            if kind[n] == 0 {
                continue;
            }
            let mut mean = [0.0; 2];
            for &e in &around[n] {
                for &q in &elements[e] {
                    mean[0] += nodes[q][0];
                    mean[1] += nodes[q][1];
                }
            }
            let count = 4.0 * around[n].len() as f64;
            let moved = if kind[n] == 2 {
                [0.0, mean[1] / count]
            } else {
                [mean[0] / count, mean[1] / count]
            };
            largest_move = largest_move
                .max((moved[0] - nodes[n][0]).abs())
                .max((moved[1] - nodes[n][1]).abs());
            nodes[n] = moved;
        }
        if largest_move <= SMOOTHING_TOLERANCE * h {
            break;
        }
    }

    for element in &elements {
        let corners = element.map(|n| nodes[n]);
        let angle = smallest_angle(corners);
        let lengths = (0..4).map(|k| {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            libm::hypot(q[0] - p[0], q[1] - p[1])
        });
        let (shortest, longest) =
            lengths.fold((f64::INFINITY, 0.0_f64), |(s, l), x| (s.min(x), l.max(x)));
        if !(angle >= MINIMUM_NOSE_ANGLE && longest <= MAXIMUM_NOSE_EDGE_RATIO * shortest) {
            let centre = corners
                .iter()
                .fold([0.0; 2], |c, p| [c[0] + 0.25 * p[0], c[1] + 0.25 * p[1]]);
            return Err(format!(
                "an element at r = {:.3e} m, {:.3e} m behind the tip, would have an interior \
                 angle of {angle:.1} degrees and an edge ratio of {:.1} (at least \
                 {MINIMUM_NOSE_ANGLE} and at most {MAXIMUM_NOSE_EDGE_RATIO}): choose a \
                 smaller element size or a larger meplat",
                centre[0],
                centre[1],
                longest / shortest
            ));
        }
    }
    let shoulder = (0..=columns)
        .map(|i| {
            if i <= core_columns {
                core_index(i, rows)
            } else {
                ring_index(boundary_segments, columns - i)
            }
        })
        .collect();
    let surface = (0..=boundary_segments).map(|k| ring_index(k, 0)).collect();
    Ok(NoseRegion {
        nodes,
        elements,
        shoulder,
        surface,
    })
}

/// Smallest interior angle (degrees) of a quadrilateral; 0 if it is folded or degenerate.
pub fn smallest_angle(corners: [[f64; 2]; 4]) -> f64 {
    let mut smallest = 180.0_f64;
    for k in 0..4 {
        let p = corners[k];
        let next = corners[(k + 1) % 4];
        let before = corners[(k + 3) % 4];
        let u = [next[0] - p[0], next[1] - p[1]];
        let v = [before[0] - p[0], before[1] - p[1]];
        let cross = u[0] * v[1] - u[1] * v[0];
        // NaN coordinates count as folded.
        if cross.is_nan() || cross <= 0.0 {
            return 0.0;
        }
        let dot = u[0] * v[0] + u[1] * v[1];
        smallest = smallest.min(libm::atan2(cross, dot).to_degrees());
    }
    smallest
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::f64::consts::PI;

    /// A tangent ogive of radius `a` and length `l` blunted to a meplat of radius `meplat`
    /// (the penetration experiment's profile).
    fn ogive(a: f64, l: f64, meplat: f64) -> impl Fn(f64) -> f64 {
        move |y: f64| {
            let s = (l * l + a * a) / (2.0 * a);
            let y = y.clamp(0.0, l);
            let sharp = (libm::sqrt((s * s - (l - y) * (l - y)).max(0.0)) - (s - a)).max(0.0);
            meplat + (a - meplat) * sharp / a
        }
    }

    /// A hemisphere of radius `a` blunted to a meplat of radius `meplat`.
    fn hemisphere(a: f64, meplat: f64) -> impl Fn(f64) -> f64 {
        move |y: f64| {
            let y = y.clamp(0.0, a);
            meplat + (a - meplat) * libm::sqrt((a * a - (a - y) * (a - y)).max(0.0)) / a
        }
    }

    /// Volume of revolution of `profile` over the nose by Simpson's rule, plus the shank.
    fn exact_volume(rod: &PointedRod<'_>) -> f64 {
        let n = 4000;
        let step = rod.nose_length / n as f64;
        let nose: f64 = (0..=n)
            .map(|k| {
                let weight = match k {
                    0 => 1.0,
                    k if k == n => 1.0,
                    k if k % 2 == 1 => 4.0,
                    _ => 2.0,
                };
                let r = (rod.profile)(k as f64 * step);
                weight * PI * r * r
            })
            .sum::<f64>()
            * step
            / 3.0;
        nose + PI * rod.radius * rod.radius * (rod.length - rod.nose_length)
    }

    #[test]
    fn an_o_grid_nose_keeps_its_elements_shaped_and_fills_the_profile() {
        // GOAL: the O-grid meshes every pointed nose the experiments use with elements of a
        //       usable shape down to the meplat, conforming, and with the body's volume.
        // SETUP: the ballistic kind's WC core (4 mm, ogive 6 mm, meplat 0.4 mm) at 0.4 / 0.2
        //        / 0.1 mm, seed 000's rod with a CRH 3 ogive (5 mm, meplat 0.5 mm) at 0.4 /
        //        0.2 mm, the 152 mm CRH 2.5 concrete penetrator (meplat 15.2 mm) at 30 / 15 /
        //        10 / 5 mm, a hemispherical 5 mm nose at 0.4 / 0.2 mm.
        // REFERENCE: geometry: positive areas, interior angles >= 30 degrees, longest over
        //   shortest edge <= 3.5, shortest edge >= h/5; every edge shared by two elements
        //   except those on the axis, the outer surface and the tail; the volume of
        //   revolution within 0.5 % of the profile's (Simpson, 4000 intervals; chords
        //   under-fill a convex curve).
        let core = ogive(2.0e-3, 6.0e-3, 0.4e-3);
        let crh3_length = 2.5e-3 * 11f64.sqrt();
        let crh3 = ogive(2.5e-3, crh3_length, 0.5e-3);
        let penetrator = ogive(0.076, 0.228, 0.0152);
        let round = hemisphere(2.5e-3, 0.5e-3);
        let cases: Vec<(PointedRod<'_>, Vec<f64>)> = vec![
            (
                PointedRod {
                    radius: 2.0e-3,
                    length: 16.0e-3,
                    nose_length: 6.0e-3,
                    profile: &core,
                    element_size: 0.0,
                    tip: 0.02e-3,
                },
                vec![0.4e-3, 0.2e-3, 0.1e-3],
            ),
            (
                PointedRod {
                    radius: 2.5e-3,
                    length: 30.0e-3,
                    nose_length: crh3_length,
                    profile: &crh3,
                    element_size: 0.0,
                    tip: 0.0,
                },
                vec![0.4e-3, 0.2e-3],
            ),
            (
                PointedRod {
                    radius: 0.076,
                    length: 0.552,
                    nose_length: 0.228,
                    profile: &penetrator,
                    element_size: 0.0,
                    tip: 1.0e-3,
                },
                vec![30.0e-3, 15.0e-3, 10.0e-3, 5.0e-3],
            ),
            (
                PointedRod {
                    radius: 2.5e-3,
                    length: 30.0e-3,
                    nose_length: 2.5e-3,
                    profile: &round,
                    element_size: 0.0,
                    tip: 0.0,
                },
                vec![0.4e-3, 0.2e-3],
            ),
        ];
        for (geometry, sizes) in &cases {
            for &h in sizes {
                let rod = PointedRod {
                    element_size: h,
                    ..*geometry
                };
                let mesh = pointed_rod("rod", 1, &rod).unwrap();
                let label = format!("radius {} at h {h}", rod.radius);
                let mut volume = 0.0;
                let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
                for (e, element) in mesh.elements.iter().enumerate() {
                    let corners = element.map(|n| mesh.nodes[n]);
                    assert!(mesh.area(e) > 0.0, "{label}: element {e} inverted");
                    assert!(smallest_angle(corners) >= 30.0, "{label}: element {e}");
                    let lengths: Vec<f64> = (0..4)
                        .map(|k| {
                            let (p, q) = (corners[k], corners[(k + 1) % 4]);
                            libm::hypot(q[0] - p[0], q[1] - p[1])
                        })
                        .collect();
                    let longest = lengths.iter().copied().fold(0.0, f64::max);
                    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
                    assert!(longest / shortest <= 3.5, "{label}: element {e}");
                    assert!(shortest >= 0.2 * h, "{label}: element {e}");
                    let mean_radius = 0.25 * corners.iter().map(|p| p[0]).sum::<f64>();
                    volume += 2.0 * PI * mean_radius * mesh.area(e);
                    for k in 0..4 {
                        let (p, q) = (element[k], element[(k + 1) % 4]);
                        *edges.entry((p.min(q), p.max(q))).or_default() += 1;
                    }
                }
                let expected = exact_volume(&rod);
                assert!(
                    (volume / expected - 1.0).abs() < 5e-3,
                    "{label}: volume {volume:e} against {expected:e}"
                );
                let on_axis = |n: usize| mesh.nodes[n][0] == 0.0;
                let outer: Vec<usize> = mesh.node_sets["rod.outer"].clone();
                let tail: Vec<usize> = mesh.node_sets["rod.top"].clone();
                for (&(p, q), &count) in &edges {
                    let boundary = (on_axis(p) && on_axis(q))
                        || (outer.contains(&p) && outer.contains(&q))
                        || (tail.contains(&p) && tail.contains(&q));
                    assert_eq!(count, if boundary { 1 } else { 2 }, "{label}: edge {p}-{q}");
                }
                // The node sets.
                let axis = &mesh.node_sets["rod.axis"];
                assert!(axis.iter().all(|&n| on_axis(n)));
                assert_eq!(
                    axis.len(),
                    (0..mesh.nodes.len()).filter(|&n| on_axis(n)).count()
                );
                assert!(tail
                    .iter()
                    .all(|&n| (mesh.nodes[n][1] - (rod.tip + rod.length)).abs() < 1e-15));
                let meplat = (rod.profile)(0.0);
                assert!(outer.iter().any(|&n| mesh.nodes[n] == [meplat, rod.tip]));
                // The tail row is the last row of elements.
                let last = mesh.elements.last().unwrap();
                assert!(last.iter().filter(|n| tail.contains(n)).count() == 2);
            }
        }
    }

    #[test]
    fn an_impossible_nose_is_refused_with_its_reason() {
        // GOAL: bad geometry gives an error naming what is wrong, never a folded mesh.
        // SETUP: a meplat as wide as the rod, a zero meplat, a nose as long as the rod, a
        //        meplat of an eighth of the element size (its one element a sliver).
        // REFERENCE: Err naming the meplat or the nose length.
        let flat = |_: f64| 2.0e-3;
        let sharp = ogive(2.0e-3, 6.0e-3, 0.0);
        let core = ogive(2.0e-3, 6.0e-3, 0.4e-3);
        let rod = |profile: &'static dyn Fn(f64) -> f64, nose_length: f64| PointedRod {
            radius: 2.0e-3,
            length: 16.0e-3,
            nose_length,
            profile,
            element_size: 0.2e-3,
            tip: 0.0,
        };
        let leak = |f: Box<dyn Fn(f64) -> f64>| -> &'static dyn Fn(f64) -> f64 { Box::leak(f) };
        let error = pointed_rod("rod", 1, &rod(leak(Box::new(flat)), 6.0e-3)).unwrap_err();
        assert!(error.contains("meplat"), "{error}");
        let error = pointed_rod("rod", 1, &rod(leak(Box::new(sharp)), 6.0e-3)).unwrap_err();
        assert!(error.contains("meplat"), "{error}");
        let error = pointed_rod("rod", 1, &rod(leak(Box::new(core)), 16.0e-3)).unwrap_err();
        assert!(error.contains("nose length"), "{error}");
        let needle = ogive(2.0e-3, 6.0e-3, 0.025e-3);
        let error = pointed_rod("rod", 1, &rod(leak(Box::new(needle)), 6.0e-3)).unwrap_err();
        assert!(
            error.contains("edge ratio") && error.contains("meplat"),
            "{error}"
        );
    }
}
