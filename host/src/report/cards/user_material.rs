//! The stoss user material's own card for any model: the C ABI's card (the
//! `StossMaterialBlock` as a flat array, docs/user-material.md section 5) written as LS-DYNA
//! `*MAT_USER_DEFINED_MATERIAL_MODELS` and Abaqus `*USER MATERIAL` input. Every J2 model
//! stoss has, the diagnosis' terms included, and RHT and K&C concrete run bit for bit as in
//! stoss through it.

use super::line;
use crate::input::material::AnyMaterialFile;
use std::fmt::Write as _;
use stoss_kernel_ffi::card::{card_from_block, STOSS_CARD_BULK_MODULUS, STOSS_CARD_SHEAR_MODULUS};
use stoss_kernel_ffi::export::{from_kc, from_material, from_rht};

/// Specific heat written on a concrete's card (RHT, K&C; J/kg/K): the block requires one, the
/// concrete models (isothermal) do not read it; a typical concrete's.
const CONCRETE_SPECIFIC_HEAT: f64 = 880.0;

/// The user-material cards of `file` at `initial_temperature` (K): `(LS-DYNA, Abaqus)`, or
/// the reason there is none.
pub fn cards(file: &AnyMaterialFile, initial_temperature: f64) -> Result<(String, String), String> {
    let (block, dropped, erodes) = match file {
        AnyMaterialFile::J2(file) => {
            let material = file.material().map_err(|e| e.to_string())?;
            let (block, dropped) =
                from_material(&material, initial_temperature).map_err(|e| e.message)?;
            let f = &material.failure;
            let erodes = f.erode_on_failure || f.erosion_plastic_strain.is_some();
            (block, dropped, erodes)
        }
        AnyMaterialFile::Rht(file) => {
            let material = file.material().map_err(|e| e.to_string())?;
            let (block, dropped) = from_rht(&material, initial_temperature, CONCRETE_SPECIFIC_HEAT)
                .map_err(|e| e.message)?;
            (block, dropped, material.erosion_plastic_strain.is_some())
        }
        AnyMaterialFile::Kc(file) => {
            let material = file.material().map_err(|e| e.to_string())?;
            let (block, dropped) = from_kc(&material, initial_temperature, CONCRETE_SPECIFIC_HEAT)
                .map_err(|e| e.message)?;
            (block, dropped, false)
        }
    };
    let name = file.name();
    let density = block.density;
    let (card, length) = card_from_block(&block).map_err(|e| e.message)?;
    let card = &card[..length];
    let note = if dropped {
        "$ NOTE: the geometric-strain erosion and principal-strain failure of the stoss file are \
         host criteria, not part of the user material: use the host code's own erosion.\n"
    } else {
        ""
    };
    // LS-DYNA reads at most 48 constants into cm; longer cards (JWL, P-alpha, tabulated EoS)
    // need Abaqus or the batch interface.
    let lmc = length.max(48);
    let mut dyna = format!(
        "$ stoss user material: {}\n$ units: kg, m, s, Pa, K\n\
         $ link libstoss_kernel.a and call stoss_lsdyna_umat from umat41 (docs/user-material.md \
         section 7); 8 history variables.\n\
         $ fixed format keeps 5 significant digits; the Abaqus input beside this file keeps \
         every digit.\n{note}",
        name
    );
    if length > 48 {
        let _ = writeln!(
            dyna,
            "$ NOTE: this card has {length} constants; LS-DYNA passes at most 48 to a umat."
        );
    }
    let _ = writeln!(
        dyna,
        "*MAT_USER_DEFINED_MATERIAL_MODELS\n$      MID        RO        MT       LMC       NHV    IORTHO     IBULK        IG\n{}",
        line(
            &[
                1.0,
                density,
                41.0,
                lmc as f64,
                8.0,
                0.0,
                STOSS_CARD_BULK_MODULUS as f64,
                STOSS_CARD_SHEAR_MODULUS as f64
            ],
            10
        )
    );
    let _ = writeln!(
        dyna,
        "$    IVECT     IFAIL    ITHERM    IHYPER      IEOS\n{}",
        line(&[0.0, f64::from(u8::from(erodes)), 0.0, 0.0, 0.0], 10)
    );
    let mut padded = card.to_vec();
    padded.resize(lmc, 0.0);
    for (row, values) in padded.chunks(8).enumerate() {
        let _ = writeln!(
            dyna,
            "$ P{}..P{}\n{}",
            8 * row + 1,
            8 * row + values.len(),
            line(values, 10)
        );
    }
    let mut abaqus = format!(
        "** stoss user material: {}\n** units: kg, m, s, Pa, K\n\
         ** call stoss_abaqus_vumat from your VUMAT (docs/user-material.md section 8)\n\
         *MATERIAL, NAME=STOSS\n*DENSITY\n{:e}\n*USER MATERIAL, CONSTANTS={length}\n",
        name, density
    );
    for values in card.chunks(8) {
        let text: Vec<String> = values.iter().map(|v| format!("{v:e}")).collect();
        let _ = writeln!(abaqus, "{}", text.join(", "));
    }
    let _ = writeln!(abaqus, "*DEPVAR\n8");
    Ok((dyna, abaqus))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::material::StrengthSpec;
    use stoss_kernel::strength::RateTerm;
    use stoss_kernel_ffi::block_from_card;

    /// The constants of an Abaqus `*USER MATERIAL` block, as Abaqus reads them.
    fn abaqus_constants(abaqus: &str) -> Vec<f64> {
        abaqus
            .lines()
            .skip_while(|l| !l.starts_with("*USER MATERIAL"))
            .skip(1)
            .take_while(|l| !l.starts_with('*'))
            .flat_map(|l| {
                l.split(", ")
                    .map(|v| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    #[test]
    fn a_diagnosed_model_reads_back_from_its_user_material_cards() {
        // GOAL: a model the diagnosis accepts (JC + high-rate upturn) is a user-material card.
        // SETUP: the bundled 4340 file with the upturn term; both cards written, their
        //        constants read back (LS-DYNA 10-column fields, Abaqus comma lists).
        // REFERENCE: the kernel material: exact from the Abaqus card; from LS-DYNA's 5-digit
        //            fields, the same model codes and every constant within 5e-5.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/4340-jc.toml");
        let (mut file, _) = crate::input::material::load(&path).unwrap();
        let mut composed = stoss_kernel::strength::JohnsonCook::STEEL_4340.composed();
        composed.rate = RateTerm::LogUpturn {
            rate_sensitivity: 0.0141234567,
            reference_rate: 1.0,
            upturn_exponent: 0.0812345678,
            upturn_rate: 2.0e3,
        };
        file.strength = StrengthSpec::Composed(composed);
        let material = file.material().unwrap();
        let (dyna, abaqus) = cards(&AnyMaterialFile::J2(file), 298.0).unwrap();

        let values = abaqus_constants(&abaqus);
        let read = block_from_card(&values).unwrap().to_material().unwrap();
        assert_eq!(read, material);

        let rows: Vec<Vec<f64>> = dyna
            .lines()
            .filter(|l| !l.starts_with('$') && !l.starts_with('*'))
            .map(|l| super::super::read_fields(l, &[10; 8]).unwrap())
            .collect();
        assert_eq!(rows[0][3], 48.0);
        let card: Vec<f64> = rows[2..].iter().flatten().copied().collect();
        let (exact, length) = card_from_block(&from_material(&material, 298.0).unwrap().0).unwrap();
        for (read, exact) in card.iter().zip(&exact[..length]) {
            assert!(
                (read - exact).abs() <= 5e-5 * exact.abs(),
                "{read} vs {exact}"
            );
        }
        let read = block_from_card(&card).unwrap().to_material().unwrap();
        assert!(matches!(
            read.strength,
            stoss_kernel::strength::Strength::Composed(c)
                if matches!(c.rate, RateTerm::LogUpturn { .. })
        ));
    }

    #[test]
    fn rht_concrete_reads_back_from_its_user_material_card() {
        // GOAL: RHT concrete (C ABI layout 3) gets a user-material card that gives back the
        //       same kernel material.
        // SETUP: the bundled seed 001 HPC file (P-alpha EoS, geometric erosion); its Abaqus
        //        card read back with the C ABI's card reader.
        // REFERENCE: the file's kernel material, constant for constant, without the
        //            geometric erosion strain (a host criterion the card notes it leaves out).
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/hpc-92-rht.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let (file, _) = crate::input::material::parse_part(&path, &text).unwrap();
        let AnyMaterialFile::Rht(concrete) = &file else {
            panic!("the HPC file is RHT concrete");
        };
        let mut expected = concrete.material().unwrap();
        let (dyna, abaqus) = cards(&file, 293.0).unwrap();
        let values = abaqus_constants(&abaqus);
        assert_eq!(values[6], 7.0, "strength model RHT");
        let read = block_from_card(&values).unwrap().to_rht().unwrap();
        if expected.erosion_geometric_strain.take().is_some() {
            assert!(dyna.contains("host criteria"), "{dyna}");
        }
        assert_eq!(read, expected);
    }

    #[test]
    fn kc_concrete_reads_back_from_its_user_material_card() {
        // GOAL: K&C concrete (C ABI layout 5) gets a user-material card that gives back the
        //       same kernel material.
        // SETUP: the bundled seed 001 HPC 100 MPa K&C file (tabulated EoS, damage table);
        //        its Abaqus card read back with the C ABI's card reader.
        // REFERENCE: the file's kernel material, constant for constant.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/hpc-100-kc.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let (file, _) = crate::input::material::parse_part(&path, &text).unwrap();
        let AnyMaterialFile::Kc(concrete) = &file else {
            panic!("the HPC 100 file is K&C concrete");
        };
        let expected = concrete.material().unwrap();
        let (dyna, abaqus) = cards(&file, 293.0).unwrap();
        assert!(dyna.contains("*MAT_USER_DEFINED_MATERIAL_MODELS"), "{dyna}");
        let values = abaqus_constants(&abaqus);
        assert_eq!(values[6], 8.0, "strength model K&C");
        let read = block_from_card(&values).unwrap().to_kc().unwrap();
        assert_eq!(read, expected);
    }
}
