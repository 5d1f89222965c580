//! Second-order Godunov finite volumes for the compressible Euler equations on a uniform 2D
//! grid, planar `(x, y)` or axisymmetric `(r, z)`:
//!
//! - MUSCL-Hancock (Toro, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, 3rd ed.
//!   2009, sec. 14.4), unsplit: van Leer-limited slopes of the primitive variables
//!   `(rho, u, v, p, Y)`, a half-step predictor from the primitive equations (with the
//!   axisymmetric terms `-rho u/r` and `-rho c^2 u/r`), and the face states `W +- dW/2`;
//! - the HLLC approximate Riemann solver (Toro sec. 10.4, eqs. 10.37-10.39) with Davis's wave
//!   speed estimates (eq. 10.48), the products' mass fraction `Y` riding on the contact;
//! - axisymmetric fluxes weighted by the face radius and the source `p/r` in the radial
//!   momentum, written so that a uniform state at rest stays exactly at rest;
//! - reflective or transmissive (zero-gradient) boundaries through two ghost layers;
//! - cells of an explosive charge (burn fraction below 1) and cells whose reconstruction
//!   would give a non-positive density or pressure fall back to first order.
//!
//! Cells are updated in parallel by rows with no reductions other than exact maxima, so the
//! results do not depend on the thread count.

use rayon::prelude::*;

use super::fluid::Fluids;

/// The coordinate system of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// Cartesian `(x, y)`, unit depth.
    Planar,
    /// Cylindrical `(r, z)` with the axis at `r = 0`, per radian.
    Axisymmetric,
}

/// What a grid edge does to the flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// A rigid wall (or the symmetry axis): the normal velocity is mirrored.
    Reflective,
    /// Zero gradient: waves leave with little reflection.
    Transmissive,
}

/// A uniform grid of `cells_r x cells_z` cells whose lower-left corner is the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Cells along `r` (or `x`).
    pub cells_r: usize,
    /// Cells along `z` (or `y`).
    pub cells_z: usize,
    /// Cell size along `r` (m).
    pub spacing_r: f64,
    /// Cell size along `z` (m).
    pub spacing_z: f64,
    /// Planar or axisymmetric.
    pub geometry: Geometry,
}

impl Grid {
    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells_r * self.cells_z
    }

    /// Index of cell `(i, j)` (`i` along `r`).
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.cells_r + i
    }

    /// Centre of cell `(i, j)`.
    pub fn centre(&self, i: usize, j: usize) -> (f64, f64) {
        (
            (i as f64 + 0.5) * self.spacing_r,
            (j as f64 + 0.5) * self.spacing_z,
        )
    }

    /// Volume of a cell in column `i` (per radian when axisymmetric).
    pub fn cell_volume(&self, i: usize) -> f64 {
        let area = self.spacing_r * self.spacing_z;
        match self.geometry {
            Geometry::Planar => area,
            Geometry::Axisymmetric => area * (i as f64 + 0.5) * self.spacing_r,
        }
    }
}

/// The four edges of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Boundaries {
    /// `r = 0` (the axis when axisymmetric: must be reflective).
    pub inner: Boundary,
    /// `r = cells_r spacing_r`.
    pub outer: Boundary,
    /// `z = 0`.
    pub bottom: Boundary,
    /// `z = cells_z spacing_z`.
    pub top: Boundary,
}

/// Conserved variables of a cell: `[rho, rho u, rho v, E, rho Y]` with `E` the total energy per
/// unit volume and `Y` the products' mass fraction.
pub type Conserved = [f64; 5];

/// Why the Euler solver stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EulerError {
    /// The set-up is not valid (named field).
    #[error("blast solver set-up: {0}")]
    Setup(String),
    /// A cell's state became non-finite.
    #[error("blast solver: cell {cell} became non-finite at t = {time:.4e} s")]
    NonFinite {
        /// Cell index.
        cell: usize,
        /// Time (s).
        time: f64,
    },
}

/// A face state: `[rho, u, v, p, Y, E, c]`.
type Face = [f64; 7];
const RHO: usize = 0;
const P: usize = 3;
const Y: usize = 4;
const ENERGY: usize = 5;
const SOUND: usize = 6;

/// Ghost layers on each side.
const GHOSTS: usize = 2;

/// Floors that keep a cell physical in near-vacuum (counted in [`EulerSolver::floor_count`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floors {
    /// Smallest density (kg/m^3).
    pub density: f64,
    /// Smallest pressure (Pa).
    pub pressure: f64,
}

/// A cell is quiescent when it differs from the ambient state by at most this fraction: its
/// density and total energy relative to the ambient's, its momenta relative to the ambient
/// density times sound speed, its products' density relative to the ambient density. At
/// 101 kPa that is 1e-4 Pa of pressure.
pub const QUIESCENT_TOLERANCE: f64 = 1.0e-9;

