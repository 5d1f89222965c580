//! Thin adapters to the calling conventions of LS-DYNA user materials (`umat4X`/`umat4Xv`) and
//! Abaqus/Explicit `VUMAT`.
//!
//! Both keep the point's non-stress history in a host-owned array of doubles (LS-DYNA `hsv`,
//! Abaqus `stateOld`/`stateNew`) with the same layout, [`STOSS_HISTORY_COUNT`] values:
//!
//! | C index | Fortran | quantity |
//! |---|---|---|
//! | 0 | 1 | equivalent plastic strain `eps_p` (-) |
//! | 1 | 2 | equivalent plastic strain rate of the last step (1/s) |
//! | 2 | 3 | temperature (K) |
//! | 3 | 4 | damage `D` (-) |
//! | 4 | 5 | relative volume `V/V0` (-); **0 marks an uninitialised point** |
//! | 5 | 6 | internal energy per unit reference volume (J/m^3) |
//! | 6 | 7 | EoS history (P-alpha distension, tabulated-compaction max strain; else 0) |
//! | 7 | 8 | state flags (1 plastic, 2 failed, 4 erode, 8 pressure cut-off), an exact integer |
//!
//! Hosts zero their history arrays before the first step; a point whose relative volume slot
//! is 0 starts from the material's initial state (initial temperature, `V/V0 = 1`, initial EoS
//! history) with the stress the host passes in. History values beyond the eighth are not
//! touched, so a host may keep its own variables there.
//!
//! The relative volume is integrated from the strain increments, `V1 = V0 exp(tr deps)`, as
//! in stoss's own drivers (LS-DYNA's and Abaqus's strain increments are increments of
//! logarithmic strain, so this is the host's volume to the accuracy of its integration).

use stoss_kernel::tensor::{self, Sym};
use stoss_kernel::{MaterialState, StateFlags, StepOutput, UpdateError, YieldCheck, LANES};

use crate::batch::{failure_code, step_input, step_point, zero_step, AbiModel};
use crate::block::initial_bulk_modulus;
use crate::boundary::{ArrayIn, ArrayOut};
use crate::status::StossStatus;

/// History values per point used by the adapters (LS-DYNA `NHV`, Abaqus `*DEPVAR`, at least).
pub const STOSS_HISTORY_COUNT: usize = 8;
/// History index (0-based) of the equivalent plastic strain.
pub const STOSS_HISTORY_PLASTIC_STRAIN: usize = 0;
/// History index of the plastic strain rate.
pub const STOSS_HISTORY_PLASTIC_STRAIN_RATE: usize = 1;
/// History index of the temperature.
pub const STOSS_HISTORY_TEMPERATURE: usize = 2;
/// History index of the damage.
pub const STOSS_HISTORY_DAMAGE: usize = 3;
/// History index of the relative volume (0: uninitialised point).
pub const STOSS_HISTORY_RELATIVE_VOLUME: usize = 4;
/// History index of the internal energy per reference volume.
pub const STOSS_HISTORY_INTERNAL_ENERGY: usize = 5;
/// History index of the EoS history variable.
pub const STOSS_HISTORY_EOS_HISTORY: usize = 6;
/// History index of the state flags.
pub const STOSS_HISTORY_FLAGS: usize = 7;

/// The history of one point.
pub type History = [f64; STOSS_HISTORY_COUNT];

