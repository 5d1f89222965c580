//! A multi-material Eulerian solver for solids with strength on a fixed 2D grid, axisymmetric
//! `(r, z)` or planar: the Lagrange-plus-remap scheme of CTH (McGlaun, Thompson & Elrick,
//! IJIE 10 (1990) 351), PAGOSA and Autodyn-Euler, as surveyed by Benson, CMAME 99 (1992) 235.
//! The method, its references, its verification table and its validation are in
//! docs/euler.md.
//!
//! Each cycle:
//! 1. **Lagrange step** ([`lagrange`]) on the grid's rectangles: staggered velocities at the
//!    nodes, stresses at the cells; the nodal forces of the one-point axisymmetric quad
//!    (volume-weighted, as the Lagrangian solver's, `crate::solver::axisymmetric`), viscous
//!    hourglass control and linear + quadratic bulk viscosity; the velocities advance, and the
//!    strain increments and each face's swept volume follow from them. The volume change of a
//!    mixed cell is shared among its materials by the closure of [`closure`]; **every material
//!    update goes through the kernel** (any [`PointModel`]: J2 metals, RHT, K&C).
//! 2. **Remap** ([`remap`]): the same swept volumes, directionally split (the order alternates
//!    each cycle), carry each material's volume, mass and state (internal energy, stress,
//!    plastic strain and rate, temperature, damage, EoS history) between cells; each
//!    material's share of a face's volume is cut from the donor cell by Youngs' PLIC
//!    interface with nested dissection ([`interface`]); nodal momentum moves with the cell mass
//!    fluxes averaged onto the nodal control volumes (consistent with the nodal masses, so
//!    momentum is conserved exactly), with van Leer's limited upwind velocity.
//!
//! Void is a phase of its own (the last, without mass): free surfaces and the crater are its
//! interfaces. Erosion is not needed; failed material (damage 1) carries no shear and no
//! tension.
//!
//! Cells and nodes are updated in parallel with no reductions other than exact maxima and
//! sums in a fixed order ([`ordered_sum`]), so results do not depend on the thread count.

pub mod closure;
pub mod interface;
pub mod lagrange;
pub mod remap;

use crate::blast::euler::{Geometry, Grid};
use crate::solver::BulkViscosity;
use stoss_kernel::{MaterialState, PointModel, StepInput};

/// Largest number of cells (or faces) in one parallel task of a cell loop: small enough that
/// a thread finishing its share of void cells takes over part of the material cells' work.
const CELLS_PER_TASK: usize = 4096;

/// Terms per partial sum of [`ordered_sum`].
const SUM_CHUNK: usize = 4096;

/// `sum_{i < count} term(i)`, computed in parallel as partial sums over fixed chunks of
/// [`SUM_CHUNK`] terms added in chunk order: the same bits for any thread count.
pub fn ordered_sum(count: usize, term: impl Fn(usize) -> f64 + Sync) -> f64 {
    use rayon::prelude::*;
    let partial: Vec<f64> = (0..count.div_ceil(SUM_CHUNK))
        .into_par_iter()
        .map(|chunk| {
            (chunk * SUM_CHUNK..((chunk + 1) * SUM_CHUNK).min(count))
                .map(&term)
                .sum::<f64>()
        })
        .collect();
    partial.iter().sum()
}

/// Whether cell `(i, j)` is in the cycle's work: `active_end` holds each row's end
/// ([`EulerSolver::active_columns`]), or nothing outside a cycle (every cell).
#[inline]
pub(crate) fn in_work(active_end: &[usize], i: usize, j: usize) -> bool {
    active_end.get(j).is_none_or(|&end| i < end)
}

/// [`in_work`] of cell `c` of a grid `cells_r` cells wide.
#[inline]
pub(crate) fn cell_in_work(active_end: &[usize], cells_r: usize, c: usize) -> bool {
    in_work(active_end, c % cells_r, c / cells_r)
}

/// Whether node `(i, j)` is in the cycle's work: a corner of a cell in it ([`in_work`]).
/// The others have no mass and no velocity.
#[inline]
pub(crate) fn node_in_work(active_end: &[usize], i: usize, j: usize) -> bool {
    if active_end.is_empty() {
        return true;
    }
    let end = |row: usize| active_end.get(row).copied().unwrap_or(0);
    i <= end(j).max(j.checked_sub(1).map_or(0, end))
}

/// Most materials a model may hold (besides void).
pub const MAX_MATERIALS: usize = 3;

/// Phases of a cell: the materials and void.
pub const MAX_PHASES: usize = MAX_MATERIALS + 1;

/// Volume fraction below which a material does not take part in a cell's Lagrange step (its
/// state is carried unchanged) and above `1 -` which a cell counts as pure.
pub const ACTIVE_FRACTION: f64 = 1e-6;

/// Cells of void kept in a cycle's work beyond the last cell holding material in each
/// direction ([`EulerSolver::active_columns`]). Within one cycle material crosses at most one
/// cell per sweep (the Courant number is below one), and the widest stencil, the remap's
/// van Leer slope, reads one cell beyond the donor: three cells keep every cell the cycle can
/// change or read inside the work.
const ACTIVE_MARGIN: usize = 3;

/// Fraction of a full control volume's mass below which a node is light: it is carried by
/// the remap but not accelerated, and sets no time step. A sliver of material stranded in a
/// cell (fractions of 1e-12 and below) otherwise meets the stress of a neighbouring full cell
/// with almost no mass and runs away (60 km/s seen in the 1700 m/s shot), collapsing the step.
pub const LIGHT_NODE_FRACTION: f64 = 1e-6;

