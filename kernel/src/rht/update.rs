//! The RHT stress update for one integration point and one step.
//!
//! Order of operations (given the strain increment `deps`, `dt` and the new relative volume
//! `V1`):
//! 1. EoS: the P-alpha (or any) pressure at `mu = 1/V1 - 1`, with the energy equation solved
//!    in closed form for the volumetric work only (`E* = E0 - (p0 + p*)/2 (V1 - V0)`); this
//!    pressure predictor is the pressure at which the deviatoric return is made;
//! 2. strain rate [`strain_rate`] (largest absolute principal strain rate) and the
//!    rate factor at the predictor pressure; hydro tensile limit check: below
//!    `p_min(D_n)` the point fails ([`super::TensileFailure::HydroTensileLimit`]) or the
//!    pressure is held at it ([`super::TensileFailure::PressureCutoff`]); a failed point
//!    carries no tension (pressure floor 0);
//! 3. deviatoric elastic predictor with the damaged shear modulus `G(D_n)`, Lode angle of the
//!    trial deviator;
//! 4. **radial return in the deviatoric plane at fixed pressure** (the usual Autodyn
//!    choice: no plastic volume change, the Lode angle is kept) onto the current surface.
//!    At fixed pressure, Lode angle and rate factor the current strength is piecewise
//!    linear in the plastic multiplier `dl` (linear hardening from the elastic limit to the
//!    failure surface, then linear softening in `D` towards the residual surface, then the
//!    residual surface), so `q_trial - 3 G dl = Y(dl)` is solved exactly, segment by
//!    segment, without iteration;
//! 5. damage `dD = d eps_p / eps_f(p)` for the plastic strain beyond the failure surface;
//!    optional principal-stress tensile failure;
//! 6. energy
//!    `E1 = E0 + W_dev - (p0 + p1)/2 (V1 - V0)` with the stored pressure `p1`, erosion flag,
//!    wave speed.
//!
//! The stored pressure is the one the surfaces were evaluated at, so a stored stress lies
//! exactly on the surface it was returned to. The price: the EoS energy term of this step's
//! deviatoric (dissipated) work, `dp/dE W_dev` (of the order of kPa per step for concrete),
//! enters the pressure one step later, when the next predictor re-evaluates the EoS with
//! `E1`. The energy bookkeeping itself is exact.

use super::surfaces::{Lode, Surfaces};
use super::{RhtMaterial, RhtParameters, TensileFailure};
use crate::eos::{EnergyLinearPressure, Eos};
use crate::error::UpdateError;
use crate::math::{clamp, sqrt};
use crate::point_model::{StepInput, StepOutput};
use crate::state::{MaterialState, StateFlags};
use crate::tangent::central_difference_tangent;
use crate::tensor::{self, Matrix6, Sym};

/// Update `state` over one step with the RHT model. On error, `state` is unchanged.
pub fn update(
    material: &RhtMaterial,
    state: &mut MaterialState,
    input: &StepInput,
) -> Result<StepOutput, UpdateError> {
    let (next, output) = compute(material, state, input)?;
    *state = next;
    Ok(output)
}

