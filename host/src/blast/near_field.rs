//! The near-field blast load on a plate: a charge on the plate's axis, detonated in air, its
//! products and air shock reflected by the plate taken as a rigid wall, computed with the
//! [`euler`](super::euler) solver on an axisymmetric grid. The result is the overpressure
//! history on the wall, a [`PressureHistory`].
//!
//! **One-way coupling.** The wall does not move, so the load does not depend on the plate's
//! constants and is computed once per charge and stand-off. This holds while the plate moves
//! little during the load: the pressure is over in tens of microseconds, while a 4 mm steel
//! plate bulges over about a millisecond (docs/solver.md, "Blast plate", measures the
//! plate's displacement at the end of the load).

use serde::{Deserialize, Serialize};
use stoss_kernel::eos::Jwl;

use super::euler::{
    Boundaries, Boundary, Conserved, EulerError, EulerSolver, Floors, Geometry, Grid, BURN_STEPS,
};
use super::fluid::Fluids;
use super::record::WallRecorder;
use crate::solver::PressureHistory;

/// The explosive's products.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Explosive {
    /// Composition C-4 ([`Jwl::C4`]). PE4, the UK's RDX plastic explosive (88 % RDX against
    /// C-4's 91 %), is modelled with it, as seed 000 did; a campaign may fit an impulse scale
    /// factor for the difference.
    C4,
    /// TNT ([`Jwl::TNT`]).
    Tnt,
}

impl Explosive {
    /// The JWL constants.
    pub fn jwl(self) -> Jwl {
        match self {
            Explosive::C4 => Jwl::C4,
            Explosive::Tnt => Jwl::TNT,
        }
    }
}

/// The charge's shape; its axis is the plate's axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChargeShape {
    /// A disc or cylinder of the given `diameter`, its flat face parallel to the plate; the
    /// height follows from the mass.
    Cylinder,
    /// A sphere; its diameter follows from the mass.
    Sphere,
}

/// Where the detonator is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Detonation {
    /// The centre of the face away from the plate (a detonator on top of a disc).
    #[default]
    FarFace,
    /// The charge's centre.
    Centre,
    /// The centre of the face nearest the plate.
    NearFace,
}

/// The charge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Charge {
    /// Explosive mass (kg).
    pub mass: f64,
    /// The explosive.
    pub explosive: Explosive,
    /// Its shape.
    pub shape: ChargeShape,
    /// Diameter of a cylindrical charge (m).
    #[serde(default)]
    pub diameter: Option<f64>,
    /// Stand-off: from the plate to the nearest point of the charge (m).
    pub standoff: f64,
    /// Detonator position.
    #[serde(default)]
    pub detonation: Detonation,
}

impl Charge {
    /// `(radius, height)` of the charge (m); a sphere's height is its diameter.
    pub fn dimensions(&self) -> (f64, f64) {
        let volume = self.mass / self.explosive.jwl().reference_density;
        match self.shape {
            ChargeShape::Cylinder => {
                let radius = 0.5 * self.diameter.unwrap_or(f64::NAN);
                (radius, volume / (core::f64::consts::PI * radius * radius))
            }
            ChargeShape::Sphere => {
                let radius = libm::cbrt(3.0 * volume / (4.0 * core::f64::consts::PI));
                (radius, 2.0 * radius)
            }
        }
    }

    /// The charge's smallest dimension (m): its diameter or its height.
    pub fn smallest_dimension(&self) -> f64 {
        let (radius, height) = self.dimensions();
        (2.0 * radius).min(height)
    }

    /// The largest grid cell (m) that puts [`MINIMUM_CELLS_ACROSS_CHARGE`] cells across the
    /// charge's smallest dimension, as the grid check computes it (rounded down until it does).
    pub fn largest_cell_size(&self) -> f64 {
        let smallest = self.smallest_dimension();
        let mut cell = smallest / MINIMUM_CELLS_ACROSS_CHARGE;
        while cell > 0.0 && smallest / cell < MINIMUM_CELLS_ACROSS_CHARGE {
            cell = cell.next_down();
        }
        cell
    }

