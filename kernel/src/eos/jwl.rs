//! Jones-Wilkins-Lee EoS for detonation products (Lee, Hornig & Kury 1968; LS-DYNA
//! `*EOS_JWL`, EOS type 2):
//!
//! ```text
//! p = A (1 - w/(R1 V)) exp(-R1 V) + B (1 - w/(R2 V)) exp(-R2 V) + w E / V
//! ```
//!
//! with `V = rho0/rho = 1/(1 + mu)` the relative volume and `E` the internal energy per unit
//! **reference** volume (the detonation energy `E0` is the initial value of `E`). In
//! energy-linear form `base(mu) = A(..)exp(..) + B(..)exp(..)` and
//! `energy_coefficient = w/V = w (1 + mu)`.
//!
//! The EoS carries no burn model: the host sets `E = E0` (the state's internal energy) and
//! decides when a point detonates (e.g. programmed burn with [`Jwl::detonation_velocity`]).

use super::EnergyLinearPressure;
use crate::error::{check, ParameterError};
use crate::math::{exp, sqrt};

/// JWL constants (SI) and the published detonation data that go with them.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Jwl {
    /// `A` (Pa).
    pub a: f64,
    /// `B` (Pa).
    pub b: f64,
    /// `R1` (-).
    pub r1: f64,
    /// `R2` (-).
    pub r2: f64,
    /// `w` (omega, -), the Grüneisen coefficient of the products.
    pub omega: f64,
    /// Unreacted explosive density `rho0` (kg/m^3), the reference of `V` and `E`.
    pub reference_density: f64,
    /// Detonation energy per unit reference volume `E0` (J/m^3), the initial `E`.
    pub detonation_energy: f64,
    /// Published Chapman-Jouguet detonation velocity `D` (m/s). Not used by the pressure.
    pub detonation_velocity: f64,
    /// Published Chapman-Jouguet pressure `P_CJ` (Pa). Not used by the pressure.
    pub cj_pressure: f64,
}

impl Jwl {
    /// Composition C-4, LLNL Explosives Handbook: B. M. Dobratz & P. C. Crawford, *LLNL
    /// Explosives Handbook: Properties of Chemical Explosives and Explosive Simulants*,
    /// UCRL-52997 Change 2 (1985), JWL table: rho0 1.601 g/cm^3, D 0.8193 cm/us,
    /// P_CJ 0.280 Mbar, A 6.0977 Mbar, B 0.1295 Mbar, R1 4.5, R2 1.4, w 0.25,
    /// E0 0.090 Mbar (per unit initial volume); converted to SI here. The same numbers
    /// appear unchanged as the "C4" products set in several public hydrocode inputs
    /// (e.g. blastFoam's C-4 tutorial dictionaries). The test
    /// `c4_chapman_jouguet_state_matches_the_published_values` recomputes D and P_CJ from
    /// A, B, R1, R2, w, E0 and rho0 (8193.0 m/s, 28.00 GPa).
    pub const C4: Jwl = Jwl {
        a: 609.77e9,
        b: 12.95e9,
        r1: 4.5,
        r2: 1.4,
        omega: 0.25,
        reference_density: 1601.0,
        detonation_energy: 9.0e9,
        detonation_velocity: 8193.0,
        cj_pressure: 28.0e9,
    };

    /// TNT, LLNL Explosives Handbook (Dobratz & Crawford, UCRL-52997 Change 2, 1985), JWL
    /// table: rho0 1.630 g/cm^3, D 0.693 cm/us, P_CJ 0.210 Mbar, A 3.712 Mbar, B 0.03231 Mbar,
    /// R1 4.15, R2 0.95, w 0.30, E0 0.070 Mbar; the same set is OpenRadioss's `/MAT/JWL`
    /// TNT example. The test `tnt_chapman_jouguet_state_matches_the_published_values`
    /// recomputes D and P_CJ from the constants.
    pub const TNT: Jwl = Jwl {
        a: 371.2e9,
        b: 3.231e9,
        r1: 4.15,
        r2: 0.95,
        omega: 0.30,
        reference_density: 1630.0,
        detonation_energy: 7.0e9,
        detonation_velocity: 6930.0,
        cj_pressure: 21.0e9,
    };

    /// Energy-linear terms at compression `mu` (`V = 1/(1 + mu)`).
    ///
    /// With `g_i(V) = (1 - w/(R_i V)) exp(-R_i V)`,
    /// `dg_i/dV = exp(-R_i V) (w/(R_i V^2) + w/V - R_i)` and `dV/dmu = -V^2`.
    pub fn evaluate(&self, mu: f64) -> EnergyLinearPressure {
        let one_plus = 1.0 + mu;
        let v = 1.0 / one_plus;
        let w = self.omega;
        let e1 = exp(-self.r1 * v);
        let e2 = exp(-self.r2 * v);
        let base =
            self.a * (1.0 - w / (self.r1 * v)) * e1 + self.b * (1.0 - w / (self.r2 * v)) * e2;
        let d_base_d_v = self.a * e1 * (w / (self.r1 * v * v) + w / v - self.r1)
            + self.b * e2 * (w / (self.r2 * v * v) + w / v - self.r2);
        EnergyLinearPressure {
            base,
            d_base_d_mu: -v * v * d_base_d_v,
            energy_coefficient: w * one_plus,
            d_energy_coefficient_d_mu: w,
        }
    }

