//! One explicit run as an object: the state and the work arrays as fields, one method per
//! stage of the step, and a short driver ([`Run::step`]). The stages run in the order the
//! central-difference step needs, and each keeps the order of its floating-point operations,
//! so a run is bit-identical for any thread count.

use super::{
    add_pressure_forces, dot, gathered_force, kinetic, move_rigidly, ChunkSummary, Discretisation,
    ElementSlot, ElementTask, ExplicitModel, ExplicitRun, NodeStep, NodeTask, NodeWork, Snapshot,
    StretchWindow, Vector, ELEMENT_CHUNK, NODE_CHUNK,
};
use crate::measure::{StateHistory, StateSample};
use crate::solver::contact::{absorbed_work, ErodingSurfaces, PenaltyContact};
use crate::solver::energy::EnergyBalance;
use crate::solver::moving_wall::{self, WallState};
use crate::solver::nonlocal::NonlocalField;
use crate::solver::truss::Trusses;
use crate::solver::{DampingStart, HourglassControl, SolverError};
use rayon::prelude::*;
use std::ops::ControlFlow;
use stoss_kernel::{MaterialState, PointModel, StateFlags, StepInput};

/// The observer of a run's output times.
pub(super) type Observer<'o> = dyn FnMut(&Snapshot) -> ControlFlow<()> + Send + 'o;

/// Each element's material index and reference volume, and the lumped nodal masses.
struct ElementTables {
    material_of: Vec<usize>,
    reference_volume: Vec<f64>,
    mass: Vec<f64>,
}

/// The rigid parts: which elements belong to one, and each body's nodes.
struct RigidBodies {
    element: Vec<bool>,
    bodies: Vec<Vec<usize>>,
}

/// The pressure loads' nodes (ascending, once each) and each segment's radial interpolation
/// weights in its history, from its initial mid-radius.
struct LoadTables {
    nodes: Vec<usize>,
    weights: Vec<Vec<(usize, usize, f64)>>,
}

/// The nodes a constraint, a wall or a node contact may change (`kinematic`), and those
/// finished after the kinematic changes (`deferred`: those and the rigid bodies' nodes),
/// ascending, once each, with the flag per node.
struct NodeOrder {
    kinematic: Vec<usize>,
    deferred: Vec<usize>,
    is_deferred: Vec<bool>,
}

/// Each node's (element, corner) pairs in ascending element order: node `n`'s are
/// `pairs[start[n]..start[n + 1]]`.
struct NodeElements {
    start: Vec<usize>,
    pairs: Vec<(usize, usize)>,
}

/// A run of an [`ExplicitModel`]: its tables, state, work arrays and balances.
pub(super) struct Run<'m, M, P> {
    model: &'m ExplicitModel<M, P>,
    /// The loops run on the calling thread (no pool).
    serial: bool,
    dimension: usize,
    measure: f64,
    element_count: usize,
    node_count: usize,
    material_of: Vec<usize>,
    reference_volume: Vec<f64>,
    mass: Vec<f64>,
    rigid: RigidBodies,
    trusses: Trusses<'m>,
    /// Reference positions (for the kinematic criteria).
    reference: Vec<Vector>,
    stretch_windows: Vec<Option<StretchWindow>>,
    loads: LoadTables,
    /// Each wall's slave nodes (all nodes when it names none).
    wall_slaves: Vec<Vec<usize>>,
    /// Each wall's point and normal in the model's dimension.
    wall_planes: Vec<(Vector, Vector)>,
    nodes: NodeOrder,
    node_elements: NodeElements,
    /// Without contact or loads, the force gather joins the nodal update.
    gather_with_nodes: bool,
    safety: f64,
    minimum_dt: f64,
    contact: PenaltyContact<'m>,
    eroding: Option<ErodingSurfaces>,
    nonlocal: Option<NonlocalField>,
    /// `x_n`, and `x_{n+1}` while the step runs.
    x: Vec<Vector>,
    x_new: Vec<Vector>,
    /// `v_{n+1/2}` (after the nodal update), and `v_{n-1/2}`.
    v: Vec<Vector>,
    v_old: Vec<Vector>,
    force: Vec<Vector>,
    pressure_force: Vec<Vector>,
    shares: Vec<(usize, f64)>,
    dv_constraint: Vec<Vector>,
    dv_wall: Vec<Vector>,
    node_work: Vec<NodeWork>,
    states: Vec<MaterialState>,
    eroded: Vec<bool>,
    newly_eroded: Vec<usize>,
    slots: Vec<ElementSlot>,
    summaries: Vec<ChunkSummary>,
    wall_states: Vec<WallState>,
    wall_order: Vec<(f64, usize)>,
    energy: EnergyBalance,
    energy_history: Vec<EnergyBalance>,
    tracked: Vec<StateHistory>,
    constraint_forces: Vec<Vec<(f64, f64)>>,
    time: f64,
    dt: f64,
    dt_previous: f64,
    next_output: f64,
    steps: usize,
    element_cycles: u64,
    /// Time from which nodal damping applies ([`super::super::DampingStart`]): its
    /// `start_time`, or the end of the plastic event; infinite without damping or until then.
    damping_from: f64,
    /// `(time, summed plastic strain)` at each output while an early damping start is watched.
    plastic_history: Vec<(f64, f64)>,
}

