//! The `eos` target: every [`Eos`] variant with fuzzed constants, `validate()`, then
//! `evaluate` over a fuzzed sequence of compressions with the history carried, then a short
//! hydrostatic sequence through `update` with that EoS.
//!
//! Domains (where the strong properties are asserted; the EoS must also validate):
//! - compression `mu` in `[-0.5, 1]` (`V/V0` in `[0.5, 2]`); incoming history: tabulated
//!   compaction `h` in `[0, 1]`, P-alpha `alpha` in `[1, alpha0]` or the unseeded `0`;
//! - linear: `K` in `[1e8, 1e12]` Pa (log);
//! - Mie-Grüneisen: `rho0` in `[100, 25000]`, `C` in `[100, 1e4]` m/s, `S1` in `[0, 5]`,
//!   `S2`, `S3` in `[-10, 10]`, `gamma0` in `[0, 4]`, `a` in `[-1, 2]`;
//! - polynomial (also the P-alpha matrix): `A1`, `T1` in `[1e8, 1e12]` Pa (log), `A2`, `A3`,
//!   `T2` in `[-1e12, 1e12]` Pa, `B0`, `B1` in `[-5, 5]`;
//! - JWL: `A` in `[1e9, 1e13]` Pa (log), `B` in `[-1e12, 1e12]` Pa, `R1` in `[1, 15]`,
//!   `R2` in `[0.1, 5]`, `w` in `[0.05, 1]`, `rho0` in `[500, 3000]`, `E0` in
//!   `[1e8, 2e10]` J/m^3, `D` in `[1000, 10000]` m/s, `P_CJ` in `[1e9, 1e11]` Pa;
//! - tabulated compaction: 2 to 16 points from `eps = 0`, strain steps in `[1e-5, 0.1]`,
//!   pressure steps in `[0, 1 GPa]`, unloading moduli in `[1e8, 1e12]` Pa (log);
//! - P-alpha: `alpha0` in `[1, 3]`, `p_crush` in `[0, 1 GPa]`, `p_lock - p_crush` in
//!   `[1 MPa, 10 GPa]` (log), `n` in `[0.1, 10]`.
//!
//! Properties of `evaluate`, beyond "no panic" and determinism (bitwise): for a validated EoS
//! in domain the four terms and the new history are finite, except Mie-Grüneisen at or past
//! its limiting compression (Hugoniot denominator `D(mu) < 1e-6`, where its module docs return
//! `+inf`); history-free EoS return the history
//! unchanged; tabulated compaction returns `max(h, ln(1 + mu))`; P-alpha returns a distension
//! in `[1, alpha_in]` (the incoming value read as documented: below 1 or NaN as `alpha0`,
//! above `alpha0` capped); the history-dependent EoS are idempotent (re-evaluating at the same
//! `mu` with the returned history returns the same bits); the reference state is stress-free
//! (`base(0) = 0` for linear, Mie-Grüneisen, polynomial, virgin P-alpha and tabulated).

use crate::check::{run_steps, FuzzStep, Tally};
use crate::source::Source;
use stoss_kernel::eos::{
    CompactionPoint, EnergyLinearPressure, Eos, Jwl, LinearEos, MieGruneisen, PAlpha, Polynomial,
    TabulatedCompaction, MAX_COMPACTION_POINTS,
};
use stoss_kernel::strength::JohnsonCook;
use stoss_kernel::{Material, MaterialState, StepInput};

fn polynomial(src: &mut Source) -> Polynomial {
    Polynomial {
        a1: src.log(1e8, 1e12),
        a2: src.linear(-1e12, 1e12),
        a3: src.linear(-1e12, 1e12),
        b0: src.linear(-5.0, 5.0),
        b1: src.linear(-5.0, 5.0),
        t1: src.log(1e8, 1e12),
        t2: src.linear(-1e12, 1e12),
    }
}

