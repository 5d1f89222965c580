//! 2D axisymmetric 4-node quadrilaterals (`r`, `z`), one-point integration.
//!
//! Element formulation (per radian; the time loop reports energies and forces over 2 pi):
//! - mean-derivative (Flanagan-Belytschko) gradients at the centroid, `b_r`, `b_z`;
//! - volume `V = A r_bar` with `r_bar` the mean nodal radius, hoop rate `d_tt = v_r_bar / r_bar`;
//! - volume-weighted nodal forces `f_r,i = -(s_rr b_r,i + s_rz b_z,i) V - s_tt A/4`,
//!   `f_z,i = -(s_rz b_r,i + s_zz b_z,i) V`, which are exactly the derivative of the
//!   internal power `V s:d` (so stress work and kinetic energy balance);
//! - Flanagan-Belytschko viscous hourglass forces, linear + quadratic bulk viscosity;
//! - Jaumann rotation with the in-plane spin before the kernel update.
//!
//! Kernel Voigt mapping: `[rr, zz, tt, rz, 0, 0]` (x = r, y = z, z = theta).

use super::explicit::{
    Discretisation, ElementStep, ExplicitModel, ExplicitRun, HourglassStress, StretchWindow,
    Vector, MAX_NODES,
};
use super::{HourglassControl, SolverError, SolverSettings};
use crate::mesh::QuadMesh;
use std::f64::consts::PI;
use stoss_kernel::{MaterialState, PointModel, StepInput};

/// An axisymmetric model.
pub type AxisymmetricModel = ExplicitModel<QuadMesh>;

/// The result of an axisymmetric run.
pub type AxisymmetricRun = ExplicitRun;

/// Geometry of a quad: area, mean radius, gradient operators.
pub(crate) struct Geometry {
    pub(crate) area: f64,
    pub(crate) mean_radius: f64,
    pub(crate) b_r: [f64; 4],
    pub(crate) b_z: [f64; 4],
    pub(crate) longest_diagonal: f64,
}

/// Area, mean radius and gradient operators of a quad, without its diagonals.
fn gradients(p: [Vector; 4]) -> (f64, f64, [f64; 4], [f64; 4]) {
    let [p0, p1, p2, p3] = p;
    let area = 0.5 * ((p2[0] - p0[0]) * (p3[1] - p1[1]) - (p3[0] - p1[0]) * (p2[1] - p0[1]));
    let inv = 0.5 / area;
    let b_r = [
        inv * (p1[1] - p3[1]),
        inv * (p2[1] - p0[1]),
        inv * (p3[1] - p1[1]),
        inv * (p0[1] - p2[1]),
    ];
    let b_z = [
        inv * (p3[0] - p1[0]),
        inv * (p0[0] - p2[0]),
        inv * (p1[0] - p3[0]),
        inv * (p2[0] - p0[0]),
    ];
    (area, 0.25 * (p0[0] + p1[0] + p2[0] + p3[0]), b_r, b_z)
}

pub(crate) fn geometry(p: [Vector; 4]) -> Geometry {
    let [p0, p1, p2, p3] = p;
    let (area, mean_radius, b_r, b_z) = gradients(p);
    let d1 = ((p2[0] - p0[0]).powi(2) + (p2[1] - p0[1]).powi(2)).sqrt();
    let d2 = ((p3[0] - p1[0]).powi(2) + (p3[1] - p1[1]).powi(2)).sqrt();
    Geometry {
        area,
        mean_radius,
        b_r,
        b_z,
        longest_diagonal: d1.max(d2),
    }
}

