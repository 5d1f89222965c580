//! Mie-Grüneisen EoS with a cubic shock-velocity fit, in the form of LS-DYNA
//! `*EOS_GRUNEISEN` (LS-DYNA Keyword User's Manual, vol. II, EOS type 4):
//!
//! ```text
//! compression (mu > 0):
//!   p = rho0 C^2 mu [1 + (1 - gamma0/2) mu - (a/2) mu^2]
//!       / [1 - (S1 - 1) mu - S2 mu^2/(mu + 1) - S3 mu^3/(mu + 1)^2]^2
//!     + (gamma0 + a mu) E
//! expansion (mu <= 0):
//!   p = rho0 C^2 mu + (gamma0 + a mu) E
//! ```
//!
//! `mu = rho/rho0 - 1`, `E` internal energy per unit reference volume, `C` the intercept and
//! `S1..S3` the coefficients of `Us = C + S1 up + S2 up^2/Us + S3 up^3/Us^2`, `gamma0` the
//! Grüneisen coefficient and `a` its first-order volume correction. With `S2 = S3 = 0` the
//! compression branch is exactly `p = p_H(mu) + (gamma0 + a mu)(E - E_H(mu))` around the
//! linear `Us-up` Hugoniot (`p_H = rho0 Us up`, `E_H = p_H (1 - V)/2`).
//!
//! The denominator vanishes at the Hugoniot's limiting compression (for `S2 = S3 = 0`,
//! `mu = 1/(S1 - 1)`); at and beyond it the form has no meaning: the pressure is returned as
//! `+inf`, which the stress update reports as [`crate::UpdateError::NonFiniteResult`].

use super::EnergyLinearPressure;
use crate::error::{check, ParameterError};

/// Mie-Grüneisen constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct MieGruneisen {
    /// Reference density `rho0` (kg/m^3) of the Hugoniot fit (normally the material density).
    pub reference_density: f64,
    /// Intercept `C` of the `Us-up` fit (m/s).
    pub sound_speed: f64,
    /// `S1` (-).
    pub s1: f64,
    /// `S2` (-).
    pub s2: f64,
    /// `S3` (-).
    pub s3: f64,
    /// Grüneisen coefficient `gamma0` (-).
    pub gamma0: f64,
    /// First-order volume correction `a` to `gamma0` (-).
    pub volume_correction: f64,
}

impl MieGruneisen {
    /// Energy-linear terms at compression `mu`, with the analytical derivative of the base.
    ///
    /// Compression: `base = N/D^2` with `N = rho0 C^2 mu (1 + b mu - (a/2) mu^2)`,
    /// `b = 1 - gamma0/2`, `D = 1 - (S1-1) mu - S2 mu^2/(1+mu) - S3 mu^3/(1+mu)^2`, so
    /// `base' = N'/D^2 - 2 N D'/D^3` with `N' = rho0 C^2 (1 + 2 b mu - (3a/2) mu^2)` and
    /// `D' = -(S1-1) - S2 mu (2+mu)/(1+mu)^2 - S3 mu^2 (3+mu)/(1+mu)^3`.
    pub fn evaluate(&self, mu: f64) -> EnergyLinearPressure {
        let stiffness = self.reference_density * self.sound_speed * self.sound_speed;
        let a = self.volume_correction;
        let energy_coefficient = self.gamma0 + a * mu;
        if mu > 0.0 {
            let b = 1.0 - 0.5 * self.gamma0;
            let numerator = stiffness * mu * (1.0 + b * mu - 0.5 * a * mu * mu);
            let d_numerator = stiffness * (1.0 + 2.0 * b * mu - 1.5 * a * mu * mu);
            let one_plus = 1.0 + mu;
            let denominator = 1.0
                - (self.s1 - 1.0) * mu
                - self.s2 * mu * mu / one_plus
                - self.s3 * mu * mu * mu / (one_plus * one_plus);
            let d_denominator = -(self.s1 - 1.0)
                - self.s2 * mu * (2.0 + mu) / (one_plus * one_plus)
                - self.s3 * mu * mu * (3.0 + mu) / (one_plus * one_plus * one_plus);
            if denominator <= 0.0 {
                // At or past the limiting compression: no meaningful pressure.
                return EnergyLinearPressure {
                    base: f64::INFINITY,
                    d_base_d_mu: f64::INFINITY,
                    energy_coefficient,
                    d_energy_coefficient_d_mu: a,
                };
            }
            let denominator_sq = denominator * denominator;
            EnergyLinearPressure {
                base: numerator / denominator_sq,
                d_base_d_mu: d_numerator / denominator_sq
                    - 2.0 * numerator * d_denominator / (denominator_sq * denominator),
                energy_coefficient,
                d_energy_coefficient_d_mu: a,
            }
        } else {
            EnergyLinearPressure {
                base: stiffness * mu,
                d_base_d_mu: stiffness,
                energy_coefficient,
                d_energy_coefficient_d_mu: a,
            }
        }
    }

