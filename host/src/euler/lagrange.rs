//! The Lagrange step of the Eulerian cycle on the grid's rectangles.
//!
//! Cell `(i, j)` has the nodes `0: (i, j)`, `1: (i+1, j)`, `2: (i+1, j+1)`, `3: (i, j+1)`. On a
//! rectangle `h_r x h_z` at centre radius `r_c` the one-point quad of the Lagrangian solver
//! (`crate::solver::axisymmetric`) has the constant gradients `b_r = (-1, 1, 1, -1) / 2h_r`,
//! `b_z = (-1, -1, 1, 1) / 2h_z`, volume `V = A r_c` (per radian; `A` in planar grids), and
//! nodal forces `f_r,k = -(s_rr b_r,k + s_rz b_z,k) V - s_tt A / 4`,
//! `f_z,k = -(s_rz b_r,k + s_zz b_z,k) V`, the derivative of the internal power `V s : d`
//! with `d_tt = v_r_bar / r_c`. The cell's stress is the volume-fraction-weighted sum of its
//! materials' stresses (void carries none), less the bulk-viscosity pressure.
//!
//! The same velocities give the volume each face sweeps over the step, which is exactly the
//! cell's volume change of the quad (`V tr d dt = sum of the faces`): `h_z r_f v_r,f dt` across a
//! face of constant `r` and `h_r r_c v_z,f dt` across one of constant `z`, with the face
//! velocity the mean of its two nodes. The remap moves material by these volumes, so the
//! Lagrange step and the remap agree to round-off.

use super::closure::{self, Phase};
use super::interface::{block_cells, youngs_normal};
use super::CavityDrive;
use super::{EulerError, EulerSolver, Wall, MAX_MATERIALS, MAX_PHASES};
use crate::solver::axisymmetric::rotate_jaumann;
use rayon::prelude::*;
use stoss_kernel::{PointModel, StepInput};

/// The volumes swept by the faces in one step (per radian or unit depth), positive along
/// `+r` or `+z`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceFluxes {
    /// Faces of constant `r`: `(cells_r + 1) x cells_z`, face `i` of row `j` at
    /// `j (cells_r + 1) + i`, between cells `(i - 1, j)` and `(i, j)`.
    pub r: Vec<f64>,
    /// Faces of constant `z`: `cells_r x (cells_z + 1)`, face `j` of column `i` at
    /// `j cells_r + i`, between cells `(i, j - 1)` and `(i, j)`.
    pub z: Vec<f64>,
}

/// Velocity gradient of a rectangle from its nodal velocities, with the hoop rate.
#[derive(Clone, Copy, Debug)]
struct Rates {
    rr: f64,
    zz: f64,
    tt: f64,
    rz: f64,
    spin: f64,
}

/// The cell's nodes in the order 0-3.
fn cell_nodes(nodes_r: usize, i: usize, j: usize) -> [usize; 4] {
    [
        j * nodes_r + i,
        j * nodes_r + i + 1,
        (j + 1) * nodes_r + i + 1,
        (j + 1) * nodes_r + i,
    ]
}

const B_R: [f64; 4] = [-0.5, 0.5, 0.5, -0.5];
const B_Z: [f64; 4] = [-0.5, -0.5, 0.5, 0.5];
const HOURGLASS: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

fn rates(v: &[[f64; 2]; 4], h_r: f64, h_z: f64, hoop_radius: Option<f64>) -> Rates {
    let mut g = [[0.0; 2]; 2];
    for k in 0..4 {
        g[0][0] += B_R[k] * v[k][0] / h_r;
        g[0][1] += B_Z[k] * v[k][0] / h_z;
        g[1][0] += B_R[k] * v[k][1] / h_r;
        g[1][1] += B_Z[k] * v[k][1] / h_z;
    }
    let tt = hoop_radius.map_or(0.0, |r| 0.25 * (v[0][0] + v[1][0] + v[2][0] + v[3][0]) / r);
    Rates {
        rr: g[0][0],
        zz: g[1][1],
        tt,
        rz: 0.5 * (g[0][1] + g[1][0]),
        spin: 0.5 * (g[0][1] - g[1][0]),
    }
}

