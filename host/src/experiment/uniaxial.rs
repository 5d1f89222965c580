//! Homogeneous uniaxial stress at constant true strain rate and initial temperature: the
//! characterisation curves (e.g. `shared/data/real/4340-flow`) and, for concrete, the
//! strength against strain rate (dynamic increase factors). Runs the kernel's uniaxial-stress
//! driver with either model family. Quantities:
//! - `true_stress` (Pa, magnitude) at `position` = true plastic strain, or true total strain
//!   with `recorded_strain = "total"`;
//! - `peak_stress` (Pa, magnitude; `position` unused, 0): the largest axial stress of the
//!   path, the uniaxial strength of a softening material such as RHT concrete.

use super::{Check, ExperimentReport, Outcome, SimulationError};
use crate::experiment::SummaryValue;
use crate::history::History;
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::{interpolate, StateHistory, StateSample};
use serde::{Deserialize, Serialize};
use stoss_kernel::drivers::{uniaxial_stress, UniaxialStressLoading};
use stoss_kernel::{Heating, PartMaterial, PointModel};

/// Quantities a uniaxial test records.
pub const QUANTITIES: &[&str] = &["true_stress", "peak_stress"];

/// Plastic-strain step of the driver.
const STRAIN_STEP: f64 = 2.0e-4;

/// Largest true plastic strain a recorded flow curve may reach: it bounds the driver's steps
/// (25 000 at this strain), and a larger one is a curve in percent.
pub(super) const MAXIMUM_PLASTIC_STRAIN: f64 = 5.0;

/// A homogeneous uniaxial-stress test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UniaxialSpec {
    /// True strain rate magnitude (1/s).
    pub strain_rate: f64,
    /// Initial temperature (K).
    pub temperature: f64,
    /// Compression (`true`) or tension.
    #[serde(default)]
    pub compression: bool,
    /// Force isothermal conditions (quasi-static tests), whatever the material's heating (J2
    /// metals; RHT concrete has no heating).
    #[serde(default)]
    pub isothermal: bool,
    /// What the recording's `position` of `true_stress` is: the true *plastic* strain (the
    /// default, as flow curves are published) or the true *total* strain a test machine
    /// records (`"total"`), elastic part included.
    #[serde(default)]
    pub recorded_strain: RecordedStrain,
    /// Leave out the `true_stress` points recorded after the largest recorded stress (a
    /// tension test past its maximum load necks: the stress there is no longer the homogeneous
    /// uniaxial flow stress this experiment simulates). Default `false`.
    #[serde(default)]
    pub trim_at_maximum: bool,
    /// How many points `trim_at_maximum` left out (set on load; said in the run's report).
    #[serde(skip)]
    pub trimmed: usize,
    /// What the recording's stress and strain are: true (the default) or engineering
    /// (`"engineering"`: force over initial area against elongation over initial length, a
    /// total strain, so `recorded_strain = "total"` is required). Engineering points are
    /// converted on load to true stress and true total strain for uniform deformation,
    /// [`engineering_to_true`]; the run's report says so.
    #[serde(default)]
    pub recorded_measure: RecordedMeasure,
}

/// Whether a flow curve's stress and strain are true or engineering measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RecordedMeasure {
    /// True stress and true strain.
    #[default]
    True,
    /// Engineering stress (force / initial area) and strain (elongation / initial length).
    Engineering,
}

/// A `true_stress` point given as engineering stress `s` and strain `e` (magnitudes) as true
/// stress and true total strain, for uniform deformation at constant volume: in tension
/// `sigma = s (1 + e)`, `eps = ln(1 + e)`; in compression `sigma = s (1 - e)`,
/// `eps = -ln(1 - e)` (Dieter, Mechanical Metallurgy, sec. 8-2). The uncertainty scales as the
/// stress. Valid up to the maximum load (necking in tension); `trim_at_maximum` drops the rest.
pub fn engineering_to_true(point: &RecordedPoint, compression: bool) -> RecordedPoint {
    let e = point.position;
    let (factor, strain) = if compression {
        (1.0 - e, -libm::log(1.0 - e))
    } else {
        (1.0 + e, libm::log1p(e))
    };
    RecordedPoint {
        quantity: point.quantity.clone(),
        position: strain,
        value: point.value * factor,
        uncertainty: point.uncertainty * factor,
    }
}

/// The recording with its `true_stress` points after the largest recorded stress left out,
/// and how many were (the curve's order is the recording's; other quantities are kept).
pub fn trimmed_at_maximum(recording: Vec<RecordedPoint>) -> (Vec<RecordedPoint>, usize) {
    let curve = |p: &RecordedPoint| p.quantity == "true_stress";
    let Some(peak) = recording
        .iter()
        .filter(|p| curve(p))
        .map(|p| (p.position, p.value.abs()))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(position, _)| position)
    else {
        return (recording, 0);
    };
    let before = recording.len();
    let kept: Vec<RecordedPoint> = recording
        .into_iter()
        .filter(|p| !curve(p) || p.position <= peak)
        .collect();
    let trimmed = before - kept.len();
    (kept, trimmed)
}