/// Why the Eulerian solver stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EulerError {
    /// The set-up is not valid (named field).
    #[error("Eulerian solver set-up: {0}")]
    Setup(String),
    /// The kernel refused a material's update.
    #[error(
        "Eulerian solver: the {material} material in cell ({i}, {j}) at r = {r:.4e} m, \
         z = {z:.4e} m, t = {time:.4e} s, relative volume V/V0 = {relative_volume:.4}: {error}"
    )]
    Update {
        /// Material name.
        material: String,
        /// Cell column.
        i: usize,
        /// Cell row.
        j: usize,
        /// Cell centre (m).
        r: f64,
        /// Cell centre (m).
        z: f64,
        /// Time (s).
        time: f64,
        /// `V/V0` the step asked for.
        relative_volume: f64,
        /// The kernel's error.
        #[source]
        error: stoss_kernel::UpdateError,
    },
    /// A cell's state or a node's velocity became non-finite.
    #[error(
        "Eulerian solver: cell ({i}, {j}) holding {materials} became non-finite at \
         t = {time:.4e} s"
    )]
    NonFinite {
        /// Cell column.
        i: usize,
        /// Cell row.
        j: usize,
        /// The materials in the cell.
        materials: String,
        /// Time (s).
        time: f64,
    },
    /// The time step collapsed.
    #[error(
        "Eulerian solver: time step collapsed to {time_step:.3e} s at t = {time:.4e} s (the \
         first cycle's was {first_time_step:.3e} s)"
    )]
    TimeStepCollapse {
        /// Time (s).
        time: f64,
        /// Time step (s).
        time_step: f64,
        /// The first cycle's time step (s).
        first_time_step: f64,
    },
    /// The run took more cycles than its budget ([`EulerSettings::cycle_budget`]).
    #[error(
        "Eulerian solver: {cycles} cycles reached at t = {time:.4e} s of a run to \
         {end_time:.4e} s, over its budget of {budget} ({multiple} times the cycles at the first \
         cycle's step of {first_time_step:.3e} s, plus {CYCLE_BUDGET_ALLOWANCE}); the step now \
         is {time_step:.3e} s"
    )]
    CycleBudget {
        /// Time (s).
        time: f64,
        /// The run's end time (s).
        end_time: f64,
        /// Cycles the run has taken.
        cycles: u64,
        /// Most cycles allowed.
        budget: u64,
        /// [`EulerSettings::cycle_budget`].
        multiple: f64,
        /// The first cycle's time step (s).
        first_time_step: f64,
        /// The last cycle's time step (s).
        time_step: f64,
    },
}

/// What a grid edge does to the material next to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wall {
    /// Both velocity components zero (a clamped rim).
    Fixed,
    /// Normal velocity zero, tangential free (a symmetry plane, a frictionless wall).
    Slip,
}

/// The outer edges of the grid (`r = 0` is the axis in axisymmetric grids, a slip wall in
/// planar ones).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Walls {
    /// `r = cells_r spacing_r`.
    pub outer: Wall,
    /// The lowest edge.
    pub bottom: Wall,
    /// The highest edge.
    pub top: Wall,
}

/// The default Courant number, 2/3: Autodyn's default time-step safety factor. On the
/// stable-step formula of [`EulerSolver::stable_time_step`] it keeps a square cell's acoustic
/// number below the 2D Lagrange step's limit `1/sqrt(2)` and a remap sweep's below one cell;
/// the long-rod depths are 0.3-0.4 % shallower at it than at 0.25 (docs/euler.md, "Time step").
pub const DEFAULT_COURANT: f64 = 2.0 / 3.0;

/// Numerical settings.
#[derive(Clone, Debug, PartialEq)]
pub struct EulerSettings {
    /// Courant number on `min(h) / (c + |v|)` (default [`DEFAULT_COURANT`]).
    pub courant: f64,
    /// Bulk viscosity (LS-DYNA's 1.5 / 0.06 by default).
    pub bulk_viscosity: BulkViscosity,
    /// Viscous hourglass coefficient (LS-DYNA QH, default 0.1).
    pub hourglass_coefficient: f64,
    /// Worker threads (`None`: rayon's default). Results do not depend on it.
    pub threads: Option<usize>,
    /// Smallest time step accepted before the run stops (s).
    pub minimum_time_step: f64,
    /// Smallest time step accepted before the run stops, as a fraction of the first cycle's
    /// (default 0.01). On a fixed grid the step `h / (c + |v|)` falls to 1 % of its first
    /// value only if a cell's sound speed plus speed grows a hundredfold (some 500 km/s in
    /// steel), which no impact produces: a run that gets there has collapsed numerically,
    /// and it stops with a typed error instead of running on for hours (LS-DYNA's `TSMIN`
    /// of `*CONTROL_TERMINATION` is the same kind of floor).
    pub minimum_time_step_fraction: f64,
    /// Most cycles a [`EulerSolver::run`] may take, as a multiple of the cycles the run
    /// would take at its first cycle's step (`(end_time - start) / dt_first`, plus
    /// [`CYCLE_BUDGET_ALLOWANCE`]; default 10). An impact's step stays near its first (the
    /// seed's 1250 m/s shot at 0.4 mm takes 1 794 cycles, about 1.01 times the 1 779 of its
    /// first step, set by the rod's wave speed plus its velocity), so a run that needs ten times as
    /// many cycles has a step hovering just above the floor, and stops with
    /// [`EulerError::CycleBudget`] after a bounded, deterministic amount of work instead of
    /// running on: a calibration candidate whose target hardened with temperature once ran
    /// 43 minutes where the shot takes 17 s. `f64::INFINITY` turns it off.
    pub cycle_budget: f64,
    /// Leave the void farther than [`ACTIVE_MARGIN`] cells from all material out of each
    /// cycle's cell and node loops ([`EulerSolver::active_columns`]; default `true`). The
    /// results are the same to the bit either way (`false`: every cell every cycle, the
    /// reference the skip is tested against, `tests/euler.rs`).
    pub skip_far_void: bool,
    /// Frictionless sliding between materials (default `false`: welded, the one velocity
    /// field's own interface). In each cell whose 3 x 3 block holds another material (the
    /// interface's boundary layer), every material's strain increment and stress lose their
    /// shear on the plane of its interface (Youngs' normal of its fractions), so it neither
    /// resists nor heats by sliding past the other; normal stress and pressure still act.
    /// **Simplified:** the materials still share the nodes' velocity and move with it in the
    /// remap; the slip is released in the constitutive update only (docs/euler.md, "A rod that
    /// does not erode").
    pub sliding_interfaces: bool,
}

