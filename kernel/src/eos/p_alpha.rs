//! P-alpha porous compaction (Herrmann 1969, "Constitutive equation for the dynamic
//! compaction of ductile porous materials", J. Appl. Phys. 40, 2490) over the
//! [`Polynomial`] solid EoS; seed 001 eqs. 4.10a-b (solid) and 4.11 (compaction).
//!
//! # Exact form used
//!
//! The material's reference density is the **porous** density `rho0 = rho_s0 / alpha0`
//! (`Material::density` must be set to it), `mu = rho/rho0 - 1`, and `E` is the internal
//! energy per unit porous reference volume, `E = rho0 e`. With the distension
//! `alpha = rho_s/rho >= 1` (`rho_s` the matrix density):
//!
//! ```text
//! matrix compression  mu_s = rho_s/rho_s0 - 1 = (alpha/alpha0)(1 + mu) - 1
//! matrix energy       E_s  = rho_s0 e = alpha0 E
//! pressure            p    = p_s(mu_s, E_s) / alpha
//!                          = [f(mu_s) + (B0 + B1 mu_s) alpha0 E] / alpha      (mu_s >= 0)
//!                          = [T1 mu_s + T2 mu_s^2 + B0 alpha0 E] / alpha      (mu_s <  0)
//! compaction curve    alpha_c(p) = alpha0                                      p <= p_crush
//!                     alpha_c(p) = 1 + (alpha0 - 1) ((p_lock - p)/(p_lock - p_crush))^n
//!                     alpha_c(p) = 1                                           p >= p_lock
//! ```
//!
//! The `1/alpha` factor is Herrmann's (the porous pressure is the matrix pressure averaged
//! over the pores). Seed 001 eq. 4.11 as printed reads `P = f(rho alpha, e)` without it;
//! this implementation follows Herrmann. `p_crush` is the elastic limit (`p_el`), `p_lock`
//! the full-compaction pressure (`p_s`), `n` the compaction exponent.
//!
//! # History and the closed-form energy update
//!
//! The history variable is the current distension `alpha` (initially `alpha0`), which only
//! decreases. The stress update evaluates the EoS at the new `mu` before the step's energy is
//! known, so `alpha` is resolved from the **cold** porous pressure `p_c(alpha) = f(mu_s)/alpha`
//! (the `E = 0` part); the pressure returned then includes the energy term at that fixed
//! `alpha`, which keeps `p` linear in `E` for the closed-form energy equation. Given `mu` and
//! the previous distension `alpha_n`:
//!
//! 1. if `alpha_n <= alpha_c(p_c(alpha_n))` the state is on the elastic side of the
//!    compaction curve: `alpha = alpha_n` (elastic loading, unloading or reloading at constant
//!    distension);
//! 2. else if `p_c(1) >= p_lock`: fully compacted, `alpha = 1` (pure matrix response);
//! 3. else `alpha` in `(1, alpha_n)` solves `alpha = alpha_c(p_c(alpha))` by bisection on
//!    `[1, alpha_n]` (the residual `alpha - alpha_c(p_c(alpha))` is increasing in `alpha` for a
//!    matrix with `f'(mu)(1+mu) > f(mu)`), at most [`MAX_DISTENSION_ITERATIONS`] halvings, and
//!    the returned value is the lower bracket end, which lies on the elastic side so that
//!    re-evaluating at the same `mu` changes nothing.
//!
//! A history value below 1 (impossible for a distension; in particular the `0.0` of a
//! `MaterialState` that was not seeded with [`crate::eos::Eos::initial_history`]) is read as
//! the virgin state `alpha0`; a value above `alpha0` is capped at `alpha0`.
//!
//! # Derivatives and sound speed
//!
//! The derivatives in [`EnergyLinearPressure`] are taken at the resolved (frozen) `alpha`:
//! `d base/d mu = f'(mu_s)/alpha0`, `d coefficient/d mu = B1` (or 0 in tension). The bulk
//! sound speed from [`crate::eos::Eos::sound_speed_squared`] is therefore the elastic porous
//! sound speed at constant distension, which equals the matrix bulk sound speed at `mu_s`
//! (`c^2 = f'(mu_s)/rho_s0 + ...`): the unloading (fastest) wave, appropriate for the host's
//! time step. Autodyn's separate "porous sound speed" (seed 001 table 4.1) is not a
//! parameter here: with constant distension below `p_crush` the elastic porous bulk modulus is
//! `A1/alpha0` in terms of `mu`.

