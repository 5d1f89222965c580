//! The `strength_update_<model>` targets: a material of one strength family with fuzzed
//! constants, a fuzzed state and a sequence of fuzzed steps through `update`.
//!
//! Domains (where the strong properties of [`crate::check::run_steps`] are asserted):
//! - family constants: each family's search ranges (`PARAMETERS`) (seed 000 section 4.1); constants without a
//!   bound: reference rates log-uniform in `[1e-3, 1e3]` /s (TJC: its bounds), `Tr` in
//!   `[250, 350]` K, `Tm` in `[800, 4000]` K, ZA `C2` in `[0, 3 GPa]`; PTW `G0` in
//!   `[10, 300]` GPa (log), `alpha` in `[0, 0.6]`, `rho` in `[1000, 20000]` kg/m^3, `M` in
//!   `[5, 250]` g/mol; KHL `D0p` in `[1e4, 1e8]` /s (log); Voce-Kocks `e_s0` in `[1e5, 1e9]`
//!   /s (log); MTS `sigma_i` 0 (one draw in two) or in its range, `e_0i` in `[1e9, 1e15]` /s
//!   and `e_0e`, `e_es0` in `[1e5, 1e9]` /s (log), `p` in `[0.1, 1]`, `q` in `[1, 2]`, `a_1`
//!   in `[-20, 50]` MPa, `a_2` in `[0, 5]` MPa, `a_3` in `[0, 5]` MPa/K, `alpha` 0 (one in
//!   four) or in `[0.01, 5]`, `mu_0` in `[10, 300]` GPa (log), `D` in `[0, 0.2] mu_0`, `T_0`
//!   in `[50, 400]` K, `k/b^3` in `[0.3, 2]` MPa/K (PTW's scaled constants drawn in their ranges; draws that break
//!   `y_inf <= y0 <= s0`, `y_inf <= s_inf <= s0` fail `validate()` and only the weak
//!   properties apply);
//! - material: `rho0` in `[1000, 20000]` kg/m^3, `G` in `[1, 300]` GPa (log), `c_p` in
//!   `[100, 2000]` J/kg/K, isothermal, adiabatic or transition heating with `chi` in
//!   `[0, 1]`, linear EoS `K` in `[1, 500]` GPa (log), optional JC failure (`D1` in
//!   `[-0.5, 1]`, `D2` in `[0, 5]`, `D3` in `[-5, 1]`, `D4` in `[-0.05, 0.1]`, `D5` in
//!   `[-1, 2]`), erosion strain, pressure cut-off in `[-10 GPa, 0]`, implicit or lagged rate;
//!   and `validate()` (family and material) must pass;
//! - initial state: stress components in `[-5, 5]` GPa, `eps_p` 0 or in `[1e-8, 5]`, rate 0 or
//!   in `[1e-6, 1e7]` /s, `T` in `[200, 4000]` K, `D` in `[0, 1]`, `V` in `[0.5, 2]`, `E` in
//!   `[-1e10, 1e10]` J/m^3, any flags (one state in eight; the others none);
//! - steps (1 to 12): strain-increment components in `[-0.05, 0.05]`, `dt` in
//!   `[1e-9, 1e-3]` s (log), new `V` in `[0.5, 2]`.

use crate::check::{run_steps, FuzzStep, Tally};
use crate::source::Source;
use stoss_kernel::damage::{Failure, JohnsonCookFailure};
use stoss_kernel::eos::{Eos, LinearEos};
use stoss_kernel::parameters::Parameter;
use stoss_kernel::strength::{
    CrystalStructure, JohnsonCook, KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook,
    PrestonTonksWallace, Strength, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};
use stoss_kernel::{
    Heating, Material, MaterialState, ParameterError, RateTreatment, StateFlags, StepInput,
    YieldCheck,
};

/// The strength family of a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Johnson-Cook.
    JohnsonCook,
    /// Zerilli-Armstrong, BCC or FCC (chosen by the input).
    ZerilliArmstrong,
    /// Modified Johnson-Cook.
    ModifiedJohnsonCook,
    /// Two-part-rate Johnson-Cook.
    TwoRateJohnsonCook,
    /// Preston-Tonks-Wallace.
    PrestonTonksWallace,
    /// Khan-Huang-Liang.
    KhanHuangLiang,
    /// Voce-Kocks.
    VoceKocks,
    /// Mechanical Threshold Stress.
    MechanicalThresholdStress,
}

/// The bound named `name` in `bounds`.
fn bound(bounds: &[Parameter], name: &str) -> (f64, f64) {
    bounds
        .iter()
        .find(|b| b.name == name)
        .and_then(|b| b.search)
        .unwrap_or_else(|| panic!("harness: no search range for {name}"))
}

