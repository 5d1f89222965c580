//! The explicit time integration shared by every element formulation: central differences,
//! lumped mass, CFL time step, prescribed velocities, rigid walls, penalty contact between
//! parts, nodal damping, erosion, energy balance and the deterministic parallel element loop.
//!
//! Contact ([`super::contact`], 2D only) hooks in at two points of the step: its forces at
//! `x_n` are added to the assembled internal forces before the velocity update (computed
//! serially in a fixed order, so the loop stays bit-identical for any thread count), and their
//! work is booked as `EnergyBalance::contact` with the same mid-step velocities as the walls'.

use super::contact::{
    absorbed_work, ContactPair, ContactStatistics, ErodingContact, ErodingSurfaces,
    NodeToNodeContact, PenaltyContact,
};
use super::energy::EnergyBalance;
use super::loads::{PressureHistory, PressureLoad, RigidWall, VelocityConstraint};
use super::moving_wall::{self, WallState};
use super::nonlocal::NonlocalField;
use super::truss::{Truss, Trusses};
use super::{HourglassControl, SolverError, SolverSettings};
use crate::measure::{StateHistory, StateSample};
use rayon::prelude::*;
use std::ops::ControlFlow;
use stoss_kernel::{Material, MaterialState, PointModel, StateFlags, StepInput};

/// Nodal vectors are stored with three components; 2D formulations use the first two.
pub type Vector = [f64; 3];

/// Largest worker-thread count a run accepts (a guard against a runaway thread pool).
pub const MAXIMUM_THREADS: usize = 256;

/// Largest number of nodes per element.
pub const MAX_NODES: usize = 8;

/// Flanagan-Belytschko generalised hourglass force of a quad's one mode, in `r` and `z`,
/// carried from step to step (2D only): integrated by the stiffness form; for the viscous
/// form the last step's force, whose mean with the new one books the hourglass work.
pub type HourglassStress = [f64; 2];

/// Per-element result of one step.
#[derive(Clone, Copy, Debug)]
pub struct ElementStep {
    /// Updated material state.
    pub state: MaterialState,
    /// Updated generalised hourglass forces (2D; zero in 3D).
    pub hourglass: HourglassStress,
    /// Hourglass dissipation rate.
    pub hourglass_power: f64,
    /// Bulk-viscosity work of the step.
    pub viscous_work: f64,
    /// Stable time step of the element.
    pub stable_dt: f64,
}

/// Elements per task of the element loop, and nodes per task of the force gather: fixed sizes,
/// so that the tasks' partial results combine the same way for any thread count.
const ELEMENT_CHUNK: usize = 64;
const NODE_CHUNK: usize = 512;

/// What an element keeps between the element loop and the force gather.
#[derive(Clone, Copy, Debug, Default)]
struct ElementSlot {
    /// Nodal forces of the last step.
    forces: [Vector; MAX_NODES],
    /// The forces enter the assembly (stepped, not rigid, not eroded).
    assembles: bool,
    /// Hourglass forces carried by the stiffness form.
    hourglass: HourglassStress,
    /// Hourglass energy dissipated so far, in the integration measure.
    hourglass_energy: f64,
    /// Bulk-viscosity work so far, in the integration measure.
    viscous_energy: f64,
}

/// A task of the element loop: the chunk's index, its states and slots, and its summary.
type ElementTask<'a> = (
    (usize, (&'a mut [MaterialState], &'a mut [ElementSlot])),
    &'a mut ChunkSummary,
);

/// A task of the nodal update: the chunk's index, its forces, velocities, previous velocities
/// and new positions, and its work sums.
type NodeTask<'a> = (
    (
        usize,
        (
            ((&'a mut [Vector], &'a mut [Vector]), &'a mut [Vector]),
            &'a mut [Vector],
        ),
    ),
    &'a mut NodeWork,
);

/// The internal force on node `n`: the forces of the elements around it (those that assemble
/// this step), summed in ascending element order, as a serial assembly in element order sums
/// them.
fn gathered_force(
    n: usize,
    slots: &[ElementSlot],
    node_elements: &[(usize, usize)],
    node_element_start: &[usize],
    dimension: usize,
) -> Vector {
    let mut total = [0.0; 3];
    for &(e, k) in &node_elements[node_element_start[n]..node_element_start[n + 1]] {
        let slot = &slots[e];
        if slot.assembles {
            for (sum, part) in total.iter_mut().zip(&slot.forces[k]).take(dimension) {
                *sum += part;
            }
        }
    }
    total
}

/// What the end of a node's step needs besides its velocities and new position.
struct NodeStep<'a> {
    mass: f64,
    /// `x_n`.
    position: &'a Vector,
    /// Velocity change by prescribed velocities this step.
    constraint_change: &'a Vector,
    /// Velocity change by rigid walls this step.
    wall_change: &'a Vector,
    /// Nodal damping's `1 - c dt`, if damping is on.
    damping_factor: Option<f64>,
    dt: f64,
}

impl<'a> NodeStep<'a> {
    /// Node `n`'s entries of the nodal arrays.
    fn at(
        n: usize,
        mass: &[f64],
        x: &'a [Vector],
        constraint_change: &'a [Vector],
        wall_change: &'a [Vector],
        damping_factor: Option<f64>,
        dt: f64,
    ) -> Self {
        Self {
            mass: mass[n],
            position: &x[n],
            constraint_change: &constraint_change[n],
            wall_change: &wall_change[n],
            damping_factor,
            dt,
        }
    }

