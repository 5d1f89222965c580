//! Damage, failure and erosion shared by every strength model.
//!
//! Failure turns a point into a fluid that carries no shear and no tension; the host erodes an
//! element on [`crate::StateFlags::ERODE`].

mod johnson_cook_failure;

pub use johnson_cook_failure::JohnsonCookFailure;

use crate::error::{check, ParameterError};

/// Failure and erosion settings of a material.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Failure {
    /// Cumulative Johnson-Cook damage `D = sum(deps_p / eps_f)`; fails at `D >= 1`.
    pub johnson_cook: Option<JohnsonCookFailure>,
    /// Equivalent plastic strain at which the host should erode the element (seed 001 uses
    /// 1.5 for HNS). `None`: never by strain.
    pub erosion_plastic_strain: Option<f64>,
    /// Erode (not only fail) when damage reaches 1, as LS-DYNA *MAT_JOHNSON_COOK does.
    #[cfg_attr(feature = "serde", serde(default))]
    pub erode_on_failure: bool,
    /// Hydrodynamic tensile limit `p_min <= 0` (Pa): pressure is never below it (spall
    /// cut-off, Autodyn "hydro tensile limit"). `None`: no cut-off for intact material.
    pub pressure_cutoff: Option<f64>,
}

impl Failure {
    /// No damage, no erosion, no cut-off.
    pub const NONE: Failure = Failure {
        johnson_cook: None,
        erosion_plastic_strain: None,
        erode_on_failure: false,
        pressure_cutoff: None,
    };

    /// Reject non-physical settings.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if let Some(jc) = &self.johnson_cook {
            jc.validate()?;
        }
        if let Some(strain) = self.erosion_plastic_strain {
            check::positive("erosion_plastic_strain", strain)?;
        }
        if let Some(cutoff) = self.pressure_cutoff {
            check::finite("pressure_cutoff", cutoff)?;
            if cutoff > 0.0 {
                return Err(ParameterError::OutOfRange {
                    field: "pressure_cutoff",
                    value: cutoff,
                    min: f64::NEG_INFINITY,
                    max: 0.0,
                });
            }
        }
        Ok(())
    }
}