/// The nodal forces per radian of a quad whose stress is `[rr, zz, tt, rz]`, written into
/// the first four entries of `forces`: `f_r,k = -(s_rr b_r,k + s_rz b_z,k) V - s_tt A/4`,
/// `f_z,k = -(s_rz b_r,k + s_zz b_z,k) V` with `V = A r_bar` (the module's formulation).
#[inline(always)]
pub(crate) fn stress_forces(
    geom: &Geometry,
    [s_rr, s_zz, s_tt, s_rz]: [f64; 4],
    forces: &mut [Vector],
) {
    let volume = geom.area * geom.mean_radius;
    for (k, force) in forces.iter_mut().take(4).enumerate() {
        force[0] = -(s_rr * geom.b_r[k] + s_rz * geom.b_z[k]) * volume - s_tt * geom.area * 0.25;
        force[1] = -(s_rz * geom.b_r[k] + s_zz * geom.b_z[k]) * volume;
    }
}

/// The Flanagan-Belytschko hourglass shape vector of a quad with corners `p` and geometry
/// `geom`: `gamma_k = h_k - (h . r) b_r,k - (h . z) b_z,k`, `h = (1, -1, 1, -1)`, orthogonal
/// to the linear field.
#[inline(always)]
pub(crate) fn hourglass_shape(p: &[Vector; 4], geom: &Geometry) -> [f64; 4] {
    let h = [1.0, -1.0, 1.0, -1.0];
    let hr: f64 = (0..4).map(|k| h[k] * p[k][0]).sum();
    let hz: f64 = (0..4).map(|k| h[k] * p[k][1]).sum();
    core::array::from_fn(|k| h[k] - hr * geom.b_r[k] - hz * geom.b_z[k])
}

/// The stiffness form's stiffness on a quad's hourglass mode, `QH rho c^2 V sum_k |b_k|^2`
/// (a fraction `QH` of the element's longitudinal stiffness on it; [`HourglassControl`]).
#[inline(always)]
pub(crate) fn hourglass_stiffness(
    coefficient: f64,
    density: f64,
    wave_speed: f64,
    volume: f64,
    geom: &Geometry,
) -> f64 {
    let gradients: f64 = (0..4)
        .map(|k| geom.b_r[k] * geom.b_r[k] + geom.b_z[k] * geom.b_z[k])
        .sum();
    coefficient * density * wave_speed * wave_speed * volume * gradients
}

/// Jaumann rotation of the stress over one step with in-plane spin `w = (dv_r/dz - dv_z/dr)/2`.
pub(crate) fn rotate_jaumann(stress: &mut [f64; 6], spin: f64, dt: f64) {
    let (rr, zz, rz) = (stress[0], stress[1], stress[3]);
    let wdt = spin * dt;
    stress[0] = rr + 2.0 * wdt * rz;
    stress[1] = zz - 2.0 * wdt * rz;
    stress[3] = rz + wdt * (zz - rr);
}

/// The principal stretches of an element: the eigenvalues of `F^T F` in the plane, the
/// larger first, and the hoop stretch.
struct PrincipalStretches {
    in_plane_squared: [f64; 2],
    hoop: f64,
}

impl QuadMesh {
    /// The positions of element `e`'s corners in `x`.
    #[inline]
    pub(crate) fn corners(&self, e: usize, x: &[Vector]) -> [Vector; 4] {
        self.elements[e].map(|n| x[n])
    }

    /// The principal stretches of element `e` between `reference` and `x`, from the
    /// centroidal deformation gradient (see `element_principal_strains`).
    fn principal_stretches(
        &self,
        e: usize,
        reference: &[Vector],
        x: &[Vector],
    ) -> PrincipalStretches {
        let (_, initial_radius, b_r, b_z) = gradients(self.corners(e, reference));
        let current = self.corners(e, x);
        let mut f = [[0.0; 2]; 2];
        for (k, p) in current.iter().enumerate() {
            f[0][0] += p[0] * b_r[k];
            f[0][1] += p[0] * b_z[k];
            f[1][0] += p[1] * b_r[k];
            f[1][1] += p[1] * b_z[k];
        }
        let c11 = f[0][0] * f[0][0] + f[1][0] * f[1][0];
        let c22 = f[0][1] * f[0][1] + f[1][1] * f[1][1];
        let c12 = f[0][0] * f[0][1] + f[1][0] * f[1][1];
        let mean = 0.5 * (c11 + c22);
        let radius = (0.25 * (c11 - c22) * (c11 - c22) + c12 * c12).sqrt();
        PrincipalStretches {
            in_plane_squared: [mean + radius, (mean - radius).max(f64::MIN_POSITIVE)],
            hoop: 0.25 * (current[0][0] + current[1][0] + current[2][0] + current[3][0])
                / initial_radius,
        }
    }
}