fn draw(src: &mut Source, bounds: &[Parameter], name: &str) -> f64 {
    let (min, max) = bound(bounds, name);
    src.linear(min, max)
}

fn draw_log(src: &mut Source, bounds: &[Parameter], name: &str) -> f64 {
    let (min, max) = bound(bounds, name);
    src.log(min, max)
}

/// Family constants; returns the strength and the family's own `validate()`.
fn strength(src: &mut Source, family: Family) -> (Strength, Result<(), ParameterError>) {
    match family {
        Family::JohnsonCook => {
            let b = &JohnsonCook::PARAMETERS;
            let model = JohnsonCook {
                yield_stress: draw(src, b, "yield_stress"),
                hardening_modulus: draw(src, b, "hardening_modulus"),
                hardening_exponent: draw(src, b, "hardening_exponent"),
                rate_sensitivity: draw(src, b, "rate_sensitivity"),
                thermal_exponent: draw(src, b, "thermal_exponent"),
                reference_rate: src.log(1e-3, 1e3),
                reference_temperature: src.linear(250.0, 350.0),
                melting_temperature: src.linear(800.0, 4000.0),
            };
            (model.into(), model.validate())
        }
        Family::ZerilliArmstrong => {
            let b = &ZerilliArmstrong::PARAMETERS;
            let structure = if src.flag() {
                CrystalStructure::Fcc
            } else {
                CrystalStructure::Bcc
            };
            let model = ZerilliArmstrong {
                structure,
                athermal_stress: draw(src, b, "athermal_stress"),
                c1: draw(src, b, "c1"),
                c2: src.linear(0.0, 3.0e9),
                c3: draw(src, b, "c3"),
                c4: draw(src, b, "c4"),
                c5: draw(src, b, "c5"),
                exponent: draw(src, b, "exponent"),
                reference_rate: src.log(1e-3, 1e3),
            };
            (model.into(), model.validate())
        }
        Family::ModifiedJohnsonCook => {
            let b = &ModifiedJohnsonCook::PARAMETERS;
            let model = ModifiedJohnsonCook {
                yield_stress: draw(src, b, "yield_stress"),
                hardening_modulus: draw(src, b, "hardening_modulus"),
                hardening_exponent: draw(src, b, "hardening_exponent"),
                saturation_stress_1: draw(src, b, "saturation_stress_1"),
                saturation_rate_1: draw(src, b, "saturation_rate_1"),
                saturation_stress_2: draw(src, b, "saturation_stress_2"),
                saturation_rate_2: draw(src, b, "saturation_rate_2"),
                rate_exponent: draw(src, b, "rate_exponent"),
                reference_rate: src.log(1e-3, 1e3),
                thermal_exponent: draw(src, b, "thermal_exponent"),
                reference_temperature: src.linear(250.0, 350.0),
                melting_temperature: src.linear(800.0, 4000.0),
            };
            (model.into(), model.validate())
        }
        Family::TwoRateJohnsonCook => {
            let b = &TwoRateJohnsonCook::PARAMETERS;
            let model = TwoRateJohnsonCook {
                yield_stress: draw(src, b, "yield_stress"),
                hardening_modulus: draw(src, b, "hardening_modulus"),
                hardening_exponent: draw(src, b, "hardening_exponent"),
                saturation_stress_1: draw(src, b, "saturation_stress_1"),
                saturation_rate_1: draw(src, b, "saturation_rate_1"),
                saturation_stress_2: draw(src, b, "saturation_stress_2"),
                saturation_rate_2: draw(src, b, "saturation_rate_2"),
                rate_exponent_1: draw(src, b, "rate_exponent_1"),
                reference_rate_1: draw_log(src, b, "reference_rate_1"),
                rate_exponent_2: draw(src, b, "rate_exponent_2"),
                reference_rate_2: draw_log(src, b, "reference_rate_2"),
                thermal_exponent: draw(src, b, "thermal_exponent"),
                reference_temperature: src.linear(250.0, 350.0),
                melting_temperature: src.linear(800.0, 4000.0),
            };
            (model.into(), model.validate())
        }
        Family::PrestonTonksWallace => {
            let b = &PrestonTonksWallace::PARAMETERS;
            let model = PrestonTonksWallace {
                theta: draw(src, b, "theta"),
                p: draw(src, b, "p"),
                s0: draw(src, b, "s0"),
                s_inf: draw(src, b, "s_inf"),
                kappa: draw(src, b, "kappa"),
                gamma: draw_log(src, b, "gamma"),
                y0: draw(src, b, "y0"),
                y_inf: draw(src, b, "y_inf"),
                y1: draw(src, b, "y1"),
                y2: draw(src, b, "y2"),
                beta: draw(src, b, "beta"),
                shear_modulus_0: src.log(1e10, 3e11),
                alpha: src.linear(0.0, 0.6),
                melting_temperature: src.linear(800.0, 4000.0),
                density: src.linear(1000.0, 20000.0),
                atomic_mass: src.linear(5.0, 250.0),
            };
            (model.into(), model.validate())
        }
        Family::KhanHuangLiang => {
            let b = &KhanHuangLiang::PARAMETERS;
            let model = KhanHuangLiang {
                yield_stress: draw(src, b, "yield_stress"),
                hardening_modulus: draw(src, b, "hardening_modulus"),
                hardening_exponent: draw(src, b, "hardening_exponent"),
                coupling_exponent: draw(src, b, "coupling_exponent"),
                rate_sensitivity: draw(src, b, "rate_sensitivity"),
                reference_rate: src.log(1e-3, 1e3),
                upper_rate: src.log(1e4, 1e8),
                thermal_exponent: draw(src, b, "thermal_exponent"),
                reference_temperature: src.linear(250.0, 350.0),
                melting_temperature: src.linear(800.0, 4000.0),
            };
            (model.into(), model.validate())
        }
        Family::VoceKocks => {
            let b = &VoceKocks::PARAMETERS;
            let model = VoceKocks {
                yield_stress: draw(src, b, "yield_stress"),
                initial_hardening: draw(src, b, "initial_hardening"),
                saturation_stress: draw(src, b, "saturation_stress"),
                saturation_reference_rate: src.log(1e5, 1e9),
                activation_temperature: draw(src, b, "activation_temperature"),
            };
            (model.into(), model.validate())
        }
        Family::MechanicalThresholdStress => {
            let b = &MechanicalThresholdStress::PARAMETERS;
            let intrinsic = src.choice(2) == 1;
            let shear_modulus_0 = src.log(1e10, 3e11);
            let model = MechanicalThresholdStress {
                athermal_stress: draw(src, b, "athermal_stress"),
                intrinsic_stress: if intrinsic {
                    draw(src, b, "intrinsic_stress")
                } else {
                    0.0
                },
                intrinsic_activation_energy: draw(src, b, "intrinsic_activation_energy"),
                intrinsic_reference_rate: src.log(1e9, 1e15),
                intrinsic_p: src.linear(0.1, 1.0),
                intrinsic_q: src.linear(1.0, 2.0),
                structure_activation_energy: draw(src, b, "structure_activation_energy"),
                structure_reference_rate: src.log(1e5, 1e9),
                structure_p: src.linear(0.1, 1.0),
                structure_q: src.linear(1.0, 2.0),
                saturation_stress: draw(src, b, "saturation_stress"),
                saturation_activation_energy: draw(src, b, "saturation_activation_energy"),
                saturation_reference_rate: src.log(1e5, 1e9),
                hardening_a0: draw(src, b, "hardening_a0"),
                hardening_a1: src.linear(-20e6, 50e6),
                hardening_a2: src.linear(0.0, 5e6),
                hardening_a3: src.linear(0.0, 5e6),
                hardening_shape: if src.choice(4) == 0 {
                    0.0
                } else {
                    src.linear(0.01, 5.0)
                },
                shear_modulus_0,
                shear_modulus_drop: src.linear(0.0, 0.2) * shear_modulus_0,
                varshni_temperature: src.linear(50.0, 400.0),
                boltzmann_per_burgers_cubed: src.linear(0.3e6, 2e6),
            };
            (model.into(), model.validate())
        }
    }
}

