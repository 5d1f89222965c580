//! The material "card": the [`StossMaterialBlock`] as a flat list of doubles, for hosts that
//! hand a user material its constants as an array (LS-DYNA `cm(lmc)`, Abaqus `props(nprops)`).
//!
//! Positions are given 1-based (`P1` = `cm(1)` = `card[0]`), as users type them on the
//! material card. Integer codes (selectors, flags) are stored as exact doubles.
//!
//! | P | meaning |
//! |---|---|
//! | 1 | card layout version (`STOSS_LAYOUT_VERSION` = 7; cards of versions 1 to 6 are read too) |
//! | 2 | reference density `rho0` (kg/m^3) |
//! | 3 | shear modulus `G` (Pa) — LS-DYNA `IG = 3` |
//! | 4 | bulk modulus `K` (Pa) — LS-DYNA `IBULK = 4`; the linear EoS's `K`, otherwise the initial EoS slope (informative, must be > 0) |
//! | 5 | specific heat `c_p` (J/kg/K) |
//! | 6 | initial temperature (K) |
//! | 7 | strength model code |
//! | 8 | rate treatment code |
//! | 9 | EoS code |
//! | 10 | heating code |
//! | 11..13 | Taylor-Quinney `chi`, transition isothermal rate, adiabatic rate |
//! | 14 | failure flags: 1 JC damage, 2 erode on failure, 4 erode at P15, 8 pressure cut-off P16 (sum) |
//! | 15 | erosion plastic strain |
//! | 16 | pressure cut-off `p_min <= 0` (Pa) |
//! | 17..24 | JC failure `D1 D2 D3 D4 D5 e0 Tr Tm` |
//! | 25..41 | strength constants (17 slots, by model, see below) |
//! | 42.. | EoS constants (by EoS, see [`eos_length`]) |
//!
//! Strength slots P25..P41 (unused slots ignored):
//!
//! | model | P25, P26, ... |
//! |---|---|
//! | Johnson-Cook | `A B n C m e0 Tr Tm` |
//! | Zerilli-Armstrong (BCC, FCC) | `sigma_a C1 C2 C3 C4 C5 n e0` |
//! | modified Johnson-Cook | `A B n Q1 c1 Q2 c2 beta e0 m Tr Tm` |
//! | two-rate Johnson-Cook | `A B n Q1 c1 Q2 c2 beta1 e01 beta2 e02 m Tr Tm` |
//! | composed | `hardening rate thermal A B n Q1 c1 Q2 c2 R1 R2 R3 R4 m Tr Tm` |
//! | Preston-Tonks-Wallace (code 9, layout 6) | `theta p s0 s_inf kappa gamma y0 y_inf y1 y2 beta G0 alpha Tm rho M` |
//! | Khan-Huang-Liang (code 10, layout 6) | `A B n0 n1 C e0 D0p m Tr Tm` |
//! | Voce-Kocks (code 11, layout 6) | `sigma_0 theta_0 sigma_s0 e_s0 T_A` |
//! | Mechanical Threshold Stress (code 12, layout 7) | `sigma_a sigma_i g_0i e_0i p_i q_i g_0e e_0e p_e q_e sigma_es0 g_0es e_es0 a_0 a_1 a_2 a_3`, and after the EoS section `alpha mu_0 D T_0 k/b^3` |
//!
//! RHT concrete (strength code 7) uses P17..P40 instead of the JC failure and strength slots:
//! P17..P20 its tensile-failure, meridian and rate-scaling codes and elastic-cap switch,
//! P21..P40 its twenty constants in the order of the kernel's descriptor.
//!
//! K&C concrete (strength code 8, layout 5) uses P17..P41 the same way: P17 rate code, P18
//! crack band (0/1), P19, P20 its reference width and width, P21..P23 maximum surface
//! `a0 a1 a2`, P24..P26 yield surface `a0y a1y a2y`, P27, P28 residual `a1f a2f`, P29.. its
//! described scalars in the descriptor's order (`fc ft fbc/fc b1 b2` today); after the EoS
//! section follow the damage function's point count `n` and its `n` `lambda` and `n` `eta`.
//!
//! with the composed rate slots `R1..R4`: JC log `C e0`; power `beta e0`; two-part
//! `beta1 e01 beta2 e02`; Cowper-Symonds `D q`; log-upturn `C e0 beta e_up` and log-thermal
//! `C e0 kappa` (layout 2), whose `T*` uses the `Tr Tm` slots of the thermal term.

use stoss_kernel::PartMaterial;

use crate::block::{
    initial_bulk_modulus, StossEosModel, StossHardeningModel, StossHeatingModel, StossJohnsonCook,
    StossKhanHuangLiang, StossMaterialBlock, StossMechanicalThresholdStress,
    StossModifiedJohnsonCook, StossPrestonTonksWallace, StossRateModel, StossRht,
    StossStrengthModel, StossThermalModel, StossTwoRateJohnsonCook, StossVoceKocks,
    StossZerilliArmstrong, KC_CONSTANTS, STOSS_KC_MAX_DAMAGE_POINTS, STOSS_LAYOUT_VERSION,
    STOSS_MAX_COMPACTION_POINTS,
};
use crate::section::DescribedSection;
use crate::status::{FfiError, StossStatus};

/// 1-based card position of the shear modulus (LS-DYNA `IG`).
pub const STOSS_CARD_SHEAR_MODULUS: usize = 3;
/// 1-based card position of the bulk modulus (LS-DYNA `IBULK`).
pub const STOSS_CARD_BULK_MODULUS: usize = 4;
/// Card length of the header, JC failure and strength sections (the EoS section follows).
pub const STOSS_CARD_FIXED_LENGTH: usize = 41;
/// Longest card (K&C over a tabulated compaction EoS with 16 points and a damage function of
/// 16 points).
pub const STOSS_CARD_MAX_LENGTH: usize = STOSS_CARD_FIXED_LENGTH
    + 1
    + 3 * STOSS_MAX_COMPACTION_POINTS
    + 1
    + 2 * STOSS_KC_MAX_DAMAGE_POINTS;

