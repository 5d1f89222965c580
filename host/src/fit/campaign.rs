//! Campaign files (TOML): which experiments, which model family, which constants to fit and
//! within which bounds, the realism constraints, and the optimiser budget.
//!
//! ```toml
//! name = "4340 steel, real data"
//! material = "../materials/4340-jc.toml"   # fixed constants: density, elasticity, EoS, heating
//!
//! [[models]]                               # several models: model selection (seed 000 table 1)
//! name = "jc"
//! strength = { model = "johnson-cook", yield_stress = 792e6, ... }  # optional start / fixed values
//! [models.parameters]                      # constants to fit, SI bounds (seed 000 sec. 4.1)
//! yield_stress = [0.3e9, 1.5e9]
//! hardening_modulus = [0.0, 1.5e9]
//!
//! [[experiments]]
//! file = "../experiments/taylor-4340-208.toml"
//! holdout = false                          # true: scored, never fitted
//! weight = 1.0
//!
//! [constraints]
//! max_flow_stress = 4.0e9                  # flow stress over the check grid must stay below
//! min_flow_stress = 20e6                   # ... and above (default: 5 % of the base's yield)
//!
//! [optimiser]
//! budget = 40                              # simulations per instance, Latin hypercube included
//! instances = 2
//! seed = 1
//! parallel = 2                             # simulations run at once (one batch)
//! polish = 20                              # Nelder-Mead from each instance's best (default budget/2)
//! design = 15                              # initial Latin hypercube (default 3 x constants)
//! leave_one_out = "selected"               # false, true (every model) or "selected"
//! fold_budget = 3                          # warm-started folds: new simulations per fold
//! uncertainty = "selected"                 # linearised intervals: "every" (default), "selected", "none"
//!
//! [executor]                               # optional: run the simulations on a Slurm cluster
//! kind = "slurm"                           # (executor/settings.rs lists every key)
//! time_limit = "00:20:00"
//! ```
//!
//! **Concrete.** When the campaign's `material` is an RHT file (`model = "rht"`) or a K&C
//! file (`model = "kc"`), a model has no `strength`, and its parameter names are dotted paths
//! into that file (`parameters.residual_b`, `parameters.damage_d1`, `eos.crush_pressure`;
//! for K&C the described scalars `parameters.compressive_strength`, `tensile_strength`,
//! `biaxial_ratio`, `compression_damage_exponent`, `tension_damage_exponent`,
//! `shear_modulus`; its meridians and damage table are held). The flow-stress constraints,
//! flow-curve figures, cards and the diagnosis are for J2 metals and are skipped.

use crate::experiment::Experiment;
use crate::experiment::RECORDED_SCALE;
use crate::fit::space::{experiment_stem, with_setup, SetupParameter, SetupValue, SETUP_PREFIX};
use crate::fit::ModelSpace;
use crate::input::material::{self, AnyMaterialFile, StrengthSpec};
use crate::input::{self, InputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn one() -> f64 {
    1.0
}

/// One experiment of a campaign.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentEntry {
    /// Experiment file, relative to the campaign file.
    pub file: String,
    /// Held out: scored but never fitted.
    #[serde(default)]
    pub holdout: bool,
    /// Weight of its error in the total.
    #[serde(default = "one")]
    pub weight: f64,
    /// Multi-fidelity (docs/calibration.md, "Multi-fidelity"): the factor (> 1) on every
    /// element size of this experiment's mesh at which the search's candidates simulate it
    /// (`Setup::with_element_scale`); one in [`OptimiserEntry::fine_every`] of them also runs
    /// it as written, and the difference learned from those pairs corrects the rest. Unset:
    /// every candidate runs it as written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarse: Option<f64>,
}

/// Largest coarse factor: an eighth of the elements across a length already leaves the
/// penetration and Taylor meshes at two or three elements across the rod.
pub const MAXIMUM_COARSE_FACTOR: f64 = 8.0;

/// One model (family) to fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelEntry {
    /// Short name (report labels).
    pub name: String,
    /// Starting and fixed constants; default: the base material's strength (J2 metals only).
    #[serde(default)]
    pub strength: Option<StrengthSpec>,
    /// Constants to fit with `[lower, upper]` bounds (SI). For a J2 metal the names are the
    /// strength's field names; nested fields of a composed strength are dotted
    /// (`hardening.yield_stress`). For RHT concrete they are dotted paths into the material
    /// file (`parameters.residual_b`).
    pub parameters: BTreeMap<String, [f64; 2]>,
    /// Set-up fields to search beside the constants, `"<target>.<field>" = [lower, upper]`
    /// (SI, or with units): `<target>` is an experiment's file stem (that experiment) or an
    /// experiment kind (every experiment of the campaign of that kind, as one parameter).
    /// Nuisance parameters: reported with the constants, never written into a material.
    #[serde(default)]
    pub setup: BTreeMap<String, [f64; 2]>,
}

