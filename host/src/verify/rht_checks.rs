//! RHT concrete rows of `stoss verify` (seed 001 chapter 4, table 4.4 HPC,
//! [`RhtMaterial::HPC_92MPA`]): the single-element tests of seed section 4.3.2 through the
//! kernel drivers, each against the model's equations evaluated directly.
//!
//! - uniaxial compression and tension peaks: `fc` and `ft = FT* fc` (quasi-static);
//! - dynamic increase of the compressive peak at 1, 10, 100, 1000 /s against the root of
//!   eq. 4.1 written out here (`z = F A (z/3 - p*_0 F)^N` on the compressive meridian,
//!   `F = (rate/rate0)^alpha`, eq. 4.4), which is larger than `F` itself ("with pressure
//!   effects included", seed fig. 4.12);
//! - uniaxial strain: stress difference against the kernel's surfaces evaluated directly;
//! - the Lode factor `R3` on the meridians (eqs. 4.2-4.3);
//! - hydrostatic loading and unloading against the P-alpha equations written out in
//!   [`super::eos_checks::PAlphaReference`].
//!
//! Peaks are located by stepping the uniaxial-stress driver with strain steps of 2e-5 and
//! refining around the largest sample three times by 20 (final step 2.5e-9): the error of a
//! sampled maximum is at most the slope of the curve times the final step.

use super::checks::{max_or_infinite, relative, CheckResult, Expectation};
use super::eos_checks::{compare_with_p_alpha, drive_hydrostatic, hpc_p_alpha, PAlphaReference};
use crate::history::History;
use std::sync::OnceLock;
use stoss_kernel::drivers::{
    uniaxial_strain, uniaxial_stress, Record, UniaxialStrainLoading, UniaxialStressLoading,
};
use stoss_kernel::rht::{Lode, RateScaling, RhtMaterial, RhtParameters};
use stoss_kernel::{MaterialState, StateFlags};

/// Temperature of the runs (K); RHT does not depend on it.
const TEMPERATURE: f64 = 293.0;

/// First strain step of a peak search.
const COARSE_STEP: f64 = 2.0e-5;
/// Step reduction per refinement.
const REFINEMENT: u32 = 20;
/// Refinement stops once the step is at most this.
const FINEST_STEP: f64 = 3.0e-9;

/// Rates of the dynamic-increase rows (1/s).
pub const DIF_RATES: [f64; 4] = [1.0, 10.0, 100.0, 1000.0];
/// Quasi-static rate (1/s): below both reference rates of eq. 4.4 (3e-6 and 30e-6 /s).
pub const QUASI_STATIC_RATE: f64 = 1.0e-6;

const SUBJECT: &str = "rht-hpc-92";

fn row(check: String, quantity: &'static str, max_error: f64, tolerance: f64) -> CheckResult {
    CheckResult {
        subject: SUBJECT.into(),
        check,
        quantity,
        max_error,
        tolerance,
        expectation: Expectation::AtMost,
    }
}

/// `steps` uniaxial-stress steps of `step` strain (sign `sign`) at `rate` from `state`.
fn uniaxial(
    material: &RhtMaterial,
    state: &mut MaterialState,
    rate: f64,
    sign: f64,
    step: f64,
    steps: u32,
) -> Option<Vec<Record>> {
    let mut history = History::default();
    uniaxial_stress(
        material,
        state,
        &UniaxialStressLoading {
            strain_rate: rate,
            final_strain: sign * step * f64::from(steps),
            steps,
        },
        &mut history,
    )
    .ok()?;
    Some(history.0)
}

/// The record of largest `sign * sigma_xx` in uniaxial stress at `rate`, searched up to an
/// axial strain `limit`: coarse steps, then repeated refinement from the record before the
/// largest sample over three of the previous steps. `None` if the driver fails or the peak
/// is not bracketed.
pub fn uniaxial_peak(material: &RhtMaterial, rate: f64, sign: f64, limit: f64) -> Option<Record> {
    let mut start = material.initial_state(TEMPERATURE);
    let mut step = COARSE_STEP;
    let mut steps = (limit / COARSE_STEP).round() as u32;
    loop {
        let mut state = start;
        let records = uniaxial(material, &mut state, rate, sign, step, steps)?;
        let k = (0..records.len()).max_by(|&a, &b| {
            (sign * records[a].stress[0]).total_cmp(&(sign * records[b].stress[0]))
        })?;
        if k + 1 >= records.len() {
            return None;
        }
        if step <= FINEST_STEP {
            return Some(records[k]);
        }
        // The peak lies between records k - 1 and k + 1: restart from record k - 1 (k steps
        // from `start`).
        if k > 0 {
            uniaxial(material, &mut start, rate, sign, step, k as u32)?;
        }
        step /= f64::from(REFINEMENT);
        steps = 3 * REFINEMENT;
    }
}