    /// Pressure on the products Hugoniot centred on the unreacted state `(V = 1, p = 0,
    /// E = E0)`: `E - E0 = p (1 - V)/2` with `p = base(V) + (w/V) E` gives
    /// `p_H(V) = [base(V) + (w/V) E0] / [1 - (w/V)(1 - V)/2]`.
    pub fn products_hugoniot(&self, v: f64) -> f64 {
        let terms = self.evaluate(1.0 / v - 1.0);
        let coefficient = terms.energy_coefficient;
        (terms.base + coefficient * self.detonation_energy) / (1.0 - 0.5 * coefficient * (1.0 - v))
    }

    /// The Chapman-Jouguet state these constants imply: the Rayleigh line
    /// `p = rho0 D^2 (1 - V)` from `(1, 0)` that touches the products Hugoniot, i.e. the
    /// minimum over `V` of its slope `p_H(V)/(1 - V) = rho0 D^2`. Golden-section search on `V`
    /// in `(w/(2 + w), 1)` (where the Hugoniot denominator is positive), 200 fixed iterations.
    pub fn chapman_jouguet(&self) -> ChapmanJouguet {
        let slope = |v: f64| self.products_hugoniot(v) / (1.0 - v);
        let w = self.omega;
        let mut lo = w / (2.0 + w) + 1e-6;
        let mut hi = 1.0 - 1e-6;
        let ratio = 0.5 * (sqrt(5.0) - 1.0);
        let mut x1 = hi - ratio * (hi - lo);
        let mut x2 = lo + ratio * (hi - lo);
        let mut f1 = slope(x1);
        let mut f2 = slope(x2);
        for _ in 0..200 {
            if f1 < f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - ratio * (hi - lo);
                f1 = slope(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + ratio * (hi - lo);
                f2 = slope(x2);
            }
        }
        let v = 0.5 * (lo + hi);
        let velocity = sqrt(slope(v) / self.reference_density);
        ChapmanJouguet {
            relative_volume: v,
            pressure: self.products_hugoniot(v),
            detonation_velocity: velocity,
            particle_velocity: velocity * (1.0 - v),
        }
    }

    /// `A, R1, R2, w, rho0, E0, D, P_CJ > 0`; `B` finite (negative `B` is used for
    /// reactant fits).
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("a", self.a)?;
        check::finite("b", self.b)?;
        check::positive("r1", self.r1)?;
        check::positive("r2", self.r2)?;
        check::positive("omega", self.omega)?;
        check::positive("reference_density", self.reference_density)?;
        check::positive("detonation_energy", self.detonation_energy)?;
        check::positive("detonation_velocity", self.detonation_velocity)?;
        check::positive("cj_pressure", self.cj_pressure)
    }
}

