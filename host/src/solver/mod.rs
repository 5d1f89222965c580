//! Explicit central-difference dynamics.
//!
//! - lumped (row-sum) mass, CFL time step with a safety factor;
//! - 2D axisymmetric quads and 3D hexahedra, one-point integrated with Flanagan-Belytschko *viscous* hourglass control;
//! - linear + quadratic bulk viscosity (von Neumann-Richtmyer / Landshoff, LS-DYNA form);
//! - the **Jaumann** objective stress rate: the host rotates the stress with the spin of the
//!   step before the kernel updates it;
//! - the kernel is called per element (one integration point), in parallel with rayon; element
//!   results are assembled into nodes serially in element order, so results are bit-identical
//!   for any thread count;
//! - rigid planar walls (frictionless or Coulomb), fixed or moving with a mass (a drop weight), prescribed velocities, initial velocities,
//!   erosion on the kernel's flags, nodal damping, and an energy balance every run;
//! - penalty node-to-segment contact with Coulomb friction between deformable parts (2D);
//! - non-local averaging of the damage driver over a radius.

pub mod axisymmetric;
pub mod contact;
pub mod energy;
pub mod explicit;
pub mod hexahedral;
pub mod loads;
pub mod moving_wall;
pub mod nonlocal;
pub mod springback;
pub mod truss;

pub use axisymmetric::{AxisymmetricModel, AxisymmetricRun};
pub use contact::{ContactPair, ContactStatistics, ErodingContact, NodeToNodeContact, PartImpulse};
pub use energy::EnergyBalance;
pub use explicit::HourglassStress;
pub use explicit::{Discretisation, ExplicitModel, ExplicitRun, Snapshot};
pub use hexahedral::{HexModel, HexRun};
pub use loads::{
    shared, Amplitude, DampingStart, NodalDamping, PlasticSettle, PressureHistory, PressureLoad,
    RigidWall, SharedPressure, VelocityConstraint,
};
pub use moving_wall::{WallMotion, WallState};
pub use nonlocal::NonlocalAveraging;
use serde::{Deserialize, Serialize};
pub use truss::{Truss, TrussMaterial};

/// Default time-step safety factor: LS-DYNA's TSSFAC and OpenRadioss' /DT default, 0.9.
pub const DEFAULT_TIME_STEP_SAFETY: f64 = 0.9;

/// Largest time-step safety factor of a model with an eroding contact, 0.67 (the value the
/// LS-DYNA manual recommends for high-velocity and explosive problems). The eroding contact's
/// penalty bound counts on it: see [`contact::DEFAULT_ERODING_PENALTY_SCALE`].
pub const ERODING_CONTACT_TIME_STEP_SAFETY: f64 = 0.67;

/// Flanagan-Belytschko hourglass control of the one-point elements (Int. J. Numer. Meth. Eng.
/// 17 (1981) 679-706), with `gamma` the hourglass shape vectors orthogonal to the linear
/// field and `q = sum_k gamma_k v_k` the hourglass velocity of a mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HourglassControl {
    /// Viscous form (LS-DYNA `IHQ = 1`): `f_k = -kappa q gamma_k`, `kappa = QH rho c l^2 / 4`
    /// (per radian: `l^2 = A r_bar / sqrt(A)`). Resists the hourglass *rate* only: a mode
    /// excited slowly, as under a punch, accumulates without a restoring force.
    #[default]
    Viscous,
    /// Stiffness form (LS-DYNA `IHQ = 4`; 2D quads only): each mode carries a force `Q`,
    /// incremented by `dQ = QH rho c^2 V sum_k |b_k|^2 q dt` (a fraction `QH` of the element's
    /// elastic stiffness on that mode) and turned with the element's spin; `f_k = -Q gamma_k`.
    /// Its work is stored, not dissipated. It keeps the target out of a blunt penetrator whose
    /// contact the viscous form loses, but, being elastic, it adds strength to plastic flow in
    /// proportion to `QH` (docs/solver.md, "Hourglass control under a penetrator").
    Stiffness,
}

/// Linear and quadratic bulk viscosity (von Neumann-Richtmyer / Landshoff), in the form LS-DYNA
/// (`*CONTROL_BULK_VISCOSITY` Q1, Q2) and Autodyn (quadratic and linear viscosity) share:
/// `q = rho L (C0 L d_v^2 - C1 c d_v)` while compressing (`d_v < 0`), else 0, with `L` the
/// element length, `c` the wave speed and `d_v` the volumetric strain rate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BulkViscosity {
    /// Quadratic coefficient `C0` (LS-DYNA Q1, default 1.5; Autodyn's default 1.0).
    pub quadratic: f64,
    /// Linear coefficient `C1` (LS-DYNA Q2, default 0.06; Autodyn's default 0.2).
    pub linear: f64,
}