/// Cells computed around the last cell that is not quiescent: a cell's update reads the cells
/// up to two away (the neighbours' reconstructions), and a disturbance spreads at most one
/// cell per step.
const ACTIVE_MARGIN: usize = 3;

/// The columns `lo <= i < hi` of one row that are computed (none when `lo >= hi`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Span {
    lo: usize,
    hi: usize,
}

impl Span {
    const EMPTY: Span = Span { lo: 0, hi: 0 };

    fn is_empty(self) -> bool {
        self.lo >= self.hi
    }

    /// The smallest span holding both.
    fn hull(self, other: Span) -> Span {
        match (self.is_empty(), other.is_empty()) {
            (true, _) => other,
            (_, true) => self,
            _ => Span {
                lo: self.lo.min(other.lo),
                hi: self.hi.max(other.hi),
            },
        }
    }
}

/// Every cell of `grid`, a span per row.
fn whole_spans(grid: &Grid) -> Vec<Span> {
    vec![
        Span {
            lo: 0,
            hi: grid.cells_r
        };
        grid.cells_z
    ]
}

/// `spans` (one per row of the `width`-column grid) grown by `margin` cells in every
/// direction, as spans of padded rows and columns (`GHOSTS` added; rows and columns outside
/// `[GHOSTS - limit, GHOSTS + n + limit)` dropped, so `limit = 0` keeps the interior and
/// `limit = 1` the first ghost layer).
fn grown(spans: &[Span], width: usize, margin: usize, limit: usize) -> Vec<Span> {
    let rows = spans.len();
    let mut padded = vec![Span::EMPTY; rows + 2 * GHOSTS];
    for (j, span) in spans.iter().enumerate() {
        if span.is_empty() {
            continue;
        }
        let widened = Span {
            lo: (GHOSTS + span.lo)
                .saturating_sub(margin)
                .max(GHOSTS - limit),
            hi: (GHOSTS + span.hi + margin).min(GHOSTS + width + limit),
        };
        let first = (GHOSTS + j).saturating_sub(margin).max(GHOSTS - limit);
        let last = (GHOSTS + j + margin).min(GHOSTS + rows + limit - 1);
        for row in &mut padded[first..=last] {
            *row = row.hull(widened);
        }
    }
    padded
}

/// The state of an Euler calculation and its work arrays.
#[derive(Clone, Debug)]
pub struct EulerSolver {
    /// The grid.
    pub grid: Grid,
    /// Its edges.
    pub boundaries: Boundaries,
    /// The fluids.
    pub fluids: Fluids,
    /// Conserved variables, `grid.index(i, j)` order.
    pub cells: Vec<Conserved>,
    /// Programmed-burn arrival time of each cell (s); `-inf` for cells without explosive.
    pub burn_time: Vec<f64>,
    /// Time over which a cell's burn fraction rises from 0 to 1 once the front arrives (s).
    pub burn_duration: f64,
    /// When the last cell of explosive has burned (s; `-inf` without explosive).
    burn_end: f64,
    /// The quiescent state (the initial state of the last cell, if it is air at rest), or
    /// `None` when every cell is computed every step.
    ambient: Option<(Conserved, [f64; 5])>,
    /// The cells computed each step, a span per row: every cell outside has been quiescent
    /// since the start, and so have the cells around it, so its update would leave it within
    /// [`QUIESCENT_TOLERANCE`] of where it is. The spans only grow.
    active: Vec<Span>,
    /// Whether the work arrays have been filled over the whole grid once (the first step),
    /// so that the quiescent cells' entries are in place.
    filled: bool,
    /// Floors.
    pub floors: Floors,
    /// Time (s).
    pub time: f64,
    /// Steps taken.
    pub steps: usize,
    /// How many times a floor was applied.
    pub floor_count: u64,
    /// Time integral of the normal momentum flux through each face of the bottom edge
    /// (Pa s, absolute pressure): the impulse per unit area delivered to a wall there.
    pub bottom_impulse: Vec<f64>,
    /// Normal (z) velocity of a reflective bottom edge in each column (m/s; 0 = fixed).
    /// A wall that moves this way is treated in the transpiration approximation: its
    /// velocity enters the Riemann problem at its fixed position `z = 0`, and gas crosses the
    /// edge at that velocity (Lesoinne & Farhat 1996).
    pub bottom_wall_velocity: Vec<f64>,
    // Work arrays over the padded grid.
    primitive: Vec<[f64; 5]>,
    sound: Vec<f64>,
    burn: Vec<f64>,
    faces: Vec<[Face; 4]>,
    predicted_pressure: Vec<f64>,
    flux_r: Vec<Conserved>,
    flux_z: Vec<Conserved>,
}

const WEST: usize = 0;
const EAST: usize = 1;
const SOUTH: usize = 2;
const NORTH: usize = 3;

