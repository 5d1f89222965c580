//! Properties shared by the targets: bitwise state comparison, the state domain, and the
//! checks made on every update.

use stoss_kernel::j2::update::{MAX_RETURN_ITERATIONS, RETURN_TOLERANCE};
use stoss_kernel::tensor;
use stoss_kernel::{
    update, update_with_tangent, Heating, Material, MaterialState, RateTreatment, StateFlags,
    StepInput, StepOutput, UpdateError,
};

/// Largest stress component of a state in the checked domain (Pa).
pub const STRESS_LIMIT: f64 = 1e12;

/// Highest temperature of a checked state (K). Adiabatic heating with a low `c_p` and a flow
/// stress of tens of GPa can carry a point to 1e5 K within a few fuzzed steps; Zerilli-Armstrong,
/// whose rate exponent is `C4 T`, is meaningless (and overflows) there. Above about 6000 K
/// every metal is vapour.
pub const MAX_TEMPERATURE: f64 = 6000.0;

/// Relative tolerance of the yield condition `q <= sigma_y (1 + tol) + abs`.
pub const YIELD_RELATIVE: f64 = 1e-9;

/// Absolute part of the yield tolerance (Pa), besides the round-off of recovering the
/// deviator from a stress that carries a large pressure (`1e-14 max |sigma_i|`).
pub const YIELD_ABSOLUTE: f64 = 1e-6;

/// Every stored number of a state as bits (NaN-safe, distinguishes -0.0).
pub fn state_bits(state: &MaterialState) -> [u64; 14] {
    let s = &state.stress;
    [
        s[0].to_bits(),
        s[1].to_bits(),
        s[2].to_bits(),
        s[3].to_bits(),
        s[4].to_bits(),
        s[5].to_bits(),
        state.plastic_strain.to_bits(),
        state.plastic_strain_rate.to_bits(),
        state.temperature.to_bits(),
        state.damage.to_bits(),
        state.relative_volume.to_bits(),
        state.internal_energy.to_bits(),
        state.eos_history.to_bits(),
        u64::from(state.flags.0),
    ]
}

/// The output's numbers as bits.
pub fn output_bits(output: &StepOutput) -> [u64; 4] {
    [
        output.wave_speed.to_bits(),
        output.plastic_increment.to_bits(),
        output.yield_stress.to_bits(),
        u64::from(output.iterations),
    ]
}

/// A state inside the domain where the strong properties are asserted: finite, stress
/// components within [`STRESS_LIMIT`], plastic strain in `[0, 1e3]`, rate in `[0, 1e9]`,
/// temperature in `(0, MAX_TEMPERATURE]`, damage in `[0, 1]`, `V/V0` in `[0.5, 2]`, `|E| <= 1e14`.
pub fn state_in_domain(state: &MaterialState) -> bool {
    state.is_finite()
        && state.stress.iter().all(|s| s.abs() <= STRESS_LIMIT)
        && (0.0..=1e3).contains(&state.plastic_strain)
        && (0.0..=1e9).contains(&state.plastic_strain_rate)
        && state.temperature > 0.0
        && state.temperature <= MAX_TEMPERATURE
        && (0.0..=1.0).contains(&state.damage)
        && (0.5..=2.0).contains(&state.relative_volume)
        && state.internal_energy.abs() <= 1e14
}

/// One fuzzed step: its input, whether it asks for the tangent, and whether the input lies
/// in the documented domain (`|deps_i| <= 0.05`, `dt in [1e-9, 1e-3]`, `V in [0.5, 2]`).
#[derive(Clone, Copy, Debug)]
pub struct FuzzStep {
    /// The step.
    pub input: StepInput,
    /// Call `update_with_tangent` instead of `update`.
    pub tangent: bool,
    /// Input drawn inside its domain.
    pub in_domain: bool,
}

/// What a sequence of steps did (for the replay statistics).
#[derive(Clone, Copy, Debug, Default)]
pub struct Tally {
    /// Steps run.
    pub steps: u64,
    /// Steps whose material, state and input were all in domain.
    pub checked: u64,
    /// Of those, steps that were plastic.
    pub plastic: u64,
    /// Of those, steps that returned an error, by kind: non-finite result, diverged, other.
    pub errors: [u64; 3],
}