/// Failure flag bits of card slot P14.
pub const STOSS_CARD_FAILURE_JOHNSON_COOK: u32 = 1;
/// Erode when damage reaches 1.
pub const STOSS_CARD_FAILURE_ERODE_ON_FAILURE: u32 = 2;
/// Erode at the plastic strain of P15.
pub const STOSS_CARD_FAILURE_EROSION_STRAIN: u32 = 4;
/// Pressure cut-off at P16.
pub const STOSS_CARD_FAILURE_PRESSURE_CUTOFF: u32 = 8;

/// 0-based index of the first strength slot (P25).
const STRENGTH: usize = 24;
/// 0-based index of the first RHT slot (P17): RHT concrete has no Johnson-Cook failure, so
/// its 24 values take P17..P40 (the JC failure and strength slots).
const RHT: usize = 16;
/// 0-based index of the first K&C slot (P17): K&C concrete has no Johnson-Cook failure; its
/// options, surfaces and described scalars take P17.. (see [`KC_CONSTANTS_SLOT`]).
const KC: usize = 16;
/// 0-based index of the first described K&C scalar (P29): after the rate code, the crack
/// band (flag and two widths) and the eight surface constants.
const KC_CONSTANTS_SLOT: usize = KC + 12;

const _: () = assert!(
    RHT + 4 + <StossRht as DescribedSection>::FIELDS.len() <= STOSS_CARD_FIXED_LENGTH,
    "RHT's described constants no longer fit in P21..P41 of the card"
);
const _: () = assert!(
    <StossJohnsonCook as DescribedSection>::FIELDS.len() <= 17
        && <StossZerilliArmstrong as DescribedSection>::FIELDS.len() <= 17
        && <StossModifiedJohnsonCook as DescribedSection>::FIELDS.len() <= 17
        && <StossTwoRateJohnsonCook as DescribedSection>::FIELDS.len() <= 17
        && <StossPrestonTonksWallace as DescribedSection>::FIELDS.len() <= 17
        && <StossKhanHuangLiang as DescribedSection>::FIELDS.len() <= 17
        && <StossVoceKocks as DescribedSection>::FIELDS.len() <= 17,
    "a J2 family's constants no longer fit in the 17 strength slots P25..P41"
);

const _: () = assert!(
    KC_CONSTANTS_SLOT + KC_CONSTANTS <= STOSS_CARD_FIXED_LENGTH,
    "K&C's described constants no longer fit in P29..P41 of the card"
);

/// Constants of the Mechanical Threshold Stress beyond the 17 strength slots: written right
/// after the EoS section (`alpha mu_0 D T_0 k/b^3`).
const MTS_TAIL: usize = <StossMechanicalThresholdStress as DescribedSection>::FIELDS.len() - 17;

const _: () = assert!(
    MTS_TAIL <= 1 + 2 * STOSS_KC_MAX_DAMAGE_POINTS,
    "the MTS tail no longer fits in the card's longest tail"
);

/// 0-based index of the first EoS slot (P42).
const EOS: usize = STOSS_CARD_FIXED_LENGTH;

/// Number of EoS slots (from P42) the EoS with code `eos` needs; for the tabulated
/// compaction EoS it depends on the point count in P42.
pub fn eos_length(eos: StossEosModel, point_count: usize) -> usize {
    match eos {
        StossEosModel::Linear => 0,
        StossEosModel::MieGruneisen | StossEosModel::Polynomial => 7,
        StossEosModel::Jwl => 9,
        StossEosModel::PAlpha => 11,
        StossEosModel::TabulatedCompaction => 1 + 3 * point_count,
    }
}

fn slot_error(index: usize, what: &str, message: impl std::fmt::Display) -> FfiError {
    FfiError::new(
        StossStatus::InvalidParameter,
        format!("card P{} ({what}): {message}", index + 1),
    )
}

/// Set a named section's constants from the card slots that start at `slots`, in ABI order.
fn read_constants<S: DescribedSection>(slots: &[f64], section: &mut S) {
    let constants = section.constants_mut();
    let count = constants.len();
    constants.copy_from_slice(&slots[..count]);
}

/// Write a named section's constants to the card slots that start at `slots`, in ABI order.
fn write_constants<S: DescribedSection>(slots: &mut [f64], section: &S) {
    let constants = section.constants();
    slots[..constants.len()].copy_from_slice(constants);
}

/// An integer code stored as a double: exact, in `i32` range.
fn code(card: &[f64], index: usize, what: &str) -> Result<i32, FfiError> {
    let value = card[index];
    if value.is_finite() && value == value.trunc() && value.abs() <= f64::from(i32::MAX) {
        Ok(value as i32)
    } else {
        Err(slot_error(
            index,
            what,
            format_args!("{value} is not an integer code"),
        ))
    }
}