impl Default for BulkViscosity {
    /// LS-DYNA's defaults, Q1 = 1.5 and Q2 = 0.06.
    fn default() -> Self {
        Self {
            quadratic: 1.5,
            linear: 0.06,
        }
    }
}

impl BulkViscosity {
    /// The viscous pressure `q = rho L (C0 L d_v^2 - C1 c d_v)` for `d_v < 0`, else 0.
    pub fn pressure(
        &self,
        density: f64,
        length: f64,
        volumetric_rate: f64,
        wave_speed: f64,
    ) -> f64 {
        if volumetric_rate < 0.0 {
            density
                * length
                * (self.quadratic * length * volumetric_rate * volumetric_rate
                    - self.linear * wave_speed * volumetric_rate)
        } else {
            0.0
        }
    }

    /// The stable step of a compressing element over the inviscid one, from the linear term
    /// alone: `1 / (C1 + sqrt(C1^2 + 1))` (the quadratic term shortens it further with the
    /// strain rate).
    pub fn linear_step_factor(&self) -> f64 {
        1.0 / (self.linear + (self.linear * self.linear + 1.0).sqrt())
    }

    /// The speed that sets the stable step `L / (Q + sqrt(Q^2 + c^2))` of an element with wave
    /// speed `c` and viscous speed `Q` ([`Self::time_step_speed`]; LS-DYNA's form).
    pub fn signal_speed(viscous_speed: f64, wave_speed: f64) -> f64 {
        viscous_speed + (viscous_speed * viscous_speed + wave_speed * wave_speed).sqrt()
    }

    /// The speed the viscosity adds to the stable-step formula, `Q = C1 c + C0 L |d_v|` while
    /// compressing, else 0 (LS-DYNA's form).
    pub fn time_step_speed(&self, length: f64, wave_speed: f64, volumetric_rate: f64) -> f64 {
        if volumetric_rate < 0.0 {
            self.linear * wave_speed + self.quadratic * length * volumetric_rate.abs()
        } else {
            0.0
        }
    }
}

/// Numerical settings of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverSettings {
    /// End time (s).
    pub end_time: f64,
    /// Time-step safety factor on the CFL limit (LS-DYNA's TSSFAC, OpenRadioss' /DT scale;
    /// default [`DEFAULT_TIME_STEP_SAFETY`]). A model with an eroding contact runs at most at
    /// [`ERODING_CONTACT_TIME_STEP_SAFETY`].
    pub time_step_safety: f64,
    /// Bulk-viscosity coefficients (LS-DYNA's defaults unless an experiment names others).
    pub bulk_viscosity: BulkViscosity,
    /// Hourglass coefficient (LS-DYNA QH, default 0.1), of the form `hourglass`.
    pub hourglass_coefficient: f64,
    /// Form of the hourglass control (default viscous).
    pub hourglass: HourglassControl,
    /// Optional nodal damping to reach a final shape.
    pub damping: Option<NodalDamping>,
    /// Worker threads (`None`: rayon's default). Results do not depend on it.
    pub threads: Option<usize>,
    /// Interval between energy/probe records (s).
    pub output_interval: f64,
    /// Stop early when the kinetic energy falls below this fraction of the initial energy
    /// after damping started (0 disables).
    pub rest_fraction: f64,
    /// Where a run reports how far it has come (`stoss simulate`'s progress); results never
    /// depend on it.
    pub progress: RunProgress,
    /// Non-local averaging of the damage driver over a radius (`None`: local; [`nonlocal`]).
    pub nonlocal: Option<NonlocalAveraging>,
}

/// The fraction of its end time a run has reached, and for an experiment of several runs (a
/// ballistic sweep's shots) how many have finished of how many are expected, shared with
/// whoever reports progress (a thread of `stoss simulate`). Every settings with a progress
/// cell compare equal: it is not a numerical setting.
#[derive(Clone, Debug, Default)]
pub struct RunProgress(Option<std::sync::Arc<ProgressCells>>);

/// The cells of a watched [`RunProgress`].
#[derive(Debug, Default)]
pub struct ProgressCells {
    /// The current run's fraction of its end time (`f64` bits).
    fraction: std::sync::atomic::AtomicU64,
    /// Runs finished.
    finished: std::sync::atomic::AtomicU64,
    /// Runs the experiment expects to make (0: one, or not said).
    expected: std::sync::atomic::AtomicU64,
}

impl PartialEq for RunProgress {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl RunProgress {
    /// A cell to watch.
    pub fn watched() -> Self {
        Self(Some(std::sync::Arc::new(ProgressCells::default())))
    }