/// Everything but the strength: density, elasticity, heating, linear EoS, failure, rate
/// treatment.
pub fn material_with(src: &mut Source, strength: Strength) -> Material {
    let density = src.linear(1000.0, 20000.0);
    let shear_modulus = src.log(1e9, 3e11);
    let specific_heat = src.linear(100.0, 2000.0);
    let heating = match src.choice(3) {
        0 => Heating::Isothermal,
        1 => Heating::Adiabatic {
            taylor_quinney: src.linear(0.0, 1.0),
        },
        _ => {
            let isothermal_rate = src.log(1e-4, 1e2);
            Heating::Transition {
                taylor_quinney: src.linear(0.0, 1.0),
                isothermal_rate,
                adiabatic_rate: isothermal_rate * src.log(1.001, 1e5),
            }
        }
    };
    let eos = Eos::Linear(LinearEos {
        bulk_modulus: src.log(1e9, 5e11),
    });
    let johnson_cook = if src.flag() {
        Some(JohnsonCookFailure {
            d1: src.linear(-0.5, 1.0),
            d2: src.linear(0.0, 5.0),
            d3: src.linear(-5.0, 1.0),
            d4: src.linear(-0.05, 0.1),
            d5: src.linear(-1.0, 2.0),
            reference_rate: src.log(1e-3, 1e3),
            reference_temperature: src.linear(250.0, 350.0),
            melting_temperature: src.linear(800.0, 4000.0),
        })
    } else {
        None
    };
    let erosion_plastic_strain = if src.flag() {
        Some(src.linear(0.01, 5.0))
    } else {
        None
    };
    let erode_on_failure = src.flag();
    let pressure_cutoff = if src.flag() {
        Some(src.linear(-1e10, 0.0))
    } else {
        None
    };
    let rate_treatment = if src.flag() {
        RateTreatment::Lagged
    } else {
        RateTreatment::Implicit
    };
    Material {
        density,
        shear_modulus,
        specific_heat,
        strength,
        heating,
        eos,
        failure: Failure {
            johnson_cook,
            erosion_plastic_strain,
            erode_on_failure,
            erosion_geometric_strain: None,
            failure_principal_strain: None,
            pressure_cutoff,
        },
        rate_treatment,
    }
}