/// Fewest steps per burn duration while any cell of the charge burns.
///
/// The stable step of a cell still unburned knows nothing of the pressure the burn is about
/// to release in it (its sound speed is that of a cold, pressureless solid), so without this
/// bound the first step after the detonation is as long as the air's stable step (about 1 us
/// on a 1.2 mm grid, four burn durations). The load then converges at first order in the
/// steps per burn: the 37.5 g, 13 mm shot's peak deflection (coarse plate, two-way) is
/// 27.46 / 27.39 / 27.30 / 27.28 / 27.26 mm at 1 / 7 / 20 / 40 / 80 steps per burn, against
/// 27.57 mm without the bound, so 20 steps is within 0.2 % of the limit (docs/solver.md,
/// "The blast load's time step and coupling").
pub const BURN_STEPS: f64 = 20.0;

/// van Leer's harmonic limiter of the one-sided differences `a` and `b`.
fn van_leer(a: f64, b: f64) -> f64 {
    if a * b > 0.0 {
        2.0 * a * b / (a + b)
    } else {
        0.0
    }
}

impl EulerSolver {
    /// A solver on `grid` with the given initial cells and burn times.
    pub fn new(
        grid: Grid,
        boundaries: Boundaries,
        fluids: Fluids,
        cells: Vec<Conserved>,
        burn_time: Vec<f64>,
        burn_duration: f64,
        floors: Floors,
    ) -> Result<Self, EulerError> {
        if grid.cells_r == 0 || grid.cells_z == 0 {
            return Err(EulerError::Setup(
                "the grid needs at least one cell in each direction".into(),
            ));
        }
        let size_ok = |h: f64| h > 0.0 && h.is_finite();
        if !(size_ok(grid.spacing_r) && size_ok(grid.spacing_z)) {
            return Err(EulerError::Setup("cell sizes must be positive".into()));
        }
        if grid.geometry == Geometry::Axisymmetric && boundaries.inner != Boundary::Reflective {
            return Err(EulerError::Setup(
                "the axis of an axisymmetric grid must be reflective".into(),
            ));
        }
        if cells.len() != grid.cell_count() || burn_time.len() != grid.cell_count() {
            return Err(EulerError::Setup(format!(
                "{} cells and {} burn times given for a grid of {} cells",
                cells.len(),
                burn_time.len(),
                grid.cell_count()
            )));
        }
        if fluids.air_gamma.is_nan() || fluids.air_gamma <= 1.0 {
            return Err(EulerError::Setup(format!(
                "air_gamma must exceed 1, got {}",
                fluids.air_gamma
            )));
        }
        fluids
            .products
            .validate()
            .map_err(|e| EulerError::Setup(format!("products JWL: {e}")))?;
        if burn_duration.is_nan() || burn_duration <= 0.0 {
            return Err(EulerError::Setup("burn duration must be positive".into()));
        }
        if !(floors.density > 0.0 && floors.pressure > 0.0) {
            return Err(EulerError::Setup("floors must be positive".into()));
        }
        for (k, cell) in cells.iter().enumerate() {
            if !cell.iter().all(|v| v.is_finite()) || cell[0] <= 0.0 {
                return Err(EulerError::Setup(format!(
                    "cell {k} has a non-positive density or a non-finite state"
                )));
            }
        }
        let padded = (grid.cells_r + 2 * GHOSTS) * (grid.cells_z + 2 * GHOSTS);
        let burn_end = burn_time
            .iter()
            .filter(|t| t.is_finite())
            .fold(f64::NEG_INFINITY, |end, &t| end.max(t + burn_duration));
        let last = cells[cells.len() - 1];
        let ambient = (burn_time[cells.len() - 1] == f64::NEG_INFINITY
            && last[1] == 0.0
            && last[2] == 0.0
            && last[4] == 0.0)
            .then(|| {
                let (_, c2) = fluids.state(last[0], last[3] / last[0], 0.0, 1.0);
                let momentum = last[0] * c2.sqrt();
                let t = QUIESCENT_TOLERANCE;
                (
                    last,
                    [
                        t * last[0],
                        t * momentum,
                        t * momentum,
                        t * last[3].abs(),
                        t * last[0],
                    ],
                )
            });
        let whole = whole_spans(&grid);
        Ok(Self {
            grid,
            boundaries,
            fluids,
            bottom_impulse: vec![0.0; grid.cells_r],
            bottom_wall_velocity: vec![0.0; grid.cells_r],
            cells,
            burn_time,
            burn_duration,
            burn_end,
            ambient,
            active: whole,
            filled: false,
            floors,
            time: 0.0,
            steps: 0,
            floor_count: 0,
            primitive: vec![[0.0; 5]; padded],
            sound: vec![0.0; padded],
            burn: vec![1.0; padded],
            faces: vec![[[0.0; 7]; 4]; padded],
            predicted_pressure: vec![0.0; padded],
            flux_r: vec![[0.0; 5]; (grid.cells_r + 1) * grid.cells_z],
            flux_z: vec![[0.0; 5]; grid.cells_r * (grid.cells_z + 1)],
        })
    }

