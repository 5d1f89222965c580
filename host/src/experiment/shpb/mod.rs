//! Split Hopkinson (Kolsky) compression bar: a cylindrical specimen of the material under
//! calibration between an incident and a transmitter bar, loaded by the pulse of a striker;
//! the specimen's engineering stress-strain curve comes from the bar gauges, as in the
//! laboratory. Quantity `engineering_stress` (Pa, compressive positive) at `position` =
//! engineering strain (compressive positive), on the loading branch.
//!
//! # Model (axisymmetric, [`crate::solver`])
//!
//! - Incident bar `z in [-L_i, 0]`, specimen `z in [0, l_s]`, transmitter `z in [l_s, l_s + L_t]`,
//!   three separate parts. The bars are linear elastic (Young's modulus `E`, density `rho`,
//!   Poisson's ratio `nu` from the spec: a kernel material with `G = E / 2(1 + nu)`, a linear
//!   EoS `K = E / 3(1 - 2 nu)` and an unreachable yield stress), the specimen is the calibrated
//!   material. Defaults: 12.7 mm maraging-steel bars (E 200 GPa, 8000 kg/m^3, nu 0.29,
//!   `c0 = 5000 m/s`), 500 mm each, gauges at mid-bar (250 mm from the specimen faces),
//!   specimen 6 mm diameter x 4 mm.
//! - Bar/specimen interfaces: penalty contact ([`crate::solver::contact`]) with the
//!   specimen's end-face nodes as slaves on the bar faces, Coulomb friction 0.05 by default (a
//!   lubricated interface), penalty scale [`INTERFACE_PENALTY_SCALE`]: a stiffer interface
//!   than the contact default, because a compliant penalty interface adds a spring between bar
//!   and specimen that delays and rounds the ring-up. With the default 0.1 the stress at 1 %
//!   strain changed by 15 % between time-step safety 0.3 and 0.67; with 0.3 the curve at the
//!   0.9 default is within 1.7 % of the fine-step one from 2 % strain on.
//! - Loading: a striker of the bar's material and impedance at velocity `V` gives the incident
//!   bar a particle velocity `V/2` for `T = 2 L_striker / c0`; it is prescribed on the incident
//!   bar's free end as a trapezoid `0 -> V/2` over `rise_time`, held to `T`, back to 0 at
//!   `T + rise_time`. The end is then held (v = 0), which matters only after `2 L_i / c0`,
//!   outside the analysis window.
//! - Mesh: square bar elements, `bar_radial_elements` across the radius; square-ish specimen
//!   elements, `specimen_radial_elements` across its radius and an odd number along it (so an
//!   element row sits on the specimen's mid-plane).
//! - Gauges: the bar surface axial strain `eps = -sigma_zz / E` (compressive positive) of the
//!   outer-column element whose centre is nearest the stated distance from the specimen face;
//!   the time shifts use that element's distance `d`.
//!
//! # Analysis
//!
//! [`kolsky`]: wave separation and the 1-, 2- and 3-wave Kolsky analysis, the same for the
//! simulated gauges and for a real bar's recorded ones (`stoss analyse-shpb`).

pub mod kolsky;
mod model;

pub use kolsky::{BarWaves, KolskyBar, StressStrain};

use super::default_temperature;
use super::{check_positive, Check, FieldOutput, Outcome, SimulationError};
use crate::experiment::SummaryValue;
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::interpolate;
use crate::solver::SolverSettings;
use serde::{Deserialize, Serialize};
use stoss_kernel::Material;

/// Quantities a Hopkinson bar test records.
pub const QUANTITIES: &[&str] = &["engineering_stress"];

/// Sampling interval of the gauges and of the analysis grid (s).
pub const SAMPLING: f64 = 0.1e-6;

/// Penalty scale of the bar/specimen interfaces (module notes). Stable at the default
/// safety factor: the element's own frequency (`omega dt <= 2 x 0.9 = 1.8`) and the contact
/// spring's (`sqrt(0.3) = 0.55`) add in quadrature to 1.88 < 2.
pub const INTERFACE_PENALTY_SCALE: f64 = 0.3;

