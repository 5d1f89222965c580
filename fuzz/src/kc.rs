//! The `kc_update` target: a K&C concrete material with fuzzed constants around seed 001's
//! 100 MPa HPC, a fuzzed state and a sequence of fuzzed steps through
//! `stoss_kernel::kc::update` (or `update_with_tangent`).
//!
//! Domains (bracketing published concrete sets around Malvar's and seed 001 chapter 5's):
//! - `fc` in `[20, 200]` MPa, `ft/fc` in `[0.03, 0.15]`, `G` in `[5, 50]` GPa (log); the
//!   meridians of `KcParameters::from_strength` each scaled by a factor in `[0.8, 1.25]`;
//!   biaxial ratio in `[1, 1.3]`, `b1`, `b2` in `[0, 3]`; the damage function either seed
//!   table 5.3 or 3 to 12 points with `lambda` steps in `[1e-6, 1e-2]` (log), `eta` rising to
//!   1 at a fuzzed peak and falling after it; rates off or CEB-FIP; a crack band (width over
//!   reference in `[0.1, 10]`) or none;
//! - `rho0` in `[1500, 3000]` kg/m^3; EoS: table 5.2 or linear (`K` in `[10, 50]` GPa);
//! - state: the initial state, or (one input in two) stress components in `[-200, 200]` MPa,
//!   `lambda` in `[0, 0.05]` with its damage measure, `V` in `[0.8, 1.2]`, `E` in
//!   `[-1e8, 1e8]` J/m^3;
//! - steps (1 to 12): components in `[-0.05, 0.05]`, `dt` in `[1e-9, 1e-3]` s (log), the new
//!   `V` from `V exp(tr deps)` (three steps in four) or in `[0.5, 2]`.
//!
//! Properties: those of every target (no panic, state bitwise unchanged on `Err`, bitwise
//! determinism, finite `Ok` state and wave speed); in domain on `Ok`: finite outputs and
//! tangent, `dl >= 0`, `lambda` and the damage measure not decreasing and in range, `V` from
//! the input, and the stored stress on or inside the strength the update reports.

use crate::check::{
    common_violation, concrete_steps, run_point_steps, FuzzStep, PointTarget, Tally,
};
use crate::source::Source;
use stoss_kernel::eos::{Eos, LinearEos, TabulatedCompaction};
use stoss_kernel::kc::{
    damage_measure, update, update_with_tangent, CrackBand, DamageFunction, KcMaterial,
    KcParameters, RateEnhancement,
};
use stoss_kernel::tensor;
use stoss_kernel::{MaterialState, StepOutput, UpdateError};

fn damage_function(src: &mut Source) -> DamageFunction {
    if src.flag() {
        return DamageFunction::FOI_TABLE_5_3;
    }
    let count = usize::from(src.count(3, 12));
    let peak = 1 + usize::from(src.byte()) % (count - 1);
    let mut points = [(0.0, 0.0); 12];
    let mut lambda = 0.0;
    let mut eta = 0.0_f64;
    for (i, point) in points.iter_mut().enumerate().take(count).skip(1) {
        lambda += src.log(1e-6, 1e-2);
        eta = if i < peak {
            eta.max(src.linear(0.0, 1.0))
        } else if i == peak {
            1.0
        } else {
            src.linear(0.0, eta)
        };
        *point = (lambda, eta);
    }
    DamageFunction::from_points(&points[..count])
}

fn material(src: &mut Source) -> KcMaterial {
    let fc = src.linear(20e6, 200e6);
    let ft = fc * src.linear(0.03, 0.15);
    let mut parameters = KcParameters::from_strength(fc, ft, src.log(5e9, 5e10));
    for value in parameters
        .maximum_surface
        .iter_mut()
        .chain(parameters.yield_surface.iter_mut())
        .chain(parameters.residual_surface.iter_mut())
    {
        *value *= src.log(0.8, 1.25);
    }
    parameters.biaxial_ratio = src.linear(1.0, 1.3);
    parameters.compression_damage_exponent = src.linear(0.0, 3.0);
    parameters.tension_damage_exponent = src.linear(0.0, 3.0);
    parameters.damage = damage_function(src);
    parameters.rate = if src.flag() {
        RateEnhancement::CebFip
    } else {
        RateEnhancement::None
    };
    parameters.crack_band = if src.flag() {
        Some(CrackBand {
            reference_width: 0.01,
            width: 0.01 * src.log(0.1, 10.0),
        })
    } else {
        None
    };
    let density = src.linear(1500.0, 3000.0);
    let eos = if src.flag() {
        Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2)
    } else {
        Eos::Linear(LinearEos {
            bulk_modulus: src.log(1e10, 5e10),
        })
    };
    KcMaterial {
        density,
        parameters,
        eos,
        erosion_geometric_strain: None,
    }
}

fn state(src: &mut Source, material: &KcMaterial) -> MaterialState {
    let mut state = material.initial_state(293.0);
    if src.flag() {
        for s in state.stress.iter_mut() {
            *s = src.linear(-2e8, 2e8);
        }
        let table = material.parameters.damage;
        state.plastic_strain = src.linear(0.0, 0.05);
        state.damage = damage_measure(
            state.plastic_strain,
            table.peak_lambda(),
            table.eta_at(state.plastic_strain),
        );
        state.relative_volume = src.linear(0.8, 1.2);
        state.internal_energy = src.linear(-1e8, 1e8);
    }
    state
}

fn run_once(
    material: &KcMaterial,
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

/// One fuzz case of the `kc_update` target.
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
            name: "K&C update",
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
    material: &KcMaterial,
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
    let largest = after.stress.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    let round_off = 1e-6 + 1e-14 * largest;
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
