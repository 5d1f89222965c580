//! Near-field blast-bulged plate (seed 000 sec. 2.3/3.3): a clamped circular plate loaded by
//! the overpressure of a charge on its axis, computed once by the built-in Euler blast
//! solver ([`crate::blast`]) and cached; the plate's permanent deflection profile is
//! measured once the shape is steady.
//!
//! - **Plate:** 2D axisymmetric quads, `layers` through the thickness, `aspect_ratio` times
//!   as long radially (1, square, by default);
//!   the clamped annulus beyond `exposed_radius` is rigid, so it is not meshed: the nodes of
//!   the plate's edge at `exposed_radius` are fixed in `r` and `z` (a fully clamped rim
//!   without pull-in).
//! - **Load:** the loaded face is `z = 0`, the charge above it; the plate occupies
//!   `-thickness <= z <= 0`. The pressure is applied to the loaded face's segments, times the
//!   optional nuisance constant `impulse_scale`.
//! - **Settling:** nodal damping from `damping_start` (LS-DYNA `*DAMPING_GLOBAL`). The run
//!   stops at the first output at which, over the last [`BlastPlateSpec::steady_window`] (half
//!   the period of the flat plate's fundamental mode), the centre deflection varied by less
//!   than the steady tolerance ([`STEADY_FRACTION`] of the recording's smallest deflection
//!   uncertainty, or `steady_tolerance`) and the kinetic energy is below [`REST_FRACTION`] of
//!   the work the load did; at the latest at `end_time`, by default `damping_start` plus
//!   [`CAP_PERIODS`] fundamental periods. The domed plate is stiffer than the flat one (its
//!   membrane), so its damped ring-down crosses its final shape at least once in any such
//!   window: the window's range then bounds the distance to the final shape. A window far
//!   shorter than the period (the former fixed 0.1 ms) ends the run at a turning point of the
//!   ring-down, 1-1.6 % off the final deflection on seed 000's plates (docs/benchmarks.md,
//!   "End criteria").
//! - **Quantities:** `deflection` (m) of the rear face at `position` = radius (m), measured
//!   at the rear face's current radius; `peak_deflection` (m), the largest over the profile
//!   (`position` unused).

use crate::experiment::SummaryValue;
use std::ops::ControlFlow;
use std::path::PathBuf;

use super::{check_positive, default_temperature, Chart, ExperimentReport};
use super::{
    check_run_budget, check_run_budget_of, undeformed_time_step, Check, FieldOutput, Outcome,
    SimulationError,
};
use crate::blast::cache;
use crate::blast::near_field::{Air, Charge, EulerSettings, NearFieldBlast};
use crate::blast::record::WallRecorder;
use crate::figure::{Series, Style};
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::interpolate;
use crate::mesh::{Grading, QuadMesh};
use crate::solver::springback::{self, springback, SpringbackSettings};
use crate::solver::{
    shared, Amplitude, AxisymmetricModel, DampingStart, NodalDamping, PlasticSettle,
    PressureHistory, PressureLoad, SharedPressure, Snapshot, SolverError, SolverSettings,
    VelocityConstraint,
};
use serde::{Deserialize, Serialize};
use stoss_kernel::Material;

/// How often, per half period of the flat plate, the deformed plate's quiet time before the
/// springback is worked out again ([`BlastPlateSpec::deformed_quiet`]).
const QUIET_UPDATES: f64 = 8.0;

/// Quantities a blast-plate test records.
pub const QUANTITIES: &[&str] = &["deflection", "peak_deflection"];

/// The shape is steady when the centre deflection varies by less than this fraction of the
/// recording's smallest deflection uncertainty over the steady window.
pub const STEADY_FRACTION: f64 = 0.1;

/// Steady tolerance (m) of a run without a recorded deflection uncertainty (a tenth of a
/// 0.1 mm reading).
pub const DEFAULT_STEADY_TOLERANCE: f64 = 1.0e-5;

/// Default latest end of a run, in periods of the flat plate's fundamental mode after
/// `damping_start`.
pub const CAP_PERIODS: f64 = 3.0;

/// The plate has stopped yielding (`damping_after_yielding`) when its summed plastic strain
/// grew by at most this fraction of itself over the steady window: a plate that has shaken
/// down does not yield at all, and growth at this level moves the deflection by micrometres
/// ([`YIELDING_UNDER_DAMPING`], the same level).
pub const SHAKEDOWN_FRACTION: f64 = 1.0e-5;

/// Growth of the summed plastic strain after the damping started (over its final value)
/// above which the report warns that the damping acted on a yielding plate: on seed 000's
/// 37.5 g plate a growth of 0.19 % under the damping from 1 ms came with 1.9 mm more
/// permanent deflection than the plate left to stop yielding, so this level stands for about
/// 10 um, a tenth of a 0.1 mm reading.
pub const YIELDING_UNDER_DAMPING: f64 = 1.0e-5;

/// Plate wave speed `sqrt(E / (rho (1 - nu^2)))` (m/s) assumed by the run-size check, which runs
/// before the material is known: below that of steels, aluminium and titanium alloys
/// (5 000-5 500 m/s), so the estimated end is late.
pub const BUDGET_PLATE_SPEED: f64 = 4000.0;

/// The springback's Newton iterations stop when the largest correction is below this fraction
/// of the steady tolerance.
pub const SPRINGBACK_TOLERANCE_FRACTION: f64 = 1.0e-3;

/// Newton iterations the springback may take.
pub const SPRINGBACK_ITERATIONS: usize = 40;

/// Interval at which the run is observed (s).
pub const OBSERVATION_INTERVAL: f64 = 2.0e-6;

/// Time by which `fraction` of the impulse of `wall` on the disc `r <= radius` is delivered.
pub fn impulse_time(wall: &PressureHistory, radius: f64, fraction: f64) -> f64 {
    let rings = 200;
    let dr = radius / rings as f64;
    let force: Vec<f64> = (0..wall.values.len())
        .map(|k| {
            (0..rings)
                .map(|i| {
                    let r = (i as f64 + 0.5) * dr;
                    wall.at(r, (k as f64 + 0.5) * wall.interval) * r * dr
                })
                .sum::<f64>()
        })
        .collect();
    let total: f64 = force.iter().sum();
    let mut sum = 0.0;
    for (k, f) in force.iter().enumerate() {
        sum += f;
        if sum >= fraction * total {
            return (k + 1) as f64 * wall.interval;
        }
    }
    wall.duration()
}