/// [`update`] that also writes the algorithmic tangent `d sigma_{n+1} / d deps` (Voigt,
/// tensor shear columns) into `tangent`, by central differences of the whole update
/// ([`crate::tangent::central_difference_tangent`]).
pub fn update_with_tangent(
    material: &RhtMaterial,
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

/// The strain rate of the rate factor: the largest absolute principal value of the strain
/// increment over `dt`. In the single-element tests of seed 001 section 4.3.2 (uniaxial
/// stress, uniaxial strain) this is the axial strain rate, whatever the lateral strains do,
/// which is the rate the dynamic increase factors of seed fig. 4.12 (and concrete DIF data)
/// are plotted against. Principal values by the trigonometric solution:
/// `m + 2 sqrt(J2/3) cos(theta)` (largest) and `m - 2 sqrt(J2/3) cos(pi/3 - theta)`
/// (smallest), with `m` the mean and `theta` the Lode angle of the increment's deviator.
pub fn strain_rate(increment: &tensor::Sym, dt: f64) -> f64 {
    let mean = tensor::trace(increment) / 3.0;
    let deviator = tensor::deviator(increment);
    let radius = sqrt(tensor::contract(&deviator, &deviator) / 6.0);
    let cos_theta = Lode::from_deviator(&deviator).cos_theta;
    let sin_theta = sqrt(clamp(1.0 - cos_theta * cos_theta, 0.0, 1.0));
    let largest = mean + 2.0 * radius * cos_theta;
    let smallest = mean - 2.0 * radius * (0.5 * cos_theta + 0.5 * sqrt(3.0) * sin_theta);
    let magnitude = if largest.abs() > smallest.abs() {
        largest.abs()
    } else {
        smallest.abs()
    };
    magnitude / dt
}

pub(crate) fn check_input(state: &MaterialState, input: &StepInput) -> Result<(), UpdateError> {
    if !crate::math::all_finite(&input.strain_increment)
        || !input.dt.is_finite()
        || !input.relative_volume.is_finite()
    {
        return Err(UpdateError::NonFiniteInput);
    }
    if input.dt <= 0.0 {
        return Err(UpdateError::NonPositiveTimeStep);
    }
    if input.relative_volume <= 0.0 {
        return Err(UpdateError::NonPositiveVolume);
    }
    if !state.is_finite() || state.relative_volume <= 0.0 {
        return Err(UpdateError::NonFiniteState);
    }
    Ok(())
}

/// Result of the return in the deviatoric plane.
struct Return {
    /// Plastic multiplier (equivalent plastic strain increment).
    increment: f64,
    /// Equivalent stress after the return.
    equivalent: f64,
    /// Damage after the return.
    damage: f64,
}

/// Solve `q_trial - 3 G dl = Y(dl)` on the piecewise-linear current strength, starting from
/// `(eps_p, D)`; `q_trial` exceeds the current strength.
fn radial_return(
    surfaces: &Surfaces,
    shear: f64,
    trial: f64,
    plastic_strain: f64,
    damage: f64,
) -> Return {
    let three_g = 3.0 * shear;
    let mut hardening_increment = 0.0;
    if damage <= 0.0 && plastic_strain < surfaces.pre_softening_strain {
        // Linear hardening from the elastic limit towards the failure surface.
        let modulus = (surfaces.failure - surfaces.elastic) / surfaces.pre_softening_strain;
        let current = surfaces.current(plastic_strain, 0.0);
        let increment = (trial - current) / (three_g + modulus);
        hardening_increment = surfaces.pre_softening_strain - plastic_strain;
        if increment <= hardening_increment {
            return Return {
                increment,
                equivalent: trial - three_g * increment,
                damage,
            };
        }
    }
    // Softening on the damaged surface (1 - D) Y_fail + D Y_resid.
    let drop = surfaces.failure - surfaces.residual;
    let remaining = trial - three_g * hardening_increment;
    let start = surfaces.failure - damage * drop;
    let to_full_damage = (1.0 - damage) * surfaces.failure_strain;
    let denominator = three_g - drop / surfaces.failure_strain;
    if denominator > 0.0 {
        let softening = (remaining - start) / denominator;
        if softening <= to_full_damage {
            return Return {
                increment: hardening_increment + softening,
                equivalent: remaining - three_g * softening,
                damage: damage + softening / surfaces.failure_strain,
            };
        }
    }
    // Fully damaged (or snap-back: softening faster than elastic unloading): residual.
    let increment = (trial - surfaces.residual) / three_g;
    Return {
        increment: if increment > 0.0 { increment } else { 0.0 },
        equivalent: surfaces.residual,
        damage: 1.0,
    }
}

/// Step 1 of the concrete updates (RHT, K&C): the EoS pressure predictor with the volumetric
/// work only, `e* = (e_n - (p_n + p_base) dV / 2) / (1 + Gamma-term dV / 2)`.
pub(crate) struct Predictor {
    pub volume_change: f64,
    pub mid_volume: f64,
    pub terms: EnergyLinearPressure,
    pub eos_history: f64,
    pub old_pressure: f64,
    pub energy: f64,
    pub pressure: f64,
}

/// The predictor of `eos` for the step from `state` to `input`'s relative volume.
#[inline(always)]
pub(crate) fn pressure_predictor(eos: &Eos, state: &MaterialState, input: &StepInput) -> Predictor {
    let volume_change = input.relative_volume - state.relative_volume;
    let mid_volume = 0.5 * (input.relative_volume + state.relative_volume);
    let mu = 1.0 / input.relative_volume - 1.0;
    let (terms, eos_history) = eos.evaluate(mu, state.eos_history);
    let old_pressure = state.pressure();
    let energy = (state.internal_energy - 0.5 * (old_pressure + terms.base) * volume_change)
        / (1.0 + 0.5 * terms.energy_coefficient * volume_change);
    let pressure = terms.pressure(energy);
    Predictor {
        volume_change,
        mid_volume,
        terms,
        eos_history,
        old_pressure,
        energy,
        pressure,
    }
}

/// The last step of the concrete updates: the energy (volumetric work with the stored
/// pressure, redone when a limit changed it from the predictor's, plus the deviatoric work)
/// and the new stress, volume and EoS history in `next`. Returns the energy.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn book_energy(
    state: &MaterialState,
    next: &mut MaterialState,
    predictor: &Predictor,
    pressure: f64,
    old_deviator: &Sym,
    new_deviator: &Sym,
    deviatoric_increment: &Sym,
    relative_volume: f64,
) -> f64 {
    let mut volumetric_energy = predictor.energy;
    if pressure != predictor.pressure {
        next.flags.insert(StateFlags::PRESSURE_CUTOFF);
        volumetric_energy = state.internal_energy
            - 0.5 * (predictor.old_pressure + pressure) * predictor.volume_change;
    }
    let mean_deviator = tensor::scale(&tensor::add(old_deviator, new_deviator), 0.5);
    let deviatoric_work =
        tensor::contract(&mean_deviator, deviatoric_increment) * predictor.mid_volume;
    let energy = volumetric_energy + deviatoric_work;
    next.stress = tensor::from_deviator_and_pressure(new_deviator, pressure);
    next.relative_volume = relative_volume;
    next.internal_energy = energy;
    next.eos_history = predictor.eos_history;
    energy
}

