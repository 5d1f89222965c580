//! The codes' own material cards, for the families they fit exactly (see [`super`]).

use super::units::{CardOptions, Quantity};
use super::{bulk_modulus, field, line, young_and_poisson};
use crate::input::material::{MaterialFile, StrengthSpec};
use std::fmt::Write as _;
use stoss_kernel::eos::Eos;
use stoss_kernel::strength::{CrystalStructure, JohnsonCook, ZerilliArmstrong};

/// LS-DYNA keyword cards (`None` if the family has no LS-DYNA equivalent), in `options`'
/// units, with its material id (the EoS takes the same id).
pub fn ls_dyna(file: &MaterialFile, options: &CardOptions) -> Option<String> {
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let mut text = format!(
        "$ stoss calibrated material: {} ({})\n$ {}\n",
        file.name,
        options.name,
        options.units.header()
    );
    match file.strength {
        StrengthSpec::JohnsonCook(jc) => {
            johnson_cook(&mut text, file, &jc, young, poisson, options)
        }
        StrengthSpec::ZerilliArmstrong(za) => zerilli_armstrong(&mut text, file, &za, options),
        _ => return None,
    }
    equation_of_state(&mut text, file, bulk, options);
    Some(text)
}

/// One LS-DYNA card: its comment header (and the keyword above it, if any) and its values in
/// 10-character fields.
fn card(text: &mut String, header: &str, values: &[f64]) {
    let _ = writeln!(text, "{header}\n{}", line(values, 10));
}

/// LS-DYNA's `*MAT_JOHNSON_COOK` card, with the Johnson-Cook failure constants if any.
fn johnson_cook(
    text: &mut String,
    file: &MaterialFile,
    jc: &JohnsonCook,
    young: f64,
    poisson: f64,
    options: &CardOptions,
) {
    let u = |value: f64, quantity: Quantity| options.units.from_si(value, quantity);
    let (d1, d2, d3, d4, d5) = file
        .failure
        .and_then(|f| f.johnson_cook)
        .map_or((0.0, 0.0, 0.0, 0.0, 0.0), |f| {
            (f.d1, f.d2, f.d3, f.d4, f.d5)
        });
    card(
        text,
        "*MAT_JOHNSON_COOK\n$      MID        RO         G         E        PR       DTF        VP    RATEOP",
        &[
            f64::from(options.material_id),
            u(file.density, Quantity::Density),
            u(file.shear_modulus, Quantity::Stress),
            u(young, Quantity::Stress),
            poisson,
            0.0,
            1.0,
            0.0,
        ],
    );
    card(
        text,
        "$        A         B         N         C         M        TM        TR      EPSO",
        &[
            u(jc.yield_stress, Quantity::Stress),
            u(jc.hardening_modulus, Quantity::Stress),
            jc.hardening_exponent,
            jc.rate_sensitivity,
            jc.thermal_exponent,
            jc.melting_temperature,
            jc.reference_temperature,
            u(jc.reference_rate, Quantity::Rate),
        ],
    );
    card(
        text,
        "$       CP        PC     SPALL        IT        D1        D2        D3        D4",
        &[
            u(file.specific_heat, Quantity::SpecificHeat),
            u(-1.0e20, Quantity::Stress),
            2.0,
            0.0,
            d1,
            d2,
            d3,
            d4,
        ],
    );
    card(
        text,
        "$       D5      C2/P      EROD     EFMIN    NUMINT",
        &[d5, 0.0, 0.0, 0.0, 0.0],
    );
}