/// Most set-up parameters a model may search (its corners, 2^n, are each checked at load).
pub const MAX_SETUP_PARAMETERS: usize = 8;

/// Realism constraints on the flow stress, checked before any simulation on a grid of
/// plastic strain 0-1, rates 1e-4-1e4 /s and the reference temperature.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constraints {
    /// Upper limit of the flow stress (Pa).
    #[serde(default = "default_max_flow_stress")]
    pub max_flow_stress: f64,
    /// Lower limit of the flow stress (Pa); absent: [`FLOOR_FRACTION`] of the starting
    /// material's initial yield stress ([`Campaign::flow_stress_floor`]).
    #[serde(default)]
    pub min_flow_stress: Option<f64>,
    /// The flow stress must not decrease with plastic strain (isothermal).
    #[serde(default = "yes")]
    pub monotone_hardening: bool,
    /// The flow stress must not decrease with strain rate.
    #[serde(default = "yes")]
    pub monotone_rate: bool,
    /// The flow stress must not rise with temperature, from the check temperature to
    /// [`THERMAL_CHECK_CEILING`](super::objective::THERMAL_CHECK_CEILING), at the checked rates
    /// and up to [`THERMAL_CHECK_MAX_RATE`](super::objective::THERMAL_CHECK_MAX_RATE).
    #[serde(default = "yes")]
    pub monotone_temperature: bool,
}

fn default_max_flow_stress() -> f64 {
    5.0e9
}
/// The default lower flow-stress limit as a fraction of the starting material's initial
/// yield stress: a candidate whose flow stress falls to a twentieth of where the calibration
/// started has lost its strength, whatever the metal (a fixed 50 MPa, the limit before, held
/// copper and aluminium candidates to a steel's floor and marked them all infeasible).
pub const FLOOR_FRACTION: f64 = 0.05;
fn yes() -> bool {
    true
}

impl Default for Constraints {
    fn default() -> Self {
        Self {
            max_flow_stress: default_max_flow_stress(),
            min_flow_stress: None,
            monotone_hardening: true,
            monotone_rate: true,
            monotone_temperature: true,
        }
    }
}

fn default_budget() -> usize {
    40
}
fn default_instances() -> usize {
    2
}
fn default_parallel() -> usize {
    std::thread::available_parallelism().map_or(2, usize::from)
}

/// Optimiser settings of a campaign.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimiserEntry {
    /// Simulations per instance, initial design included.
    #[serde(default = "default_budget")]
    pub budget: usize,
    /// Independent instances per model.
    #[serde(default = "default_instances")]
    pub instances: usize,
    /// Seed of the first instance (instance k uses seed + k); recorded in the log.
    #[serde(default)]
    pub seed: u64,
    /// Simulations run at once.
    #[serde(default = "default_parallel")]
    pub parallel: usize,
    /// Leave-one-out over the fitted experiments (fit on n-1, score all n): `false`, `true`
    /// (every model) or `"selected"` (only the model that model selection picks, as seed 000
    /// did for MJC).
    #[serde(default)]
    pub leave_one_out: LeaveOneOut,
    /// Simulations of the Nelder-Mead polish from each instance's best point (default: half
    /// the Bayesian budget; 0 disables).
    #[serde(default)]
    pub polish: Option<usize>,
    /// Levenberg-Marquardt iterations of the least-squares finish from each instance's best
    /// point (the diagnosis' bounded fit on the whitened residuals), after the polish; 0 (the
    /// default) disables it. Not in warm-started leave-one-out folds. J2 metals only.
    #[serde(default)]
    pub least_squares: Option<usize>,
    /// End an instance's Bayesian phase and polish as soon as its best candidate fits the
    /// fitted experiments within their recorded noise: a chi-square of the whitened residuals
    /// at most `nu + 2 sqrt(2 nu)` for `nu = points - constants` (two standard deviations above
    /// the noise's own expectation). Default `false`.
    #[serde(default)]
    pub stop_at_noise_floor: bool,
    /// Points of the initial Latin hypercube (default `3 x` the number of fitted constants,
    /// seed 000 sec. 4.1; at most the budget).
    #[serde(default)]
    pub design: Option<usize>,
    /// Warm-started leave-one-out: each fold's instances start from every simulation of the
    /// model's all-experiment instances (scored without the left-out experiment) and run this
    /// many new simulations each, without polish. Unset: each fold is an independent
    /// calibration with the full budget and polish.
    #[serde(default)]
    pub fold_budget: Option<usize>,
    /// Which models get the linearised 95 % intervals of their constants (a forward-difference
    /// Jacobian: one more candidate per fitted constant, not logged): `"every"` (default),
    /// `"selected"` (the calibration's selected model, `fit::result::selected_model`) or `"none"`.
    #[serde(default)]
    pub uncertainty: UncertaintyFor,
    /// Multi-fidelity: one in this many of the search's candidates (the initial design and
    /// the Bayesian proposals; the first of every run of this many) also simulates the
    /// experiments that have a `coarse` factor at their own mesh (a fine check). Default 4;
    /// without a `coarse` experiment it has no effect.
    #[serde(default = "default_fine_every")]
    pub fine_every: usize,
}