/// Parse a card into a block. The block is not validated here beyond the card's own
/// structure (length, integer codes, layout version): call
/// [`StossMaterialBlock::to_material`] for that.
pub fn block_from_card(card: &[f64]) -> Result<StossMaterialBlock, FfiError> {
    if card.len() < STOSS_CARD_FIXED_LENGTH {
        return Err(FfiError::new(
            StossStatus::InvalidParameter,
            format!(
                "card: {} values, at least {STOSS_CARD_FIXED_LENGTH} needed (P1..P41)",
                card.len()
            ),
        ));
    }
    let version = code(card, 0, "layout version")?;
    // A version-1 card is a version-2 card without the two rate codes version 2 added.
    if !(1..=STOSS_LAYOUT_VERSION as i32).contains(&version) {
        return Err(FfiError::new(
            StossStatus::BadLayoutVersion,
            format!(
                "card P1 (layout version): card has {version}, this library reads 1 to \
                 {STOSS_LAYOUT_VERSION}"
            ),
        ));
    }
    let mut block = StossMaterialBlock::empty();
    block.density = card[1];
    block.shear_modulus = card[2];
    let bulk_modulus = card[3];
    if !(bulk_modulus.is_finite() && bulk_modulus > 0.0) {
        return Err(slot_error(
            3,
            "bulk modulus",
            format_args!("must be > 0, got {bulk_modulus}"),
        ));
    }
    block.specific_heat = card[4];
    block.initial_temperature = card[5];
    block.strength_model = code(card, 6, "strength model")?;
    block.rate_treatment = code(card, 7, "rate treatment")?;
    block.eos_model = code(card, 8, "eos model")?;
    block.heating_model = code(card, 9, "heating model")?;
    block.heating.taylor_quinney = card[10];
    block.heating.isothermal_rate = card[11];
    block.heating.adiabatic_rate = card[12];
    let flags = code(card, 13, "failure flags")?;
    if !(0..16).contains(&flags) {
        return Err(slot_error(
            13,
            "failure flags",
            format_args!("{flags} is not a sum of 1, 2, 4, 8"),
        ));
    }
    let flags = flags as u32;
    let f = &mut block.failure;
    f.johnson_cook_enabled = u32::from(flags & STOSS_CARD_FAILURE_JOHNSON_COOK != 0);
    f.erode_on_failure = u32::from(flags & STOSS_CARD_FAILURE_ERODE_ON_FAILURE != 0);
    f.erosion_enabled = u32::from(flags & STOSS_CARD_FAILURE_EROSION_STRAIN != 0);
    f.pressure_cutoff_enabled = u32::from(flags & STOSS_CARD_FAILURE_PRESSURE_CUTOFF != 0);
    f.erosion_plastic_strain = card[14];
    f.pressure_cutoff = card[15];
    if block.strength_model == StossStrengthModel::Rht as i32 {
        let r = &mut block.strength.rht;
        r.tensile_failure = code(card, RHT, "RHT tensile failure")?;
        r.meridian = code(card, RHT + 1, "RHT meridian")?;
        r.rate_scaling = code(card, RHT + 2, "RHT rate scaling")?;
        let cap = code(card, RHT + 3, "RHT elastic cap")?;
        r.elastic_cap = u32::try_from(cap)
            .map_err(|_| slot_error(RHT + 3, "RHT elastic cap", "must be 0 or 1"))?;
        read_constants(&card[RHT + 4..], r);
        read_eos(card, &mut block, bulk_modulus)?;
        return Ok(block);
    }
    if block.strength_model == StossStrengthModel::Kc as i32 {
        let k = &mut block.strength.kc;
        k.rate = code(card, KC, "K&C rate")?;
        let band = code(card, KC + 1, "K&C crack band")?;
        k.crack_band_enabled = u32::try_from(band)
            .map_err(|_| slot_error(KC + 1, "K&C crack band", "must be 0 or 1"))?;
        [k.crack_band_reference_width, k.crack_band_width] = [card[KC + 2], card[KC + 3]];
        k.maximum_surface = card[KC + 4..KC + 7].try_into().expect("3 slots");
        k.yield_surface = card[KC + 7..KC + 10].try_into().expect("3 slots");
        k.residual_surface = card[KC + 10..KC + 12].try_into().expect("2 slots");
        k.constants[..KC_CONSTANTS]
            .copy_from_slice(&card[KC_CONSTANTS_SLOT..KC_CONSTANTS_SLOT + KC_CONSTANTS]);
        let damage = read_eos(card, &mut block, bulk_modulus)?;
        read_damage(card, damage, &mut block)?;
        return Ok(block);
    }
    let j = &mut f.johnson_cook;
    [
        j.d1,
        j.d2,
        j.d3,
        j.d4,
        j.d5,
        j.reference_rate,
        j.reference_temperature,
        j.melting_temperature,
    ] = card[16..24].try_into().expect("8 slots");

    let s: [f64; 17] = card[STRENGTH..STRENGTH + 17].try_into().expect("17 slots");
    let strength = &mut block.strength;
    match StossStrengthModel::from_code(block.strength_model)? {
        // Read with their own slots above.
        StossStrengthModel::Rht | StossStrengthModel::Kc => {}
        StossStrengthModel::JohnsonCook => read_constants(&s, &mut strength.johnson_cook),
        StossStrengthModel::ZerilliArmstrongBcc | StossStrengthModel::ZerilliArmstrongFcc => {
            read_constants(&s, &mut strength.zerilli_armstrong);
        }
        StossStrengthModel::ModifiedJohnsonCook => {
            read_constants(&s, &mut strength.modified_johnson_cook);
        }
        StossStrengthModel::TwoRateJohnsonCook => {
            read_constants(&s, &mut strength.two_rate_johnson_cook);
        }
        StossStrengthModel::PrestonTonksWallace => {
            read_constants(&s, &mut strength.preston_tonks_wallace);
        }
        StossStrengthModel::KhanHuangLiang => {
            read_constants(&s, &mut strength.khan_huang_liang);
        }
        StossStrengthModel::VoceKocks => read_constants(&s, &mut strength.voce_kocks),
        StossStrengthModel::MechanicalThresholdStress => {
            let tail = read_eos(card, &mut block, bulk_modulus)?;
            if card.len() < tail + MTS_TAIL {
                return Err(FfiError::new(
                    StossStatus::InvalidParameter,
                    format!(
                        "card: {} values, the Mechanical Threshold Stress needs {} (its last \
                         {MTS_TAIL} constants `alpha mu_0 D T_0 k/b^3` follow the EoS section \
                         at P{}..P{})",
                        card.len(),
                        tail + MTS_TAIL,
                        tail + 1,
                        tail + MTS_TAIL
                    ),
                ));
            }
            let constants = block.strength.mechanical_threshold_stress.constants_mut();
            constants[..17].copy_from_slice(&s);
            constants[17..].copy_from_slice(&card[tail..tail + MTS_TAIL]);
            return Ok(block);
        }
        StossStrengthModel::Composed => {
            let p = &mut strength.composed;
            p.hardening_model = code(card, STRENGTH, "composed hardening model")?;
            p.rate_model = code(card, STRENGTH + 1, "composed rate model")?;
            p.thermal_model = code(card, STRENGTH + 2, "composed thermal model")?;
            let h = &mut p.hardening;
            [
                h.yield_stress,
                h.hardening_modulus,
                h.exponent,
                h.saturation_stress_1,
                h.saturation_rate_1,
                h.saturation_stress_2,
                h.saturation_rate_2,
            ] = s[3..10].try_into().expect("7");
            let r = &mut p.rate;
            match StossRateModel::from_code(p.rate_model)? {
                StossRateModel::None => {}
                StossRateModel::JohnsonCookLog => {
                    [r.rate_sensitivity, r.reference_rate] = [s[10], s[11]];
                }
                StossRateModel::Power => [r.exponent, r.reference_rate] = [s[10], s[11]],
                StossRateModel::TwoPart => {
                    [
                        r.exponent,
                        r.reference_rate,
                        r.exponent_2,
                        r.reference_rate_2,
                    ] = [s[10], s[11], s[12], s[13]];
                }
                StossRateModel::CowperSymonds => {
                    [r.cowper_symonds_d, r.cowper_symonds_q] = [s[10], s[11]];
                }
                StossRateModel::LogUpturn => {
                    [
                        r.rate_sensitivity,
                        r.reference_rate,
                        r.upturn_exponent,
                        r.upturn_rate,
                    ] = [s[10], s[11], s[12], s[13]];
                }
                StossRateModel::LogThermal => {
                    [r.rate_sensitivity, r.reference_rate, r.coupling] = [s[10], s[11], s[12]];
                    [
                        r.coupling_reference_temperature,
                        r.coupling_melting_temperature,
                    ] = [s[15], s[16]];
                }
            }
            if StossThermalModel::from_code(p.thermal_model)?
                == StossThermalModel::HomologousPowerDrop
            {
                return Err(slot_error(
                    STRENGTH + 2,
                    "composed thermal model",
                    "the thermal drop's three constants have no card slots (use the block)",
                ));
            }
            let t = &mut p.thermal;
            [t.exponent, t.reference_temperature, t.melting_temperature] = [s[14], s[15], s[16]];
        }
    }

    read_eos(card, &mut block, bulk_modulus)?;
    Ok(block)
}

