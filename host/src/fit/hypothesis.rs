//! A hypothesis of the diagnosis: a material (with its strength written as composable terms
//! where the family allows), the experiment-level settings a physics term may change (anvil
//! friction, the rate treatment), and the constants that are fitted with their bounds.
//!
//! Fitted constants are named by where they live:
//! - `strength.<name>`, `heating.<name>`: a described constant of the material
//!   ([`MaterialFile::constant`], e.g. `strength.hardening.yield_stress`);
//! - [`ANVIL_FRICTION`]: the Coulomb friction of every Taylor test's anvil;
//! - [`LAGGED_MIXTURE`]: the weight `lambda` of the lagged-rate prediction in
//!   `(1 - lambda) P(current treatment) + lambda P(other treatment)` (the linear family
//!   through which the score test sees the seed 001 rate-treatment defect);
//! - [`EROSION_INTENSITY`]: `gamma = 1 / eps_f`, elements erode at plastic strain `eps_f`
//!   (`gamma = 0`: no failure);
//! - `setup.<target>.<field>`: a set-up parameter of the calibration (a nuisance parameter,
//!   [`super::space::SetupParameter`]), written into the experiments it names.

use super::space::{with_setup, ModelSpace, SetupValue, SETUP_PREFIX};
use super::unit_cube;
use crate::experiment::{Experiment, Setup};
use crate::input::material::{AnyMaterialFile, MaterialFile, StrengthSpec};
use crate::solver::SolverSettings;
use serde::{Deserialize, Serialize};
use stoss_kernel::damage::Failure;
use stoss_kernel::{Material, PartMaterial, RateTreatment};

/// Name of the anvil-friction constant.
pub const ANVIL_FRICTION: &str = "setup.anvil_friction";
/// Name of the lagged-rate mixture weight.
pub const LAGGED_MIXTURE: &str = "mixture.lagged";
/// Name of the erosion intensity `1 / eps_f`.
pub const EROSION_INTENSITY: &str = "failure.intensity";

/// A fitted constant and its bounds (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// Where it lives (see the module docs).
    pub name: String,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
}

impl Parameter {
    /// `value` in unit coordinates of the bounds.
    pub fn to_unit(&self, value: f64) -> f64 {
        unit_cube::to_unit(value, self.lower, self.upper)
    }

    /// Unit coordinate `unit` in SI.
    pub fn from_unit(&self, unit: f64) -> f64 {
        unit_cube::from_unit(unit, self.lower, self.upper)
    }
}

/// A model to fit: material, experiment-level settings and fitted constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hypothesis {
    /// `base` or the candidate term's name.
    pub label: String,
    /// The material file (fitted constants hold their last values).
    pub material: MaterialFile,
    /// Anvil friction of every Taylor test (`None`: as each experiment file says).
    pub anvil_friction: Option<f64>,
    /// Lagged-rate mixture weight (0: none).
    pub lagged_mixture: f64,
    /// Erosion intensity `1 / eps_f` (0: the material file's failure model alone).
    #[serde(default)]
    pub erosion_intensity: f64,
    /// The set-up parameters' current values (the calibration's nuisance parameters).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub setup: Vec<SetupValue>,
    /// Fitted constants.
    pub parameters: Vec<Parameter>,
}

/// A hypothesis with values for its constants: what the simulations run.
#[derive(Clone, Debug)]
pub struct Realisation {
    /// The material file with the values written in.
    pub file: MaterialFile,
    /// The kernel material.
    pub material: Material,
    /// Anvil friction override.
    pub anvil_friction: Option<f64>,
    /// Lagged-rate mixture weight.
    pub lagged_mixture: f64,
    /// Erosion intensity (already applied to `file` and `material`).
    pub erosion_intensity: f64,
    /// Set-up parameters, written into the experiments they name.
    pub setup: Vec<SetupValue>,
}

impl Hypothesis {
    /// The calibrated model of a campaign (its base material file `campaign_base`, the
    /// model's `space` at `values`) as the diagnosis's base hypothesis: a Johnson-Cook
    /// strength is rewritten as its composed terms (the same kernel model, bit for bit) so
    /// that the library can add a term; other families keep their form.
    pub fn base(
        campaign_base: &AnyMaterialFile,
        space: &ModelSpace,
        values: &[f64],
    ) -> Result<Self, String> {
        let AnyMaterialFile::J2(base) = campaign_base else {
            let family = match campaign_base {
                AnyMaterialFile::Kc(_) => "K&C concrete",
                _ => "RHT concrete",
            };
            return Err(format!(
                "the diagnosis is for J2 metals; {} is {family}",
                campaign_base.name()
            ));
        };
        let mut material = base.clone();
        material.strength = space.strength_with(values)?;
        // A family with a composed form is rewritten as its terms, its constants renamed to
        // their paths there (the kernel's `COMPOSED_PATHS`).
        let paths = match material.strength.composed_with_paths() {
            Some((composed, paths)) => {
                material.strength = StrengthSpec::Composed(composed);
                paths
            }
            None => space.names.iter().map(|n| (n.clone(), n.clone())).collect(),
        };
        let mut parameters = Vec::new();
        for (i, name) in space.names.iter().enumerate() {
            if i >= space.constant_count() {
                parameters.push(Parameter {
                    name: name.clone(),
                    lower: space.lower[i],
                    upper: space.upper[i],
                });
                continue;
            }
            let path = paths
                .iter()
                .find(|(family, _)| family == name)
                .map(|(_, path)| path)
                .ok_or_else(|| format!("`{name}` is not a constant of this model"))?;
            parameters.push(Parameter {
                name: format!("strength.{path}"),
                lower: space.lower[i],
                upper: space.upper[i],
            });
        }
        Ok(Self {
            label: "base".into(),
            material,
            anvil_friction: None,
            lagged_mixture: 0.0,
            erosion_intensity: 0.0,
            setup: space.setup_values(values),
            parameters,
        })
    }