/// LS-DYNA's `*MAT_ZERILLI-ARMSTRONG` card.
fn zerilli_armstrong(
    text: &mut String,
    file: &MaterialFile,
    za: &ZerilliArmstrong,
    options: &CardOptions,
) {
    let u = |value: f64, quantity: Quantity| options.units.from_si(value, quantity);
    let mix = match za.structure {
        CrystalStructure::Fcc => 1.0,
        CrystalStructure::Bcc => 2.0,
    };
    let _ = writeln!(text, "$ ZA: sigma = C1 + [C2 eps^0.5 (FCC)] exp(-C3 T + C4 T ln e*) + C5 eps^N; stoss C1 -> athermal stress");
    card(
        text,
        "*MAT_ZERILLI-ARMSTRONG\n$      MID        RO         G      E0        N     TROOM     PC      SPALL",
        &[
            f64::from(options.material_id),
            u(file.density, Quantity::Density),
            u(file.shear_modulus, Quantity::Stress),
            u(za.reference_rate, Quantity::Rate),
            za.exponent,
            298.0,
            u(-1.0e20, Quantity::Stress),
            2.0,
        ],
    );
    let thermal = if mix == 1.0 { za.c2 } else { za.c1 };
    card(
        text,
        "$       C1        C2        C3        C4        C5        C6     EFAIL    NUMINT",
        &[
            u(za.athermal_stress, Quantity::Stress),
            u(thermal, Quantity::Stress),
            za.c3,
            za.c4,
            u(za.c5, Quantity::Stress),
            0.0,
            1.0e20,
            0.0,
        ],
    );
    card(text, "$     LCMU       MIX", &[0.0, mix]);
}

/// LS-DYNA's `*EOS_GRUNEISEN` card for a Mie-Grüneisen equation of state, else
/// `*EOS_LINEAR_POLYNOMIAL` with the bulk modulus.
fn equation_of_state(text: &mut String, file: &MaterialFile, bulk: f64, options: &CardOptions) {
    let u = |value: f64, quantity: Quantity| options.units.from_si(value, quantity);
    let id = f64::from(options.material_id);
    match file.eos {
        Eos::MieGruneisen(g) => {
            card(
                text,
                "*EOS_GRUNEISEN\n$    EOSID         C        S1        S2        S3    GAMAO         A        E0",
                &[
                    id,
                    u(g.sound_speed, Quantity::Velocity),
                    g.s1,
                    g.s2,
                    g.s3,
                    g.gamma0,
                    g.volume_correction,
                    0.0,
                ],
            );
            card(text, "$       V0", &[1.0]);
        }
        _ => {
            card(
                text,
                "*EOS_LINEAR_POLYNOMIAL\n$    EOSID        C0        C1        C2        C3        C4        C5        C6",
                &[id, 0.0, u(bulk, Quantity::Stress), 0.0, 0.0, 0.0, 0.0, 0.0],
            );
            card(text, "$       E0        V0", &[0.0, 1.0]);
        }
    }
}

/// Abaqus input lines for Johnson-Cook (`None` for other families), in `options`' units.
pub fn abaqus(file: &MaterialFile, options: &CardOptions) -> Option<String> {
    let StrengthSpec::JohnsonCook(jc) = file.strength else {
        return None;
    };
    let u = |value: f64, quantity: Quantity| options.units.from_si(value, quantity);
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let chi = match file.heating {
        stoss_kernel::Heating::Adiabatic { taylor_quinney } => Some(taylor_quinney),
        _ => None,
    };
    let mut text = format!(
        "** stoss calibrated material: {}\n** {}\n*MATERIAL, NAME={}\n*DENSITY\n{:e}\n*ELASTIC\n{:e}, {:e}\n",
        file.name,
        options.units.header(),
        options.name,
        u(file.density, Quantity::Density),
        u(young, Quantity::Stress),
        poisson
    );
    let _ = writeln!(
        text,
        "*PLASTIC, HARDENING=JOHNSON COOK\n{:e}, {:e}, {:e}, {:e}, {:e}, {:e}",
        u(jc.yield_stress, Quantity::Stress),
        u(jc.hardening_modulus, Quantity::Stress),
        jc.hardening_exponent,
        jc.thermal_exponent,
        jc.melting_temperature,
        jc.reference_temperature
    );
    let _ = writeln!(
        text,
        "*RATE DEPENDENT, TYPE=JOHNSON COOK\n{:e}, {:e}",
        jc.rate_sensitivity,
        u(jc.reference_rate, Quantity::Rate)
    );
    if let Some(chi) = chi {
        let _ = writeln!(
            text,
            "*SPECIFIC HEAT\n{:e}\n*INELASTIC HEAT FRACTION\n{chi}",
            u(file.specific_heat, Quantity::SpecificHeat)
        );
    }
    Some(text)
}