impl Tally {
    /// Add another tally.
    pub fn add(&mut self, other: &Tally) {
        self.steps += other.steps;
        self.checked += other.checked;
        self.plastic += other.plastic;
        for (a, b) in self.errors.iter_mut().zip(other.errors.iter()) {
            *a += b;
        }
    }
}

fn run_once(
    material: &Material,
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

/// Run `steps` from `state` through `update`, asserting after every step:
///
/// - always: no panic; on `Err` the state is bitwise unchanged; the same call on a copy gives
///   the same bits (determinism); an `Ok` state and wave speed are finite (the kernel's
///   promise for any material);
/// - when `checked` (validated material in domain) and the incoming state and the step are in
///   domain, on `Ok`: finite outputs and tangent; `dl >= 0`; `eps_p` not decreasing;
///   temperature not decreasing (and unchanged bit for bit without heating); damage in
///   `[0, 1]` and not decreasing; `V` taken from the input; iterations within the bound; and
///   the yield condition `q_{n+1} <= sigma_y (1 + 1e-9) + 1e-6 Pa + 1e-14 max|sigma| +
///   2 RETURN_TOLERANCE q_trial` (the last two: round-off of the deviator under a large
///   pressure, and the return mapping's own stopping tolerance) with
///   `sigma_y = sigma_y(eps_{n+1}, dl/dt, T_n)` (implicit) or `sigma_y(eps_n, rate_n, T_n)`
///   (lagged) after a plastic step, `sigma_y(eps_n, 0 or rate_n, T_n)` after an elastic one.
///
/// The sequence continues from the returned state after `Ok` and from the unchanged state
/// after `Err`.
pub fn run_steps(
    material: &Material,
    checked: bool,
    initial: MaterialState,
    initial_in_domain: bool,
    steps: &[FuzzStep],
) -> Tally {
    run_point_steps(
        &PointTarget {
            name: "update",
            material,
            run_once: &|state, step, tangent| run_once(material, state, step, tangent),
            // update.rs documents that its iteration bound is never the reason for a result
            // (MAX_RETURN_ITERATIONS).
            iteration_bound_is_a_defect: true,
            check_step: &|before, after, step, output, tangent, context| {
                check_step(material, before, after, step, output, tangent, context)
            },
        },
        checked,
        initial,
        initial_in_domain,
        steps,
    )
}

/// One fuzzed step: `(state before, state after, step, output, tangent, context)`.
pub type StepCheck<'a> = dyn Fn(&MaterialState, &MaterialState, &FuzzStep, &StepOutput, &[[f64; 6]; 6], &dyn Fn() -> String)
    + 'a;

/// What [`run_point_steps`] needs of a target: its name for messages, the material (for
/// messages), one update with or without the tangent, whether the return mapping's
/// iteration bound is a defect inside the domain, and the model's own properties of an
/// in-domain `Ok` step.
pub struct PointTarget<'a> {
    /// Name of the update in messages (`"update"`, `"RHT update"`...).
    pub name: &'static str,
    /// The material, printed with a failing step.
    pub material: &'a dyn core::fmt::Debug,
    /// One update (with the tangent when the step asks for it).
    #[allow(clippy::type_complexity)]
    pub run_once: &'a dyn Fn(
        &mut MaterialState,
        &FuzzStep,
        &mut [[f64; 6]; 6],
    ) -> Result<StepOutput, UpdateError>,
    /// `ReturnMappingDiverged` inside the domain is a defect (the J2 return says its bound is
    /// never the reason for a result).
    pub iteration_bound_is_a_defect: bool,
    /// The model's properties of an in-domain `Ok` step.
    pub check_step: &'a StepCheck<'a>,
}