use super::{EnergyLinearPressure, Polynomial};
use crate::error::{check, ParameterError};
use crate::math::pow;

/// Bound on the bisection halvings that resolve `alpha`; the bracket `[1, alpha0]` reaches
/// adjacent doubles in fewer (about 52 for `alpha0 < 2`), at which point it stops.
pub const MAX_DISTENSION_ITERATIONS: u32 = 64;

/// P-alpha constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct PAlpha {
    /// Matrix (solid) EoS in terms of the matrix compression `mu_s` and matrix energy
    /// `E_s = alpha0 E` (seed 001 eqs. 4.10a-b).
    pub solid: Polynomial,
    /// Initial distension `alpha0 = rho_s0/rho0 >= 1` (-).
    pub initial_distension: f64,
    /// Pore-crush (elastic-limit) pressure `p_crush = p_el` (Pa).
    pub crush_pressure: f64,
    /// Full-compaction pressure `p_lock = p_s` (Pa), `> p_crush`.
    pub lock_pressure: f64,
    /// Compaction exponent `n` (-), Herrmann's quadratic law is `n = 2`, Autodyn's default 3.
    pub exponent: f64,
}

impl PAlpha {
    /// Distension on the compaction curve at pressure `p`, `alpha_c(p)` (eq. 4.11).
    pub fn compaction_distension(&self, pressure: f64) -> f64 {
        if pressure <= self.crush_pressure {
            self.initial_distension
        } else if pressure >= self.lock_pressure {
            1.0
        } else {
            let fraction =
                (self.lock_pressure - pressure) / (self.lock_pressure - self.crush_pressure);
            1.0 + (self.initial_distension - 1.0) * pow(fraction, self.exponent)
        }
    }

    /// Matrix compression `mu_s = (alpha/alpha0)(1 + mu) - 1`, evaluated as
    /// `(r - 1) + r mu` with `r = alpha/alpha0` (no cancellation at small `mu`; exactly `mu`
    /// while `alpha = alpha0`).
    #[inline]
    pub fn matrix_compression(&self, mu: f64, distension: f64) -> f64 {
        let ratio = distension / self.initial_distension;
        (ratio - 1.0) + ratio * mu
    }

    /// Cold porous pressure `f(mu_s)/alpha` (the `E = 0` part).
    fn cold_pressure(&self, mu: f64, distension: f64) -> f64 {
        self.solid
            .evaluate(self.matrix_compression(mu, distension))
            .base
            / distension
    }

    /// `alpha - alpha_c(p_c(alpha))`: `<= 0` on the elastic side of the compaction curve.
    fn excess(&self, mu: f64, distension: f64) -> f64 {
        distension - self.compaction_distension(self.cold_pressure(mu, distension))
    }

    /// The distension at compression `mu` given the previous distension `history` (see the
    /// module docs for the algorithm and the handling of out-of-range history values).
    pub fn distension(&self, mu: f64, history: f64) -> f64 {
        let initial = self.initial_distension;
        let current = if history >= 1.0 && history <= initial {
            history
        } else if history > initial {
            initial
        } else {
            // Below 1 or NaN: never produced by this EoS, read as the virgin state.
            initial
        };
        if self.excess(mu, current) <= 0.0 {
            return current;
        }
        if self.cold_pressure(mu, 1.0) >= self.lock_pressure {
            return 1.0;
        }
        // excess(1) < 0 < excess(current): bisection, keeping `lower` on the elastic side.
        let mut lower = 1.0_f64;
        let mut upper = current;
        for _ in 0..MAX_DISTENSION_ITERATIONS {
            let middle = 0.5 * (lower + upper);
            if middle <= lower || middle >= upper {
                break;
            }
            if self.excess(mu, middle) > 0.0 {
                upper = middle;
            } else {
                lower = middle;
            }
        }
        lower
    }