/// Kinetic energy, as a fraction of the load's work, below which the plate may be at rest.
pub const REST_FRACTION: f64 = 1.0e-3;

fn default_layers() -> usize {
    8
}
fn default_damping_start() -> f64 {
    1.0e-3
}
fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}

/// How the blast load and the plate are coupled.
///
/// Two-way is the default: in the near field the plate moves further than the stand-off while
/// the load still acts (seed 000's 37.5 g at 13 mm: 19 mm by the time 95 % of the impulse is
/// delivered), and the rigid-wall load of a one-way run then over-predicts the impulse by 19 %
/// and the deflection by 31 % (docs/solver.md, "Blast load and the blast-bulged plate").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// The load is computed once on a rigid wall and cached (it does not depend on the
    /// plate's constants). Valid where the plate moves little while the load acts (far field).
    OneWay,
    /// The Euler calculation runs alongside the plate: every record interval the plate's
    /// loaded-face velocity becomes the wall velocity of the Euler grid (transpiration
    /// boundary, [`crate::blast::euler::EulerSolver::bottom_wall_velocity`]), so the plate's
    /// motion relieves the pressure on it. Recomputed for every simulation.
    #[default]
    TwoWay,
}

/// The Euler calculation of a two-way coupled run, kept ahead of the plate.
///
/// The gas runs ahead of the plate, so the wall velocity of each gas step is the plate's
/// loaded-face velocity extrapolated from the plate's last two observations to the middle of
/// the step (a linear predictor, as in the staggered coupling schemes of Piperno & Farhat
/// 2001). Holding the last observed velocity instead lagged the wall by about 1.5 records, a
/// first-order error: +1.2 % in the peak deflection of seed 000's coarse 37.5 g plate at
/// 0.25 us records, 0.02 % with the predictor (docs/solver.md, "The blast load's time step
/// and coupling").
struct CoupledLoad {
    euler: crate::blast::euler::EulerSolver,
    recorder: WallRecorder,
    /// Plate time (s) of the last observation.
    observed_at: f64,
    /// The loaded face's velocity (m/s) at each gas column at the last observation.
    wall_velocity: Vec<f64>,
    /// Its rate of change (m/s^2) between the last two observations.
    wall_acceleration: Vec<f64>,
    /// The last gas step (s), to place the next one's middle.
    last_step: f64,
    history: SharedPressure,
    interval: f64,
    records: usize,
    courant: f64,
    radii: Vec<f64>,
    exposed_radius: f64,
    seconds: f64,
}

impl CoupledLoad {
    fn new(spec: &BlastPlateSpec) -> Result<Self, SolverError> {
        let euler = spec
            .blast()
            .solver(spec.load_radius())
            .map_err(|e| SolverError::Model(e.to_string()))?;
        let radii: Vec<f64> = (0..euler.grid.cells_r)
            .map(|i| euler.grid.centre(i, 0).0)
            .collect();
        let interval = spec.euler.output_interval;
        Ok(Self {
            recorder: WallRecorder::new(&euler, interval, spec.air.pressure),
            observed_at: 0.0,
            wall_velocity: vec![0.0; radii.len()],
            wall_acceleration: vec![0.0; radii.len()],
            last_step: 0.0,
            history: shared(PressureHistory {
                radii: radii.clone(),
                interval,
                values: Vec::new(),
            }),
            euler,
            interval,
            records: libm::ceil(spec.euler.end_time / interval - 1e-9) as usize,
            courant: spec.euler.courant,
            radii,
            exposed_radius: spec.exposed_radius,
            seconds: 0.0,
        })
    }