/// Which bar signals give the specimen stress and strain rate (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Analysis {
    /// Stress from the transmitted wave, strain rate from the reflected wave.
    #[default]
    #[serde(rename = "1-wave")]
    OneWave,
    /// Stress from the incident and reflected waves (front face), rate from the reflected.
    #[serde(rename = "2-wave")]
    TwoWave,
    /// Mean of front and back face stresses, rate from all three waves.
    #[serde(rename = "3-wave")]
    ThreeWave,
}

fn default_bar_diameter() -> f64 {
    12.7e-3
}
fn default_bar_length() -> f64 {
    0.5
}
fn default_bar_young_modulus() -> f64 {
    200.0e9
}
fn default_bar_density() -> f64 {
    8000.0
}
fn default_bar_poisson_ratio() -> f64 {
    0.29
}
fn default_specimen_diameter() -> f64 {
    6.0e-3
}
fn default_specimen_length() -> f64 {
    4.0e-3
}
fn default_striker_length() -> f64 {
    0.2
}
fn default_rise_time() -> f64 {
    5.0e-6
}
fn default_gauge() -> f64 {
    0.25
}
fn default_friction() -> f64 {
    0.05
}
fn default_bar_radial_elements() -> usize {
    4
}
fn default_specimen_radial_elements() -> usize {
    8
}

/// Geometry, bars, loading, gauges and discretisation of a split Hopkinson compression bar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShpbSpec {
    /// Bar diameter (m), both bars.
    #[serde(default = "default_bar_diameter")]
    pub bar_diameter: f64,
    /// Incident bar length (m).
    #[serde(default = "default_bar_length")]
    pub incident_length: f64,
    /// Transmitter bar length (m).
    #[serde(default = "default_bar_length")]
    pub transmitter_length: f64,
    /// Young's modulus of the bars (and striker) (Pa).
    #[serde(default = "default_bar_young_modulus")]
    pub bar_young_modulus: f64,
    /// Density of the bars (kg/m^3).
    #[serde(default = "default_bar_density")]
    pub bar_density: f64,
    /// Poisson's ratio of the bars.
    #[serde(default = "default_bar_poisson_ratio")]
    pub bar_poisson_ratio: f64,
    /// Specimen diameter (m).
    #[serde(default = "default_specimen_diameter")]
    pub specimen_diameter: f64,
    /// Specimen length (m).
    #[serde(default = "default_specimen_length")]
    pub specimen_length: f64,
    /// Striker velocity (m/s).
    pub striker_velocity: f64,
    /// Striker length (m): the pulse lasts `2 L_striker / c0`.
    #[serde(default = "default_striker_length")]
    pub striker_length: f64,
    /// Rise (and fall) time of the prescribed pulse (s).
    #[serde(default = "default_rise_time")]
    pub rise_time: f64,
    /// Incident gauge: distance from the specimen face (m).
    #[serde(default = "default_gauge")]
    pub incident_gauge: f64,
    /// Transmitter gauge: distance from the specimen face (m).
    #[serde(default = "default_gauge")]
    pub transmitter_gauge: f64,
    /// Coulomb friction between specimen and bars.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Initial temperature (K).
    #[serde(default = "default_temperature")]
    pub temperature: f64,
    /// Analysis that gives the recorded curve.
    #[serde(default)]
    pub analysis: Analysis,
    /// Elements across the bar radius.
    #[serde(default = "default_bar_radial_elements")]
    pub bar_radial_elements: usize,
    /// Elements across the specimen radius.
    #[serde(default = "default_specimen_radial_elements")]
    pub specimen_radial_elements: usize,
}

/// Everything a Hopkinson bar run produces.
#[derive(Clone, Debug)]
pub struct ShpbResult {
    /// Incident gauge signal `(time, strain)`, compressive positive.
    pub incident_gauge: Vec<(f64, f64)>,
    /// Transmitter gauge signal `(time, strain)`, compressive positive.
    pub transmitter_gauge: Vec<(f64, f64)>,
    /// Gauge distances from the specimen faces actually used (element centres) (m).
    pub gauge_distances: (f64, f64),
    /// The separated waves.
    pub waves: BarWaves,
    /// 1-wave analysis.
    pub one_wave: StressStrain,
    /// 2-wave analysis.
    pub two_wave: StressStrain,
    /// 3-wave analysis.
    pub three_wave: StressStrain,
    /// The specimen's own engineering stress from its mid-plane element row, `(time, stress)`
    /// at simulation time, compressive positive: the force `sum -sigma_zz,e A_e` over the
    /// initial area, each element's current area `A_e = A0_e exp(eps_p,e)` from its plastic
    /// strain by volume constancy (elastic volume change, about 0.3 %, neglected).
    pub specimen_stress: Vec<(f64, f64)>,
}

