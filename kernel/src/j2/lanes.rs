//! The stress update of a group of independent points, advanced stage by stage.
//!
//! One point's update is a chain of dependent operations (divisions, square roots, the `pow`
//! and `ln` of the flow stress), each waiting on the one before. A host updates many points
//! that do not depend on one another (a VUMAT's block, a solver's element loop), so the
//! group's points go through each stage of [`update`](super::update::update) together: every
//! point's predictor, then every point's flow stress at its warm start (the thermal factor's
//! and the flow stress's `pow`, `ln` and `exp` evaluated in lanes, `crate::math::lanes`; an
//! `exp` whose argument takes an announced `ln`, as Zerilli-Armstrong's, after it), then
//! every point's return, then every point's heating, EoS, damage and wave speed. Each stage's
//! per-point work is short, so the processor runs the points' chains side by side instead of
//! one after the other.
//!
//! Every stage is the one-point update's own function ([`super::update`]), called with the
//! same arguments, and the lane functions have the scalar ones' bits, so each point's result
//! has the bits of `update`'s. The stages cover the steps a developed computation is made of:
//! a plastic step from the implicit treatment's warm start (eq. 3.8; a return that needs more
//! evaluations continues from the lanes' one, one point at a time) and an elastic step decided
//! by the stored yield check. Any other point (a failed point, a cold start, a step the result
//! test refuses, an inadmissible input), and every point of a material the stages do not pay
//! for ([`staged`]), is updated by `update` itself, from its unchanged state.

use super::material::{Material, RateTreatment};
use super::update::{
    admissible, finish, implicit_entry, plastic_return, predict, residual_with, returned, update,
    Entry, Flow, Predictor, Residual,
};
use crate::error::UpdateError;
use crate::math::lanes::{self, Calls, Given};
use crate::point_model::{StepInput, StepOutput, LANES};
use crate::state::{MaterialState, StateFlags};
use crate::strength::FlowAtTemperature;

/// Whether a material's points go through the stages: the implicit treatment of a strength
/// that announces its `pow`, `ln` and `exp` ([`crate::strength::Strength::announces_calls`]:
/// JC, MJC, TJC and the diagnosis's variants, and Zerilli-Armstrong, whose `exp` takes the
/// value of its `ln`), so that the group evaluates them in lanes. Without a lane evaluation
/// the stages' bookkeeping costs more than the overlap of the points' chains gains on a shared
/// core (docs/benchmarks.md); the other models' points are updated one at a time.
#[inline(always)]
fn staged(material: &Material) -> bool {
    material.rate_treatment == RateTreatment::Implicit && material.strength.announces_calls()
}

/// A point's way through the stages.
#[derive(Clone, Copy)]
enum Route {
    /// Updated by [`update`] after the stages.
    Alone,
    /// A warm start at this multiplier.
    Warm(f64),
    /// An elastic step proved by the stored check (its value).
    Elastic(f64),
}