impl Discretisation for QuadMesh {
    const DIMENSION: usize = 2;
    const NODES: usize = 4;
    const MEASURE: f64 = 2.0 * PI;
    const AXIAL_COMPONENT: usize = 1;

    fn reference_positions(&self) -> Vec<Vector> {
        self.nodes.iter().map(|p| [p[0], p[1], 0.0]).collect()
    }

    fn element_count(&self) -> usize {
        self.elements.len()
    }

    fn element_nodes(&self, e: usize) -> &[usize] {
        &self.elements[e]
    }

    fn element_material(&self, e: usize) -> (usize, &str) {
        let part = &self.parts[self.element_part[e]];
        (part.material, &part.name)
    }

    fn element_part(&self, e: usize) -> usize {
        self.element_part[e]
    }

    fn part_count(&self) -> usize {
        self.parts.len()
    }

    fn element_volume(&self, e: usize, x: &[Vector]) -> f64 {
        let geom = geometry(self.corners(e, x));
        if geom.area <= 0.0 || geom.mean_radius <= 0.0 {
            return 0.0;
        }
        geom.area * geom.mean_radius
    }

    /// Principal logarithmic strains from the centroidal deformation gradient: in-plane
    /// `F = sum_k x_k (x) b_k` with the reference-configuration gradients `b_k`, hoop stretch
    /// `r_bar / R_bar` (mean nodal radii); `e_i = ln(lambda_i)` with `lambda_i^2` the
    /// eigenvalues of `F^T F`.
    fn element_principal_strains(
        &self,
        e: usize,
        reference: &[Vector],
        x: &[Vector],
    ) -> Option<[f64; 3]> {
        let stretches = self.principal_stretches(e, reference, x);
        Some([
            0.5 * libm::log(stretches.in_plane_squared[0]),
            0.5 * libm::log(stretches.in_plane_squared[1]),
            libm::log(stretches.hoop.max(f64::MIN_POSITIVE)),
        ])
    }

    fn element_stretches_within(
        &self,
        e: usize,
        reference: &[Vector],
        x: &[Vector],
        window: &StretchWindow,
    ) -> bool {
        let stretches = self.principal_stretches(e, reference, x);
        let inside = |value: f64, (low, high): (f64, f64)| value > low && value < high;
        stretches
            .in_plane_squared
            .iter()
            .all(|&value| inside(value, window.stretch_squared))
            && inside(stretches.hoop, window.stretch)
    }

    fn element_time_step(&self, e: usize, x: &[Vector], wave_speed: f64) -> f64 {
        let geom = geometry(self.corners(e, x));
        let length = geom.area / geom.longest_diagonal;
        length / wave_speed
    }