/// The state of a point from its stress and history; a zero relative volume means "not yet
/// initialised" and gives `initial` with `stress`. A flags value that is not an exact
/// integer in `u32` range is an invalid state.
#[inline(always)]
pub fn state_from_history(
    stress: &Sym,
    history: &History,
    initial: &MaterialState,
) -> Result<MaterialState, UpdateError> {
    if history[STOSS_HISTORY_RELATIVE_VOLUME] == 0.0 {
        return Ok(MaterialState {
            stress: *stress,
            ..*initial
        });
    }
    let flags = history[STOSS_HISTORY_FLAGS];
    // In range, the cast truncates exactly, so equality after the round trip is integrality
    // (without `f64::trunc`, a library call on targets without SSE4.1).
    if !(flags >= 0.0 && flags <= f64::from(u32::MAX) && f64::from(flags as u32) == flags) {
        return Err(UpdateError::NonFiniteState);
    }
    Ok(MaterialState {
        stress: *stress,
        plastic_strain: history[STOSS_HISTORY_PLASTIC_STRAIN],
        plastic_strain_rate: history[STOSS_HISTORY_PLASTIC_STRAIN_RATE],
        temperature: history[STOSS_HISTORY_TEMPERATURE],
        damage: history[STOSS_HISTORY_DAMAGE],
        relative_volume: history[STOSS_HISTORY_RELATIVE_VOLUME],
        internal_energy: history[STOSS_HISTORY_INTERNAL_ENERGY],
        eos_history: history[STOSS_HISTORY_EOS_HISTORY],
        flags: StateFlags(flags as u32),
        yield_check: YieldCheck::NONE,
    })
}

/// The history values of a state.
#[inline(always)]
pub fn history_from_state(state: &MaterialState) -> History {
    let mut history = [0.0; STOSS_HISTORY_COUNT];
    history[STOSS_HISTORY_PLASTIC_STRAIN] = state.plastic_strain;
    history[STOSS_HISTORY_PLASTIC_STRAIN_RATE] = state.plastic_strain_rate;
    history[STOSS_HISTORY_TEMPERATURE] = state.temperature;
    history[STOSS_HISTORY_DAMAGE] = state.damage;
    history[STOSS_HISTORY_RELATIVE_VOLUME] = state.relative_volume;
    history[STOSS_HISTORY_INTERNAL_ENERGY] = state.internal_energy;
    history[STOSS_HISTORY_EOS_HISTORY] = state.eos_history;
    history[STOSS_HISTORY_FLAGS] = f64::from(state.flags.0);
    history
}

/// LS-DYNA umat convention for one point: strain increments with **engineering** shear
/// (`gamma = 2 eps`) in Voigt order `xx yy zz xy yz zx`, the full Cauchy stress `sig`
/// (updated in place) and the history `hsv` (updated in place). On error nothing is changed.
#[inline(always)]
pub fn lsdyna_umat_point<M: AbiModel>(
    material: &M,
    initial: &MaterialState,
    dt: f64,
    engineering_strain_increment: &Sym,
    sig: &mut Sym,
    hsv: &mut History,
) -> Result<(StepOutput, MaterialState), UpdateError> {
    let e = engineering_strain_increment;
    // Halving is exact in binary floating point (barring subnormals).
    let increment = [e[0], e[1], e[2], 0.5 * e[3], 0.5 * e[4], 0.5 * e[5]];
    let mut state = state_from_history(sig, hsv, initial)?;
    let output = step_point(material, &mut state, &increment, dt, None, None)?;
    *sig = state.stress;
    *hsv = history_from_state(&state);
    Ok((output, state))
}

/// The inputs of one VUMAT point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VumatInput {
    /// Time step (s).
    pub dt: f64,
    /// Abaqus's data-check call (`totalTime = stepTime = 0`).
    pub data_check: bool,
    /// `strainInc` (tensor shear), Abaqus order 11 22 33 12 23 31.
    pub strain_increment: Sym,
    /// `stressOld`.
    pub stress_old: Sym,
    /// `stateOld` (first [`STOSS_HISTORY_COUNT`] values).
    pub state_old: History,
    /// `enerInternOld` (J/kg); only passed through by the data-check call.
    pub energy_per_mass_old: f64,
}

