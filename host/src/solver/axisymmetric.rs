//! 2D axisymmetric explicit solver on 4-node quadrilaterals (`r`, `z`), one-point integration.
//!
//! Element formulation (per radian; energies and forces are reported over 2 pi):
//! - mean-derivative (Flanagan-Belytschko) gradients at the centroid, `b_r`, `b_z`;
//! - volume `V = A r_bar` with `r_bar` the mean nodal radius, hoop rate `d_tt = v_r_bar / r_bar`;
//! - volume-weighted nodal forces `f_r,i = -(s_rr b_r,i + s_rz b_z,i) V - s_tt A/4`,
//!   `f_z,i = -(s_rz b_r,i + s_zz b_z,i) V`, which are exactly the derivative of the
//!   internal power `V s:d` (so stress work and kinetic energy balance);
//! - lumped mass `rho0 V0 / 4` per node.
//!
//! Kernel Voigt mapping: `[rr, zz, tt, rz, 0, 0]` (x = r, y = z, z = theta).

use super::energy::EnergyBalance;
use super::loads::{RigidWall, VelocityConstraint};
use super::{SolverError, SolverSettings};
use crate::measure::{StateHistory, StateSample};
use crate::mesh::QuadMesh;
use rayon::prelude::*;
use std::f64::consts::PI;
use stoss_kernel::{update, Material, MaterialState, StateFlags, StepInput};

/// A complete axisymmetric model.
#[derive(Clone, Debug)]
pub struct AxisymmetricModel {
    /// The mesh; each part names its material index.
    pub mesh: QuadMesh,
    /// Materials, indexed by `Part::material`.
    pub materials: Vec<Material>,
    /// Initial temperature (K).
    pub initial_temperature: f64,
    /// Initial nodal velocities `[v_r, v_z]` (empty: at rest).
    pub initial_velocity: Vec<[f64; 2]>,
    /// Prescribed velocities.
    pub constraints: Vec<VelocityConstraint>,
    /// Rigid walls.
    pub walls: Vec<RigidWall>,
    /// Numerical settings.
    pub settings: SolverSettings,
    /// Elements whose state history is recorded (for measurements and diagnosis).
    pub tracked_elements: Vec<usize>,
}

/// The result of a run.
#[derive(Clone, Debug)]
pub struct AxisymmetricRun {
    /// Final nodal positions `[r, z]`.
    pub positions: Vec<[f64; 2]>,
    /// Final nodal velocities.
    pub velocities: Vec<[f64; 2]>,
    /// Final element states.
    pub states: Vec<MaterialState>,
    /// Eroded elements.
    pub eroded: Vec<bool>,
    /// Energy balance at every output interval, and the final one last.
    pub energy_history: Vec<EnergyBalance>,
    /// Tracked element histories, in the order of `tracked_elements`.
    pub tracked: Vec<StateHistory>,
    /// Reaction force histories `(time, force over 2 pi)` on each constraint's dof.
    pub constraint_forces: Vec<Vec<(f64, f64)>>,
    /// Time steps taken.
    pub steps: usize,
    /// Element updates performed (element-cycles).
    pub element_cycles: u64,
}

impl AxisymmetricRun {
    /// The final energy balance.
    pub fn energy(&self) -> EnergyBalance {
        self.energy_history.last().copied().unwrap_or_default()
    }
}

/// Per-element result of one step.
#[derive(Clone, Copy)]
struct ElementStep {
    state: MaterialState,
    forces: [[f64; 2]; 4],
    hourglass_power: f64,
    viscous_work: f64,
    stable_dt: f64,
    erode: bool,
}

/// Geometry of a quad: area, mean radius, gradient operators.
struct Geometry {
    area: f64,
    mean_radius: f64,
    b_r: [f64; 4],
    b_z: [f64; 4],
    longest_diagonal: f64,
}

fn geometry(x: &[[f64; 2]; 4]) -> Geometry {
    let [p0, p1, p2, p3] = *x;
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
    let d1 = ((p2[0] - p0[0]).powi(2) + (p2[1] - p0[1]).powi(2)).sqrt();
    let d2 = ((p3[0] - p1[0]).powi(2) + (p3[1] - p1[1]).powi(2)).sqrt();
    Geometry {
        area,
        mean_radius: 0.25 * (p0[0] + p1[0] + p2[0] + p3[0]),
        b_r,
        b_z,
        longest_diagonal: d1.max(d2),
    }
}