impl<'m, M: Discretisation, P: PointModel + Sync> Run<'m, M, P> {
    /// Check the model and set up its tables, its initial state and its first time step.
    pub(super) fn new(model: &'m ExplicitModel<M, P>, serial: bool) -> Result<Self, SolverError> {
        let dimension = M::DIMENSION;
        let measure = M::MEASURE;
        let settings = &model.settings;
        let mesh = &model.mesh;
        let element_count = mesh.element_count();
        let x = mesh.reference_positions();
        let node_count = x.len();
        model.validate_materials()?;
        let ElementTables {
            material_of,
            reference_volume,
            mut mass,
        } = model.element_tables(&x)?;
        let rigid = model.rigid_bodies()?;
        if M::DIMENSION == 3 && settings.hourglass == HourglassControl::Stiffness {
            // Tried on hexahedra with the quads' scaling: an element of the 343 m/s Taylor
            // rod inverted at 15 us with QH 0.1 (docs/solver.md).
            return Err(SolverError::Model(
                "the stiffness hourglass form is built for the 2D quads only; hexahedral models \
                 use the viscous form"
                    .into(),
            ));
        }
        let trusses = Trusses::new(&model.trusses, &x, dimension)?;
        trusses.add_masses(&mut mass);
        let mut v = model.initial_velocities(node_count)?;
        let states: Vec<MaterialState> = material_of
            .iter()
            .map(|&m| model.materials[m].initial_state(model.initial_temperature))
            .collect();
        move_rigidly(&rigid.bodies, &mass, &mut v, dimension, measure);
        let mut dt = model.first_time_step(&states, &material_of, &rigid.element, &x)?;
        dt = dt.min(trusses.stable_time_step());
        let safety = settings.effective_time_step_safety(model.eroding_contact.is_some());
        dt *= safety;
        let contact = PenaltyContact::new(&model.contacts, &mass, dt, dimension)?;
        let eroding = model.eroding_surfaces(&x, dt)?;
        let stretch_windows: Vec<Option<StretchWindow>> = model
            .materials
            .iter()
            .map(|m| m.kinematic_strain_bound().map(StretchWindow::new))
            .collect();
        let kinematic_criteria = stretch_windows.iter().any(Option::is_some);
        if kinematic_criteria
            && (element_count > 0 && mesh.element_principal_strains(0, &x, &x).is_none())
        {
            return Err(SolverError::Model(
                "geometric-strain erosion and principal-strain failure are implemented for 2D \
                 (axisymmetric) models only"
                    .into(),
            ));
        }
        let loads = model.load_tables(&x)?;
        model.check_moving_walls(node_count)?;
        let wall_states: Vec<WallState> = model
            .walls
            .iter()
            .map(|wall| WallState {
                velocity: wall.motion.map_or(0.0, |m| m.velocity),
                ..WallState::default()
            })
            .collect();
        let nonlocal = model.nonlocal_field(&x, &reference_volume)?;
        let mut energy = EnergyBalance {
            kinetic: kinetic(&v, &mass, measure, dimension) + model.walls_kinetic(&wall_states),
            ..EnergyBalance::default()
        };
        energy.initial = energy.total();
        let wall_slaves = model.wall_slaves(node_count);
        let nodes = model.node_order(&wall_slaves, &rigid.bodies, node_count)?;
        Ok(Self {
            serial,
            dimension,
            measure,
            element_count,
            node_count,
            material_of,
            reference_volume,
            rigid,
            trusses,
            reference: x.clone(),
            stretch_windows,
            loads,
            wall_planes: model.wall_planes(),
            wall_slaves,
            nodes,
            node_elements: model.node_elements(node_count),
            gather_with_nodes: model.contacts.is_empty()
                && model.eroding_contact.is_none()
                && model.pressure_loads.is_empty(),
            safety,
            minimum_dt: dt * 1e-4,
            contact,
            eroding,
            nonlocal,
            x_new: x.clone(),
            v_old: v.clone(),
            force: vec![[0.0; 3]; node_count],
            pressure_force: vec![[0.0; 3]; node_count],
            shares: Vec::new(),
            dv_constraint: vec![[0.0; 3]; node_count],
            dv_wall: vec![[0.0; 3]; node_count],
            node_work: vec![NodeWork::default(); node_count.div_ceil(NODE_CHUNK)],
            x,
            v,
            mass,
            states,
            eroded: vec![false; element_count],
            newly_eroded: Vec::new(),
            slots: vec![ElementSlot::default(); element_count],
            summaries: (0..element_count.div_ceil(ELEMENT_CHUNK))
                .map(|_| ChunkSummary::default())
                .collect(),
            wall_states,
            wall_order: Vec::new(),
            energy,
            energy_history: vec![energy],
            tracked: model.tracked_histories(),
            constraint_forces: vec![Vec::new(); model.constraints.len()],
            time: 0.0,
            dt,
            dt_previous: 0.0,
            next_output: settings.output_interval,
            steps: 0,
            element_cycles: 0,
            damping_from: settings.damping.map_or(f64::INFINITY, |d| match d.start {
                DampingStart::Fixed | DampingStart::SettledOrAt(_) => d.start_time,
                DampingStart::SettledAfter { latest, .. } => latest,
            }),
            plastic_history: Vec::new(),
            model,
        })
    }

    /// Whether the run has reached its end time.
    pub(super) fn is_done(&self) -> bool {
        self.time >= self.model.settings.end_time
    }

