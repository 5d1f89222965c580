//! Regressions found by the cargo-fuzz targets in `fuzz/` (see `fuzz/README.md`). Each test
//! is the fuzzer's reproducer (the exact values it printed, bit for bit where it matters)
//! or a smaller hand-made case of the same defect; the byte inputs are in
//! `fuzz/regressions/<target>/`. The return-mapping defects were found against commit
//! 992507f (`MAX_RETURN_ITERATIONS = 100`, linear bisection, unguarded Newton steps).

use stoss_kernel::eos::{Eos, LinearEos};
use stoss_kernel::rht::{update as rht_update, RhtMaterial};
use stoss_kernel::strength::{
    CrystalStructure, JohnsonCook, ModifiedJohnsonCook, Strength, ZerilliArmstrong,
};
use stoss_kernel::{
    update, Heating, Material, MaterialState, StateFlags, StepInput, StepOutput, UpdateError,
};

/// `q_{n+1} <= sigma_y(eps_{n+1}, dl/dt, T_n) (1 + 1e-9) + 1e-6 Pa` after an implicit plastic
/// step (the property the fuzz targets assert, without the large-pressure round-off term,
/// which these cases do not need).
fn assert_on_yield_surface(material: &Material, before: &MaterialState, after: &MaterialState) {
    assert!(after.flags.contains(StateFlags::PLASTIC));
    let flow = material
        .strength
        .flow_stress(
            after.plastic_strain,
            after.plastic_strain_rate,
            before.temperature,
        )
        .value;
    let q = after.equivalent_stress();
    assert!(
        q <= flow * (1.0 + 1e-9) + 1e-6,
        "q {q:e} > sigma_y {flow:e}"
    );
}

fn run(material: &Material, state: &mut MaterialState, input: &StepInput) -> StepOutput {
    let before = *state;
    let result = update(material, state, input);
    assert_ne!(
        result,
        Err(UpdateError::ReturnMappingDiverged),
        "update.rs documents that the iteration bound is never the reason for a result"
    );
    let output = result.expect("a validated material in its domain must update");
    assert!(output.plastic_increment > 0.0);
    assert_on_yield_surface(material, &before, state);
    output
}