    fn element_step<P: PointModel>(
        &self,
        e: usize,
        x: &[Vector],
        x_new: &[Vector],
        v: &[Vector],
        state: &mut MaterialState,
        hourglass: &mut HourglassStress,
        material: &P,
        reference_volume: f64,
        dt: f64,
        settings: &SolverSettings,
        time: f64,
        forces: &mut [Vector; MAX_NODES],
    ) -> Result<ElementStep, SolverError> {
        let element = self.elements[e];
        let nodes_new = self.corners(e, x_new);
        let nodes_mid: [Vector; 4] = element.map(|n| {
            [
                0.5 * (x[n][0] + x_new[n][0]),
                0.5 * (x[n][1] + x_new[n][1]),
                0.0,
            ]
        });
        let vel = element.map(|n| v[n]);
        let mid = geometry(nodes_mid);
        let new = geometry(nodes_new);
        if mid.area <= 0.0 || new.area <= 0.0 || new.mean_radius <= 0.0 {
            return Err(SolverError::InvertedElement {
                element: e,
                part: self.parts[self.element_part[e]].name.clone(),
                time,
            });
        }
        let mut grad = [[0.0; 2]; 2]; // grad[i][j] = d v_i / d x_j, x = (r, z)
        for (k, velocity) in vel.iter().enumerate() {
            grad[0][0] += mid.b_r[k] * velocity[0];
            grad[0][1] += mid.b_z[k] * velocity[0];
            grad[1][0] += mid.b_r[k] * velocity[1];
            grad[1][1] += mid.b_z[k] * velocity[1];
        }
        let hoop = 0.25 * (vel[0][0] + vel[1][0] + vel[2][0] + vel[3][0]) / mid.mean_radius;
        let d_rz = 0.5 * (grad[0][1] + grad[1][0]);
        let spin = 0.5 * (grad[0][1] - grad[1][0]);
        let volumetric_rate = grad[0][0] + grad[1][1] + hoop;
        let old_relative_volume = state.relative_volume;
        rotate_jaumann(&mut state.stress, spin, dt);
        let input = StepInput {
            strain_increment: [
                grad[0][0] * dt,
                grad[1][1] * dt,
                hoop * dt,
                d_rz * dt,
                0.0,
                0.0,
            ],
            dt,
            relative_volume: new.area * new.mean_radius / reference_volume,
        };
        let output = material
            .update(state, &input)
            .map_err(|error| SolverError::Update {
                element: e,
                part: self.parts[self.element_part[e]].name.clone(),
                time,
                relative_volume: input.relative_volume,
                error,
            })?;
        // Bulk viscosity (compression only), as a pressure added to the forces.
        let density = material.density() / input.relative_volume;
        let viscous_pressure = settings.bulk_viscosity.pressure(
            density,
            new.area.sqrt(),
            volumetric_rate,
            output.wave_speed,
        );
        let mid_volume = 0.5 * (old_relative_volume + input.relative_volume) * reference_volume;
        let viscous_work = -viscous_pressure * volumetric_rate * dt * mid_volume;
        let s = state.stress;
        let (s_rr, s_zz, s_tt, s_rz) = (
            s[0] - viscous_pressure,
            s[1] - viscous_pressure,
            s[2] - viscous_pressure,
            s[3],
        );
        let volume = new.area * new.mean_radius;
        stress_forces(&new, [s_rr, s_zz, s_tt, s_rz], forces);
        // Flanagan-Belytschko hourglass control.
        let gamma = hourglass_shape(&nodes_new, &new);
        let q_r: f64 = (0..4).map(|k| gamma[k] * vel[k][0]).sum();
        let q_z: f64 = (0..4).map(|k| gamma[k] * vel[k][1]).sum();
        let (hourglass_r, hourglass_z, hourglass_power, carried) = hourglass_step(
            settings,
            density,
            output.wave_speed,
            &new,
            volume,
            spin * dt,
            dt,
            hourglass,
            [q_r, q_z],
        );
        *hourglass = carried;
        for (k, force) in forces.iter_mut().take(4).enumerate() {
            force[0] -= hourglass_r * gamma[k];
            force[1] -= hourglass_z * gamma[k];
        }
        Ok(ElementStep {
            hourglass_power,
            viscous_work,
            stable_dt: settings.stable_time_step(
                new.area / new.longest_diagonal,
                output.wave_speed,
                volumetric_rate,
            ),
        })
    }
}