    /// Step the Euler grid until it has formed `wanted` records, and append them.
    fn advance_to(&mut self, wanted: usize) -> Result<(), SolverError> {
        let clock = std::time::Instant::now();
        let mut rows = Vec::new();
        while self.recorder.made() < wanted {
            let ahead = self.euler.time + 0.5 * self.last_step - self.observed_at;
            for ((wall, &v), &a) in self
                .euler
                .bottom_wall_velocity
                .iter_mut()
                .zip(&self.wall_velocity)
                .zip(&self.wall_acceleration)
            {
                *wall = v + a * ahead;
            }
            let before = self.euler.time;
            self.recorder
                .step(&mut self.euler, self.courant, self.records, &mut |row| {
                    rows.push(row)
                })
                .map_err(|e| SolverError::Model(e.to_string()))?;
            self.last_step = self.euler.time - before;
        }
        self.history
            .write()
            .map_err(|_| SolverError::Model("the blast load's lock is poisoned".into()))?
            .values
            .append(&mut rows);
        self.seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// At plate time `time`, with the loaded face's nodes at initial radii `radii` moving at
    /// `velocities` (z) and `time_step` the plate's next step, update the predicted wall
    /// velocity and run the gas far enough ahead for every plate step until the next
    /// observation.
    ///
    /// The plate observes at least every record interval, and a step at `t` applies the
    /// records' mean over `[t - dt_previous/2, t + dt/2)`
    /// ([`PressureHistory::overlaps`]), so the records must reach `time + interval + dt/2`;
    /// they are run to `time + interval + 0.75 dt` (room for the step to grow by half),
    /// at least the next two records. A missing record would read as no load.
    fn follow(
        &mut self,
        time: f64,
        time_step: f64,
        radii: &[f64],
        velocities: &[f64],
    ) -> Result<(), SolverError> {
        let profile: Vec<(f64, f64)> = radii
            .iter()
            .copied()
            .zip(velocities.iter().copied())
            .collect();
        let elapsed = time - self.observed_at;
        for ((velocity, acceleration), &r) in self
            .wall_velocity
            .iter_mut()
            .zip(self.wall_acceleration.iter_mut())
            .zip(&self.radii)
        {
            let now = if r <= self.exposed_radius {
                interpolate(&profile, r)
            } else {
                0.0
            };
            *acceleration = if elapsed > 0.0 {
                (now - *velocity) / elapsed
            } else {
                0.0
            };
            *velocity = now;
        }
        self.observed_at = time;
        let reach = (time + self.interval + 0.75 * time_step) / self.interval;
        let wanted = (libm::ceil(reach - 1e-9) as usize)
            .max((time / self.interval) as usize + 2)
            .min(self.records);
        self.advance_to(wanted)
    }
}

/// Impulse of `wall` on the disc `r <= radius` (N s).
pub fn total_impulse(wall: &PressureHistory, radius: f64) -> f64 {
    let rings = 400;
    let dr = radius / rings as f64;
    (0..rings)
        .map(|i| {
            let r = (i as f64 + 0.5) * dr;
            wall.impulse(r) * 2.0 * std::f64::consts::PI * r * dr
        })
        .sum()
}

/// Geometry, load and discretisation of a blast-plate test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlastPlateSpec {
    /// Plate thickness (m).
    pub thickness: f64,
    /// Radius inside the clamp (m).
    pub exposed_radius: f64,
    /// Elements through the thickness (square elements; at least 4, 8 or more recommended).
    #[serde(default = "default_layers")]
    pub layers: usize,
    /// Radial length of the plate's elements over their length through the thickness (1:
    /// square elements). A calibration mesh may take 2: half the elements, a longer stable
    /// time step, and the deflection within the mesh error measured in docs/solver.md.
    #[serde(default = "one")]
    pub aspect_ratio: f64,
    /// Initial temperature (K).
    #[serde(default = "default_temperature")]
    pub temperature: f64,
    /// The charge.
    pub charge: Charge,
    /// The air.
    #[serde(default)]
    pub air: Air,
    /// The Euler grid of the load calculation (its radius defaults to the exposed radius
    /// plus 25 %).
    #[serde(default)]
    pub euler: EulerSettings,
    /// Two-way (default) or one-way (cached rigid-wall load) coupling.
    #[serde(default)]
    pub coupling: Coupling,
    /// Factor on the load (a nuisance constant for explosive and charge-shape differences).
    #[serde(default = "one")]
    pub impulse_scale: f64,
    /// Start of nodal damping (s); with `damping_after_yielding`, its earliest start.
    #[serde(default = "default_damping_start")]
    pub damping_start: f64,
    /// Start the damping only once the plate has stopped yielding (after `damping_start`):
    /// the summed plastic strain grew by at most [`SHAKEDOWN_FRACTION`] of itself over the
    /// steady window, at the latest [`CAP_PERIODS`] fundamental periods after
    /// `damping_start`. Off by default (seed 000's procedure: damping from 1 ms whatever the
    /// plate does). Damping that acts while the plate still yields in its rebound changes the
    /// permanent deflection it reads (docs/solver.md, "When the damping starts").
    #[serde(default)]
    pub damping_after_yielding: bool,
    /// Nodal damping coefficient (1/s); default twice the circular frequency of the clamped
    /// plate's fundamental mode, `2 (10.22/a^2) sqrt(D/(rho h))` (Leissa 1969).
    #[serde(default)]
    pub damping_coefficient: Option<f64>,
    /// Latest end of the run (s); default `damping_start` plus [`CAP_PERIODS`] periods of the
    /// plate's fundamental mode.
    #[serde(default)]
    pub end_time: Option<f64>,
    /// Range of the centre deflection over the steady window below which the shape is final
    /// (m); default [`STEADY_FRACTION`] of the recording's smallest deflection uncertainty.
    #[serde(default)]
    pub steady_tolerance: Option<f64>,
    /// Find the final shape by a static springback ([`crate::solver::springback`]) once the
    /// damped plate has gone [`BlastPlateSpec::springback_quiet`] without yielding (default);
    /// `false` runs the damped ring-down out to the steady criterion.
    #[serde(default = "yes")]
    pub springback: bool,
    /// Time the damped plate must go without any element yielding before the springback
    /// (s); default half the damped period of the deformed plate's slowest vibration
    /// ([`BlastPlateSpec::deformed_quiet`]), else the steady window
    /// ([`BlastPlateSpec::steady_window`], half the flat plate's fundamental period).
    #[serde(default)]
    pub springback_quiet: Option<f64>,
    /// Folder of the blast-load cache (relative to the experiment file); default
    /// [`cache::default_folder`].
    #[serde(default)]
    pub load_cache: Option<String>,
    /// The resolved cache folder (set when the experiment is loaded).
    #[serde(skip)]
    pub cache_folder: Option<PathBuf>,
}

/// A plate run: its measurement, the solver's run and the model it ran.
pub type PlateRun = (
    BlastPlateResult,
    crate::solver::AxisymmetricRun,
    AxisymmetricModel,
);

/// The plate's final shape and the run's figures.
#[derive(Clone, Debug)]
pub struct BlastPlateResult {
    /// Rear-face profile `(current radius, deflection)` (m), sorted by radius.
    pub profile: Vec<(f64, f64)>,
    /// Time at which the shape was read (s).
    pub settled_at: f64,
    /// Whether it was steady then (else the latest end was reached).
    pub steady: bool,
    /// Time from which the nodal damping acted (s; infinite if it never started).
    pub damping_from: f64,
    /// The latest time at which it could start (s).
    pub latest_damping_start: f64,
    /// Growth of the plate's summed plastic strain after the damping started, over its final
    /// value: above zero, the damping acted on a plate that still yielded, and the permanent
    /// deflection depends on when it started.
    pub plastic_after_damping: f64,
    /// Time by which 95 % of the load's impulse on the exposed plate is delivered (s).
    pub load_time: f64,
    /// Centre deflection at `load_time` (m): how far the plate had moved away from the rigid
    /// wall the load was computed on while the load acted (the one-way coupling's error
    /// measure).
    pub deflection_at_load_time: f64,
    /// Where a one-way load came from (`None`: computed with the plate, two-way) and the
    /// wall time the load took (s).
    pub load_source: (Option<cache::Source>, f64),
    /// Impulse the load delivered to the exposed plate (N s).
    pub load_impulse: f64,
    /// The static springback that found the final shape (`None`: the ring-down was run out).
    pub springback: Option<SpringbackFigures>,
}