    /// `rho0 > 0`, `C > 0`; `S1..S3`, `gamma0`, `a` finite.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("reference_density", self.reference_density)?;
        check::positive("sound_speed", self.sound_speed)?;
        check::finite("s1", self.s1)?;
        check::finite("s2", self.s2)?;
        check::finite("s3", self.s3)?;
        check::finite("gamma0", self.gamma0)?;
        check::finite("volume_correction", self.volume_correction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eos::Eos;

    /// OFHC copper as given in the task (C 3940 m/s, S1 1.49, gamma0 2.02, rho0 8930 kg/m^3).
    const COPPER: MieGruneisen = MieGruneisen {
        reference_density: 8930.0,
        sound_speed: 3940.0,
        s1: 1.49,
        s2: 0.0,
        s3: 0.0,
        gamma0: 2.02,
        volume_correction: 0.0,
    };

    /// Rankine-Hugoniot state behind a shock with particle velocity `up` for the linear fit
    /// `Us = C + S1 up`: returns `(mu, p_H, E_H)` with `E_H` per reference volume.
    fn hugoniot_state(eos: &MieGruneisen, up: f64) -> (f64, f64, f64) {
        let us = eos.sound_speed + eos.s1 * up;
        let mu = up / (us - up);
        let pressure = eos.reference_density * us * up;
        let relative_volume = (us - up) / us;
        let energy = 0.5 * pressure * (1.0 - relative_volume);
        (mu, pressure, energy)
    }

    #[test]
    fn copper_reproduces_the_rankine_hugoniot_pressure() {
        // GOAL: on the linear Us-up Hugoniot, p(mu_H, E_H) = p_H = rho0 Us up.
        // SETUP: copper (C 3940, S1 1.49, gamma0 2.02, rho0 8930, S2 = S3 = 0), with a = 0
        //   and with a = 0.47; up = 100..2000 m/s; mu = up/(Us - up), E_H = p_H (1 - V)/2.
        // REFERENCE: Rankine-Hugoniot jump conditions (mass, momentum, energy) from rest;
        //   tolerance 1e-12 relative.
        for a in [0.0, 0.47] {
            let eos = MieGruneisen {
                volume_correction: a,
                ..COPPER
            };
            for up in [100.0, 250.0, 500.0, 1000.0, 1500.0, 2000.0] {
                let (mu, p_h, e_h) = hugoniot_state(&eos, up);
                let p = eos.evaluate(mu).pressure(e_h);
                let relative = ((p - p_h) / p_h).abs();
                assert!(
                    relative < 1e-12,
                    "a {a} up {up}: {p} vs {p_h} ({relative:e})"
                );
            }
        }
    }

    #[test]
    fn pressure_is_linear_in_energy_with_coefficient_gamma0_plus_a_mu() {
        // GOAL: the energy-linear structure: p(mu, E) - p(mu, 0) = (gamma0 + a mu) E in both
        //   branches, d(coefficient)/dmu = a.
        // SETUP: copper with a = 0.47; mu = -0.05, 0.1; E = 0, 1, 5 GJ/m^3.
        // REFERENCE: the stated form; tolerance 1e-12 relative.
        let eos = MieGruneisen {
            volume_correction: 0.47,
            ..COPPER
        };
        for mu in [-0.05, 0.1] {
            let terms = eos.evaluate(mu);
            let coefficient = 2.02 + 0.47 * mu;
            assert!((terms.energy_coefficient - coefficient).abs() < 1e-15);
            assert_eq!(terms.d_energy_coefficient_d_mu, 0.47);
            for energy in [1.0e9, 5.0e9] {
                let delta = terms.pressure(energy) - terms.pressure(0.0);
                assert!(((delta - coefficient * energy) / (coefficient * energy)).abs() < 1e-12);
            }
        }
        // Expansion is the linear branch rho0 C^2 mu.
        let terms = COPPER.evaluate(-0.05);
        assert_eq!(terms.base, 8930.0 * 3940.0 * 3940.0 * -0.05);
    }

    #[test]
    fn analytical_derivative_matches_central_differences() {
        // GOAL: d_base_d_mu is the derivative of the base in both branches.
        // SETUP: S1..S3 all non-zero (S1 1.5, S2 0.3, S3 -0.2), a = 0.47; mu in
        //   {-0.1, 0.02, 0.1, 0.3}; step 1e-7.
        // REFERENCE: central differences; tolerance 1e-6 relative.
        let eos = MieGruneisen {
            s1: 1.5,
            s2: 0.3,
            s3: -0.2,
            volume_correction: 0.47,
            ..COPPER
        };
        for mu in [-0.1, 0.02, 0.1, 0.3] {
            let h = 1e-7;
            let fd = (eos.evaluate(mu + h).base - eos.evaluate(mu - h).base) / (2.0 * h);
            let exact = eos.evaluate(mu).d_base_d_mu;
            assert!(((exact - fd) / fd).abs() < 1e-6, "mu {mu}: {exact} vs {fd}");
        }
        // Both branches meet at mu = 0 with value 0 and slope rho0 C^2.
        let stiffness = 8930.0 * 3940.0 * 3940.0;
        let right = eos.evaluate(1e-12);
        assert!((right.d_base_d_mu - stiffness).abs() < 1e-9 * stiffness);
        assert_eq!(eos.evaluate(0.0).base, 0.0);
    }

    #[test]
    fn bulk_sound_speed_at_reference_is_c() {
        // GOAL: the Eos sound-speed helper gives c = C at mu = 0, E = 0.
        // SETUP: copper, reference state. REFERENCE: c^2 = d p/d rho = C^2; tolerance 1e-14.
        let terms = COPPER.evaluate(0.0);
        let c2 = Eos::sound_speed_squared(&terms, 0.0, 0.0, 0.0, 8930.0);
        assert!((c2 / (3940.0 * 3940.0) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn bad_constants_give_typed_errors() {
        // GOAL: validate() names the offending field.
        // SETUP: copper with one field broken at a time. REFERENCE: ParameterError variants.
        let mut eos = COPPER;
        eos.reference_density = -8930.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotPositive {
                field: "reference_density",
                value: -8930.0
            })
        );
        let mut eos = COPPER;
        eos.sound_speed = 0.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotPositive {
                field: "sound_speed",
                value: 0.0
            })
        );
        let mut eos = COPPER;
        eos.gamma0 = f64::INFINITY;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotFinite { field: "gamma0" })
        );
        assert_eq!(Eos::from(COPPER).validate(), Ok(()));
    }
}

crate::struct_constants!(
    MieGruneisen,
    [
        reference_density = ("rho0", "kg/m^3", crate::parameters::FIXED),
        sound_speed = ("C", "m/s", crate::parameters::FIXED),
        s1 = ("S1", "-", crate::parameters::FIXED),
        s2 = ("S2", "-", crate::parameters::FIXED),
        s3 = ("S3", "-", crate::parameters::FIXED),
        gamma0 = ("gamma0", "-", crate::parameters::FIXED),
        volume_correction = ("a", "-", crate::parameters::FIXED),
    ]
);
