//! Material cards to paste into other codes, from a calibrated material file. Units are SI
//! (kg, m, s, Pa, K): set the host model's unit system accordingly.
//!
//! - Johnson-Cook: LS-DYNA `*MAT_JOHNSON_COOK` (*MAT_015) with `*EOS_LINEAR_POLYNOMIAL`
//!   (C1 = K) or `*EOS_GRUNEISEN`; Abaqus `*PLASTIC, HARDENING=JOHNSON COOK` with
//!   `*RATE DEPENDENT, TYPE=JOHNSON COOK`; OpenRadioss `/MAT/PLAS_JOHNS` (law 2).
//! - Zerilli-Armstrong: LS-DYNA `*MAT_ZERILLI-ARMSTRONG` (*MAT_065; BCC/FCC by its `MIX`
//!   flag, rate reference EPSO).
//! - MJC, TJC and composed models have no exact equivalent card: the stoss material TOML is
//!   written (usable through the stoss C ABI user material), and the note says so.

use crate::input::material::{MaterialFile, StrengthSpec};
use std::fmt::Write as _;
use stoss_kernel::eos::Eos;
use stoss_kernel::strength::CrystalStructure;

/// Young's modulus and Poisson's ratio from the bulk and shear moduli.
fn young_and_poisson(bulk: f64, shear: f64) -> (f64, f64) {
    (
        9.0 * bulk * shear / (3.0 * bulk + shear),
        (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear)),
    )
}

/// The bulk modulus of the material's EoS at the reference state.
fn bulk_modulus(file: &MaterialFile) -> Option<f64> {
    match file.eos {
        Eos::Linear(e) => Some(e.bulk_modulus),
        Eos::MieGruneisen(e) => Some(e.reference_density * e.sound_speed * e.sound_speed),
        Eos::Polynomial(e) => Some(e.a1),
        _ => None,
    }
}

/// A fixed-width LS-DYNA card line of 10-character fields.
fn dyna_line(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{:>10}", format_short(*v)))
        .collect()
}

/// A number in at most 9 characters, so that a 10-column field always keeps a separating
/// blank.
fn format_short(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 9 {
        return plain;
    }
    for digits in (0..=5).rev() {
        let text = format!("{v:.digits$e}");
        if text.len() <= 9 {
            return text;
        }
    }
    format!("{v:.0e}")
}

/// LS-DYNA keyword cards (`None` if the family has no LS-DYNA equivalent).
pub fn ls_dyna(file: &MaterialFile) -> Option<String> {
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let mut text = format!(
        "$ stoss calibrated material: {}\n$ units: kg, m, s, Pa, K\n",
        file.name
    );
    match file.strength {
        StrengthSpec::JohnsonCook(jc) => {
            let (d1, d2, d3, d4, d5) = file
                .failure
                .and_then(|f| f.johnson_cook)
                .map_or((0.0, 0.0, 0.0, 0.0, 0.0), |f| {
                    (f.d1, f.d2, f.d3, f.d4, f.d5)
                });
            let _ = writeln!(text, "*MAT_JOHNSON_COOK\n$      MID        RO         G         E        PR       DTF        VP    RATEOP");
            let _ = writeln!(
                text,
                "{}",
                dyna_line(&[
                    1.0,
                    file.density,
                    file.shear_modulus,
                    young,
                    poisson,
                    0.0,
                    1.0,
                    0.0
                ])
            );
            let _ = writeln!(
                text,
                "$        A         B         N         C         M        TM        TR      EPSO"
            );
            let _ = writeln!(
                text,
                "{}",
                dyna_line(&[
                    jc.yield_stress,
                    jc.hardening_modulus,
                    jc.hardening_exponent,
                    jc.rate_sensitivity,
                    jc.thermal_exponent,
                    jc.melting_temperature,
                    jc.reference_temperature,
                    jc.reference_rate
                ])
            );
            let _ = writeln!(
                text,
                "$       CP        PC     SPALL        IT        D1        D2        D3        D4"
            );
            let _ = writeln!(
                text,
                "{}",
                dyna_line(&[file.specific_heat, -1.0e20, 2.0, 0.0, d1, d2, d3, d4])
            );
            let _ = writeln!(
                text,
                "$       D5      C2/P      EROD     EFMIN    NUMINT\n{}",
                dyna_line(&[d5, 0.0, 0.0, 0.0, 0.0])
            );
        }
        StrengthSpec::ZerilliArmstrong(za) => {
            let mix = match za.structure {
                CrystalStructure::Fcc => 1.0,
                CrystalStructure::Bcc => 2.0,
            };
            let _ = writeln!(text, "$ ZA: sigma = C1 + [C2 eps^0.5 (FCC)] exp(-C3 T + C4 T ln e*) + C5 eps^N; stoss C1 -> athermal stress");
            let _ = writeln!(text, "*MAT_ZERILLI-ARMSTRONG\n$      MID        RO         G      E0        N     TROOM     PC      SPALL");
            let _ = writeln!(
                text,
                "{}",
                dyna_line(&[
                    1.0,
                    file.density,
                    file.shear_modulus,
                    za.reference_rate,
                    za.exponent,
                    298.0,
                    -1.0e20,
                    2.0
                ])
            );
            let thermal = if mix == 1.0 { za.c2 } else { za.c1 };
            let _ = writeln!(
                text,
                "$       C1        C2        C3        C4        C5        C6     EFAIL    NUMINT"
            );
            let _ = writeln!(
                text,
                "{}",
                dyna_line(&[
                    za.athermal_stress,
                    thermal,
                    za.c3,
                    za.c4,
                    za.c5,
                    0.0,
                    1.0e20,
                    0.0
                ])
            );
            let _ = writeln!(text, "$     LCMU       MIX\n{}", dyna_line(&[0.0, mix]));
        }
        _ => return None,
    }
    match file.eos {
        Eos::MieGruneisen(g) => {
            let _ = writeln!(text, "*EOS_GRUNEISEN\n$    EOSID         C        S1        S2        S3    GAMAO         A        E0");
            let _ = writeln!(
                text,
                "{}\n$       V0\n{}",
                dyna_line(&[
                    1.0,
                    g.sound_speed,
                    g.s1,
                    g.s2,
                    g.s3,
                    g.gamma0,
                    g.volume_correction,
                    0.0
                ]),
                dyna_line(&[1.0])
            );
        }
        _ => {
            let _ = writeln!(text, "*EOS_LINEAR_POLYNOMIAL\n$    EOSID        C0        C1        C2        C3        C4        C5        C6");
            let _ = writeln!(
                text,
                "{}\n$       E0        V0\n{}",
                dyna_line(&[1.0, 0.0, bulk, 0.0, 0.0, 0.0, 0.0, 0.0]),
                dyna_line(&[0.0, 1.0])
            );
        }
    }
    Some(text)
}