    /// Record that a run is at `time` of `end_time`.
    pub fn report(&self, time: f64, end_time: f64) {
        if let Some(cells) = &self.0 {
            let fraction = if end_time > 0.0 {
                (time / end_time).clamp(0.0, 1.0)
            } else {
                0.0
            };
            cells
                .fraction
                .store(fraction.to_bits(), std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Say that the experiment expects to make `runs` runs in all (a ballistic sweep's
    /// shots); a search that needs more raises it.
    pub fn expect_runs(&self, runs: usize) {
        if let Some(cells) = &self.0 {
            cells
                .expected
                .fetch_max(runs as u64, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Record that one of the experiment's runs has finished.
    pub fn run_finished(&self) {
        if let Some(cells) = &self.0 {
            let finished = cells
                .finished
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed)
                + 1;
            cells
                .expected
                .fetch_max(finished, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// The fraction reached by the current run (0 to 1), if the cell is watched.
    pub fn fraction(&self) -> Option<f64> {
        self.0
            .as_ref()
            .map(|cells| f64::from_bits(cells.fraction.load(std::sync::atomic::Ordering::Relaxed)))
    }

    /// Runs finished and runs expected, if the experiment said it makes more than one.
    pub fn runs(&self) -> Option<(usize, usize)> {
        let cells = self.0.as_ref()?;
        let expected = cells.expected.load(std::sync::atomic::Ordering::Relaxed) as usize;
        let finished = cells.finished.load(std::sync::atomic::Ordering::Relaxed) as usize;
        (expected > 1).then_some((finished, expected))
    }
}

impl SolverSettings {
    /// The safety factor a model runs at: [`Self::time_step_safety`], at most
    /// [`ERODING_CONTACT_TIME_STEP_SAFETY`] with an eroding contact.
    pub fn effective_time_step_safety(&self, eroding_contact: bool) -> f64 {
        if eroding_contact {
            self.time_step_safety.min(ERODING_CONTACT_TIME_STEP_SAFETY)
        } else {
            self.time_step_safety
        }
    }

    /// Reject a thread count outside `1..=`[`explicit::MAXIMUM_THREADS`] before any pool is
    /// built (a guard against a runaway thread pool).
    pub fn check_threads(&self) -> Result<(), SolverError> {
        match self.threads {
            Some(threads) if !(1..=explicit::MAXIMUM_THREADS).contains(&threads) => {
                Err(SolverError::Model(format!(
                    "threads must be in 1..={}, got {threads}",
                    explicit::MAXIMUM_THREADS
                )))
            }
            _ => Ok(()),
        }
    }

    /// Stable time step of an element of characteristic length `length`:
    /// `L / (Q + sqrt(Q^2 + c^2))`, `Q = C1 c + C0 L |d_v|` while compressing (LS-DYNA's form
    /// with bulk viscosity).
    pub fn stable_time_step(&self, length: f64, wave_speed: f64, volumetric_rate: f64) -> f64 {
        let q = self
            .bulk_viscosity
            .time_step_speed(length, wave_speed, volumetric_rate);
        length / BulkViscosity::signal_speed(q, wave_speed)
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            end_time: 1e-4,
            time_step_safety: DEFAULT_TIME_STEP_SAFETY,
            bulk_viscosity: BulkViscosity::default(),
            hourglass_coefficient: 0.1,
            hourglass: HourglassControl::Viscous,
            damping: None,
            threads: None,
            output_interval: 1e-6,
            rest_fraction: 0.0,
            progress: RunProgress::default(),
            nonlocal: None,
        }
    }
}

/// Why a run stopped with an error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// A material failed validation.
    #[error("part {part}: {error}")]
    Material {
        /// Part name.
        part: String,
        /// The kernel's error.
        #[source]
        error: stoss_kernel::ParameterError,
    },
    /// The kernel rejected an update (e.g. an element crushed past its equation of state's
    /// limiting compression, whose pressure is then not finite).
    #[error(
        "element {element} of part {part} at t = {time:.4e} s, relative volume V/V0 = \
         {relative_volume:.4}: {error}"
    )]
    Update {
        /// Element index.
        element: usize,
        /// Its part.
        part: String,
        /// Time (s).
        time: f64,
        /// The element's relative volume `V/V0` at the end of the rejected step.
        relative_volume: f64,
        /// The kernel's error.
        #[source]
        error: stoss_kernel::UpdateError,
    },
    /// An element inverted (non-positive area or volume).
    #[error("element {element} of part {part} inverted at t = {time:.4e} s")]
    InvertedElement {
        /// Element index.
        element: usize,
        /// Its part.
        part: String,
        /// Time (s).
        time: f64,
    },
    /// The time step collapsed below the given floor.
    #[error("time step collapsed to {time_step:.3e} s at t = {time:.4e} s")]
    TimeStepCollapse {
        /// Time (s).
        time: f64,
        /// The time step (s).
        time_step: f64,
    },
    /// The model is not well formed.
    #[error("{0}")]
    Model(String),
}