/// Compressive rate factor of eq. 4.4, `F = (rate/rate0)^alpha`, 1 below `rate0`.
fn compressive_rate_factor(params: &RhtParameters, rate: f64) -> f64 {
    let ratio = rate / params.compressive_reference_rate;
    if ratio > 1.0 {
        ratio.powf(params.compressive_rate_exponent)
    } else {
        1.0
    }
}

/// Uniaxial compressive strength over `fc` at rate factor `F`, from eq. 4.1 as printed with
/// eq. 4.5 (seed rate scaling): on the compressive meridian (`R3 = 1`) at `p* = z/3`,
/// `z = F A (z/3 - p*_0 F)^N` with `p*_0 = 1/3 - A^(-1/N)` (so that `z = 1` at `F = 1`).
/// Bisection on `[F, 10 F]`, where the residual changes sign.
pub fn eq_4_1_uniaxial_strength(params: &RhtParameters, rate_factor: f64) -> f64 {
    let (a, n, f) = (params.failure_a, params.failure_n, rate_factor);
    let intercept = 1.0 / 3.0 - a.powf(-1.0 / n);
    let residual = |z: f64| f * a * (z / 3.0 - intercept * f).powf(n) - z;
    let (mut lo, mut hi) = (f, 10.0 * f);
    if !(residual(lo) >= 0.0 && residual(hi) < 0.0) {
        return f64::NAN;
    }
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            return lo;
        }
        if residual(mid) >= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

/// One rate of the compressive dynamic-increase comparison.
#[derive(Clone, Copy, Debug)]
pub struct DifRow {
    /// Axial strain rate (1/s).
    pub rate: f64,
    /// `F = (rate/rate0)^alpha` (eq. 4.4).
    pub rate_factor: f64,
    /// Root of eq. 4.1 on the uniaxial path, `z` (the expected DIF).
    pub surface: f64,
    /// Peak compressive stress over `fc` from the driver (NaN if the search failed).
    pub measured: f64,
}

/// The quasi-static row and the [`DIF_RATES`] rows, computed once per process.
pub fn dif_table() -> &'static [DifRow] {
    static TABLE: OnceLock<Vec<DifRow>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let material = RhtMaterial::HPC_92MPA;
        let params = material.parameters;
        std::iter::once(QUASI_STATIC_RATE)
            .chain(DIF_RATES)
            .map(|rate| {
                let rate_factor = compressive_rate_factor(&params, rate);
                let measured = uniaxial_peak(&material, rate, -1.0, 0.008)
                    .map_or(f64::NAN, |r| -r.stress[0] / params.compressive_strength);
                DifRow {
                    rate,
                    rate_factor,
                    surface: eq_4_1_uniaxial_strength(&params, rate_factor),
                    measured,
                }
            })
            .collect()
    })
}

fn peaks() -> Vec<CheckResult> {
    let material = RhtMaterial::HPC_92MPA;
    let params = material.parameters;
    let seed_scaling = params.rate_scaling == RateScaling::SeedEquation;
    let mut rows = Vec::new();
    for (i, dif) in dif_table().iter().enumerate() {
        let error = if seed_scaling {
            relative(dif.measured, dif.surface)
        } else {
            f64::INFINITY
        };
        if i == 0 {
            // Quasi-static: F = 1, the reference is fc itself.
            rows.push(row(
                format!("uniaxial compression {QUASI_STATIC_RATE:e}/s"),
                "peak -sigma_xx vs fc = 92 MPa, rel.",
                relative(dif.measured, 1.0).max(relative(dif.surface, 1.0)),
                1e-5,
            ));
        } else {
            rows.push(row(
                format!("uniaxial compression {}/s, DIF", dif.rate),
                "peak/fc vs eq.4.1 root z(F), F=(rate/rate0)^alpha",
                error,
                1e-5,
            ));
        }
    }
    let ft = params.tensile_strength_ratio * params.compressive_strength;
    let tension = uniaxial_peak(&material, QUASI_STATIC_RATE, 1.0, 0.0008)
        .map_or(f64::INFINITY, |r| relative(r.stress[0], ft));
    rows.push(row(
        format!("uniaxial tension {QUASI_STATIC_RATE:e}/s"),
        "peak sigma_xx vs ft = FT* fc = 5.244 MPa, rel.",
        tension,
        1e-5,
    ));
    rows
}

