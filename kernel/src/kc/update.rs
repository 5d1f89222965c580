//! The K&C stress update for one integration point and one step.
//!
//! Order of operations (given `deps`, `dt` and the new relative volume `V1`):
//! 1. EoS pressure predictor at `mu = 1/V1 - 1` with the volumetric work only, as for RHT
//!    ([`crate::rht::update()`]);
//! 2. rate factor `r_f` at the largest principal strain rate ([`crate::rht::strain_rate`]);
//!    tension cut-off: the pressure is held at `-r_f ft` before the peak of `eta` and at
//!    `-r_f eta ft` after it (where the softened tensile surface closes);
//! 3. deviatoric elastic predictor, Lode angle of the trial deviator;
//! 4. radial return in the deviatoric plane at fixed pressure (no dilatancy, LS-DYNA's
//!    `omega = 0`) onto the current surface, with the damage parameter growing as
//!    `d lambda = d eps_p / (r_f (1 + p/(r_f ft))^b)` (`b1` for `p >= 0`, `b2` below),
//!    times the crack-band scale after the peak. At fixed pressure the current strength is
//!    linear in `lambda` on each segment of the damage function and `lambda` is linear in
//!    the multiplier, so `q_trial - 3 G dl = Y(lambda_n + k dl)` is solved exactly, segment
//!    by segment (a segment whose softening is faster than the elastic unloading, a
//!    snap-back, is passed whole);
//! 5. energy `E1 = E0 + W_dev - (p0 + p1)/2 (V1 - V0)` with the stored pressure, wave speed.

use super::surfaces::Strengths;
use super::KcMaterial;
use crate::error::UpdateError;
use crate::point_model::{StepInput, StepOutput};
use crate::rht::update::{book_energy, check_input, pressure_predictor};
use crate::rht::{strain_rate, Lode};
use crate::state::{MaterialState, StateFlags};
use crate::tangent::central_difference_tangent;
use crate::tensor::{self, Matrix6};

/// Update `state` over one step with the K&C model. On error, `state` is unchanged.
pub fn update(
    material: &KcMaterial,
    state: &mut MaterialState,
    input: &StepInput,
) -> Result<StepOutput, UpdateError> {
    let (next, output) = compute(material, state, input)?;
    *state = next;
    Ok(output)
}

/// [`update`] that also writes the algorithmic tangent by central differences
/// ([`crate::tangent::central_difference_tangent`]).
pub fn update_with_tangent(
    material: &KcMaterial,
    state: &mut MaterialState,
    input: &StepInput,
    tangent: &mut Matrix6,
) -> Result<StepOutput, UpdateError> {
    let (next, output) = compute(material, state, input)?;
    central_difference_tangent(
        input,
        |perturbed| Ok(compute(material, state, perturbed)?.0.stress),
        tangent,
    )?;
    *state = next;
    Ok(output)
}

/// The scaled damage measure of LS-DYNA `*MAT_072R3`, halved to lie in `[0, 1]`:
/// `lambda/(lambda + lambda_m)` before the peak, `(2 - eta)/2` after it (1/2 at the peak,
/// 1 when only the residual strength is left).
///
/// Written `1 - lambda_m/(lambda + lambda_m)` before the peak so that every rounded
/// operation is monotone in `lambda`: the measure never decreases as `lambda` grows, to the
/// last bit (`lambda/(lambda + lambda_m)` can lose an ulp when `lambda` gains one).
pub fn damage_measure(lambda: f64, peak_lambda: f64, eta: f64) -> f64 {
    if lambda < peak_lambda {
        1.0 - peak_lambda / (lambda + peak_lambda)
    } else {
        1.0 - 0.5 * eta
    }
}

/// Result of the return: plastic multiplier, equivalent stress, damage parameter.
struct Return {
    increment: f64,
    equivalent: f64,
    lambda: f64,
}

/// Solve `q - 3 G dl = Y(lambda_n + k dl)` segment by segment (see the module's item 4);
/// `k` is `growth.0` before the peak and `growth.1` after it.
fn radial_return(
    material: &KcMaterial,
    strengths: &Strengths,
    three_g: f64,
    trial: f64,
    lambda_n: f64,
    growth: (f64, f64),
) -> Return {
    let table = &material.parameters.damage;
    let n = table.used();
    let peak = table.peak();
    let mut used = 0.0;
    let mut lambda = lambda_n;
    // At most one pass over each segment (bounded whatever an unvalidated table holds).
    for i in table.segment(lambda)..n.saturating_sub(1) {
        if lambda >= table.lambda[n - 1] {
            break;
        }
        let post_peak = i >= peak;
        let k = if post_peak { growth.1 } else { growth.0 };
        let (la, lb) = (table.lambda[i], table.lambda[i + 1]);
        let (ea, eb) = (table.eta[i], table.eta[i + 1]);
        let eta_start = ea + (eb - ea) * (lambda - la) / (lb - la);
        // Linear along the segment; a strength that falls below zero (the tensile surface
        // closing) is zero from there on.
        let start = strengths.linear(eta_start, post_peak);
        let end = strengths.linear(eb, post_peak);
        let slope = (end - start) / (lb - lambda);
        let to_end = (lb - lambda) / k;
        let denominator = three_g + slope * k;
        let remaining = trial - three_g * used;
        if start <= 0.0 {
            return to_zero_strength(used, remaining / three_g, lambda, k);
        }
        if denominator > 0.0 {
            let x = (remaining - start) / denominator;
            let x = if x > 0.0 { x } else { 0.0 };
            if start + slope * k * x < 0.0 {
                return to_zero_strength(used, remaining / three_g, lambda, k);
            }
            if x <= to_end {
                return returned(trial, three_g, used + x, lambda + k * x);
            }
        }
        // Passed whole; never more than removes the whole trial deviator.
        used = (used + to_end).min(trial / three_g);
        lambda = lb;
    }
    // Beyond the table (after the peak, which is a table point): eta constant.
    let strength = strengths.at(table.eta[n - 1], true);
    let x = (trial - three_g * used - strength) / three_g;
    let x = if x > 0.0 { x } else { 0.0 };
    returned(trial, three_g, used + x, lambda + growth.1 * x)
}