    /// One central-difference step from `t_n` to `t_{n+1}`, then the output if one is due;
    /// `Break` when the observer or the rest criterion ends the run.
    pub(super) fn step(
        &mut self,
        observer: &mut Observer<'_>,
    ) -> Result<ControlFlow<()>, SolverError> {
        let settings = &self.model.settings;
        let dt_average = 0.5 * (self.dt_previous + self.dt);
        self.add_contact_forces(dt_average);
        self.add_pressure_forces()?;
        let damping_factor = match settings.damping {
            Some(damping) if self.time >= self.damping_from => {
                Some(1.0 - damping.coefficient * self.dt)
            }
            _ => None,
        };
        self.update_nodes(dt_average, damping_factor);
        for &n in &self.nodes.kinematic {
            self.dv_constraint[n] = [0.0; 3];
            self.dv_wall[n] = [0.0; 3];
        }
        move_rigidly(
            &self.rigid.bodies,
            &self.mass,
            &mut self.v,
            self.dimension,
            self.measure,
        );
        self.apply_constraints(dt_average);
        self.apply_fixed_walls();
        self.move_walls(dt_average);
        for contact in &self.model.node_contacts {
            contact.resolve(
                &self.mass,
                &self.x,
                &mut self.v,
                &mut self.dv_wall,
                self.dt,
                self.dimension,
            );
        }
        self.finish_deferred_nodes(damping_factor);
        self.book_load_and_contact_work(dt_average);
        if let Some(field) = self.nonlocal.as_mut() {
            field.record(&self.states);
        }
        self.update_elements();
        let mut dt_next = self.collect_element_steps()?;
        if let Some(field) = self.nonlocal.as_mut() {
            field.apply(&mut self.states, &self.eroded);
        }
        dt_next = dt_next.min(self.trusses.step(&self.x_new)?);
        if !self.gather_with_nodes {
            self.gather_forces();
        }
        self.remove_eroded();
        self.advance(dt_next)?;
        if self.time >= self.next_output || self.time >= settings.end_time {
            return Ok(self.output(observer));
        }
        Ok(ControlFlow::Continue(()))
    }

    /// Contact: the penalty pairs' and the eroding contact's forces at `x_n`, added to the
    /// assembled internal forces.
    fn add_contact_forces(&mut self, dt_average: f64) {
        self.contact
            .add_forces(&self.x, &self.v, dt_average, &mut self.force);
        if let Some(surfaces) = self.eroding.as_mut() {
            surfaces.add_forces(&self.x, &self.v, &self.mass, dt_average, &mut self.force);
        }
    }

    /// Pressure loads: their consistent nodal forces at `t_n`, standing for the window
    /// `[t_n - dt_previous/2, t_n + dt/2)`, added to the assembled forces.
    fn add_pressure_forces(&mut self) -> Result<(), SolverError> {
        if self.loads.nodes.is_empty() {
            return Ok(());
        }
        for &n in &self.loads.nodes {
            self.pressure_force[n] = [0.0; 3];
        }
        let window = (
            self.time - 0.5 * self.dt_previous,
            self.time + 0.5 * self.dt,
        );
        for (load, weights) in self.model.pressure_loads.iter().zip(&self.loads.weights) {
            let history = load
                .history
                .read()
                .map_err(|_| SolverError::Model("a pressure history's lock is poisoned".into()))?;
            history.overlaps(window.0, window.1, &mut self.shares);
            add_pressure_forces(
                load,
                &history,
                weights,
                &self.shares,
                &self.x,
                &mut self.pressure_force,
            );
        }
        for &n in &self.loads.nodes {
            for d in 0..self.dimension {
                self.force[n][d] += self.pressure_force[n][d];
            }
        }
        Ok(())
    }