fn default_fine_every() -> usize {
    4
}

/// Which models get the linearised uncertainty of their constants.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum UncertaintyFor {
    /// Every model.
    #[default]
    Every,
    /// The selected model (`fit::result::selected_model`).
    Selected,
    /// No model.
    None,
}

/// Which models leave-one-out runs for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeaveOneOut {
    /// None.
    #[default]
    Off,
    /// Every model of the campaign.
    Every,
    /// The selected model (`fit::result::selected_model`: held-out prediction where experiments
    /// are held out, else the fit; model selection first).
    Selected,
}

impl LeaveOneOut {
    /// Whether any model runs leave-one-out.
    pub fn is_on(self) -> bool {
        self != LeaveOneOut::Off
    }
}

impl Serialize for LeaveOneOut {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            LeaveOneOut::Off => serializer.serialize_bool(false),
            LeaveOneOut::Every => serializer.serialize_bool(true),
            LeaveOneOut::Selected => serializer.serialize_str("selected"),
        }
    }
}

impl<'de> Deserialize<'de> for LeaveOneOut {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Written {
            Flag(bool),
            Word(String),
        }
        match Written::deserialize(deserializer)? {
            Written::Flag(false) => Ok(LeaveOneOut::Off),
            Written::Flag(true) => Ok(LeaveOneOut::Every),
            Written::Word(word) if word == "selected" => Ok(LeaveOneOut::Selected),
            Written::Word(word) => Err(serde::de::Error::custom(format!(
                "`{word}`: expected true, false or \"selected\""
            ))),
        }
    }
}

impl Default for OptimiserEntry {
    fn default() -> Self {
        Self {
            budget: default_budget(),
            instances: default_instances(),
            seed: 0,
            parallel: default_parallel(),
            leave_one_out: LeaveOneOut::Off,
            polish: None,
            least_squares: None,
            stop_at_noise_floor: false,
            design: None,
            fold_budget: None,
            uncertainty: UncertaintyFor::Every,
            fine_every: default_fine_every(),
        }
    }
}

/// The campaign file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignFile {
    /// Display name.
    pub name: String,
    /// What the campaign is for.
    #[serde(default)]
    pub description: String,
    /// Base material file (fixed constants), relative to the campaign file.
    pub material: String,
    /// Where the recordings come from: laboratory measurements (the default) or another
    /// code's simulations (code-to-code tables, synthetic data).
    #[serde(default)]
    pub recordings: RecordingSource,
    /// Models to fit.
    pub models: Vec<ModelEntry>,
    /// Experiments.
    pub experiments: Vec<ExperimentEntry>,
    /// Realism constraints.
    #[serde(default)]
    pub constraints: Constraints,
    /// Optimiser settings.
    #[serde(default)]
    pub optimiser: OptimiserEntry,
    /// Where the simulations run (default: this machine).
    #[serde(default)]
    pub executor: super::executor::ExecutorEntry,
}

/// Where a campaign's recordings come from. A numerical property of an FE code (the lagged
/// rate update of seed 001 eq. 3.7) can explain a simulation's output, never a material's
/// measured response, so the diagnosis offers it only for simulated recordings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RecordingSource {
    /// Laboratory measurements.
    #[default]
    Experiment,
    /// Another code's (or stoss's own) simulations.
    Simulation,
}

/// A loaded campaign: file, base material and experiments.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The campaign file's path.
    pub path: PathBuf,
    /// Its contents.
    pub file: CampaignFile,
    /// The base material file (either family).
    pub base: AnyMaterialFile,
    /// The experiments, in the file's order.
    pub experiments: Vec<Experiment>,
    /// Each experiment's coarse fidelity (its `coarse` factor applied), in the same order;
    /// `None` where the entry gives no factor.
    pub coarse: Vec<Option<Experiment>>,
}