/// The result of one VUMAT point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VumatPoint {
    /// `stressNew` (Abaqus order 11 22 33 12 23 31 = stoss's xx yy zz xy yz zx).
    pub stress: Sym,
    /// `stateNew` (first [`STOSS_HISTORY_COUNT`] values).
    pub history: History,
    /// `enerInternNew`: internal energy per unit **mass** (J/kg) = stoss's energy per unit
    /// reference volume divided by the reference density.
    pub internal_energy_per_mass: f64,
    /// Wave speed and the rest of the kernel's per-step output (`None` for the data-check
    /// call).
    pub output: Option<StepOutput>,
    /// The full state after the step.
    pub state: MaterialState,
}

/// Abaqus/Explicit VUMAT convention for one point: **tensor** shear strain increments, stress
/// and state "old" in, "new" out.
///
/// `data_check` is Abaqus's start-of-analysis call (`totalTime = stepTime = 0`) with a
/// fictitious strain increment: it returns the elastic response
/// `stressOld + K tr(deps) 1 + 2G dev(deps)` (`K` the initial EoS bulk modulus) and the
/// (initialised) old history, and does not call the kernel.
#[inline(always)]
pub fn vumat_point<M: AbiModel>(
    material: &M,
    initial: &MaterialState,
    input: &VumatInput,
) -> Result<VumatPoint, UpdateError> {
    let VumatInput {
        dt,
        data_check,
        strain_increment,
        stress_old,
        state_old,
        energy_per_mass_old,
    } = input;
    let (strain_increment, stress_old) = (&strain_increment, &stress_old);
    if !*data_check {
        return vumat_step(
            material,
            initial,
            *dt,
            strain_increment,
            stress_old,
            state_old,
        );
    }
    let state = state_from_history(stress_old, state_old, initial)?;
    let bulk = initial_bulk_modulus(material.eos());
    let shear = material.shear_modulus();
    let volumetric = tensor::trace(strain_increment);
    let deviator = tensor::deviator(strain_increment);
    let stress: Sym = core::array::from_fn(|k| {
        let spherical = if k < 3 { bulk * volumetric } else { 0.0 };
        stress_old[k] + spherical + 2.0 * shear * deviator[k]
    });
    Ok(VumatPoint {
        stress,
        history: history_from_state(&state),
        internal_energy_per_mass: *energy_per_mass_old,
        output: None,
        state,
    })
}

/// The VUMAT step proper (not the data-check call): the kernel update from the old stress and
/// history, with the energy per unit mass.
#[inline(always)]
fn vumat_step<M: AbiModel>(
    material: &M,
    initial: &MaterialState,
    dt: f64,
    strain_increment: &Sym,
    stress_old: &Sym,
    state_old: &History,
) -> Result<VumatPoint, UpdateError> {
    let mut state = state_from_history(stress_old, state_old, initial)?;
    let output = step_point(material, &mut state, strain_increment, dt, None, None)?;
    Ok(vumat_result(material, state, output))
}

/// A VUMAT step's outputs from the kernel's new state and output.
#[inline(always)]
fn vumat_result<M: AbiModel>(material: &M, state: MaterialState, output: StepOutput) -> VumatPoint {
    VumatPoint {
        stress: state.stress,
        history: history_from_state(&state),
        internal_energy_per_mass: state.internal_energy / material.density(),
        output: Some(output),
        state,
    }
}

/// Column-major (Fortran) arrays of an LS-DYNA style call: `eps(nlq, 6)`, `sig(nlq, 6)`,
/// `hsv(nlq, nhv)`.
pub(crate) struct LsDynaArrays<'a> {
    pub nlq: usize,
    pub nhv: usize,
    pub eps: ArrayIn<'a, f64>,
    pub sig: ArrayOut<'a, f64>,
    pub hsv: ArrayOut<'a, f64>,
    pub failel: Option<ArrayOut<'a, i32>>,
    pub wave_speed: Option<ArrayOut<'a, f64>>,
    pub status: Option<ArrayOut<'a, i32>>,
}