    /// Energy-linear terms at compression `mu` and the updated distension.
    pub fn evaluate(&self, mu: f64, history: f64) -> (EnergyLinearPressure, f64) {
        let distension = self.distension(mu, history);
        let solid = self.solid.evaluate(self.matrix_compression(mu, distension));
        let initial = self.initial_distension;
        (
            EnergyLinearPressure {
                base: solid.base / distension,
                // d mu_s/d mu = alpha/alpha0 at frozen alpha, so (1/alpha) d/dmu = 1/alpha0.
                d_base_d_mu: solid.d_base_d_mu / initial,
                energy_coefficient: solid.energy_coefficient * initial / distension,
                d_energy_coefficient_d_mu: solid.d_energy_coefficient_d_mu,
            },
            distension,
        )
    }

    /// Solid EoS valid; `alpha0 >= 1`; `p_crush >= 0`; `p_lock > p_crush`; `n > 0`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.solid.validate()?;
        check::range(
            "initial_distension",
            self.initial_distension,
            1.0,
            f64::INFINITY,
        )?;
        check::non_negative("crush_pressure", self.crush_pressure)?;
        check::finite("lock_pressure", self.lock_pressure)?;
        if self.lock_pressure <= self.crush_pressure {
            return Err(ParameterError::Inconsistent {
                field: "lock_pressure",
                other: "crush_pressure",
            });
        }
        check::positive("exponent", self.exponent)
    }
}