/// Cycles every run may take beyond its [`EulerSettings::cycle_budget`] multiple, so that a
/// run of a few cycles is not stopped by the rounding of its estimate.
pub const CYCLE_BUDGET_ALLOWANCE: u64 = 100;

impl Default for EulerSettings {
    fn default() -> Self {
        Self {
            courant: DEFAULT_COURANT,
            bulk_viscosity: BulkViscosity::default(),
            hourglass_coefficient: 0.1,
            threads: None,
            minimum_time_step: 1e-14,
            minimum_time_step_fraction: 1e-2,
            cycle_budget: 10.0,
            skip_far_void: true,
            sliding_interfaces: false,
        }
    }
}

/// A region of the initial state: where a material sits and how it moves.
pub struct Region<'a> {
    /// Index into the model's materials.
    pub material: usize,
    /// `true` for the points `(r, z)` inside it. Earlier regions win where two overlap.
    pub inside: &'a dyn Fn([f64; 2]) -> bool,
    /// Initial velocity `(v_r, v_z)` (m/s).
    pub velocity: [f64; 2],
    /// Initial temperature (K).
    pub temperature: f64,
}

/// A material of the model.
#[derive(Clone, Debug)]
pub struct EulerMaterial<P> {
    /// Name (for messages and output).
    pub name: String,
    /// The constitutive model (any kernel model).
    pub model: P,
    /// Void insertion (tensile failure on the grid, [`closure`]): the pressure (Pa, negative)
    /// below which the material does not stretch but void opens beside it, returning it to
    /// zero pressure (CTH's fracture pressure, with its default void pressure 0); `None`: the
    /// material carries whatever tension its model gives.
    pub fracture_pressure: Option<f64>,
}

/// The energy booked by an Eulerian run, per the whole body (J, 2 pi per radian).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EulerEnergy {
    /// Kinetic energy of the nodes.
    pub kinetic: f64,
    /// Internal energy of every material.
    pub internal: f64,
    /// Work of the bulk viscosity (dissipated, not added to the internal energy).
    pub viscous: f64,
    /// Work of the hourglass control.
    pub hourglass: f64,
    /// Kinetic energy lost by the remap of nodal momentum (its numerical dissipation).
    pub remap: f64,
    /// Total at the start.
    pub initial: f64,
    /// Work a [`CavityDrive`] did on the nodes it moves (J, the whole body).
    pub driven: f64,
}

impl EulerEnergy {
    /// Relative energy error `(K + I + viscous + hourglass + remap - initial - driven) /
    /// max(initial, driven)` (fixed walls do no work; a drive's work enters the body).
    pub fn relative_error(&self) -> f64 {
        (self.kinetic + self.internal + self.viscous + self.hourglass + self.remap
            - self.initial
            - self.driven)
            / self
                .initial
                .abs()
                .max(self.driven.abs())
                .max(f64::MIN_POSITIVE)
    }
}

/// A spherical cavity opened at a constant speed about a point of the axis: the nodes inside
/// the sphere of radius `a(t) = initial_radius + speed t` about `(0, center_z)` move with the
/// homologous field `v = speed (x - c) / a(t)` (the cavity-expansion verification problem,
/// Hill 1950; Forrestal & Luk 1988). What the drive adds to the nodes' kinetic energy is
/// booked as [`EulerEnergy::driven`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CavityDrive {
    /// `z` of the centre on the axis (m).
    pub center_z: f64,
    /// Radius at `t = 0` (m).
    pub initial_radius: f64,
    /// Expansion speed (m/s).
    pub speed: f64,
}

impl CavityDrive {
    /// The radius at time `t` (s).
    pub fn radius(&self, t: f64) -> f64 {
        self.initial_radius + self.speed * t
    }
}

/// The state of an Eulerian calculation.
#[derive(Clone, Debug)]
pub struct EulerSolver<P> {
    /// The grid (its lower-left corner at `(0, origin_z)`).
    pub grid: Grid,
    /// `z` of the grid's lowest edge (m).
    pub origin_z: f64,
    /// The edges.
    pub walls: Walls,
    /// The materials.
    pub materials: Vec<EulerMaterial<P>>,
    /// Settings.
    pub settings: EulerSettings,
    /// Phase volumes per cell (per radian in axisymmetric grids, per unit depth in planar
    /// ones), `cell * MAX_PHASES + phase`, void last (`MAX_PHASES - 1`).
    pub volume: Vec<f64>,
    /// Material masses per cell, `cell * MAX_MATERIALS + material`.
    pub mass: Vec<f64>,
    /// Material states per cell, `cell * MAX_MATERIALS + material`.
    pub state: Vec<MaterialState>,
    /// Each material's last longitudinal wave speed per cell (m/s).
    pub wave_speed: Vec<f64>,
    /// Bulk-viscosity pressure of each cell from the last step (Pa).
    pub viscous_pressure: Vec<f64>,
    /// The speed the bulk viscosity adds to each cell's stable-step formula, from the last
    /// step (m/s; [`BulkViscosity::time_step_speed`], 0 where the cell expands).
    pub viscous_speed: Vec<f64>,
    /// Nodal velocities `(v_r, v_z)`, node `(i, j)` at `j (cells_r + 1) + i`.
    pub velocity: Vec<[f64; 2]>,
    /// Time (s).
    pub time: f64,
    /// Cycles taken.
    pub cycles: u64,
    /// Energy booking.
    pub energy: EulerEnergy,
    /// A driven cavity (verification problems), applied after the walls every cycle.
    pub drive: Option<CavityDrive>,
    /// Material-cell updates done by the kernel (for performance figures).
    pub material_updates: u64,
    /// The first cycle's time step (s), the reference of the collapse floor.
    first_time_step: Option<f64>,
    /// Each node's light-mass threshold ([`Self::light_node_masses`]; fixed by the grid).
    light_mass: Vec<f64>,
    /// The remap's work buffers.
    workspace: remap::Workspace,
    /// Per row, the end of the columns this cycle works on ([`Self::active_columns`]).
    active_end: Vec<usize>,
}