/// Set the walls' velocity components (the axis of an axisymmetric grid and the inner edge of
/// a planar one are slip walls).
pub fn apply_walls<P>(s: &mut EulerSolver<P>) {
    let nr = s.grid.cells_r + 1;
    let nz = s.grid.cells_z + 1;
    for j in 0..nz {
        s.velocity[j * nr][0] = 0.0;
        match s.walls.outer {
            Wall::Fixed => s.velocity[j * nr + nr - 1] = [0.0; 2],
            Wall::Slip => s.velocity[j * nr + nr - 1][0] = 0.0,
        }
    }
    for i in 0..nr {
        match s.walls.bottom {
            Wall::Fixed => s.velocity[i] = [0.0; 2],
            Wall::Slip => s.velocity[i][1] = 0.0,
        }
        match s.walls.top {
            Wall::Fixed => s.velocity[(nz - 1) * nr + i] = [0.0; 2],
            Wall::Slip => s.velocity[(nz - 1) * nr + i][1] = 0.0,
        }
    }
}

/// What one cell's Lagrange update produced.
#[derive(Clone, Copy, Debug, Default)]
struct CellWork {
    viscous: f64,
    updates: u64,
}

impl<P: PointModel + Sync + Send + Clone> EulerSolver<P> {
    /// Nodal forces of every cell: `(corner forces, hourglass power)`.
    fn cell_forces(&self) -> Vec<([[f64; 2]; 4], f64)> {
        let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
        let cells_r = self.grid.cells_r;
        let nodes_r = self.nodes_r();
        let axisymmetric = self.axisymmetric();
        let area = h_r * h_z;
        let coefficient = self.settings.hourglass_coefficient;
        (0..self.grid.cell_count())
            .into_par_iter()
            .with_max_len(super::CELLS_PER_TASK)
            .map(|c| {
                let (i, j) = (c % cells_r, c / cells_r);
                if !super::in_work(&self.active_end, i, j) {
                    return ([[0.0; 2]; 4], 0.0);
                }
                let volume = self.cell_volume(i);
                let mut stress = [0.0; 4];
                let mut mass = 0.0;
                let mut material_volume = 0.0;
                let mut wave = 0.0_f64;
                for k in 0..self.materials.len() {
                    let slot = c * MAX_MATERIALS + k;
                    let f = self.volume[c * MAX_PHASES + k] / volume;
                    // A material below the active fraction takes no part in the Lagrange
                    // step: its (unupdated) stress acts on no node.
                    if self.mass[slot] <= 0.0 || f < super::ACTIVE_FRACTION {
                        continue;
                    }
                    let s = &self.state[slot].stress;
                    stress[0] += f * s[0];
                    stress[1] += f * s[1];
                    stress[2] += f * s[2];
                    stress[3] += f * s[3];
                    mass += self.mass[slot];
                    material_volume += self.volume[c * MAX_PHASES + k];
                    wave = wave.max(self.wave_speed[slot]);
                }
                if mass == 0.0 {
                    return ([[0.0; 2]; 4], 0.0);
                }
                let q = self.viscous_pressure[c] * material_volume / volume;
                let (s_rr, s_zz, s_tt, s_rz) =
                    (stress[0] - q, stress[1] - q, stress[2] - q, stress[3]);
                let hoop = if axisymmetric {
                    0.25 * area * s_tt
                } else {
                    0.0
                };
                let v: [[f64; 2]; 4] = cell_nodes(nodes_r, i, j).map(|n| self.velocity[n]);
                // LS-DYNA's viscous form (IHQ = 1), as the Lagrangian quad.
                let kappa = 0.25 * coefficient * mass / volume
                    * wave
                    * area.sqrt()
                    * self.weight((i as f64 + 0.5) * h_r);
                let q_r: f64 = (0..4).map(|k| HOURGLASS[k] * v[k][0]).sum();
                let q_z: f64 = (0..4).map(|k| HOURGLASS[k] * v[k][1]).sum();
                let mut f = [[0.0; 2]; 4];
                for k in 0..4 {
                    let (b_r, b_z) = (B_R[k] / h_r, B_Z[k] / h_z);
                    f[k][0] =
                        -(s_rr * b_r + s_rz * b_z) * volume - hoop - kappa * q_r * HOURGLASS[k];
                    f[k][1] = -(s_rz * b_r + s_zz * b_z) * volume - kappa * q_z * HOURGLASS[k];
                }
                (f, kappa * (q_r * q_r + q_z * q_z))
            })
            .collect()
    }