/// A fuzzed EoS, or `None` when a tabulated curve was rejected by its constructor (that path
/// is the constructor's validation; it is still exercised).
fn eos(src: &mut Source) -> Option<Eos> {
    Some(match src.choice(6) {
        0 => Eos::Linear(LinearEos {
            bulk_modulus: src.log(1e8, 1e12),
        }),
        1 => Eos::MieGruneisen(MieGruneisen {
            reference_density: src.linear(100.0, 25000.0),
            sound_speed: src.linear(100.0, 1e4),
            s1: src.linear(0.0, 5.0),
            s2: src.linear(-10.0, 10.0),
            s3: src.linear(-10.0, 10.0),
            gamma0: src.linear(0.0, 4.0),
            volume_correction: src.linear(-1.0, 2.0),
        }),
        2 => Eos::Polynomial(polynomial(src)),
        3 => Eos::Jwl(Jwl {
            a: src.log(1e9, 1e13),
            b: src.linear(-1e12, 1e12),
            r1: src.linear(1.0, 15.0),
            r2: src.linear(0.1, 5.0),
            omega: src.linear(0.05, 1.0),
            reference_density: src.linear(500.0, 3000.0),
            detonation_energy: src.log(1e8, 2e10),
            detonation_velocity: src.linear(1000.0, 10000.0),
            cj_pressure: src.log(1e9, 1e11),
        }),
        4 => {
            let count = src.count(2, MAX_COMPACTION_POINTS as u8 + 1) as usize;
            let mut points = [CompactionPoint::new(0.0, 0.0, 1e9); MAX_COMPACTION_POINTS + 1];
            let mut strain = 0.0;
            let mut pressure = 0.0;
            for (i, point) in points.iter_mut().take(count).enumerate() {
                if i > 0 {
                    strain += src.linear(1e-5, 0.1);
                    pressure += src.linear(0.0, 1e9);
                }
                *point = CompactionPoint::new(strain, pressure, src.log(1e8, 1e12));
            }
            // count may be one above the maximum: the constructor must refuse it.
            let table = TabulatedCompaction::new(&points[..count]);
            if count > MAX_COMPACTION_POINTS {
                assert!(table.is_err(), "17 points accepted");
            }
            Eos::TabulatedCompaction(table.ok()?)
        }
        _ => {
            let solid = polynomial(src);
            let crush_pressure = src.linear(0.0, 1e9);
            Eos::PAlpha(PAlpha {
                solid,
                initial_distension: src.linear(1.0, 3.0),
                crush_pressure,
                lock_pressure: crush_pressure + src.log(1e6, 1e10),
                exponent: src.linear(0.1, 10.0),
            })
        }
    })
}

fn terms_bits(t: &EnergyLinearPressure) -> [u64; 4] {
    [
        t.base.to_bits(),
        t.d_base_d_mu.to_bits(),
        t.energy_coefficient.to_bits(),
        t.d_energy_coefficient_d_mu.to_bits(),
    ]
}

fn terms_finite(t: &EnergyLinearPressure) -> bool {
    t.base.is_finite()
        && t.d_base_d_mu.is_finite()
        && t.energy_coefficient.is_finite()
        && t.d_energy_coefficient_d_mu.is_finite()
}

/// The Mie-Grüneisen Hugoniot denominator `D(mu)` of the module docs (1 in expansion).
fn mie_gruneisen_denominator(eos: &MieGruneisen, mu: f64) -> f64 {
    if mu <= 0.0 {
        return 1.0;
    }
    let one_plus = 1.0 + mu;
    1.0 - (eos.s1 - 1.0) * mu
        - eos.s2 * mu * mu / one_plus
        - eos.s3 * mu * mu * mu / (one_plus * one_plus)
}

/// A fuzzed incoming history for `eos`.
fn history(src: &mut Source, eos: &Eos) -> f64 {
    match eos {
        Eos::TabulatedCompaction(_) => src.linear(0.0, 1.0),
        Eos::PAlpha(p) => {
            if src.byte() & 7 == 0 {
                0.0
            } else {
                src.linear(1.0, p.initial_distension.max(1.0))
            }
        }
        // Unused by the history-free EoS: any value, which must come back unchanged.
        _ => src.linear(-1.0, 1.0),
    }
}

