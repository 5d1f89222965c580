//! The explicit time integration shared by every element formulation: central differences,
//! lumped mass, CFL time step, prescribed velocities, rigid walls, penalty contact between
//! parts, nodal damping, erosion, energy balance and the deterministic parallel element loop.
//!
//! Contact ([`super::contact`], 2D only) hooks in at two points of the step: its forces at
//! `x_n` are added to the assembled internal forces before the velocity update (computed
//! serially in a fixed order, so the loop stays bit-identical for any thread count), and their
//! work is booked as `EnergyBalance::contact` with the same mid-step velocities as the walls'.

mod run;

use super::contact::{ContactPair, ContactStatistics, ErodingContact, NodeToNodeContact};
use super::energy::EnergyBalance;
use super::loads::{PressureHistory, PressureLoad, RigidWall, VelocityConstraint};
use super::moving_wall::WallState;
use super::truss::Truss;
use super::{SolverError, SolverSettings};
use crate::measure::StateHistory;
use run::Run;
use std::ops::ControlFlow;
use stoss_kernel::{Material, MaterialState, PointModel};

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

/// Per-element result of one step besides the state, hourglass forces and nodal forces the
/// step writes in place.
#[derive(Clone, Copy, Debug)]
pub struct ElementStep {
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
    /// model. The element's `state` and its generalised `hourglass` forces (2D; untouched in
    /// 3D) are advanced in place, and the nodal forces, in the model's integration measure, are
    /// written into the first [`Self::NODES`] entries of `forces`: the element's own slots, so
    /// that no state is copied. On an error the run ends, and `state` may hold the stress
    /// rotated for the step.
    #[allow(clippy::too_many_arguments)]
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

    /// The time the run ended at (s; that of its final energy balance).
    pub fn final_time(&self) -> f64 {
        self.energy().time
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
    /// The step the solver takes next (s).
    pub time_step: f64,
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
    /// Time from which nodal damping applies (s); infinite without damping or while its start
    /// waits for the end of the plastic event.
    pub damping_from: f64,
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

    /// The driver: set up the run, step it to the end time (or until the observer or the
    /// rest criterion ends it), and return its result.
    fn run_in_pool(
        &self,
        observer: &mut (dyn FnMut(&Snapshot) -> ControlFlow<()> + Send),
        serial: bool,
    ) -> Result<ExplicitRun, SolverError> {
        let mut run = Run::new(self, serial)?;
        while !run.is_done() {
            if run.step(observer)?.is_break() {
                break;
            }
        }
        Ok(run.finish())
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
