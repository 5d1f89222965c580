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
