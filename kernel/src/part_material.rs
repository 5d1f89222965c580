//! The material of one part of a mesh: any of the kernel's point models, chosen per part, as
//! the parts of an LS-DYNA or Autodyn model carry different `*MAT` cards (a steel projectile
//! against a concrete target).

use crate::error::{ParameterError, UpdateError};
use crate::j2::Material;
use crate::kc::KcMaterial;
use crate::point_model::PointModel;
use crate::point_model::{StepInput, StepOutput, LANES};
use crate::rht::RhtMaterial;
use crate::state::{MaterialState, StateFlags};
use crate::tensor::Matrix6;

/// One part's material model. Every call dispatches to the variant's own update, so a J2
/// metal computes exactly what [`crate::update()`] computes, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum PartMaterial {
    /// A J2 metal: flow-stress model, EoS, heating, damage ([`Material`]).
    J2(Material),
    /// RHT concrete over its EoS ([`RhtMaterial`]).
    Rht(RhtMaterial),
    /// Karagozian & Case concrete over its EoS ([`KcMaterial`]).
    Kc(KcMaterial),
}

impl PartMaterial {
    /// The model family's name, for messages: `"J2 metal"`, `"RHT concrete"` or
    /// `"K&C concrete"`.
    pub fn family(&self) -> &'static str {
        match self {
            PartMaterial::J2(_) => "J2 metal",
            PartMaterial::Rht(_) => "RHT concrete",
            PartMaterial::Kc(_) => "K&C concrete",
        }
    }

    /// The J2 metal, if this is one.
    pub fn j2(&self) -> Option<&Material> {
        match self {
            PartMaterial::J2(material) => Some(material),
            PartMaterial::Rht(_) | PartMaterial::Kc(_) => None,
        }
    }

    /// The K&C concrete, if this is one.
    pub fn kc(&self) -> Option<&KcMaterial> {
        match self {
            PartMaterial::J2(_) | PartMaterial::Rht(_) => None,
            PartMaterial::Kc(material) => Some(material),
        }
    }

    /// The RHT concrete, if this is one.
    pub fn rht(&self) -> Option<&RhtMaterial> {
        match self {
            PartMaterial::J2(_) | PartMaterial::Kc(_) => None,
            PartMaterial::Rht(material) => Some(material),
        }
    }
}

impl From<Material> for PartMaterial {
    fn from(material: Material) -> Self {
        PartMaterial::J2(material)
    }
}

impl From<KcMaterial> for PartMaterial {
    fn from(material: KcMaterial) -> Self {
        PartMaterial::Kc(material)
    }
}

impl From<RhtMaterial> for PartMaterial {
    fn from(material: RhtMaterial) -> Self {
        PartMaterial::Rht(material)
    }
}

impl PointModel for PartMaterial {
    fn validate(&self) -> Result<(), ParameterError> {
        match self {
            PartMaterial::J2(m) => PointModel::validate(m),
            PartMaterial::Rht(m) => PointModel::validate(m),
            PartMaterial::Kc(m) => PointModel::validate(m),
        }
    }

    fn shear_modulus(&self) -> f64 {
        match self {
            PartMaterial::J2(m) => PointModel::shear_modulus(m),
            PartMaterial::Rht(m) => PointModel::shear_modulus(m),
            PartMaterial::Kc(m) => PointModel::shear_modulus(m),
        }
    }

    fn density(&self) -> f64 {
        match self {
            PartMaterial::J2(m) => PointModel::density(m),
            PartMaterial::Rht(m) => PointModel::density(m),
            PartMaterial::Kc(m) => PointModel::density(m),
        }
    }

    fn initial_state(&self, temperature: f64) -> MaterialState {
        match self {
            PartMaterial::J2(m) => PointModel::initial_state(m, temperature),
            PartMaterial::Rht(m) => PointModel::initial_state(m, temperature),
            PartMaterial::Kc(m) => PointModel::initial_state(m, temperature),
        }
    }

    fn kinematic_strain_bound(&self) -> Option<f64> {
        match self {
            PartMaterial::J2(m) => m.kinematic_strain_bound(),
            PartMaterial::Rht(m) => m.kinematic_strain_bound(),
            PartMaterial::Kc(m) => m.kinematic_strain_bound(),
        }
    }

    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        match self {
            PartMaterial::J2(m) => m.kinematic_flags(principal_strains),
            PartMaterial::Rht(m) => m.kinematic_flags(principal_strains),
            PartMaterial::Kc(m) => m.kinematic_flags(principal_strains),
        }
    }

    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        match self {
            PartMaterial::J2(m) => PointModel::update(m, state, input),
            PartMaterial::Rht(m) => PointModel::update(m, state, input),
            PartMaterial::Kc(m) => PointModel::update(m, state, input),
        }
    }

    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        match self {
            PartMaterial::J2(m) => PointModel::update_with_tangent(m, state, input, tangent),
            PartMaterial::Rht(m) => PointModel::update_with_tangent(m, state, input, tangent),
            PartMaterial::Kc(m) => PointModel::update_with_tangent(m, state, input, tangent),
        }
    }
    fn update_lanes(
        &self,
        states: &mut [MaterialState; LANES],
        inputs: &[StepInput; LANES],
        results: &mut [Result<StepOutput, UpdateError>; LANES],
    ) {
        match self {
            PartMaterial::J2(m) => PointModel::update_lanes(m, states, inputs, results),
            PartMaterial::Rht(m) => PointModel::update_lanes(m, states, inputs, results),
            PartMaterial::Kc(m) => PointModel::update_lanes(m, states, inputs, results),
        }
    }
}