    /// Damp `velocity` (`v_{n+1/2}`), book the work of the kinematic changes and of the damping
    /// as `m dv . (v_{n-1/2} + v_{n+1/2}) / 2`, and set `x_{n+1} = x_n + v_{n+1/2} dt`.
    fn finish(
        &self,
        velocity: &mut Vector,
        old: &Vector,
        next: &mut Vector,
        dimension: usize,
        sums: &mut NodeWork,
    ) {
        let mut damping_change = [0.0; 3];
        if let Some(factor) = self.damping_factor {
            for d in 0..dimension {
                damping_change[d] = velocity[d] * (factor - 1.0);
                velocity[d] *= factor;
            }
        }
        let mean: Vector = core::array::from_fn(|d| 0.5 * (old[d] + velocity[d]));
        let work = |dv: &Vector| self.mass * dot(dv, &mean, dimension);
        sums.external += work(self.constraint_change);
        sums.wall -= work(self.wall_change);
        sums.damping -= work(&damping_change);
        for d in 0..dimension {
            next[d] = self.position[d] + velocity[d] * self.dt;
        }
    }
}

/// One node chunk's work of the kinematic velocity changes in a step (per unit measure).
#[derive(Clone, Copy, Debug, Default)]
struct NodeWork {
    external: f64,
    wall: f64,
    damping: f64,
}

/// One chunk's contribution to the step: its smallest stable step, its element-cycles,
/// whether an element in it eroded, and the first error in element order.
#[derive(Debug)]
struct ChunkSummary {
    stable_dt: f64,
    cycles: u64,
    eroding: bool,
    error: Option<SolverError>,
}

impl Default for ChunkSummary {
    fn default() -> Self {
        Self {
            stable_dt: f64::INFINITY,
            cycles: 0,
            eroding: false,
            error: None,
        }
    }
}

/// An element formulation over a mesh: what the time loop needs to know about geometry,
/// kinematics and internal forces.
pub trait Discretisation: Sync {
    /// Spatial dimension of the nodal vectors (2 or 3).
    const DIMENSION: usize;
    /// Nodes per element (at most [`MAX_NODES`]).
    const NODES: usize;
    /// Factor from the integration measure to physical quantities (2 pi for axisymmetric
    /// models, which integrate per radian; 1 in 3D).
    const MEASURE: f64;
    /// Kernel stress component reported as the axial stress of tracked elements.
    const AXIAL_COMPONENT: usize;
    /// Reference nodal positions.
    fn reference_positions(&self) -> Vec<Vector>;
    /// Number of elements.
    fn element_count(&self) -> usize;
    /// Node indices of element `e`.
    fn element_nodes(&self, e: usize) -> &[usize];
    /// Material index of element `e`, and its part name (for messages).
    fn element_material(&self, e: usize) -> (usize, &str);
    /// Part index of element `e`.
    fn element_part(&self, e: usize) -> usize;
    /// Number of parts.
    fn part_count(&self) -> usize;
    /// Principal logarithmic strains of element `e` between the reference positions
    /// `reference` and positions `x` (for the kinematic failure and erosion criteria), or
    /// `None` if the formulation does not provide them.
    fn element_principal_strains(
        &self,
        _e: usize,
        _reference: &[Vector],
        _x: &[Vector],
    ) -> Option<[f64; 3]> {
        None
    }
    /// Whether every principal stretch of element `e` between `reference` and `x` lies inside
    /// `window`, so that no kinematic criterion can be met and the logarithms of
    /// [`Self::element_principal_strains`] are not needed; `false` when the formulation
    /// cannot tell.
    fn element_stretches_within(
        &self,
        _e: usize,
        _reference: &[Vector],
        _x: &[Vector],
        _window: &StretchWindow,
    ) -> bool {
        false
    }
    /// Volume of element `e` in the integration measure at positions `x` (<= 0: inverted).
    fn element_volume(&self, e: usize, x: &[Vector]) -> f64;
    /// Stable time step of element `e` at positions `x` for a wave speed, at rest.
    fn element_time_step(&self, e: usize, x: &[Vector], wave_speed: f64) -> f64;
    /// Kinematics, the kernel update, bulk viscosity, internal and hourglass forces of element
    /// `e` over a step from `x` to `x_new` with velocities `v`, with the element's own point
    /// model and its hourglass forces of the previous step. The nodal forces, in the model's
    /// integration measure, are written into the first [`Self::NODES`] entries of `forces`
    /// (in place: the element's slot, not a copy).
    #[allow(clippy::too_many_arguments)]
    fn element_step<P: PointModel>(
        &self,
        e: usize,
        x: &[Vector],
        x_new: &[Vector],
        v: &[Vector],
        state: &MaterialState,
        hourglass: &HourglassStress,
        material: &P,
        reference_volume: f64,
        dt: f64,
        settings: &SolverSettings,
        time: f64,
        forces: &mut [Vector; MAX_NODES],
    ) -> Result<ElementStep, SolverError>;
}

/// The principal stretches `lambda` with `|ln lambda|` below a material's kinematic strain
/// bound ([`PointModel::kinematic_strain_bound`]), narrowed by a relative 1e-9 so that the
/// logarithms, rounded, stay below it too: inside, no erosion or failure criterion on the
/// total strain can be met.
#[derive(Clone, Copy, Debug)]
pub struct StretchWindow {
    /// Open interval of `lambda`.
    pub stretch: (f64, f64),
    /// Open interval of `lambda^2`.
    pub stretch_squared: (f64, f64),
}