/// Uniaxial strain compression to 5 % at 1 /s without rate enhancement (alpha = delta = 0,
/// seed figs. 4.14-4.15): on every plastic step the stress difference equals the current
/// strength from the surfaces evaluated directly at the recorded pressure, plastic strain
/// and damage (hardening from the capped elastic surface, then damage softening).
fn uniaxial_strain_surfaces() -> CheckResult {
    let mut material = RhtMaterial::HPC_92MPA;
    material.parameters.compressive_rate_exponent = 0.0;
    material.parameters.tensile_rate_exponent = 0.0;
    let params = material.parameters;
    let fc = params.compressive_strength;
    let mut state = material.initial_state(TEMPERATURE);
    let mut history = History::default();
    let ran = uniaxial_strain(
        &material,
        &mut state,
        &UniaxialStrainLoading {
            strain_rate: 1.0,
            final_strain: -0.05,
            steps: 5000,
        },
        &mut history,
    );
    let plastic: Vec<&Record> = history
        .0
        .iter()
        .filter(|r| r.flags & StateFlags::PLASTIC != 0)
        .collect();
    let damaged = plastic.iter().any(|r| r.damage > 0.0);
    let error = if ran.is_ok() && damaged {
        max_or_infinite(plastic.iter().map(|r| {
            let strength = params
                .surfaces(
                    r.pressure,
                    Lode::COMPRESSIVE_MERIDIAN,
                    1.0,
                    material.cap_pressure(),
                )
                .current(r.plastic_strain, r.damage);
            let difference = r.stress[1] - r.stress[0];
            (difference - strength).abs() / fc
        }))
    } else {
        f64::INFINITY
    };
    row(
        "uniaxial strain 1/s to 5 %, F = 1".into(),
        "sigma_yy - sigma_xx vs Y(p, eps_p, D), / fc",
        error,
        // The return is made at the pressure predictor; the recorded pressure also holds the
        // energy term of the step's deviatoric work.
        2e-5,
    )
}

/// Eqs. 4.2-4.3: `R3 = 1` on the compressive meridian, `R3 = Q2 = Q2,0 + BQ p*` (clamped to
/// [0.5, 1]) on the tensile meridian, for `p*` from -30 to 40.
fn lode_factor() -> [CheckResult; 2] {
    let params = RhtParameters::HPC_92MPA;
    let fc = params.compressive_strength;
    let pressures = [-30.0, -1.0, -0.05, 0.0, 1.0 / 3.0, 1.0, 2.0, 10.0, 40.0];
    let compressive = max_or_infinite(
        pressures
            .iter()
            .map(|p| (params.lode_factor(Lode::COMPRESSIVE_MERIDIAN, p * fc) - 1.0).abs()),
    );
    let tensile = max_or_infinite(pressures.iter().map(|p| {
        let q2 =
            (params.tensile_meridian_ratio + params.brittle_ductile_transition * p).clamp(0.5, 1.0);
        (params.lode_factor(Lode::TENSILE_MERIDIAN, p * fc) - q2).abs()
    }));
    [
        row(
            "R3 on the compressive meridian".into(),
            "R3(theta = pi/3) vs 1, p* -30..40, abs.",
            compressive,
            1e-15,
        ),
        row(
            "R3 on the tensile meridian".into(),
            "R3(theta = 0) vs Q2,0 + BQ p* in [0.5,1], abs.",
            tensile,
            1e-15,
        ),
    ]
}

/// Hydrostatic loading to 6 % volumetric strain and unloading to V0 (10 /s, 3000 + 3000
/// steps): pressure and energy against the P-alpha equations written out in the host, up to
/// the hydro tensile limit on unloading (where the point fails and the pressure is held).
fn hydrostatic_p_alpha() -> [CheckResult; 2] {
    let material = RhtMaterial::HPC_92MPA;
    let compared = hpc_p_alpha().and_then(|eos| {
        let records = drive_hydrostatic(
            &material,
            material.initial_state(TEMPERATURE),
            0.06,
            3000,
            3000,
        );
        // The unloading must reach the hydro tensile limit (failure) after the loading.
        let failed = records
            .iter()
            .position(|r| r.flags & StateFlags::FAILED != 0)
            .is_some_and(|k| k >= 3000);
        let held = records
            .iter()
            .skip_while(|r| r.flags & StateFlags::FAILED == 0)
            .all(|r| r.pressure >= 0.0);
        if failed && held {
            compare_with_p_alpha(&PAlphaReference::new(&eos), &records)
        } else {
            None
        }
    });
    let (pressure, energy) = compared.unwrap_or((f64::INFINITY, f64::INFINITY));
    [
        row(
            "hydrostatic 6 % and back, 10/s".into(),
            "p vs P-alpha (host) to tensile limit, / p_peak",
            pressure,
            1e-9,
        ),
        row(
            "hydrostatic 6 % and back, 10/s".into(),
            "E vs -int p dV (host), / E_peak",
            energy,
            1e-9,
        ),
    ]
}

/// Every RHT row, in table order.
pub fn run_all() -> Vec<CheckResult> {
    let mut rows = peaks();
    rows.push(uniaxial_strain_surfaces());
    rows.extend(lode_factor());
    rows.extend(hydrostatic_p_alpha());
    rows
}