    /// Advance the nodal velocities over `dt` under the cell forces; returns the hourglass
    /// work (per radian or unit depth).
    fn accelerate(&mut self, dt: f64) -> f64 {
        let forces = self.cell_forces();
        let masses = self.node_masses();
        // A drive's work needs each node's velocity before the step.
        let before = self.drive.map(|_| self.velocity.clone());

        let cells_r = self.grid.cells_r;
        let cells_z = self.grid.cells_z;
        let nodes_r = self.nodes_r();
        self.velocity.par_iter_mut().enumerate().for_each(|(n, v)| {
            let (i, j) = (n % nodes_r, n / nodes_r);
            let m = masses[n];
            if m <= 0.0 {
                *v = [0.0; 2];
                return;
            }
            let mut f = [0.0; 2];
            // (cell column, cell row, corner of that cell at this node)
            let around = [
                (i.wrapping_sub(1), j.wrapping_sub(1), 2),
                (i, j.wrapping_sub(1), 3),
                (i, j, 0),
                (i.wrapping_sub(1), j, 1),
            ];
            for (ci, cj, corner) in around {
                if ci < cells_r && cj < cells_z {
                    let cf = forces[cj * cells_r + ci].0[corner];
                    f[0] += cf[0];
                    f[1] += cf[1];
                }
            }
            v[0] += dt * f[0] / m;
            v[1] += dt * f[1] / m;
        });
        let hourglass = super::ordered_sum(forces.len(), |c| forces[c].1);
        // A wall node was at rest (in the constrained direction) and stays so: the wall's
        // reaction does no work, and the velocity the step gave it is not kinetic energy.
        apply_walls(self);
        if let (Some(drive), Some(before)) = (self.drive, before) {
            let driven = self.apply_drive(&drive, &masses, &before, dt);
            self.energy.driven += driven * self.body_factor();
        }
        hourglass * dt
    }

    /// Set the velocity of every node inside the drive's sphere at mid-step; returns the
    /// work of the constraint over the step, `sum m (v_drive - v_free) . (v_drive + v_before)
    /// / 2` (what the leapfrog's kinetic energy gains beyond the forces' work; per radian or
    /// unit depth, as the nodal masses).
    fn apply_drive(
        &mut self,
        drive: &CavityDrive,
        masses: &[f64],
        before: &[[f64; 2]],
        dt: f64,
    ) -> f64 {
        let radius = drive.radius(self.time + 0.5 * dt);
        let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
        let nodes_r = self.nodes_r();
        let origin_z = self.origin_z;
        let mut added = 0.0;
        for (n, v) in self.velocity.iter_mut().enumerate() {
            let (i, j) = (n % nodes_r, n / nodes_r);
            let offset = [i as f64 * h_r, origin_z + j as f64 * h_z - drive.center_z];
            if offset[0] * offset[0] + offset[1] * offset[1] > radius * radius {
                continue;
            }
            let driven = [
                drive.speed * offset[0] / radius,
                drive.speed * offset[1] / radius,
            ];
            let old = before[n];
            added += 0.5
                * masses[n]
                * ((driven[0] - v[0]) * (driven[0] + old[0])
                    + (driven[1] - v[1]) * (driven[1] + old[1]));
            *v = driven;
        }
        added
    }