/// The step loop every point-model target shares: no panic; on `Err` the state is bitwise
/// unchanged; the same call on a copy gives the same bits (determinism, the tangent
/// included); an `Ok` state and wave speed are finite; inside the domain the target's own
/// properties ([`PointTarget::check_step`]). The sequence continues from the returned state
/// after `Ok` and from the unchanged one after `Err`.
pub fn run_point_steps(
    target: &PointTarget<'_>,
    checked: bool,
    initial: MaterialState,
    initial_in_domain: bool,
    steps: &[FuzzStep],
) -> Tally {
    let name = target.name;
    let mut tally = Tally::default();
    let mut state = initial;
    for (index, step) in steps.iter().enumerate() {
        tally.steps += 1;
        let before = state;
        let domain = checked
            && step.in_domain
            && state_in_domain(&before)
            && (index > 0 || initial_in_domain);
        let context = || {
            format!(
                "step {index}\nmaterial: {:?}\nstate before: {before:?}\n\
                 state bits: {:016x?}\ninput: {:?}\ntangent requested: {}",
                target.material,
                state_bits(&before),
                step.input,
                step.tangent
            )
        };

        let mut tangent = [[f64::NAN; 6]; 6];
        let result = (target.run_once)(&mut state, step, &mut tangent);
        let mut again = before;
        let mut tangent_again = [[f64::NAN; 6]; 6];
        let result_again = (target.run_once)(&mut again, step, &mut tangent_again);
        let same = match (&result, &result_again) {
            (Ok(a), Ok(b)) => output_bits(a) == output_bits(b),
            (Err(a), Err(b)) => a == b,
            _ => false,
        };
        assert!(
            same && state_bits(&state) == state_bits(&again)
                && (!step.tangent
                    || tangent
                        .iter()
                        .flatten()
                        .zip(tangent_again.iter().flatten())
                        .all(|(a, b)| a.to_bits() == b.to_bits())),
            "{name} is not deterministic: {result:?} vs {result_again:?}\n{}",
            context()
        );

        let output = match result {
            Err(error) => {
                assert_eq!(
                    state_bits(&state),
                    state_bits(&before),
                    "state changed although {name} returned {error:?}\nafter: {state:?}\n{}",
                    context()
                );
                if domain {
                    assert!(
                        !(target.iteration_bound_is_a_defect
                            && error == UpdateError::ReturnMappingDiverged),
                        "return mapping hit its iteration bound inside the domain\n{}",
                        context()
                    );
                    tally.checked += 1;
                    tally.errors[match error {
                        UpdateError::NonFiniteResult => 0,
                        UpdateError::ReturnMappingDiverged => 1,
                        _ => 2,
                    }] += 1;
                }
                continue;
            }
            Ok(output) => output,
        };
        assert!(
            state.is_finite() && output.wave_speed.is_finite(),
            "Ok with a non-finite state or wave speed {state:?} {output:?}\n{}",
            context()
        );
        if !domain {
            continue;
        }
        tally.checked += 1;
        if state.flags.contains(StateFlags::PLASTIC) {
            tally.plastic += 1;
        }
        (target.check_step)(&before, &state, step, &output, &tangent, &context);
    }
    tally
}

/// The first violated property of an in-domain `Ok` step that holds for every model: finite
/// outputs (and tangent when asked for), `dl >= 0`, the plastic-strain variable not
/// decreasing, damage in `[0, 1]` and not decreasing, `V` taken from the input.
pub fn common_violation(
    before: &MaterialState,
    after: &MaterialState,
    step: &FuzzStep,
    output: &StepOutput,
    tangent: &[[f64; 6]; 6],
) -> Option<String> {
    if !(output.wave_speed.is_finite()
        && output.plastic_increment.is_finite()
        && output.yield_stress.is_finite())
    {
        return Some(format!("non-finite output {output:?}"));
    }
    if step.tangent && !tangent.iter().flatten().all(|c| c.is_finite()) {
        return Some(format!("non-finite tangent {tangent:?}"));
    }
    if !(output.plastic_increment >= 0.0) {
        return Some(format!(
            "negative plastic increment {}",
            output.plastic_increment
        ));
    }
    if !(after.plastic_strain >= before.plastic_strain) {
        return Some("the plastic-strain variable decreased".into());
    }
    if !((0.0..=1.0).contains(&after.damage) && after.damage >= before.damage) {
        return Some(format!(
            "damage {} -> {} (must stay in [0, 1], not decrease)",
            before.damage, after.damage
        ));
    }
    if after.relative_volume.to_bits() != step.input.relative_volume.to_bits() {
        return Some("relative volume not taken from the input".into());
    }
    None
}

