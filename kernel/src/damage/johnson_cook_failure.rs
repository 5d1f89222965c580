//! Johnson-Cook (1985) failure strain
//! `eps_f = (D1 + D2 exp(D3 sigma*)) (1 + D4 ln e*) (1 + D5 T*)`, with stress triaxiality
//! `sigma* = -p / q`, `e* = max(deps_p / e0, 1)` and homologous temperature `T*`.

use crate::error::{check, ParameterError};
use crate::math::{exp, ln};
use crate::strength::homologous_temperature;

/// Johnson-Cook failure constants.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct JohnsonCookFailure {
    /// `D1` (-).
    pub d1: f64,
    /// `D2` (-).
    pub d2: f64,
    /// `D3` (-).
    pub d3: f64,
    /// `D4` (-).
    pub d4: f64,
    /// `D5` (-).
    pub d5: f64,
    /// Reference rate `e0` (1/s).
    pub reference_rate: f64,
    /// Reference temperature `Tr` (K).
    pub reference_temperature: f64,
    /// Melting temperature `Tm` (K).
    pub melting_temperature: f64,
}

impl JohnsonCookFailure {
    /// Smallest failure strain used, so that `dD = deps_p / eps_f` stays finite.
    pub const MINIMUM_FAILURE_STRAIN: f64 = 1e-6;

    /// 4340 steel, Johnson & Cook (1985): D1 0.05, D2 3.44, D3 -2.12, D4 0.002, D5 0.61.
    pub const STEEL_4340: JohnsonCookFailure = JohnsonCookFailure {
        d1: 0.05,
        d2: 3.44,
        d3: -2.12,
        d4: 0.002,
        d5: 0.61,
        reference_rate: 1.0,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };

    /// Failure strain at triaxiality `triaxiality`, plastic strain rate `plastic_strain_rate`,
    /// temperature `temperature`.
    pub fn failure_strain(
        &self,
        triaxiality: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> f64 {
        let ratio = plastic_strain_rate / self.reference_rate;
        let rate_factor = if ratio > 1.0 {
            1.0 + self.d4 * ln(ratio)
        } else {
            1.0
        };
        let t_star = homologous_temperature(
            temperature,
            self.reference_temperature,
            self.melting_temperature,
        );
        let strain = (self.d1 + self.d2 * exp(self.d3 * triaxiality))
            * rate_factor
            * (1.0 + self.d5 * t_star);
        if strain > Self::MINIMUM_FAILURE_STRAIN {
            strain
        } else {
            Self::MINIMUM_FAILURE_STRAIN
        }
    }

    /// All constants finite, reference rate and temperatures positive, `Tm > Tr`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::finite("d1", self.d1)?;
        check::finite("d2", self.d2)?;
        check::finite("d3", self.d3)?;
        check::finite("d4", self.d4)?;
        check::finite("d5", self.d5)?;
        check::positive("reference_rate", self.reference_rate)?;
        check::positive("reference_temperature", self.reference_temperature)?;
        check::positive("melting_temperature", self.melting_temperature)?;
        if self.melting_temperature <= self.reference_temperature {
            return Err(ParameterError::Inconsistent {
                field: "melting_temperature",
                other: "reference_temperature",
            });
        }
        if self.d1 + self.d2 <= 0.0 {
            return Err(ParameterError::NotPositive {
                field: "d1",
                value: self.d1 + self.d2,
            });
        }
        Ok(())
    }
}
