//! Bad parameters and bad step inputs are rejected with typed errors, and the state is left
//! untouched.

use stoss_kernel::strength::{
    CrystalStructure, JohnsonCook, ModifiedJohnsonCook, Strength, TwoRateJohnsonCook,
    ZerilliArmstrong,
};
use stoss_kernel::{
    update, Heating, Material, MaterialState, ParameterError, StepInput, UpdateError,
};

#[test]
fn non_physical_johnson_cook_constants_are_rejected() {
    // GOAL: validate() names the offending field with a typed error.
    // SETUP: 4340 JC with one field broken at a time.
    // REFERENCE: the ParameterError variant and field.
    let mut jc = JohnsonCook::STEEL_4340;
    jc.yield_stress = -1.0;
    assert_eq!(
        jc.validate(),
        Err(ParameterError::NotPositive {
            field: "yield_stress",
            value: -1.0
        })
    );
    let mut jc = JohnsonCook::STEEL_4340;
    jc.hardening_exponent = f64::NAN;
    assert_eq!(
        jc.validate(),
        Err(ParameterError::NotFinite {
            field: "hardening_exponent"
        })
    );
    let mut jc = JohnsonCook::STEEL_4340;
    jc.melting_temperature = 200.0;
    assert_eq!(
        jc.validate(),
        Err(ParameterError::Inconsistent {
            field: "melting_temperature",
            other: "reference_temperature"
        })
    );
    let mut jc = JohnsonCook::STEEL_4340;
    jc.rate_sensitivity = -0.01;
    assert!(matches!(
        jc.validate(),
        Err(ParameterError::OutOfRange {
            field: "rate_sensitivity",
            ..
        })
    ));
}

#[test]
fn non_physical_za_mjc_tjc_constants_are_rejected() {
    // GOAL: each family rejects a negative constant and an inconsistent pair.
    // SETUP: one broken field per family. REFERENCE: typed errors.
    let za = ZerilliArmstrong {
        structure: CrystalStructure::Bcc,
        athermal_stress: 65e6,
        c1: 1033e6,
        c2: 0.0,
        c3: -0.1,
        c4: 0.000415,
        c5: 266e6,
        exponent: 0.289,
        reference_rate: 1.0,
    };
    assert_eq!(
        za.validate(),
        Err(ParameterError::Negative {
            field: "c3",
            value: -0.1
        })
    );
    let mjc = ModifiedJohnsonCook {
        yield_stress: 1e9,
        hardening_modulus: 5e8,
        hardening_exponent: 0.3,
        saturation_stress_1: -1.0,
        saturation_rate_1: 10.0,
        saturation_stress_2: 0.0,
        saturation_rate_2: 0.0,
        rate_exponent: 0.01,
        reference_rate: 1.0,
        thermal_exponent: 1.0,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };
    assert!(matches!(
        mjc.validate(),
        Err(ParameterError::Negative {
            field: "saturation_stress_1",
            ..
        })
    ));
    let tjc = TwoRateJohnsonCook {
        yield_stress: 1e9,
        hardening_modulus: 5e8,
        hardening_exponent: 0.3,
        saturation_stress_1: 0.0,
        saturation_rate_1: 0.0,
        saturation_stress_2: 0.0,
        saturation_rate_2: 0.0,
        rate_exponent_1: 0.01,
        reference_rate_1: 10.0,
        rate_exponent_2: 0.05,
        reference_rate_2: 1.0,
        thermal_exponent: 1.0,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };
    assert_eq!(
        tjc.validate(),
        Err(ParameterError::Inconsistent {
            field: "reference_rate_2",
            other: "reference_rate_1"
        })
    );
}

#[test]
fn material_level_fields_are_validated() {
    // GOAL: density, moduli, heating are checked. REFERENCE: typed errors.
    let mut material = Material::STEEL_4340;
    material.density = 0.0;
    assert!(matches!(
        material.validate(),
        Err(ParameterError::NotPositive {
            field: "density",
            ..
        })
    ));
    let mut material = Material::STEEL_4340;
    material.heating = Heating::Adiabatic {
        taylor_quinney: 1.5,
    };
    assert!(matches!(
        material.validate(),
        Err(ParameterError::OutOfRange {
            field: "taylor_quinney",
            ..
        })
    ));
    assert_eq!(Material::STEEL_4340.validate(), Ok(()));
    let strength: Strength = JohnsonCook::HNS_FOI.into();
    assert_eq!(strength.validate(), Ok(()));
}