/// The return with multiplier `increment`: equivalent stress `q_trial - 3G dl`, never below
/// zero (round-off of a return that removes the whole deviator).
fn returned(trial: f64, three_g: f64, increment: f64, lambda: f64) -> Return {
    let equivalent = trial - three_g * increment;
    Return {
        increment,
        equivalent: if equivalent > 0.0 { equivalent } else { 0.0 },
        lambda,
    }
}

/// The return to a zero deviator once the strength is zero: the rest of the trial
/// deviator, `x = remaining / 3G`, is plastic, and `lambda` keeps growing with it.
fn to_zero_strength(used: f64, x: f64, lambda: f64, k: f64) -> Return {
    Return {
        increment: used + x,
        equivalent: 0.0,
        lambda: lambda + k * x,
    }
}

/// The damage measure's growth per unit plastic strain, `1 / (r_f (1 + p / (r_f f_t))^b)`
/// with `b = b1` in compression and `b2` in tension (the base held at 0.01 or more).
#[inline(always)]
fn damage_growth(material: &KcMaterial, pressure: f64, rate_factor: f64) -> f64 {
    let params = &material.parameters;
    let base = 1.0 + pressure / (rate_factor * params.tensile_strength);
    let base = if base > 0.01 { base } else { 0.01 };
    let exponent = if pressure >= 0.0 {
        params.compression_damage_exponent
    } else {
        params.tension_damage_exponent
    };
    1.0 / (rate_factor * crate::math::pow(base, exponent))
}

fn compute(
    material: &KcMaterial,
    state: &MaterialState,
    input: &StepInput,
) -> Result<(MaterialState, StepOutput), UpdateError> {
    check_input(state, input)?;
    let params = &material.parameters;
    let table = &params.damage;
    let dt = input.dt;
    let mut next = *state;
    next.flags
        .remove(StateFlags::PLASTIC | StateFlags::PRESSURE_CUTOFF);
    let lambda_n = if state.plastic_strain > 0.0 {
        state.plastic_strain
    } else {
        0.0
    };
    let peak_lambda = table.peak_lambda();
    let post_peak = lambda_n >= peak_lambda;
    let eta_n = table.eta_at(lambda_n);

    // 1. EoS pressure predictor (volumetric work only).
    let predictor = pressure_predictor(&material.eos, state, input);
    let eos_pressure = predictor.pressure;

    // 2. Rate factor; tension cut-off.
    let rate = strain_rate(&input.strain_increment, dt);
    let rate_factor = params.rate_factor(rate, eos_pressure);
    let open = if post_peak { eta_n } else { 1.0 };
    let tension_limit = -rate_factor * params.tensile_strength * open;
    let pressure = if eos_pressure < tension_limit {
        tension_limit
    } else {
        eos_pressure
    };

    // 3. Elastic predictor.
    let shear = params.shear_modulus;
    let three_g = 3.0 * shear;
    let deviatoric_increment = tensor::deviator(&input.strain_increment);
    let old_deviator = tensor::deviator(&state.stress);
    let trial = tensor::add(
        &old_deviator,
        &tensor::scale(&deviatoric_increment, 2.0 * shear),
    );
    let trial_equivalent = tensor::von_mises(&trial);
    let lode = Lode::from_deviator(&trial);

    // 4. Return onto the current surface.
    let strengths = params.strengths(pressure, lode, rate_factor);
    let current = strengths.at(eta_n, post_peak);
    let result = if trial_equivalent > current {
        let growth = damage_growth(material, pressure, rate_factor);
        radial_return(
            material,
            &strengths,
            three_g,
            trial_equivalent,
            lambda_n,
            (growth, growth * params.softening_scale()),
        )
    } else {
        Return {
            increment: 0.0,
            equivalent: trial_equivalent,
            lambda: lambda_n,
        }
    };
    let new_deviator = if trial_equivalent > 0.0 {
        tensor::scale(&trial, result.equivalent / trial_equivalent)
    } else {
        trial
    };
    let eta = table.eta_at(result.lambda);
    if result.increment > 0.0 {
        next.flags.insert(StateFlags::PLASTIC);
    }
    if result.lambda >= peak_lambda && eta <= 0.0 {
        next.flags.insert(StateFlags::FAILED);
    }
    next.plastic_strain = result.lambda;
    next.plastic_strain_rate = result.increment / dt;
    next.damage = damage_measure(result.lambda, peak_lambda, eta);

    // 5. Energy with the stored pressure, wave speed.
    let energy = book_energy(
        state,
        &mut next,
        &predictor,
        pressure,
        &old_deviator,
        &new_deviator,
        &deviatoric_increment,
        input.relative_volume,
    );
    let wave_speed = crate::eos::longitudinal_wave_speed(
        &predictor.terms,
        energy,
        material.density,
        input.relative_volume,
        shear,
    );
    if !next.is_finite() || !wave_speed.is_finite() {
        return Err(UpdateError::NonFiniteResult);
    }
    Ok((
        next,
        StepOutput {
            wave_speed,
            plastic_increment: result.increment,
            yield_stress: if result.increment > 0.0 {
                result.equivalent
            } else {
                current
            },
            iterations: 0,
        },
    ))
}