    /// Whether the point `(r, z)` (plate at `z = 0`) is inside the charge.
    fn contains(&self, r: f64, z: f64) -> bool {
        let (radius, height) = self.dimensions();
        match self.shape {
            ChargeShape::Cylinder => {
                r <= radius && z >= self.standoff && z <= self.standoff + height
            }
            ChargeShape::Sphere => {
                let dz = z - (self.standoff + radius);
                r * r + dz * dz <= radius * radius
            }
        }
    }

    /// Height of the detonation point above the plate (m).
    fn detonation_height(&self) -> f64 {
        let (_, height) = self.dimensions();
        match self.detonation {
            Detonation::FarFace => self.standoff + height,
            Detonation::Centre => self.standoff + 0.5 * height,
            Detonation::NearFace => self.standoff,
        }
    }
}

/// The surrounding air, an ideal gas.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Air {
    /// Density (kg/m^3).
    pub density: f64,
    /// Pressure (Pa).
    pub pressure: f64,
    /// Ratio of specific heats.
    pub gamma: f64,
}

impl Default for Air {
    /// Sea-level standard air: 1.225 kg/m^3, 101.325 kPa, gamma 1.4.
    fn default() -> Self {
        Self {
            density: 1.225,
            pressure: 101_325.0,
            gamma: 1.4,
        }
    }
}

/// The Euler grid and run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EulerSettings {
    /// Square cell size (m).
    pub cell_size: f64,
    /// Radius of the grid (m); 0 takes the plate radius given to [`NearFieldBlast::solve`].
    pub radius: f64,
    /// Air above the charge's top (m).
    pub headroom: f64,
    /// Time to which the load is computed (s).
    pub end_time: f64,
    /// Interval of the recorded wall pressure (s).
    pub output_interval: f64,
    /// Courant number on `(|u| + c)/dr + (|v| + c)/dz`.
    pub courant: f64,
    /// Width of the programmed-burn front, in cells.
    pub burn_width: f64,
}

impl Default for EulerSettings {
    fn default() -> Self {
        Self {
            cell_size: 1.0e-3,
            radius: 0.0,
            headroom: 0.05,
            end_time: 2.0e-4,
            output_interval: 2.0e-7,
            courant: 0.6,
            burn_width: 2.0,
        }
    }
}

/// Cells across the charge's smallest dimension below which the grid is refused.
pub const MINIMUM_CELLS_ACROSS_CHARGE: f64 = 10.0;

/// Largest grid accepted (cells).
const MAXIMUM_CELLS: f64 = 2.0e7;

/// Largest number of Euler steps accepted (estimated at the detonation front's speed).
const MAXIMUM_STEPS: f64 = 1.0e6;

/// Largest estimated Euler run (cell-steps): about 45 minutes at the 7.5 M cell-steps/s
/// measured on 2 cores.
const MAXIMUM_CELL_STEPS: f64 = 2.0e10;

/// Largest recorded wall history (records times radial cells): 160 MB of pressures.
const MAXIMUM_RECORD_VALUES: f64 = 2.0e7;

/// A near-field blast: charge, air and grid.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NearFieldBlast {
    /// The charge.
    pub charge: Charge,
    /// The air.
    #[serde(default)]
    pub air: Air,
    /// The grid and run.
    #[serde(default)]
    pub euler: EulerSettings,
}

/// What a near-field blast calculation reports besides the wall pressure.
#[derive(Clone, Debug, PartialEq)]
pub struct BlastRun {
    /// The overpressure `p - p_ambient` on the wall `z = 0`, as interval means (its time
    /// integral is the impulse the Euler solver delivered).
    pub wall: PressureHistory,
    /// Euler steps taken.
    pub steps: usize,
    /// Grid cells.
    pub cells: usize,
    /// Cell updates performed.
    pub cell_updates: u64,
    /// Times a density or pressure floor was applied.
    pub floor_count: u64,
    /// Explosive energy on the grid at the start (J).
    pub explosive_energy: f64,
    /// Charge height (m).
    pub charge_height: f64,
}