/// A Chapman-Jouguet detonation state (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChapmanJouguet {
    /// `V_CJ = rho0/rho_CJ`.
    pub relative_volume: f64,
    /// `P_CJ` (Pa).
    pub pressure: f64,
    /// `D` (m/s).
    pub detonation_velocity: f64,
    /// `u_CJ = D (1 - V_CJ)` (m/s), the particle velocity behind the front.
    pub particle_velocity: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c4_chapman_jouguet_state_matches_the_published_values() {
        // GOAL: the shipped C-4 constants are self-consistent with the published CJ data.
        // SETUP: Jwl::C4. CJ state = tangency of the Rayleigh line from (V = 1, p = 0) with
        //   the products Hugoniot through (V = 1, E = E0), found by minimising the Rayleigh
        //   slope p_H(V)/(1 - V) = rho0 D^2 (golden section, `Jwl::chapman_jouguet`).
        // REFERENCE: Dobratz & Crawford (1985): D = 8193 m/s, P_CJ = 28.0 GPa, given to 3-4
        //   significant digits; tolerance 0.5 % (measured: D 8193.0 m/s, P_CJ 28.00 GPa,
        //   V_CJ 0.7395).
        let cj = Jwl::C4.chapman_jouguet();
        let (v, pressure, velocity) = (cj.relative_volume, cj.pressure, cj.detonation_velocity);
        std::println!(
            "C-4 CJ: V {v:.5}, P {:.4} GPa, D {velocity:.2} m/s",
            pressure / 1e9
        );
        let dp = (pressure - Jwl::C4.cj_pressure) / Jwl::C4.cj_pressure;
        let dd = (velocity - Jwl::C4.detonation_velocity) / Jwl::C4.detonation_velocity;
        assert!(dp.abs() < 5e-3, "P_CJ {pressure} ({dp:e})");
        assert!(dd.abs() < 5e-3, "D {velocity} ({dd:e})");
        assert!(v > 0.70 && v < 0.78, "V_CJ {v}");
        // At the tangent point the Rayleigh line also has the slope of the isentrope through
        // it (the CJ condition): dp/dV|_s = -rho0 D^2, with dE = -p dV on the isentrope.
        let mu = 1.0 / v - 1.0;
        let terms = Jwl::C4.evaluate(mu);
        let energy = (pressure - terms.base) / terms.energy_coefficient;
        let dp_dmu_isentrope =
            terms.d_pressure_d_mu(energy) + terms.energy_coefficient * pressure * v * v;
        let dp_dv_isentrope = -dp_dmu_isentrope / (v * v);
        let rayleigh = -Jwl::C4.reference_density * velocity * velocity;
        assert!(((dp_dv_isentrope - rayleigh) / rayleigh).abs() < 1e-4);
    }

    #[test]
    fn tnt_chapman_jouguet_state_matches_the_published_values() {
        // GOAL: the shipped TNT constants are self-consistent with the published CJ data.
        // SETUP: Jwl::TNT; CJ state by `Jwl::chapman_jouguet`.
        // REFERENCE: Dobratz & Crawford (1985): D = 6930 m/s, P_CJ = 21.0 GPa (3 digits);
        //   tolerance 1.5 % on P_CJ and 0.5 % on D (the published pair is rounded).
        let cj = Jwl::TNT.chapman_jouguet();
        std::println!(
            "TNT CJ: V {:.5}, P {:.4} GPa, D {:.2} m/s",
            cj.relative_volume,
            cj.pressure / 1e9,
            cj.detonation_velocity
        );
        assert!(
            (cj.pressure / 21.0e9 - 1.0).abs() < 1.5e-2,
            "{}",
            cj.pressure
        );
        assert!((cj.detonation_velocity / 6930.0 - 1.0).abs() < 5e-3);
    }

    #[test]
    fn pressure_is_the_jwl_formula_with_energy_per_reference_volume() {
        // GOAL: p(mu, E) is the stated JWL formula with V = 1/(1 + mu).
        // SETUP: C-4, V = 0.5, 1, 3; E = E0 and 0.3 E0.
        // REFERENCE: direct evaluation of the formula; tolerance 1e-13 relative.
        let eos = Jwl::C4;
        for v in [0.5_f64, 1.0, 3.0] {
            for energy in [eos.detonation_energy, 0.3 * eos.detonation_energy] {
                let w = eos.omega;
                let expected = eos.a * (1.0 - w / (eos.r1 * v)) * exp(-eos.r1 * v)
                    + eos.b * (1.0 - w / (eos.r2 * v)) * exp(-eos.r2 * v)
                    + w * energy / v;
                let got = eos.evaluate(1.0 / v - 1.0).pressure(energy);
                assert!(((got - expected) / expected).abs() < 1e-13, "V {v}");
            }
        }
    }

    #[test]
    fn analytical_derivative_matches_central_differences() {
        // GOAL: d_base_d_mu and d_energy_coefficient_d_mu are the mu-derivatives.
        // SETUP: C-4 at mu = -0.6, 0, 0.4; step 1e-7.
        // REFERENCE: central differences; tolerance 1e-6 relative.
        for mu in [-0.6, 0.0, 0.4] {
            let h = 1e-7;
            let up = Jwl::C4.evaluate(mu + h);
            let down = Jwl::C4.evaluate(mu - h);
            let terms = Jwl::C4.evaluate(mu);
            let fd = (up.base - down.base) / (2.0 * h);
            assert!(((terms.d_base_d_mu - fd) / fd).abs() < 1e-6, "mu {mu}");
            let fd_c = (up.energy_coefficient - down.energy_coefficient) / (2.0 * h);
            assert!((terms.d_energy_coefficient_d_mu - fd_c).abs() < 1e-6);
        }
    }

    #[test]
    fn bad_constants_give_typed_errors() {
        // GOAL: validate() names the offending field.
        // SETUP: C-4 with one field broken at a time. REFERENCE: ParameterError variants.
        assert_eq!(Jwl::C4.validate(), Ok(()));
        let mut eos = Jwl::C4;
        eos.r1 = 0.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotPositive {
                field: "r1",
                value: 0.0
            })
        );
        let mut eos = Jwl::C4;
        eos.b = f64::NAN;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotFinite { field: "b" })
        );
        let mut eos = Jwl::C4;
        eos.detonation_energy = -1.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotPositive {
                field: "detonation_energy",
                value: -1.0
            })
        );
    }
}

crate::struct_constants!(
    Jwl,
    [
        a = ("A", "Pa", crate::parameters::FIXED),
        b = ("B", "Pa", crate::parameters::FIXED),
        r1 = ("R1", "-", crate::parameters::FIXED),
        r2 = ("R2", "-", crate::parameters::FIXED),
        omega = ("w", "-", crate::parameters::FIXED),
        reference_density = ("rho0", "kg/m^3", crate::parameters::FIXED),
        detonation_energy = ("E0", "J/m^3", crate::parameters::FIXED),
        detonation_velocity = ("D", "m/s", crate::parameters::FIXED),
        cj_pressure = ("P_CJ", "Pa", crate::parameters::FIXED),
    ]
);