impl Campaign {
    /// The lower flow-stress realism limit (Pa): the campaign's `min_flow_stress`, or
    /// [`FLOOR_FRACTION`] of the starting material's flow stress at plastic strain 0, 1 /s and
    /// 298 K; 0 for a starting material without a J2 flow stress (concrete).
    pub fn flow_stress_floor(&self) -> f64 {
        if let Some(floor) = self.file.constraints.min_flow_stress {
            return floor;
        }
        match self.base.material() {
            Ok(material) => material.j2().map_or(0.0, |metal| {
                FLOOR_FRACTION * metal.strength.flow_stress(0.0, 1.0, 298.0).value
            }),
            Err(_) => 0.0,
        }
    }

    /// The campaign's model entry named `name`.
    pub fn model(&self, name: &str) -> Option<&ModelEntry> {
        self.file.models.iter().find(|m| m.name == name)
    }

    /// Load a campaign, its base material and every experiment. Errors name file, line, field.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let text = input::read_text(path)?;
        let document = input::parse_document(path, &text)?;
        let file: CampaignFile = input::typed(path, &document.si)?;
        check_bound_pairs(path, &text, &document.tree)?;
        let folder = path.parent().unwrap_or(Path::new("."));
        let (base, _) = material::load_part(&folder.join(&file.material))?;
        check_models(path, &text, &file)?;
        check_experiments_and_optimiser(path, &text, &file)?;
        let experiments = file
            .experiments
            .iter()
            .map(|entry| Experiment::load(&folder.join(&entry.file)))
            .collect::<Result<Vec<_>, _>>()?;
        check_experiments_accept(path, &text, &file, &base, &experiments)?;
        let coarse = coarse_experiments(path, &text, &file, &experiments)?;
        let campaign = Self {
            path: path.into(),
            file,
            base,
            experiments,
            coarse,
        };
        for (index, model) in campaign.file.models.iter().enumerate() {
            campaign.check_model(path, &text, index, model)?;
        }
        Ok(campaign)
    }

    /// A model's bounds, constants and middle material (its `[[models]]` entry `index`).
    fn check_model(
        &self,
        path: &Path,
        text: &str,
        index: usize,
        model: &ModelEntry,
    ) -> Result<(), InputError> {
        let campaign = self;
        let index = index.to_string();
        let at = |keys: &[&str]| -> Vec<String> {
            ["models", index.as_str()]
                .iter()
                .chain(keys)
                .map(|k| k.to_string())
                .collect()
        };
        let error_at = |keys: &[&str], message: String| {
            let keys = at(keys);
            let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
            InputError::at(path, text, &keys, message)
        };
        let space = campaign.space(model);
        for (name, [lower, upper]) in &model.parameters {
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(error_at(
                    &["parameters", name],
                    format!("bounds [{lower}, {upper}] must be finite with lower < upper"),
                ));
            }
        }
        self.check_setup(model, &error_at)?;
        let middle: Vec<f64> = space
            .lower
            .iter()
            .zip(&space.upper)
            .map(|(l, u)| 0.5 * (l + u))
            .collect();
        if matches!(
            campaign.base,
            AnyMaterialFile::Rht(_) | AnyMaterialFile::Kc(_)
        ) && model.strength.is_some()
        {
            return Err(error_at(
                &["strength"],
                format!(
                    "model {}: a concrete campaign (RHT or K&C) has no flow-stress model; \
                     fit its constants by their dotted paths in [models.parameters]",
                    model.name
                ),
            ));
        }
        if let Some(strength) = &space.strength {
            let described = strength.constants();
            let constants: Vec<&str> = described.iter().map(|(n, _)| n.as_str()).collect();
            let listed: Vec<String> = described
                .iter()
                .map(|(n, p)| format!("{n} ({}, {})", p.symbol, p.unit))
                .collect();
            if let Some(name) = space.names[..space.constant_count()]
                .iter()
                .find(|n| !constants.contains(&n.as_str()))
            {
                return Err(error_at(
                    &["parameters", name],
                    format!(
                        "model {}: `{name}` is not a constant of this model; its constants \
                         are {}",
                        model.name,
                        listed.join(", ")
                    ),
                ));
            }
        }
        if let Err(message) = space.material(&campaign.base, &middle) {
            return Err(error_at(
                &["parameters"],
                format!("model {}: {message}", model.name),
            ));
        }
        // The box, not only its middle (issue 52, item 4): a bound that makes the model
        // invalid (a negative exponent, a reference temperature above the melting one) would
        // let infeasible candidates run and fail one by one. Every corner when the constants
        // are few (the kernel's constraints are intervals of one or two constants, so the
        // corners hold the extremes); else each constant at its bounds, the others in the
        // middle.
        let constants = space.constant_count();
        let corners: Vec<Vec<f64>> = if constants <= MAXIMUM_CORNER_CONSTANTS {
            (0..(1_usize << constants))
                .map(|corner| {
                    let mut values = middle.clone();
                    for (k, value) in values.iter_mut().take(constants).enumerate() {
                        *value = if (corner >> k) & 1 == 0 {
                            space.lower[k]
                        } else {
                            space.upper[k]
                        };
                    }
                    values
                })
                .collect()
        } else {
            (0..constants)
                .flat_map(|k| {
                    [space.lower[k], space.upper[k]].map(|bound| {
                        let mut values = middle.clone();
                        values[k] = bound;
                        values
                    })
                })
                .collect()
        };
        for values in &corners {
            if let Err(message) = space.material(&campaign.base, values) {
                // Name the first constant whose bound the corner takes and which alone makes
                // the model invalid; else the corner as a whole.
                let culprit = (0..constants).find(|&k| {
                    let mut single = middle.clone();
                    single[k] = values[k];
                    values[k] != middle[k] && space.material(&campaign.base, &single).is_err()
                });
                let corner: Vec<String> = (0..constants)
                    .map(|k| format!("{} = {}", space.names[k], values[k]))
                    .collect();
                return Err(match culprit {
                    Some(k) => error_at(
                        &["parameters", &space.names[k]],
                        format!(
                            "model {}: at its bound {} the model is invalid: {message}",
                            model.name, values[k]
                        ),
                    ),
                    None => error_at(
                        &["parameters"],
                        format!(
                            "model {}: the bounds allow an invalid model at the corner {}: \
                             {message}",
                            model.name,
                            corner.join(", ")
                        ),
                    ),
                });
            }
        }
        Ok(())
    }

    /// A model's `[models.setup]`: each key names experiments and a field they may
    /// calibrate, its bounds are finite and ordered, and every experiment it names is a valid
    /// set-up at every corner of the set-up box (each parameter at either bound), checked with
    /// the experiment kind's own rules.
    fn check_setup(
        &self,
        model: &ModelEntry,
        error_at: &dyn Fn(&[&str], String) -> InputError,
    ) -> Result<(), InputError> {
        let mut parameters = Vec::new();
        for (key, &[lower, upper]) in &model.setup {
            let parameter = self.setup_parameter(key).map_err(|message| {
                error_at(&["setup", key], format!("model {}: {message}", model.name))
            })?;
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(error_at(
                    &["setup", key],
                    format!("bounds [{lower}, {upper}] must be finite with lower < upper"),
                ));
            }
            parameters.push((key, parameter, [lower, upper]));
        }
        if parameters.len() > MAX_SETUP_PARAMETERS {
            return Err(error_at(
                &["setup"],
                format!(
                    "model {}: {} set-up parameters; at most {MAX_SETUP_PARAMETERS}",
                    model.name,
                    parameters.len()
                ),
            ));
        }
        for corner in 0..(1_usize << parameters.len()) {
            let values: Vec<SetupValue> = parameters
                .iter()
                .enumerate()
                .map(|(bit, (key, p, bounds))| SetupValue {
                    name: format!("{SETUP_PREFIX}{key}"),
                    field: p.field.clone(),
                    experiments: p.experiments.clone(),
                    value: bounds[(corner >> bit) & 1],
                })
                .collect();
            for experiment in &self.experiments {
                let stem = experiment_stem(experiment);
                let Some((key, _, _)) = parameters
                    .iter()
                    .find(|(_, p, _)| p.experiments.contains(&stem))
                else {
                    continue;
                };
                let changed = with_setup(experiment, &values)
                    .map_err(|message| error_at(&["setup", key], message))?;
                let corner_text: Vec<String> = parameters
                    .iter()
                    .zip(&values)
                    .filter(|((_, p, _), _)| p.experiments.contains(&stem))
                    .map(|((k, _, _), v)| format!("{k} = {}", v.value))
                    .collect();
                let check = |field: &str, ok: bool, message: &str| {
                    if ok {
                        Ok(())
                    } else {
                        Err(error_at(
                            &["setup", key],
                            format!(
                                "model {}: at {} the set-up of {stem} is invalid: {field}: \
                                 {message}",
                                model.name,
                                corner_text.join(", ")
                            ),
                        ))
                    }
                };
                changed.file.setup.validate(&check)?;
                let [low, high] = crate::experiment::RECORDED_SCALE_RANGE;
                let scale = changed.file.recorded_scale;
                check(
                    RECORDED_SCALE,
                    (low..=high).contains(&scale),
                    &format!("{scale} lies outside {low}..={high}"),
                )?;
            }
        }
        Ok(())
    }

    /// The resolved search space of a model.
    pub fn space(&self, model: &ModelEntry) -> ModelSpace {
        let (mut names, mut bounds): (Vec<String>, Vec<[f64; 2]>) = model
            .parameters
            .iter()
            .map(|(n, b)| (n.clone(), *b))
            .unzip();
        let mut setup = Vec::new();
        for (key, range) in &model.setup {
            let Ok(parameter) = self.setup_parameter(key) else {
                // Refused when the campaign loads ([`Campaign::check_model`]).
                continue;
            };
            names.push(format!("{SETUP_PREFIX}{key}"));
            bounds.push(*range);
            setup.push(parameter);
        }
        ModelSpace {
            setup,
            name: model.name.clone(),
            strength: match &self.base {
                AnyMaterialFile::J2(base) => Some(model.strength.unwrap_or(base.strength)),
                AnyMaterialFile::Rht(_) | AnyMaterialFile::Kc(_) => None,
            },
            names,
            lower: bounds.iter().map(|b| b[0]).collect(),
            upper: bounds.iter().map(|b| b[1]).collect(),
        }
    }

    /// The set-up parameter `"<target>.<field>"` of `[models.setup]`: the experiments it
    /// names (by file stem, or every one of a kind) and the value their files give; an error
    /// says what is wrong and what is allowed.
    pub fn setup_parameter(&self, key: &str) -> Result<SetupParameter, String> {
        let Some((target, field)) = key.rsplit_once('.') else {
            return Err(format!(
                "`{key}`: write \"<experiment file stem or kind>.<field>\" = [lower, upper]"
            ));
        };
        let stems: Vec<String> = self.experiments.iter().map(experiment_stem).collect();
        let by_stem: Vec<usize> = (0..stems.len()).filter(|&i| stems[i] == target).collect();
        let by_kind: Vec<usize> = (0..stems.len())
            .filter(|&i| crate::experiment::kind_name(&self.experiments[i].file.setup) == target)
            .collect();
        let by_group: Vec<usize> = (0..stems.len())
            .filter(|&i| self.experiments[i].file.source_group.as_deref() == Some(target))
            .collect();
        if !by_group.is_empty() {
            if !by_stem.is_empty() || !by_kind.is_empty() {
                return Err(format!(
                    "`{target}` is a source group and also an experiment's file stem or kind: \
                     rename the group"
                ));
            }
            if field != RECORDED_SCALE {
                return Err(format!(
                    "`{field}`: a source group (`{target}`) has one set-up field, \
                     `{RECORDED_SCALE}` (its recordings' systematic scale)"
                ));
            }
            return Ok(SetupParameter {
                field: field.to_string(),
                experiments: by_group.iter().map(|&i| stems[i].clone()).collect(),
                start: self.experiments[by_group[0]].file.recorded_scale,
            });
        }
        let chosen = match (by_stem.is_empty(), by_kind.is_empty()) {
            (false, true) if by_stem.len() == 1 => by_stem,
            (false, true) => {
                return Err(format!(
                    "`{target}` names {} experiments of the campaign (files of one stem in \
                     different folders): rename one",
                    by_stem.len()
                ))
            }
            (true, false) => by_kind,
            (false, false) => {
                return Err(format!(
                    "`{target}` is both an experiment's file stem and an experiment kind: \
                     rename the file"
                ))
            }
            (true, true) => {
                let kinds: std::collections::BTreeSet<&str> = self
                    .experiments
                    .iter()
                    .map(|e| crate::experiment::kind_name(&e.file.setup))
                    .collect();
                let groups: std::collections::BTreeSet<&str> = self
                    .experiments
                    .iter()
                    .filter_map(|e| e.file.source_group.as_deref())
                    .collect();
                let groups = if groups.is_empty() {
                    String::new()
                } else {
                    format!(
                        " nor a source group ({})",
                        groups.into_iter().collect::<Vec<_>>().join(", ")
                    )
                };
                return Err(format!(
                    "`{target}` is neither an experiment of the campaign (file stems: {}) nor \
                     the kind of one ({}){groups}",
                    stems.join(", "),
                    kinds.into_iter().collect::<Vec<_>>().join(", ")
                ));
            }
        };
        if field == RECORDED_SCALE {
            return Ok(SetupParameter {
                field: field.to_string(),
                experiments: chosen.iter().map(|&i| stems[i].clone()).collect(),
                start: self.experiments[chosen[0]].file.recorded_scale,
            });
        }
        let mut start = None;
        for &i in &chosen {
            let experiment = &self.experiments[i];
            let mut setup = experiment.file.setup.clone();
            let allowed = setup.calibratable_fields();
            match setup.calibratable_mut(field) {
                Some(value) => {
                    start.get_or_insert(*value);
                }
                None if allowed.contains(&field) => {
                    return Err(format!(
                        "`{field}`: {} gives no value for it; give one in its [setup] first",
                        stems[i]
                    ))
                }
                None => {
                    return Err(format!(
                        "`{field}` is not a set-up field a {} experiment may calibrate ({}); \
                         those are: {}",
                        crate::experiment::kind_name(&experiment.file.setup),
                        stems[i],
                        allowed.join(", ")
                    ))
                }
            }
        }
        Ok(SetupParameter {
            field: field.to_string(),
            experiments: chosen.iter().map(|&i| stems[i].clone()).collect(),
            start: start.unwrap_or_default(),
        })
    }

    /// Whether any experiment has a coarse fidelity (a multi-fidelity calibration).
    pub fn is_multi_fidelity(&self) -> bool {
        self.coarse.iter().any(Option::is_some)
    }

    /// Indices of the fitted (not held-out) experiments.
    pub fn fitted(&self) -> Vec<usize> {
        (0..self.experiments.len())
            .filter(|&i| !self.file.experiments[i].holdout)
            .collect()
    }
}