    fn padded_width(&self) -> usize {
        self.grid.cells_r + 2 * GHOSTS
    }

    /// The spans of the cells computed this step (the whole grid until the work arrays are
    /// filled), grown by `margin` as [`grown`] does.
    fn computed(&self, margin: usize, limit: usize) -> Vec<Span> {
        let whole;
        let spans = if self.filled {
            &self.active
        } else {
            whole = whole_spans(&self.grid);
            &whole
        };
        grown(spans, self.grid.cells_r, margin, limit)
    }

    /// Whether some cell is outside the active spans.
    fn partly_active(&self) -> bool {
        self.filled
            && self
                .active
                .iter()
                .any(|s| s.lo > 0 || s.hi < self.grid.cells_r)
    }

    /// Grow the active spans around the cells that are no longer quiescent and the columns
    /// whose wall moves (after the first step, shrink them from the whole grid to those).
    fn update_active(&mut self) {
        let Some((ambient, bounds)) = self.ambient else {
            return;
        };
        let grid = self.grid;
        if !self.filled {
            self.filled = true;
            self.active = vec![Span::EMPTY; grid.cells_z];
            // Scan the whole grid this once.
            self.grow_active(&whole_spans(&grid), ambient, bounds);
        } else {
            let scan = self.active.clone();
            self.grow_active(&scan, ambient, bounds);
        }
    }

    fn grow_active(&mut self, scan: &[Span], ambient: Conserved, bounds: [f64; 5]) {
        let grid = self.grid;
        let mut disturbed = vec![Span::EMPTY; grid.cells_z];
        for (j, span) in scan.iter().enumerate() {
            for i in span.lo..span.hi {
                let k = grid.index(i, j);
                let cell = &self.cells[k];
                let quiet = self.burn_time[k] == f64::NEG_INFINITY
                    && (0..5).all(|q| (cell[q] - ambient[q]).abs() <= bounds[q]);
                if !quiet {
                    disturbed[j] = disturbed[j].hull(Span { lo: i, hi: i + 1 });
                }
            }
        }
        for (i, &wall) in self.bottom_wall_velocity.iter().enumerate() {
            if wall != 0.0 {
                disturbed[0] = disturbed[0].hull(Span { lo: i, hi: i + 1 });
            }
        }
        let around = grown(&disturbed, grid.cells_r, ACTIVE_MARGIN, 0);
        for (active, add) in self.active.iter_mut().zip(&around[GHOSTS..]) {
            if !add.is_empty() {
                *active = active.hull(Span {
                    lo: add.lo - GHOSTS,
                    hi: add.hi - GHOSTS,
                });
            }
        }
    }

    /// Burn fraction of cell `k` at time `t`.
    fn burn_fraction(&self, k: usize, t: f64) -> f64 {
        let arrival = self.burn_time[k];
        if arrival == f64::NEG_INFINITY {
            1.0
        } else {
            ((t - arrival) / self.burn_duration).clamp(0.0, 1.0)
        }
    }

    /// Primitive state `[rho, u, v, p, Y]`, pressure and sound speed of cell `k` now.
    pub fn cell_state(&self, k: usize) -> ([f64; 5], f64) {
        let burn = self.burn_fraction(k, self.time);
        self.primitive_of(&self.cells[k], burn)
    }

    fn primitive_of(&self, cell: &Conserved, burn: f64) -> ([f64; 5], f64) {
        let rho = cell[0];
        let u = cell[1] / rho;
        let v = cell[2] / rho;
        let y = (cell[4] / rho).clamp(0.0, 1.0);
        let e = cell[3] / rho - 0.5 * (u * u + v * v);
        let (p, c2) = self.fluids.state(rho, e, y, burn);
        ([rho, u, v, p, y], c2.sqrt())
    }

    /// Total mass and total energy on the grid (per radian when axisymmetric).
    pub fn totals(&self) -> (f64, f64) {
        let mut mass = 0.0;
        let mut energy = 0.0;
        for j in 0..self.grid.cells_z {
            for i in 0..self.grid.cells_r {
                let volume = self.grid.cell_volume(i);
                let cell = &self.cells[self.grid.index(i, j)];
                mass += cell[0] * volume;
                energy += cell[3] * volume;
            }
        }
        (mass, energy)
    }