/// Stable time step of an element: `L / (Q + sqrt(Q^2 + c^2))`, `L = A / longest diagonal`,
/// `Q = C1 c + C0 L |d_v|` while compressing (LS-DYNA's form with bulk viscosity).
fn stable_time_step(
    geom: &Geometry,
    wave_speed: f64,
    volumetric_rate: f64,
    s: &SolverSettings,
) -> f64 {
    let length = geom.area / geom.longest_diagonal;
    let q = if volumetric_rate < 0.0 {
        s.linear_viscosity * wave_speed + s.quadratic_viscosity * length * volumetric_rate.abs()
    } else {
        0.0
    };
    length / (q + (q * q + wave_speed * wave_speed).sqrt())
}

/// Jaumann rotation of the stress over one step with in-plane spin `w = (dv_r/dz - dv_z/dr)/2`.
fn rotate_jaumann(stress: &mut [f64; 6], spin: f64, dt: f64) {
    let (rr, zz, rz) = (stress[0], stress[1], stress[3]);
    let wdt = spin * dt;
    stress[0] = rr + 2.0 * wdt * rz;
    stress[1] = zz - 2.0 * wdt * rz;
    stress[3] = rz + wdt * (zz - rr);
}

struct Precomputed {
    reference_volume: Vec<f64>,
    mass: Vec<f64>,
    material_of: Vec<usize>,
}

impl AxisymmetricModel {
    fn precompute(&self) -> Result<Precomputed, SolverError> {
        let mesh = &self.mesh;
        let mut mass = vec![0.0; mesh.nodes.len()];
        let mut reference_volume = Vec::with_capacity(mesh.elements.len());
        let mut material_of = Vec::with_capacity(mesh.elements.len());
        for (e, element) in mesh.elements.iter().enumerate() {
            let part = &mesh.parts[mesh.element_part[e]];
            let material = self.materials.get(part.material).ok_or_else(|| {
                SolverError::Model(format!(
                    "part {} names material {} which does not exist",
                    part.name, part.material
                ))
            })?;
            let geom = geometry(&element.map(|n| mesh.nodes[n]));
            if geom.area <= 0.0 || geom.mean_radius <= 0.0 {
                return Err(SolverError::InvertedElement {
                    element: e,
                    time: 0.0,
                });
            }
            let volume = geom.area * geom.mean_radius;
            reference_volume.push(volume);
            for &n in element {
                mass[n] += 0.25 * material.density * volume;
            }
            material_of.push(part.material);
        }
        for (index, material) in self.materials.iter().enumerate() {
            material.validate().map_err(|error| SolverError::Material {
                part: mesh
                    .parts
                    .iter()
                    .find(|p| p.material == index)
                    .map_or_else(|| format!("material {index}"), |p| p.name.clone()),
                error,
            })?;
        }
        Ok(Precomputed {
            reference_volume,
            mass,
            material_of,
        })
    }