/// Why a blast load could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlastError {
    /// A field is out of range (field name and reason).
    #[error("{field}: {reason}")]
    Invalid {
        /// The field.
        field: &'static str,
        /// Why.
        reason: String,
    },
    /// The Euler solver failed.
    #[error(transparent)]
    Euler(#[from] EulerError),
}

fn invalid(field: &'static str, reason: String) -> BlastError {
    BlastError::Invalid { field, reason }
}

fn positive(field: &'static str, value: f64) -> Result<(), BlastError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be positive and finite, got {value}"),
        ))
    }
}

/// Sub-cell samples per direction used to find the charge's volume fraction in a cell.
const SUBSAMPLES: usize = 8;

impl NearFieldBlast {
    /// Check every field; `plate_radius` is the radius the wall pressure must cover.
    pub fn validate(&self, plate_radius: f64) -> Result<(), BlastError> {
        let c = &self.charge;
        positive("charge.mass", c.mass)?;
        if !(c.standoff.is_finite()) || c.standoff < 0.0 {
            return Err(invalid(
                "charge.standoff",
                format!(
                    "must be zero or positive (the charge may not overlap the plate), got {}",
                    c.standoff
                ),
            ));
        }
        match (c.shape, c.diameter) {
            (ChargeShape::Cylinder, Some(diameter)) => positive("charge.diameter", diameter)?,
            (ChargeShape::Cylinder, None) => {
                return Err(invalid(
                    "charge.diameter",
                    "a cylindrical charge needs its diameter (m)".into(),
                ))
            }
            (ChargeShape::Sphere, Some(_)) => {
                return Err(invalid(
                    "charge.diameter",
                    "a sphere's diameter follows from its mass; remove it".into(),
                ))
            }
            (ChargeShape::Sphere, None) => {}
        }
        positive("air.density", self.air.density)?;
        positive("air.pressure", self.air.pressure)?;
        if !(self.air.gamma > 1.0 && self.air.gamma.is_finite()) {
            return Err(invalid(
                "air.gamma",
                format!("must exceed 1, got {}", self.air.gamma),
            ));
        }
        let e = &self.euler;
        positive("euler.cell_size", e.cell_size)?;
        positive("euler.end_time", e.end_time)?;
        positive("euler.output_interval", e.output_interval)?;
        positive("euler.headroom", e.headroom)?;
        positive("euler.burn_width", e.burn_width)?;
        if !(e.courant > 0.0 && e.courant <= 0.9) {
            return Err(invalid(
                "euler.courant",
                format!("must be in (0, 0.9], got {}", e.courant),
            ));
        }
        if !(e.radius >= 0.0 && e.radius.is_finite()) {
            return Err(invalid(
                "euler.radius",
                format!("must be zero or positive, got {}", e.radius),
            ));
        }
        let (radius, height) = c.dimensions();
        // The detonation must cross the charge well within the run, or the plate never sees
        // the whole load: a charge whose detonation alone outlasts `euler.end_time` is a mass
        // in the wrong unit (grams read as kilograms make a disc metres tall), not a test.
        let detonation = c.explosive.jwl().chapman_jouguet().detonation_velocity;
        let crossing = (2.0 * radius).max(height) / detonation;
        if crossing > e.end_time {
            return Err(invalid(
                "charge.mass",
                format!(
                    "{} kg makes a charge {:.3} m across and {:.3} m tall, which the detonation \
                     needs {crossing:.2e} s to cross, longer than the whole run \
                     (euler.end_time {:.2e} s): a mass in g written as kg?",
                    c.mass,
                    2.0 * radius,
                    height,
                    e.end_time
                ),
            ));
        }
        let smallest = c.smallest_dimension();
        let across = smallest / e.cell_size;
        if across < MINIMUM_CELLS_ACROSS_CHARGE {
            return Err(invalid(
                "euler.cell_size",
                format!(
                    "{:.3} mm gives {across:.1} cells across the charge's {:.2} mm; at least {MINIMUM_CELLS_ACROSS_CHARGE} are needed",
                    e.cell_size * 1e3,
                    smallest * 1e3
                ),
            ));
        }
        let grid_radius = self.grid_radius(plate_radius);
        if grid_radius < radius + 2.0 * e.cell_size {
            return Err(invalid(
                "euler.radius",
                format!("{grid_radius} m does not contain the charge (radius {radius} m)"),
            ));
        }
        let radial_cells = grid_radius / e.cell_size;
        let cells = radial_cells * ((c.standoff + height + e.headroom) / e.cell_size);
        if cells > MAXIMUM_CELLS {
            return Err(invalid(
                "euler.cell_size",
                format!("the grid would have {cells:.3e} cells (limit 2e7)"),
            ));
        }
        // The step is at most courant dx / (2 (|u| + c)); behind the detonation front
        // |u| + c is the detonation speed D, and the gas never outruns it much. While the
        // charge burns (until the front has crossed it, `2 r + h` at most, and the last cell
        // has burned) it is also at most the burn duration over `BURN_STEPS`.
        let speed = c.explosive.jwl().chapman_jouguet().detonation_velocity;
        let flow_steps = e.end_time / (e.courant * e.cell_size / (2.0 * speed));
        let burn_duration = e.burn_width * e.cell_size / speed;
        let burning = ((2.0 * radius + height) / speed + burn_duration).min(e.end_time);
        let burn_steps = burning / (burn_duration / BURN_STEPS);
        let steps = flow_steps + burn_steps;
        if steps > MAXIMUM_STEPS || steps * cells > MAXIMUM_CELL_STEPS {
            let field = if burn_steps > flow_steps {
                "euler.burn_width"
            } else {
                "euler.end_time"
            };
            return Err(invalid(
                field,
                format!(
                    "needs at least {steps:.0} steps of {cells:.0} cells ({:.1e} cell-steps, \
                     {burn_steps:.0} of the steps while the charge burns; at most \
                     {MAXIMUM_STEPS:.0} steps and {MAXIMUM_CELL_STEPS:.0e} cell-steps, about \
                     45 minutes on 2 cores): check the units (s) and the burn width (cells)",
                    steps * cells
                ),
            ));
        }
        let record_values = (e.end_time / e.output_interval) * radial_cells;
        if record_values > MAXIMUM_RECORD_VALUES {
            return Err(invalid(
                "euler.output_interval",
                format!(
                    "gives {:.0} records of {radial_cells:.0} wall pressures ({record_values:.1e} \
                     values, limit {MAXIMUM_RECORD_VALUES:.0e}): check the units (s)",
                    e.end_time / e.output_interval
                ),
            ));
        }
        Ok(())
    }