    /// Fill the primitives of the interior and the ghost layers.
    fn fill_primitives(&mut self) {
        let grid = self.grid;
        let width = self.padded_width();
        let time = self.time;
        // The padded arrays are filled in place, a row per task (taken out of `self` while
        // the rows read the cells).
        let mut primitive = std::mem::take(&mut self.primitive);
        let mut sound = std::mem::take(&mut self.sound);
        let mut burn = std::mem::take(&mut self.burn);
        // Every cell the computed region's reconstructions read; the others are quiescent
        // and their entries stand from the first step.
        let spans = self.computed(GHOSTS, 0);
        let this = &*self;
        primitive
            .par_chunks_mut(width)
            .zip(sound.par_chunks_mut(width))
            .zip(burn.par_chunks_mut(width))
            .zip(&spans)
            .skip(GHOSTS)
            .take(grid.cells_z)
            .enumerate()
            .for_each(|(j, (((primitive, sound), burn), span))| {
                if span.is_empty() {
                    return;
                }
                for i in span.lo - GHOSTS..span.hi - GHOSTS {
                    let k = grid.index(i, j);
                    let fraction = this.burn_fraction(k, time);
                    let (w, c) = this.primitive_of(&this.cells[k], fraction);
                    primitive[i + GHOSTS] = w;
                    sound[i + GHOSTS] = c;
                    burn[i + GHOSTS] = fraction;
                }
            });
        self.primitive = primitive;
        self.sound = sound;
        self.burn = burn;
        // Ghosts along r for the interior rows, then along z for every padded column.
        let nr = grid.cells_r;
        let nz = grid.cells_z;
        for jp in GHOSTS..GHOSTS + nz {
            for g in 0..GHOSTS {
                let (ghost, source) = match self.boundaries.inner {
                    Boundary::Reflective => (GHOSTS - 1 - g, GHOSTS + g),
                    Boundary::Transmissive => (GHOSTS - 1 - g, GHOSTS),
                };
                self.copy_ghost(
                    jp * width + source,
                    jp * width + ghost,
                    1,
                    self.boundaries.inner,
                );
                let (ghost, source) = match self.boundaries.outer {
                    Boundary::Reflective => (GHOSTS + nr + g, GHOSTS + nr - 1 - g),
                    Boundary::Transmissive => (GHOSTS + nr + g, GHOSTS + nr - 1),
                };
                self.copy_ghost(
                    jp * width + source,
                    jp * width + ghost,
                    1,
                    self.boundaries.outer,
                );
            }
        }
        for ip in 0..width {
            for g in 0..GHOSTS {
                let (ghost, source) = match self.boundaries.bottom {
                    Boundary::Reflective => (GHOSTS - 1 - g, GHOSTS + g),
                    Boundary::Transmissive => (GHOSTS - 1 - g, GHOSTS),
                };
                self.copy_ghost(
                    source * width + ip,
                    ghost * width + ip,
                    2,
                    self.boundaries.bottom,
                );
                if self.boundaries.bottom == Boundary::Reflective {
                    // A moving wall: mirror the normal velocity about the wall's.
                    let column = ip.saturating_sub(GHOSTS).min(nr - 1);
                    self.primitive[ghost * width + ip][2] +=
                        2.0 * self.bottom_wall_velocity[column];
                }
                let (ghost, source) = match self.boundaries.top {
                    Boundary::Reflective => (GHOSTS + nz + g, GHOSTS + nz - 1 - g),
                    Boundary::Transmissive => (GHOSTS + nz + g, GHOSTS + nz - 1),
                };
                self.copy_ghost(
                    source * width + ip,
                    ghost * width + ip,
                    2,
                    self.boundaries.top,
                );
            }
        }
    }

    fn copy_ghost(&mut self, source: usize, ghost: usize, normal: usize, boundary: Boundary) {
        let mut w = self.primitive[source];
        if boundary == Boundary::Reflective {
            w[normal] = -w[normal];
        }
        self.primitive[ghost] = w;
        self.sound[ghost] = self.sound[source];
        self.burn[ghost] = self.burn[source];
    }

    /// Largest stable time step: `cfl / max((|u| + c)/dr + (|v| + c)/dz)` over the interior
    /// (over the cells whose primitives are fresh, and the ambient state for the quiescent
    /// rest).
    fn stable_time_step(&self, cfl: f64) -> f64 {
        let grid = self.grid;
        let width = self.padded_width();
        let spans = self.computed(GHOSTS, 0);
        let quiescent_rate = match self.ambient {
            Some((ambient, _)) if self.partly_active() => {
                let (w, c) = self.primitive_of(&ambient, 1.0);
                (w[1].abs() + c) / grid.spacing_r + (w[2].abs() + c) / grid.spacing_z
            }
            _ => 0.0,
        };
        let rate = (0..grid.cells_z)
            .into_par_iter()
            .map(|j| {
                let mut rate: f64 = 0.0;
                let span = spans[j + GHOSTS];
                for ip in span.lo..span.hi.max(span.lo) {
                    let at = (j + GHOSTS) * width + ip;
                    let w = self.primitive[at];
                    let c = self.sound[at];
                    rate = rate
                        .max((w[1].abs() + c) / grid.spacing_r + (w[2].abs() + c) / grid.spacing_z);
                }
                rate
            })
            .reduce(|| 0.0, f64::max)
            .max(quiescent_rate);
        cfl / rate
    }