/// The K&C damage function from 0-based card index `start` (right after the EoS section):
/// the point count, then the `lambda`s, then the `eta`s.
fn read_damage(card: &[f64], start: usize, block: &mut StossMaterialBlock) -> Result<(), FfiError> {
    let what = "K&C damage point count";
    let count = if card.len() > start {
        code(card, start, what)?
    } else {
        0
    };
    if !(2..=STOSS_KC_MAX_DAMAGE_POINTS as i32).contains(&count) {
        return Err(slot_error(
            start,
            what,
            format_args!("{count} is outside [2, {STOSS_KC_MAX_DAMAGE_POINTS}]"),
        ));
    }
    let count = count as usize;
    let needed = start + 1 + 2 * count;
    if card.len() < needed {
        return Err(FfiError::new(
            StossStatus::InvalidParameter,
            format!(
                "card: {} values, the K&C damage function needs {needed} (P{}..P{needed})",
                card.len(),
                start + 1
            ),
        ));
    }
    let k = &mut block.strength.kc;
    k.damage_point_count = count as u32;
    k.damage_lambda[..count].copy_from_slice(&card[start + 1..start + 1 + count]);
    k.damage_eta[..count].copy_from_slice(&card[start + 1 + count..needed]);
    Ok(())
}

/// The EoS section (from P42) of a card into `block` (`bulk_modulus`, P4, is the linear
/// EoS's `K`); returns the 0-based index just past it.
fn read_eos(
    card: &[f64],
    block: &mut StossMaterialBlock,
    bulk_modulus: f64,
) -> Result<usize, FfiError> {
    let eos = StossEosModel::from_code(block.eos_model)?;
    let point_count = if eos == StossEosModel::TabulatedCompaction {
        let count = card.get(EOS).copied().unwrap_or(0.0);
        let count_code = if card.len() > EOS {
            code(card, EOS, "tabulated point count")?
        } else {
            0
        };
        if !(2..=STOSS_MAX_COMPACTION_POINTS as i32).contains(&count_code) {
            return Err(slot_error(
                EOS,
                "tabulated point count",
                format_args!("{count} is outside [2, {STOSS_MAX_COMPACTION_POINTS}]"),
            ));
        }
        count_code as usize
    } else {
        0
    };
    let needed = EOS + eos_length(eos, point_count);
    if card.len() < needed {
        return Err(FfiError::new(
            StossStatus::InvalidParameter,
            format!(
                "card: {} values, the selected EoS needs {needed} (P42..P{needed})",
                card.len()
            ),
        ));
    }
    let e = &card[EOS..needed];
    let eos_block = &mut block.eos;
    match eos {
        StossEosModel::Linear => eos_block.linear.bulk_modulus = bulk_modulus,
        StossEosModel::MieGruneisen => {
            let p = &mut eos_block.mie_gruneisen;
            [
                p.reference_density,
                p.sound_speed,
                p.s1,
                p.s2,
                p.s3,
                p.gamma0,
                p.volume_correction,
            ] = e.try_into().expect("7");
        }
        StossEosModel::Polynomial => {
            let p = &mut eos_block.polynomial;
            [p.a1, p.a2, p.a3, p.b0, p.b1, p.t1, p.t2] = e.try_into().expect("7");
        }
        StossEosModel::Jwl => {
            let p = &mut eos_block.jwl;
            [
                p.a,
                p.b,
                p.r1,
                p.r2,
                p.omega,
                p.reference_density,
                p.detonation_energy,
                p.detonation_velocity,
                p.cj_pressure,
            ] = e.try_into().expect("9");
        }
        StossEosModel::PAlpha => {
            let p = &mut eos_block.p_alpha;
            let q = &mut p.solid;
            [
                q.a1,
                q.a2,
                q.a3,
                q.b0,
                q.b1,
                q.t1,
                q.t2,
                p.initial_distension,
                p.crush_pressure,
                p.lock_pressure,
                p.exponent,
            ] = e.try_into().expect("11");
        }
        StossEosModel::TabulatedCompaction => {
            let p = &mut eos_block.tabulated_compaction;
            p.point_count = point_count as u32;
            for i in 0..point_count {
                p.volumetric_strain[i] = e[1 + 3 * i];
                p.pressure[i] = e[2 + 3 * i];
                p.unloading_bulk_modulus[i] = e[3 + 3 * i];
            }
        }
    }
    Ok(needed)
}