    /// The nodal update, in parallel over fixed node chunks: the force gathered from the
    /// elements (here when no contact or load adds to it first, else after the element loop),
    /// the velocity update `v_{n+1/2}` and, for every node that is not deferred, damping, the
    /// work sums and the new position. Each chunk's work sums are added in chunk order.
    fn update_nodes(&mut self, dt_average: f64, damping_factor: Option<f64>) {
        let (model, dimension, gather_with_nodes, dt) =
            (self.model, self.dimension, self.gather_with_nodes, self.dt);
        let (mass, nodes, node_elements, slots) =
            (&self.mass, &self.nodes, &self.node_elements, &self.slots);
        let (x, dv_constraint, dv_wall) = (&self.x, &self.dv_constraint, &self.dv_wall);
        let trusses = &self.trusses;
        // Without bars nothing is added (not even zeros, which would turn a -0.0 into +0.0).
        let truss_force = (!model.trusses.is_empty()).then_some(&trusses.node_force);
        let update_nodes =
            |((c, (((chunk_f, chunk_v), chunk_old), chunk_x)), sums): NodeTask<'_>| {
                *sums = NodeWork::default();
                for (i, (((total, vel), old), position)) in chunk_f
                    .iter_mut()
                    .zip(chunk_v)
                    .zip(chunk_old)
                    .zip(chunk_x)
                    .enumerate()
                {
                    let n = c * NODE_CHUNK + i;
                    if gather_with_nodes {
                        *total = gathered_force(
                            n,
                            slots,
                            &node_elements.pairs,
                            &node_elements.start,
                            dimension,
                        );
                    }
                    *old = *vel;
                    if mass[n] > 0.0 {
                        match truss_force {
                            Some(bars) => {
                                for d in 0..dimension {
                                    vel[d] += (total[d] + bars[n][d]) / mass[n] * dt_average;
                                }
                            }
                            None => {
                                for d in 0..dimension {
                                    vel[d] += total[d] / mass[n] * dt_average;
                                }
                            }
                        }
                        if let Some(g) = &model.body_acceleration {
                            for d in 0..dimension {
                                vel[d] += g[d] * dt_average;
                            }
                        }
                    }
                    if nodes.is_deferred[n] {
                        continue;
                    }
                    NodeStep::at(n, mass, x, dv_constraint, dv_wall, damping_factor, dt)
                        .finish(vel, old, position, dimension, sums);
                }
            };
        if self.serial {
            self.force
                .chunks_mut(NODE_CHUNK)
                .zip(self.v.chunks_mut(NODE_CHUNK))
                .zip(self.v_old.chunks_mut(NODE_CHUNK))
                .zip(self.x_new.chunks_mut(NODE_CHUNK))
                .enumerate()
                .zip(self.node_work.iter_mut())
                .for_each(update_nodes);
        } else {
            self.force
                .par_chunks_mut(NODE_CHUNK)
                .zip(self.v.par_chunks_mut(NODE_CHUNK))
                .zip(self.v_old.par_chunks_mut(NODE_CHUNK))
                .zip(self.x_new.par_chunks_mut(NODE_CHUNK))
                .enumerate()
                .zip(self.node_work.par_iter_mut())
                .for_each(update_nodes);
        }
    }

    /// Prescribed velocities at `t_{n+1/2}`: each records its velocity change (its work is the
    /// central-difference-consistent `m dv . (v_old + v_new)/2`) and its reaction force.
    fn apply_constraints(&mut self, dt_average: f64) {
        let half_time = self.time + 0.5 * self.dt;
        for (c, constraint) in self.model.constraints.iter().enumerate() {
            let target = constraint.velocity.at(half_time);
            let mut reaction = 0.0;
            for &n in &constraint.nodes {
                let change = target - self.v[n][constraint.dof];
                self.dv_constraint[n][constraint.dof] += change;
                if dt_average > 0.0 {
                    reaction += self.mass[n] * change / dt_average;
                }
                self.v[n][constraint.dof] = target;
            }
            self.constraint_forces[c].push((self.time, self.measure * reaction));
        }
    }

    /// Fixed rigid walls: stop the normal approach; Coulomb friction on the tangential part.
    fn apply_fixed_walls(&mut self) {
        let (dimension, dt) = (self.dimension, self.dt);
        let v = &mut self.v;
        for ((wall, (point, normal)), slaves) in self
            .model
            .walls
            .iter()
            .zip(&self.wall_planes)
            .zip(&self.wall_slaves)
        {
            if wall.motion.is_some() {
                continue;
            }
            for &n in slaves {
                let offset: Vector = core::array::from_fn(|d| self.x[n][d] - point[d]);
                let gap = dot(&offset, normal, dimension);
                let vn = dot(&v[n], normal, dimension);
                if gap + vn * dt >= 0.0 {
                    continue;
                }
                let before = v[n];
                let vn_new = -gap / dt;
                let dvn = vn_new - vn;
                let mut vt: Vector = core::array::from_fn(|d| v[n][d] - vn * normal[d]);
                let speed_t = dot(&vt, &vt, dimension).sqrt();
                if speed_t > 0.0 {
                    let keep = (speed_t - (wall.friction * dvn).min(speed_t)) / speed_t;
                    vt = vt.map(|c| c * keep);
                }
                for d in 0..dimension {
                    v[n][d] = vt[d] + vn_new * normal[d];
                    self.dv_wall[n][d] += v[n][d] - before[d];
                }
            }
        }
    }

    /// Moving walls: gravity on the wall, then the momentum-conserving contact with its slave
    /// nodes; the work of both is booked.
    fn move_walls(&mut self, dt_average: f64) {
        let (dimension, measure, dt) = (self.dimension, self.measure, self.dt);
        let model = self.model;
        for (((wall, (point, normal)), slaves), state) in model
            .walls
            .iter()
            .zip(&self.wall_planes)
            .zip(&self.wall_slaves)
            .zip(self.wall_states.iter_mut())
        {
            let Some(motion) = &wall.motion else {
                continue;
            };
            let gravity = model
                .body_acceleration
                .as_ref()
                .map_or(0.0, |g| dot(g, normal, dimension));
            let before = state.velocity;
            let step = moving_wall::resolve(
                point,
                normal,
                state.displacement,
                motion.mass / measure,
                before + gravity * dt_average,
                wall.friction,
                slaves,
                &self.mass,
                &self.x,
                &mut self.v,
                &mut self.dv_wall,
                dt,
                dimension,
                &mut self.wall_order,
            );
            let mean = 0.5 * (before + step.velocity);
            self.energy.external_work += motion.mass * gravity * dt_average * mean;
            self.energy.contact -= motion.mass * (step.velocity - step.free_velocity) * mean;
            state.contact_force = if dt_average > 0.0 {
                motion.mass * (step.velocity - step.free_velocity) / dt_average
            } else {
                0.0
            };
            state.velocity = step.velocity;
            state.displacement += step.velocity * dt;
        }
    }

    /// The deferred nodes, in ascending order, after the kinematic changes; then every node
    /// chunk's work sums (the deferred nodes' last) booked.
    fn finish_deferred_nodes(&mut self, damping_factor: Option<f64>) {
        let mut deferred_work = NodeWork::default();
        for &n in &self.nodes.deferred {
            NodeStep::at(
                n,
                &self.mass,
                &self.x,
                &self.dv_constraint,
                &self.dv_wall,
                damping_factor,
                self.dt,
            )
            .finish(
                &mut self.v[n],
                &self.v_old[n],
                &mut self.x_new[n],
                self.dimension,
                &mut deferred_work,
            );
        }
        let measure = self.measure;
        for sums in self.node_work.iter().chain([&deferred_work]) {
            self.energy.external_work += measure * sums.external;
            self.energy.contact += measure * sums.wall;
            self.energy.damping += measure * sums.damping;
        }
    }

    /// The step's work of the penalty contact, the pressure loads, the eroding contact and
    /// the body load, with the mid-step velocities.
    fn book_load_and_contact_work(&mut self, dt_average: f64) {
        let (measure, dimension) = (self.measure, self.dimension);
        let energy = &mut self.energy;
        if self.contact.is_active() {
            energy.contact += measure * self.contact.absorbed(&self.v_old, &self.v, dt_average);
        }
        if !self.loads.nodes.is_empty() {
            energy.external_work -= measure
                * absorbed_work(
                    &self.pressure_force,
                    &self.loads.nodes,
                    &self.v_old,
                    &self.v,
                    dt_average,
                );
        }
        if let Some(surfaces) = &self.eroding {
            energy.contact += measure * surfaces.absorbed(&self.v_old, &self.v, dt_average);
        }
        if let Some(g) = &self.model.body_acceleration {
            // In node order, so the sum does not depend on the thread count.
            let mut work = 0.0;
            for n in 0..self.node_count {
                if self.mass[n] > 0.0 {
                    let mean: Vector =
                        core::array::from_fn(|d| 0.5 * (self.v_old[n][d] + self.v[n][d]));
                    work += self.mass[n] * dot(g, &mean, dimension) * dt_average;
                }
            }
            energy.external_work += measure * work;
        }
    }

    /// Elements and materials: every element's kinematics, material update, kinematic
    /// criteria and nodal forces, in parallel (or serially on one thread) over chunks of a
    /// fixed size. Each element writes its own state and slot, each chunk its summary.
    fn update_elements(&mut self) {
        let (model, time, dt) = (self.model, self.time, self.dt);
        let (mesh, settings) = (&model.mesh, &model.settings);
        let (material_of, reference_volume, rigid) =
            (&self.material_of, &self.reference_volume, &self.rigid);
        let (reference, stretch_windows, eroded) =
            (&self.reference, &self.stretch_windows, &self.eroded);
        let (x, x_new, v) = (&self.x, &self.x_new, &self.v);
        let step_chunk = |((c, (chunk_states, chunk_slots)), summary): ElementTask<'_>| {
            *summary = ChunkSummary::default();
            for (i, (state, slot)) in chunk_states.iter_mut().zip(chunk_slots).enumerate() {
                let e = c * ELEMENT_CHUNK + i;
                slot.assembles = false;
                if eroded[e] || rigid.element[e] {
                    continue;
                }
                let material = &model.materials[material_of[e]];
                let step = match mesh.element_step(
                    e,
                    x,
                    x_new,
                    v,
                    state,
                    &mut slot.hourglass,
                    material,
                    reference_volume[e],
                    dt,
                    settings,
                    time,
                    &mut slot.forces,
                ) {
                    Ok(step) => step,
                    Err(error) => {
                        summary.error = Some(error);
                        return;
                    }
                };
                if let Some(window) = &stretch_windows[material_of[e]] {
                    if !mesh.element_stretches_within(e, reference, x_new, window) {
                        if let Some(strains) = mesh.element_principal_strains(e, reference, x_new) {
                            state.flags.insert(material.kinematic_flags(strains).0);
                        }
                    }
                }
                summary.cycles += 1;
                slot.hourglass_energy += step.hourglass_power * dt;
                slot.viscous_energy += step.viscous_work;
                if state.flags.contains(StateFlags::ERODE) {
                    summary.eroding = true;
                    continue;
                }
                slot.assembles = true;
                summary.stable_dt = summary.stable_dt.min(step.stable_dt);
            }
        };
        if self.serial {
            self.states
                .chunks_mut(ELEMENT_CHUNK)
                .zip(self.slots.chunks_mut(ELEMENT_CHUNK))
                .enumerate()
                .zip(self.summaries.iter_mut())
                .for_each(step_chunk);
        } else {
            self.states
                .par_chunks_mut(ELEMENT_CHUNK)
                .zip(self.slots.par_chunks_mut(ELEMENT_CHUNK))
                .enumerate()
                .zip(self.summaries.par_iter_mut())
                .with_max_len(1)
                .for_each(step_chunk);
        }
    }

    /// The chunks' summaries in element order: the first error, the element-cycles, the
    /// smallest stable step (returned), and the newly eroded elements with their internal
    /// energy booked as eroded.
    fn collect_element_steps(&mut self) -> Result<f64, SolverError> {
        let mut dt_next = f64::INFINITY;
        for (c, summary) in self.summaries.iter_mut().enumerate() {
            if let Some(error) = summary.error.take() {
                return Err(error);
            }
            self.element_cycles += summary.cycles;
            dt_next = dt_next.min(summary.stable_dt);
            if summary.eroding {
                let first = c * ELEMENT_CHUNK;
                for e in first..(first + ELEMENT_CHUNK).min(self.element_count) {
                    if !self.eroded[e]
                        && !self.rigid.element[e]
                        && self.states[e].flags.contains(StateFlags::ERODE)
                    {
                        self.eroded[e] = true;
                        self.newly_eroded.push(e);
                        self.energy.eroded += self.measure
                            * self.states[e].internal_energy
                            * self.reference_volume[e];
                    }
                }
            }
        }
        Ok(dt_next)
    }

    /// With contact or loads, the nodal forces are gathered after the element loop, before
    /// those add theirs at the next step.
    fn gather_forces(&mut self) {
        let (slots, node_elements, dimension) = (&self.slots, &self.node_elements, self.dimension);
        let gather = |(c, chunk): (usize, &mut [Vector])| {
            for (i, total) in chunk.iter_mut().enumerate() {
                *total = gathered_force(
                    c * NODE_CHUNK + i,
                    slots,
                    &node_elements.pairs,
                    &node_elements.start,
                    dimension,
                );
            }
        };
        if self.serial {
            self.force
                .chunks_mut(NODE_CHUNK)
                .enumerate()
                .for_each(gather);
        } else {
            self.force
                .par_chunks_mut(NODE_CHUNK)
                .enumerate()
                .for_each(gather);
        }
    }

    /// Erosion: the eroding contact follows the newly eroded elements (their nodes' mass
    /// removed when they are left free, its kinetic energy booked as eroded).
    fn remove_eroded(&mut self) {
        if self.newly_eroded.is_empty() {
            return;
        }
        if let Some(surfaces) = self.eroding.as_mut() {
            let mesh = &self.model.mesh;
            let removed = surfaces.on_erosion(
                &self.newly_eroded,
                |e| mesh.element_nodes(e),
                &self.eroded,
                &mut self.mass,
                &mut self.v,
            );
            self.energy.eroded += self.measure * removed;
        }
        self.newly_eroded.clear();
    }

    /// Time-step control: `x_{n+1}` becomes `x_n`, the time advances, and the next step is the
    /// safety factor times the smallest stable step (kept when none is finite); an error when
    /// it has collapsed.
    fn advance(&mut self, dt_next: f64) -> Result<(), SolverError> {
        std::mem::swap(&mut self.x, &mut self.x_new);
        self.time += self.dt;
        self.steps += 1;
        self.energy.time = self.time;
        self.dt_previous = self.dt;
        if dt_next.is_finite() {
            self.dt = self.safety * dt_next;
        }
        if self.dt < self.minimum_dt {
            return Err(SolverError::TimeStepCollapse {
                time: self.time,
                time_step: self.dt,
            });
        }
        Ok(())
    }

    /// Output: the energy balance's kinetic, internal, hourglass and viscous terms, the
    /// tracked elements' samples, progress, and the observer; `Break` when the observer ends
    /// the run or the damped model has come to rest.
    fn output(&mut self, observer: &mut Observer<'_>) -> ControlFlow<()> {
        let (model, measure, time) = (self.model, self.measure, self.time);
        let settings = &model.settings;
        let energy = &mut self.energy;
        energy.kinetic = kinetic(&self.v, &self.mass, measure, self.dimension)
            + model.walls_kinetic(&self.wall_states);
        energy.internal = measure
            * self
                .states
                .iter()
                .zip(&self.reference_volume)
                .zip(&self.eroded)
                .filter(|(_, gone)| !**gone)
                .map(|((s, v0), _)| s.internal_energy * v0)
                .sum::<f64>();
        if !model.trusses.is_empty() {
            energy.internal += measure * self.trusses.internal_energy();
        }
        energy.hourglass = measure * self.slots.iter().map(|s| s.hourglass_energy).sum::<f64>();
        energy.viscous = measure * self.slots.iter().map(|s| s.viscous_energy).sum::<f64>();
        self.next_output += settings.output_interval;
        self.energy_history.push(*energy);
        for (slot, &e) in model.tracked_elements.iter().enumerate() {
            self.tracked[slot].samples.push(StateSample::from_state(
                time,
                &self.states[e],
                M::AXIAL_COMPONENT,
            ));
        }
        settings.progress.report(time, settings.end_time);
        self.watch_plastic_event(time);
        let decision = observer(&Snapshot {
            time,
            time_step: self.dt,
            positions: &self.x,
            velocities: &self.v,
            states: &self.states,
            eroded: &self.eroded,
            energy: &self.energy,
            walls: &self.wall_states,
            damping_from: self.damping_from,
        });
        if decision.is_break() {
            return ControlFlow::Break(());
        }
        if settings.rest_fraction > 0.0 {
            if let Some(damping) = settings.damping {
                if time > damping.start_time
                    && self.energy.kinetic < settings.rest_fraction * self.energy.initial
                {
                    return ControlFlow::Break(());
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// A damping start set by the plastic event ([`super::super::DampingStart`]): once it is
    /// over (summed plastic strain positive and grown by at most the settle fraction over its
    /// window), damping applies from `time`, if the rule allows a start then.
    fn watch_plastic_event(&mut self, time: f64) {
        let Some(damping) = self.model.settings.damping else {
            return;
        };
        let Some(settle) = damping.start.settle() else {
            return;
        };
        if time >= self.damping_from {
            return;
        }
        let plastic: f64 = self
            .states
            .iter()
            .zip(&self.eroded)
            .filter(|(_, gone)| !**gone)
            .map(|(s, _)| s.plastic_strain)
            .sum();
        self.plastic_history.push((time, plastic));
        let start = time - settle.window;
        if start <= 0.0 || plastic <= 0.0 {
            return;
        }
        if matches!(damping.start, DampingStart::SettledAfter { .. }) && time < damping.start_time {
            return;
        }
        let earlier = self
            .plastic_history
            .iter()
            .rev()
            .find(|(t, _)| *t <= start)
            .map_or(0.0, |p| p.1);
        if plastic - earlier <= settle.fraction * plastic {
            self.damping_from = time;
        }
    }

    /// The result: the final state, the balances and histories (the final energy balance
    /// appended unless the last output was at the final time).
    pub(super) fn finish(mut self) -> ExplicitRun {
        if self.energy_history.last().map(|e| e.time) != Some(self.energy.time) {
            self.energy_history.push(self.energy);
        }
        ExplicitRun {
            positions: self.x,
            velocities: self.v,
            states: self.states,
            eroded: self.eroded,
            energy_history: self.energy_history,
            tracked: self.tracked,
            constraint_forces: self.constraint_forces,
            steps: self.steps,
            element_cycles: self.element_cycles,
            contact: self
                .eroding
                .as_ref()
                .map(ErodingSurfaces::statistics)
                .unwrap_or_default(),
            walls: self.wall_states,
        }
    }
}

/// The set-up pieces of a run, each checking its part of the model.
impl<M: Discretisation, P: PointModel + Sync> ExplicitModel<M, P> {
    /// Every material's constants are valid (the error names the first part using it).
    fn validate_materials(&self) -> Result<(), SolverError> {
        let mesh = &self.mesh;
        let element_count = mesh.element_count();
        for (index, material) in self.materials.iter().enumerate() {
            material.validate().map_err(|error| SolverError::Material {
                part: (0..element_count)
                    .map(|e| mesh.element_material(e))
                    .find(|(m, _)| *m == index)
                    .map_or_else(|| format!("material {index}"), |(_, name)| name.to_string()),
                error,
            })?;
        }
        Ok(())
    }

    /// Each element's material and reference volume at `x`, and the lumped nodal masses.
    fn element_tables(&self, x: &[Vector]) -> Result<ElementTables, SolverError> {
        let mesh = &self.mesh;
        let element_count = mesh.element_count();
        let mut material_of = Vec::with_capacity(element_count);
        let mut reference_volume = Vec::with_capacity(element_count);
        let mut mass = vec![0.0; x.len()];
        for e in 0..element_count {
            let (index, name) = mesh.element_material(e);
            let material = self.materials.get(index).ok_or_else(|| {
                SolverError::Model(format!(
                    "part {name} names material {index}, which does not exist"
                ))
            })?;
            let volume = mesh.element_volume(e, x);
            if volume <= 0.0 || !volume.is_finite() {
                return Err(SolverError::InvertedElement {
                    element: e,
                    part: name.to_string(),
                    time: 0.0,
                });
            }
            let nodes = mesh.element_nodes(e);
            for &n in nodes {
                mass[n] += material.density() * volume / nodes.len() as f64;
            }
            material_of.push(index);
            reference_volume.push(volume);
        }
        Ok(ElementTables {
            material_of,
            reference_volume,
            mass,
        })
    }

    /// The rigid parts' elements and each body's nodes (ascending, once each).
    fn rigid_bodies(&self) -> Result<RigidBodies, SolverError> {
        let mesh = &self.mesh;
        let element_count = mesh.element_count();
        let mut element = vec![false; element_count];
        let mut bodies: Vec<Vec<usize>> = Vec::with_capacity(self.rigid_parts.len());
        for &part in &self.rigid_parts {
            if part >= mesh.part_count() {
                return Err(SolverError::Model(format!(
                    "rigid part {part} does not exist (the mesh has {} parts)",
                    mesh.part_count()
                )));
            }
            let mut nodes = Vec::new();
            for e in (0..element_count).filter(|&e| mesh.element_part(e) == part) {
                element[e] = true;
                nodes.extend_from_slice(mesh.element_nodes(e));
            }
            nodes.sort_unstable();
            nodes.dedup();
            bodies.push(nodes);
        }
        Ok(RigidBodies { element, bodies })
    }

    /// The initial nodal velocities (at rest when none are given).
    fn initial_velocities(&self, node_count: usize) -> Result<Vec<Vector>, SolverError> {
        if self.initial_velocity.is_empty() {
            Ok(vec![[0.0; 3]; node_count])
        } else if self.initial_velocity.len() == node_count {
            Ok(self.initial_velocity.clone())
        } else {
            Err(SolverError::Model(
                "initial velocity must give one vector per node".into(),
            ))
        }
    }

    /// The smallest stable step of the deformable elements at `x` from their elastic wave
    /// speeds (a zero-strain kernel update), before the safety factor.
    fn first_time_step(
        &self,
        states: &[MaterialState],
        material_of: &[usize],
        rigid_element: &[bool],
        x: &[Vector],
    ) -> Result<f64, SolverError> {
        let mesh = &self.mesh;
        let mut dt = f64::INFINITY;
        for e in (0..mesh.element_count()).filter(|&e| !rigid_element[e]) {
            let mut probe = states[e];
            let output = self.materials[material_of[e]]
                .update(
                    &mut probe,
                    &StepInput {
                        strain_increment: [0.0; 6],
                        dt: 1.0,
                        relative_volume: 1.0,
                    },
                )
                .map_err(|error| SolverError::Update {
                    element: e,
                    part: mesh.element_material(e).1.to_string(),
                    time: 0.0,
                    relative_volume: 1.0,
                    error,
                })?;
            dt = dt.min(mesh.element_time_step(e, x, output.wave_speed));
        }
        Ok(dt)
    }

    /// The eroding contact's surfaces (none without one), the constrained dofs marked.
    fn eroding_surfaces(
        &self,
        x: &[Vector],
        dt: f64,
    ) -> Result<Option<ErodingSurfaces>, SolverError> {
        let Some(settings) = &self.eroding_contact else {
            return Ok(None);
        };
        let mesh = &self.mesh;
        let mut surfaces = ErodingSurfaces::new(
            settings,
            mesh.element_count(),
            |e| (mesh.element_nodes(e), mesh.element_part(e)),
            mesh.part_count(),
            x,
            dt,
            M::DIMENSION,
        )?;
        for constraint in &self.constraints {
            surfaces.prescribe(&constraint.nodes, constraint.dof);
        }
        Ok(Some(surfaces))
    }

    /// The pressure loads' nodes and segment weights (2D only; nodes of the mesh).
    fn load_tables(&self, x: &[Vector]) -> Result<LoadTables, SolverError> {
        let node_count = x.len();
        if !self.pressure_loads.is_empty() && M::DIMENSION != 2 {
            return Err(SolverError::Model(
                "pressure loads are implemented for 2D (axisymmetric) models only".into(),
            ));
        }
        let mut nodes: Vec<usize> = Vec::new();
        for load in &self.pressure_loads {
            for segment in &load.segments {
                for &n in segment {
                    if n >= node_count {
                        return Err(SolverError::Model(format!(
                            "a pressure-load segment names node {n}; the mesh has {node_count}"
                        )));
                    }
                    nodes.push(n);
                }
            }
        }
        nodes.sort_unstable();
        nodes.dedup();
        let weights = self
            .pressure_loads
            .iter()
            .map(|load| {
                let history = load.history.read().map_err(|_| {
                    SolverError::Model("a pressure history's lock is poisoned".into())
                })?;
                Ok(load
                    .segments
                    .iter()
                    .map(|&[a, b]| history.radial_weights(0.5 * (x[a][0] + x[b][0])))
                    .collect())
            })
            .collect::<Result<_, SolverError>>()?;
        Ok(LoadTables { nodes, weights })
    }

    /// Every moving wall has a mass, a finite velocity, a friction >= 0, a unit normal and
    /// slave nodes of the mesh.
    fn check_moving_walls(&self, node_count: usize) -> Result<(), SolverError> {
        for (index, wall) in self.walls.iter().enumerate() {
            if let Some(motion) = &wall.motion {
                let length = wall.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
                let valid = motion.mass > 0.0
                    && motion.mass.is_finite()
                    && motion.velocity.is_finite()
                    && wall.friction >= 0.0
                    && (length - 1.0).abs() < 1e-9
                    && wall.point.iter().all(|c| c.is_finite())
                    && wall.nodes.iter().all(|&n| n < node_count);
                if !valid {
                    return Err(SolverError::Model(format!(
                        "moving wall {index}: needs a mass > 0 (kg), a finite velocity, a \
                         friction >= 0, a unit normal and slave nodes of the mesh ({wall:?})"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The moving walls' kinetic energy.
    fn walls_kinetic(&self, states: &[WallState]) -> f64 {
        self.walls
            .iter()
            .zip(states)
            .filter_map(|(wall, state)| {
                wall.motion
                    .map(|m| 0.5 * m.mass * state.velocity * state.velocity)
            })
            .sum::<f64>()
    }

    /// The nonlocal averaging over the element centroids at `x` (none without one).
    fn nonlocal_field(
        &self,
        x: &[Vector],
        reference_volume: &[f64],
    ) -> Result<Option<NonlocalField>, SolverError> {
        let Some(averaging) = &self.settings.nonlocal else {
            return Ok(None);
        };
        let mesh = &self.mesh;
        let centroids: Vec<Vector> = (0..mesh.element_count())
            .map(|e| {
                let nodes = mesh.element_nodes(e);
                core::array::from_fn(|d| {
                    nodes.iter().map(|&n| x[n][d]).sum::<f64>() / nodes.len() as f64
                })
            })
            .collect();
        Ok(Some(NonlocalField::new(
            averaging,
            &centroids,
            reference_volume,
            |e| mesh.element_part(e),
        )?))
    }

    /// An empty state history per tracked element.
    fn tracked_histories(&self) -> Vec<StateHistory> {
        self.tracked_elements
            .iter()
            .map(|e| StateHistory {
                label: format!("element {e}"),
                samples: Vec::new(),
            })
            .collect()
    }

    /// Each wall's slave nodes: those it names, or every node.
    fn wall_slaves(&self, node_count: usize) -> Vec<Vec<usize>> {
        self.walls
            .iter()
            .map(|w| {
                if w.nodes.is_empty() {
                    (0..node_count).collect()
                } else {
                    w.nodes.clone()
                }
            })
            .collect()
    }

    /// Each wall's point and normal, their components beyond the model's dimension zero.
    fn wall_planes(&self) -> Vec<(Vector, Vector)> {
        self.walls
            .iter()
            .map(|w| {
                let component = |values: &[f64], d: usize| {
                    if d < M::DIMENSION {
                        values.get(d).copied().unwrap_or(0.0)
                    } else {
                        0.0
                    }
                };
                let point: Vector = core::array::from_fn(|d| component(&w.point, d));
                let normal: Vector = core::array::from_fn(|d| component(&w.normal, d));
                (point, normal)
            })
            .collect()
    }

    /// The kinematic and deferred nodes (the node contacts checked first).
    fn node_order(
        &self,
        wall_slaves: &[Vec<usize>],
        rigid_bodies: &[Vec<usize>],
        node_count: usize,
    ) -> Result<NodeOrder, SolverError> {
        for contact in &self.node_contacts {
            contact.check(node_count)?;
        }
        let mut kinematic: Vec<usize> = self
            .constraints
            .iter()
            .flat_map(|c| c.nodes.iter().copied())
            .chain(wall_slaves.iter().flatten().copied())
            .chain(
                self.node_contacts
                    .iter()
                    .flat_map(|c| c.pairs.iter().flatten().copied()),
            )
            .collect();
        kinematic.sort_unstable();
        kinematic.dedup();
        let mut deferred: Vec<usize> = kinematic
            .iter()
            .chain(rigid_bodies.iter().flatten())
            .copied()
            .collect();
        deferred.sort_unstable();
        deferred.dedup();
        let mut is_deferred = vec![false; node_count];
        for &n in &deferred {
            is_deferred[n] = true;
        }
        Ok(NodeOrder {
            kinematic,
            deferred,
            is_deferred,
        })
    }

    /// Each node's (element, corner) pairs in ascending element order.
    fn node_elements(&self, node_count: usize) -> NodeElements {
        let mesh = &self.mesh;
        let element_count = mesh.element_count();
        let mut start = vec![0usize; node_count + 1];
        for e in 0..element_count {
            for &n in mesh.element_nodes(e) {
                start[n + 1] += 1;
            }
        }
        for n in 0..node_count {
            start[n + 1] += start[n];
        }
        let mut pairs = vec![(0usize, 0usize); start[node_count]];
        let mut filled = start.clone();
        for e in 0..element_count {
            for (k, &n) in mesh.element_nodes(e).iter().enumerate() {
                pairs[filled[n]] = (e, k);
                filled[n] += 1;
            }
        }
        NodeElements { start, pairs }
    }
}