pub(crate) fn run_lsdyna<M: AbiModel>(
    material: &M,
    initial: &MaterialState,
    dt: f64,
    arrays: &mut LsDynaArrays<'_>,
) -> Option<(usize, UpdateError)> {
    let nlq = arrays.nlq;
    let values = nlq * 6;
    let histories = nlq * STOSS_HISTORY_COUNT;
    // One check per call instead of one per access (as in `run_vumat`): the per-point
    // accesses below are unchecked.
    assert!(
        arrays.nhv >= STOSS_HISTORY_COUNT
            && arrays.eps.covers(values)
            && arrays.sig.covers(values)
            && arrays.hsv.covers(histories)
            && arrays.failel.as_ref().is_none_or(|a| a.covers(nlq))
            && arrays.wave_speed.as_ref().is_none_or(|a| a.covers(nlq))
            && arrays.status.as_ref().is_none_or(|a| a.covers(nlq)),
        "LS-DYNA arrays shorter than their nlq x 6 / nlq x {STOSS_HISTORY_COUNT}"
    );
    let mut first_failure = None;
    for i in 0..nlq {
        // SAFETY (every unchecked access in this loop): `i < nlq`, `k < 6` and
        // `j < STOSS_HISTORY_COUNT`, so `i + nlq k < values` and `i + nlq j < histories`,
        // which the arrays cover (asserted above).
        let eps: Sym = core::array::from_fn(|k| {
            // SAFETY: see the loop's comment.
            unsafe { arrays.eps.get_unchecked(i + nlq * k) }
        });
        let mut sig: Sym = core::array::from_fn(|k| {
            // SAFETY: see the loop's comment.
            unsafe { arrays.sig.get_unchecked(i + nlq * k) }
        });
        let mut hsv: History = core::array::from_fn(|j| {
            // SAFETY: see the loop's comment.
            unsafe { arrays.hsv.get_unchecked(i + nlq * j) }
        });
        let (status, failure) =
            match lsdyna_umat_point(material, initial, dt, &eps, &mut sig, &mut hsv) {
                Ok((output, state)) => {
                    // SAFETY: see the loop's comment.
                    unsafe {
                        for (k, value) in sig.iter().enumerate() {
                            arrays.sig.set_unchecked(i + nlq * k, *value);
                        }
                        for (j, value) in hsv.iter().enumerate() {
                            arrays.hsv.set_unchecked(i + nlq * j, *value);
                        }
                        if let Some(array) = &mut arrays.wave_speed {
                            array.set_unchecked(i, output.wave_speed);
                        }
                    }
                    (StossStatus::Ok, failure_code(&state))
                }
                Err(error) => {
                    first_failure.get_or_insert((i, error));
                    (StossStatus::from(error), 0)
                }
            };
        // SAFETY: see the loop's comment.
        unsafe {
            if status == StossStatus::Ok {
                if let Some(array) = &mut arrays.failel {
                    array.set_unchecked(i, failure);
                }
            }
            if let Some(array) = &mut arrays.status {
                array.set_unchecked(i, status as i32);
            }
        }
    }
    first_failure
}

/// Column-major (Fortran) arrays of a VUMAT call.
pub(crate) struct VumatArrays<'a> {
    pub nblock: usize,
    /// Shear components present: 3 (3D) or 1 (plane strain, axisymmetric: `12` only).
    pub nshr: usize,
    pub nstatev: usize,
    pub strain_inc: ArrayIn<'a, f64>,
    pub stress_old: ArrayIn<'a, f64>,
    pub state_old: ArrayIn<'a, f64>,
    pub ener_intern_old: ArrayIn<'a, f64>,
    pub stress_new: ArrayOut<'a, f64>,
    pub state_new: ArrayOut<'a, f64>,
    pub ener_intern_new: ArrayOut<'a, f64>,
    pub wave_speed: Option<ArrayOut<'a, f64>>,
    pub status: Option<ArrayOut<'a, i32>>,
}