impl ShpbResult {
    /// The analysis by kind.
    pub fn analysis(&self, analysis: Analysis) -> &StressStrain {
        match analysis {
            Analysis::OneWave => &self.one_wave,
            Analysis::TwoWave => &self.two_wave,
            Analysis::ThreeWave => &self.three_wave,
        }
    }
}

impl ShpbSpec {
    /// A spec with every default and the given striker velocity.
    pub fn new(striker_velocity: f64) -> Self {
        Self {
            bar_diameter: default_bar_diameter(),
            incident_length: default_bar_length(),
            transmitter_length: default_bar_length(),
            bar_young_modulus: default_bar_young_modulus(),
            bar_density: default_bar_density(),
            bar_poisson_ratio: default_bar_poisson_ratio(),
            specimen_diameter: default_specimen_diameter(),
            specimen_length: default_specimen_length(),
            striker_velocity,
            striker_length: default_striker_length(),
            rise_time: default_rise_time(),
            incident_gauge: default_gauge(),
            transmitter_gauge: default_gauge(),
            friction: default_friction(),
            temperature: default_temperature(),
            analysis: Analysis::default(),
            bar_radial_elements: default_bar_radial_elements(),
            specimen_radial_elements: default_specimen_radial_elements(),
        }
    }

    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        let positive =
            |field: &str, value: f64, unit: &str| check_positive(check, field, value, unit);
        positive("bar_diameter", self.bar_diameter, "m")?;
        positive("incident_length", self.incident_length, "m")?;
        positive("transmitter_length", self.transmitter_length, "m")?;
        positive("bar_young_modulus", self.bar_young_modulus, "Pa")?;
        positive("bar_density", self.bar_density, "kg/m^3")?;
        check(
            "bar_poisson_ratio",
            (0.0..0.5).contains(&self.bar_poisson_ratio),
            "must be in [0, 0.5)",
        )?;
        positive("specimen_diameter", self.specimen_diameter, "m")?;
        check(
            "specimen_diameter",
            self.specimen_diameter <= self.bar_diameter,
            "must not exceed bar_diameter",
        )?;
        positive("specimen_length", self.specimen_length, "m")?;
        positive("striker_velocity", self.striker_velocity, "m/s")?;
        positive("striker_length", self.striker_length, "m")?;
        check(
            "rise_time",
            self.rise_time >= 0.0 && self.rise_time < 0.5 * self.pulse_duration(),
            "must be >= 0 and shorter than half the pulse 2 L_striker / c0",
        )?;
        check(
            "incident_gauge",
            self.incident_gauge > 0.0 && self.incident_gauge < self.incident_length,
            "must be inside the incident bar (m from the specimen face)",
        )?;
        check(
            "transmitter_gauge",
            self.transmitter_gauge > 0.0 && self.transmitter_gauge < self.transmitter_length,
            "must be inside the transmitter bar (m from the specimen face)",
        )?;
        check("friction", self.friction >= 0.0, "must be >= 0")?;
        check("temperature", self.temperature > 0.0, "must be > 0 (K)")?;
        check(
            "bar_radial_elements",
            (2..=64).contains(&self.bar_radial_elements),
            "must be in 2..=64",
        )?;
        check(
            "specimen_radial_elements",
            (2..=64).contains(&self.specimen_radial_elements),
            "must be in 2..=64",
        )?;
        // Bars or a specimen in mm entered as m are a runaway: refuse them up front (the end
        // time is about two bar transits; square elements in the bars and the specimen, whose
        // smaller elements set the step). The error names the part with more elements.
        let bar_size = 0.5 * self.bar_diameter / self.bar_radial_elements as f64;
        let specimen_size = 0.5 * self.specimen_diameter / self.specimen_radial_elements as f64;
        let bars = self.incident_length + self.transmitter_length;
        let bar_elements = self.bar_radial_elements as f64 * bars / bar_size;
        let specimen_elements =
            self.specimen_radial_elements as f64 * self.specimen_length / specimen_size;
        super::check_run_budget_of(
            check,
            if specimen_elements > bar_elements {
                "specimen_length"
            } else {
                "incident_length"
            },
            2.0 * bars / self.bar_wave_speed(),
            super::undeformed_time_step(bar_size.min(specimen_size), false),
            bar_elements + specimen_elements,
        )?;
        let span = self.pulse_duration() + self.rise_time;
        let c0 = self.bar_wave_speed();
        check(
            "striker_length",
            span <= 2.0
                * self
                    .incident_gauge
                    .min(self.incident_length - self.incident_gauge)
                / c0
                && span <= 2.0 * (self.transmitter_length - self.transmitter_gauge) / c0,
            "the pulse (2 L_striker / c0 + rise_time) is too long for the gauge positions: \
             incident and reflected waves would overlap at a gauge",
        )
    }

    /// Bar wave speed `c0 = sqrt(E / rho)` (m/s).
    pub fn bar_wave_speed(&self) -> f64 {
        (self.bar_young_modulus / self.bar_density).sqrt()
    }

    /// Pulse duration `2 L_striker / c0` (s).
    pub fn pulse_duration(&self) -> f64 {
        2.0 * self.striker_length / self.bar_wave_speed()
    }

    /// Time at which the incident pulse reaches the specimen, `L_i / c0` (s).
    pub fn arrival_time(&self) -> f64 {
        self.incident_length / self.bar_wave_speed()
    }

    /// The bars and specimen as the Kolsky analysis sees them.
    pub fn kolsky_bar(&self) -> KolskyBar {
        KolskyBar {
            young_modulus: self.bar_young_modulus,
            wave_speed: self.bar_wave_speed(),
            area_ratio: (self.bar_diameter / self.specimen_diameter).powi(2),
            specimen_length: self.specimen_length,
        }
    }

    /// The analysis window at the specimen faces `(start, end)` (s).
    fn window(&self) -> (f64, f64) {
        KolskyBar::window(self.arrival_time(), self.pulse_duration(), self.rise_time)
    }

    pub(super) fn simulate(
        &self,
        material: &Material,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let (result, run, model) = self.run(material, settings)?;
        let analysis = result.analysis(self.analysis);
        let curve = analysis.curve();
        let predicted = recording
            .iter()
            .map(|point| interpolate(&curve, point.position))
            .collect();
        let peak = analysis.stress.iter().copied().fold(0.0, f64::max);
        let mut states = run.tracked.clone();
        states[0].label = format!("incident gauge ({})", states[0].label);
        states[1].label = format!("transmitter gauge ({})", states[1].label);
        for history in states.iter_mut().skip(2) {
            history.label = format!("specimen mid-plane ({})", history.label);
        }
        Ok(Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("mean_strain_rate", analysis.mean_strain_rate(), "1/s"),
                SummaryValue::new("max_engineering_strain", analysis.max_strain(), "-"),
                SummaryValue::new("peak_engineering_stress", peak, "Pa"),
                SummaryValue::new(
                    "incident_amplitude_strain",
                    result.waves.incident.iter().copied().fold(0.0, f64::max),
                    "-",
                ),
            ],
            energy: Some(run.energy()),
            states,
            element_cycles: run.element_cycles,
            report: None,
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use stoss_kernel::eos::{Eos, LinearEos};

    #[test]
    fn the_bar_material_has_the_given_elastic_constants() {
        // GOAL: E, rho, nu of the spec map onto the kernel's G and K.
        // SETUP: the defaults E 200 GPa, rho 8000, nu 0.29.
        // REFERENCE: E = 9KG/(3K+G), nu = (3K-2G)/(2(3K+G)), c0 = sqrt(E/rho) = 5000 m/s.
        let spec = ShpbSpec::new(10.0);
        let bar = spec.bar_material();
        let g = bar.shear_modulus;
        let Eos::Linear(LinearEos { bulk_modulus: k }) = bar.eos else {
            panic!("linear EoS expected");
        };
        assert!((9.0 * k * g / (3.0 * k + g) / 200.0e9 - 1.0).abs() < 1e-12);
        assert!(((3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g)) - 0.29).abs() < 1e-12);
        assert!((spec.bar_wave_speed() - 5000.0).abs() < 1e-9);
        assert!(bar.validate().is_ok());
    }
}