    /// The face state of primitive `w` with burn fraction `burn`; `energy` (specific) is used
    /// when the cell is not fully burned.
    fn face(&self, w: [f64; 5], burn: f64, cell_energy: f64, cell_sound: f64) -> Face {
        let kinetic = 0.5 * w[0] * (w[1] * w[1] + w[2] * w[2]);
        if burn < 1.0 {
            return [
                w[0],
                w[1],
                w[2],
                w[3],
                w[4],
                w[0] * cell_energy + kinetic,
                cell_sound,
            ];
        }
        let (e, c2) = self.fluids.energy_and_sound_speed_squared(w[0], w[3], w[4]);
        [w[0], w[1], w[2], w[3], w[4], w[0] * e + kinetic, c2.sqrt()]
    }

    /// Slopes, half-step predictor and face states of every cell of the interior and of the
    /// first ghost layer.
    fn reconstruct(&mut self, dt: f64) {
        let grid = self.grid;
        let width = self.padded_width();
        let height = grid.cells_z + 2 * GHOSTS;
        let axisymmetric = grid.geometry == Geometry::Axisymmetric;
        let half = 0.5 * dt;
        // The computed cells and their neighbours (in padded indices; at the edges, the
        // first ghost layer).
        let spans = self.computed(1, 1);
        // The faces and predicted pressures are filled in place, a row per task (taken out of
        // `self` while the rows read the primitives).
        let mut faces = std::mem::take(&mut self.faces);
        let mut predicted_pressure = std::mem::take(&mut self.predicted_pressure);
        let this = &*self;
        faces
            .par_chunks_mut(width)
            .zip(predicted_pressure.par_chunks_mut(width))
            .zip(&spans)
            .enumerate()
            .skip(1)
            .take(height - 2)
            .for_each(|(jp, ((face_row, pressure_row), span))| {
                for ip in span.lo..span.hi.max(span.lo) {
                    let cell = || {
                        let at = jp * width + ip;
                        let w = this.primitive[at];
                        let c = this.sound[at];
                        let burn = this.burn[at];
                        let kinetic = 0.5 * (w[1] * w[1] + w[2] * w[2]);
                        let cell_energy = if burn < 1.0 {
                            // Specific internal energy straight from the conserved state.
                            let i = ip as isize - GHOSTS as isize;
                            let j = jp as isize - GHOSTS as isize;
                            let inside = i >= 0
                                && j >= 0
                                && (i as usize) < grid.cells_r
                                && (j as usize) < grid.cells_z;
                            if inside {
                                let cell = &this.cells[grid.index(i as usize, j as usize)];
                                cell[3] / cell[0] - kinetic
                            } else {
                                this.fluids
                                    .specific_energy(w[0], w[3] / burn.max(1e-300), w[4])
                            }
                        } else {
                            0.0
                        };
                        let first_order = |w: [f64; 5]| {
                            let face = this.face(w, burn, cell_energy, c);
                            ([face; 4], w[3])
                        };
                        if burn < 1.0 {
                            return first_order(w);
                        }
                        let mut dr = [0.0; 5];
                        let mut dz = [0.0; 5];
                        let west = this.primitive[at - 1];
                        let east = this.primitive[at + 1];
                        let south = this.primitive[at - width];
                        let north = this.primitive[at + width];
                        for q in 0..5 {
                            dr[q] = van_leer(w[q] - west[q], east[q] - w[q]);
                            dz[q] = van_leer(w[q] - south[q], north[q] - w[q]);
                        }
                        let (hr, hz) = (half / grid.spacing_r, half / grid.spacing_z);
                        let divergence_r = dr[1] * hr;
                        let divergence_z = dz[2] * hz;
                        let geometric = if axisymmetric {
                            let r = (ip as f64 - GHOSTS as f64 + 0.5) * grid.spacing_r;
                            half * w[1] / r
                        } else {
                            0.0
                        };
                        let rho_c2 = w[0] * c * c;
                        let predicted = [
                            w[0] - (w[1] * dr[0] * hr + w[2] * dz[0] * hz)
                                - w[0] * (divergence_r + divergence_z + geometric),
                            w[1] - (w[1] * dr[1] * hr + w[2] * dz[1] * hz) - dr[3] * hr / w[0],
                            w[2] - (w[1] * dr[2] * hr + w[2] * dz[2] * hz) - dz[3] * hz / w[0],
                            w[3] - (w[1] * dr[3] * hr + w[2] * dz[3] * hz)
                                - rho_c2 * (divergence_r + divergence_z + geometric),
                            w[4] - (w[1] * dr[4] * hr + w[2] * dz[4] * hz),
                        ];
                        let shifted = |slope: &[f64; 5], sign: f64| -> [f64; 5] {
                            let mut s = predicted;
                            for q in 0..5 {
                                s[q] += sign * 0.5 * slope[q];
                            }
                            s[4] = s[4].clamp(0.0, 1.0);
                            s
                        };
                        let states = [
                            shifted(&dr, -1.0),
                            shifted(&dr, 1.0),
                            shifted(&dz, -1.0),
                            shifted(&dz, 1.0),
                        ];
                        if states.iter().any(|s| !(s[RHO] > 0.0 && s[P] > 0.0)) {
                            return first_order(w);
                        }
                        let faces = states.map(|s| this.face(s, burn, 0.0, c));
                        if faces.iter().any(|f| !f.iter().all(|v| v.is_finite())) {
                            return first_order(w);
                        }
                        (faces, predicted[3])
                    };
                    (face_row[ip], pressure_row[ip]) = cell();
                }
            });
        self.faces = faces;
        self.predicted_pressure = predicted_pressure;
    }