    fn grid_radius(&self, plate_radius: f64) -> f64 {
        if self.euler.radius > 0.0 {
            self.euler.radius
        } else {
            plate_radius
        }
    }

    /// Build the Euler solver: air at rest, the charge's cells filled by volume fraction
    /// (mass and energy exact to the sub-sampling), burn times from the detonation point at
    /// the JWL's detonation velocity.
    pub fn solver(&self, plate_radius: f64) -> Result<EulerSolver, BlastError> {
        self.validate(plate_radius)?;
        let e = &self.euler;
        let jwl = self.charge.explosive.jwl();
        let (_, height) = self.charge.dimensions();
        let grid_radius = self.grid_radius(plate_radius);
        let grid_height = self.charge.standoff + height + e.headroom;
        let grid = Grid {
            cells_r: libm::ceil(grid_radius / e.cell_size) as usize,
            cells_z: libm::ceil(grid_height / e.cell_size) as usize,
            spacing_r: e.cell_size,
            spacing_z: e.cell_size,
            geometry: Geometry::Axisymmetric,
        };
        let fluids = Fluids {
            products: jwl,
            air_gamma: self.air.gamma,
        };
        let air_energy = fluids.specific_energy(self.air.density, self.air.pressure, 0.0);
        let explosive_energy = jwl.detonation_energy / jwl.reference_density;
        let detonation = self.charge.detonation_height();
        let mut cells: Vec<Conserved> = Vec::with_capacity(grid.cell_count());
        let mut burn_time = Vec::with_capacity(grid.cell_count());
        for j in 0..grid.cells_z {
            for i in 0..grid.cells_r {
                let (r, z) = grid.centre(i, j);
                // Volume fraction of explosive, radius-weighted sub-samples.
                let (mut inside, mut total) = (0.0, 0.0);
                for a in 0..SUBSAMPLES {
                    for b in 0..SUBSAMPLES {
                        let sr = (i as f64 + (a as f64 + 0.5) / SUBSAMPLES as f64) * e.cell_size;
                        let sz = (j as f64 + (b as f64 + 0.5) / SUBSAMPLES as f64) * e.cell_size;
                        total += sr;
                        if self.charge.contains(sr, sz) {
                            inside += sr;
                        }
                    }
                }
                let fraction = inside / total;
                let explosive = fraction * jwl.reference_density;
                let air = (1.0 - fraction) * self.air.density;
                let rho = explosive + air;
                cells.push([
                    rho,
                    0.0,
                    0.0,
                    explosive * explosive_energy + air * air_energy,
                    explosive,
                ]);
                burn_time.push(if fraction > 0.0 {
                    libm::hypot(r, z - detonation) / jwl.detonation_velocity
                } else {
                    f64::NEG_INFINITY
                });
            }
        }
        let boundaries = Boundaries {
            inner: Boundary::Reflective,
            outer: Boundary::Transmissive,
            bottom: Boundary::Reflective,
            top: Boundary::Transmissive,
        };
        let floors = Floors {
            density: 1e-4 * self.air.density,
            pressure: 1e-4 * self.air.pressure,
        };
        Ok(EulerSolver::new(
            grid,
            boundaries,
            fluids,
            cells,
            burn_time,
            e.burn_width * e.cell_size / jwl.detonation_velocity,
            floors,
        )?)
    }