impl StretchWindow {
    /// The window of the strain bound `bound` (> 0).
    pub fn new(bound: f64) -> Self {
        let narrowed = bound * (1.0 - 1e-9);
        Self {
            stretch: (libm::exp(-narrowed), libm::exp(narrowed)),
            stretch_squared: (libm::exp(-2.0 * narrowed), libm::exp(2.0 * narrowed)),
        }
    }
}

/// A complete explicit model over a discretisation `M`, its parts' materials being kernel point
/// models `P`: [`Material`] (J2 metals, the default) for metal-only models, or
/// [`stoss_kernel::PartMaterial`] when the parts use different model families (a steel
/// projectile against RHT concrete). The element loop is compiled for `P`, so a metal-only
/// model calls the J2 update directly.
#[derive(Clone, Debug)]
pub struct ExplicitModel<M, P = Material> {
    /// The mesh (with its element formulation).
    pub mesh: M,
    /// Materials, indexed by the parts' material index.
    pub materials: Vec<P>,
    /// Initial temperature (K).
    pub initial_temperature: f64,
    /// Initial nodal velocities (empty: at rest).
    pub initial_velocity: Vec<Vector>,
    /// Prescribed velocities.
    pub constraints: Vec<VelocityConstraint>,
    /// Rigid walls.
    pub walls: Vec<RigidWall>,
    /// Penalty contact pairs between parts (2D models only).
    pub contacts: Vec<ContactPair>,
    /// Contact between parts that follows erosion (2D models only).
    pub eroding_contact: Option<ErodingContact>,
    /// Parts moved as rigid bodies (LS-DYNA `*MAT_RIGID`), by part index: their elements
    /// carry mass (from their material's density) but no stress and set no time step; their
    /// nodes share one velocity, the part's momentum over its mass after each step's forces.
    /// Translation only: along the axis in an axisymmetric model (no radial motion), in all
    /// three directions in 3D (no rotation: a body struck off its centre line would need
    /// it).
    pub rigid_parts: Vec<usize>,
    /// Pressures on boundary segments (2D models only).
    pub pressure_loads: Vec<PressureLoad>,
    /// A uniform body acceleration `g` (m/s^2; LS-DYNA `*LOAD_BODY`), gravity: every node
    /// feels `m g`, and its work `m g . (v_n-1/2 + v_n+1/2)/2 dt` is booked as external work
    /// (the loss of potential energy). `None`: no body load.
    pub body_acceleration: Option<Vector>,
    /// Truss (axial bar) elements on the mesh's nodes, e.g. reinforcement merged with the
    /// concrete (3D models only; [`super::truss`]).
    pub trusses: Vec<Truss>,
    /// Node-to-node contact of faces meshed on the same planes (a striker head on its pad;
    /// [`super::contact::node_to_node`]).
    pub node_contacts: Vec<NodeToNodeContact>,
    /// Numerical settings.
    pub settings: SolverSettings,
    /// Elements whose state history is recorded.
    pub tracked_elements: Vec<usize>,
}

/// The result of a run.
#[derive(Clone, Debug)]
pub struct ExplicitRun {
    /// Final nodal positions.
    pub positions: Vec<Vector>,
    /// Final nodal velocities.
    pub velocities: Vec<Vector>,
    /// Final element states.
    pub states: Vec<MaterialState>,
    /// Eroded elements.
    pub eroded: Vec<bool>,
    /// Energy balance at every output interval, the final one last.
    pub energy_history: Vec<EnergyBalance>,
    /// Tracked element histories, in the order of `tracked_elements`.
    pub tracked: Vec<StateHistory>,
    /// Reaction force histories `(time, force)` on each constraint's dof (physical measure).
    pub constraint_forces: Vec<Vec<(f64, f64)>>,
    /// Time steps taken.
    pub steps: usize,
    /// Element updates performed (element-cycles).
    pub element_cycles: u64,
    /// The eroding contact's statistics (default when the model has none).
    pub contact: ContactStatistics,
    /// Final state of each wall, in the order of `walls` (default for a fixed wall).
    pub walls: Vec<WallState>,
}

impl ExplicitRun {
    /// The final energy balance.
    pub fn energy(&self) -> EnergyBalance {
        self.energy_history.last().copied().unwrap_or_default()
    }
}

fn dot(a: &Vector, b: &Vector, dimension: usize) -> f64 {
    (0..dimension).map(|d| a[d] * b[d]).sum()
}

/// Kinetic energy `measure sum m v.v / 2`.
fn kinetic(v: &[Vector], mass: &[f64], measure: f64, dimension: usize) -> f64 {
    measure
        * v.iter()
            .zip(mass)
            .map(|(vel, m)| 0.5 * m * dot(vel, vel, dimension))
            .sum::<f64>()
}

/// The model's state at an output time, for observers that measure during a run.
#[derive(Clone, Copy, Debug)]
pub struct Snapshot<'a> {
    /// Time (s).
    pub time: f64,
    /// Nodal positions.
    pub positions: &'a [Vector],
    /// Nodal velocities (`v_{n+1/2}` of the last step).
    pub velocities: &'a [Vector],
    /// Element states.
    pub states: &'a [MaterialState],
    /// Eroded elements.
    pub eroded: &'a [bool],
    /// The energy balance.
    pub energy: &'a EnergyBalance,
    /// Each wall's state, in the order of the model's `walls` (default for a fixed wall).
    pub walls: &'a [WallState],
}