    /// Fluxes through every face of the interior.
    fn fluxes(&mut self) {
        let grid = self.grid;
        let width = self.padded_width();
        let (nr, nz) = (grid.cells_r, grid.cells_z);
        let faces = &self.faces;
        let spans = &self.computed(0, 0)[GHOSTS..GHOSTS + nz];
        self.flux_r
            .par_chunks_mut(nr + 1)
            .zip(spans)
            .enumerate()
            .for_each(|(j, (row, span))| {
                if span.is_empty() {
                    return;
                }
                let jp = j + GHOSTS;
                for (f, flux) in row
                    .iter_mut()
                    .enumerate()
                    .take(span.hi - GHOSTS + 1)
                    .skip(span.lo - GHOSTS)
                {
                    // Face between cells i = f - 1 and i = f.
                    let left = &faces[jp * width + f + GHOSTS - 1][EAST];
                    let right = &faces[jp * width + f + GHOSTS][WEST];
                    *flux = hllc(left, right, 1);
                }
            });
        self.flux_z
            .par_chunks_mut(nr)
            .enumerate()
            .for_each(|(f, row)| {
                // Faces between rows j = f - 1 and j = f: those of the computed cells.
                let below = if f > 0 { spans[f - 1] } else { Span::EMPTY };
                let above = spans.get(f).copied().unwrap_or(Span::EMPTY);
                let span = below.hull(above);
                if span.is_empty() {
                    return;
                }
                for (i, flux) in row
                    .iter_mut()
                    .enumerate()
                    .take(span.hi - GHOSTS)
                    .skip(span.lo - GHOSTS)
                {
                    let ip = i + GHOSTS;
                    let below = &faces[(f + GHOSTS - 1) * width + ip][NORTH];
                    let above = &faces[(f + GHOSTS) * width + ip][SOUTH];
                    *flux = hllc(below, above, 2);
                }
            });
        debug_assert_eq!(self.flux_z.len(), nr * (nz + 1));
    }