/// A Johnson-Cook material in seed 000's bounds with a small hardening exponent `n` puts the
/// root of `q_trial - 3G dl - sigma_y(dl) = 0` at a tiny `dl` (here about 1e-70: `B dl^n`
/// climbs from 0 to a large fraction of `B` within a few ulps of 0). The return mapping's
/// bisection halves the bracket `[0, q_trial/3G]` linearly and stops only when
/// `upper - lower <= EPSILON * upper`, so reaching `dl ~ 1e-70` from `~5e-3` takes about
/// 220 halvings; Newton steps leave the bracket every time (the residual is concave in `dl`),
/// so after `MAX_RETURN_ITERATIONS = 100` the update returns `ReturnMappingDiverged`,
/// contradicting update.rs ("bisection alone shrinks the bracket by 2^-100, far below double
/// precision, so the bound is never the reason for a result": true relative to the bracket,
/// not near a root at 0).
///
/// Hand-made case: JC A = B = 1 GPa, n = 0.01 (bounds: n in [0, 1]), C = 0, 4340 elsewhere,
/// isothermal at the reference temperature, virgin state, simple shear with q_trial =
/// 1.2 GPa.
#[test]
fn small_hardening_exponent_return_mapping_converges() {
    let jc = JohnsonCook {
        yield_stress: 1.0e9,
        hardening_modulus: 1.0e9,
        hardening_exponent: 0.01,
        rate_sensitivity: 0.0,
        ..JohnsonCook::STEEL_4340
    };
    assert_eq!(jc.validate(), Ok(()));
    let material = Material {
        heating: Heating::Isothermal,
        ..Material::STEEL_4340.with_strength(jc)
    };
    assert_eq!(material.validate(), Ok(()));
    let mut state = MaterialState::initial(298.0);
    // q_trial = sqrt(3) * 2G * gamma = 1.2 GPa.
    let gamma = 1.2e9 / (stoss_kernel::math::sqrt(3.0) * 2.0 * material.shear_modulus);
    let input = StepInput {
        strain_increment: [0.0, 0.0, 0.0, gamma, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    run(&material, &mut state, &input);
}

/// Same defect at the limit: MJC with a subnormal hardening exponent (n = 1e-310, inside
/// the bounds [0, 1]). `B dl^n` equals `B` for every positive double `dl` and 0 at `dl = 0`,
/// so no positive double is a root; the bisection has to walk the bracket down to the
/// smallest subnormal (about 1070 halvings) and `upper - lower <= EPSILON * upper` never
/// holds there. Expected: a result on (or inside) the yield surface, e.g. the smallest `dl`
/// with `g(dl) <= 0`.
#[test]
fn subnormal_hardening_exponent_return_mapping_converges() {
    let mjc = ModifiedJohnsonCook {
        yield_stress: 0.75e9,
        hardening_modulus: 0.9e9,
        hardening_exponent: 1e-310,
        saturation_stress_1: 0.0,
        saturation_rate_1: 0.0,
        saturation_stress_2: 0.0,
        saturation_rate_2: 0.0,
        rate_exponent: 0.0,
        reference_rate: 1.0,
        thermal_exponent: 1.0,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };
    assert_eq!(mjc.validate(), Ok(()));
    let material = Material {
        heating: Heating::Isothermal,
        ..Material::STEEL_4340.with_strength(mjc)
    };
    let mut state = MaterialState::initial(298.0);
    let gamma = 1.2e9 / (stoss_kernel::math::sqrt(3.0) * 2.0 * material.shear_modulus);
    let input = StepInput {
        strain_increment: [0.0, 0.0, 0.0, gamma, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    run(&material, &mut state, &input);
}

/// Same defect in Zerilli-Armstrong BCC at its lower bound `n = 0.01` (seed 000 bounds
/// `[0.01, 1.5]`), rate-independent (`C4 = 0`): the root of `C5 dl^0.01 = 0.2 GPa` is near
/// `0.2^100 ~ 1e-70` (the fuzzer's `crash-8ee27cbc...` is this case with `C3 > 0`).
#[test]
fn za_bcc_lowest_bound_hardening_exponent_return_mapping_converges() {
    let za = ZerilliArmstrong {
        structure: CrystalStructure::Bcc,
        athermal_stress: 0.5e9,
        c1: 0.5e9,
        c2: 0.0,
        c3: 0.0,
        c4: 0.0,
        c5: 1.0e9,
        exponent: 0.01,
        reference_rate: 1.0,
    };
    assert_eq!(za.validate(), Ok(()));
    let material = Material {
        heating: Heating::Isothermal,
        ..Material::STEEL_4340.with_strength(za)
    };
    let mut state = MaterialState::initial(298.0);
    // q_trial = 1.2 GPa: the root is where C5 dl^0.01 = 0.2 GPa (minus 3G dl).
    let gamma = 1.2e9 / (stoss_kernel::math::sqrt(3.0) * 2.0 * material.shear_modulus);
    let input = StepInput {
        strain_increment: [0.0, 0.0, 0.0, gamma, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    run(&material, &mut state, &input);
}

/// A second mechanism, Zerilli-Armstrong only: a steep rate dependence. With `C3 = 0`,
/// `C4 = 1e-3 /K` (both inside the bounds) at 4000 K, `sigma_y ~ C1 (rate/e0)^(C4 T)` is a
/// fourth power of the rate; with `dt = 1e-9 s` and `e0 = 1e-3 /s` the root is near
/// `dl ~ 1e-12` while the first iterate is `~1`. Newton steps from the steep side stay inside
/// the bracket, so they are accepted, but on `x^4` each one only shrinks `dl` by 1/4: about
/// 100 iterations before the end game, and the bracket is never bisected.
/// Fuzzer reproducer, `fuzz/regressions/strength_update_za/crash-9af6d5a4...` (step 0;
/// values as printed by the harness).
#[test]
fn fuzz_za_bcc_steep_rate_return_mapping_converges() {
    let material = Material {
        density: 12160.363961718173,
        shear_modulus: 1000000001.0311643,
        specific_heat: 100.0,
        strength: Strength::from(ZerilliArmstrong {
            structure: CrystalStructure::Bcc,
            athermal_stress: 789330005.5546572,
            c1: 2999999999.9999995,
            c2: 2999999999.9999995,
            c3: 3.906249999999889e-5,
            c4: 0.001,
            c5: 3000000000.0,
            exponent: 1.5,
            reference_rate: 0.001,
        }),
        heating: Heating::Isothermal,
        eos: Eos::Linear(LinearEos {
            bulk_modulus: 1000000000.0,
        }),
        ..Material::STEEL_4340
    };
    assert_eq!(material.validate(), Ok(()));
    let mut state = MaterialState {
        stress: [
            -5000000000.0,
            4468717274.962048,
            4999999998.284294,
            4999999999.999998,
            4999999999.999998,
            4999999403.9626465,
        ],
        plastic_strain: 1.1690403917882233e-8,
        plastic_strain_rate: 0.0,
        temperature: 3999.9999999999995,
        damage: 0.9999999999999999,
        relative_volume: 1.9999999999999998,
        internal_energy: -539550781.2500019,
        eos_history: 0.0,
        flags: StateFlags(0),
        yield_check: stoss_kernel::YieldCheck::NONE,
    };
    let input = StepInput {
        strain_increment: [
            -0.0039062499887341368,
            -0.022293476373156953,
            -0.02714468110935535,
            -0.04999999446451375,
            -0.05,
            -0.05,
        ],
        dt: 1e-9,
        relative_volume: 0.5,
    };
    run(&material, &mut state, &input);
}

/// The fuzzer's Johnson-Cook reproducer, `fuzz/regressions/strength_update_jc/crash-9e8e6e3d...`
/// (step 4 of its sequence; state as printed by the harness): n = 0.0039, hot (T* = 0.79),
/// dt = 1e-9 s, under 52 GPa of pressure. Same defect as
/// [`small_hardening_exponent_return_mapping_converges`].
#[test]
fn fuzz_jc_small_exponent_return_mapping_converges() {
    let material = Material {
        density: 10500.0,
        shear_modulus: 1000000000.0,
        specific_heat: 1050.0,
        strength: Strength::from(JohnsonCook {
            yield_stress: 2868075113.5687566,
            hardening_modulus: 2759472087.731282,
            hardening_exponent: 0.0039141763657409845,
            rate_sensitivity: 0.07928575468605492,
            thermal_exponent: 1.5,
            reference_rate: 1.7878551261958109,
            reference_temperature: 300.0,
            melting_temperature: 2590.8511997772603,
        }),
        heating: Heating::Isothermal,
        eos: Eos::Linear(LinearEos {
            bulk_modulus: 51836989031.82575,
        }),
        ..Material::STEEL_4340
    };
    assert_eq!(material.validate(), Ok(()));
    let mut state = MaterialState {
        stress: [
            -51778949816.13948,
            -51953067463.1983,
            -51778949816.13948,
            -374117647.0588201,
            -200000000.0,
            -200000000.0,
        ],
        plastic_strain: 0.0,
        plastic_strain_rate: 0.0,
        temperature: 2100.0,
        damage: 0.5,
        relative_volume: 0.5,
        internal_energy: 14679533718.537924,
        eos_history: 0.0,
        flags: StateFlags(0),
        yield_check: stoss_kernel::YieldCheck::NONE,
    };
    let input = StepInput {
        strain_increment: [-0.05; 6],
        dt: 1e-9,
        relative_volume: 0.5,
    };
    run(&material, &mut state, &input);
}

/// RHT: a tiny but non-zero trial deviator (below about 1e-103 Pa) gives a NaN Lode angle:
/// in `Lode::from_deviator`, `J3` and `J2^(3/2)` both underflow to 0 and `cos 3theta = 0/0`
/// passes through the clamp, so every surface is NaN. `trial > NaN` is false, the step is
/// taken as elastic (the stress stays finite) but `StepOutput::yield_stress` is NaN, and the
/// final finiteness check covers only the state and the wave speed. Fuzzer reproducer:
/// `fuzz/regressions/rht_update/` (strain increment components of 7.6e-142); here seed 001's
/// HPC from its initial state with a 1e-142 shear increment.
#[test]
fn rht_tiny_deviator_gives_finite_output() {
    let material = RhtMaterial::HPC_92MPA;
    assert_eq!(material.validate(), Ok(()));
    let mut state = material.initial_state(293.0);
    let input = StepInput {
        strain_increment: [0.0, 0.0, 0.0, 1e-142, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    let output = rht_update(&material, &mut state, &input).expect("a tiny elastic step");
    assert!(state.is_finite());
    assert!(
        output.yield_stress.is_finite() && output.wave_speed.is_finite(),
        "{output:?}"
    );
}

/// The implicit return once accepted a Newton step on the flow stress's curvature alone,
/// whatever the step's size. A one-step return of `dl ~ 2` through a Voce term (`c ~ 8`) met
/// the test at a point where the Voce curvature was exponentially small, though not along the
/// step: the state was left 1e-8 outside the yield surface (the `strength_update_mjc`
/// fuzzer, and `strength_update_tjc` on the same hardening; reproducers in
/// `fuzz/regressions/`). Fixed by stopping without a last evaluation only for steps below
/// 1e-3 of the multiplier (`update::CORRECTION_STEP_LIMIT`).
#[test]
fn fuzz_large_step_through_a_voce_term_stays_on_the_yield_surface() {
    // GOAL: a one-step plastic return of dl ~ 2 ends on the yield surface.
    // SETUP: the fuzzer's material (MJC hardening, A 1.5 GPa, B 3 GPa, n 1, Voce Q1 1.275 GPa,
    //        c1 7.84; no rate term; G 1 GPa, K 1 GPa, isothermal), virgin state at 200 K,
    //        tensor shear increments 2.55 in xy, yz, zx (q_trial 1.53e10 Pa), dt 1e-9 s,
    //        relative volume 0.5.
    // REFERENCE: q <= sigma_y (1 + 1e-9) + 1e-6 Pa at the new state (`assert_on_yield_surface`).
    let material = Material {
        density: 1000.0,
        shear_modulus: 1.0e9,
        specific_heat: 100.0,
        strength: Strength::Composed(stoss_kernel::strength::ComposedStrength {
            hardening: stoss_kernel::strength::Hardening::PowerVoce2 {
                yield_stress: 1.5e9,
                hardening_modulus: 3.0e9,
                exponent: 1.0,
                saturation_stress_1: 1275251426.3884964,
                saturation_rate_1: 7.843137256459132,
                saturation_stress_2: 3.0e9,
                saturation_rate_2: 0.0,
            },
            rate: stoss_kernel::strength::RateTerm::Power {
                exponent: 0.0,
                reference_rate: 0.001,
            },
            thermal: stoss_kernel::strength::ThermalTerm::HomologousPower {
                exponent: 0.5,
                reference_temperature: 250.0,
                melting_temperature: 800.0,
            },
        }),
        heating: Heating::Isothermal,
        eos: Eos::Linear(LinearEos {
            bulk_modulus: 1.0e9,
        }),
        ..Material::STEEL_4340
    };
    material.validate().unwrap();
    let mut state = MaterialState::initial(200.0);
    let volumetric = stoss_kernel::math::ln(0.5) / 3.0;
    let input = StepInput {
        strain_increment: [volumetric, volumetric, volumetric, 2.55, 2.55, 2.55],
        dt: 1.0e-9,
        relative_volume: 0.5,
    };
    let output = run(&material, &mut state, &input);
    assert!(output.plastic_increment > 1.0, "{output:?}");
}

#[test]
fn a_kc_material_with_a_biaxial_ratio_below_one_half_does_not_recurse() {
    // GOAL: kc_update's chaos seed (fuzz/regressions/kc_update/) overflowed the stack: the
    //       meridian ratio evaluated the maximum surface at the biaxial pressure `2 alpha
    //       fc/3`, which for `alpha < 1/2` lies below `fc/3`, where the maximum surface asks
    //       the meridian ratio again. Invalid constants must give a result or an error, never
    //       a crash.
    // SETUP: HPC_100MPA_FOI with biaxial ratio 0.3 (validate() refuses it), one step of
    //        uniaxial compression that reaches the low-pressure branch.
    // REFERENCE: the update returns (Ok or Err), the surfaces are finite.
    use stoss_kernel::kc::{update as kc_update, KcMaterial, KcParameters};
    let material = KcMaterial {
        parameters: KcParameters {
            biaxial_ratio: 0.3,
            ..KcParameters::HPC_100MPA_FOI
        },
        ..KcMaterial::HPC_100MPA_FOI
    };
    assert!(material.validate().is_err());
    assert!(material.parameters.maximum_meridian(10.0e6).is_finite());
    let mut state = material.initial_state(293.0);
    let input = StepInput {
        strain_increment: [-1.0e-3, 2.0e-4, 2.0e-4, 0.0, 0.0, 0.0],
        dt: 1.0e-6,
        relative_volume: stoss_kernel::math::exp(-6.0e-4),
    };
    let _ = kc_update(&material, &mut state, &input);
}

#[test]
fn the_kc_damage_measure_never_loses_an_ulp() {
    // GOAL: kc_update found the damage measure 1 ulp lower after lambda grew by 1 ulp
    //       (lambda/(lambda + lambda_m) rounds both ways); written 1 - lambda_m/(lambda +
    //       lambda_m) every operation is monotone.
    // SETUP: the reproducer's lambda (fuzz/regressions/kc_update/damage-measure-lost-an-ulp)
    //        and its next 1000 doubles, lambda_m of its table.
    // REFERENCE: non-decreasing measure.
    use stoss_kernel::kc::damage_measure;
    let peak = 3.224_733_310_375_842_6e-6;
    let mut lambda: f64 = 1.751_239_267_264_592_9e-6;
    let mut previous = damage_measure(lambda, peak, 0.0);
    for _ in 0..1000 {
        lambda = f64::from_bits(lambda.to_bits() + 1);
        let measure = damage_measure(lambda, peak, 0.0);
        assert!(measure >= previous, "{lambda:e}: {measure} < {previous}");
        previous = measure;
    }
}

#[test]
fn a_kc_snap_back_never_returns_below_zero_strength() {
    // GOAL: kc_update found a return that passed snap-back segments whole and removed more
    //       than the trial deviator (stored q above a negative reported strength).
    // SETUP: the reproducer (fuzz/regressions/kc_update/snap-back-passes-removed-more-than-
    //        the-deviator): a three-point damage function peaking at 1.46e-4, exponents 0,
    //        one step from the virgin state to V = 2 (deep hydrostatic tension).
    // REFERENCE: reported strength >= 0 and the stored q on or inside it.
    use stoss_kernel::kc::{update as kc_update, DamageFunction, KcMaterial, KcParameters};
    let parameters = KcParameters {
        maximum_surface: [
            14_479_003.663_965_221,
            0.390_373_994_880_708,
            1.262_239_668_097_613_6e-9,
        ],
        yield_surface: [
            10_929_382.050_370_17,
            0.637_075_498_937_181,
            5.557_856_816_288_592e-9,
        ],
        residual_surface: [0.552_123_685_181_770_9, 2.642_928_596_773_876e-9],
        biaxial_ratio: 1.000_000_000_000_273,
        compression_damage_exponent: 0.0,
        tension_damage_exponent: 0.0,
        damage: DamageFunction::from_points(&[
            (0.0, 0.0),
            (1.461_187_278_110_748_5e-4, 1.0),
            (4.695_663_192_985_233e-4, 0.0),
        ]),
        ..KcParameters::from_strength(
            55_999_999.462_968_074,
            8_246_282.735_842_79,
            7_924_465_996.292_801,
        )
    };
    let material = KcMaterial {
        density: 1500.0,
        parameters,
        eos: Eos::Linear(LinearEos {
            bulk_modulus: 23_892_748_959.183_857,
        }),
        erosion_geometric_strain: None,
    };
    let mut state = material.initial_state(293.0);
    let input = StepInput {
        strain_increment: [
            -0.024_840_800_137_298_16,
            -0.021_348_620_268_396_058,
            -0.009_038_873_568_631_908,
            0.016_538_339_870_508_33,
            -0.033_137_254_901_960_79,
            -0.033_137_254_901_960_79,
        ],
        dt: 2.008_397_896_240_989e-9,
        relative_volume: 2.0,
    };
    let output = kc_update(&material, &mut state, &input).expect("update");
    assert!(output.yield_stress >= 0.0, "{output:?}");
    assert!(state.equivalent_stress() <= output.yield_stress * (1.0 + 1e-9) + 1e-6);
}
