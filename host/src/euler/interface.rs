//! Interface reconstruction in a cell of the Eulerian grid: Youngs' piecewise-linear interface
//! calculation (PLIC) with nested dissection, in the meridian plane of an axisymmetric grid.
//!
//! - **Normal** (Youngs 1982, "Time-dependent multi-material flow with large fluid
//!   distortion"): `n = -grad f`, the gradient of the material's volume fraction from the
//!   3 x 3 stencil with weights 1-2-1 across the gradient's direction.
//! - **Line**: the straight line `n . x = d` whose half plane `n . x <= d` holds, within what
//!   the earlier materials of the cell left (nested dissection, Benson 1992 sec. 6.3), exactly
//!   the material's volume. Volumes are the **axisymmetric** ones, `int r dA` per radian, so a
//!   reconstruction holds each material's volume fraction exactly, not its area fraction (the
//!   line position is found by bisection on the clipped polygon's first moment of area).
//! - **Fluxes**: the volume of each material inside the strip of the donor cell that a face
//!   sweeps over in one step: the strip clipped against the material's polygon.
//!
//! Polygons are convex (a rectangle clipped by half planes), at most 8 vertices, on the stack.

/// A point `(r, z)` of the meridian plane (m).
pub type Point = [f64; 2];

/// Largest vertex count of a clipped polygon: a rectangle clipped by up to four half planes.
pub const MAX_VERTICES: usize = 12;

/// A convex polygon with at most [`MAX_VERTICES`] vertices, counter-clockwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    vertices: [Point; MAX_VERTICES],
    count: usize,
}

impl Polygon {
    /// The rectangle `[r0, r1] x [z0, z1]`.
    pub fn rectangle(r0: f64, r1: f64, z0: f64, z1: f64) -> Self {
        let mut vertices = [[0.0; 2]; MAX_VERTICES];
        vertices[0] = [r0, z0];
        vertices[1] = [r1, z0];
        vertices[2] = [r1, z1];
        vertices[3] = [r0, z1];
        Self { vertices, count: 4 }
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices[..self.count]
    }

    /// `true` if the polygon has no area.
    pub fn is_empty(&self) -> bool {
        self.count < 3
    }

    /// The part of the polygon where `normal . x <= level` (Sutherland-Hodgman against one
    /// half plane).
    pub fn clip(&self, normal: [f64; 2], level: f64) -> Self {
        let mut out = Self {
            vertices: [[0.0; 2]; MAX_VERTICES],
            count: 0,
        };
        if self.count == 0 {
            return out;
        }
        let side = |p: &Point| normal[0] * p[0] + normal[1] * p[1] - level;
        let mut push = |p: Point| {
            if out.count < MAX_VERTICES {
                out.vertices[out.count] = p;
                out.count += 1;
            }
        };
        for k in 0..self.count {
            let a = self.vertices[k];
            let b = self.vertices[(k + 1) % self.count];
            let (sa, sb) = (side(&a), side(&b));
            if sa <= 0.0 {
                push(a);
            }
            if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                let t = sa / (sa - sb);
                push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        out
    }

    /// The part where `normal . x >= level`.
    pub fn clip_outside(&self, normal: [f64; 2], level: f64) -> Self {
        self.clip([-normal[0], -normal[1]], -level)
    }

    /// Axisymmetric volume per radian, `int r dA` (Green's theorem:
    /// `sum (r_k z_{k+1} - r_{k+1} z_k)(r_k + r_{k+1}) / 6`); the plane area if `planar`.
    pub fn volume(&self, planar: bool) -> f64 {
        let mut sum = 0.0;
        for k in 0..self.count {
            let a = self.vertices[k];
            let b = self.vertices[(k + 1) % self.count];
            let cross = a[0] * b[1] - b[0] * a[1];
            sum += if planar {
                0.5 * cross
            } else {
                cross * (a[0] + b[0]) / 6.0
            };
        }
        sum
    }

    /// Smallest and largest `normal . x` over the vertices.
    fn extent(&self, normal: [f64; 2]) -> (f64, f64) {
        let mut low = f64::INFINITY;
        let mut high = f64::NEG_INFINITY;
        for p in self.vertices() {
            let s = normal[0] * p[0] + normal[1] * p[1];
            low = low.min(s);
            high = high.max(s);
        }
        (low, high)
    }
}

/// Largest number of steps of the line search.
const LINE_ITERATIONS: usize = 100;

/// Relative volume error at which the line search stops.
const LINE_TOLERANCE: f64 = 1e-13;

/// The level `d` of the line `normal . x = d` whose half plane `normal . x <= d` holds
/// `volume` of `polygon`: the Illinois variant of regula falsi on the clipped volume, which
/// is monotone (and piecewise cubic) in `d`, to [`LINE_TOLERANCE`] of the polygon's volume.
pub fn line_level(polygon: &Polygon, normal: [f64; 2], volume: f64, planar: bool) -> f64 {
    let (mut low, mut high) = polygon.extent(normal);
    let total = polygon.volume(planar);
    let tolerance = LINE_TOLERANCE * total.abs();
    let (mut f_low, mut f_high) = (-volume, total - volume);
    if f_low >= 0.0 {
        return low;
    }
    if f_high <= 0.0 {
        return high;
    }
    let mut level = 0.5 * (low + high);
    let mut side = 0;
    for _ in 0..LINE_ITERATIONS {
        level = (low * f_high - high * f_low) / (f_high - f_low);
        if !(level > low && level < high) {
            level = 0.5 * (low + high);
        }
        let f = polygon.clip(normal, level).volume(planar) - volume;
        if f.abs() <= tolerance {
            return level;
        }
        if f > 0.0 {
            high = level;
            f_high = f;
            if side == -1 {
                f_low *= 0.5;
            }
            side = -1;
        } else {
            low = level;
            f_low = f;
            if side == 1 {
                f_high *= 0.5;
            }
            side = 1;
        }
        if high - low <= f64::EPSILON * (low.abs() + high.abs()) {
            break;
        }
    }
    level
}

/// The reconstructed interface of one material in a mixed cell: the half plane
/// `normal . x <= level`, intersected with what the earlier materials left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    /// Unit normal pointing out of the material.
    pub normal: [f64; 2],
    /// Line level (m).
    pub level: f64,
}