/// Step 2's tensile limit: the hydrostatic tensile limit fails the point (`failed` set), a
/// failed point carries no tension, and the pressure cut-off option holds the pressure at the
/// limit. Returns the pressure.
#[inline(always)]
fn tensile_limit(
    params: &RhtParameters,
    mut pressure: f64,
    rate_factor: f64,
    damage_before: f64,
    failed: &mut bool,
) -> f64 {
    let hydro = params.tensile_failure == TensileFailure::HydroTensileLimit;
    if hydro && !*failed && pressure < params.hydro_tensile_limit(rate_factor, damage_before) {
        *failed = true;
    }
    if *failed && pressure < 0.0 {
        pressure = 0.0;
    }
    if params.tensile_failure == TensileFailure::PressureCutoff && !*failed {
        let limit = params.hydro_tensile_limit(rate_factor, damage_before);
        if pressure < limit {
            pressure = limit;
        }
    }
    pressure
}

/// Steps 4-5: the current strength (the residual surface once failed, else between the
/// elastic and failure surfaces by hardening and damage) and the return onto it.
#[inline(always)]
fn surface_return(
    surfaces: &Surfaces,
    shear: f64,
    trial_equivalent: f64,
    plastic_strain: f64,
    damage_before: f64,
    failed: bool,
) -> (f64, Return) {
    let (current, damage) = if failed {
        (surfaces.residual, 1.0)
    } else {
        (
            surfaces.current(plastic_strain, damage_before),
            damage_before,
        )
    };
    // A strength is never negative (round-off of (1 - D) Y_fail + D Y_resid near D = 1).
    let current = if current > 0.0 { current } else { 0.0 };
    let result = if trial_equivalent > current {
        if failed {
            Return {
                increment: (trial_equivalent - current) / (3.0 * shear),
                equivalent: current,
                damage: 1.0,
            }
        } else {
            radial_return(surfaces, shear, trial_equivalent, plastic_strain, damage)
        }
    } else {
        Return {
            increment: 0.0,
            equivalent: trial_equivalent,
            damage,
        }
    };
    (current, result)
}

