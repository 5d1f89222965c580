//! Damage, failure and erosion shared by every strength model.
//!
//! Failure turns a point into a fluid that carries no shear and no tension; the host erodes an
//! element on [`crate::StateFlags::ERODE`].

mod johnson_cook_failure;

pub use johnson_cook_failure::JohnsonCookFailure;

use crate::error::{check, ParameterError};
use crate::math::sqrt;
use crate::StateFlags;

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
    /// Autodyn-style *instantaneous geometric strain* at which the host erodes an element
    /// (seed 001 uses 1.5): the equivalent of the element's total logarithmic strain, see
    /// [`Failure::geometric_strain`]. The kernel has no geometry: the host FE code evaluates
    /// it from the element's deformation ([`Failure::kinematic_flags`]). `None`: never.
    #[cfg_attr(feature = "serde", serde(default))]
    pub erosion_geometric_strain: Option<f64>,
    /// Largest principal *tensile* logarithmic strain at which the point fails (becomes a
    /// fluid without shear or tensile strength, as on Johnson-Cook failure; seed 001 uses 1.2
    /// for HNS), evaluated by the host FE code like the geometric strain. `None`: never.
    #[cfg_attr(feature = "serde", serde(default))]
    pub failure_principal_strain: Option<f64>,
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
        erosion_geometric_strain: None,
        failure_principal_strain: None,
        pressure_cutoff: None,
    };

    /// The smallest magnitude of a principal logarithmic strain at which a kinematic
    /// criterion can be met, `None` without one: the failure strain itself, and
    /// `limit / sqrt 2` for the geometric strain (`sqrt(2/3 e:e) <= sqrt 2 max |e_i|`). An
    /// element whose principal strains all stay below it needs no evaluation.
    pub fn kinematic_strain_bound(&self) -> Option<f64> {
        let failure = self.failure_principal_strain;
        let erosion = self
            .erosion_geometric_strain
            .map(|limit| limit * core::f64::consts::FRAC_1_SQRT_2);
        match (failure, erosion) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Autodyn's effective geometric strain from the principal logarithmic strains `e_i` of
    /// the total deformation: `sqrt(2/3 e:e)` over the *whole* tensor (the volumetric part
    /// included, so crushed elements count too). It equals the axial strain in
    /// incompressible uniaxial stretching.
    pub fn geometric_strain(principal_strains: [f64; 3]) -> f64 {
        let [a, b, c] = principal_strains;
        sqrt(2.0 / 3.0 * (a * a + b * b + c * c))
    }

    /// The flags the kinematic criteria set for an element with principal logarithmic strains
    /// `principal_strains`: [`StateFlags::FAILED`] when the largest reaches
    /// `failure_principal_strain`, [`StateFlags::ERODE`] when the geometric strain reaches
    /// `erosion_geometric_strain`.
    pub fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        let mut flags = StateFlags(0);
        if let Some(limit) = self.failure_principal_strain {
            let largest = principal_strains[0]
                .max(principal_strains[1])
                .max(principal_strains[2]);
            if largest >= limit {
                flags.insert(StateFlags::FAILED);
            }
        }
        if let Some(limit) = self.erosion_geometric_strain {
            if Self::geometric_strain(principal_strains) >= limit {
                flags.insert(StateFlags::ERODE);
            }
        }
        flags
    }

    /// Reject non-physical settings.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if let Some(jc) = &self.johnson_cook {
            jc.validate()?;
        }
        if let Some(strain) = self.erosion_plastic_strain {
            check::positive("erosion_plastic_strain", strain)?;
        }
        if let Some(strain) = self.erosion_geometric_strain {
            check::positive("erosion_geometric_strain", strain)?;
        }
        if let Some(strain) = self.failure_principal_strain {
            check::positive("failure_principal_strain", strain)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_strain_and_the_kinematic_flags() {
        // GOAL: Autodyn's effective geometric strain and the host-evaluated criteria.
        // SETUP: incompressible uniaxial stretch (e, -e/2, -e/2), e = 1.6; pure volumetric
        //        compression ln(0.5)/3 each way; limits 1.5 (erosion) and 1.2 (failure).
        // REFERENCE: sqrt(2/3 (e^2 + e^2/4 + e^2/4)) = e exactly in reals (to round-off
        //   here); volumetric: sqrt(2/3 * 3 v^2) = sqrt(2) |v|; uniaxial 1.6 passes both
        //   limits (largest principal 1.6 >= 1.2), compression reaches neither.
        let e = 1.6;
        let stretch = [e, -0.5 * e, -0.5 * e];
        assert!((Failure::geometric_strain(stretch) - e).abs() < 1e-15);
        let v = libm::log(0.5) / 3.0;
        let squeeze = [v, v, v];
        assert!((Failure::geometric_strain(squeeze) - sqrt(2.0) * v.abs()).abs() < 1e-15);
        let failure = Failure {
            erosion_geometric_strain: Some(1.5),
            failure_principal_strain: Some(1.2),
            ..Failure::NONE
        };
        assert_eq!(
            failure.kinematic_strain_bound(),
            Some(1.5 * core::f64::consts::FRAC_1_SQRT_2)
        );
        let flags = failure.kinematic_flags(stretch);
        assert!(flags.contains(StateFlags::ERODE) && flags.contains(StateFlags::FAILED));
        assert_eq!(failure.kinematic_flags(squeeze), StateFlags(0));
        assert_eq!(Failure::NONE.kinematic_strain_bound(), None);
        let bad = Failure {
            erosion_geometric_strain: Some(0.0),
            ..Failure::NONE
        };
        assert!(bad.validate().is_err());
    }
}