/// The cells of the 3 x 3 block about cell `(i, j)` as [`youngs_normal`] reads it (`[dz][dr]`,
/// the cell at `[1][1]`): across the axis (or a symmetry edge) at `i = 0` the mirror cell,
/// beyond the grid's other edges the cell itself.
pub fn block_cells(i: usize, j: usize, cells_r: usize, cells_z: usize) -> [[usize; 3]; 3] {
    let c = j * cells_r + i;
    core::array::from_fn(|dz| {
        core::array::from_fn(|dr| {
            let (ni, nj) = ((i + dr).wrapping_sub(1), (j + dz).wrapping_sub(1));
            if ni < cells_r && nj < cells_z {
                nj * cells_r + ni
            } else if ni >= cells_r && i == 0 && nj < cells_z {
                nj * cells_r + i
            } else {
                c
            }
        })
    })
}

/// Youngs' normal `-grad f` from the 3 x 3 block of volume fractions `f[dz][dr]` (`dr`, `dz`
/// in `0..3`, the cell at `[1][1]`), for cells `spacing_r x spacing_z`; `None` where the
/// gradient vanishes.
pub fn youngs_normal(f: [[f64; 3]; 3], spacing_r: f64, spacing_z: f64) -> Option<[f64; 2]> {
    let d_dr = ((f[0][2] + 2.0 * f[1][2] + f[2][2]) - (f[0][0] + 2.0 * f[1][0] + f[2][0]))
        / (8.0 * spacing_r);
    let d_dz = ((f[2][0] + 2.0 * f[2][1] + f[2][2]) - (f[0][0] + 2.0 * f[0][1] + f[0][2]))
        / (8.0 * spacing_z);
    let norm = libm::sqrt(d_dr * d_dr + d_dz * d_dz);
    (norm > 0.0 && norm.is_finite()).then(|| [-d_dr / norm, -d_dz / norm])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_moment_of_a_rectangle_is_its_axisymmetric_volume() {
        // GOAL: Polygon::volume is int r dA per radian.
        // REFERENCE: (r1^2 - r0^2)/2 (z1 - z0).
        let p = Polygon::rectangle(1.0, 3.0, 0.0, 2.0);
        assert!((p.volume(false) - 8.0).abs() < 1e-14);
        assert!((p.volume(true) - 4.0).abs() < 1e-14);
    }

    #[test]
    fn a_line_cuts_the_requested_volume_at_any_angle() {
        // GOAL: the line search holds the volume to round-off for oblique normals.
        let p = Polygon::rectangle(2.0, 3.0, -1.0, 0.0);
        for angle in [0.1_f64, 0.7, 1.9, 3.0, 4.4, 5.9] {
            let n = [angle.cos(), angle.sin()];
            for fraction in [1e-6, 0.13, 0.5, 0.87, 1.0 - 1e-6] {
                let target = fraction * p.volume(false);
                let level = line_level(&p, n, target, false);
                let got = p.clip(n, level).volume(false);
                assert!(
                    (got - target).abs() < 1e-12 * p.volume(false),
                    "{angle} {fraction}"
                );
                let rest = p.clip_outside(n, level).volume(false);
                assert!((got + rest - p.volume(false)).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn youngs_normal_points_out_of_the_material() {
        // Material below z = 0.5 in a column of cells: the normal points up (+z).
        let f = [[1.0; 3], [0.5; 3], [0.0; 3]];
        let n = youngs_normal(f, 1.0, 1.0).unwrap();
        assert!((n[1] - 1.0).abs() < 1e-15 && n[0].abs() < 1e-15);
        assert!(youngs_normal([[0.3; 3]; 3], 1.0, 1.0).is_none());
    }
}