pub(crate) fn run_vumat<M: AbiModel>(
    material: &M,
    initial: &MaterialState,
    dt: f64,
    data_check: bool,
    arrays: &mut VumatArrays<'_>,
) -> Option<(usize, UpdateError)> {
    let nblock = arrays.nblock;
    let components = 3 + arrays.nshr;
    let nstatev = arrays.nstatev;
    let values = nblock * components;
    let states = nblock * nstatev;
    // One check per call instead of one per access: the per-point accesses below are
    // unchecked. (A checked store reloads every array's length after each write through an
    // array that may alias it.)
    assert!(
        components <= 6
            && nstatev >= STOSS_HISTORY_COUNT
            && arrays.strain_inc.covers(values)
            && arrays.stress_old.covers(values)
            && arrays.stress_new.covers(values)
            && arrays.state_old.covers(states)
            && arrays.state_new.covers(states)
            && arrays.ener_intern_old.covers(nblock)
            && arrays.ener_intern_new.covers(nblock)
            && arrays.wave_speed.as_ref().is_none_or(|a| a.covers(nblock))
            && arrays.status.as_ref().is_none_or(|a| a.covers(nblock)),
        "VUMAT arrays shorter than their nblock x components / nstatev"
    );
    let mut first_failure = None;
    // One point's old stress and history and internal energy per unit mass.
    // SAFETY (every unchecked access in the closures and loops below): `i < nblock`,
    // `k < components` and `j < nstatev`, so `i + nblock k < values` and `i + nblock j <
    // states`, which the arrays cover (asserted above).
    let read = |array: &ArrayIn<'_, f64>, i: usize| -> Sym {
        core::array::from_fn(|k| {
            if k < components {
                // SAFETY: see above.
                unsafe { array.get_unchecked(i + nblock * k) }
            } else {
                0.0
            }
        })
    };
    let old = |arrays: &VumatArrays<'_>, i: usize| -> (Sym, Sym, History, f64) {
        let strain = read(&arrays.strain_inc, i);
        let stress_old = read(&arrays.stress_old, i);
        // SAFETY: see above.
        let state_old: History =
            core::array::from_fn(|j| unsafe { arrays.state_old.get_unchecked(i + nblock * j) });
        // SAFETY: see above.
        let energy_old = unsafe { arrays.ener_intern_old.get_unchecked(i) };
        (strain, stress_old, state_old, energy_old)
    };
    // A step (not the data check) advances its points LANES at a time through the model's
    // group update, bit for bit the one-point update; the rest one at a time.
    let grouped = if data_check {
        0
    } else {
        nblock - nblock % LANES
    };
    // One group's points, steps and results, every entry overwritten for each group.
    let zero_step = zero_step(dt);
    let mut points = [*initial; LANES];
    let mut inputs = [zero_step; LANES];
    let mut converted = [Ok(()); LANES];
    let mut results = [Err(UpdateError::NonFiniteInput); LANES];
    for first in (0..grouped).step_by(LANES) {
        for lane in 0..LANES {
            let (strain, stress_old, state_old, _) = old(arrays, first + lane);
            converted[lane] = match state_from_history(&stress_old, &state_old, initial) {
                Ok(state) => {
                    points[lane] = state;
                    inputs[lane] = step_input(&state, &strain, dt, None);
                    Ok(())
                }
                // The point is not updated; its lane runs a zero step from the initial state.
                Err(error) => {
                    points[lane] = *initial;
                    inputs[lane] = zero_step;
                    Err(error)
                }
            };
        }
        material.update_lanes(&mut points, &inputs, &mut results);
        for lane in 0..LANES {
            let result = converted[lane]
                .and(results[lane])
                .map(|output| vumat_result(material, points[lane], output));
            store_vumat(material, arrays, first + lane, result, &mut first_failure);
        }
    }
    for i in grouped..nblock {
        let (strain, stress_old, state_old, energy_old) = old(arrays, i);
        let result = if data_check {
            let input = VumatInput {
                dt,
                data_check,
                strain_increment: strain,
                stress_old,
                state_old,
                energy_per_mass_old: energy_old,
            };
            vumat_point(material, initial, &input)
        } else {
            vumat_step(material, initial, dt, &strain, &stress_old, &state_old)
        };
        store_vumat(material, arrays, i, result, &mut first_failure);
    }
    first_failure
}