/// The step sequence of the concrete targets (`rht_update`, `kc_update`): 1 to 12 steps,
/// components in `[-0.05, 0.05]`, `dt` in `[1e-9, 1e-3]` s (log), the new `V` from
/// `V exp(tr deps)` (three steps in four) or in `[0.5, 2]`, the tangent one step in two.
pub fn concrete_steps(src: &mut crate::source::Source, initial_volume: f64) -> Vec<FuzzStep> {
    let count = src.count(1, 12);
    let mut volume = initial_volume;
    (0..count)
        .map(|_| {
            src.take_domain();
            let mut strain_increment = [0.0; 6];
            for d in strain_increment.iter_mut() {
                *d = src.linear(-0.05, 0.05);
            }
            let dt = src.log(1e-9, 1e-3);
            let trace = strain_increment[0] + strain_increment[1] + strain_increment[2];
            let relative_volume = if src.byte() & 3 == 0 {
                src.linear(0.5, 2.0)
            } else {
                volume * trace.exp()
            };
            let tangent = src.flag();
            let in_domain = src.take_domain() && (0.5..=2.0).contains(&relative_volume);
            volume = relative_volume;
            FuzzStep {
                input: StepInput {
                    strain_increment,
                    dt,
                    relative_volume,
                },
                tangent,
                in_domain,
            }
        })
        .collect()
}

fn check_step(
    material: &Material,
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
    if !(output.yield_stress >= 0.0) {
        fail(format!("negative flow stress {}", output.yield_stress));
    }
    if output.iterations > MAX_RETURN_ITERATIONS {
        fail(format!("{} return iterations", output.iterations));
    }
    if !(after.temperature >= before.temperature) {
        fail(format!(
            "temperature decreased from {} to {}",
            before.temperature, after.temperature
        ));
    }
    if matches!(material.heating, Heating::Isothermal)
        && after.temperature.to_bits() != before.temperature.to_bits()
    {
        fail("isothermal material changed temperature".into());
    }
    // Yield condition (a failed point carries no deviator: its flow stress is 0).
    let plastic = after.flags.contains(StateFlags::PLASTIC);
    let flow = if after.flags.contains(StateFlags::FAILED) {
        0.0
    } else {
        match (plastic, material.rate_treatment) {
            (true, RateTreatment::Implicit) => material.strength.flow_stress(
                after.plastic_strain,
                after.plastic_strain_rate,
                before.temperature,
            ),
            (false, RateTreatment::Implicit) => {
                material
                    .strength
                    .flow_stress(before.plastic_strain, 0.0, before.temperature)
            }
            (_, RateTreatment::Lagged) => material.strength.flow_stress(
                before.plastic_strain,
                before.plastic_strain_rate,
                before.temperature,
            ),
        }
        .value
    };
    let q = after.equivalent_stress();
    let largest = after.stress.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    // The return stops at |g| <= RETURN_TOLERANCE q_trial, so q may exceed sigma_y by that
    // much even where sigma_y is tiny (e.g. at the melting temperature).
    let trial = tensor::add(
        &tensor::deviator(&before.stress),
        &tensor::scale(
            &tensor::deviator(&step.input.strain_increment),
            2.0 * material.shear_modulus,
        ),
    );
    let trial_equivalent = tensor::von_mises(&trial);
    let limit = flow * (1.0 + YIELD_RELATIVE)
        + YIELD_ABSOLUTE
        + 1e-14 * largest
        + 2.0 * RETURN_TOLERANCE * trial_equivalent;
    if !(q <= limit) {
        fail(format!(
            "outside the yield surface: q {q:e} > sigma_y {flow:e} (excess {:e}, \
             relative {:e}, allowed {limit:e}, q_trial {trial_equivalent:e}, plastic {plastic})",
            q - flow,
            (q - flow) / flow
        ));
    }
}