/// The principal-stress tensile failure option: the largest principal stress at or above the
/// (rate-enhanced) tensile strength fails the point; its tension goes and its deviator
/// returns to the residual strength. Returns whether it failed.
#[inline(always)]
fn principal_stress_failure(
    params: &RhtParameters,
    surfaces: &Surfaces,
    lode: Lode,
    rate: f64,
    shear: f64,
    pressure: &mut f64,
    result: &mut Return,
) -> bool {
    let largest = lode.largest_principal_deviator(result.equivalent) - *pressure;
    let (_, tension_factor) = params.rate_factors(rate);
    if largest < tension_factor * params.tensile_strength() {
        return false;
    }
    result.damage = 1.0;
    if *pressure < 0.0 {
        *pressure = 0.0;
    }
    let residual = params.residual_strength(*pressure);
    let residual = if residual < surfaces.failure {
        residual
    } else {
        surfaces.failure
    };
    if result.equivalent > residual {
        result.increment += (result.equivalent - residual) / (3.0 * shear);
        result.equivalent = residual;
    }
    true
}

/// The return's history: plastic strain and rate, damage, and the plastic, failed and erode
/// flags.
#[inline(always)]
fn book_return(
    material: &RhtMaterial,
    state: &MaterialState,
    next: &mut MaterialState,
    result: &Return,
    failed: bool,
    dt: f64,
) {
    if result.increment > 0.0 {
        next.flags.insert(StateFlags::PLASTIC);
    }
    next.plastic_strain = state.plastic_strain + result.increment;
    next.plastic_strain_rate = result.increment / dt;
    next.damage = if failed { 1.0 } else { result.damage };
    if failed {
        next.flags.insert(StateFlags::FAILED);
    }
    if let Some(limit) = material.erosion_plastic_strain {
        if next.plastic_strain >= limit {
            next.flags.insert(StateFlags::ERODE);
        }
    }
}