/// Writes VUMAT point `i`'s step: its new stress, history (the host's extra state variables
/// carried over) and energy, its wave speed and status; a failed point keeps its old values,
/// and the first failure is kept. Requires `i < nblock` of arrays `run_vumat` checked.
#[inline(always)]
fn store_vumat<M: AbiModel>(
    material: &M,
    arrays: &mut VumatArrays<'_>,
    i: usize,
    result: Result<VumatPoint, UpdateError>,
    first_failure: &mut Option<(usize, UpdateError)>,
) {
    let (nblock, components, nstatev) = (arrays.nblock, 3 + arrays.nshr, arrays.nstatev);
    // Extra state variables (the host's own) are carried over unchanged.
    for j in STOSS_HISTORY_COUNT..nstatev {
        // SAFETY: `i < nblock`, `j < nstatev`: covered (`run_vumat`).
        unsafe {
            let value = arrays.state_old.get_unchecked(i + nblock * j);
            arrays.state_new.set_unchecked(i + nblock * j, value);
        }
    }
    let (stress, history, energy, wave_speed, status) = match result {
        Ok(point) => {
            let wave_speed = match point.output {
                Some(output) => output.wave_speed,
                None => elastic_wave_speed(material),
            };
            (
                point.stress,
                point.history,
                point.internal_energy_per_mass,
                wave_speed,
                StossStatus::Ok,
            )
        }
        Err(error) => {
            // The point keeps its old state: new = old.
            first_failure.get_or_insert((i, error));
            // SAFETY: `i < nblock`, `k < components`, `j < STOSS_HISTORY_COUNT <= nstatev`:
            // covered (`run_vumat`).
            let (stress_old, state_old, energy_old) = unsafe {
                (
                    core::array::from_fn(|k| {
                        if k < components {
                            arrays.stress_old.get_unchecked(i + nblock * k)
                        } else {
                            0.0
                        }
                    }),
                    core::array::from_fn(|j| arrays.state_old.get_unchecked(i + nblock * j)),
                    arrays.ener_intern_old.get_unchecked(i),
                )
            };
            (
                stress_old,
                state_old,
                energy_old,
                0.0,
                StossStatus::from(error),
            )
        }
    };
    // SAFETY: `i < nblock`, `k < components`, `j < STOSS_HISTORY_COUNT <= nstatev`: covered
    // (`run_vumat`).
    unsafe {
        for (k, value) in stress.iter().enumerate().take(components) {
            arrays.stress_new.set_unchecked(i + nblock * k, *value);
        }
        for (j, value) in history.iter().enumerate() {
            arrays.state_new.set_unchecked(i + nblock * j, *value);
        }
        arrays.ener_intern_new.set_unchecked(i, energy);
        if status == StossStatus::Ok {
            if let Some(array) = &mut arrays.wave_speed {
                array.set_unchecked(i, wave_speed);
            }
        }
        if let Some(array) = &mut arrays.status {
            array.set_unchecked(i, status as i32);
        }
    }
}

/// Elastic longitudinal wave speed at the reference state, `sqrt((K + 4G/3)/rho0)`.
pub fn elastic_wave_speed<M: AbiModel>(material: &M) -> f64 {
    let modulus = initial_bulk_modulus(material.eos()) + 4.0 * material.shear_modulus() / 3.0;
    stoss_kernel::math::sqrt(modulus / material.density())
}

#[cfg(test)]
mod tests {
    use super::*;
    use stoss_kernel::drivers::UniaxialStrainLoading;
    use stoss_kernel::drivers::{simple_shear, uniaxial_strain, LastRecord, SimpleShearLoading};
    use stoss_kernel::Material;