#[test]
fn bad_step_inputs_leave_the_state_unchanged() {
    // GOAL: NaN strain, non-positive dt or volume give typed errors, no partial update.
    // SETUP: a pre-loaded 4340 state, each bad input in turn.
    // REFERENCE: UpdateError variants; state bit-identical afterwards.
    let material = Material::STEEL_4340;
    let mut state = MaterialState::initial(298.0);
    let good = StepInput {
        strain_increment: [1e-3, -5e-4, -5e-4, 0.0, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    update(&material, &mut state, &good).unwrap();
    let before = state;
    let cases = [
        (
            StepInput {
                strain_increment: [f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0],
                ..good
            },
            UpdateError::NonFiniteInput,
        ),
        (
            StepInput { dt: 0.0, ..good },
            UpdateError::NonPositiveTimeStep,
        ),
        (
            StepInput { dt: -1e-6, ..good },
            UpdateError::NonPositiveTimeStep,
        ),
        (
            StepInput {
                relative_volume: -0.1,
                ..good
            },
            UpdateError::NonPositiveVolume,
        ),
        (
            StepInput {
                relative_volume: f64::INFINITY,
                ..good
            },
            UpdateError::NonFiniteInput,
        ),
    ];
    for (input, expected) in cases {
        assert_eq!(update(&material, &mut state, &input), Err(expected));
        assert_eq!(state, before);
    }
    let mut broken = state;
    broken.temperature = f64::NAN;
    assert_eq!(
        update(&material, &mut broken, &good),
        Err(UpdateError::NonFiniteState)
    );
}

/// Materials covering every path a non-finite value could take through an update: each EoS
/// family (history-free, tabulated compaction and P-alpha, whose history is a maximum and a
/// distension), JC damage with erosion and a pressure cut-off, ZA's coupled strength, and
/// the lagged rate.
fn materials_for_bad_values() -> Vec<Material> {
    use stoss_kernel::damage::{Failure, JohnsonCookFailure};
    use stoss_kernel::eos::{Eos, Jwl, MieGruneisen, PAlpha, Polynomial, TabulatedCompaction};
    use stoss_kernel::RateTreatment;
    let base = Material::STEEL_4340;
    let failing = Material {
        failure: Failure {
            johnson_cook: Some(JohnsonCookFailure::STEEL_4340),
            erode_on_failure: true,
            pressure_cutoff: Some(-1.0e9),
            ..Failure::NONE
        },
        eos: Eos::MieGruneisen(MieGruneisen {
            reference_density: 7830.0,
            sound_speed: 4570.0,
            s1: 1.49,
            s2: 0.0,
            s3: 0.0,
            gamma0: 1.93,
            volume_correction: 0.5,
        }),
        ..base
    };
    let p_alpha = PAlpha {
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
    let materials = vec![
        base,
        failing,
        Material {
            rate_treatment: RateTreatment::Lagged,
            ..base
        },
        base.with_strength(ZerilliArmstrong::ARMCO_IRON),
        Material {
            eos: Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2),
            ..base
        },
        Material {
            eos: Eos::PAlpha(p_alpha),
            ..base
        },
        Material {
            eos: Eos::Jwl(Jwl::C4),
            ..base
        },
    ];
    for material in &materials {
        material.validate().expect("test material");
    }
    materials
}

#[test]
fn every_non_finite_value_is_refused_and_named() {
    // GOAL: the update refuses a NaN or infinite value in any of the step's 8 input values or
    //       the state's 13 stored values with the error naming its side, and leaves the state
    //       untouched, whatever path the value would take through the update (the kernel
    //       tests the ranges up front and finiteness on the result; see `admissible`).
    // SETUP: every material of `materials_for_bad_values`, from a virgin, a plastically
    //        flowing and a failed state (where one exists), NaN, +inf and -inf in each slot
    //        in turn, a compressive shear step.
    // REFERENCE: NonFiniteInput for the strain increment, dt and V1; NonFiniteState for the
    //            state (the order of the checks: input first).
    let step = |volume: f64| StepInput {
        strain_increment: [-2.0e-3, 1.0e-3, 1.0e-3, 5.0e-4, 0.0, 0.0],
        dt: 1.0e-6,
        relative_volume: volume,
    };
    for material in materials_for_bad_values() {
        let initial = MaterialState::initial(298.0);
        let initial = MaterialState {
            eos_history: material.eos.initial_history(),
            ..initial
        };
        let mut flowing = initial;
        let mut states = vec![initial];
        for _ in 0..400 {
            let input = step(flowing.relative_volume * (1.0 - 0.5e-3));
            if update(&material, &mut flowing, &input).is_err() || flowing.damage >= 1.0 {
                break;
            }
            if flowing.plastic_strain > 0.0 && states.len() == 1 {
                states.push(flowing);
            }
        }
        states.push(flowing);
        for state in states {
            let good = step(state.relative_volume * (1.0 - 0.5e-3));
            let mut probe = state;
            update(&material, &mut probe, &good).expect("the good step");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for slot in 0..21 {
                    let mut input = good;
                    let mut broken = state;
                    let expected = if slot < 8 {
                        match slot {
                            0..=5 => input.strain_increment[slot] = bad,
                            6 => input.dt = bad,
                            _ => input.relative_volume = bad,
                        }
                        UpdateError::NonFiniteInput
                    } else {
                        let field = match slot - 8 {
                            k @ 0..=5 => &mut broken.stress[k],
                            6 => &mut broken.plastic_strain,
                            7 => &mut broken.plastic_strain_rate,
                            8 => &mut broken.temperature,
                            9 => &mut broken.damage,
                            10 => &mut broken.relative_volume,
                            11 => &mut broken.internal_energy,
                            _ => &mut broken.eos_history,
                        };
                        *field = bad;
                        UpdateError::NonFiniteState
                    };
                    let before = broken;
                    let result = update(&material, &mut broken, &input);
                    assert_eq!(
                        result,
                        Err(expected),
                        "{:?} / {:?}: {bad} in slot {slot}",
                        material.strength,
                        material.eos
                    );
                    assert_eq!(
                        broken.values().map(f64::to_bits),
                        before.values().map(f64::to_bits)
                    );
                }
            }
        }
    }
}
