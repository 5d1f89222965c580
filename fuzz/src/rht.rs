//! The `rht_update` target: an RHT concrete material with fuzzed constants around seed 001's
//! 92 MPa HPC, a fuzzed state and a sequence of fuzzed steps through
//! `stoss_kernel::rht::update` (or `update_with_tangent`).
//!
//! Domains (the kernel gives no optimisation bounds for RHT; these bracket published concrete
//! sets, Riedel 2000 and seed 001 table 4.4):
//! - `G` in `[5, 50]` GPa (log), `fc` in `[20, 200]` MPa, `FT*` in `[0.03, 0.15]`, `FS*` in
//!   `[0.1, 0.5]`, `A` in `[1, 3]`, `N` in `[0.4, 0.9]`, `Q2,0` in `[0.5, 1]`, `BQ` in
//!   `[0, 0.05]`, `PREFACT` in `[1, 3]`, `TENSRAT`, `COMPRAT` in `[0.5, 1]`, `B` in `[0, 3]`,
//!   `M` in `[0.3, 1]`, `alpha`, `delta` in `[0, 0.05]`, reference rates in `[1e-6, 1e-4]`
//!   /s (log), `D1` in `[0.01, 0.1]`, `D2` in `[0.5, 2]`, `EFMIN` in `[0.001, 0.1]`,
//!   `SHRATD` in `[0.05, 1]`, every enum option, cap on or off;
//! - `rho0` in `[1500, 3000]` kg/m^3; EoS: P-alpha (A1, T1 in `[10, 50]` GPa, A2 in
//!   `[0, 60]` GPa, A3 in `[0, 20]` GPa, B0, B1 in `[0, 2]`, `alpha0` in `[1, 1.3]`, crush
//!   in `[10, 300]` MPa, lock in `[1, 10]` GPa, `n` in `[1, 5]`) or linear (`K` in
//!   `[10, 50]` GPa); optional erosion strain in `[0.5, 3]`; `validate()` must pass;
//! - state: the initial state, or (one input in two) stress components in `[-200, 200]` MPa,
//!   `eps_p` in `[0, 0.1]`, `D` in `[0, 1]`, `V` in `[0.8, 1.2]`, `E` in `[-1e8, 1e8]` J/m^3,
//!   distension in `[1, alpha0]`;
//! - steps (1 to 12): components in `[-0.05, 0.05]`, `dt` in `[1e-9, 1e-3]` s (log), the new
//!   `V` from `V exp(tr deps)` (three steps in four) or in `[0.5, 2]`.
//!
//! Properties: those of every target (no panic, state bitwise unchanged on `Err`, bitwise
//! determinism, finite `Ok` state and wave speed); in domain on `Ok`: finite outputs and
//! tangent, `dl >= 0`, `eps_p` and `D` not decreasing, `D` in `[0, 1]`, `V` from the input,
//! P-alpha distension in `[1, alpha0]` and not increasing, a point failed before the step
//! carries no tension, and the stored stress on or inside the strength the update reports
//! (`q <= yield_stress (1 + 1e-9) + 1e-6 Pa + 1e-14 (max|sigma| + q_trial bound)`: "a stored
//! stress lies exactly on the surface it was returned to", kernel/src/rht/update.rs).

use crate::check::{
    common_violation, concrete_steps, run_point_steps, FuzzStep, PointTarget, Tally,
};
use crate::source::Source;
use stoss_kernel::eos::{Eos, LinearEos, PAlpha, Polynomial};
use stoss_kernel::rht::{
    update, update_with_tangent, FailureMeridian, RateScaling, RhtMaterial, RhtParameters,
    TensileFailure,
};
use stoss_kernel::tensor;
use stoss_kernel::{MaterialState, StepOutput, UpdateError};

fn parameters(src: &mut Source) -> RhtParameters {
    RhtParameters {
        shear_modulus: src.log(5e9, 5e10),
        compressive_strength: src.linear(20e6, 200e6),
        tensile_strength_ratio: src.linear(0.03, 0.15),
        shear_strength_ratio: src.linear(0.1, 0.5),
        failure_a: src.linear(1.0, 3.0),
        failure_n: src.linear(0.4, 0.9),
        tensile_meridian_ratio: src.linear(0.5, 1.0),
        brittle_ductile_transition: src.linear(0.0, 0.05),
        shear_modulus_ratio: src.linear(1.0, 3.0),
        tensile_elastic_ratio: src.linear(0.5, 1.0),
        compressive_elastic_ratio: src.linear(0.5, 1.0),
        elastic_cap: src.flag(),
        residual_b: src.linear(0.0, 3.0),
        residual_m: src.linear(0.3, 1.0),
        compressive_rate_exponent: src.linear(0.0, 0.05),
        tensile_rate_exponent: src.linear(0.0, 0.05),
        compressive_reference_rate: src.log(1e-6, 1e-4),
        tensile_reference_rate: src.log(1e-6, 1e-4),
        damage_d1: src.linear(0.01, 0.1),
        damage_d2: src.linear(0.5, 2.0),
        minimum_failure_strain: src.linear(0.001, 0.1),
        residual_shear_modulus_ratio: src.linear(0.05, 1.0),
        // One byte, as `flag()` took before the third option: odd bytes keep the principal
        // stress, even ones split between the hydro limit and the pressure cut-off.
        tensile_failure: match src.byte() & 3 {
            1 | 3 => TensileFailure::PrincipalStress,
            0 => TensileFailure::HydroTensileLimit,
            _ => TensileFailure::PressureCutoff,
        },
        meridian: if src.flag() {
            FailureMeridian::PowerLaw
        } else {
            FailureMeridian::CharacteristicPoints
        },
        rate_scaling: if src.flag() {
            RateScaling::Homothetic
        } else {
            RateScaling::SeedEquation
        },
    }
}

