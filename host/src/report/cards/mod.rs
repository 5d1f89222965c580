//! Material cards to paste into other codes, from a calibrated material file, in the unit
//! system, material id and name of [`units::CardOptions`] (default SI, id 1, `STOSS`); every
//! card states its units in its header. The user-material cards stay SI: the C ABI computes in
//! SI.
//!
//! - [`native`]: the codes' own cards where the model fits them exactly: Johnson-Cook as
//!   LS-DYNA `*MAT_JOHNSON_COOK` (*MAT_015) with `*EOS_LINEAR_POLYNOMIAL` (C1 = K) or
//!   `*EOS_GRUNEISEN`, Abaqus `*PLASTIC, HARDENING=JOHNSON COOK` with
//!   `*RATE DEPENDENT, TYPE=JOHNSON COOK`, OpenRadioss `/MAT/PLAS_JOHNS` (law 2);
//!   Zerilli-Armstrong as LS-DYNA `*MAT_ZERILLI-ARMSTRONG` (*MAT_065).
//! - [`tabulated`]: any J2 model (ZA, MJC, TJC, the diagnosis' composed terms) as tables of
//!   flow stress: LS-DYNA `*MAT_TABULATED_JOHNSON_COOK` (*MAT_224) and Abaqus/Explicit
//!   `*PLASTIC, RATE=` with a temperature column, with the sampled ranges and the largest
//!   interpolation error written in the card.
//! - [`user_material`]: the stoss user material's own card (the C ABI's card) for any model,
//!   as LS-DYNA `*MAT_USER_DEFINED_MATERIAL_MODELS` and Abaqus `*USER MATERIAL` input.
//!
//! Fixed-width fields are written so that every number fits its field with a separating
//! blank ([`field`]); the tests read every card back with the target format's column rules.

pub mod native;
pub mod tabulated;
pub mod units;
pub mod user_material;

use crate::input::material::MaterialFile;
use stoss_kernel::eos::Eos;

pub use native::{abaqus, ls_dyna, open_radioss};
pub use units::{CardOptions, CardUnits};

/// Young's modulus and Poisson's ratio from the bulk and shear moduli.
pub(crate) fn young_and_poisson(bulk: f64, shear: f64) -> (f64, f64) {
    (
        9.0 * bulk * shear / (3.0 * bulk + shear),
        (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear)),
    )
}

/// The bulk modulus of the material's EoS at the reference state.
pub(crate) fn bulk_modulus(file: &MaterialFile) -> Option<f64> {
    match file.eos {
        Eos::Linear(e) => Some(e.bulk_modulus),
        Eos::MieGruneisen(e) => Some(e.reference_density * e.sound_speed * e.sound_speed),
        Eos::Polynomial(e) => Some(e.a1),
        _ => None,
    }
}

/// `value` right-aligned in a fixed-width field of `width` characters, in at most
/// `width - 1` characters so that a blank always separates it from the field before: the
/// shortest form that reads back exactly (plain, then scientific) if it fits, else
/// scientific notation with as many digits as fit (at least 15 significant digits in a
/// 20-character field, 5 in a 10-character one).
pub fn field(value: f64, width: usize) -> String {
    let room = width.saturating_sub(1).max(1);
    let plain = format!("{value}");
    let shortest = format!("{value:e}");
    let text = if plain.len() <= room {
        plain
    } else if shortest.len() <= room {
        shortest
    } else {
        (0..=16)
            .rev()
            .map(|digits| format!("{value:.digits$e}"))
            .find(|text| text.len() <= room)
            .unwrap_or_else(|| format!("{value:.0e}"))
    };
    format!("{text:>width$}")
}

/// A card line of fixed-width fields.
pub(crate) fn line(values: &[f64], width: usize) -> String {
    values.iter().map(|v| field(*v, width)).collect()
}

/// Split a data line into fields of the given widths and read each as a number, as a
/// fixed-format reader does (a blank field reads as 0). For the tests, and for a user
/// checking a card by hand.
pub fn read_fields(line: &str, widths: &[usize]) -> Result<Vec<f64>, String> {
    let mut start = 0;
    let mut values = Vec::new();
    for width in widths {
        let end = (start + width).min(line.len());
        let text = line.get(start..end).unwrap_or("").trim();
        values.push(if text.is_empty() {
            0.0
        } else {
            text.parse::<f64>()
                .map_err(|_| format!("columns {}-{end}: `{text}` is not a number", start + 1))?
        });
        start += width;
    }
    if line.len() > start && !line[start..].trim().is_empty() {
        return Err(format!("text past column {start}: `{}`", &line[start..]));
    }
    Ok(values)
}