fn compute(
    material: &RhtMaterial,
    state: &MaterialState,
    input: &StepInput,
) -> Result<(MaterialState, StepOutput), UpdateError> {
    check_input(state, input)?;
    let params = &material.parameters;
    let dt = input.dt;
    let mut next = *state;
    next.flags
        .remove(StateFlags::PLASTIC | StateFlags::PRESSURE_CUTOFF);
    let damage_before = if state.damage > 0.0 {
        state.damage
    } else {
        0.0
    };
    let mut failed = damage_before >= 1.0;

    // 1. EoS pressure predictor (volumetric work only).
    let predictor = pressure_predictor(&material.eos, state, input);
    let eos_pressure = predictor.pressure;
    let mut pressure = eos_pressure;

    // 2. Rate factor; hydro tensile limit.
    let deviatoric_increment = tensor::deviator(&input.strain_increment);
    let rate = strain_rate(&input.strain_increment, dt);
    let rate_factor = params.rate_factor(rate, pressure);
    pressure = tensile_limit(params, pressure, rate_factor, damage_before, &mut failed);

    // 3. Elastic predictor with the damaged shear modulus.
    let shear = params.damaged_shear_modulus(if failed { 1.0 } else { damage_before });
    let old_deviator = tensor::deviator(&state.stress);
    let trial = tensor::add(
        &old_deviator,
        &tensor::scale(&deviatoric_increment, 2.0 * shear),
    );
    let trial_equivalent = tensor::von_mises(&trial);
    let lode = Lode::from_deviator(&trial);

    // 4-5. Return onto the current surface; damage.
    let cap = material.cap_pressure();
    let surfaces = params.surfaces(pressure, lode, rate_factor, cap);
    let (current, mut result) = surface_return(
        &surfaces,
        shear,
        trial_equivalent,
        state.plastic_strain,
        damage_before,
        failed,
    );
    if result.damage >= 1.0 {
        failed = true;
    }
    if params.tensile_failure == TensileFailure::PrincipalStress && !failed {
        failed = principal_stress_failure(
            params,
            &surfaces,
            lode,
            rate,
            shear,
            &mut pressure,
            &mut result,
        );
    }
    let new_deviator = if trial_equivalent > 0.0 {
        tensor::scale(&trial, result.equivalent / trial_equivalent)
    } else {
        trial
    };
    book_return(material, state, &mut next, &result, failed, dt);

    // 6. Energy: volumetric work with the stored pressure (changed only by a failure's
    // pressure floor), plus the deviatoric work.
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

    // Wave speed with the undamaged shear modulus (the fastest wave, for the CFL step).
    let wave_speed = crate::eos::longitudinal_wave_speed(
        &predictor.terms,
        energy,
        material.density,
        input.relative_volume,
        params.shear_modulus,
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Surfaces of a made-up point: elastic 60, failure 100, residual 40 (MPa), hardening
    /// over 1e-3, failure strain 0.01.
    const SURFACES: Surfaces = Surfaces {
        failure: 100e6,
        elastic: 60e6,
        residual: 40e6,
        pre_softening_strain: 1e-3,
        failure_strain: 0.01,
    };
    const SHEAR: f64 = 10e9;

    fn check(result: &Return, trial: f64, plastic_strain: f64) {
        // The returned stress is the current strength at the returned state and obeys
        // q = q_trial - 3 G dl.
        let strength = SURFACES.current(plastic_strain + result.increment, result.damage);
        assert!((result.equivalent - strength).abs() < 1e-6, "{strength}");
        assert!((result.equivalent - (trial - 3.0 * SHEAR * result.increment)).abs() < 1e-6);
    }

    #[test]
    fn return_solves_each_segment_exactly() {
        // GOAL: the closed-form return lands on the piecewise-linear current strength in each
        //   segment: hardening only, hardening into softening, softening only, to the
        //   residual surface; and with a snap-back softening (faster than elastic unloading)
        //   it goes to the residual surface.
        // SETUP: SURFACES (H = 40 MPa / 1e-3 = 40 GPa, softening 60 MPa / 0.01 = 6 GPa),
        //   G = 10 GPa. REFERENCE: q = Y(eps_p + dl, D) and q = q_trial - 3 G dl; 1e-6 Pa.
        // Hardening only: from eps_p = 0, q_trial 70 MPa.
        let r = radial_return(&SURFACES, SHEAR, 70e6, 0.0, 0.0);
        assert_eq!(r.damage, 0.0);
        assert!((r.increment - 10e6 / (30e9 + 40e9)).abs() < 1e-18);
        check(&r, 70e6, 0.0);
        // Hardening then softening: q_trial 200 MPa from eps_p = 5e-4.
        let r = radial_return(&SURFACES, SHEAR, 200e6, 5e-4, 0.0);
        assert!(r.damage > 0.0 && r.damage < 1.0);
        check(&r, 200e6, 5e-4);
        // Softening only from D = 0.5.
        let r = radial_return(&SURFACES, SHEAR, 90e6, 2e-3, 0.5);
        assert!(r.damage > 0.5 && r.damage < 1.0);
        check(&r, 90e6, 2e-3);
        // To the residual surface.
        let r = radial_return(&SURFACES, SHEAR, 2e9, 2e-3, 0.5);
        assert_eq!(r.damage, 1.0);
        assert_eq!(r.equivalent, 40e6);
        check(&r, 2e9, 2e-3);
        // Snap-back: failure strain so small that softening outruns elastic unloading.
        let brittle = Surfaces {
            failure_strain: 1e-4,
            ..SURFACES
        };
        let r = radial_return(&brittle, SHEAR, 105e6, 2e-3, 0.1);
        assert_eq!(r.damage, 1.0);
        assert_eq!(r.equivalent, brittle.residual);
    }

    #[test]
    fn strain_rate_is_the_largest_principal_rate() {
        // GOAL: strain_rate() is max |principal strain| / dt.
        // SETUP: uniaxial-stress-like, uniaxial strain, hydrostatic and pure shear increments.
        // REFERENCE: the principal values by hand; tolerance 1e-15 relative.
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(rel(strain_rate(&[-1e-3, 3e-4, 3e-4, 0.0, 0.0, 0.0], 1e-3), 1.0) < 1e-15);
        assert!(rel(strain_rate(&[2e-3, -1e-4, -5e-4, 0.0, 0.0, 0.0], 1.0), 2e-3) < 1e-15);
        assert!(rel(strain_rate(&[1e-3, 0.0, 0.0, 0.0, 0.0, 0.0], 1.0), 1e-3) < 1e-15);
        assert!(
            rel(
                strain_rate(&[-1e-3, -1e-3, -1e-3, 0.0, 0.0, 0.0], 1.0),
                1e-3
            ) < 1e-15
        );
        assert!(rel(strain_rate(&[0.0, 0.0, 0.0, 0.0, 0.0, 4e-3], 2.0), 2e-3) < 1e-15);
        assert_eq!(strain_rate(&[0.0; 6], 1.0), 0.0);
    }
}