/// Abaqus input lines for Johnson-Cook (`None` for other families).
pub fn abaqus(file: &MaterialFile) -> Option<String> {
    let StrengthSpec::JohnsonCook(jc) = file.strength else {
        return None;
    };
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let chi = match file.heating {
        stoss_kernel::Heating::Adiabatic { taylor_quinney } => Some(taylor_quinney),
        _ => None,
    };
    let mut text = format!("** stoss calibrated material: {}\n** units: kg, m, s, Pa, K\n*MATERIAL, NAME=STOSS\n*DENSITY\n{:e}\n*ELASTIC\n{:e}, {:e}\n", file.name, file.density, young, poisson);
    let _ = writeln!(
        text,
        "*PLASTIC, HARDENING=JOHNSON COOK\n{:e}, {:e}, {:e}, {:e}, {:e}, {:e}",
        jc.yield_stress,
        jc.hardening_modulus,
        jc.hardening_exponent,
        jc.thermal_exponent,
        jc.melting_temperature,
        jc.reference_temperature
    );
    let _ = writeln!(
        text,
        "*RATE DEPENDENT, TYPE=JOHNSON COOK\n{:e}, {:e}",
        jc.rate_sensitivity, jc.reference_rate
    );
    if let Some(chi) = chi {
        let _ = writeln!(
            text,
            "*SPECIFIC HEAT\n{:e}\n*INELASTIC HEAT FRACTION\n{chi}",
            file.specific_heat
        );
    }
    Some(text)
}

/// OpenRadioss `/MAT/PLAS_JOHNS` (law 2, Johnson-Cook) (`None` for other families).
pub fn open_radioss(file: &MaterialFile) -> Option<String> {
    let StrengthSpec::JohnsonCook(jc) = file.strength else {
        return None;
    };
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let rho_cp = file.density * file.specific_heat;
    let mut text = format!(
        "# stoss calibrated material: {}\n# units: kg, m, s, Pa, K\n/MAT/PLAS_JOHNS/1\nstoss\n",
        file.name
    );
    let _ = writeln!(text, "#              RHO_I\n{:>20e}", file.density);
    let _ = writeln!(
        text,
        "#                  E                  NU\n{young:>20e}{poisson:>20e}"
    );
    let _ = writeln!(text, "#                  A                   B                   N             EPS_MAX             SIG_MAX\n{:>20e}{:>20e}{:>20e}{:>20e}{:>20e}", jc.yield_stress, jc.hardening_modulus, jc.hardening_exponent, 0.0, 0.0);
    let _ = writeln!(text, "#                  C           EPS_DOT_0       ICC   Fsmooth               F_cut\n{:>20e}{:>20e}{:>10}{:>10}{:>20e}", jc.rate_sensitivity, jc.reference_rate, 1, 0, 0.0);
    let _ = writeln!(text, "#                  M              T_melt              rhoC_p                 T_r\n{:>20e}{:>20e}{:>20e}{:>20e}", jc.thermal_exponent, jc.melting_temperature, rho_cp, jc.reference_temperature);
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn johnson_cook_cards_carry_the_constants() {
        // GOAL: the exported cards hold the calibrated constants.
        // SETUP: the bundled 4340 JC material file.
        // REFERENCE: A, B, n, C, m appear in each card; fields fit LS-DYNA's 10 columns.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/4340-jc.toml");
        let (file, _) = crate::input::material::load(&path).unwrap();
        let dyna = ls_dyna(&file).unwrap();
        assert!(
            dyna.contains("*MAT_JOHNSON_COOK")
                && dyna.contains("792000000")
                && dyna.contains("0.014")
        );
        assert!(dyna
            .lines()
            .filter(|l| !l.starts_with('$') && !l.starts_with('*'))
            .all(|l| l.len() <= 80));
        assert!(abaqus(&file).unwrap().contains("7.92e8, 5.1e8, 2.6e-1"));
        assert!(open_radioss(&file).unwrap().contains("/MAT/PLAS_JOHNS"));
        assert_eq!(format_short(1.2345678901e-7).len(), 9);
    }
}
