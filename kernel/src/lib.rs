//! # stoss-kernel
//!
//! Deterministic, fixed-size constitutive updates for metals and concrete under impact, for
//! one integration point and one time step. No heap, no `std`, no platform float functions:
//! every transcendental goes through [`libm`], so a history computed here is bit-identical on
//! every target and inside every host (stoss's own solver, or a foreign FE code through the
//! C ABI).
//!
//! Layout (one concept, one home):
//! - [`tensor`]: symmetric 3x3 tensors in Voigt order `xx yy zz xy yz zx`, tensor shear.
//! - [`strength`]: flow-stress models built from composable terms (hardening, rate, thermal),
//!   plus Zerilli-Armstrong, which couples rate and temperature.
//! - [`eos`]: equations of state (pressure from compression and internal energy).
//! - [`damage`]: Johnson-Cook failure and the erosion flags shared by every model.
//! - [`parameters`]: one description (name, symbol, unit, search range) per model constant.
//! - [`point_model`]: the [`PointModel`] trait every law implements, and the step's input and
//!   output.
//! - [`j2`]: J2 metals: a complete material (elasticity, strength, heating, EoS, damage) and
//!   its stress update (EoS, elastic predictor, implicit or lagged radial return, heating,
//!   damage, failure, the consistent tangent and the wave speed).
//! - [`rht`] and [`kc`]: the RHT and Karagozian & Case concrete models.
//! - [`tangent`]: central-difference tangents for models without a closed-form one.
//! - [`part_material`]: the material of one part, any of the laws.
//! - [`drivers`]: single-element drivers writing into caller-provided buffers.
//!
//! Conventions (SI): stress positive in tension; pressure `p = -tr(sigma)/3` positive in
//! compression; `mu = rho/rho0 - 1`; strain increments use tensor (not engineering) shear.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod damage;
pub mod drivers;
pub mod eos;
pub mod error;
pub mod j2;
pub mod kc;
pub mod math;
pub mod parameters;
pub mod part_material;
pub mod point_model;
pub mod rht;
pub mod state;
pub mod strength;
pub mod tangent;
pub mod tensor;

pub use error::{ParameterError, UpdateError};
pub use j2::{
    update, update_block, update_lanes, update_with_tangent, Heating, Material, RateTreatment,
};
pub use part_material::PartMaterial;
pub use point_model::{PointModel, StepInput, StepOutput, LANES};
pub use state::{MaterialState, StateFlags, YieldCheck};