    /// The current values of the fitted constants (read back from the material and settings).
    pub fn values(&self) -> Result<Vec<f64>, String> {
        self.parameters
            .iter()
            .map(|p| match p.name.as_str() {
                ANVIL_FRICTION => Ok(self.anvil_friction.unwrap_or(0.0)),
                LAGGED_MIXTURE => Ok(self.lagged_mixture),
                EROSION_INTENSITY => Ok(self.erosion_intensity),
                name if name.starts_with(SETUP_PREFIX) => self
                    .setup
                    .iter()
                    .find(|s| s.name == name)
                    .map(|s| s.value)
                    .ok_or_else(|| format!("`{name}` is not a set-up parameter of the hypothesis")),
                path => self
                    .material
                    .constant(path)
                    .ok_or_else(|| format!("`{path}` is not a constant of the material")),
            })
            .collect()
    }

    /// Write `values` into a copy of the material and settings and build the kernel material.
    pub fn realise(&self, values: &[f64]) -> Result<Realisation, String> {
        let mut file = self.material.clone();
        let mut anvil_friction = self.anvil_friction;
        let mut lagged_mixture = self.lagged_mixture;
        let mut erosion_intensity = self.erosion_intensity;
        let mut setup = self.setup.clone();
        for (parameter, value) in self.parameters.iter().zip(values) {
            match parameter.name.as_str() {
                ANVIL_FRICTION => anvil_friction = Some(*value),
                LAGGED_MIXTURE => lagged_mixture = *value,
                EROSION_INTENSITY => erosion_intensity = *value,
                name if name.starts_with(SETUP_PREFIX) => {
                    setup
                        .iter_mut()
                        .find(|s| s.name == name)
                        .ok_or_else(|| {
                            format!("`{name}` is not a set-up parameter of the hypothesis")
                        })?
                        .value = *value;
                }
                path => file
                    .set_constant(path, *value)
                    .ok_or_else(|| format!("`{path}` is not a constant of the material"))?,
            }
        }
        if erosion_intensity > 0.0 {
            let mut failure = file.failure.unwrap_or(Failure::NONE);
            failure.erosion_plastic_strain = Some(1.0 / erosion_intensity);
            file.failure = Some(failure);
        }
        let material = file.material().map_err(|e| e.to_string())?;
        Ok(Realisation {
            file,
            material,
            anvil_friction,
            lagged_mixture,
            erosion_intensity,
            setup,
        })
    }

    /// This hypothesis with its material and settings holding `values`.
    pub fn with_values(&self, values: &[f64]) -> Result<Self, String> {
        let realised = self.realise(values)?;
        Ok(Self {
            material: realised.file,
            anvil_friction: realised.anvil_friction,
            lagged_mixture: realised.lagged_mixture,
            erosion_intensity: realised.erosion_intensity,
            setup: realised.setup,
            ..self.clone()
        })
    }
}

/// The rate treatment the lagged-rate term switches to: implicit <-> lagged.
pub fn other_rate_treatment(treatment: RateTreatment) -> RateTreatment {
    match treatment {
        RateTreatment::Implicit => RateTreatment::Lagged,
        RateTreatment::Lagged => RateTreatment::Implicit,
    }
}

/// The experiment as this realisation runs it (anvil friction overridden).
fn adjusted(
    experiment: &Experiment,
    anvil_friction: Option<f64>,
) -> std::borrow::Cow<'_, Experiment> {
    match (&experiment.file.setup, anvil_friction) {
        (Setup::Taylor(spec), Some(friction)) if spec.anvil_friction != friction => {
            let mut changed = experiment.clone();
            if let Setup::Taylor(spec) = &mut changed.file.setup {
                spec.anvil_friction = friction;
            }
            std::borrow::Cow::Owned(changed)
        }
        _ => std::borrow::Cow::Borrowed(experiment),
    }
}

impl Realisation {
    /// Predictions of `experiment` (the recording's points); an error names the experiment.
    pub fn predict(
        &self,
        experiment: &Experiment,
        settings: &SolverSettings,
    ) -> Result<Vec<f64>, String> {
        let experiment = with_setup(experiment, &self.setup)?;
        let experiment = experiment.as_ref();
        let run = |material: &Material| -> Result<Vec<f64>, String> {
            let outcome = adjusted(experiment, self.anvil_friction)
                .simulate(&PartMaterial::from(*material), settings)
                .map_err(|e| format!("{}: {e}", experiment.file.name))?;
            if outcome.predicted.iter().all(|p| p.is_finite()) {
                Ok(outcome.predicted)
            } else {
                Err(format!("{}: non-finite prediction", experiment.file.name))
            }
        };
        let current = run(&self.material)?;
        if self.lagged_mixture == 0.0 {
            return Ok(current);
        }
        let mut other = self.material;
        other.rate_treatment = other_rate_treatment(other.rate_treatment);
        let switched = run(&other)?;
        let weight = self.lagged_mixture;
        Ok(current
            .iter()
            .zip(&switched)
            .map(|(a, b)| (1.0 - weight) * a + weight * b)
            .collect())
    }

    /// Full outcome of `experiment` (states and fields for the locate step; no mixture).
    pub fn outcome(
        &self,
        experiment: &Experiment,
        settings: &SolverSettings,
    ) -> Result<crate::experiment::Outcome, String> {
        let experiment = with_setup(experiment, &self.setup)?;
        adjusted(experiment.as_ref(), self.anvil_friction)
            .simulate(&PartMaterial::from(self.material), settings)
            .map_err(|e| format!("{}: {e}", experiment.file.name))
    }
}