/// OpenRadioss `/MAT/PLAS_JOHNS` (law 2, Johnson-Cook) (`None` for other families), with a
/// `/UNIT` block that declares the card's units (Radioss reference, `/UNIT`: a title line,
/// then the mass, length and time units as multiplying factors of kg, m and s): the starter
/// converts them to the deck's input units (`/BEGIN`), so the card is correct in a model of
/// any system.
pub fn open_radioss(file: &MaterialFile, options: &CardOptions) -> Option<String> {
    let StrengthSpec::JohnsonCook(jc) = file.strength else {
        return None;
    };
    let units = &options.units;
    let u = |value: f64, quantity: Quantity| units.from_si(value, quantity);
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let rho_cp = file.density * file.specific_heat;
    let id = options.material_id;
    let mut text = format!(
        "# stoss calibrated material: {}\n# {}\n# the card's units as multiplying factors (kg, m, s): {}, {}, {}\n/UNIT/{id}\nunits of {}\n#{:>19}{:>20}{:>20}\n{}\n/MAT/PLAS_JOHNS/{id}/{id}\n{}\n",
        file.name,
        units.header(),
        units.mass.0,
        units.length.0,
        units.time.0,
        options.name,
        "mass_unit",
        "length_unit",
        "time_unit",
        line(&[units.mass.1, units.length.1, units.time.1], 20),
        options.name
    );
    let _ = writeln!(
        text,
        "#              RHO_I\n{}",
        field(u(file.density, Quantity::Density), 20)
    );
    // Iflag 0 (a, b, n given); flagVP 1: the rate in the law is the equivalent plastic
    // strain rate, as in stoss's kernel and LS-DYNA's VP = 1 (OpenRadioss's default, 2, is the
    // total strain rate). With VP = 1 the starter filters the plastic strain rate itself
    // (10 kHz) and reads no F_cut, so the card raises no cut-off warning. flagVP is read by
    // the 2023 input format and later (hm_cfg_files matl2_plas_johns.cfg).
    let _ = writeln!(
        text,
        "#                  E                  NU     Iflag    flagVP\n{}{}",
        line(&[u(young, Quantity::Stress), poisson], 20),
        line(&[0.0, 1.0], 10)
    );
    let _ = writeln!(
        text,
        "#                  A                   B                   N             EPS_MAX             SIG_MAX\n{}",
        line(
            &[
                u(jc.yield_stress, Quantity::Stress),
                u(jc.hardening_modulus, Quantity::Stress),
                jc.hardening_exponent,
                0.0,
                0.0
            ],
            20
        )
    );
    let _ = writeln!(
        text,
        "#                  C           EPS_DOT_0       ICC   Fsmooth               F_cut\n{}{}{}",
        line(
            &[jc.rate_sensitivity, u(jc.reference_rate, Quantity::Rate)],
            20
        ),
        line(&[1.0, 0.0], 10),
        field(0.0, 20)
    );
    let _ = writeln!(
        text,
        "#                  M              T_melt              rhoC_p                 T_r\n{}",
        line(
            &[
                jc.thermal_exponent,
                jc.melting_temperature,
                u(rho_cp, Quantity::VolumetricHeat),
                jc.reference_temperature
            ],
            20
        )
    );
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::super::read_fields;
    use super::*;

    /// The data lines of a card (not comments, keywords or titles) read with `widths`.
    fn data(card: &str, comment: char, widths: &[usize]) -> Vec<Vec<f64>> {
        card.lines()
            .filter(|l| !l.starts_with(comment) && !l.starts_with('*') && !l.starts_with('/'))
            .filter(|l| l.trim() != "STOSS")
            .map(|l| read_fields(l, widths).unwrap_or_else(|e| panic!("{l}: {e}")))
            .collect()
    }

    fn close(read: f64, exact: f64, digits: i32) -> bool {
        (read - exact).abs() <= exact.abs() * 10f64.powi(1 - digits)
    }

    #[test]
    fn johnson_cook_cards_read_back_with_each_formats_column_rules() {
        // GOAL: a code reading the exported cards gets the calibrated constants, not numbers
        //       run together (an OpenRadioss card once read E as 20.9 Pa).
        // SETUP: the bundled 4340 JC file with its Young's modulus perturbed to need every
        //        digit (2.0947709377236935e11 Pa is 21 characters in Rust's `e` format).
        // REFERENCE: the constants; LS-DYNA fixed format is 8 fields of 10 columns (5
        //            significant digits fit), OpenRadioss lines are 20-column fields (10 for
        //            the ICC and Fsmooth flags), read with the same rules.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/4340-jc.toml");
        let (mut file, _) = crate::input::material::load(&path).unwrap();
        file.shear_modulus = 80.8e9 + 0.123456789;
        let StrengthSpec::JohnsonCook(jc) = file.strength else {
            panic!("JC file")
        };
        let bulk = bulk_modulus(&file).unwrap();
        let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);

        let dyna = ls_dyna(&file, &CardOptions::default()).unwrap();
        let lines = data(&dyna, '$', &[10; 8]);
        let mat = &lines[0];
        assert!(
            close(mat[1], file.density, 5) && close(mat[3], young, 5),
            "{mat:?}"
        );
        assert!(close(mat[4], poisson, 5));
        let constants = &lines[1];
        for (read, exact) in constants.iter().zip([
            jc.yield_stress,
            jc.hardening_modulus,
            jc.hardening_exponent,
            jc.rate_sensitivity,
            jc.thermal_exponent,
            jc.melting_temperature,
            jc.reference_temperature,
            jc.reference_rate,
        ]) {
            assert!(close(*read, exact, 5), "{read} vs {exact}");
        }

        let radioss = open_radioss(&file, &CardOptions::default()).unwrap();
        let rows: Vec<&str> = radioss
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('/') && l.trim() != "STOSS")
            // The /UNIT block's title and its factors.
            .skip(2)
            .collect();
        assert!(close(
            read_fields(rows[0], &[20]).unwrap()[0],
            file.density,
            15
        ));
        let elastic = read_fields(rows[1], &[20, 20, 10, 10]).unwrap();
        assert!(
            close(elastic[0], young, 15) && close(elastic[1], poisson, 15),
            "{elastic:?}"
        );
        // Iflag 0 (a, b, n), flagVP 1 (the plastic strain rate, as the kernel's law).
        assert_eq!((elastic[2], elastic[3]), (0.0, 1.0), "{elastic:?}");
        let hardening = read_fields(rows[2], &[20; 5]).unwrap();
        assert!(close(hardening[0], jc.yield_stress, 15));
        assert!(close(hardening[2], jc.hardening_exponent, 15));
        let rate = read_fields(rows[3], &[20, 20, 10, 10, 20]).unwrap();
        assert!(close(rate[0], jc.rate_sensitivity, 15) && rate[2] == 1.0);
        let thermal = read_fields(rows[4], &[20; 4]).unwrap();
        assert!(close(thermal[0], jc.thermal_exponent, 15));
        assert!(close(thermal[2], file.density * file.specific_heat, 15));

        let abaqus = abaqus(&file, &CardOptions::default()).unwrap();
        assert!(abaqus.contains("7.92e8, 5.1e8, 2.6e-1"));
    }

    #[test]
    fn johnson_cook_cards_in_every_unit_system_read_back_to_the_si_constants() {
        // GOAL: a card written in a user's unit system holds the calibrated material: each
        //       field read back with the format's column rules and converted to SI by its
        //       dimension is the SI constant; the ids and the name are the user's.
        // SETUP: the bundled 4340 JC file; LS-DYNA, Abaqus and OpenRadioss cards in SI,
        //        mm-ms-kg-GPa, mm-s-t-MPa, mm-ms-g-MPa and cm-us-g-Mbar, material id 42,
        //        name HHA.
        // REFERENCE: the constants (LS-DYNA's 10-column fields keep 5 digits, OpenRadioss'
        //            20-column ones 15); the OpenRadioss card declares its units in /UNIT.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/4340-jc.toml");
        let (file, _) = crate::input::material::load(&path).unwrap();
        let StrengthSpec::JohnsonCook(jc) = file.strength else {
            panic!("JC file")
        };
        let bulk = bulk_modulus(&file).unwrap();
        let (young, _) = young_and_poisson(bulk, file.shear_modulus);
        for (name, options) in super::super::units::test_systems() {
            let units = &options.units;
            let si = |value: f64, quantity: Quantity| units.to_si(value, quantity);
            let dyna = ls_dyna(&file, &options).unwrap();
            let lines = data(&dyna, '$', &[10; 8]);
            let (mat, constants, thermal) = (&lines[0], &lines[1], &lines[2]);
            assert_eq!(mat[0], 42.0, "{name}");
            for (read, quantity, exact) in [
                (mat[1], Quantity::Density, file.density),
                (mat[2], Quantity::Stress, file.shear_modulus),
                (mat[3], Quantity::Stress, young),
                (constants[0], Quantity::Stress, jc.yield_stress),
                (constants[1], Quantity::Stress, jc.hardening_modulus),
                (constants[3], Quantity::Unchanged, jc.rate_sensitivity),
                (constants[7], Quantity::Rate, jc.reference_rate),
                (thermal[0], Quantity::SpecificHeat, file.specific_heat),
            ] {
                assert!(
                    close(si(read, quantity), exact, 5),
                    "{name}: LS-DYNA {read} ({quantity:?}) against {exact}"
                );
            }
            let eos = &lines[4];
            assert_eq!(eos[0], 42.0, "{name}: EOSID");

            let radioss = open_radioss(&file, &options).unwrap();
            assert!(radioss.contains("/UNIT/42") && radioss.contains("/MAT/PLAS_JOHNS/42/42"));
            let declared_line = radioss
                .lines()
                .skip_while(|l| !l.contains("mass_unit"))
                .nth(1)
                .unwrap();
            let declared = read_fields(declared_line, &[20; 3]).unwrap();
            assert_eq!(
                declared,
                [units.mass.1, units.length.1, units.time.1],
                "{name}"
            );
            let rows: Vec<&str> = radioss
                .lines()
                .skip_while(|l| !l.starts_with("/MAT"))
                .filter(|l| !l.starts_with('#') && !l.starts_with('/') && l.trim() != "HHA")
                .collect();
            let density = read_fields(rows[0], &[20]).unwrap()[0];
            let elastic = read_fields(rows[1], &[20, 20, 10, 10]).unwrap();
            let hardening = read_fields(rows[2], &[20; 5]).unwrap();
            let rate = read_fields(rows[3], &[20, 20, 10, 10, 20]).unwrap();
            let heat = read_fields(rows[4], &[20; 4]).unwrap();
            for (read, quantity, exact) in [
                (density, Quantity::Density, file.density),
                (elastic[0], Quantity::Stress, young),
                (hardening[0], Quantity::Stress, jc.yield_stress),
                (rate[1], Quantity::Rate, jc.reference_rate),
                (
                    heat[2],
                    Quantity::VolumetricHeat,
                    file.density * file.specific_heat,
                ),
            ] {
                assert!(
                    close(si(read, quantity), exact, 14),
                    "{name}: OpenRadioss {read} ({quantity:?}) against {exact}"
                );
            }

            let inp = abaqus(&file, &options).unwrap();
            assert!(inp.contains("*MATERIAL, NAME=HHA"), "{name}");
            let after = |keyword: &str| -> Vec<f64> {
                let line = inp
                    .lines()
                    .skip_while(|l| !l.starts_with(keyword))
                    .nth(1)
                    .unwrap();
                line.split(',').map(|v| v.trim().parse().unwrap()).collect()
            };
            let plastic = after("*PLASTIC");
            assert!(close(si(plastic[0], Quantity::Stress), jc.yield_stress, 14));
            assert!(close(
                si(after("*DENSITY")[0], Quantity::Density),
                file.density,
                14
            ));
            let rate = after("*RATE DEPENDENT");
            assert!(close(si(rate[1], Quantity::Rate), jc.reference_rate, 14));
        }
    }

    #[test]
    fn fields_keep_a_separating_blank_and_the_most_digits_that_fit() {
        // GOAL: no number fills or overflows its field.
        // SETUP: numbers of every size in 10- and 20-column fields.
        // REFERENCE: width - 1 characters at most; read back within the digits kept.
        for value in [
            0.0,
            1.0,
            -1.0e20,
            2.0947709377236935e11,
            -3.3e-7,
            1.2345678901e-7,
            7830.0,
            0.26,
        ] {
            for (width, digits) in [(10, 4), (20, 15)] {
                let text = field(value, width);
                assert_eq!(text.len(), width);
                assert!(text.starts_with(' '), "`{text}`");
                let read: f64 = text.trim().parse().unwrap();
                assert!(close(read, value, digits), "{text} vs {value}");
            }
        }
    }
}