/// [`update`] of `L` independent points: `states[i]` over the step `inputs[i]`, its result in
/// `results[i]`. Each point's result and new state are bit for bit those of `update`; a point
/// whose step fails keeps its state, as with `update`.
#[inline]
pub fn update_lanes<const L: usize>(
    material: &Material,
    states: &mut [MaterialState; L],
    inputs: &[StepInput; L],
    results: &mut [Result<StepOutput, UpdateError>; L],
) {
    let shear = material.shear_modulus;
    let three_g = 3.0 * shear;
    let mut route = [Route::Alone; L];
    let mut predicted = [Predictor::default(); L];
    if !staged(material) {
        for ((state, input), result) in states.iter_mut().zip(inputs).zip(results.iter_mut()) {
            *result = update(material, state, input);
        }
        return;
    }
    // Stage 1: the predictor and the step's entry (eq. 3.8's warm start or a stored check).
    {
        for l in 0..L {
            let (state, input) = (&states[l], &inputs[l]);
            if admissible(state, input) && !state.flags.contains(StateFlags::FAILED) {
                predicted[l] = predict(material, state, input);
                route[l] =
                    match implicit_entry(state, predicted[l].trial_equivalent, input.dt, three_g) {
                        Entry::Warm(warm_dl) => Route::Warm(warm_dl),
                        Entry::Elastic(check) => Route::Elastic(check),
                        Entry::Cold(_) => Route::Alone,
                    };
            }
        }
    }
    // Stage 2: the warm points' flow stress at the warm start and its residual; the
    // temperature factor's and the flow stress's `pow`, `ln` and `exp` in lanes.
    let mut calls = [Calls::default(); L];
    for l in 0..L {
        if let Route::Warm(warm_dl) = route[l] {
            let (state, calls) = (&states[l], &mut calls[l]);
            (material.strength).announce_temperature(state.temperature, calls);
            (material.strength).announce_path(
                state.plastic_strain,
                warm_dl,
                predicted[l].inverse_dt,
                state.temperature,
                calls,
            );
        }
    }
    let values = lanes::evaluate(&mut calls);
    let mut at_temperature: [Option<FlowAtTemperature<'_>>; L] = [None; L];
    let mut evaluated: [Option<Residual>; L] = [None; L];
    for l in 0..L {
        if let Route::Warm(warm_dl) = route[l] {
            let state = &states[l];
            let mut given = Given::new(&calls[l], &values[l]);
            let flow = (material.strength).at_temperature_with(state.temperature, &mut given);
            evaluated[l] = Some(residual_with(
                &flow,
                three_g,
                predicted[l].trial_equivalent,
                state.plastic_strain,
                warm_dl,
                predicted[l].inverse_dt,
                &mut given,
            ));
            at_temperature[l] = Some(flow);
        }
    }
    // Stage 3: the return from the warm start (g > 0 there proves the step plastic), its
    // further evaluations, if any, one point at a time; or the elastic check.
    let mut flows: [Option<Flow>; L] = [None; L];
    for l in 0..L {
        flows[l] = match (route[l], evaluated[l], &at_temperature[l]) {
            (Route::Warm(warm_dl), Some(evaluated), Some(flow)) if evaluated.value > 0.0 => {
                plastic_return(
                    flow,
                    shear,
                    predicted[l].trial_equivalent,
                    states[l].plastic_strain,
                    (warm_dl, Some(evaluated)),
                    inputs[l].dt,
                    predicted[l].inverse_dt,
                )
                .ok()
            }
            (Route::Elastic(check), _, _) => Some(Err((check, true))),
            _ => None,
        };
    }
    // Stage 4: heating, EoS, damage, wave speed; then the points the stages did not finish.
    let mut done = [false; L];
    for l in 0..L {
        if let Some(flow) = flows[l] {
            let p = &predicted[l];
            let back = returned(material, &p.trial, p.trial_equivalent, flow);
            if let Ok(step) = finish(material, &states[l], &inputs[l], p, &back) {
                states[l] = step.state;
                results[l] = Ok(step.output);
                done[l] = true;
            }
        }
    }
    for l in 0..L {
        if !done[l] {
            results[l] = update(material, &mut states[l], &inputs[l]);
        }
    }
}

/// [`update`] of every point of a block, [`LANES`] at a time ([`update_lanes`]): `states[i]`
/// over `inputs[i]`, its result in `results[i]`, for the first `n` points, `n` the shortest of
/// the three slices' lengths (returned). Bit for bit the results of `update` point by point.
pub fn update_block(
    material: &Material,
    states: &mut [MaterialState],
    inputs: &[StepInput],
    results: &mut [Result<StepOutput, UpdateError>],
) -> usize {
    let n = states.len().min(inputs.len()).min(results.len());
    let whole = n - n % LANES;
    let groups = states[..whole]
        .chunks_exact_mut(LANES)
        .zip(inputs[..whole].chunks_exact(LANES))
        .zip(results[..whole].chunks_exact_mut(LANES));
    for ((states, inputs), results) in groups {
        if let (Ok(states), Ok(inputs), Ok(results)) = (
            <&mut [MaterialState; LANES]>::try_from(states),
            <&[StepInput; LANES]>::try_from(inputs),
            <&mut [Result<StepOutput, UpdateError>; LANES]>::try_from(results),
        ) {
            update_lanes(material, states, inputs, results);
        }
    }
    for i in whole..n {
        results[i] = update(material, &mut states[i], &inputs[i]);
    }
    n
}