/// Each experiment's coarse fidelity: its set-up with every element size multiplied by its
/// entry's `coarse` factor, checked by the kind's own rules. Errors name the entry's field.
fn coarse_experiments(
    path: &Path,
    text: &str,
    file: &CampaignFile,
    experiments: &[Experiment],
) -> Result<Vec<Option<Experiment>>, InputError> {
    file.experiments
        .iter()
        .zip(experiments)
        .enumerate()
        .map(|(index, (entry, experiment))| {
            let Some(factor) = entry.coarse else {
                return Ok(None);
            };
            let keys = ["experiments", &index.to_string(), "coarse"];
            let error = |message: String| InputError::at(path, text, &keys, message);
            if !(factor > 1.0 && factor <= MAXIMUM_COARSE_FACTOR) {
                return Err(error(format!(
                    "{}: {factor} is not a coarse factor: give the factor on the element \
                     size, above 1 and at most {MAXIMUM_COARSE_FACTOR}",
                    entry.file
                )));
            }
            let (change, setup) = experiment
                .file
                .setup
                .with_element_scale(factor)
                .map_err(|message| error(format!("{}: {message}", entry.file)))?;
            let check = |field: &str, ok: bool, message: &str| {
                if ok {
                    Ok(())
                } else {
                    Err(error(format!(
                        "{}: at the coarse factor {factor} ({change}) the set-up is invalid: \
                         {field}: {message}",
                        entry.file
                    )))
                }
            };
            setup.validate(&check)?;
            let mut coarse = experiment.clone();
            coarse.file.setup = setup;
            Ok(Some(coarse))
        })
        .collect()
}