/// The strain measure of a flow curve's positions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RecordedStrain {
    /// True plastic strain.
    #[default]
    Plastic,
    /// True total strain `ln(L/L0)`: elastic plus plastic.
    Total,
}

impl RecordedStrain {
    /// The measure's name in sentences and axis labels.
    pub fn name(self) -> &'static str {
        match self {
            RecordedStrain::Plastic => "true plastic strain",
            RecordedStrain::Total => "true total strain",
        }
    }
}

impl UniaxialSpec {
    /// What a run says about how its recording was read (total strain, trimmed points).
    fn report_text(&self) -> Option<String> {
        let mut text = String::new();
        if self.recorded_strain == RecordedStrain::Total {
            text.push_str(
                "flow curve recorded against true total strain (elastic part included): the \
                 simulated curve is compared at rate x time, its own elasticity included\n",
            );
        }
        if self.recorded_measure == RecordedMeasure::Engineering {
            text.push_str(
                "recorded as engineering stress and strain: converted on load to true stress \
                 s (1 + e) and true strain ln(1 + e) (compression: s (1 - e), -ln(1 - e)), \
                 valid for uniform deformation, before necking\n",
            );
        }
        if self.trimmed > 0 {
            text.push_str(&format!(
                "{} recorded points after the largest stress were left out (trim_at_maximum: \
                 necking)\n",
                self.trimmed
            ));
        }
        (!text.is_empty()).then_some(text)
    }

    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        check(
            "strain_rate",
            self.strain_rate > 0.0 && self.strain_rate.is_finite(),
            "must be > 0 (1/s)",
        )?;
        check(
            "temperature",
            self.temperature > 0.0 && self.temperature.is_finite(),
            "must be > 0 (K)",
        )
    }

    /// Run the driver up to `max_plastic_strain` and return the state history.
    pub fn history(
        &self,
        material: &PartMaterial,
        max_plastic_strain: f64,
    ) -> Result<StateHistory, SimulationError> {
        let mut material = *material;
        if let (true, PartMaterial::J2(metal)) = (self.isothermal, &mut material) {
            metal.heating = Heating::Isothermal;
        }
        // Total strain: plastic target plus a generous elastic allowance.
        let total = max_plastic_strain.max(0.02) + 0.03;
        let steps = ((total / STRAIN_STEP).ceil() as u32).max(200);
        let sign = if self.compression { -1.0 } else { 1.0 };
        let mut state = material.initial_state(self.temperature);
        let mut history = History::default();
        uniaxial_stress(
            &material,
            &mut state,
            &UniaxialStressLoading {
                strain_rate: self.strain_rate,
                final_strain: sign * total,
                steps,
            },
            &mut history,
        )
        .map_err(SimulationError::Driver)?;
        let samples = history
            .0
            .iter()
            .map(|r| StateSample {
                time: r.time,
                plastic_strain: r.plastic_strain,
                plastic_strain_rate: r.plastic_strain_rate,
                temperature: r.temperature,
                pressure: r.pressure,
                equivalent_stress: r.equivalent_stress,
                triaxiality: if r.equivalent_stress > 0.0 {
                    -r.pressure / r.equivalent_stress
                } else {
                    0.0
                },
                axial_stress: r.stress[0],
            })
            .collect();
        Ok(StateHistory {
            label: "uniaxial driver".into(),
            samples,
        })
    }

    pub(super) fn simulate(
        &self,
        material: &PartMaterial,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let max_strain = recording
            .iter()
            .filter(|p| p.quantity == "true_stress")
            .map(|p| p.position)
            .fold(0.0, f64::max);
        let history = self.history(material, max_strain)?;
        let curve: Vec<(f64, f64)> = match self.recorded_strain {
            RecordedStrain::Plastic => history
                .samples
                .iter()
                .filter(|s| s.plastic_strain > 0.0)
                .map(|s| (s.plastic_strain, s.axial_stress.abs()))
                .collect(),
            // The driver strains at a constant true rate from zero, so the total true strain
            // of a sample is rate x time: the simulated curve itself, with the model's own
            // elasticity, is mapped to the recording's measure (the recording is not changed).
            RecordedStrain::Total => std::iter::once((0.0, 0.0))
                .chain(
                    history
                        .samples
                        .iter()
                        .map(|s| (self.strain_rate * s.time, s.axial_stress.abs())),
                )
                .collect(),
        };
        let peak = history
            .samples
            .iter()
            .map(|s| s.axial_stress.abs())
            .fold(0.0, f64::max);
        let predicted = recording
            .iter()
            .map(|p| match p.quantity.as_str() {
                "peak_stress" => peak,
                _ => interpolate(&curve, p.position),
            })
            .collect();
        let last = history.samples.last().copied().unwrap_or_default();
        Ok(Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("peak_stress", peak, "Pa"),
                SummaryValue::new("final_true_stress", last.axial_stress.abs(), "Pa"),
                SummaryValue::new("final_plastic_strain", last.plastic_strain, "-"),
                SummaryValue::new("final_temperature", last.temperature, "K"),
            ],
            energy: None,
            states: vec![history],
            field: None,
            element_cycles: 0,
            report: self.report_text().map(|text| ExperimentReport {
                text,
                ..ExperimentReport::default()
            }),
        })
    }
}