impl<M: Discretisation, P: PointModel + Sync> ExplicitModel<M, P> {
    /// Run to `settings.end_time`; `progress(time, energy)` at every output interval.
    pub fn run(
        &self,
        progress: &mut (dyn FnMut(f64, &EnergyBalance) + Send),
    ) -> Result<ExplicitRun, SolverError> {
        self.run_observed(&mut |snapshot| {
            progress(snapshot.time, snapshot.energy);
            ControlFlow::Continue(())
        })
    }

    /// Run to `settings.end_time`; `observer` sees the model at every output interval (and at
    /// the end) and may end the run there by returning `ControlFlow::Break` (an experiment
    /// whose outcome is decided).
    pub fn run_observed(
        &self,
        observer: &mut (dyn FnMut(&Snapshot) -> ControlFlow<()> + Send),
    ) -> Result<ExplicitRun, SolverError> {
        self.settings.check_threads()?;
        // One thread runs the element loop on the calling thread, without a pool: a pool's
        // `install` from another pool's worker would let that worker take more of its own
        // pool's jobs while it waits (a calibration's parallel simulations would then all run
        // at once, oversubscribing the cores).
        match self.settings.threads {
            Some(1) => self.run_in_pool(observer, true),
            Some(threads) => rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| SolverError::Model(format!("thread pool: {e}")))?
                .install(|| self.run_in_pool(observer, false)),
            None => self.run_in_pool(observer, false),
        }
    }

    fn run_in_pool(
        &self,
        observer: &mut (dyn FnMut(&Snapshot) -> ControlFlow<()> + Send),
        serial: bool,
    ) -> Result<ExplicitRun, SolverError> {
        let dimension = M::DIMENSION;
        let measure = M::MEASURE;
        let settings = &self.settings;
        let mesh = &self.mesh;
        let element_count = mesh.element_count();
        let mut x = mesh.reference_positions();
        let node_count = x.len();

        // Materials, reference volumes, lumped masses.
        for (index, material) in self.materials.iter().enumerate() {
            material.validate().map_err(|error| SolverError::Material {
                part: (0..element_count)
                    .map(|e| mesh.element_material(e))
                    .find(|(m, _)| *m == index)
                    .map_or_else(|| format!("material {index}"), |(_, name)| name.to_string()),
                error,
            })?;
        }
        let mut material_of = Vec::with_capacity(element_count);
        let mut reference_volume = Vec::with_capacity(element_count);
        let mut mass = vec![0.0; node_count];
        for e in 0..element_count {
            let (index, name) = mesh.element_material(e);
            let material = self.materials.get(index).ok_or_else(|| {
                SolverError::Model(format!(
                    "part {name} names material {index}, which does not exist"
                ))
            })?;
            let volume = mesh.element_volume(e, &x);
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

        // Rigid bodies: their nodes, and which elements belong to one.
        let mut rigid_element = vec![false; element_count];
        let mut rigid_bodies: Vec<Vec<usize>> = Vec::with_capacity(self.rigid_parts.len());
        for &part in &self.rigid_parts {
            if part >= mesh.part_count() {
                return Err(SolverError::Model(format!(
                    "rigid part {part} does not exist (the mesh has {} parts)",
                    mesh.part_count()
                )));
            }
            let mut nodes = Vec::new();
            for e in (0..element_count).filter(|&e| mesh.element_part(e) == part) {
                rigid_element[e] = true;
                nodes.extend_from_slice(mesh.element_nodes(e));
            }
            nodes.sort_unstable();
            nodes.dedup();
            rigid_bodies.push(nodes);
        }
        if M::DIMENSION == 3 && self.settings.hourglass == HourglassControl::Stiffness {
            // Tried on hexahedra with the quads' scaling: an element of the 343 m/s Taylor
            // rod inverted at 15 us with QH 0.1 (docs/solver.md).
            return Err(SolverError::Model(
                "the stiffness hourglass form is built for the 2D quads only; hexahedral models \
                 use the viscous form"
                    .into(),
            ));
        }
        let mut trusses = Trusses::new(&self.trusses, &x, dimension)?;
        trusses.add_masses(&mut mass);
        let mut v = if self.initial_velocity.is_empty() {
            vec![[0.0; 3]; node_count]
        } else if self.initial_velocity.len() == node_count {
            self.initial_velocity.clone()
        } else {
            return Err(SolverError::Model(
                "initial velocity must give one vector per node".into(),
            ));
        };
        let mut states: Vec<MaterialState> = material_of
            .iter()
            .map(|&m| self.materials[m].initial_state(self.initial_temperature))
            .collect();
        let mut eroded = vec![false; element_count];
        let mut force = vec![[0.0; 3]; node_count];

        move_rigidly(&rigid_bodies, &mass, &mut v, dimension, measure);
        // First time step from the elastic wave speeds (a zero-strain kernel update).
        let mut dt = f64::INFINITY;
        for e in (0..element_count).filter(|&e| !rigid_element[e]) {
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
            dt = dt.min(mesh.element_time_step(e, &x, output.wave_speed));
        }
        dt = dt.min(trusses.stable_time_step());
        let safety = settings.effective_time_step_safety(self.eroding_contact.is_some());
        dt *= safety;
        let minimum_dt = dt * 1e-4;
        let mut contact = PenaltyContact::new(&self.contacts, &mass, dt, dimension)?;
        let mut eroding = match &self.eroding_contact {
            Some(settings) => Some(ErodingSurfaces::new(
                settings,
                element_count,
                |e| (mesh.element_nodes(e), mesh.element_part(e)),
                mesh.part_count(),
                &x,
                dt,
                dimension,
            )?),
            None => None,
        };
        if let Some(surfaces) = eroding.as_mut() {
            for constraint in &self.constraints {
                surfaces.prescribe(&constraint.nodes, constraint.dof);
            }
        }
        let stretch_windows: Vec<Option<StretchWindow>> = self
            .materials
            .iter()
            .map(|m| m.kinematic_strain_bound().map(StretchWindow::new))
            .collect();
        let kinematic_criteria = stretch_windows.iter().any(Option::is_some);
        let reference = x.clone();
        if kinematic_criteria
            && (element_count > 0 && mesh.element_principal_strains(0, &x, &x).is_none())
        {
            return Err(SolverError::Model(
                "geometric-strain erosion and principal-strain failure are implemented for 2D \
                 (axisymmetric) models only"
                    .into(),
            ));
        }
        let mut newly_eroded: Vec<usize> = Vec::new();
        if !self.pressure_loads.is_empty() && dimension != 2 {
            return Err(SolverError::Model(
                "pressure loads are implemented for 2D (axisymmetric) models only".into(),
            ));
        }
        let mut loaded_nodes: Vec<usize> = Vec::new();
        for load in &self.pressure_loads {
            for segment in &load.segments {
                for &n in segment {
                    if n >= node_count {
                        return Err(SolverError::Model(format!(
                            "a pressure-load segment names node {n}; the mesh has {node_count}"
                        )));
                    }
                    loaded_nodes.push(n);
                }
            }
        }
        loaded_nodes.sort_unstable();
        loaded_nodes.dedup();
        // Each segment's interpolation weights in its history, from its initial mid-radius.
        let load_weights: Vec<Vec<(usize, usize, f64)>> = self
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
        let mut pressure_force = vec![[0.0; 3]; node_count];
        let mut shares: Vec<(usize, f64)> = Vec::new();

        // Moving walls: checked, and their velocities `w_{n-1/2}` (the initial one first).
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
        let mut wall_states: Vec<WallState> = self
            .walls
            .iter()
            .map(|wall| WallState {
                velocity: wall.motion.map_or(0.0, |m| m.velocity),
                ..WallState::default()
            })
            .collect();
        let walls_kinetic = |states: &[WallState]| -> f64 {
            self.walls
                .iter()
                .zip(states)
                .filter_map(|(wall, state)| {
                    wall.motion
                        .map(|m| 0.5 * m.mass * state.velocity * state.velocity)
                })
                .sum::<f64>()
        };
        let mut wall_order: Vec<(f64, usize)> = Vec::new();
        let mut nonlocal = match &settings.nonlocal {
            Some(averaging) => {
                let centroids: Vec<Vector> = (0..element_count)
                    .map(|e| {
                        let nodes = mesh.element_nodes(e);
                        core::array::from_fn(|d| {
                            nodes.iter().map(|&n| x[n][d]).sum::<f64>() / nodes.len() as f64
                        })
                    })
                    .collect();
                Some(NonlocalField::new(
                    averaging,
                    &centroids,
                    &reference_volume,
                    |e| mesh.element_part(e),
                )?)
            }
            None => None,
        };
        let mut energy = EnergyBalance {
            kinetic: kinetic(&v, &mass, measure, dimension) + walls_kinetic(&wall_states),
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
        let walls: Vec<(Vector, Vector)> = self
            .walls
            .iter()
            .map(|w| {
                let component = |values: &[f64], d: usize| {
                    if d < dimension {
                        values.get(d).copied().unwrap_or(0.0)
                    } else {
                        0.0
                    }
                };
                let point: Vector = core::array::from_fn(|d| component(&w.point, d));
                let normal: Vector = core::array::from_fn(|d| component(&w.normal, d));
                (point, normal)
            })
            .collect();

        // Work arrays, allocated once.
        let mut x_new = x.clone();
        let mut v_old = v.clone();
        let mut dv_constraint = vec![[0.0; 3]; node_count];
        let mut dv_wall = vec![[0.0; 3]; node_count];
        let mut node_work = vec![NodeWork::default(); node_count.div_ceil(NODE_CHUNK)];
        // Nodes whose velocity a constraint or a wall may change.
        for contact in &self.node_contacts {
            contact.check(node_count)?;
        }
        let mut kinematic_nodes: Vec<usize> = self
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
        kinematic_nodes.sort_unstable();
        kinematic_nodes.dedup();
        // Nodes finished after the kinematic changes: those, and the rigid bodies' nodes.
        let mut deferred_nodes: Vec<usize> = kinematic_nodes
            .iter()
            .chain(rigid_bodies.iter().flatten())
            .copied()
            .collect();
        deferred_nodes.sort_unstable();
        deferred_nodes.dedup();
        let mut deferred = vec![false; node_count];
        for &n in &deferred_nodes {
            deferred[n] = true;
        }
        // Without contact or loads, the force gather joins the nodal update.
        let gather_with_nodes = self.contacts.is_empty()
            && self.eroding_contact.is_none()
            && self.pressure_loads.is_empty();
        let mut slots = vec![ElementSlot::default(); element_count];
        let mut summaries: Vec<ChunkSummary> = (0..element_count.div_ceil(ELEMENT_CHUNK))
            .map(|_| ChunkSummary::default())
            .collect();
        // Each node's (element, corner) pairs in ascending element order.
        let mut node_element_start = vec![0usize; node_count + 1];
        for e in 0..element_count {
            for &n in mesh.element_nodes(e) {
                node_element_start[n + 1] += 1;
            }
        }
        for n in 0..node_count {
            node_element_start[n + 1] += node_element_start[n];
        }
        let mut node_elements = vec![(0usize, 0usize); node_element_start[node_count]];
        let mut filled = node_element_start.clone();
        for e in 0..element_count {
            for (k, &n) in mesh.element_nodes(e).iter().enumerate() {
                node_elements[filled[n]] = (e, k);
                filled[n] += 1;
            }
        }

        let mut time = 0.0;
        let mut dt_previous = 0.0;
        let mut next_output = settings.output_interval;
        let mut steps = 0;
        let mut element_cycles = 0u64;
        while time < settings.end_time {
            let dt_average = 0.5 * (dt_previous + dt);
            contact.add_forces(&x, &v, dt_average, &mut force);
            if let Some(surfaces) = eroding.as_mut() {
                surfaces.add_forces(&x, &v, &mass, dt_average, &mut force);
            }
            if !loaded_nodes.is_empty() {
                for &n in &loaded_nodes {
                    pressure_force[n] = [0.0; 3];
                }
                // The force at t_n stands for [t_n - dt_previous/2, t_n + dt/2).
                let window = (time - 0.5 * dt_previous, time + 0.5 * dt);
                for (load, weights) in self.pressure_loads.iter().zip(&load_weights) {
                    let history = load.history.read().map_err(|_| {
                        SolverError::Model("a pressure history's lock is poisoned".into())
                    })?;
                    history.overlaps(window.0, window.1, &mut shares);
                    add_pressure_forces(load, &history, weights, &shares, &x, &mut pressure_force);
                }
                for &n in &loaded_nodes {
                    for d in 0..dimension {
                        force[n][d] += pressure_force[n][d];
                    }
                }
            }
            // The nodal update, in parallel over fixed node chunks: the force gathered from the
            // elements (here when no contact or load adds to it first, else after the element
            // loop), the velocity update and, for every node no constraint, wall or rigid body
            // may change, damping, the work sums and the new position. Each chunk's work sums
            // are added in chunk order.
            // Without bars nothing is added (not even zeros, which would turn a -0.0 into +0.0).
            let truss_force = (!self.trusses.is_empty()).then_some(&trusses.node_force);
            let damping_factor = match settings.damping {
                Some(damping) if time >= damping.start_time => Some(1.0 - damping.coefficient * dt),
                _ => None,
            };
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
                                &slots,
                                &node_elements,
                                &node_element_start,
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
                            if let Some(g) = &self.body_acceleration {
                                for d in 0..dimension {
                                    vel[d] += g[d] * dt_average;
                                }
                            }
                        }
                        if deferred[n] {
                            continue;
                        }
                        NodeStep::at(n, &mass, &x, &dv_constraint, &dv_wall, damping_factor, dt)
                            .finish(vel, old, position, dimension, sums);
                    }
                };
            if serial {
                force
                    .chunks_mut(NODE_CHUNK)
                    .zip(v.chunks_mut(NODE_CHUNK))
                    .zip(v_old.chunks_mut(NODE_CHUNK))
                    .zip(x_new.chunks_mut(NODE_CHUNK))
                    .enumerate()
                    .zip(node_work.iter_mut())
                    .for_each(update_nodes);
            } else {
                force
                    .par_chunks_mut(NODE_CHUNK)
                    .zip(v.par_chunks_mut(NODE_CHUNK))
                    .zip(v_old.par_chunks_mut(NODE_CHUNK))
                    .zip(x_new.par_chunks_mut(NODE_CHUNK))
                    .enumerate()
                    .zip(node_work.par_iter_mut())
                    .for_each(update_nodes);
            }
            for &n in &kinematic_nodes {
                dv_constraint[n] = [0.0; 3];
                dv_wall[n] = [0.0; 3];
            }
            move_rigidly(&rigid_bodies, &mass, &mut v, dimension, measure);
            let half_time = time + 0.5 * dt;
            // Kinematic modifications of v_{n+1/2}; each records its velocity change so that its
            // work is the central-difference-consistent `m dv . (v_old + v_new)/2`.
            for (c, constraint) in self.constraints.iter().enumerate() {
                let target = constraint.velocity.at(half_time);
                let mut reaction = 0.0;
                for &n in &constraint.nodes {
                    let change = target - v[n][constraint.dof];
                    dv_constraint[n][constraint.dof] += change;
                    if dt_average > 0.0 {
                        reaction += mass[n] * change / dt_average;
                    }
                    v[n][constraint.dof] = target;
                }
                constraint_forces[c].push((time, measure * reaction));
            }
            // Rigid walls: stop the normal approach; Coulomb friction on the tangential part.
            for ((wall, (point, normal)), slaves) in self.walls.iter().zip(&walls).zip(&wall_slaves)
            {
                if wall.motion.is_some() {
                    continue;
                }
                for &n in slaves {
                    let offset: Vector = core::array::from_fn(|d| x[n][d] - point[d]);
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
                        dv_wall[n][d] += v[n][d] - before[d];
                    }
                }
            }
            // Moving walls: gravity on the wall, then the momentum-conserving contact.
            for (((wall, (point, normal)), slaves), state) in self
                .walls
                .iter()
                .zip(&walls)
                .zip(&wall_slaves)
                .zip(wall_states.iter_mut())
            {
                let Some(motion) = &wall.motion else {
                    continue;
                };
                let gravity = self
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
                    &mass,
                    &x,
                    &mut v,
                    &mut dv_wall,
                    dt,
                    dimension,
                    &mut wall_order,
                );
                let mean = 0.5 * (before + step.velocity);
                energy.external_work += motion.mass * gravity * dt_average * mean;
                energy.contact -= motion.mass * (step.velocity - step.free_velocity) * mean;
                state.contact_force = if dt_average > 0.0 {
                    motion.mass * (step.velocity - step.free_velocity) / dt_average
                } else {
                    0.0
                };
                state.velocity = step.velocity;
                state.displacement += step.velocity * dt;
            }
            for contact in &self.node_contacts {
                contact.resolve(&mass, &x, &mut v, &mut dv_wall, dt, dimension);
            }
            // The deferred nodes, in ascending order, after the kinematic changes.
            let mut deferred_work = NodeWork::default();
            for &n in &deferred_nodes {
                NodeStep::at(n, &mass, &x, &dv_constraint, &dv_wall, damping_factor, dt).finish(
                    &mut v[n],
                    &v_old[n],
                    &mut x_new[n],
                    dimension,
                    &mut deferred_work,
                );
            }
            for sums in node_work.iter().chain([&deferred_work]) {
                energy.external_work += measure * sums.external;
                energy.contact += measure * sums.wall;
                energy.damping += measure * sums.damping;
            }
            if contact.is_active() {
                energy.contact += measure * contact.absorbed(&v_old, &v, dt_average);
            }
            if !loaded_nodes.is_empty() {
                energy.external_work -=
                    measure * absorbed_work(&pressure_force, &loaded_nodes, &v_old, &v, dt_average);
            }
            if let Some(surfaces) = &eroding {
                energy.contact += measure * surfaces.absorbed(&v_old, &v, dt_average);
            }
            if let Some(g) = &self.body_acceleration {
                // In node order, so the sum does not depend on the thread count.
                let mut work = 0.0;
                for n in 0..node_count {
                    if mass[n] > 0.0 {
                        let mean: Vector = core::array::from_fn(|d| 0.5 * (v_old[n][d] + v[n][d]));
                        work += mass[n] * dot(g, &mean, dimension) * dt_average;
                    }
                }
                energy.external_work += measure * work;
            }

            if let Some(field) = nonlocal.as_mut() {
                field.record(&states);
            }
            // Elements in parallel (or serially on one thread), in chunks of a fixed size: each
            // element writes its own state and slot; the chunks' summaries are combined in
            // element order, so nothing depends on the thread count.
            let step_chunk = |((c, (chunk_states, chunk_slots)), summary): ElementTask<'_>| {
                *summary = ChunkSummary::default();
                for (i, (state, slot)) in chunk_states.iter_mut().zip(chunk_slots).enumerate() {
                    let e = c * ELEMENT_CHUNK + i;
                    slot.assembles = false;
                    if eroded[e] || rigid_element[e] {
                        continue;
                    }
                    let material = &self.materials[material_of[e]];
                    let mut step = match mesh.element_step(
                        e,
                        &x,
                        &x_new,
                        &v,
                        state,
                        &slot.hourglass,
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
                        if !mesh.element_stretches_within(e, &reference, &x_new, window) {
                            if let Some(strains) =
                                mesh.element_principal_strains(e, &reference, &x_new)
                            {
                                step.state.flags.insert(material.kinematic_flags(strains).0);
                            }
                        }
                    }
                    summary.cycles += 1;
                    slot.hourglass_energy += step.hourglass_power * dt;
                    slot.viscous_energy += step.viscous_work;
                    *state = step.state;
                    slot.hourglass = step.hourglass;
                    if step.state.flags.contains(StateFlags::ERODE) {
                        summary.eroding = true;
                        continue;
                    }
                    slot.assembles = true;
                    summary.stable_dt = summary.stable_dt.min(step.stable_dt);
                }
            };
            if serial {
                states
                    .chunks_mut(ELEMENT_CHUNK)
                    .zip(slots.chunks_mut(ELEMENT_CHUNK))
                    .enumerate()
                    .zip(summaries.iter_mut())
                    .for_each(step_chunk);
            } else {
                states
                    .par_chunks_mut(ELEMENT_CHUNK)
                    .zip(slots.par_chunks_mut(ELEMENT_CHUNK))
                    .enumerate()
                    .zip(summaries.par_iter_mut())
                    .with_max_len(1)
                    .for_each(step_chunk);
            }
            let mut dt_next = f64::INFINITY;
            for (c, summary) in summaries.iter_mut().enumerate() {
                if let Some(error) = summary.error.take() {
                    return Err(error);
                }
                element_cycles += summary.cycles;
                dt_next = dt_next.min(summary.stable_dt);
                if summary.eroding {
                    let first = c * ELEMENT_CHUNK;
                    for e in first..(first + ELEMENT_CHUNK).min(element_count) {
                        if !eroded[e]
                            && !rigid_element[e]
                            && states[e].flags.contains(StateFlags::ERODE)
                        {
                            eroded[e] = true;
                            newly_eroded.push(e);
                            energy.eroded +=
                                measure * states[e].internal_energy * reference_volume[e];
                        }
                    }
                }
            }

            if let Some(field) = nonlocal.as_mut() {
                field.apply(&mut states, &eroded);
            }
            dt_next = dt_next.min(trusses.step(&x_new)?);

            // With contact or loads, the nodal forces are gathered here, before those add theirs.
            if !gather_with_nodes {
                let gather = |(c, chunk): (usize, &mut [Vector])| {
                    for (i, total) in chunk.iter_mut().enumerate() {
                        *total = gathered_force(
                            c * NODE_CHUNK + i,
                            &slots,
                            &node_elements,
                            &node_element_start,
                            dimension,
                        );
                    }
                };
                if serial {
                    force.chunks_mut(NODE_CHUNK).enumerate().for_each(gather);
                } else {
                    force
                        .par_chunks_mut(NODE_CHUNK)
                        .enumerate()
                        .for_each(gather);
                }
            }
            if !newly_eroded.is_empty() {
                if let Some(surfaces) = eroding.as_mut() {
                    let removed = surfaces.on_erosion(
                        &newly_eroded,
                        |e| mesh.element_nodes(e),
                        &eroded,
                        &mut mass,
                        &mut v,
                    );
                    energy.eroded += measure * removed;
                }
                newly_eroded.clear();
            }
            std::mem::swap(&mut x, &mut x_new);
            time += dt;
            steps += 1;
            energy.time = time;
            dt_previous = dt;
            if dt_next.is_finite() {
                dt = safety * dt_next;
            }
            if dt < minimum_dt {
                return Err(SolverError::TimeStepCollapse {
                    time,
                    time_step: dt,
                });
            }
            if time >= next_output || time >= settings.end_time {
                energy.kinetic =
                    kinetic(&v, &mass, measure, dimension) + walls_kinetic(&wall_states);
                energy.internal = measure
                    * states
                        .iter()
                        .zip(&reference_volume)
                        .zip(&eroded)
                        .filter(|(_, gone)| !**gone)
                        .map(|((s, v0), _)| s.internal_energy * v0)
                        .sum::<f64>();
                if !self.trusses.is_empty() {
                    energy.internal += measure * trusses.internal_energy();
                }
                energy.hourglass = measure * slots.iter().map(|s| s.hourglass_energy).sum::<f64>();
                energy.viscous = measure * slots.iter().map(|s| s.viscous_energy).sum::<f64>();
                next_output += settings.output_interval;
                energy_history.push(energy);
                for (slot, &e) in self.tracked_elements.iter().enumerate() {
                    tracked[slot].samples.push(StateSample::from_state(
                        time,
                        &states[e],
                        M::AXIAL_COMPONENT,
                    ));
                }
                settings.progress.report(time, settings.end_time);
                let decision = observer(&Snapshot {
                    time,
                    positions: &x,
                    velocities: &v,
                    states: &states,
                    eroded: &eroded,
                    energy: &energy,
                    walls: &wall_states,
                });
                if decision.is_break() {
                    break;
                }
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
        Ok(ExplicitRun {
            positions: x,
            velocities: v,
            states,
            eroded,
            energy_history,
            tracked,
            constraint_forces,
            steps,
            element_cycles,
            contact: eroding
                .as_ref()
                .map(ErodingSurfaces::statistics)
                .unwrap_or_default(),
            walls: wall_states,
        })
    }
}