/// Fitted constants up to which every corner of a model's box is checked at load (2^10
/// material validations, a few milliseconds); above, each constant at its bounds.
const MAXIMUM_CORNER_CONSTANTS: usize = 10;

/// Bounds are `[lower, upper]`: serde reads the first two numbers of a longer array and would
/// drop the rest silently.
fn check_bound_pairs(path: &Path, text: &str, tree: &toml::Table) -> Result<(), InputError> {
    let models = tree.get("models").and_then(toml::Value::as_array);
    for (index, model) in models.into_iter().flatten().enumerate() {
        for table in ["parameters", "setup"] {
            let parameters = model.get(table).and_then(toml::Value::as_table);
            for (name, bounds) in parameters.into_iter().flatten() {
                if let Some(items) = bounds.as_array().filter(|a| a.len() != 2) {
                    return Err(InputError::at(
                        path,
                        text,
                        &["models", &index.to_string(), table, name],
                        format!("give [lower, upper], not {} numbers", items.len()),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// At least one model, each with its own name.
fn check_models(path: &Path, text: &str, file: &CampaignFile) -> Result<(), InputError> {
    if file.models.is_empty() {
        return Err(InputError::field(
            path,
            text,
            "models",
            "at least one [[models]] entry is needed",
        ));
    }
    for (k, model) in file.models.iter().enumerate() {
        if file.models[..k].iter().any(|m| m.name == model.name) {
            return Err(InputError::Field {
                path: path.into(),
                line: text
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| {
                        let l = l.trim_start();
                        l.starts_with("name") && l.contains(&format!("\"{}\"", model.name))
                    })
                    .nth(1)
                    .map(|(i, _)| i + 1),
                field: "name".into(),
                message: format!(
                    "model name `{}` is used twice: each [[models]] entry needs its own name \
                     (the run log and the report are keyed by it)",
                    model.name
                ),
            });
        }
    }
    Ok(())
}

/// At least one fitted experiment, positive weights, and the optimiser's and executor's
/// settings in range.
fn check_experiments_and_optimiser(
    path: &Path,
    text: &str,
    file: &CampaignFile,
) -> Result<(), InputError> {
    if file.experiments.iter().all(|e| e.holdout) {
        return Err(InputError::field(
            path,
            text,
            "experiments",
            "at least one experiment must be fitted (holdout = false)",
        ));
    }
    for (index, entry) in file.experiments.iter().enumerate() {
        // One recording fitted twice would count twice: refused (issue 52, item 1).
        if let Some(first) = file.experiments[..index]
            .iter()
            .position(|other| other.file == entry.file)
        {
            return Err(InputError::at(
                path,
                text,
                &["experiments", &index.to_string(), "file"],
                format!(
                    "{} is listed twice (also experiment {}): each experiment once",
                    entry.file,
                    first + 1
                ),
            ));
        }
        if !(entry.weight > 0.0 && entry.weight.is_finite()) {
            return Err(InputError::at(
                path,
                text,
                &["experiments", &index.to_string(), "weight"],
                format!("{}: must be > 0", entry.file),
            ));
        }
    }
    let o = &file.optimiser;
    // Each size is named by its own field (a `parallel = 0` once read as a budget error).
    for (field, ok, message) in [
        (
            "budget",
            o.budget >= 4,
            "give at least 4 simulations per instance (the initial design)",
        ),
        ("instances", o.instances >= 1, "give at least 1"),
        (
            "fine_every",
            o.fine_every >= 1,
            "give at least 1 (one in this many search candidates is checked at the fine mesh)",
        ),
        (
            "parallel",
            o.parallel >= 1,
            "give at least 1 (simulations at once)",
        ),
    ] {
        if !ok {
            return Err(InputError::field(path, text, field, message));
        }
    }
    // A feasible band that is empty would reject every candidate one by one.
    let constraints = &file.constraints;
    if let Some(min) = constraints.min_flow_stress {
        if min >= constraints.max_flow_stress {
            return Err(InputError::field(
                path,
                text,
                "max_flow_stress",
                format!(
                    "{} Pa is not above min_flow_stress ({min} Pa): no candidate could be \
                     feasible",
                    constraints.max_flow_stress
                ),
            ));
        }
    }
    if o.design == Some(0) || o.design.is_some_and(|d| d > o.budget) {
        return Err(InputError::field(
            path,
            text,
            "design",
            format!("must be between 1 and the budget ({})", o.budget),
        ));
    }
    // Options that would be silently ignored are errors (issue 52, item 5).
    let fitted = file.experiments.iter().filter(|e| !e.holdout).count();
    if o.leave_one_out != LeaveOneOut::Off && fitted < 2 {
        return Err(InputError::field(
            path,
            text,
            "leave_one_out",
            format!(
                "leave-one-out needs at least 2 fitted experiments; the campaign fits {fitted} \
                 (set leave_one_out = false, or fit more experiments)"
            ),
        ));
    }
    if o.fold_budget.is_some() && o.leave_one_out == LeaveOneOut::Off {
        return Err(InputError::field(
            path,
            text,
            "fold_budget",
            "takes effect only with leave-one-out: set leave_one_out = true or \"selected\", \
             or remove fold_budget",
        ));
    }
    if o.fold_budget == Some(0) {
        return Err(InputError::field(
            path,
            text,
            "fold_budget",
            "must be at least 1 (leave it out for independent folds)",
        ));
    }
    // A fixed bound, not one from this machine's cores: `parallel` sets the optimiser's
    // batch, so the same campaign must mean the same run everywhere.
    if o.parallel > crate::solver::explicit::MAXIMUM_THREADS {
        return Err(InputError::field(
            path,
            text,
            "parallel",
            format!(
                "{} simulations at once is more than the {} stoss runs at most (each is a \
                 thread; this machine has {} cores)",
                o.parallel,
                crate::solver::explicit::MAXIMUM_THREADS,
                std::thread::available_parallelism().map_or(1, usize::from)
            ),
        ));
    }
    if let Err((field, message)) = file.executor.check() {
        return Err(InputError::field(
            path,
            text,
            &format!("executor.{field}"),
            message,
        ));
    }
    Ok(())
}

/// Every experiment's set-up accepts the campaign's material family.
fn check_experiments_accept(
    path: &Path,
    text: &str,
    file: &CampaignFile,
    base: &AnyMaterialFile,
    experiments: &[Experiment],
) -> Result<(), InputError> {
    if let Ok(family) = base.material() {
        for (index, (entry, experiment)) in file.experiments.iter().zip(experiments).enumerate() {
            if let Err(error) = experiment.file.setup.accepts(&family) {
                return Err(InputError::at(
                    path,
                    text,
                    &["experiments", &index.to_string(), "file"],
                    format!("{}: {error} (the campaign's material)", entry.file),
                ));
            }
        }
    }
    Ok(())
}
