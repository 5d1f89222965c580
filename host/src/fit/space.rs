//! The search space of a model: its fitted constants by name with their search bounds
//! (SI), and the strength or concrete file they are written into, then its set-up parameters
//! (nuisance parameters: fields of experiments' set-ups searched beside the constants, never
//! written into a material). Built by a campaign (`Campaign::space` in the calibration) and
//! read by both the calibration and the diagnosis; bounds map to unit coordinates through
//! [`super::unit_cube`].

use crate::experiment::Experiment;
use crate::input::material::{AnyMaterialFile, StrengthSpec};
use serde::{Deserialize, Serialize};
use stoss_kernel::parameters::ConstantPaths;
use stoss_kernel::PartMaterial;

/// A model of a campaign, resolved: its strength and the names and bounds of its fitted
/// constants.
#[derive(Clone, Debug)]
pub struct ModelSpace {
    /// Model name.
    pub name: String,
    /// Starting strength (fitted constants are overwritten); `None` for RHT concrete, whose
    /// constants are edited in the base file itself.
    pub strength: Option<StrengthSpec>,
    /// Searched names: the fitted constants, then the set-up parameters (`setup.<target>.<field>`,
    /// in the order of [`ModelSpace::setup`]).
    pub names: Vec<String>,
    /// Lower bounds.
    pub lower: Vec<f64>,
    /// Upper bounds.
    pub upper: Vec<f64>,
    /// The set-up parameters: the last `setup.len()` entries of `names`, `lower`, `upper`.
    pub setup: Vec<SetupParameter>,
}

/// A set-up field searched beside the constants (`[models.setup]`), shared by every
/// experiment it names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetupParameter {
    /// The set-up field (one of its kind's [`crate::experiment::Setup::calibratable_fields`]).
    pub field: String,
    /// The experiments whose set-up holds it, by their files' stems.
    pub experiments: Vec<String>,
    /// The value the experiments' files give (the first one's), SI.
    pub start: f64,
}

/// A set-up field at a value, as a realised hypothesis carries it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetupValue {
    /// The parameter's name (`setup.<target>.<field>`).
    pub name: String,
    /// The set-up field.
    pub field: String,
    /// The experiments it applies to, by their files' stems.
    pub experiments: Vec<String>,
    /// Its value (SI).
    pub value: f64,
}

/// The prefix of a set-up parameter's name.
pub const SETUP_PREFIX: &str = "setup.";

/// The stem of an experiment's file: how `[models.setup]` names it.
pub fn experiment_stem(experiment: &Experiment) -> String {
    experiment
        .path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// `experiment` with the set-up values that name it written in (borrowed if none does).
pub fn with_setup<'e>(
    experiment: &'e Experiment,
    values: &[SetupValue],
) -> Result<std::borrow::Cow<'e, Experiment>, String> {
    let stem = experiment_stem(experiment);
    let mine: Vec<&SetupValue> = values
        .iter()
        .filter(|v| v.experiments.contains(&stem))
        .collect();
    if mine.is_empty() {
        return Ok(std::borrow::Cow::Borrowed(experiment));
    }
    let mut changed = experiment.clone();
    for value in mine {
        if value.field == crate::experiment::RECORDED_SCALE {
            changed.file.recorded_scale = value.value;
            continue;
        }
        let slot = changed
            .file
            .setup
            .calibratable_mut(&value.field)
            .ok_or_else(|| {
                format!(
                    "{}: set-up field `{}` cannot be calibrated",
                    experiment.file.name, value.field
                )
            })?;
        *slot = value.value;
    }
    Ok(std::borrow::Cow::Owned(changed))
}

impl ModelSpace {
    /// Number of fitted material constants (the first entries of `names`).
    pub fn constant_count(&self) -> usize {
        self.names.len() - self.setup.len()
    }

    /// The set-up values of a point of the space (its last `setup.len()` values).
    pub fn setup_values(&self, values: &[f64]) -> Vec<SetupValue> {
        let first = self.constant_count();
        self.setup
            .iter()
            .zip(&self.names[first..])
            .zip(values.iter().skip(first))
            .map(|((parameter, name), &value)| SetupValue {
                name: name.clone(),
                field: parameter.field.clone(),
                experiments: parameter.experiments.clone(),
                value,
            })
            .collect()
    }

    /// The strength with `values` for the fitted constants (J2 metals).
    pub fn strength_with(&self, values: &[f64]) -> Result<StrengthSpec, String> {
        let mut strength = self.strength.ok_or_else(|| {
            format!(
                "model {} has no flow-stress model (RHT concrete)",
                self.name
            )
        })?;
        let constants = self.constant_count();
        for (name, value) in self.names[..constants].iter().zip(values) {
            strength
                .set(name, *value)
                .ok_or_else(|| format!("`{name}` is not a constant of this model"))?;
        }
        Ok(strength)
    }