/// How the static springback found a plate's final shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringbackFigures {
    /// End of the explicit run it started from (s).
    pub from: f64,
    /// The time the plate had gone without yielding then (s).
    pub quiet: f64,
    /// The circular frequency of the deformed plate's slowest vibration that set `quiet`
    /// (rad/s; `None`: the flat plate's period or `springback_quiet` set it).
    pub frequency: Option<f64>,
    /// Newton iterations.
    pub iterations: usize,
    /// The largest nodal displacement from the run's end to the final shape (m).
    pub displacement: f64,
    /// Kinetic and internal energy the ring-down would have dissipated, booked as damping (J).
    pub energy: f64,
}

impl BlastPlateResult {
    /// Deflection at radius `r`.
    pub fn deflection_at(&self, radius: f64) -> f64 {
        interpolate(&self.profile, radius)
    }

    /// Largest deflection.
    pub fn peak(&self) -> f64 {
        self.profile.iter().map(|p| p.1).fold(0.0, f64::max)
    }
}

impl BlastPlateSpec {
    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        check_positive(check, "thickness", self.thickness, "m")?;
        check_positive(check, "exposed_radius", self.exposed_radius, "m")?;
        check(
            "layers",
            (4..=40).contains(&self.layers),
            "must be in 4..=40 (elements through the thickness)",
        )?;
        check(
            "aspect_ratio",
            (1.0..=4.0).contains(&self.aspect_ratio),
            "must be in [1, 4] (radial over through-thickness element length)",
        )?;
        let elements = self.element_count();
        check(
            "layers",
            elements <= 2.0e5,
            &format!("gives {elements:.0} plate elements (limit 200000)"),
        )?;
        check_positive(check, "temperature", self.temperature, "K")?;
        check_positive(check, "impulse_scale", self.impulse_scale, "-")?;
        check_positive(check, "damping_start", self.damping_start, "s")?;
        if let Some(c) = self.damping_coefficient {
            check_positive(check, "damping_coefficient", c, "1/s")?;
        }
        if let Some(end_time) = self.end_time {
            check(
                "end_time",
                end_time > self.damping_start && end_time.is_finite(),
                "must exceed damping_start (s)",
            )?;
        }
        if let Some(tolerance) = self.steady_tolerance {
            check_positive(check, "steady_tolerance", tolerance, "m")?;
        }
        if let Some(quiet) = self.springback_quiet {
            check_positive(check, "springback_quiet", quiet, "s")?;
        }
        let time_step = self.plate_time_step();
        match self.end_time {
            Some(end_time) => check_run_budget(check, end_time, time_step, elements)?,
            None => check_run_budget_of(
                check,
                "exposed_radius",
                self.cap_at(BUDGET_PLATE_SPEED),
                time_step,
                elements,
            )?,
        }
        let blast = self.blast();
        if let Err(error) = blast.validate(self.load_radius()) {
            let (field, message) = match &error {
                crate::blast::near_field::BlastError::Invalid { field, reason } => {
                    (*field, reason.clone())
                }
                other => ("charge", other.to_string()),
            };
            return check(field, false, &message);
        }
        Ok(())
    }

    /// The near-field blast this plate sees.
    pub fn blast(&self) -> NearFieldBlast {
        NearFieldBlast {
            charge: self.charge,
            air: self.air,
            euler: self.euler,
        }
    }

    /// Radius the load must cover: the Euler grid's radius (default 1.25 x exposed radius).
    fn load_radius(&self) -> f64 {
        1.25 * self.exposed_radius
    }

    /// Elements along the radius (`aspect_ratio` times as long as they are thick).
    pub fn radial_elements(&self) -> usize {
        let size = self.aspect_ratio * self.thickness / self.layers as f64;
        ((self.exposed_radius / size).round() as usize).max(1)
    }

    /// Circular frequency of the flat clamped plate's fundamental mode (rad/s),
    /// `omega = (10.22 / a^2) sqrt(D / (rho h)) = (10.22 / a^2) h c_p / sqrt(12)` with the plate
    /// wave speed `c_p = sqrt(E / (rho (1 - nu^2)))` (Leissa 1969, table 2.1).
    fn fundamental_frequency(&self, plate_speed: f64) -> f64 {
        10.22 / (self.exposed_radius * self.exposed_radius) * self.thickness * plate_speed
            / libm::sqrt(12.0)
    }

    /// Period of the flat clamped plate's fundamental mode (s) at plate wave speed
    /// `plate_speed` (m/s).
    pub fn fundamental_period(&self, plate_speed: f64) -> f64 {
        2.0 * std::f64::consts::PI / self.fundamental_frequency(plate_speed)
    }

    /// The plate wave speed `sqrt(E / (rho (1 - nu^2)))` of `material` at its reference state
    /// (K = dp/dmu at mu = 0, E = 0).
    pub fn plate_speed(material: &Material) -> f64 {
        let (terms, _) = material.eos.evaluate(0.0, material.eos.initial_history());
        let bulk = terms.d_pressure_d_mu(0.0);
        let shear = material.shear_modulus;
        let modulus = 9.0 * bulk * shear / (3.0 * bulk + shear);
        let nu = (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear));
        libm::sqrt(modulus / (material.density * (1.0 - nu * nu)))
    }

    /// The nodal damping coefficient (1/s): `damping_coefficient`, else twice the fundamental
    /// mode's circular frequency.
    pub fn damping(&self, material: &Material) -> f64 {
        self.damping_coefficient
            .unwrap_or_else(|| 2.0 * self.fundamental_frequency(Self::plate_speed(material)))
    }

    /// The window over which the shape must be steady (s): half the flat plate's fundamental
    /// period `pi / omega`, lengthened by `c / (2 omega)` where the damping `c` exceeds the
    /// default `2 omega` (an over-damped plate creeps with time constant `c / omega^2`).
    pub fn steady_window(&self, material: &Material) -> f64 {
        let omega = self.fundamental_frequency(Self::plate_speed(material));
        std::f64::consts::PI / omega * (self.damping(material) / (2.0 * omega)).max(1.0)
    }

    /// The time the damped plate must go without yielding before the springback (s), where
    /// the deformed plate's own vibration is not known: `springback_quiet`, else the steady
    /// window. Half a period holds a turning point of the plate's slowest motion, where it is
    /// strained furthest from its final shape: a damped plate that passed one without
    /// yielding has smaller swings ahead of it. (An eighth of a period let the small test
    /// plate of tests/blast.rs yield again on its next swing.)
    pub fn springback_quiet(&self, material: &Material) -> f64 {
        self.springback_quiet
            .unwrap_or_else(|| self.steady_window(material))
    }

    /// The quiet time of the plate as it is at `time` (s), and the circular frequency of its
    /// slowest vibration (rad/s): half the damped period `pi / (omega sqrt(1 - zeta^2))`,
    /// `zeta = c / (2 omega)`, of the slowest free vibration about the deformed, stressed
    /// plate ([`springback::fundamental_frequency`]: the springback's own tangent, so its
    /// membrane and initial-stress stiffness, and the lumped masses) under the nodal damping
    /// `c`. The flat plate's period, which [`Self::springback_quiet`] takes, overstates a
    /// dished plate's several times: its membrane carries the bending. `None` where
    /// `springback_quiet` is given, where the slowest vibration is not found (a state that
    /// buckles), or where it is damped beyond `zeta = 1/sqrt(2)` (the damped period
    /// lengthens without bound towards critical damping): the caller keeps
    /// [`Self::springback_quiet`].
    pub fn deformed_quiet(
        &self,
        model: &AxisymmetricModel,
        material: &Material,
        snapshot: &Snapshot,
    ) -> Option<(f64, f64)> {
        if self.springback_quiet.is_some() {
            return None;
        }
        let omega = springback::fundamental_frequency(
            model,
            snapshot.positions,
            snapshot.states,
            snapshot.eroded,
            snapshot.time,
        )
        .ok()??;
        let zeta = self.damping(material) / (2.0 * omega);
        (zeta <= std::f64::consts::FRAC_1_SQRT_2).then(|| {
            (
                std::f64::consts::PI / (omega * libm::sqrt(1.0 - zeta * zeta)),
                omega,
            )
        })
    }

    /// The latest end of a run (s): `end_time`, else [`Self::cap_at`] the material's plate
    /// wave speed.
    pub fn latest_end(&self, material: &Material) -> f64 {
        self.end_time
            .unwrap_or_else(|| self.cap_at(Self::plate_speed(material)))
    }

    /// The default latest end at plate wave speed `plate_speed` (m/s): the latest damping
    /// start ([`Self::latest_damping_start`]) plus [`CAP_PERIODS`] fundamental periods.
    fn cap_at(&self, plate_speed: f64) -> f64 {
        self.latest_damping_start(plate_speed) + CAP_PERIODS * self.fundamental_period(plate_speed)
    }

    /// The latest damping start of a run with `material`: [`Self::latest_damping_start`], and
    /// no later than the run's latest end.
    fn damping_deadline(&self, material: &Material) -> f64 {
        self.latest_damping_start(Self::plate_speed(material))
            .min(self.latest_end(material))
    }

    /// The latest damping start at plate wave speed `plate_speed` (m/s): `damping_start`, or
    /// with `damping_after_yielding` [`CAP_PERIODS`] fundamental periods after it.
    fn latest_damping_start(&self, plate_speed: f64) -> f64 {
        if self.damping_after_yielding {
            self.damping_start + CAP_PERIODS * self.fundamental_period(plate_speed)
        } else {
            self.damping_start
        }
    }

    /// The stable time step of the undeformed plate at the fastest metal's wave speed (s),
    /// the step the run-size checks count with.
    fn plate_time_step(&self) -> f64 {
        undeformed_time_step(self.thickness / self.layers as f64, false)
    }

    /// The plate's element count.
    fn element_count(&self) -> f64 {
        self.radial_elements() as f64 * self.layers as f64
    }

    /// Refuse a run whose latest end for `material` needs more steps than the run budget
    /// allows. The check at load ([`Self::validate`]) had to assume a plate wave speed
    /// ([`BUDGET_PLATE_SPEED`]); a material whose plate is slower ends later, so the run is
    /// checked again with its own before anything is computed.
    fn check_run_size(&self, material: &Material) -> Result<(), SolverError> {
        let end = self.latest_end(material);
        let elements = self.element_count();
        let step = self.plate_time_step();
        if crate::input::implausible_allowed() || super::within_run_budget(end, step, elements) {
            return Ok(());
        }
        Err(SolverError::Model(format!(
            "the blast plate would run to {end:.3e} s (damping_start + {:.0} periods of its \
             fundamental mode at this material's plate wave speed, {:.0} m/s): {:.0} steps \
             of {elements:.0} elements, beyond the run budget; set `end_time`, check the units \
             of `exposed_radius` and `thickness`, or pass --force to run it anyway",
            if self.damping_after_yielding {
                2.0 * CAP_PERIODS
            } else {
                CAP_PERIODS
            },
            Self::plate_speed(material),
            end / step
        )))
    }

    /// The steady tolerance for `recording` (m): `steady_tolerance`, else [`STEADY_FRACTION`]
    /// of the recording's smallest positive deflection uncertainty, else
    /// [`DEFAULT_STEADY_TOLERANCE`].
    pub fn steady_tolerance(&self, recording: &[RecordedPoint]) -> f64 {
        self.steady_tolerance.unwrap_or_else(|| {
            let smallest = recording
                .iter()
                .filter(|p| QUANTITIES.contains(&p.quantity.as_str()) && p.uncertainty > 0.0)
                .map(|p| p.uncertainty)
                .fold(f64::INFINITY, f64::min);
            if smallest.is_finite() {
                STEADY_FRACTION * smallest
            } else {
                DEFAULT_STEADY_TOLERANCE
            }
        })
    }

    /// The wall load (from the cache or computed).
    pub fn load(&self) -> Result<cache::CachedLoad, SolverError> {
        let folder = self
            .cache_folder
            .clone()
            .unwrap_or_else(cache::default_folder);
        cache::load(&self.blast(), self.load_radius(), &folder, &mut |_| {})
            .map_err(|e| SolverError::Model(e.to_string()))
    }

    /// The finite-element model with `material` and the wall load `wall`.
    pub fn model(
        &self,
        material: &Material,
        settings: &SolverSettings,
        wall: SharedPressure,
    ) -> AxisymmetricModel {
        let nr = self.radial_elements();
        let mesh = QuadMesh::block(
            "plate",
            0,
            (0.0, self.exposed_radius),
            (-self.thickness, 0.0),
            nr,
            self.layers,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let axis = mesh.node_set("plate.axis").unwrap_or(&[]).to_vec();
        let rim = mesh.node_set("plate.outer").unwrap_or(&[]).to_vec();
        let top = mesh.node_set("plate.top").unwrap_or(&[]).to_vec();
        // Outer node first: the left normal of [outer, inner] on z = 0 points into the plate.
        let segments = top.windows(2).map(|w| [w[1], w[0]]).collect();
        let fixed = |nodes: &[usize], dof| VelocityConstraint {
            nodes: nodes.to_vec(),
            dof,
            velocity: Amplitude::constant(0.0),
        };
        // The rear-face elements (bottom row) are the tracked states.
        let tracked = (0..nr).step_by((nr / 20).max(1)).collect();
        AxisymmetricModel {
            mesh,
            materials: vec![*material],
            initial_temperature: self.temperature,
            initial_velocity: Vec::new(),
            constraints: vec![fixed(&axis, 0), fixed(&rim, 0), fixed(&rim, 1)],
            walls: Vec::new(),
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: vec![PressureLoad {
                segments,
                history: wall,
                scale: self.impulse_scale,
            }],
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time: self.latest_end(material),
                damping: Some(NodalDamping {
                    start_time: self.damping_start,
                    coefficient: self.damping(material),
                    start: if self.damping_after_yielding {
                        DampingStart::SettledAfter {
                            settle: PlasticSettle {
                                window: self.steady_window(material),
                                fraction: SHAKEDOWN_FRACTION,
                            },
                            latest: self.damping_deadline(material),
                        }
                    } else {
                        DampingStart::Fixed
                    },
                }),
                output_interval: OBSERVATION_INTERVAL,
                rest_fraction: 0.0,
                ..settings.clone()
            },
            tracked_elements: tracked,
        }
    }

    /// Run the plate to a steady shape at the tolerance of a run without a recording.
    pub fn run(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<PlateRun, SolverError> {
        self.run_to_tolerance(material, settings, self.steady_tolerance(&[]))
    }

    /// Run the plate until its centre deflection is steady to `tolerance` (m) (module
    /// documentation).
    pub fn run_to_tolerance(
        &self,
        material: &Material,
        settings: &SolverSettings,
        tolerance: f64,
    ) -> Result<PlateRun, SolverError> {
        self.check_run_size(material)?;
        let clock = std::time::Instant::now();
        let mut coupled = None;
        let (history, load_source) = match self.coupling {
            Coupling::OneWay => {
                let loaded = self.load()?;
                (
                    shared((*loaded.wall).clone()),
                    (Some(loaded.source), clock.elapsed().as_secs_f64()),
                )
            }
            Coupling::TwoWay => {
                let mut load = CoupledLoad::new(self)?;
                // Ahead of the plate's first step, with the plate at rest: the rule of
                // `follow` at time 0, with twice the up-front step estimate (which takes the
                // fastest metal's wave and a square element's length) for the step.
                load.follow(0.0, 2.0 * self.plate_time_step(), &[0.0], &[0.0])?;
                let history = load.history.clone();
                coupled = Some(load);
                (history, (None, 0.0))
            }
        };
        let mut model = self.model(material, settings, history.clone());
        if coupled.is_some() {
            model.settings.output_interval = self.euler.output_interval;
        }
        let rear = model.mesh.node_set("plate.bottom").unwrap_or(&[]).to_vec();
        let top = model.mesh.node_set("plate.top").unwrap_or(&[]).to_vec();
        let top_radii: Vec<f64> = top.iter().map(|&n| model.mesh.nodes[n][0]).collect();
        let centre = rear.first().copied().unwrap_or(0);
        let z0 = -self.thickness;
        let window = self.steady_window(material);
        // The summed plastic strain at the damping's start.
        let plastic_sum = |states: &[stoss_kernel::MaterialState]| -> f64 {
            states.iter().map(|s| s.plastic_strain).sum()
        };
        let mut plastic_at_damping: Option<f64> = None;
        let mut damping_from = f64::INFINITY;
        // The springback's start: the last observation at which the plastic sum grew, once
        // the plate has gone the quiet time since without yielding; the deformed plate's
        // quiet time is worked out again every QUIET_UPDATES-th of the flat plate's (the
        // moving plate's slowest vibration changes with its stresses: 1 531 rad/s at the
        // damping start on the coarse 57.5 g plate, 3 544 rad/s two milliseconds on).
        let flat_quiet = self.springback_quiet(material);
        let mut quiet = flat_quiet;
        let mut deformed: Option<(f64, f64)> = None;
        let mut quiet_found_at = f64::NEG_INFINITY;
        let mut last_plastic = f64::NEG_INFINITY;
        let mut last_yield = f64::NEG_INFINITY;
        let mut quiet_enough = false;
        let mut deflections: Vec<(f64, f64)> = Vec::new();
        let mut last_check = f64::NEG_INFINITY;
        let mut steady = false;
        let mut failure = None;
        let mut run = model.run_observed(&mut |snapshot| {
            if let Some(load) = coupled.as_mut() {
                let velocities: Vec<f64> = top.iter().map(|&n| snapshot.velocities[n][1]).collect();
                if let Err(error) =
                    load.follow(snapshot.time, snapshot.time_step, &top_radii, &velocities)
                {
                    failure = Some(error);
                    return ControlFlow::Break(());
                }
            }
            let deflection = z0 - snapshot.positions[centre][1];
            deflections.push((snapshot.time, deflection));
            if snapshot.time >= snapshot.damping_from && plastic_at_damping.is_none() {
                plastic_at_damping = Some(plastic_sum(snapshot.states));
                damping_from = snapshot.damping_from;
            }
            let damping_start = snapshot.damping_from;
            if self.springback {
                let plastic = plastic_sum(snapshot.states);
                if plastic > last_plastic {
                    last_yield = snapshot.time;
                    last_plastic = plastic;
                }
                if snapshot.time >= damping_start
                    && snapshot.time - quiet_found_at >= flat_quiet / QUIET_UPDATES
                {
                    quiet_found_at = snapshot.time;
                    deformed = self.deformed_quiet(&model, material, snapshot);
                    quiet = deformed.map_or(flat_quiet, |(window, _)| window);
                }
                if snapshot.time - last_yield.max(damping_start) >= quiet {
                    quiet_enough = true;
                    return ControlFlow::Break(());
                }
            }
            // Checked at most every OBSERVATION_INTERVAL (a coupled run observes far more
            // often), once the window lies after the damping start.
            let start = snapshot.time - window;
            let work = snapshot.energy.external_work.abs();
            if start > damping_start
                && snapshot.time >= last_check + OBSERVATION_INTERVAL
                && snapshot.energy.kinetic < REST_FRACTION * work
            {
                last_check = snapshot.time;
                // The window's outputs: from the last one at or before its start.
                let first = deflections.iter().rposition(|p| p.0 <= start).unwrap_or(0);
                let (low, high) = deflections[first..]
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p.1), hi.max(p.1))
                    });
                if high - low < tolerance {
                    steady = true;
                    return ControlFlow::Break(());
                }
            }
            ControlFlow::Continue(())
        })?;
        if let Some(error) = failure {
            return Err(error);
        }
        let springback = if quiet_enough {
            let found = springback(
                &model,
                &run,
                &SpringbackSettings {
                    tolerance: SPRINGBACK_TOLERANCE_FRACTION * tolerance,
                    iterations: SPRINGBACK_ITERATIONS,
                    pseudo_step: quiet,
                },
            )?;
            let figures = SpringbackFigures {
                from: run.final_time(),
                quiet,
                frequency: deformed.map(|(_, omega)| omega),
                iterations: found.iterations,
                displacement: found.displacement,
                energy: found.kinetic_discarded + found.internal_released,
            };
            let mut energy = run.energy();
            energy.kinetic = 0.0;
            energy.internal -= found.internal_released;
            energy.damping += figures.energy;
            run.energy_history.push(energy);
            run.positions = found.positions;
            run.states = found.states;
            run.velocities.iter_mut().for_each(|v| *v = [0.0; 3]);
            steady = true;
            Some(figures)
        } else {
            None
        };
        let load_seconds = match &coupled {
            Some(load) => load.seconds,
            None => load_source.1,
        };
        let wall = history
            .read()
            .map_err(|_| SolverError::Model("the blast load's lock is poisoned".into()))?
            .clone();
        let load_time = impulse_time(&wall, self.exposed_radius, 0.95);
        let deflection_at_load_time = interpolate(
            &deflections,
            load_time.min(deflections.last().map_or(0.0, |d| d.0)),
        );
        let mut profile: Vec<(f64, f64)> = rear
            .iter()
            .map(|&n| (run.positions[n][0], z0 - run.positions[n][1]))
            .collect();
        profile.sort_by(|a, b| a.0.total_cmp(&b.0));
        let settled_at = run.energy().time;
        let plastic_now = plastic_sum(&run.states);
        let plastic_after_damping = match plastic_at_damping {
            Some(at_start) if plastic_now > 0.0 => (plastic_now - at_start) / plastic_now,
            _ => 0.0,
        };
        Ok((
            BlastPlateResult {
                profile,
                settled_at,
                steady,
                damping_from,
                latest_damping_start: self.damping_deadline(material),
                plastic_after_damping,
                load_time,
                deflection_at_load_time,
                load_source: (load_source.0, load_seconds),
                load_impulse: total_impulse(&wall, self.exposed_radius) * self.impulse_scale,
                springback,
            },
            run,
            model,
        ))
    }

    pub(super) fn simulate(
        &self,
        material: &Material,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let (result, run, model) =
            self.run_to_tolerance(material, settings, self.steady_tolerance(recording))?;
        let predicted = recording
            .iter()
            .map(|point| match point.quantity.as_str() {
                "deflection" => result.deflection_at(point.position),
                "peak_deflection" => result.peak(),
                _ => f64::NAN,
            })
            .collect();
        let report = self.report(&result, recording, &run);
        Ok(Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("peak_deflection", result.peak(), "m"),
                SummaryValue::new("centre_deflection", result.deflection_at(0.0), "m"),
                SummaryValue::new("settled_at", result.settled_at, "s"),
                SummaryValue::new("settled", if result.steady { 1.0 } else { 0.0 }, "1"),
                SummaryValue::new("damping_from", result.damping_from, "s"),
                SummaryValue::new(
                    "plastic_strain_after_damping",
                    result.plastic_after_damping,
                    "1",
                ),
                SummaryValue::new("load_time", result.load_time, "s"),
                SummaryValue::new("load_impulse", result.load_impulse, "N s"),
                SummaryValue::new(
                    "centre_deflection_at_load_time",
                    result.deflection_at_load_time,
                    "m",
                ),
            ],
            energy: Some(run.energy()),
            states: run.tracked.clone(),
            element_cycles: run.element_cycles,
            report: Some(report),
            field: Some(FieldOutput {
                time: run.final_time(),
                mesh: model.mesh,
                positions: run.positions,
                states: run.states,
                cell_data: Vec::new(),
                eroded: run.eroded,
            }),
        })
    }

    /// The report's account of the damping: when it started, and whether the plate still
    /// yielded under it.
    fn damping_line(&self, result: &BlastPlateResult) -> String {
        if !result.damping_from.is_finite() {
            return "nodal damping never started\n".into();
        }
        let start = if !self.damping_after_yielding {
            "at damping_start"
        } else if result.damping_from >= result.latest_damping_start {
            "at the latest start: the plate had not stopped yielding by then"
        } else {
            "once the plate had stopped yielding"
        };
        let mut line = format!(
            "nodal damping from {:.3} ms ({start}); the plate's summed plastic strain grew by {:.4} % of its final value after that\n",
            result.damping_from * 1e3,
            result.plastic_after_damping * 100.0
        );
        if result.plastic_after_damping > YIELDING_UNDER_DAMPING {
            line.push_str(
                "  WARNING: the plate still yielded while the damping acted, so the permanent \
                 deflection depends on when the damping started (docs/solver.md, \"When the \
                 damping starts\"); `damping_after_yielding = true` waits until the plate has \
                 stopped yielding\n",
            );
        }
        line
    }

    fn report(
        &self,
        result: &BlastPlateResult,
        recording: &[RecordedPoint],
        run: &crate::solver::AxisymmetricRun,
    ) -> ExperimentReport {
        let mut text = String::new();
        let (radius, height) = self.charge.dimensions();
        text.push_str(&format!(
            "blast plate: {:.1} g charge ({:.1} mm x {:.2} mm), stand-off {:.1} mm; plate {:.1} mm, exposed radius {:.0} mm, {} x {} elements\n",
            self.charge.mass * 1e3,
            2.0 * radius * 1e3,
            height * 1e3,
            self.charge.standoff * 1e3,
            self.thickness * 1e3,
            self.exposed_radius * 1e3,
            self.radial_elements(),
            self.layers
        ));
        text.push_str(&format!(
            "load: {} in {:.2} s\nshape read at {:.2} ms ({})\nload impulse on the exposed plate {:.2} N s; 95 % of it delivered by {:.1} us, when the centre had moved {:.2} mm (stand-off {:.1} mm)\n",
            match result.load_source.0 {
                Some(cache::Source::Computed) => {
                    "one-way, computed by the Euler blast solver and cached"
                }
                Some(cache::Source::Disk) => "one-way, read from the cache",
                Some(cache::Source::Memory) => "one-way, reused from memory",
                None => "two-way, computed alongside the plate",
            },
            result.load_source.1,
            result.settled_at * 1e3,
            if result.steady {
                "steady"
            } else {
                "latest end reached, NOT steady"
            },
            result.load_impulse,
            result.load_time * 1e6,
            result.deflection_at_load_time * 1e3,
            self.charge.standoff * 1e3
        ));
        text.push_str(&self.damping_line(result));
        if let Some(found) = &result.springback {
            text.push_str(&format!(
                "final shape by static springback from {:.3} ms, once no element had yielded for {:.3} ms ({}): {} Newton iterations, largest displacement {:.3} mm, {:.1} J of the ring-down booked as damping\n",
                found.from * 1e3,
                found.quiet * 1e3,
                match found.frequency {
                    Some(omega) => format!(
                        "half the damped period of the deformed plate's slowest vibration, {:.1} Hz",
                        omega / (2.0 * std::f64::consts::PI)
                    ),
                    None => match self.springback_quiet {
                        Some(_) => "springback_quiet".to_string(),
                        None => "half the flat plate's fundamental period".to_string(),
                    },
                },
                found.iterations,
                found.displacement * 1e3,
                found.energy
            ));
        }
        text.push_str("  r (mm)   deflection (mm)   recorded (mm)\n");
        let radii = [
            0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 100.0, 120.0, 140.0,
            160.0, 180.0, 200.0,
        ];
        for r in radii {
            let r_m = r * 1e-3;
            if r_m > self.exposed_radius + 1e-12 {
                break;
            }
            let recorded = recording
                .iter()
                .find(|p| p.quantity == "deflection" && (p.position - r_m).abs() < 1e-6)
                .map_or(String::from("-"), |p| format!("{:.2}", p.value * 1e3));
            text.push_str(&format!(
                "  {r:6.1}   {:15.3}   {recorded:>13}\n",
                result.deflection_at(r_m) * 1e3
            ));
        }
        for p in recording.iter().filter(|p| p.quantity == "peak_deflection") {
            text.push_str(&format!(
                "  peak deflection {:.3} mm, recorded {:.2} +/- {:.2} mm\n",
                result.peak() * 1e3,
                p.value * 1e3,
                p.uncertainty * 1e3
            ));
        }
        text.push_str(&run.energy().report());
        text.push('\n');
        let mut series = vec![Series {
            errors: Vec::new(),
            label: "stoss".into(),
            points: result
                .profile
                .iter()
                .map(|(r, d)| (r * 1e3, d * 1e3))
                .collect(),
            style: Style::Line,
            colour: 0,
        }];
        let recorded: Vec<(f64, f64)> = recording
            .iter()
            .filter(|p| p.quantity == "deflection")
            .map(|p| (p.position * 1e3, p.value * 1e3))
            .chain(
                recording
                    .iter()
                    .filter(|p| p.quantity == "peak_deflection")
                    .map(|p| (0.0, p.value * 1e3)),
            )
            .collect();
        if !recorded.is_empty() {
            series.push(Series {
                errors: Vec::new(),
                label: "recorded".into(),
                points: recorded,
                style: Style::Markers,
                colour: 1,
            });
        }
        ExperimentReport {
            text,
            charts: vec![Chart {
                file: "deflection-profile.svg".into(),
                title: "Permanent deflection of the rear face".into(),
                x_label: "radius (mm)".into(),
                y_label: "deflection (mm)".into(),
                series,
            }],
            snapshots: Vec::new(),
            maps: Vec::new(),
            shot_fields: Vec::new(),
        }
    }
}