    /// The volumes the faces sweep over `dt` at the current velocities.
    pub(super) fn face_fluxes(&self, dt: f64) -> FaceFluxes {
        let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
        let cells_r = self.grid.cells_r;
        let cells_z = self.grid.cells_z;
        let nodes_r = self.nodes_r();
        let cell_scale = |i: usize| self.cell_volume(i.min(cells_r - 1));
        let r = (0..nodes_r * cells_z)
            .into_par_iter()
            .map(|f| {
                let (i, j) = (f % nodes_r, f / nodes_r);
                let u = 0.5
                    * (self.velocity[j * nodes_r + i][0] + self.velocity[(j + 1) * nodes_r + i][0]);
                negligible_to_zero(dt * h_z * self.weight(i as f64 * h_r) * u, cell_scale(i))
            })
            .collect();
        let z = (0..cells_r * (cells_z + 1))
            .into_par_iter()
            .map(|f| {
                let (i, j) = (f % cells_r, f / cells_r);
                let w = 0.5
                    * (self.velocity[j * nodes_r + i][1] + self.velocity[j * nodes_r + i + 1][1]);
                negligible_to_zero(
                    dt * h_r * self.weight((i as f64 + 0.5) * h_r) * w,
                    cell_scale(i),
                )
            })
            .collect();
        FaceFluxes { r, z }
    }
}

/// Remove the shear on the interface plane of normal `n` (in `(r, z)`) from a strain
/// increment and a stress (`rr, zz, tt, rz`, tensor components): with `t = (-n_z, n_r)`, the
/// component `x_nt = t . X . n` is taken off as `X - x_nt (t n + n t)`, which leaves the
/// trace, the normal component `n . X . n` and the hoop component unchanged. A material in an
/// interface's boundary layer then neither resists nor dissipates sliding along it: a
/// frictionless interface ([`super::EulerSettings::sliding_interfaces`]).
fn release_interface_shear(increment: &mut [f64; 6], stress: &mut [f64; 6], n: [f64; 2]) {
    let t = [-n[1], n[0]];
    for x in [increment, stress] {
        let x_nt = t[0] * n[0] * x[0] + t[1] * n[1] * x[1] + (t[0] * n[1] + t[1] * n[0]) * x[3];
        x[0] -= 2.0 * x_nt * t[0] * n[0];
        x[1] -= 2.0 * x_nt * t[1] * n[1];
        x[3] -= x_nt * (t[0] * n[1] + t[1] * n[0]);
    }
}

impl<P: PointModel + Sync + Send + Clone> EulerSolver<P> {
    /// With [`super::EulerSettings::sliding_interfaces`], each cell's materials' interface
    /// normals where they slide: a material in a cell whose 3 x 3 block holds another material
    /// (its boundary layer) takes Youngs' normal of its own fractions there (the block the
    /// remap's reconstruction reads); `None` elsewhere. Empty without the setting or with one
    /// material.
    fn slip_normals(&self) -> Vec<[Option<[f64; 2]>; MAX_MATERIALS]> {
        if !self.settings.sliding_interfaces || self.materials.len() < 2 {
            return Vec::new();
        }
        let (cells_r, cells_z) = (self.grid.cells_r, self.grid.cells_z);
        let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
        let count = self.materials.len();
        let present = |c: usize, k: usize| {
            self.mass[c * MAX_MATERIALS + k] > 0.0 && self.fraction(c, k) >= super::ACTIVE_FRACTION
        };
        (0..self.grid.cell_count())
            .into_par_iter()
            .with_max_len(super::CELLS_PER_TASK)
            .map(|c| {
                let mut normals = [None; MAX_MATERIALS];
                let (i, j) = (c % cells_r, c / cells_r);
                if !super::in_work(&self.active_end, i, j) {
                    return normals;
                }
                let block = block_cells(i, j, cells_r, cells_z);
                for (k, normal) in normals.iter_mut().enumerate().take(count) {
                    let beside_another = block
                        .iter()
                        .flatten()
                        .any(|&n| (0..count).any(|m| m != k && present(n, m)));
                    if present(c, k) && beside_another {
                        *normal = youngs_normal(
                            block.map(|row| row.map(|n| self.fraction(n, k))),
                            h_r,
                            h_z,
                        );
                    }
                }
                normals
            })
            .collect()
    }
}

/// Fraction of a cell's volume below which a face's swept volume is taken as zero, by the
/// Lagrange step and the remap alike. The explicit scheme's numerical precursor sends
/// velocities of 1e-300 m/s and below ahead of every wave; carried as fluxes, their masses
/// underflow to subnormal numbers whose ratios are not finite.
const NEGLIGIBLE_SWEPT_FRACTION: f64 = 1e-13;