/// A fuzzed incoming state (see the module docs for its domain).
pub fn state(src: &mut Source) -> MaterialState {
    let mut stress = [0.0; 6];
    for s in stress.iter_mut() {
        *s = src.linear(-5e9, 5e9);
    }
    MaterialState {
        stress,
        plastic_strain: src.zero_or_log(1e-8, 5.0),
        plastic_strain_rate: src.zero_or_log(1e-6, 1e7),
        temperature: src.linear(200.0, 4000.0),
        damage: src.linear(0.0, 1.0),
        relative_volume: src.linear(0.5, 2.0),
        internal_energy: src.linear(-1e10, 1e10),
        eos_history: 0.0,
        // Mostly a clean point; one state in eight carries arbitrary flags (FAILED included).
        flags: StateFlags(if src.byte() & 7 == 0 {
            u32::from(src.byte() & 0x0f)
        } else {
            0
        }),
        yield_check: YieldCheck::NONE,
    }
}

/// 1 to 12 fuzzed steps.
pub fn steps(src: &mut Source) -> Vec<FuzzStep> {
    let count = src.count(1, 12);
    (0..count)
        .map(|_| {
            src.take_domain();
            let mut strain_increment = [0.0; 6];
            for d in strain_increment.iter_mut() {
                *d = src.linear(-0.05, 0.05);
            }
            let dt = src.log(1e-9, 1e-3);
            let relative_volume = src.linear(0.5, 2.0);
            let tangent = src.flag();
            FuzzStep {
                input: StepInput {
                    strain_increment,
                    dt,
                    relative_volume,
                },
                tangent,
                in_domain: src.take_domain(),
            }
        })
        .collect()
}

/// A decoded strength case: the material, whether its constants validated and lie in their
/// domain, the initial state and whether it lies in its domain, and the steps.
pub struct Case {
    /// The material.
    pub material: Material,
    /// Family and material `validate()` passed and every constant lies in its domain.
    pub checked: bool,
    /// The incoming state.
    pub initial: MaterialState,
    /// The incoming state was drawn inside its domain.
    pub initial_in_domain: bool,
    /// The steps.
    pub steps: Vec<FuzzStep>,
}

/// Decode the bytes of a `strength_update_<model>` input.
pub fn decode(family: Family, data: &[u8]) -> Case {
    let mut src = Source::new(data);
    let (strength, family_check) = strength(&mut src, family);
    let material = material_with(&mut src, strength);
    let material_in_domain = src.take_domain();
    let initial = state(&mut src);
    let initial_in_domain = src.take_domain();
    let steps = steps(&mut src);
    // Material::validate() alone misses family-level checks (TJC: e02 >= e01), so both.
    let valid = family_check.is_ok() && material.validate().is_ok();
    Case {
        material,
        checked: valid && material_in_domain,
        initial,
        initial_in_domain,
        steps,
    }
}

/// One fuzz case of `family`.
pub fn run(family: Family, data: &[u8]) -> Tally {
    let case = decode(family, data);
    run_steps(
        &case.material,
        case.checked,
        case.initial,
        case.initial_in_domain,
        &case.steps,
    )
}