/// Give the nodes of each rigid body the body's velocity: its momentum over its mass
/// (`V = sum m v / sum m` over the nodes, after the step's forces), so the body moves as a
/// whole under the resultant force and the constraint forces between its nodes do no work.
/// Axisymmetric models (`measure != 1`) keep no radial velocity: an axisymmetric body can
/// only translate along the axis.
fn move_rigidly(
    bodies: &[Vec<usize>],
    mass: &[f64],
    v: &mut [Vector],
    dimension: usize,
    measure: f64,
) {
    for nodes in bodies {
        let total: f64 = nodes.iter().map(|&n| mass[n]).sum();
        if total <= 0.0 {
            continue;
        }
        let mut velocity: Vector = core::array::from_fn(|d| {
            if d < dimension {
                nodes.iter().map(|&n| mass[n] * v[n][d]).sum::<f64>() / total
            } else {
                0.0
            }
        });
        if measure != 1.0 {
            velocity[0] = 0.0;
        }
        for &n in nodes {
            v[n] = velocity;
        }
    }
}

/// Add the consistent nodal forces per radian of a pressure load (see [`PressureLoad`]):
/// `weights` are its segments' radial interpolation weights, `shares` the records that
/// overlap the step's window and their shares of it.
fn add_pressure_forces(
    load: &PressureLoad,
    history: &PressureHistory,
    weights: &[(usize, usize, f64)],
    shares: &[(usize, f64)],
    x: &[Vector],
    forces: &mut [Vector],
) {
    if shares.is_empty() {
        return;
    }
    for (&[a, b], &(lo, hi, w)) in load.segments.iter().zip(weights) {
        let mut p = 0.0;
        for &(k, share) in shares {
            let record = &history.values[k];
            p += share * ((1.0 - w) * record[lo] + w * record[hi]);
        }
        let p = load.scale * p;
        if p == 0.0 {
            continue;
        }
        let (ra, rb) = (x[a][0], x[b][0]);
        // Left normal times length: (-(z_b - z_a), r_b - r_a).
        let n = [-(x[b][1] - x[a][1]), x[b][0] - x[a][0]];
        let wa = (2.0 * ra + rb) / 6.0;
        let wb = (ra + 2.0 * rb) / 6.0;
        for d in 0..2 {
            forces[a][d] += p * n[d] * wa;
            forces[b][d] += p * n[d] * wb;
        }
    }
}