/// Test fixture (also used by the J2 update's tests). Illustrative constants, not a published
/// data set: a concrete-like matrix (A1 35 GPa, A2 39 GPa, A3 9 GPa, B0 = B1 = 1.22, T1 35 GPa),
/// alpha0 1.2, p_crush 25 MPa, p_lock 3 GPa, n 3. Seed 001 table 4.4 lists only the RHT
/// strength constants of its HPC, not its P-alpha constants, so no seed data set exists to ship.
#[cfg(test)]
pub(crate) const SAMPLE: PAlpha = PAlpha {
    solid: Polynomial {
        a1: 35.0e9,
        a2: 39.0e9,
        a3: 9.0e9,
        b0: 1.22,
        b1: 1.22,
        t1: 35.0e9,
        t2: 0.0,
    },
    initial_distension: 1.2,
    crush_pressure: 25.0e6,
    lock_pressure: 3.0e9,
    exponent: 3.0,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eos::Eos;
    use std::vec::Vec;

    /// One monotonic or cyclic path: `(mu, p at E = 0, alpha)` per step, history carried.
    fn path(eos: &PAlpha, mus: &[f64], start: f64) -> Vec<(f64, f64, f64)> {
        let mut history = start;
        let mut out = Vec::new();
        for &mu in mus {
            let (terms, alpha) = eos.evaluate(mu, history);
            history = alpha;
            out.push((mu, terms.base, alpha));
        }
        out
    }

    fn ramp(from: f64, to: f64, steps: usize) -> Vec<f64> {
        (0..=steps)
            .map(|i| from + (to - from) * (i as f64) / (steps as f64))
            .collect()
    }

    #[test]
    fn loading_follows_the_compaction_curve_then_the_solid() {
        // GOAL: monotonic hydrostatic loading: elastic at alpha0 up to p_crush; alpha(p) on
        //   the compaction curve between p_crush and p_lock; alpha = 1 and the matrix EoS
        //   (mu_s = (1 + mu)/alpha0 - 1) above p_lock; alpha never increases.
        // SETUP: SAMPLE, E = 0, mu from 0 to 0.45 in 9000 steps, history carried.
        // REFERENCE: eq. 4.11 with Herrmann's 1/alpha; tolerances: |alpha - alpha_c(p)| <=
        //   1e-12 in compaction, matrix pressure to 1e-14 relative once compacted.
        let states = path(&SAMPLE, &ramp(0.0, 0.45, 9000), SAMPLE.initial_distension);
        let mut previous = SAMPLE.initial_distension;
        let (mut elastic, mut compacting, mut compacted) = (0, 0, 0);
        for &(mu, p, alpha) in &states {
            assert!(alpha <= previous, "alpha increased at mu {mu}");
            previous = alpha;
            if alpha == SAMPLE.initial_distension {
                elastic += 1;
                assert!(p <= SAMPLE.crush_pressure * (1.0 + 1e-12), "mu {mu}: p {p}");
                let expected = SAMPLE.solid.evaluate(mu).base / SAMPLE.initial_distension;
                assert_eq!(p, expected, "mu {mu}");
            } else if alpha > 1.0 {
                compacting += 1;
                assert!(p > SAMPLE.crush_pressure && p < SAMPLE.lock_pressure);
                let on_curve = SAMPLE.compaction_distension(p);
                assert!(
                    (alpha - on_curve).abs() <= 1e-12,
                    "mu {mu}: {alpha} vs {on_curve}"
                );
            } else {
                compacted += 1;
                assert_eq!(alpha, 1.0);
                let mu_s = (1.0 + mu) / SAMPLE.initial_distension - 1.0;
                let expected = SAMPLE.solid.evaluate(mu_s).base;
                assert!(((p - expected) / expected).abs() < 1e-14);
                assert!(p >= SAMPLE.lock_pressure * (1.0 - 1e-12));
            }
        }
        assert!(elastic > 0 && compacting > 1000 && compacted > 100);
        std::println!("elastic {elastic}, compacting {compacting}, compacted {compacted}");
    }

    #[test]
    fn unloading_keeps_the_distension_and_reloading_rejoins_the_curve() {
        // GOAL: unloading from a partly compacted state is elastic at constant alpha and
        //   leaves a permanent densification; reloading retraces the same line and compaction
        //   resumes only past the previous state.
        // SETUP: SAMPLE, E = 0: load to mu = 0.12 (p ~ 0.5 GPa, alpha < alpha0), unload to
        //   mu = 0 (tension side included), reload to mu = 0.15.
        // REFERENCE: p = f((alpha/alpha0)(1 + mu) - 1)/alpha with alpha fixed; zero pressure at
        //   1 + mu = alpha0/alpha; tolerances 1e-12 relative.
        let loading = path(&SAMPLE, &ramp(0.0, 0.12, 2400), SAMPLE.initial_distension);
        let &(mu_max, p_max, alpha_u) = loading.last().unwrap();
        assert!(alpha_u > 1.0 && alpha_u < SAMPLE.initial_distension);
        let unloading = path(&SAMPLE, &ramp(mu_max, 0.0, 1200), alpha_u);
        for &(mu, p, alpha) in &unloading {
            assert_eq!(alpha, alpha_u, "alpha changed on unloading at mu {mu}");
            let expected = SAMPLE
                .solid
                .evaluate(SAMPLE.matrix_compression(mu, alpha_u))
                .base
                / alpha_u;
            assert_eq!(p, expected);
        }
        // Permanent densification: zero pressure at rho/rho0 = alpha0/alpha > 1.
        let mu_residual = SAMPLE.initial_distension / alpha_u - 1.0;
        assert!(mu_residual > 0.0);
        let (terms, _) = SAMPLE.evaluate(mu_residual, alpha_u);
        assert!(terms.base.abs() < 1e-6 * p_max, "p {}", terms.base);
        // Unloaded to mu = 0: tension, still at alpha_u.
        assert!(unloading.last().unwrap().1 < 0.0);
        // Reloading: same line back to (mu_max, p_max), then compaction continues.
        let reloading = path(&SAMPLE, &ramp(0.0, 0.15, 3000), alpha_u);
        for &(mu, p, alpha) in &reloading {
            if mu <= mu_max {
                assert_eq!(alpha, alpha_u, "mu {mu}");
            } else {
                assert!(alpha <= alpha_u);
                if alpha > 1.0 && alpha < alpha_u {
                    assert!((alpha - SAMPLE.compaction_distension(p)).abs() <= 1e-12);
                }
            }
        }
        let (again, alpha_again) = SAMPLE.evaluate(mu_max, alpha_u);
        assert_eq!(alpha_again, alpha_u);
        assert!(((again.base - p_max) / p_max).abs() < 1e-12);
        assert!(reloading.last().unwrap().2 < alpha_u);
    }

    #[test]
    fn hydrostatic_cycle_has_the_shape_of_seed_001_figure_4_11() {
        // GOAL: the loading/unloading cycle shows the features of seed 001 figure 4.11 (left,
        //   "Hydrostatic loading and unloading path for a concrete cylinder, with the use of
        //   P-alpha").
        // SETUP: SAMPLE, E = 0, loading tangent dp/dmu along the path by differences of
        //   consecutive steps (mu step 5e-5), unloading stiffness from the frozen-alpha terms.
        // REFERENCE: the seed's text holds only the figure's caption, no numbers, so the
        //   comparison is qualitative, feature by feature, against the curve it describes:
        //   (1) a straight elastic segment up to the crush pressure; (2) a softer compaction
        //   segment starting there (the knee); (3) stiffening again as the pores close, up
        //   to the matrix response at p_lock; (4) unloading steeper than loading; (5) a
        //   permanent density increase after unloading to zero pressure.
        let states = path(&SAMPLE, &ramp(0.0, 0.40, 8000), SAMPLE.initial_distension);
        let tangent = |i: usize| (states[i + 1].1 - states[i].1) / (states[i + 1].0 - states[i].0);
        let knee = states
            .iter()
            .position(|s| s.2 < SAMPLE.initial_distension)
            .unwrap();
        let elastic_slope = tangent(knee / 2);
        let just_after_knee = tangent(knee + 2);
        assert!(
            just_after_knee < 0.5 * elastic_slope,
            "(2) no softening at the knee"
        );
        let lock = states.iter().position(|s| s.2 == 1.0).unwrap();
        let before_lock = tangent(lock - 3);
        assert!(
            before_lock > just_after_knee,
            "(3) no stiffening towards p_lock"
        );
        let middle = (knee + lock) / 2;
        let (mu_m, _, alpha_m) = states[middle];
        let (frozen, _) = SAMPLE.evaluate(mu_m, alpha_m);
        assert!(
            frozen.d_base_d_mu > 2.0 * tangent(middle),
            "(4) unloading not steeper"
        );
        assert!(
            SAMPLE.initial_distension / alpha_m > 1.0,
            "(5) no permanent densification"
        );
        std::println!(
            "dp/dmu (GPa): elastic {:.2}, after knee {:.2}, before lock {:.2}, \
             mid-compaction loading {:.2} vs unloading {:.2}; residual rho/rho0 {:.4}",
            elastic_slope / 1e9,
            just_after_knee / 1e9,
            before_lock / 1e9,
            tangent(middle) / 1e9,
            frozen.d_base_d_mu / 1e9,
            SAMPLE.initial_distension / alpha_m
        );
    }

    #[test]
    fn pressure_is_linear_in_energy_at_the_resolved_distension() {
        // GOAL: p = [f(mu_s) + (B0 + B1 mu_s) alpha0 E]/alpha, linear in E.
        // SETUP: SAMPLE at a compacting state (mu = 0.05 from virgin), E = 1e8 J/m^3.
        // REFERENCE: the stated form with the resolved alpha; tolerance 1e-13 relative.
        let (terms, alpha) = SAMPLE.evaluate(0.05, SAMPLE.initial_distension);
        let mu_s = SAMPLE.matrix_compression(0.05, alpha);
        let energy = 1.0e8;
        let a = &SAMPLE.solid;
        let f = a.a1 * mu_s + a.a2 * mu_s * mu_s + a.a3 * mu_s * mu_s * mu_s;
        let expected = (f + (a.b0 + a.b1 * mu_s) * SAMPLE.initial_distension * energy) / alpha;
        assert!(((terms.pressure(energy) - expected) / expected).abs() < 1e-13);
        // Frozen-alpha derivatives match central differences at fixed alpha.
        let h = 1e-7;
        let up = SAMPLE.evaluate(0.05 + h, alpha).0;
        let down = SAMPLE.evaluate(0.05 - h, alpha).0;
        // Unloading by h keeps alpha; loading by h compacts further, so use the left side.
        let (left, alpha_left) = SAMPLE.evaluate(0.05 - h, alpha);
        assert_eq!(alpha_left, alpha);
        let fd = (terms.base - left.base) / h;
        assert!(((terms.d_base_d_mu - fd) / fd).abs() < 1e-5);
        assert!(up.base > terms.base && down.base < terms.base);
    }

    #[test]
    fn initial_history_is_alpha0_and_an_unseeded_zero_reads_as_alpha0() {
        // GOAL: Eos::initial_history() is alpha0; a history of 0.0 (an unseeded
        //   MaterialState) behaves as alpha0; the reference state is stress-free.
        // SETUP: SAMPLE through Eos. REFERENCE: exact.
        let eos = Eos::from(SAMPLE);
        assert_eq!(eos.initial_history(), 1.2);
        assert_eq!(eos.evaluate(0.01, 0.0), eos.evaluate(0.01, 1.2));
        assert_eq!(eos.evaluate(0.05, 0.0), eos.evaluate(0.05, 1.2));
        let (terms, alpha) = eos.evaluate(0.0, eos.initial_history());
        assert_eq!(alpha, 1.2);
        assert_eq!(terms.base, 0.0);
    }

    #[test]
    fn sound_speed_is_the_elastic_porous_one() {
        // GOAL: the Eos sound-speed helper gives the constant-distension (elastic) value.
        // SETUP: SAMPLE at the reference state, porous density rho0 = 2750/1.2 kg/m^3.
        // REFERENCE: c^2 = (A1/alpha0)/rho0 = A1/rho_s0; tolerance 1e-14 relative.
        let rho_s0 = 2750.0;
        let rho0 = rho_s0 / SAMPLE.initial_distension;
        let (terms, _) = SAMPLE.evaluate(0.0, SAMPLE.initial_distension);
        let c2 = Eos::sound_speed_squared(&terms, 0.0, 0.0, 0.0, rho0);
        assert!((c2 / (SAMPLE.solid.a1 / rho_s0) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn bad_constants_give_typed_errors() {
        // GOAL: validate() names the offending field.
        // SETUP: SAMPLE with one field broken at a time. REFERENCE: ParameterError variants.
        assert_eq!(SAMPLE.validate(), Ok(()));
        let mut eos = SAMPLE;
        eos.initial_distension = 0.9;
        assert!(matches!(
            eos.validate(),
            Err(ParameterError::OutOfRange {
                field: "initial_distension",
                ..
            })
        ));
        let mut eos = SAMPLE;
        eos.crush_pressure = -1.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::Negative {
                field: "crush_pressure",
                value: -1.0
            })
        );
        let mut eos = SAMPLE;
        eos.lock_pressure = 20.0e6;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::Inconsistent {
                field: "lock_pressure",
                other: "crush_pressure"
            })
        );
        let mut eos = SAMPLE;
        eos.exponent = 0.0;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotPositive {
                field: "exponent",
                value: 0.0
            })
        );
        let mut eos = SAMPLE;
        eos.solid.a1 = f64::NAN;
        assert_eq!(
            eos.validate(),
            Err(ParameterError::NotFinite { field: "a1" })
        );
        assert_eq!(Eos::from(SAMPLE).validate(), Ok(()));
    }
}

// The matrix constants are addressed as `solid.<name>` ([`super::Eos::get`]).
crate::struct_constants!(
    PAlpha,
    [
        initial_distension = ("alpha0", "-", crate::parameters::FIXED),
        crush_pressure = ("p_crush", "Pa", crate::parameters::FIXED),
        lock_pressure = ("p_lock", "Pa", crate::parameters::FIXED),
        exponent = ("n", "-", crate::parameters::FIXED),
    ]
);