    fn jc_failure() -> Material {
        let mut material = Material::STEEL_4340;
        material.failure.johnson_cook = Some(stoss_kernel::damage::JohnsonCookFailure::STEEL_4340);
        material
    }

    #[test]
    fn umat_point_reproduces_the_simple_shear_driver_bit_for_bit() {
        let material = jc_failure();
        let initial = MaterialState::initial(298.0);
        let loading = SimpleShearLoading {
            shear_rate: 1000.0,
            final_shear_strain: 0.3,
            steps: 400,
        };
        let mut reference = initial;
        let mut sink = LastRecord::default();
        simple_shear(&material, &mut reference, &loading, &mut sink).unwrap();

        let increment = loading.final_shear_strain / f64::from(loading.steps);
        let dt = increment.abs() / loading.shear_rate;
        let mut sig = [0.0; 6];
        let mut hsv = [0.0; STOSS_HISTORY_COUNT];
        let mut last = None;
        for _ in 0..loading.steps {
            let eps = [0.0, 0.0, 0.0, 2.0 * increment, 0.0, 0.0];
            last =
                Some(lsdyna_umat_point(&material, &initial, dt, &eps, &mut sig, &mut hsv).unwrap());
        }
        let (_, state) = last.unwrap();
        assert_eq!(state, reference);
        assert_eq!(sig, reference.stress);
        assert_eq!(hsv, history_from_state(&reference));
    }

    #[test]
    fn vumat_point_reproduces_the_uniaxial_strain_driver_and_converts_energy() {
        let material = Material::STEEL_4340;
        let initial = MaterialState::initial(298.0);
        let loading = UniaxialStrainLoading {
            strain_rate: 1.0e4,
            final_strain: -0.05,
            steps: 250,
        };
        let mut reference = initial;
        let mut sink = LastRecord::default();
        uniaxial_strain(&material, &mut reference, &loading, &mut sink).unwrap();

        let increment = loading.final_strain / f64::from(loading.steps);
        let dt = increment.abs() / loading.strain_rate;
        let strain = [increment, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut stress = [0.0; 6];
        let mut history = [0.0; STOSS_HISTORY_COUNT];
        let mut energy = 0.0;
        // The data-check call first: elastic, nothing committed.
        let mut input = VumatInput {
            dt: 0.0,
            data_check: true,
            strain_increment: strain,
            stress_old: stress,
            state_old: history,
            energy_per_mass_old: 0.0,
        };
        let check = vumat_point(&material, &initial, &input).unwrap();
        let lambda_2g = 159.0e9 + 4.0 / 3.0 * 81.8e9;
        assert!(
            (check.stress[0] - lambda_2g * increment).abs() < 1e-6 * lambda_2g * increment.abs()
        );
        for _ in 0..loading.steps {
            input = VumatInput {
                dt,
                data_check: false,
                strain_increment: strain,
                stress_old: stress,
                state_old: history,
                energy_per_mass_old: energy,
            };
            let point = vumat_point(&material, &initial, &input).unwrap();
            stress = point.stress;
            history = point.history;
            energy = point.internal_energy_per_mass;
        }
        assert_eq!(stress, reference.stress);
        assert_eq!(history, history_from_state(&reference));
        assert_eq!(energy, reference.internal_energy / material.density);
        assert!(energy > 0.0);
    }

    #[test]
    fn bad_history_flags_are_an_invalid_state() {
        let initial = MaterialState::initial(298.0);
        let mut history = history_from_state(&initial);
        history[STOSS_HISTORY_FLAGS] = 0.5;
        assert_eq!(
            state_from_history(&[0.0; 6], &history, &initial),
            Err(UpdateError::NonFiniteState)
        );
        history[STOSS_HISTORY_FLAGS] = f64::NAN;
        assert_eq!(
            state_from_history(&[0.0; 6], &history, &initial),
            Err(UpdateError::NonFiniteState)
        );
    }
}