fn material(src: &mut Source) -> RhtMaterial {
    let parameters = parameters(src);
    let density = src.linear(1500.0, 3000.0);
    let eos = if src.byte() & 7 == 0 {
        Eos::Linear(LinearEos {
            bulk_modulus: src.log(1e10, 5e10),
        })
    } else {
        let a1 = src.log(1e10, 5e10);
        Eos::PAlpha(PAlpha {
            solid: Polynomial {
                a1,
                a2: src.linear(0.0, 6e10),
                a3: src.linear(0.0, 2e10),
                b0: src.linear(0.0, 2.0),
                b1: src.linear(0.0, 2.0),
                t1: if src.flag() { a1 } else { src.log(1e10, 5e10) },
                t2: 0.0,
            },
            initial_distension: src.linear(1.0, 1.3),
            crush_pressure: src.linear(10e6, 300e6),
            lock_pressure: src.log(1e9, 1e10),
            exponent: src.linear(1.0, 5.0),
        })
    };
    let erosion_plastic_strain = if src.flag() {
        Some(src.linear(0.5, 3.0))
    } else {
        None
    };
    RhtMaterial {
        density,
        parameters,
        eos,
        erosion_plastic_strain,
        erosion_geometric_strain: None,
    }
}

fn state(src: &mut Source, material: &RhtMaterial) -> MaterialState {
    let mut state = material.initial_state(293.0);
    if src.flag() {
        for s in state.stress.iter_mut() {
            *s = src.linear(-2e8, 2e8);
        }
        state.plastic_strain = src.linear(0.0, 0.1);
        state.damage = src.linear(0.0, 1.0);
        state.relative_volume = src.linear(0.8, 1.2);
        state.internal_energy = src.linear(-1e8, 1e8);
        if let Eos::PAlpha(p) = material.eos {
            state.eos_history = src.linear(1.0, p.initial_distension.max(1.0));
        }
    }
    state
}

fn run_once(
    material: &RhtMaterial,
    state: &mut MaterialState,
    step: &FuzzStep,
    tangent: &mut [[f64; 6]; 6],
) -> Result<StepOutput, UpdateError> {
    if step.tangent {
        update_with_tangent(material, state, &step.input, tangent)
    } else {
        update(material, state, &step.input)
    }
}

/// One fuzz case of the `rht_update` target.
pub fn run(data: &[u8]) -> Tally {
    let mut src = Source::new(data);
    let material = material(&mut src);
    let material_in_domain = src.take_domain();
    let initial = state(&mut src, &material);
    let initial_in_domain = src.take_domain();
    let steps = concrete_steps(&mut src, initial.relative_volume);
    let checked = material_in_domain && material.validate().is_ok();
    run_point_steps(
        &PointTarget {
            name: "RHT update",
            material: &material,
            run_once: &|state, step, tangent| run_once(&material, state, step, tangent),
            iteration_bound_is_a_defect: false,
            check_step: &|before, after, step, output, tangent, context| {
                check_step(&material, before, after, step, output, tangent, context)
            },
        },
        checked,
        initial,
        initial_in_domain,
        &steps,
    )
}

fn check_step(
    material: &RhtMaterial,
    before: &MaterialState,
    after: &MaterialState,
    step: &FuzzStep,
    output: &StepOutput,
    tangent: &[[f64; 6]; 6],
    context: &dyn Fn() -> String,
) {
    let fail = |what: String| -> ! {
        panic!(
            "{what}\noutput: {output:?}\nstate after: {after:?}\n{}",
            context()
        )
    };
    if let Some(what) = common_violation(before, after, step, output, tangent) {
        fail(what);
    }
    if let Eos::PAlpha(p) = material.eos {
        let incoming = if before.eos_history >= 1.0 && before.eos_history <= p.initial_distension {
            before.eos_history
        } else {
            p.initial_distension
        };
        if !(after.eos_history >= 1.0 && after.eos_history <= incoming) {
            fail(format!(
                "distension {} outside [1, {incoming}]",
                after.eos_history
            ));
        }
    }
    let largest = after.stress.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    let round_off = 1e-6 + 1e-14 * largest;
    if before.damage >= 1.0 && after.pressure() < -round_off {
        fail(format!(
            "a failed point carries tension: p = {}",
            after.pressure()
        ));
    }
    // The return's own round-off scales with the trial stress (`q_trial - 3G dl` cancels):
    // bound q_trial by the triangle inequality with the undamaged G (G(D) <= G).
    let trial_bound = tensor::von_mises(&tensor::deviator(&before.stress))
        + 2.0
            * material.parameters.shear_modulus
            * tensor::von_mises(&tensor::deviator(&step.input.strain_increment));
    let q = after.equivalent_stress();
    let limit = output.yield_stress * (1.0 + 1e-9) + round_off + 1e-14 * trial_bound;
    if !(q <= limit) {
        fail(format!(
            "stored stress outside the reported strength: q {q:e} > {:e}",
            output.yield_stress
        ));
    }
}
