//! K&C concrete rows of `stoss verify` (seed 001 chapter 5, [`KcMaterial::HPC_100MPA_FOI`]
//! without rate enhancement): the single-element tests FOI fitted the model to, through the
//! kernel drivers, against the seed's numbers and the model's own closed forms.
//!
//! - uniaxial compression and tension peaks: `fc` = 100 MPa and `ft` = 5.2 MPa (table 5.1);
//! - fracture energy in uniaxial tension with the crack band for 5, 10.6 and 20 mm elements:
//!   `Gf` = 156 N/m (table 5.1) whatever the size;
//! - softening in uniaxial tension: `sigma = eta(lambda) ft` (the tensile surface scaled by
//!   `eta`), checked at every softening record;
//! - hydrostatic compression: table 5.2's pressures.

use super::checks::{relative, CheckResult, Expectation};
use crate::history::History;
use stoss_kernel::drivers::{
    hydrostatic, uniaxial_stress, DriverError, HydrostaticLoading, Record, UniaxialStressLoading,
};
use stoss_kernel::kc::{KcMaterial, KcParameters, RateEnhancement};

const SUBJECT: &str = "kc-hpc-100";
const FC: f64 = 100.0e6;
const FT: f64 = 5.2e6;
const FRACTURE_ENERGY: f64 = 156.0;
/// Crack-band widths (element sizes) of the fracture-energy rows (m).
pub const CRACK_BAND_WIDTHS: [f64; 3] = [5.0e-3, 10.6e-3, 20.0e-3];

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

fn quasi_static(parameters: KcParameters) -> KcMaterial {
    KcMaterial {
        parameters: KcParameters {
            rate: RateEnhancement::None,
            ..parameters
        },
        ..KcMaterial::HPC_100MPA_FOI
    }
}

/// Uniaxial stress to `final_strain` in `steps` steps at 1e-6 /s. A fully softened element
/// carries almost no uniaxial stress and the driver's lateral iteration then stops: the
/// records up to there are kept when the stress is below 1 % of `ft`.
fn uniaxial(material: &KcMaterial, final_strain: f64, steps: u32) -> Option<Vec<Record>> {
    let mut state = material.initial_state(293.0);
    let mut history = History::default();
    let result = uniaxial_stress(
        material,
        &mut state,
        &UniaxialStressLoading {
            strain_rate: 1.0e-6,
            final_strain,
            steps,
        },
        &mut history,
    );
    match result {
        Ok(()) => Some(history.0),
        Err(DriverError::LateralIterationDiverged)
            if history.0.last()?.stress[0].abs() < 0.01 * FT =>
        {
            Some(history.0)
        }
        Err(_) => None,
    }
}

fn peak(records: &[Record]) -> (usize, f64) {
    records
        .iter()
        .map(|r| r.stress[0].abs())
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (i, s)| if s > best.1 { (i, s) } else { best },
        )
}

/// Energy per unit volume dissipated after the peak: the work after it plus the elastic
/// energy stored at it.
fn softening_dissipation(records: &[Record]) -> f64 {
    let modulus = records[0].stress[0] / records[0].strain[0];
    let (index, top) = peak(records);
    let work: f64 = records[index..]
        .windows(2)
        .map(|w| 0.5 * (w[0].stress[0] + w[1].stress[0]) * (w[1].strain[0] - w[0].strain[0]))
        .sum();
    let last = records.last().map_or(0.0, |r| r.stress[0]);
    work + (top * top - last * last) / (2.0 * modulus)
}

/// Every row.
pub fn run_all() -> Vec<CheckResult> {
    let plain = quasi_static(KcParameters::HPC_100MPA_FOI);
    let mut rows = Vec::new();
    let compression = uniaxial(&plain, -0.01, 4000);
    rows.push(row(
        "uniaxial stress: compressive peak".into(),
        "peak |sigma_xx| vs fc = 100 MPa (seed table 5.1)",
        compression.map_or(f64::INFINITY, |r| relative(peak(&r).1, FC)),
        5e-3,
    ));
    let tension = uniaxial(&plain, 0.03, 12000);
    rows.push(row(
        "uniaxial stress: tensile peak".into(),
        "peak sigma_xx vs ft = 5.2 MPa (seed table 5.1)",
        tension
            .as_ref()
            .map_or(f64::INFINITY, |r| relative(peak(r).1, FT)),
        5e-3,
    ));
    let table = plain.parameters.damage;
    let softening = tension.as_ref().map_or(f64::INFINITY, |records| {
        let (index, _) = peak(records);
        records[index + 1..]
            .iter()
            .map(|r| (r.stress[0] - table.eta_at(r.plastic_strain) * FT).abs() / FT)
            .fold(0.0, f64::max)
    });
    rows.push(row(
        "uniaxial tension: softening".into(),
        "|sigma_xx - eta(lambda) ft| / ft after the peak",
        softening,
        1e-12,
    ));
    for width in CRACK_BAND_WIDTHS {
        let material =
            quasi_static(KcParameters::HPC_100MPA_FOI.with_fracture_energy(FRACTURE_ENERGY, width));
        let released = uniaxial(&material, 0.06, 20000)
            .map_or(f64::INFINITY, |r| width * softening_dissipation(&r));
        rows.push(row(
            format!("uniaxial tension: crack band h = {} mm", width * 1e3),
            "h x softening dissipation vs Gf = 156 N/m (seed table 5.1)",
            relative(released, FRACTURE_ENERGY),
            0.02,
        ));
    }
    let mut state = plain.initial_state(293.0);
    let mut history = History::default();
    let hydro = hydrostatic(
        &plain,
        &mut state,
        &HydrostaticLoading {
            peak_compression: 0.07,
            strain_rate: 1.0,
            loading_steps: 7000,
            unloading_steps: 100,
        },
        &mut history,
    );
    let points = [
        (0.0104, 90.0e6),
        (0.0289, 216.0e6),
        (0.0510, 390.0e6),
        (0.0628, 565.0e6),
    ];
    let error = hydro.ok().map_or(f64::INFINITY, |()| {
        points
            .iter()
            .map(|&(strain, pressure)| {
                history
                    .0
                    .iter()
                    .find(|r| (-(r.strain[0] + r.strain[1] + r.strain[2]) - strain).abs() < 5e-6)
                    .map_or(f64::INFINITY, |r| relative(r.pressure, pressure))
            })
            .fold(0.0, f64::max)
    });
    rows.push(row(
        "hydrostatic compression".into(),
        "pressure vs seed table 5.2 at its volumetric strains",
        error,
        2e-3,
    ));
    rows
}