    /// Run the model to `settings.end_time`. `progress(time, energy)` is called at every
    /// output interval.
    pub fn run(
        &self,
        progress: &mut (dyn FnMut(f64, &EnergyBalance) + Send),
    ) -> Result<AxisymmetricRun, SolverError> {
        match self.settings.threads {
            Some(threads) => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| SolverError::Model(format!("thread pool: {e}")))?;
                pool.install(|| self.run_in_pool(progress))
            }
            None => self.run_in_pool(progress),
        }
    }

    fn run_in_pool(
        &self,
        progress: &mut (dyn FnMut(f64, &EnergyBalance) + Send),
    ) -> Result<AxisymmetricRun, SolverError> {
        let settings = &self.settings;
        let mesh = &self.mesh;
        let pre = self.precompute()?;
        let node_count = mesh.nodes.len();
        let mut x = mesh.nodes.clone();
        let mut v = if self.initial_velocity.is_empty() {
            vec![[0.0; 2]; node_count]
        } else if self.initial_velocity.len() == node_count {
            self.initial_velocity.clone()
        } else {
            return Err(SolverError::Model(
                "initial velocity must give one vector per node".into(),
            ));
        };
        let mut states =
            vec![MaterialState::initial(self.initial_temperature); mesh.elements.len()];
        let mut eroded = vec![false; mesh.elements.len()];
        let mut force = vec![[0.0; 2]; node_count];

        // Initial wave speeds for the first time step: a zero-strain update of each material.
        let mut dt = f64::INFINITY;
        for (e, element) in mesh.elements.iter().enumerate() {
            let material = &self.materials[pre.material_of[e]];
            let mut probe = states[e];
            let output = update(
                material,
                &mut probe,
                &StepInput {
                    strain_increment: [0.0; 6],
                    dt: 1.0,
                    relative_volume: 1.0,
                },
            )
            .map_err(|error| SolverError::Update {
                element: e,
                time: 0.0,
                error,
            })?;
            let geom = geometry(&element.map(|n| x[n]));
            dt = dt.min(stable_time_step(&geom, output.wave_speed, 0.0, settings));
        }
        dt *= settings.time_step_safety;
        let minimum_dt = dt * 1e-4;

        let kinetic = |v: &[[f64; 2]]| -> f64 {
            2.0 * PI
                * v.iter()
                    .zip(&pre.mass)
                    .map(|(vel, m)| 0.5 * m * (vel[0] * vel[0] + vel[1] * vel[1]))
                    .sum::<f64>()
        };
        let mut energy = EnergyBalance {
            kinetic: kinetic(&v),
            ..EnergyBalance::default()
        };
        energy.initial = energy.total();
        let mut energy_history = vec![energy];
        let mut tracked: Vec<StateHistory> = self
            .tracked_elements
            .iter()
            .map(|e| StateHistory {
                label: format!("element {e}"),
                samples: Vec::new(),
            })
            .collect();
        let mut constraint_forces: Vec<Vec<(f64, f64)>> = vec![Vec::new(); self.constraints.len()];
        let mut time = 0.0;
        let mut dt_previous = 0.0;
        let mut next_output = settings.output_interval;
        let mut steps = 0;
        let mut element_cycles = 0u64;
        let wall_slaves: Vec<Vec<usize>> = self
            .walls
            .iter()
            .map(|w| {
                if w.nodes.is_empty() {
                    (0..node_count).collect()
                } else {
                    w.nodes.clone()
                }
            })
            .collect();

        while time < settings.end_time {
            let dt_average = 0.5 * (dt_previous + dt);
            // Velocity update v_{n+1/2} = v_{n-1/2} + a_n dt.
            let v_old = v.clone();
            for n in 0..node_count {
                if pre.mass[n] > 0.0 {
                    for d in 0..2 {
                        v[n][d] += force[n][d] / pre.mass[n] * dt_average;
                    }
                }
            }
            let half_time = time + 0.5 * dt;
            // Kinematic modifications of v_{n+1/2}; each records its velocity change per node so
            // that its work is the central-difference-consistent `m dv . (v_old + v_new)/2`.
            let mut dv_constraint = vec![[0.0; 2]; node_count];
            let mut dv_wall = vec![[0.0; 2]; node_count];
            let mut dv_damping = vec![[0.0; 2]; node_count];
            for (c, constraint) in self.constraints.iter().enumerate() {
                let target = constraint.velocity.at(half_time);
                let mut reaction = 0.0;
                for &n in &constraint.nodes {
                    let change = target - v[n][constraint.dof];
                    dv_constraint[n][constraint.dof] += change;
                    if dt_average > 0.0 {
                        reaction += pre.mass[n] * change / dt_average;
                    }
                    v[n][constraint.dof] = target;
                }
                constraint_forces[c].push((time, 2.0 * PI * reaction));
            }
            // Rigid walls: stop the normal approach, Coulomb friction on the tangential part.
            for (wall, slaves) in self.walls.iter().zip(&wall_slaves) {
                let normal = [wall.normal[0], wall.normal[1]];
                for &n in slaves {
                    let gap = (x[n][0] - wall.point[0]) * normal[0]
                        + (x[n][1] - wall.point[1]) * normal[1];
                    let vn = v[n][0] * normal[0] + v[n][1] * normal[1];
                    if gap + vn * dt >= 0.0 {
                        continue;
                    }
                    let before = v[n];
                    let vn_new = -gap / dt;
                    let dvn = vn_new - vn;
                    let mut vt = [v[n][0] - vn * normal[0], v[n][1] - vn * normal[1]];
                    let speed_t = (vt[0] * vt[0] + vt[1] * vt[1]).sqrt();
                    if speed_t > 0.0 {
                        let reduction = (wall.friction * dvn).min(speed_t);
                        let keep = (speed_t - reduction) / speed_t;
                        vt = [vt[0] * keep, vt[1] * keep];
                    }
                    v[n] = [vt[0] + vn_new * normal[0], vt[1] + vn_new * normal[1]];
                    dv_wall[n] = [
                        dv_wall[n][0] + v[n][0] - before[0],
                        dv_wall[n][1] + v[n][1] - before[1],
                    ];
                }
            }
            // Nodal damping.
            if let Some(damping) = settings.damping {
                if time >= damping.start_time {
                    let factor = 1.0 - damping.coefficient * dt;
                    for (vel, change) in v.iter_mut().zip(dv_damping.iter_mut()) {
                        *change = [vel[0] * (factor - 1.0), vel[1] * (factor - 1.0)];
                        vel[0] *= factor;
                        vel[1] *= factor;
                    }
                }
            }
            for n in 0..node_count {
                let mean = [0.5 * (v_old[n][0] + v[n][0]), 0.5 * (v_old[n][1] + v[n][1])];
                let work =
                    |dv: [f64; 2]| 2.0 * PI * pre.mass[n] * (dv[0] * mean[0] + dv[1] * mean[1]);
                energy.external_work += work(dv_constraint[n]);
                energy.contact -= work(dv_wall[n]);
                energy.damping -= work(dv_damping[n]);
            }
            let x_new: Vec<[f64; 2]> = x
                .iter()
                .zip(&v)
                .map(|(p, vel)| [p[0] + vel[0] * dt, p[1] + vel[1] * dt])
                .collect();

            // Elements, in parallel; results kept in element order.
            let results: Vec<Result<Option<ElementStep>, SolverError>> = (0..mesh.elements.len())
                .into_par_iter()
                .map(|e| {
                    if eroded[e] {
                        return Ok(None);
                    }
                    let element = mesh.elements[e];
                    let material = &self.materials[pre.material_of[e]];
                    let nodes_new = element.map(|n| x_new[n]);
                    let nodes_mid = element
                        .map(|n| [0.5 * (x[n][0] + x_new[n][0]), 0.5 * (x[n][1] + x_new[n][1])]);
                    let vel = element.map(|n| v[n]);
                    let mid = geometry(&nodes_mid);
                    let new = geometry(&nodes_new);
                    if mid.area <= 0.0 || new.area <= 0.0 || new.mean_radius <= 0.0 {
                        return Err(SolverError::InvertedElement { element: e, time });
                    }
                    let mut grad = [[0.0; 2]; 2]; // grad[i][j] = d v_i / d x_j, x = (r, z)
                    for (k, velocity) in vel.iter().enumerate() {
                        grad[0][0] += mid.b_r[k] * velocity[0];
                        grad[0][1] += mid.b_z[k] * velocity[0];
                        grad[1][0] += mid.b_r[k] * velocity[1];
                        grad[1][1] += mid.b_z[k] * velocity[1];
                    }
                    let hoop =
                        0.25 * (vel[0][0] + vel[1][0] + vel[2][0] + vel[3][0]) / mid.mean_radius;
                    let d_rz = 0.5 * (grad[0][1] + grad[1][0]);
                    let spin = 0.5 * (grad[0][1] - grad[1][0]);
                    let volumetric_rate = grad[0][0] + grad[1][1] + hoop;
                    let mut state = states[e];
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
                        relative_volume: new.area * new.mean_radius / pre.reference_volume[e],
                    };
                    let output = update(material, &mut state, &input).map_err(|error| {
                        SolverError::Update {
                            element: e,
                            time,
                            error,
                        }
                    })?;
                    // Bulk viscosity (compression only), as a pressure added to the forces.
                    let density = material.density / input.relative_volume;
                    let length = new.area.sqrt();
                    let viscous_pressure = if volumetric_rate < 0.0 {
                        density
                            * length
                            * (settings.quadratic_viscosity
                                * length
                                * volumetric_rate
                                * volumetric_rate
                                - settings.linear_viscosity * output.wave_speed * volumetric_rate)
                    } else {
                        0.0
                    };
                    let mid_volume = 0.5
                        * (states[e].relative_volume + input.relative_volume)
                        * pre.reference_volume[e];
                    let viscous_work = -viscous_pressure * volumetric_rate * dt * mid_volume;
                    let s = state.stress;
                    let (s_rr, s_zz, s_tt, s_rz) = (
                        s[0] - viscous_pressure,
                        s[1] - viscous_pressure,
                        s[2] - viscous_pressure,
                        s[3],
                    );
                    let volume = new.area * new.mean_radius;
                    let mut forces = [[0.0; 2]; 4];
                    for (k, force) in forces.iter_mut().enumerate() {
                        force[0] = -(s_rr * new.b_r[k] + s_rz * new.b_z[k]) * volume
                            - s_tt * new.area * 0.25;
                        force[1] = -(s_rz * new.b_r[k] + s_zz * new.b_z[k]) * volume;
                    }
                    // Flanagan-Belytschko viscous hourglass control.
                    let h = [1.0, -1.0, 1.0, -1.0];
                    let hr: f64 = (0..4).map(|k| h[k] * nodes_new[k][0]).sum();
                    let hz: f64 = (0..4).map(|k| h[k] * nodes_new[k][1]).sum();
                    let gamma: [f64; 4] =
                        core::array::from_fn(|k| h[k] - hr * new.b_r[k] - hz * new.b_z[k]);
                    let q_r: f64 = (0..4).map(|k| gamma[k] * vel[k][0]).sum();
                    let q_z: f64 = (0..4).map(|k| gamma[k] * vel[k][1]).sum();
                    let kappa = 0.25
                        * settings.hourglass_coefficient
                        * density
                        * output.wave_speed
                        * new.area.sqrt()
                        * new.mean_radius;
                    for k in 0..4 {
                        forces[k][0] -= kappa * q_r * gamma[k];
                        forces[k][1] -= kappa * q_z * gamma[k];
                    }
                    let hourglass_power = kappa * (q_r * q_r + q_z * q_z);
                    let stable_dt =
                        stable_time_step(&new, output.wave_speed, volumetric_rate, settings);
                    Ok(Some(ElementStep {
                        state,
                        forces,
                        hourglass_power,
                        viscous_work,
                        stable_dt,
                        erode: state.flags.contains(StateFlags::ERODE),
                    }))
                })
                .collect();

            // Serial assembly in element order: bit-identical for any thread count.
            for f in force.iter_mut() {
                *f = [0.0; 2];
            }
            let mut dt_next = f64::INFINITY;
            for (e, result) in results.into_iter().enumerate() {
                let Some(step) = result? else { continue };
                element_cycles += 1;
                energy.hourglass += 2.0 * PI * step.hourglass_power * dt;
                energy.viscous += 2.0 * PI * step.viscous_work;
                states[e] = step.state;
                if step.erode {
                    eroded[e] = true;
                    energy.eroded +=
                        2.0 * PI * step.state.internal_energy * pre.reference_volume[e];
                    continue;
                }
                for (k, &n) in mesh.elements[e].iter().enumerate() {
                    force[n][0] += step.forces[k][0];
                    force[n][1] += step.forces[k][1];
                }
                dt_next = dt_next.min(step.stable_dt);
            }
            x = x_new;
            time += dt;
            steps += 1;
            energy.time = time;
            energy.kinetic = kinetic(&v);
            energy.internal = 2.0
                * PI
                * states
                    .iter()
                    .zip(&pre.reference_volume)
                    .zip(&eroded)
                    .filter(|(_, gone)| !**gone)
                    .map(|((s, v0), _)| s.internal_energy * v0)
                    .sum::<f64>();
            dt_previous = dt;
            if dt_next.is_finite() {
                dt = settings.time_step_safety * dt_next;
            }
            if dt < minimum_dt {
                return Err(SolverError::TimeStepCollapse {
                    time,
                    time_step: dt,
                });
            }
            if time >= next_output || time >= settings.end_time {
                next_output += settings.output_interval;
                energy_history.push(energy);
                for (slot, &e) in self.tracked_elements.iter().enumerate() {
                    tracked[slot]
                        .samples
                        .push(StateSample::from_state(time, &states[e], 1));
                }
                progress(time, &energy);
                if settings.rest_fraction > 0.0 {
                    if let Some(damping) = settings.damping {
                        if time > damping.start_time
                            && energy.kinetic < settings.rest_fraction * energy.initial
                        {
                            break;
                        }
                    }
                }
            }
        }
        if energy_history.last().map(|e| e.time) != Some(energy.time) {
            energy_history.push(energy);
        }
        Ok(AxisymmetricRun {
            positions: x,
            velocities: v,
            states,
            eroded,
            energy_history,
            tracked,
            constraint_forces,
            steps,
            element_cycles,
        })
    }
}