/// `swept`, or zero if below [`NEGLIGIBLE_SWEPT_FRACTION`] of `cell`.
fn negligible_to_zero(swept: f64, cell: f64) -> f64 {
    if swept.abs() < NEGLIGIBLE_SWEPT_FRACTION * cell {
        0.0
    } else {
        swept
    }
}

/// One Lagrange step of `dt`: velocities, strain increments, every material's kernel update,
/// the bulk viscosity. Returns the faces' swept volumes for the remap.
pub fn step<P: PointModel + Sync + Send + Clone>(
    s: &mut EulerSolver<P>,
    dt: f64,
) -> Result<FaceFluxes, EulerError> {
    let hourglass = s.accelerate(dt);
    let fluxes = s.face_fluxes(dt);
    let (h_r, h_z) = (s.grid.spacing_r, s.grid.spacing_z);
    let cells_r = s.grid.cells_r;
    let nodes_r = s.nodes_r();
    let axisymmetric = s.axisymmetric();
    let time = s.time;
    let length = h_r.min(h_z);
    let slip = s.slip_normals();
    let velocity = &s.velocity;
    let materials = &s.materials;
    let settings = &s.settings;
    let origin_z = s.origin_z;
    let active_end = &s.active_end;
    let results: Vec<Result<CellWork, Box<EulerError>>> = s
        .state
        .par_chunks_mut(MAX_MATERIALS)
        .zip(s.volume.par_chunks_mut(MAX_PHASES))
        .zip(s.wave_speed.par_chunks_mut(MAX_MATERIALS))
        .zip(s.viscous_pressure.par_iter_mut())
        .zip(s.viscous_speed.par_iter_mut())
        .zip(s.mass.par_chunks(MAX_MATERIALS))
        .enumerate()
        .with_max_len(super::CELLS_PER_TASK)
        .map(
            |(c, (((((states, volumes), waves), q), q_speed), masses))| {
                let (i, j) = (c % cells_r, c / cells_r);
                if !super::in_work(active_end, i, j) {
                    return Ok(CellWork::default());
                }
                let change = fluxes.r[j * nodes_r + i + 1] - fluxes.r[j * nodes_r + i]
                    + fluxes.z[(j + 1) * cells_r + i]
                    - fluxes.z[j * cells_r + i];
                if masses.iter().all(|&m| m == 0.0) {
                    volumes[MAX_PHASES - 1] += change;
                    *q = 0.0;
                    *q_speed = 0.0;
                    return Ok(CellWork::default());
                }
                let v: [[f64; 2]; 4] = cell_nodes(nodes_r, i, j).map(|n| velocity[n]);
                let r_c = (i as f64 + 0.5) * h_r;
                let rate = rates(&v, h_r, h_z, axisymmetric.then_some(r_c));
                let total: f64 = volumes.iter().sum();
                let mut phases = [Phase::default(); MAX_PHASES];
                for k in 0..materials.len() {
                    let f = volumes[k] / total;
                    let model = &materials[k].model;
                    let stiffness =
                        model.density() / states[k].relative_volume * waves[k] * waves[k];
                    // The kernel's wave speed is sqrt((B + 4G V/3) / rho0): take the shear part off.
                    let bulk = stiffness - 4.0 / 3.0 * model.shear_modulus();
                    phases[k] = Phase {
                        volume: volumes[k],
                        stiffness,
                        pressure: -(states[k].stress[0]
                            + states[k].stress[1]
                            + states[k].stress[2])
                            / 3.0,
                        active: masses[k] > 0.0 && f >= super::ACTIVE_FRACTION,
                        bulk_modulus: if bulk > 0.0 { bulk } else { stiffness },
                        fracture_pressure: materials[k]
                            .fracture_pressure
                            .unwrap_or(f64::NEG_INFINITY),
                    };
                }
                phases[MAX_PHASES - 1].volume = volumes[MAX_PHASES - 1];
                let shares = closure::share(change, &phases, materials.len());
                let increment = [
                    rate.rr * dt,
                    rate.zz * dt,
                    rate.tt * dt,
                    rate.rz * dt,
                    0.0,
                    0.0,
                ];
                let mut work = CellWork::default();
                let mut material_change = 0.0;
                let mut material_volume = 0.0;
                let mut mass = 0.0;
                let mut wave = 0.0_f64;
                for k in 0..materials.len() {
                    if !phases[k].active {
                        continue;
                    }
                    let model = &materials[k].model;
                    let new_volume = volumes[k] + shares[k];
                    let relative_volume = model.density() * new_volume / masses[k];
                    // Advanced in place (no copy); on an error the run ends.
                    let state = &mut states[k];
                    rotate_jaumann(&mut state.stress, rate.spin, dt);
                    let mut increment = increment;
                    if let Some(n) = slip.get(c).and_then(|normals| normals[k]) {
                        release_interface_shear(&mut increment, &mut state.stress, n);
                    }
                    let output = model
                        .update(
                            state,
                            &StepInput {
                                strain_increment: increment,
                                dt,
                                relative_volume,
                            },
                        )
                        .map_err(|error| {
                            Box::new(EulerError::Update {
                                material: materials[k].name.clone(),
                                i,
                                j,
                                r: r_c,
                                z: origin_z + (j as f64 + 0.5) * h_z,
                                time,
                                relative_volume,
                                error,
                            })
                        })?;
                    waves[k] = output.wave_speed;
                    volumes[k] = new_volume;
                    material_change += shares[k];
                    material_volume += new_volume;
                    mass += masses[k];
                    wave = wave.max(output.wave_speed);
                    work.updates += 1;
                }
                volumes[MAX_PHASES - 1] += change - material_change;
                if material_volume > 0.0 {
                    let volumetric_rate = material_change / (material_volume * dt);
                    *q = settings.bulk_viscosity.pressure(
                        mass / material_volume,
                        length,
                        volumetric_rate,
                        wave,
                    );
                    *q_speed =
                        settings
                            .bulk_viscosity
                            .time_step_speed(length, wave, volumetric_rate);
                    work.viscous = -*q * material_change;
                } else {
                    *q = 0.0;
                    *q_speed = 0.0;
                }
                Ok(work)
            },
        )
        .collect();
    let mut viscous = 0.0;
    for result in results {
        let work = result.map_err(|e| *e)?;
        viscous += work.viscous;
        s.material_updates += work.updates;
    }
    let factor = s.body_factor();
    s.energy.viscous += viscous * factor;
    s.energy.hourglass += hourglass * factor;
    Ok(fluxes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn releasing_the_interface_shear_leaves_the_normal_and_volumetric_parts() {
        // GOAL: the sliding interface removes only the shear on the interface plane.
        // SETUP: a full strain increment and stress, interface normals at 0, 30, 90 and 135
        //        degrees in (r, z).
        // REFERENCE: X' = X - x_nt (t n + n t), t = (-n_z, n_r): t.X'.n = 0, and n.X'.n,
        //            t.X'.t, the trace and the hoop component are X's.
        for degrees in [0.0_f64, 30.0, 90.0, 135.0] {
            let angle = degrees.to_radians();
            let n = [angle.cos(), angle.sin()];
            let t = [-n[1], n[0]];
            let mut increment = [1.0e-3, -2.5e-3, 0.7e-3, 1.9e-3, 0.0, 0.0];
            let mut stress = [-1.2e9, 0.4e9, -0.3e9, 0.8e9, 0.0, 0.0];
            let (x0, s0) = (increment, stress);
            release_interface_shear(&mut increment, &mut stress, n);
            let along = |x: &[f64; 6], a: [f64; 2], b: [f64; 2]| {
                a[0] * b[0] * x[0] + a[1] * b[1] * x[1] + (a[0] * b[1] + a[1] * b[0]) * x[3]
            };
            for (after, before, scale) in [(&increment, &x0, 1e-3), (&stress, &s0, 1e9)] {
                assert!(
                    along(after, t, n).abs() < 1e-15 * scale,
                    "{degrees}: shear left"
                );
                assert!((along(after, n, n) - along(before, n, n)).abs() < 1e-15 * scale);
                assert!((along(after, t, t) - along(before, t, t)).abs() < 1e-15 * scale);
                assert!(((after[0] + after[1]) - (before[0] + before[1])).abs() < 1e-15 * scale);
                assert_eq!(after[2], before[2]);
            }
        }
    }
}