    /// Advance one step of at most `max_dt`, with time step `cfl` times the stable one.
    /// Returns the step taken.
    pub fn step(&mut self, cfl: f64, max_dt: f64) -> Result<f64, EulerError> {
        if self.filled {
            self.update_active();
        }
        self.fill_primitives();
        let stable = self.stable_time_step(cfl);
        let dt = if self.time < self.burn_end {
            stable.min(self.burn_duration / BURN_STEPS)
        } else {
            stable
        }
        .min(max_dt);
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(EulerError::NonFinite {
                cell: 0,
                time: self.time,
            });
        }
        self.reconstruct(dt);
        self.fluxes();
        let grid = self.grid;
        let width = self.padded_width();
        let nr = grid.cells_r;
        let axisymmetric = grid.geometry == Geometry::Axisymmetric;
        let (spacing_r, spacing_z) = (grid.spacing_r, grid.spacing_z);
        let floors = self.floors;
        let flux_r = &self.flux_r;
        let flux_z = &self.flux_z;
        let predicted = &self.predicted_pressure;
        let fluids = self.fluids;
        let burn_time = &self.burn_time;
        let burn_duration = self.burn_duration;
        let time = self.time + dt;
        let spans = self.computed(0, 0);
        let spans = &spans[GHOSTS..GHOSTS + grid.cells_z];
        let floor_counts: Vec<u64> = self
            .cells
            .par_chunks_mut(nr)
            .zip(spans)
            .enumerate()
            .map(|(j, (row, span))| {
                let mut floored = 0;
                if span.is_empty() {
                    return floored;
                }
                for (i, cell) in row
                    .iter_mut()
                    .enumerate()
                    .take(span.hi - GHOSTS)
                    .skip(span.lo - GHOSTS)
                {
                    let (area_w, area_e, area_z, volume) = if axisymmetric {
                        let r = (i as f64 + 0.5) * spacing_r;
                        (
                            i as f64 * spacing_r * spacing_z,
                            (i as f64 + 1.0) * spacing_r * spacing_z,
                            r * spacing_r,
                            r * spacing_r * spacing_z,
                        )
                    } else {
                        (spacing_z, spacing_z, spacing_r, spacing_r * spacing_z)
                    };
                    let west = &flux_r[j * (nr + 1) + i];
                    let east = &flux_r[j * (nr + 1) + i + 1];
                    let south = &flux_z[j * nr + i];
                    let north = &flux_z[(j + 1) * nr + i];
                    for q in 0..5 {
                        // The radial momentum of an axisymmetric cell takes the source
                        // `p/r` as `p (A_e - A_w)/V` inside the flux difference, so that a
                        // uniform state at rest stays at rest to the bit: `F - p` vanishes on
                        // both faces (Toro 2009, sec. 17.2: the same balance, well-balanced).
                        let centre = if axisymmetric && q == 1 {
                            predicted[(j + GHOSTS) * width + i + GHOSTS]
                        } else {
                            0.0
                        };
                        cell[q] -= dt / volume
                            * ((east[q] - centre) * area_e - (west[q] - centre) * area_w
                                + (north[q] - south[q]) * area_z);
                    }
                    if cell[0] < floors.density {
                        cell[0] = floors.density;
                        floored += 1;
                    }
                    cell[4] = cell[4].clamp(0.0, cell[0]);
                    let arrival = burn_time[j * nr + i];
                    let burned = arrival == f64::NEG_INFINITY || time - arrival >= burn_duration;
                    if burned {
                        let rho = cell[0];
                        let kinetic = 0.5 * (cell[1] * cell[1] + cell[2] * cell[2]) / rho;
                        let y = cell[4] / rho;
                        let e = (cell[3] - kinetic) / rho;
                        let pressure = fluids.pressure(rho, e, y);
                        if pressure.is_nan() || pressure < floors.pressure {
                            let e = fluids.specific_energy(rho, floors.pressure, y);
                            cell[3] = rho * e + kinetic;
                            floored += 1;
                        }
                    }
                }
                floored
            })
            .collect();
        self.floor_count += floor_counts.iter().sum::<u64>();
        // The wall feels the pressure: the momentum flux less what the gas crossing the
        // (moving) wall carries, `F_rho_v - F_rho v_wall`.
        for ((impulse, flux), wall) in self
            .bottom_impulse
            .iter_mut()
            .zip(&self.flux_z[..nr])
            .zip(&self.bottom_wall_velocity)
        {
            *impulse += dt * (flux[2] - flux[0] * wall);
        }
        self.time += dt;
        self.steps += 1;
        for (j, span) in spans.iter().enumerate() {
            for i in span.lo.saturating_sub(GHOSTS)..span.hi.saturating_sub(GHOSTS) {
                let cell = grid.index(i, j);
                if !self.cells[cell].iter().all(|v| v.is_finite()) {
                    return Err(EulerError::NonFinite {
                        cell,
                        time: self.time,
                    });
                }
            }
        }
        if !self.filled {
            self.update_active();
        }
        Ok(dt)
    }
}

/// HLLC flux (Toro eqs. 10.37-10.39, Davis wave speeds eq. 10.48) through a face whose normal
/// is velocity component `normal` (1 = r, 2 = z) of the states `[rho, u, v, p, Y, E, c]`.
fn hllc(left: &Face, right: &Face, normal: usize) -> Conserved {
    let (ul, ur) = (left[normal], right[normal]);
    let sl = (ul - left[SOUND]).min(ur - right[SOUND]);
    let sr = (ul + left[SOUND]).max(ur + right[SOUND]);
    let physical = |s: &Face| -> Conserved {
        let un = s[normal];
        let mass = s[RHO] * un;
        let mut flux = [
            mass,
            mass * s[1],
            mass * s[2],
            (s[ENERGY] + s[P]) * un,
            mass * s[Y],
        ];
        flux[normal] += s[P];
        flux
    };
    if sl >= 0.0 {
        return physical(left);
    }
    if sr <= 0.0 {
        return physical(right);
    }
    let (rl, rr) = (left[RHO], right[RHO]);
    let s_star = (right[P] - left[P] + rl * ul * (sl - ul) - rr * ur * (sr - ur))
        / (rl * (sl - ul) - rr * (sr - ur));
    let star = |s: &Face, speed: f64| -> Conserved {
        let un = s[normal];
        let factor = s[RHO] * (speed - un) / (speed - s_star);
        let mut state = [
            factor,
            factor * s[1],
            factor * s[2],
            factor
                * (s[ENERGY] / s[RHO] + (s_star - un) * (s_star + s[P] / (s[RHO] * (speed - un)))),
            factor * s[Y],
        ];
        state[normal] = factor * s_star;
        state
    };
    let conserved = |s: &Face| -> Conserved {
        [
            s[RHO],
            s[RHO] * s[1],
            s[RHO] * s[2],
            s[ENERGY],
            s[RHO] * s[Y],
        ]
    };
    let (side, speed) = if s_star >= 0.0 {
        (left, sl)
    } else {
        (right, sr)
    };
    let flux = physical(side);
    let state = star(side, speed);
    let original = conserved(side);
    core::array::from_fn(|q| flux[q] + speed * (state[q] - original[q]))
}