    /// Run the Euler calculation to `euler.end_time` and record the wall overpressure.
    /// `progress(time)` is called after every step.
    pub fn solve(
        &self,
        plate_radius: f64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<BlastRun, BlastError> {
        let mut solver = self.solver(plate_radius)?;
        let (_, explosive_energy) = {
            let jwl = self.charge.explosive.jwl();
            (
                0.0,
                self.charge.mass * jwl.detonation_energy / jwl.reference_density,
            )
        };
        let e = &self.euler;
        let records = libm::ceil(e.end_time / e.output_interval - 1e-9) as usize;
        let radii: Vec<f64> = (0..solver.grid.cells_r)
            .map(|i| solver.grid.centre(i, 0).0)
            .collect();
        let mut overpressure = Vec::with_capacity(records);
        let mut recorder = WallRecorder::new(&solver, e.output_interval, self.air.pressure);
        let mut cell_updates = 0u64;
        while recorder.made() < records {
            recorder.step(&mut solver, e.courant, records, &mut |row| {
                overpressure.push(row)
            })?;
            cell_updates += solver.grid.cell_count() as u64;
            progress(solver.time);
        }
        Ok(BlastRun {
            wall: PressureHistory {
                radii,
                interval: e.output_interval,
                values: overpressure,
            },
            steps: solver.steps,
            cells: solver.grid.cell_count(),
            cell_updates,
            floor_count: solver.floor_count,
            explosive_energy,
            charge_height: self.charge.dimensions().1,
        })
    }
}