/// Flanagan-Belytschko hourglass control of one element over a step: the generalised forces
/// `(r, z)` on the hourglass mode, the power they take from it, and the forces carried to the
/// next step. `wdt` is the spin times the step (the stiffness form turns
/// its forces with the element), `q` the hourglass velocities.
#[allow(clippy::too_many_arguments)]
fn hourglass_step(
    settings: &SolverSettings,
    density: f64,
    wave_speed: f64,
    new: &Geometry,
    volume: f64,
    wdt: f64,
    dt: f64,
    hourglass: &HourglassStress,
    [q_r, q_z]: [f64; 2],
) -> (f64, f64, f64, [f64; 2]) {
    let mut carried = [0.0; 2];
    let (r, z, power) = match settings.hourglass {
        HourglassControl::Viscous => {
            let kappa = 0.25
                * settings.hourglass_coefficient
                * density
                * wave_speed
                * new.area.sqrt()
                * new.mean_radius;
            // The generalised force is carried to the next step only for its work: booked
            // over the step at the mean of the previous and the new force, the
            // trapezoidal rule the kernel uses for the stress work. (Booked at the new
            // force alone, `kappa q^2`, a node's one-step kick is counted twice over:
            // its force acts over the next step's velocity change, not this one's.)
            carried = [kappa * q_r, kappa * q_z];
            let (old_r, old_z) = (hourglass[0], hourglass[1]);
            (
                carried[0],
                carried[1],
                0.5 * ((old_r + carried[0]) * q_r + (old_z + carried[1]) * q_z),
            )
        }
        HourglassControl::Stiffness => {
            let stiffness = hourglass_stiffness(
                settings.hourglass_coefficient,
                density,
                wave_speed,
                volume,
                new,
            );
            // Turned with the element (Q' = W Q dt), then incremented.
            let (old_r, old_z) = (hourglass[0], hourglass[1]);
            carried[0] = old_r + wdt * old_z + stiffness * q_r * dt;
            carried[1] = old_z - wdt * old_r + stiffness * q_z * dt;
            // Work over the step at the mean of the old (turned) and new forces: the
            // trapezoidal rule, as the kernel books the stress work.
            let half = 0.5 * stiffness * dt;
            (
                carried[0],
                carried[1],
                (carried[0] - half * q_r) * q_r + (carried[1] - half * q_z) * q_z,
            )
        }
    };
    (r, z, power, carried)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Grading;
    use stoss_kernel::damage::Failure;

    #[test]
    fn the_stretch_window_never_hides_a_kinematic_criterion() {
        // GOAL: skipping the logarithms of elements whose stretches lie inside the window of a
        //       failure setting never changes what the criteria decide.
        // SETUP: a 3 x 3 block of quads (one at the axis), its nodes moved by 20 000
        //        deterministic random affine maps with stretches up to e^+-1.2 and shears,
        //        plus a radial shift; geometric erosion 1.5 and principal failure 1.2, each
        //        alone and together.
        // REFERENCE: the criteria on the principal strains themselves: every element the
        //   window passes has no flag; and the window passes a good share of the maps.
        let mesh = QuadMesh::block(
            "p",
            0,
            (0.0, 3.0e-3),
            (0.0, 3.0e-3),
            3,
            3,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let reference = mesh.reference_positions();
        let settings = [(Some(1.5), None), (None, Some(1.2)), (Some(1.5), Some(1.2))];
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut passed, mut total) = (0, 0);
        for _ in 0..20_000 {
            let scale = libm::exp(2.4 * uniform() - 1.2);
            let squeeze = libm::exp(2.4 * uniform() - 1.2);
            let shear = 2.0 * uniform() - 1.0;
            let shift = 2.0e-3 * uniform();
            let x: Vec<Vector> = reference
                .iter()
                .map(|p| [shift + scale * p[0] + shear * p[1], squeeze * p[1], 0.0])
                .collect();
            for (erosion, failure) in settings {
                let criteria = Failure {
                    erosion_geometric_strain: erosion,
                    failure_principal_strain: failure,
                    ..Failure::NONE
                };
                let window = StretchWindow::new(criteria.kinematic_strain_bound().unwrap());
                for e in 0..mesh.element_count() {
                    total += 1;
                    if mesh.element_stretches_within(e, &reference, &x, &window) {
                        passed += 1;
                        let strains = mesh.element_principal_strains(e, &reference, &x).unwrap();
                        assert_eq!(criteria.kinematic_flags(strains).0, 0, "{strains:?}");
                    }
                }
            }
        }
        assert!(passed > total / 4, "{passed} of {total} passed the window");
    }
}