    /// The kernel material: the campaign's base material with this model's constants, and
    /// the material file that says so.
    pub fn material(
        &self,
        base: &AnyMaterialFile,
        values: &[f64],
    ) -> Result<(AnyMaterialFile, PartMaterial), String> {
        let mut file = base.clone();
        if let AnyMaterialFile::J2(metal) = &mut file {
            metal.strength = self.strength_with(values)?;
        } else {
            let family = file.family_mut();
            let constants = self.constant_count();
            for (name, value) in self.names[..constants].iter().zip(values) {
                let (kind, paths) = (family.family(), family.constant_paths());
                *family.constant_slot(name).ok_or_else(|| {
                    format!("`{name}` is not a constant of the {kind} file ({paths})")
                })? = *value;
            }
        }
        let material = file.material().map_err(|e| e.to_string())?;
        Ok((file, material))
    }

    /// The starting values of the fitted constants: what the model's strength (or the base
    /// material file) holds before any fit. `None` if a name is not found.
    pub fn starting_values(&self, base: &AnyMaterialFile) -> Option<Vec<f64>> {
        let constants = self.constant_count();
        self.names[..constants]
            .iter()
            .map(|name| match (&self.strength, base) {
                (Some(strength), _) => strength.get(name),
                // A metal's fitted constants are its strength model's.
                (None, AnyMaterialFile::J2(_)) => None,
                (None, _) => base
                    .clone()
                    .family_mut()
                    .constant_slot(name)
                    .map(|value| *value),
            })
            .chain(self.setup.iter().map(|p| Some(p.start)))
            .collect()
    }

    /// The SI unit of each fitted constant, from the model's descriptions (`?` for a name
    /// no description covers; the campaign refuses those when it loads).
    pub fn units(&self, base: &AnyMaterialFile) -> Vec<&'static str> {
        let strength = self.strength.map(|s| s.constants()).unwrap_or_default();
        let constants = self.constant_count();
        self.names[..constants]
            .iter()
            .map(|name| {
                if let Some((_, p)) = strength.iter().find(|(n, _)| n == name) {
                    return p.unit;
                }
                base.family().constant_unit(name).unwrap_or("?")
            })
            .chain(self.setup.iter().map(|p| {
                crate::input::units::field_dimension(&p.field)
                    .map_or("-", crate::input::units::Dimension::si_unit)
            }))
            .collect()
    }

    /// The symbol of each fitted material constant in its model's equation (`A`, `n`, `C1`),
    /// from the model's descriptions; a constant no description covers (a concrete's dotted
    /// path) is shown by its last path segment.
    pub fn symbols(&self) -> Vec<String> {
        let strength = self.strength.map(|s| s.constants()).unwrap_or_default();
        self.names[..self.constant_count()]
            .iter()
            .map(|name| {
                strength.iter().find(|(n, _)| n == name).map_or_else(
                    || name.rsplit('.').next().unwrap_or(name).to_string(),
                    |(_, p)| p.symbol.to_string(),
                )
            })
            .collect()
    }

    /// Dimension of the search space.
    pub fn dimension(&self) -> usize {
        self.names.len()
    }

    /// The search range of every dimension, `(lower, upper)`, as the optimisers take it.
    pub fn bound_pairs(&self) -> Vec<(f64, f64)> {
        self.lower
            .iter()
            .copied()
            .zip(self.upper.iter().copied())
            .collect()
    }
}

/// Fraction of a search range within which a fitted constant counts as at its bound.
pub const AT_BOUND: f64 = 0.005;

/// The constants of `values` within [`AT_BOUND`] of the search range of a bound, described
/// (`n = 1.000e0 at its upper bound 1.000e0`).
pub fn constants_at_bounds(space: &ModelSpace, values: &[f64]) -> Vec<String> {
    space
        .names
        .iter()
        .zip(values)
        .zip(space.lower.iter().zip(&space.upper))
        .filter_map(|((name, value), (lower, upper))| at_bound(name, *value, *lower, *upper))
        .collect()
}

/// `name = value` described if it lies within [`AT_BOUND`] of the range `[lower, upper]` of a
/// bound (`n = 1.000e0 at its upper bound 1.000e0`), else `None`.
pub fn at_bound(name: &str, value: f64, lower: f64, upper: f64) -> Option<String> {
    let margin = AT_BOUND * (upper - lower);
    if value <= lower + margin {
        Some(format!(
            "{name} = {value:.4e} at its lower bound {lower:.4e}"
        ))
    } else if value >= upper - margin {
        Some(format!(
            "{name} = {value:.4e} at its upper bound {upper:.4e}"
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_within_half_a_percent_of_a_bound_are_flagged() {
        // GOAL: a fit that ends at a bound says so.
        // SETUP: bounds [0, 1] for two constants; values 0.004, 0.5, 0.996, 0.006.
        // REFERENCE: 0.5 % of the range: 0.004 (lower) and 0.996 (upper) flagged, not 0.006.
        let space = ModelSpace {
            setup: Vec::new(),
            name: "jc".into(),
            strength: None,
            names: vec!["n".into(), "C".into()],
            lower: vec![0.0, 0.0],
            upper: vec![1.0, 1.0],
        };
        let flagged = constants_at_bounds(&space, &[0.004, 0.5]);
        assert_eq!(flagged.len(), 1);
        assert!(flagged[0].starts_with("n = 4.0000e-3 at its lower bound"));
        let flagged = constants_at_bounds(&space, &[0.996, 0.006]);
        assert_eq!(flagged.len(), 1);
        assert!(flagged[0].contains("at its upper bound"));
    }
}