impl<P: PointModel + Sync + Send + Clone> EulerSolver<P> {
    /// A solver on `grid` (lowest edge at `origin_z`) holding `regions` of `materials`,
    /// void elsewhere. Each cell's phase volumes are sampled on a 16 x 16 sub-grid
    /// (volume-weighted in `r`).
    pub fn new(
        grid: Grid,
        origin_z: f64,
        walls: Walls,
        materials: Vec<EulerMaterial<P>>,
        regions: &[Region<'_>],
        settings: EulerSettings,
    ) -> Result<Self, EulerError> {
        check_setup(&grid, origin_z, &materials, regions, &settings)?;
        let cells = grid.cell_count();
        let nodes = (grid.cells_r + 1) * (grid.cells_z + 1);
        let mut solver = Self {
            grid,
            origin_z,
            walls,
            settings,
            volume: vec![0.0; cells * MAX_PHASES],
            mass: vec![0.0; cells * MAX_MATERIALS],
            state: vec![MaterialState::initial(293.0); cells * MAX_MATERIALS],
            wave_speed: vec![0.0; cells * MAX_MATERIALS],
            viscous_pressure: vec![0.0; cells],
            viscous_speed: vec![0.0; cells],
            velocity: vec![[0.0; 2]; nodes],
            time: 0.0,
            cycles: 0,
            energy: EulerEnergy::default(),
            drive: None,
            material_updates: 0,
            first_time_step: None,
            light_mass: Vec::new(),
            workspace: remap::Workspace::default(),
            active_end: Vec::new(),
            materials,
        };
        solver.light_mass = solver.light_node_masses();
        solver.fill(regions)?;
        solver.energy.initial = solver.kinetic_energy() + solver.internal_energy();
        solver.energy.kinetic = solver.kinetic_energy();
        solver.energy.internal = solver.internal_energy();
        Ok(solver)
    }

    /// Number of nodes along `r`.
    pub fn nodes_r(&self) -> usize {
        self.grid.cells_r + 1
    }

    /// Whether the grid is axisymmetric.
    pub fn axisymmetric(&self) -> bool {
        self.grid.geometry == Geometry::Axisymmetric
    }

    /// The volume weight of radius `r`: `r` (axisymmetric, per radian) or 1 (planar).
    pub fn weight(&self, r: f64) -> f64 {
        if self.axisymmetric() {
            r
        } else {
            1.0
        }
    }

    /// Volume of a cell of column `i`.
    pub fn cell_volume(&self, i: usize) -> f64 {
        self.grid.spacing_r
            * self.grid.spacing_z
            * self.weight((i as f64 + 0.5) * self.grid.spacing_r)
    }

    /// Lower-left corner of cell `(i, j)`.
    pub fn corner(&self, i: usize, j: usize) -> [f64; 2] {
        [
            i as f64 * self.grid.spacing_r,
            self.origin_z + j as f64 * self.grid.spacing_z,
        ]
    }

    /// Volume fraction of `phase` in cell `c` (of the cell's current total).
    pub fn fraction(&self, c: usize, phase: usize) -> f64 {
        let v = &self.volume[c * MAX_PHASES..(c + 1) * MAX_PHASES];
        let total: f64 = v.iter().sum();
        if total > 0.0 {
            v[phase] / total
        } else {
            0.0
        }
    }

    /// Kinetic energy of the nodes (J, whole body).
    pub fn kinetic_energy(&self) -> f64 {
        let masses = self.node_masses();
        let sum = ordered_sum(masses.len(), |n| {
            let v = self.velocity[n];
            0.5 * masses[n] * (v[0] * v[0] + v[1] * v[1])
        });
        sum * self.body_factor()
    }

    /// Internal energy of every material (J, whole body).
    pub fn internal_energy(&self) -> f64 {
        let sum = ordered_sum(self.grid.cell_count(), |c| {
            let mut cell = 0.0;
            for (k, material) in self.materials.iter().enumerate() {
                let m = self.mass[c * MAX_MATERIALS + k];
                if m > 0.0 {
                    cell += m / material.model.density()
                        * self.state[c * MAX_MATERIALS + k].internal_energy;
                }
            }
            cell
        });
        sum * self.body_factor()
    }

    /// Total mass of `material` (kg, whole body).
    pub fn material_mass(&self, material: usize) -> f64 {
        (0..self.grid.cell_count())
            .map(|c| self.mass[c * MAX_MATERIALS + material])
            .sum::<f64>()
            * self.body_factor()
    }

    /// Total volume of `phase` (m^3, whole body).
    pub fn phase_volume(&self, phase: usize) -> f64 {
        (0..self.grid.cell_count())
            .map(|c| self.volume[c * MAX_PHASES + phase])
            .sum::<f64>()
            * self.body_factor()
    }

    /// Momentum of the nodes `(p_r, p_z)` (per radian or unit depth).
    pub fn momentum(&self) -> [f64; 2] {
        let masses = self.node_masses();
        let mut p = [0.0; 2];
        for (m, v) in masses.iter().zip(&self.velocity) {
            p[0] += m * v[0];
            p[1] += m * v[1];
        }
        p
    }

    /// `2 pi` for axisymmetric grids (quantities are kept per radian), 1 for planar ones.
    pub fn body_factor(&self) -> f64 {
        if self.axisymmetric() {
            2.0 * std::f64::consts::PI
        } else {
            1.0
        }
    }

    /// Each cell's total mass (zero, not summed, outside the cycle's work: [`in_work`]).
    pub fn cell_masses(&self) -> Vec<f64> {
        use rayon::prelude::*;
        let cells_r = self.grid.cells_r;
        self.mass
            .par_chunks(MAX_MATERIALS)
            .enumerate()
            .map(|(c, m)| {
                if cell_in_work(&self.active_end, cells_r, c) {
                    m.iter().sum()
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Lumped nodal masses: a quarter of each adjacent cell's mass.
    pub fn node_masses(&self) -> Vec<f64> {
        node_masses_of(&self.cell_masses(), self.grid.cells_r, self.grid.cells_z)
    }

    /// The mass below which each node counts as light: [`LIGHT_NODE_FRACTION`] of the mass
    /// its control volume would hold full of the densest material.
    pub fn light_node_masses(&self) -> Vec<f64> {
        use rayon::prelude::*;
        let nr = self.nodes_r();
        let (cells_r, cells_z) = (self.grid.cells_r, self.grid.cells_z);
        let densest = self
            .materials
            .iter()
            .map(|m| m.model.density())
            .fold(0.0, f64::max);
        (0..nr * (cells_z + 1))
            .into_par_iter()
            .map(|n| {
                let (i, j) = (n % nr, n / nr);
                let rows = [j.wrapping_sub(1), j]
                    .iter()
                    .filter(|&&r| r < cells_z)
                    .count();
                let volume: f64 = [i.wrapping_sub(1), i]
                    .iter()
                    .filter(|&&c| c < cells_r)
                    .map(|&c| self.cell_volume(c))
                    .sum::<f64>()
                    * rows as f64;
                LIGHT_NODE_FRACTION * 0.25 * volume * densest
            })
            .collect()
    }

    /// Phase volumes, masses, states and nodal velocities of the initial regions.
    fn fill(&mut self, regions: &[Region<'_>]) -> Result<(), EulerError> {
        const SUB: usize = 16;
        let (hr, hz) = (self.grid.spacing_r, self.grid.spacing_z);
        let cells_r = self.grid.cells_r;
        let nr = self.nodes_r();
        let mut momentum = vec![[0.0; 2]; self.velocity.len()];
        let mut node_mass = vec![0.0; self.velocity.len()];
        for j in 0..self.grid.cells_z {
            for i in 0..cells_r {
                let c = j * cells_r + i;
                let corner = self.corner(i, j);
                let mut share = [0.0; MAX_PHASES];
                let mut region_share = vec![0.0; regions.len()];
                for a in 0..SUB {
                    for b in 0..SUB {
                        let p = [
                            corner[0] + (a as f64 + 0.5) * hr / SUB as f64,
                            corner[1] + (b as f64 + 0.5) * hz / SUB as f64,
                        ];
                        let w = self.weight(p[0]);
                        match regions.iter().position(|region| (region.inside)(p)) {
                            Some(k) => {
                                share[regions[k].material] += w;
                                region_share[k] += w;
                            }
                            None => share[MAX_PHASES - 1] += w,
                        }
                    }
                }
                let total: f64 = share.iter().sum();
                let volume = self.cell_volume(i);
                for (phase, s) in share.iter().enumerate() {
                    self.volume[c * MAX_PHASES + phase] = volume * s / total;
                }
                let corners = [
                    j * nr + i,
                    j * nr + i + 1,
                    (j + 1) * nr + i,
                    (j + 1) * nr + i + 1,
                ];
                for (k, region) in regions.iter().enumerate() {
                    if region_share[k] == 0.0 {
                        continue;
                    }
                    let model = &self.materials[region.material].model;
                    let m = model.density() * volume * region_share[k] / total;
                    let slot = c * MAX_MATERIALS + region.material;
                    self.mass[slot] += m;
                    let mut state = model.initial_state(region.temperature);
                    state.relative_volume = 1.0;
                    self.state[slot] = state;
                    for &n in &corners {
                        node_mass[n] += 0.25 * m;
                        momentum[n][0] += 0.25 * m * region.velocity[0];
                        momentum[n][1] += 0.25 * m * region.velocity[1];
                    }
                }
                for k in 0..self.materials.len() {
                    let slot = c * MAX_MATERIALS + k;
                    if self.mass[slot] > 0.0 {
                        self.wave_speed[slot] =
                            rest_wave_speed(&self.materials[k], &self.state[slot])?;
                    }
                }
            }
        }
        for (n, v) in self.velocity.iter_mut().enumerate() {
            if node_mass[n] > 0.0 {
                *v = [momentum[n][0] / node_mass[n], momentum[n][1] / node_mass[n]];
            }
        }
        lagrange::apply_walls(self);
        Ok(())
    }

    /// Per row `j`, the end of the columns a cycle works on: every cell within
    /// [`ACTIVE_MARGIN`] cells (along `r` and `z`) of a cell holding material, and every
    /// column left of such a cell. Beyond it a row is void whose nodes have no mass, so no
    /// velocity and no swept volume: the cell loops leave those cells as they are, which is
    /// what their work would give them (pure void stays pure void, and the finishing pass
    /// still visits them). Every column when a cavity drive moves nodes of its own accord.
    fn active_columns(&self) -> Vec<usize> {
        use rayon::prelude::*;
        let (cells_r, rows) = (self.grid.cells_r, self.grid.cells_z);
        if self.drive.is_some() {
            return vec![cells_r; rows];
        }
        let last: Vec<usize> = (0..rows)
            .into_par_iter()
            .map(|j| {
                (0..cells_r)
                    .rev()
                    .find(|&i| {
                        let c = j * cells_r + i;
                        self.mass[c * MAX_MATERIALS..(c + 1) * MAX_MATERIALS]
                            .iter()
                            .any(|&m| m > 0.0)
                    })
                    .map_or(0, |i| (i + 1 + ACTIVE_MARGIN).min(cells_r))
            })
            .collect();
        (0..rows)
            .map(|j| {
                let (low, high) = (
                    j.saturating_sub(ACTIVE_MARGIN),
                    (j + ACTIVE_MARGIN).min(rows - 1),
                );
                last[low..=high].iter().copied().max().unwrap_or(0)
            })
            .collect()
    }

    /// Advance one cycle; returns the time step taken.
    pub fn step(&mut self) -> Result<f64, EulerError> {
        if self.settings.skip_far_void {
            self.active_end = self.active_columns();
        }
        let taken = self.step_in_work();
        // The bounds hold for this cycle only (the fields are public, and a caller may change
        // the state between cycles).
        self.active_end.clear();
        taken
    }

    /// [`Self::step`] within the cycle's [`Self::active_columns`].
    fn step_in_work(&mut self) -> Result<f64, EulerError> {
        let dt = self.stable_time_step();
        let first = match self.first_time_step {
            Some(first) => first,
            None if dt.is_finite() => *self.first_time_step.insert(dt),
            None => dt,
        };
        let usable = dt >= self.settings.minimum_time_step
            && dt >= self.settings.minimum_time_step_fraction * first;
        if !usable {
            return Err(EulerError::TimeStepCollapse {
                time: self.time,
                time_step: dt,
                first_time_step: first,
            });
        }
        let fluxes = lagrange::step(self, dt)?;
        remap::remap(self, &fluxes, dt);
        self.time += dt;
        self.cycles += 1;
        Ok(dt)
    }

    /// Bring the energy booking's kinetic and internal energies up to date and check that
    /// every cell and node is finite (done at each output, not each cycle: a non-finite value
    /// reaches the kernel, which refuses it, within a cycle).
    pub fn refresh(&mut self) -> Result<(), EulerError> {
        self.energy.kinetic = self.kinetic_energy();
        self.energy.internal = self.internal_energy();
        self.check_finite()
    }

    /// Carry the material over `dt` with the current nodal velocities held fixed: the remap
    /// alone, without forces or material updates (the kinematic advection tests of Rider &
    /// Kothe 1998). A cell's volume change (zero in a divergence-free field) goes to its void,
    /// or is spread over its materials in proportion to their volumes.
    pub fn advect(&mut self, dt: f64) {
        let fluxes = self.face_fluxes(dt);
        let cells_r = self.grid.cells_r;
        let nodes_r = self.nodes_r();
        for c in 0..self.grid.cell_count() {
            let (i, j) = (c % cells_r, c / cells_r);
            let change = fluxes.r[j * nodes_r + i + 1] - fluxes.r[j * nodes_r + i]
                + fluxes.z[(j + 1) * cells_r + i]
                - fluxes.z[j * cells_r + i];
            let volumes = &mut self.volume[c * MAX_PHASES..(c + 1) * MAX_PHASES];
            let total: f64 = volumes.iter().sum();
            if volumes[MAX_PHASES - 1] > 0.0 || total <= 0.0 {
                volumes[MAX_PHASES - 1] += change;
            } else {
                for v in volumes.iter_mut() {
                    *v *= 1.0 + change / total;
                }
            }
        }
        let velocity = self.velocity.clone();
        if self.settings.skip_far_void {
            self.active_end = self.active_columns();
        }
        remap::remap(self, &fluxes, dt);
        self.active_end.clear();
        self.velocity = velocity;
        self.time += dt;
        self.cycles += 1;
    }

    /// Run until `end_time`, calling `observe` after every cycle whose time crossed a
    /// multiple of `interval` (and at the start); `observe` may stop the run early.
    pub fn run(
        &mut self,
        end_time: f64,
        interval: f64,
        observe: &mut (dyn FnMut(&Self) -> std::ops::ControlFlow<()> + Send),
    ) -> Result<(), EulerError> {
        let most = crate::solver::explicit::MAXIMUM_THREADS;
        if let Some(threads) = self.settings.threads {
            if !(1..=most).contains(&threads) {
                return Err(EulerError::Setup(format!(
                    "threads must be in 1..={most}, got {threads}"
                )));
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.settings.threads.unwrap_or(0))
            .build()
            .map_err(|e| EulerError::Setup(format!("thread pool: {e}")))?;
        pool.install(|| {
            self.refresh()?;
            if observe(self).is_break() {
                return Ok(());
            }
            let mut next_output = interval;
            let (start_time, start_cycles) = (self.time, self.cycles);
            let mut budget: Option<u64> = None;
            while self.time < end_time {
                let time_step = self.step()?;
                let first = self.first_time_step.unwrap_or(time_step);
                let budget = *budget.get_or_insert_with(|| {
                    cycle_budget(self.settings.cycle_budget, end_time - start_time, first)
                });
                let cycles = self.cycles - start_cycles;
                if cycles > budget && self.time < end_time {
                    return Err(EulerError::CycleBudget {
                        time: self.time,
                        end_time,
                        cycles,
                        budget,
                        multiple: self.settings.cycle_budget,
                        first_time_step: first,
                        time_step,
                    });
                }
                if self.time >= next_output || self.time >= end_time {
                    while next_output <= self.time {
                        next_output += interval;
                    }
                    self.refresh()?;
                    if observe(self).is_break() {
                        break;
                    }
                }
            }
            Ok(())
        })
    }

    /// `courant * min(h) / (c' + |v|)` over cells holding material, with `c' = Q + sqrt(Q^2 +
    /// c^2)` where the cell compresses (`Q` the bulk viscosity's speed, LS-DYNA's stable-step
    /// form) and `c' = c` elsewhere.
    pub fn stable_time_step(&self) -> f64 {
        use rayon::prelude::*;
        let h = self.grid.spacing_r.min(self.grid.spacing_z);
        let cells_r = self.grid.cells_r;
        let nr = self.nodes_r();
        let masses = self.node_masses();
        let light = &self.light_mass;
        let largest = (0..self.grid.cell_count())
            .into_par_iter()
            .map(|c| {
                let (i, j) = (c % cells_r, c / cells_r);
                if !in_work(&self.active_end, i, j) {
                    return 0.0;
                }
                let mut c_max = 0.0_f64;
                for k in 0..self.materials.len() {
                    if self.mass[c * MAX_MATERIALS + k] > 0.0
                        && self.fraction(c, k) >= ACTIVE_FRACTION
                    {
                        c_max = c_max.max(self.wave_speed[c * MAX_MATERIALS + k]);
                    }
                }
                if c_max == 0.0 {
                    return 0.0;
                }
                // A compressing cell's bulk viscosity shortens its step as in the Lagrangian
                // solver, `L / (Q + sqrt(Q^2 + c^2))` (LS-DYNA's form; Q from the last step).
                let q = self.viscous_speed[c];
                if q > 0.0 {
                    c_max = BulkViscosity::signal_speed(q, c_max);
                }
                let mut v_max = 0.0_f64;
                for n in [
                    j * nr + i,
                    j * nr + i + 1,
                    (j + 1) * nr + i,
                    (j + 1) * nr + i + 1,
                ] {
                    if masses[n] < light[n] {
                        continue;
                    }
                    let v = self.velocity[n];
                    v_max = v_max.max(v[0].abs()).max(v[1].abs());
                }
                c_max + v_max
            })
            .reduce(|| 0.0, f64::max);
        if largest > 0.0 {
            self.settings.courant * h / largest
        } else {
            f64::INFINITY
        }
    }

    fn check_finite(&self) -> Result<(), EulerError> {
        use rayon::prelude::*;
        let cells_r = self.grid.cells_r;
        // The first non-finite cell in index order, whatever the threads.
        let first_bad = (0..self.grid.cell_count())
            .into_par_iter()
            .position_first(|c| {
                (0..self.materials.len()).any(|k| {
                    let s = &self.state[c * MAX_MATERIALS + k];
                    !(self.mass[c * MAX_MATERIALS + k].is_finite() && s.is_finite())
                }) || !self.volume[c * MAX_PHASES..(c + 1) * MAX_PHASES]
                    .iter()
                    .all(|v| v.is_finite())
            });
        if let Some(c) = first_bad {
            return Err(self.non_finite(c % cells_r, c / cells_r));
        }
        let nr = self.nodes_r();
        if let Some(n) = self
            .velocity
            .par_iter()
            .position_first(|v| !(v[0].is_finite() && v[1].is_finite()))
        {
            let (i, j) = (
                (n % nr).min(cells_r - 1),
                (n / nr).min(self.grid.cells_z - 1),
            );
            return Err(self.non_finite(i, j));
        }
        Ok(())
    }

    fn non_finite(&self, i: usize, j: usize) -> EulerError {
        let c = j * self.grid.cells_r + i;
        let names: Vec<&str> = self
            .materials
            .iter()
            .enumerate()
            .filter(|(k, _)| self.mass[c * MAX_MATERIALS + k] != 0.0)
            .map(|(_, m)| m.name.as_str())
            .collect();
        EulerError::NonFinite {
            i,
            j,
            materials: if names.is_empty() {
                "void".into()
            } else {
                names.join(", ")
            },
            time: self.time,
        }
    }
}

/// Most cycles of a run over `duration` whose first cycle's step is `first_time_step`:
/// `multiple` times the cycles at that step, plus [`CYCLE_BUDGET_ALLOWANCE`] (saturating:
/// an infinite or non-finite multiple gives no limit).
pub fn cycle_budget(multiple: f64, duration: f64, first_time_step: f64) -> u64 {
    let estimate = multiple * (duration / first_time_step).ceil();
    if estimate.is_finite() && estimate >= 0.0 && estimate < u64::MAX as f64 {
        (estimate.ceil() as u64).saturating_add(CYCLE_BUDGET_ALLOWANCE)
    } else {
        u64::MAX
    }
}

/// Lumped nodal masses of a `cells_r x cells_z` grid whose cells hold `cell_mass`: a quarter
/// of each adjacent cell's.
pub fn node_masses_of(cell_mass: &[f64], cells_r: usize, cells_z: usize) -> Vec<f64> {
    use rayon::prelude::*;
    let nodes_r = cells_r + 1;
    (0..nodes_r * (cells_z + 1))
        .into_par_iter()
        .map(|n| {
            let (i, j) = (n % nodes_r, n / nodes_r);
            let mut m = 0.0;
            for (ci, cj) in [
                (i.wrapping_sub(1), j.wrapping_sub(1)),
                (i, j.wrapping_sub(1)),
                (i.wrapping_sub(1), j),
                (i, j),
            ] {
                if ci < cells_r && cj < cells_z {
                    m += cell_mass[cj * cells_r + ci];
                }
            }
            0.25 * m
        })
        .collect()
}

/// The longitudinal wave speed of a material at rest in `state` (one zero-strain kernel
/// step).
fn rest_wave_speed<P: PointModel>(
    material: &EulerMaterial<P>,
    state: &MaterialState,
) -> Result<f64, EulerError> {
    let mut probe = *state;
    material
        .model
        .update(
            &mut probe,
            &StepInput {
                strain_increment: [0.0; 6],
                dt: 1e-9,
                relative_volume: state.relative_volume,
            },
        )
        .map(|output| output.wave_speed)
        .map_err(|error| EulerError::Update {
            material: material.name.clone(),
            i: 0,
            j: 0,
            r: 0.0,
            z: 0.0,
            time: 0.0,
            relative_volume: state.relative_volume,
            error,
        })
}

fn check_setup<P: PointModel>(
    grid: &Grid,
    origin_z: f64,
    materials: &[EulerMaterial<P>],
    regions: &[Region<'_>],
    settings: &EulerSettings,
) -> Result<(), EulerError> {
    let setup = |message: String| Err(EulerError::Setup(message));
    if grid.cells_r < 2 || grid.cells_z < 2 {
        return setup(format!(
            "the grid needs at least 2 x 2 cells (has {} x {})",
            grid.cells_r, grid.cells_z
        ));
    }
    let usable = |x: f64| x > 0.0 && x.is_finite();
    if !(usable(grid.spacing_r) && usable(grid.spacing_z) && origin_z.is_finite()) {
        return setup(format!(
            "cell sizes must be finite and positive (spacing_r {:e} m, spacing_z {:e} m)",
            grid.spacing_r, grid.spacing_z
        ));
    }
    if materials.is_empty() || materials.len() > MAX_MATERIALS {
        return setup(format!(
            "a model holds 1 to {MAX_MATERIALS} materials (has {})",
            materials.len()
        ));
    }
    for material in materials {
        material
            .model
            .validate()
            .map_err(|e| EulerError::Setup(format!("material {}: {e}", material.name)))?;
    }
    for region in regions {
        if region.material >= materials.len() {
            return setup(format!(
                "a region names material {} of {}",
                region.material,
                materials.len()
            ));
        }
        if !(region.velocity[0].is_finite() && region.velocity[1].is_finite()) {
            return setup("a region's velocity is not finite".into());
        }
        if !(region.temperature > 0.0 && region.temperature.is_finite()) {
            return setup(format!(
                "a region's temperature must be positive (is {} K)",
                region.temperature
            ));
        }
    }
    if !(settings.courant > 0.0 && settings.courant <= 1.0) {
        return setup(format!(
            "the Courant number must be in (0, 1] (is {})",
            settings.courant
        ));
    }
    if !(settings.hourglass_coefficient >= 0.0 && settings.hourglass_coefficient.is_finite()) {
        return setup("the hourglass coefficient must be finite and non-negative".into());
    }
    if settings.cycle_budget.is_nan() || settings.cycle_budget < 1.0 {
        return setup(format!(
            "the cycle budget must be at least 1 (times the cycles at the first step; is {})",
            settings.cycle_budget
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use stoss_kernel::Material;

    /// A block of the bundled HzB-W steel at 400 m/s towards the lower wall of a slip-walled
    /// grid of 20 x 30 cells of 1 mm.
    fn block(cycle_budget: f64) -> Result<EulerSolver<Material>, EulerError> {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/materials/hzb-w-jc.toml");
        let (_, steel) = crate::input::material::load(&path).unwrap();
        let inside = |p: [f64; 2]| p[0] < 6e-3 && (10e-3..20e-3).contains(&p[1]);
        EulerSolver::new(
            Grid {
                cells_r: 20,
                cells_z: 30,
                spacing_r: 1e-3,
                spacing_z: 1e-3,
                geometry: Geometry::Axisymmetric,
            },
            0.0,
            Walls {
                outer: Wall::Slip,
                bottom: Wall::Slip,
                top: Wall::Slip,
            },
            vec![EulerMaterial {
                name: "steel".into(),
                model: steel,
                fracture_pressure: None,
            }],
            &[Region {
                material: 0,
                inside: &inside,
                velocity: [0.0, -400.0],
                temperature: 293.0,
            }],
            EulerSettings {
                threads: Some(1),
                cycle_budget,
                ..EulerSettings::default()
            },
        )
    }

    #[test]
    fn a_run_over_its_cycle_budget_stops_with_a_typed_error_after_a_fixed_count() {
        // GOAL: a run that needs more cycles than its budget stops with `CycleBudget` at
        // the first cycle over it (a deterministic amount of work, whatever the machine);
        // a run within its budget is not stopped.
        // SETUP: a steel block moving in a closed grid, one cycle stepped by hand; the run
        // then believes its first step was ten times the present one (as a run whose step
        // has fallen tenfold sees it), and runs 300 present steps' worth of time.
        // REFERENCE: budget = multiple x ceil(duration / first step) + 100, counted from
        // the run's start: 1 x 30 + 100 = 130 cycles, so the 131st stops it; at the
        // default multiple (10) the budget is 400 and the run of about 300 cycles finishes.
        let probe = |multiple: f64| {
            let mut solver = block(multiple).unwrap();
            let dt = solver.step().unwrap();
            solver.first_time_step = Some(10.0 * dt);
            let end = solver.time + 300.0 * dt;
            let result = solver.run(end, end, &mut |_| std::ops::ControlFlow::Continue(()));
            (solver, result, end)
        };
        let (solver, result, end) = probe(1.0);
        match result {
            Err(EulerError::CycleBudget {
                cycles,
                budget,
                time,
                end_time,
                ..
            }) => {
                assert_eq!(budget, 130);
                assert_eq!(cycles, 131);
                assert_eq!(solver.cycles, 132, "the hand step and the run's 131");
                assert!(time < end_time && end_time == end);
            }
            other => panic!("expected the cycle budget to stop the run, got {other:?}"),
        }
        let (solver, result, end) = probe(10.0);
        result.expect("within its budget the run finishes");
        assert!(solver.time >= end);
        assert!(solver.cycles > 250, "{} cycles", solver.cycles);
    }

    #[test]
    fn the_cycle_budget_saturates_and_refuses_a_multiple_below_one() {
        // GOAL: an infinite multiple means no limit; a multiple below 1 (or NaN) is refused
        // at set-up, naming the field.
        assert_eq!(cycle_budget(f64::INFINITY, 1e-3, 1e-9), u64::MAX);
        assert_eq!(
            cycle_budget(2.0, 1e-6, 1e-8),
            2 * 100 + CYCLE_BUDGET_ALLOWANCE
        );
        for multiple in [0.5, f64::NAN] {
            let Err(error) = block(multiple) else {
                panic!("a cycle budget of {multiple} was accepted");
            };
            let error = error.to_string();
            assert!(error.contains("cycle budget"), "{error}");
        }
    }
}