/// The card of a (valid) block: `P1..P41` plus the EoS section; returns the values and the
/// number used. The block is validated first.
pub fn card_from_block(
    block: &StossMaterialBlock,
) -> Result<([f64; STOSS_CARD_MAX_LENGTH], usize), FfiError> {
    let model = block.to_model()?;
    let eos = match &model {
        PartMaterial::J2(material) => &material.eos,
        PartMaterial::Rht(material) => &material.eos,
        PartMaterial::Kc(material) => &material.eos,
    };
    let mut card = [0.0; STOSS_CARD_MAX_LENGTH];
    card[0] = f64::from(STOSS_LAYOUT_VERSION);
    card[1] = block.density;
    card[2] = block.shear_modulus;
    card[3] = initial_bulk_modulus(eos);
    card[4] = block.specific_heat;
    card[5] = block.initial_temperature;
    card[6] = f64::from(block.strength_model);
    card[7] = f64::from(block.rate_treatment);
    card[8] = f64::from(block.eos_model);
    card[9] = f64::from(block.heating_model);
    let heating = StossHeatingModel::from_code(block.heating_model)?;
    if heating != StossHeatingModel::Isothermal {
        card[10] = block.heating.taylor_quinney;
    }
    if heating == StossHeatingModel::Transition {
        card[11] = block.heating.isothermal_rate;
        card[12] = block.heating.adiabatic_rate;
    }
    let f = &block.failure;
    let flags = f.johnson_cook_enabled * STOSS_CARD_FAILURE_JOHNSON_COOK
        + f.erode_on_failure * STOSS_CARD_FAILURE_ERODE_ON_FAILURE
        + f.erosion_enabled * STOSS_CARD_FAILURE_EROSION_STRAIN
        + f.pressure_cutoff_enabled * STOSS_CARD_FAILURE_PRESSURE_CUTOFF;
    card[13] = f64::from(flags);
    if f.erosion_enabled == 1 {
        card[14] = f.erosion_plastic_strain;
    }
    if f.pressure_cutoff_enabled == 1 {
        card[15] = f.pressure_cutoff;
    }
    let j = &f.johnson_cook;
    if f.johnson_cook_enabled == 1 {
        card[16..24].copy_from_slice(&[
            j.d1,
            j.d2,
            j.d3,
            j.d4,
            j.d5,
            j.reference_rate,
            j.reference_temperature,
            j.melting_temperature,
        ]);
    }
    let s = &mut card[STRENGTH..STRENGTH + 17];
    let strength = &block.strength;
    match StossStrengthModel::from_code(block.strength_model)? {
        StossStrengthModel::Rht => {
            let r = &strength.rht;
            card[RHT] = f64::from(r.tensile_failure);
            card[RHT + 1] = f64::from(r.meridian);
            card[RHT + 2] = f64::from(r.rate_scaling);
            card[RHT + 3] = f64::from(r.elastic_cap);
            write_constants(&mut card[RHT + 4..], r);
        }
        StossStrengthModel::Kc => {
            let k = &strength.kc;
            card[KC] = f64::from(k.rate);
            card[KC + 1] = f64::from(k.crack_band_enabled);
            if k.crack_band_enabled == 1 {
                [card[KC + 2], card[KC + 3]] = [k.crack_band_reference_width, k.crack_band_width];
            }
            card[KC + 4..KC + 7].copy_from_slice(&k.maximum_surface);
            card[KC + 7..KC + 10].copy_from_slice(&k.yield_surface);
            card[KC + 10..KC + 12].copy_from_slice(&k.residual_surface);
            card[KC_CONSTANTS_SLOT..KC_CONSTANTS_SLOT + KC_CONSTANTS]
                .copy_from_slice(&k.constants[..KC_CONSTANTS]);
        }
        StossStrengthModel::JohnsonCook => write_constants(s, &strength.johnson_cook),
        StossStrengthModel::ZerilliArmstrongBcc | StossStrengthModel::ZerilliArmstrongFcc => {
            write_constants(s, &strength.zerilli_armstrong);
        }
        StossStrengthModel::ModifiedJohnsonCook => {
            write_constants(s, &strength.modified_johnson_cook);
        }
        StossStrengthModel::TwoRateJohnsonCook => {
            write_constants(s, &strength.two_rate_johnson_cook);
        }
        StossStrengthModel::PrestonTonksWallace => {
            write_constants(s, &strength.preston_tonks_wallace);
        }
        StossStrengthModel::KhanHuangLiang => {
            write_constants(s, &strength.khan_huang_liang);
        }
        StossStrengthModel::VoceKocks => write_constants(s, &strength.voce_kocks),
        StossStrengthModel::MechanicalThresholdStress => {
            // P25..P41 here; the last MTS_TAIL constants after the EoS section, below.
            s.copy_from_slice(&strength.mechanical_threshold_stress.constants()[..17]);
        }
        StossStrengthModel::Composed => {
            let p = &strength.composed;
            let h = &p.hardening;
            s[0] = f64::from(p.hardening_model);
            s[1] = f64::from(p.rate_model);
            s[2] = f64::from(p.thermal_model);
            s[3] = h.yield_stress;
            let hardening = StossHardeningModel::from_code(p.hardening_model)?;
            if hardening != StossHardeningModel::Voce2 {
                s[4] = h.hardening_modulus;
                s[5] = h.exponent;
            }
            if hardening != StossHardeningModel::Power {
                s[6..10].copy_from_slice(&[
                    h.saturation_stress_1,
                    h.saturation_rate_1,
                    h.saturation_stress_2,
                    h.saturation_rate_2,
                ]);
            }
            let r = &p.rate;
            let rate: &[f64] = match StossRateModel::from_code(p.rate_model)? {
                StossRateModel::None => &[],
                StossRateModel::JohnsonCookLog => &[r.rate_sensitivity, r.reference_rate],
                StossRateModel::Power => &[r.exponent, r.reference_rate],
                StossRateModel::TwoPart => &[
                    r.exponent,
                    r.reference_rate,
                    r.exponent_2,
                    r.reference_rate_2,
                ],
                StossRateModel::CowperSymonds => &[r.cowper_symonds_d, r.cowper_symonds_q],
                StossRateModel::LogUpturn => &[
                    r.rate_sensitivity,
                    r.reference_rate,
                    r.upturn_exponent,
                    r.upturn_rate,
                ],
                StossRateModel::LogThermal => &[r.rate_sensitivity, r.reference_rate, r.coupling],
            };
            s[10..10 + rate.len()].copy_from_slice(rate);
            let t = &p.thermal;
            match StossThermalModel::from_code(p.thermal_model)? {
                StossThermalModel::None => {}
                StossThermalModel::HomologousPower => {
                    s[14..17].copy_from_slice(&[
                        t.exponent,
                        t.reference_temperature,
                        t.melting_temperature,
                    ]);
                }
                StossThermalModel::Linear => {
                    s[15..17].copy_from_slice(&[t.reference_temperature, t.melting_temperature]);
                }
                StossThermalModel::HomologousPowerDrop => {
                    return Err(slot_error(
                        STRENGTH + 2,
                        "composed thermal model",
                        "the thermal drop's three constants have no card slots (use the block)",
                    ));
                }
            }
            // The log-thermal rate term's T* shares the thermal term's slots P40, P41.
            if StossRateModel::from_code(p.rate_model)? == StossRateModel::LogThermal {
                let coupling = [
                    r.coupling_reference_temperature,
                    r.coupling_melting_temperature,
                ];
                if StossThermalModel::from_code(p.thermal_model)? == StossThermalModel::None {
                    s[15..17].copy_from_slice(&coupling);
                } else if s[15..17] != coupling {
                    return Err(slot_error(
                        STRENGTH + 15,
                        "log-thermal rate term",
                        "its reference and melting temperatures share P40, P41 with the \
                         thermal term's and must equal them on a card (use the block)",
                    ));
                }
            }
        }
    }
    let eos = StossEosModel::from_code(block.eos_model)?;
    let e = &block.eos;
    let point_count = e.tabulated_compaction.point_count as usize;
    let length = EOS + eos_length(eos, point_count);
    let section = &mut card[EOS..length];
    match eos {
        StossEosModel::Linear => {}
        StossEosModel::MieGruneisen => {
            let p = &e.mie_gruneisen;
            section.copy_from_slice(&[
                p.reference_density,
                p.sound_speed,
                p.s1,
                p.s2,
                p.s3,
                p.gamma0,
                p.volume_correction,
            ]);
        }
        StossEosModel::Polynomial => {
            let p = &e.polynomial;
            section.copy_from_slice(&[p.a1, p.a2, p.a3, p.b0, p.b1, p.t1, p.t2]);
        }
        StossEosModel::Jwl => {
            let p = &e.jwl;
            section.copy_from_slice(&[
                p.a,
                p.b,
                p.r1,
                p.r2,
                p.omega,
                p.reference_density,
                p.detonation_energy,
                p.detonation_velocity,
                p.cj_pressure,
            ]);
        }
        StossEosModel::PAlpha => {
            let p = &e.p_alpha;
            let q = &p.solid;
            section.copy_from_slice(&[
                q.a1,
                q.a2,
                q.a3,
                q.b0,
                q.b1,
                q.t1,
                q.t2,
                p.initial_distension,
                p.crush_pressure,
                p.lock_pressure,
                p.exponent,
            ]);
        }
        StossEosModel::TabulatedCompaction => {
            let p = &e.tabulated_compaction;
            section[0] = point_count as f64;
            for i in 0..point_count {
                section[1 + 3 * i] = p.volumetric_strain[i];
                section[2 + 3 * i] = p.pressure[i];
                section[3 + 3 * i] = p.unloading_bulk_modulus[i];
            }
        }
    }
    if StossStrengthModel::from_code(block.strength_model)? == StossStrengthModel::Kc {
        let k = &block.strength.kc;
        let count = k.damage_point_count as usize;
        card[length] = count as f64;
        card[length + 1..length + 1 + count].copy_from_slice(&k.damage_lambda[..count]);
        card[length + 1 + count..length + 1 + 2 * count].copy_from_slice(&k.damage_eta[..count]);
        return Ok((card, length + 1 + 2 * count));
    }
    if StossStrengthModel::from_code(block.strength_model)?
        == StossStrengthModel::MechanicalThresholdStress
    {
        card[length..length + MTS_TAIL]
            .copy_from_slice(&block.strength.mechanical_threshold_stress.constants()[17..]);
        return Ok((card, length + MTS_TAIL));
    }
    Ok((card, length))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::{StossComposed, StossHardening, StossRateTerm, StossThermalTerm};
    use stoss_kernel::eos::TabulatedCompaction;
    use stoss_kernel::Material;

    /// 4340's Johnson-Cook as composed terms (power hardening, `1 - T*^m`) with the rate
    /// term `rate` of kind `rate_model`.
    fn jc_4340_composed(rate_model: StossRateModel, rate: StossRateTerm) -> StossComposed {
        let jc = stoss_kernel::strength::JohnsonCook::STEEL_4340;
        StossComposed {
            hardening_model: StossHardeningModel::Power as i32,
            rate_model: rate_model as i32,
            thermal_model: StossThermalModel::HomologousPower as i32,
            reserved: 0,
            hardening: StossHardening {
                yield_stress: jc.yield_stress,
                hardening_modulus: jc.hardening_modulus,
                exponent: jc.hardening_exponent,
                ..StossHardening::default()
            },
            rate,
            thermal: StossThermalTerm {
                exponent: jc.thermal_exponent,
                reference_temperature: jc.reference_temperature,
                melting_temperature: jc.melting_temperature,
                ..StossThermalTerm::default()
            },
        }
    }

    fn round_trip(block: &StossMaterialBlock) -> Material {
        let material = block.to_material().unwrap();
        let (card, length) = card_from_block(block).unwrap();
        let parsed = block_from_card(&card[..length]).unwrap();
        assert_eq!(parsed.to_material().unwrap(), material);
        // Trailing zeros (an LS-DYNA card padded to 48) change nothing.
        let parsed = block_from_card(&card[..length.max(48)]).unwrap();
        assert_eq!(parsed.to_material().unwrap(), material);
        material
    }

    #[test]
    fn default_card_round_trips_and_puts_the_moduli_where_documented() {
        let block = StossMaterialBlock::steel_4340();
        let (card, length) = card_from_block(&block).unwrap();
        assert_eq!(length, STOSS_CARD_FIXED_LENGTH);
        assert_eq!(card[STOSS_CARD_SHEAR_MODULUS - 1], 81.8e9);
        assert_eq!(card[STOSS_CARD_BULK_MODULUS - 1], 159.0e9);
        assert_eq!(round_trip(&block), Material::STEEL_4340);
    }

    #[test]
    fn the_diagnosis_rate_terms_round_trip_and_a_version_1_card_still_reads() {
        // GOAL: a model the diagnosis accepts (JC + high-rate upturn, JC + rate-temperature
        //       coupling) is a card a foreign code can run (layout 2).
        // SETUP: 4340's JC as composed terms with each added rate term.
        // REFERENCE: the kernel material, through block -> card -> block; a card whose P1
        //            says 1 and holds only version-1 codes reads the same.
        let jc = stoss_kernel::strength::JohnsonCook::STEEL_4340;
        let mut block = StossMaterialBlock::steel_4340();
        block.strength_model = StossStrengthModel::Composed as i32;
        let composed = jc_4340_composed;
        block.strength.composed = composed(
            StossRateModel::LogUpturn,
            StossRateTerm {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                upturn_exponent: 0.08,
                upturn_rate: 2.0e3,
                ..StossRateTerm::default()
            },
        );
        round_trip(&block);
        let mut coupled = StossRateTerm {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            coupling: 2.0,
            coupling_reference_temperature: jc.reference_temperature,
            coupling_melting_temperature: jc.melting_temperature,
            ..StossRateTerm::default()
        };
        block.strength.composed = composed(StossRateModel::LogThermal, coupled);
        round_trip(&block);
        coupled.coupling_melting_temperature = 1700.0;
        block.strength.composed = composed(StossRateModel::LogThermal, coupled);
        let error = card_from_block(&block).unwrap_err();
        assert!(
            error.message.starts_with("card P40 (log-thermal"),
            "{}",
            error.message
        );

        let version_1 = StossMaterialBlock::steel_4340();
        let (mut card, length) = card_from_block(&version_1).unwrap();
        card[0] = 1.0;
        let parsed = block_from_card(&card[..length]).unwrap();
        assert_eq!(parsed.to_material().unwrap(), Material::STEEL_4340);
        card[0] = f64::from(STOSS_LAYOUT_VERSION + 1);
        assert_eq!(
            block_from_card(&card[..length]).unwrap_err().status,
            StossStatus::BadLayoutVersion
        );
    }

    #[test]
    fn the_thermal_drop_goes_through_the_block_and_a_card_refuses_it() {
        // GOAL: the thermal term with a second softening stage that the diagnosis adds
        //       (layout 4) reaches a foreign code through the block; a card, which has no
        //       slots for its three constants, refuses it by name instead of dropping them.
        // SETUP: 4340's JC as composed terms with a 25 % drop over 840-960 K.
        // REFERENCE: the kernel material, through block -> material -> block; the card's
        //            error names P27 (the composed thermal model) in both directions.
        let jc = stoss_kernel::strength::JohnsonCook::STEEL_4340;
        let mut block = StossMaterialBlock::steel_4340();
        block.strength_model = StossStrengthModel::Composed as i32;
        let mut composed = jc_4340_composed(
            StossRateModel::JohnsonCookLog,
            StossRateTerm {
                rate_sensitivity: jc.rate_sensitivity,
                reference_rate: jc.reference_rate,
                ..StossRateTerm::default()
            },
        );
        composed.thermal_model = StossThermalModel::HomologousPowerDrop as i32;
        composed.thermal.drop = 0.25;
        composed.thermal.drop_start_temperature = 840.0;
        composed.thermal.drop_end_temperature = 960.0;
        block.strength.composed = composed;
        let material = block.to_material().unwrap();
        let (exported, _) =
            crate::export::from_material(&material, block.initial_temperature).unwrap();
        assert_eq!(exported.to_material().unwrap(), material);
        assert_eq!(exported.strength.composed, block.strength.composed);
        let error = card_from_block(&block).unwrap_err();
        assert!(
            error
                .message
                .starts_with("card P27 (composed thermal model)"),
            "{}",
            error.message
        );
        let mut plain = block;
        plain.strength.composed.thermal_model = StossThermalModel::HomologousPower as i32;
        let (mut card, length) = card_from_block(&plain).unwrap();
        card[STRENGTH + 2] = f64::from(StossThermalModel::HomologousPowerDrop as i32);
        let error = block_from_card(&card[..length]).unwrap_err();
        assert!(
            error
                .message
                .starts_with("card P27 (composed thermal model)"),
            "{}",
            error.message
        );
    }

    #[test]
    fn every_eos_and_a_composed_strength_round_trip() {
        let mut block = StossMaterialBlock::steel_4340();
        block.failure.johnson_cook_enabled = 1;
        block.failure.erosion_enabled = 1;
        block.failure.erosion_plastic_strain = 1.5;
        block.failure.pressure_cutoff_enabled = 1;
        block.failure.pressure_cutoff = -1.0e9;
        block.strength_model = StossStrengthModel::Composed as i32;
        block.strength.composed = StossComposed {
            hardening_model: StossHardeningModel::PowerVoce2 as i32,
            rate_model: StossRateModel::CowperSymonds as i32,
            thermal_model: StossThermalModel::Linear as i32,
            reserved: 0,
            hardening: StossHardening {
                yield_stress: 300.0e6,
                hardening_modulus: 200.0e6,
                exponent: 0.5,
                saturation_stress_1: 50.0e6,
                saturation_rate_1: 10.0,
                saturation_stress_2: 20.0e6,
                saturation_rate_2: 100.0,
            },
            rate: StossRateTerm {
                cowper_symonds_d: 40.0,
                cowper_symonds_q: 5.0,
                ..StossRateTerm::default()
            },
            thermal: StossThermalTerm {
                exponent: 0.0,
                reference_temperature: 293.0,
                melting_temperature: 1800.0,
                ..StossThermalTerm::default()
            },
        };
        round_trip(&block);

        block.eos_model = StossEosModel::MieGruneisen as i32;
        block.eos.mie_gruneisen.reference_density = 7830.0;
        block.eos.mie_gruneisen.sound_speed = 4570.0;
        block.eos.mie_gruneisen.s1 = 1.49;
        block.eos.mie_gruneisen.gamma0 = 2.0;
        let material = round_trip(&block);
        let (card, _) = card_from_block(&block).unwrap();
        assert_eq!(card[3], 7830.0 * 4570.0 * 4570.0);
        assert_eq!(initial_bulk_modulus(&material.eos), card[3]);

        block.eos_model = StossEosModel::Polynomial as i32;
        block.eos.polynomial.a1 = 159.0e9;
        block.eos.polynomial.t1 = 159.0e9;
        block.eos.polynomial.b0 = 1.5;
        round_trip(&block);

        block.eos_model = StossEosModel::Jwl as i32;
        let c4 = stoss_kernel::eos::Jwl::C4;
        block.eos.jwl = crate::block::StossJwl {
            a: c4.a,
            b: c4.b,
            r1: c4.r1,
            r2: c4.r2,
            omega: c4.omega,
            reference_density: c4.reference_density,
            detonation_energy: c4.detonation_energy,
            detonation_velocity: c4.detonation_velocity,
            cj_pressure: c4.cj_pressure,
        };
        round_trip(&block);

        block.eos_model = StossEosModel::PAlpha as i32;
        block.eos.p_alpha.solid = block.eos.polynomial;
        block.eos.p_alpha.initial_distension = 1.2;
        block.eos.p_alpha.crush_pressure = 25.0e6;
        block.eos.p_alpha.lock_pressure = 3.0e9;
        block.eos.p_alpha.exponent = 3.0;
        round_trip(&block);

        block.eos_model = StossEosModel::TabulatedCompaction as i32;
        let table = TabulatedCompaction::CONCRETE_FOI_TABLE_5_2;
        let t = &mut block.eos.tabulated_compaction;
        t.point_count = table.points().len() as u32;
        for (i, point) in table.points().iter().enumerate() {
            t.volumetric_strain[i] = point.volumetric_strain;
            t.pressure[i] = point.pressure;
            t.unloading_bulk_modulus[i] = point.unloading_bulk_modulus;
        }
        let material = round_trip(&block);
        assert_eq!(material.eos, table.into());
        let (_, length) = card_from_block(&block).unwrap();
        assert_eq!(length, STOSS_CARD_FIXED_LENGTH + 1 + 3 * 8);
    }

    #[test]
    fn card_errors_name_the_slot() {
        let (card, length) = card_from_block(&StossMaterialBlock::steel_4340()).unwrap();
        let short = block_from_card(&card[..40]).unwrap_err();
        assert_eq!(short.status, StossStatus::InvalidParameter);
        assert!(short.message.contains("at least 41"), "{}", short.message);

        let mut bad = card;
        bad[0] = f64::from(STOSS_LAYOUT_VERSION + 1);
        assert_eq!(
            block_from_card(&bad[..length]).unwrap_err().status,
            StossStatus::BadLayoutVersion
        );
        let mut bad = card;
        bad[6] = 1.5;
        assert_eq!(
            block_from_card(&bad[..length]).unwrap_err().message,
            "card P7 (strength model): 1.5 is not an integer code"
        );
        let mut bad = card;
        bad[8] = StossEosModel::MieGruneisen as i32 as f64;
        let error = block_from_card(&bad[..length]).unwrap_err();
        assert!(error.message.contains("needs 48"), "{}", error.message);
        let mut bad = card;
        bad[13] = 16.0;
        assert!(block_from_card(&bad[..length])
            .unwrap_err()
            .message
            .starts_with("card P14"));
    }

    #[test]
    fn a_mechanical_threshold_stress_card_carries_its_tail_after_the_eos() {
        // GOAL: the MTS's 22 constants survive a card; a card cut before its tail is refused
        //       naming the slots.
        // SETUP: copper MTS over 4340's block (linear EoS: the tail is P42..P46).
        // REFERENCE: the block itself; the slot numbers of the layout.
        let mut block = StossMaterialBlock::steel_4340();
        block.strength_model = StossStrengthModel::MechanicalThresholdStress as i32;
        let mut model = stoss_kernel::strength::MechanicalThresholdStress::COPPER;
        crate::section::from_model(&mut model, &mut block.strength.mechanical_threshold_stress);
        let (card, length) = card_from_block(&block).unwrap();
        assert_eq!(length, 46);
        assert_eq!(card[24], 40.0e6);
        assert_eq!(card[41..46], [2.0, 47.7e9, 3.0e9, 180.0, 0.823e6]);
        let back = block_from_card(&card[..length]).unwrap();
        assert_eq!(
            back.strength.mechanical_threshold_stress,
            block.strength.mechanical_threshold_stress
        );
        let error = block_from_card(&card[..44]).unwrap_err();
        assert_eq!(error.status, StossStatus::InvalidParameter);
        assert!(error.message.contains("P42..P46"), "{}", error.message);
    }
}
