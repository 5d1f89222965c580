//! A complete material: density, elasticity, strength, heating, EoS and failure.

use crate::damage::Failure;
use crate::eos::{Eos, LinearEos};
use crate::error::{check, ParameterError};
use crate::math::{clamp, ln};
use crate::strength::{JohnsonCook, Strength};

/// How the flow stress sees the plastic strain rate inside a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum RateTreatment {
    /// Seed 001 eq. 3.8 (Westerling 2001): `sigma_{n+1} = sigma(eps_{n+1}, (eps_{n+1} -
    /// eps_n)/dt, T_n)`, solved for the plastic multiplier. Consistent with the analytical
    /// flow stress.
    Implicit,
    /// Seed 001 eq. 3.7 (Autodyn 4.1 behaviour): `sigma_{n+1} = sigma(eps_n, (eps_n -
    /// eps_{n-1})/dt, T_n)`. Kept deliberately: it reproduces the rate-insensitivity defect
    /// that seed reports, which users must be able to show.
    Lagged,
}

/// Conversion of plastic work into heat.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum Heating {
    /// No heating: temperature stays at its initial value.
    Isothermal,
    /// Adiabatic: `dT = chi sigma_y deps_p / (rho c_p)`.
    Adiabatic {
        /// Taylor-Quinney coefficient `chi` (default 0.9).
        taylor_quinney: f64,
    },
    /// Rate-dependent isothermal-to-adiabatic transition: the Taylor-Quinney coefficient is
    /// scaled by `w(deps_p)`, 0 below `isothermal_rate`, 1 above `adiabatic_rate`, and a
    /// smoothstep `3x^2 - 2x^3` in `x = ln(rate/isothermal_rate)/ln(adiabatic_rate/isothermal_rate)`
    /// between (the same idea as LS-DYNA *MAT_224's thermal transition, smoothed).
    Transition {
        /// Taylor-Quinney coefficient `chi` in the adiabatic limit.
        taylor_quinney: f64,
        /// Rate below which the process is isothermal (1/s).
        isothermal_rate: f64,
        /// Rate above which the process is adiabatic (1/s).
        adiabatic_rate: f64,
    },
}

impl Heating {
    /// The default adiabatic heating with `chi = 0.9`.
    pub const ADIABATIC: Heating = Heating::Adiabatic {
        taylor_quinney: 0.9,
    };

    /// Fraction of plastic work converted to heat at plastic strain rate `plastic_strain_rate`.
    #[inline]
    pub fn heat_fraction(&self, plastic_strain_rate: f64) -> f64 {
        match *self {
            Heating::Isothermal => 0.0,
            Heating::Adiabatic { taylor_quinney } => taylor_quinney,
            Heating::Transition {
                taylor_quinney,
                isothermal_rate,
                adiabatic_rate,
            } => {
                if plastic_strain_rate <= isothermal_rate {
                    return 0.0;
                }
                if plastic_strain_rate >= adiabatic_rate {
                    return taylor_quinney;
                }
                let x = clamp(
                    ln(plastic_strain_rate / isothermal_rate)
                        / ln(adiabatic_rate / isothermal_rate),
                    0.0,
                    1.0,
                );
                taylor_quinney * x * x * (3.0 - 2.0 * x)
            }
        }
    }

    /// `chi` in `[0, 1]`; transition rates positive and ordered.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match *self {
            Heating::Isothermal => Ok(()),
            Heating::Adiabatic { taylor_quinney } => {
                check::range("taylor_quinney", taylor_quinney, 0.0, 1.0)
            }
            Heating::Transition {
                taylor_quinney,
                isothermal_rate,
                adiabatic_rate,
            } => {
                check::range("taylor_quinney", taylor_quinney, 0.0, 1.0)?;
                check::positive("isothermal_rate", isothermal_rate)?;
                check::positive("adiabatic_rate", adiabatic_rate)?;
                if adiabatic_rate <= isothermal_rate {
                    return Err(ParameterError::Inconsistent {
                        field: "adiabatic_rate",
                        other: "isothermal_rate",
                    });
                }
                Ok(())
            }
        }
    }
}

/// Everything the stress update needs to know about a material.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Material {
    /// Reference density `rho0` (kg/m^3).
    pub density: f64,
    /// Shear modulus `G` (Pa).
    pub shear_modulus: f64,
    /// Specific heat `c_p` (J/kg/K).
    pub specific_heat: f64,
    /// Flow stress model.
    pub strength: Strength,
    /// Plastic-work heating.
    pub heating: Heating,
    /// Equation of state.
    pub eos: Eos,
    /// Damage, failure and erosion.
    pub failure: Failure,
    /// Implicit (eq. 3.8) or lagged (eq. 3.7) rate in the flow stress.
    pub rate_treatment: RateTreatment,
}

impl Material {
    /// 4340 steel with the Johnson & Cook (1985) constants, linear EoS K 159 GPa, G 81.8 GPa,
    /// rho 7830 kg/m^3, c_p 477 J/kg/K (seed 001 table 3.2), adiabatic heating chi 0.9,
    /// implicit rate, no failure.
    pub const STEEL_4340: Material = Material {
        density: 7830.0,
        shear_modulus: 81.8e9,
        specific_heat: 477.0,
        strength: Strength::Composed(JohnsonCook::STEEL_4340.composed()),
        heating: Heating::ADIABATIC,
        eos: Eos::Linear(LinearEos {
            bulk_modulus: 159.0e9,
        }),
        failure: Failure::NONE,
        rate_treatment: RateTreatment::Implicit,
    };

    /// Validate every part; the first offending field is reported.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("density", self.density)?;
        check::positive("shear_modulus", self.shear_modulus)?;
        check::positive("specific_heat", self.specific_heat)?;
        self.strength.validate()?;
        self.heating.validate()?;
        self.eos.validate()?;
        self.failure.validate()
    }

    /// The same material with another strength model.
    pub fn with_strength(mut self, strength: impl Into<Strength>) -> Self {
        self.strength = strength.into();
        self
    }
}

// The Taylor-Quinney coefficient is in [0, 1] by definition; the transition rates are held
// by convention.
crate::enum_constants!(Heating, {
    Isothermal {},
    Adiabatic {
        taylor_quinney = ("chi", "-", Some((0.0, 1.0))),
    },
    Transition {
        taylor_quinney = ("chi", "-", Some((0.0, 1.0))),
        isothermal_rate = ("e_iso", "1/s", crate::parameters::FIXED),
        adiabatic_rate = ("e_ad", "1/s", crate::parameters::FIXED),
    },
});