fn check_evaluate(eos: &Eos, mu: f64, history: f64, checked: bool) -> f64 {
    let (terms, new_history) = eos.evaluate(mu, history);
    let (again, again_history) = eos.evaluate(mu, history);
    let context = || format!("eos: {eos:?}\nmu: {mu:?}\nhistory: {history:?}");
    assert!(
        terms_bits(&terms) == terms_bits(&again)
            && new_history.to_bits() == again_history.to_bits(),
        "evaluate is not deterministic\n{}",
        context()
    );
    if !checked {
        return new_history;
    }
    let finite_expected = match eos {
        Eos::MieGruneisen(mg) => mie_gruneisen_denominator(mg, mu) >= 1e-6,
        _ => true,
    };
    if finite_expected {
        assert!(
            terms_finite(&terms) && new_history.is_finite(),
            "non-finite EoS terms {terms:?} / history {new_history:?}\n{}",
            context()
        );
    }
    match eos {
        Eos::Linear(_) | Eos::MieGruneisen(_) | Eos::Polynomial(_) | Eos::Jwl(_) => {
            assert_eq!(
                new_history.to_bits(),
                history.to_bits(),
                "history-free EoS changed the history\n{}",
                context()
            );
        }
        Eos::TabulatedCompaction(_) => {
            let strain = stoss_kernel::math::ln(1.0 + mu);
            let expected = if strain >= history { strain } else { history };
            assert_eq!(
                new_history.to_bits(),
                expected.to_bits(),
                "tabulated compaction history is not max(h, ln(1 + mu))\n{}",
                context()
            );
        }
        Eos::PAlpha(p) => {
            let incoming = if history >= 1.0 && history <= p.initial_distension {
                history
            } else {
                p.initial_distension
            };
            assert!(
                new_history >= 1.0 && new_history <= incoming,
                "P-alpha distension {new_history} outside [1, {incoming}]\n{}",
                context()
            );
        }
    }
    if matches!(eos, Eos::TabulatedCompaction(_) | Eos::PAlpha(_)) {
        let (repeat, repeat_history) = eos.evaluate(mu, new_history);
        assert!(
            terms_bits(&repeat) == terms_bits(&terms)
                && repeat_history.to_bits() == new_history.to_bits(),
            "re-evaluation at the same mu with the returned history {new_history:?} changed \
             the result: {terms:?} -> {repeat:?}, history -> {repeat_history:?}\n{}",
            context()
        );
    }
    new_history
}

/// One fuzz case of the `eos` target.
pub fn run(data: &[u8]) -> Tally {
    let mut src = Source::new(data);
    let Some(eos) = eos(&mut src) else {
        return Tally::default();
    };
    let eos_in_domain = src.take_domain();
    let valid = eos.validate().is_ok();
    let checked = valid && eos_in_domain;

    if checked && !matches!(eos, Eos::Jwl(_)) {
        let (terms, _) = eos.evaluate(0.0, eos.initial_history());
        assert_eq!(
            terms.base, 0.0,
            "reference state not stress-free: {terms:?}\neos: {eos:?}"
        );
    }

    // evaluate over a fuzzed path, history carried (and sometimes replaced).
    src.take_domain();
    let mut carried = history(&mut src, &eos);
    let mut carried_in_domain = src.take_domain();
    let evaluations = src.count(1, 10);
    for _ in 0..evaluations {
        src.take_domain();
        let mu = src.linear(-0.5, 1.0);
        let mu_in_domain = src.take_domain();
        if src.byte() & 3 == 0 {
            carried = history(&mut src, &eos);
            carried_in_domain = src.take_domain();
        }
        carried = check_evaluate(
            &eos,
            mu,
            carried,
            checked && mu_in_domain && carried_in_domain,
        );
        // The returned history depends on mu: out of domain from now on if mu was.
        carried_in_domain = carried_in_domain && mu_in_domain;
    }

    // The same EoS inside the stress update: 4340 JC strength, fuzzed density, hydrostatic
    // steps (|d| <= 0.02 per axis) with a consistent volume, dt in [1e-9, 1e-3].
    src.take_domain();
    let mut material = Material::STEEL_4340.with_strength(JohnsonCook::STEEL_4340);
    material.density = src.linear(100.0, 20000.0);
    material.eos = eos;
    let material_in_domain = src.take_domain();
    let mut state = MaterialState::initial(298.0);
    state.eos_history = eos.initial_history();
    if let Eos::Jwl(jwl) = eos {
        state.internal_energy = jwl.detonation_energy;
    }
    let count = src.count(1, 8);
    let mut volume: f64 = 1.0;
    let steps: Vec<FuzzStep> = (0..count)
        .map(|_| {
            src.take_domain();
            let d = src.linear(-0.02, 0.02);
            let dt = src.log(1e-9, 1e-3);
            volume *= (3.0 * d).exp();
            let in_domain = src.take_domain() && (0.5..=2.0).contains(&volume);
            FuzzStep {
                input: StepInput {
                    strain_increment: [d, d, d, 0.0, 0.0, 0.0],
                    dt,
                    relative_volume: volume,
                },
                tangent: src.flag(),
                in_domain,
            }
        })
        .collect();
    let mut tally = run_steps(
        &material,
        checked && material_in_domain && material.validate().is_ok(),
        state,
        true,
        &steps,
    );
    tally.steps += u64::from(evaluations);
    tally
}
