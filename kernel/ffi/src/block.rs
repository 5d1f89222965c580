//! The versioned, `#[repr(C)]` material parameter block a host fills once per material.
//!
//! The block names every family's constants in its own nested struct; the selectors
//! (`strength_model`, `eos_model`, ...) say which one is read. Fields of families that are not
//! selected are ignored. Selector value 0 is never valid, so a zero-filled block is rejected
//! with a message instead of silently meaning "Johnson-Cook".
//!
//! `layout_version` and `struct_size` are checked on every call that takes a block, before
//! anything else is read: a host compiled against another header gets
//! `STOSS_STATUS_BAD_LAYOUT_VERSION` / `STOSS_STATUS_BAD_STRUCT_SIZE`, never a misread.

use stoss_kernel::damage::{Failure, JohnsonCookFailure};
use stoss_kernel::eos::{
    CompactionPoint, Eos, Jwl, LinearEos, MieGruneisen, PAlpha, Polynomial, TabulatedCompaction,
    MAX_COMPACTION_POINTS,
};
use stoss_kernel::kc::{
    CrackBand, DamageFunction, KcMaterial, KcParameters, RateEnhancement, MAX_DAMAGE_POINTS,
};
use stoss_kernel::rht::{FailureMeridian, RateScaling, RhtMaterial, RhtParameters, TensileFailure};
use stoss_kernel::strength::{
    ComposedStrength, CrystalStructure, Hardening, JohnsonCook, KhanHuangLiang,
    MechanicalThresholdStress, ModifiedJohnsonCook, PrestonTonksWallace, RateTerm, Strength,
    ThermalTerm, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};
use stoss_kernel::{Heating, Material, MaterialState, PartMaterial, PointModel, RateTreatment};

use crate::section::{read_section, section_length, to_model};
use crate::status::{FfiError, StossStatus};
use stoss_kernel::ParameterError;

/// Version of [`StossMaterialBlock`]'s layout (and of the card layout, slot P1). Bumped on any
/// change of field order, size or meaning. Version 2 added the rate terms the diagnosis adds
/// to a Johnson-Cook fit ([`StossRateModel::LogUpturn`], [`StossRateModel::LogThermal`]) and
/// their five fields at the end of [`StossRateTerm`]; a version-1 card is a valid version-2
/// card (it cannot hold the new codes), a version-1 block is not (its size differs).
/// Version 3 added RHT concrete ([`StossStrengthModel::Rht`], [`StossRht`] at the end of
/// [`StossStrength`]); version-1 and -2 cards are valid version-3 cards.
/// Version 4 added the thermal term with a second softening stage the diagnosis adds
/// ([`StossThermalModel::HomologousPowerDrop`]) and its three fields at the end of
/// [`StossThermalTerm`]; cards of versions 1 to 3 are valid version-4 cards (a card cannot hold
/// the new term).
/// Version 5 added K&C concrete ([`StossStrengthModel::Kc`], [`StossKc`] at the end of
/// [`StossStrength`]); cards of versions 1 to 4 are valid version-5 cards.
/// Version 6 added Preston-Tonks-Wallace ([`StossStrengthModel::PrestonTonksWallace`],
/// [`StossPrestonTonksWallace`]) and Khan-Huang-Liang ([`StossStrengthModel::KhanHuangLiang`],
/// [`StossKhanHuangLiang`]) and Voce-Kocks ([`StossStrengthModel::VoceKocks`],
/// [`StossVoceKocks`]) at the end of [`StossStrength`]; cards of versions 1 to 5 are valid
/// version-6 cards.
/// Version 7 added the Mechanical Threshold Stress
/// ([`StossStrengthModel::MechanicalThresholdStress`], [`StossMechanicalThresholdStress`]) at
/// the end of [`StossStrength`]; its card takes P25..P41 and five slots after the EoS section.
/// Cards of versions 1 to 6 are valid version-7 cards.
pub const STOSS_LAYOUT_VERSION: u32 = 7;

/// Points of the tabulated-compaction EoS table in the block (the kernel's
/// `MAX_COMPACTION_POINTS`).
pub const STOSS_MAX_COMPACTION_POINTS: usize = 16;

const _: () = assert!(STOSS_MAX_COMPACTION_POINTS == MAX_COMPACTION_POINTS);

/// Points of the K&C damage function `eta(lambda)` in the block (the kernel's
/// `kc::MAX_DAMAGE_POINTS`).
pub const STOSS_KC_MAX_DAMAGE_POINTS: usize = 16;

const _: () = assert!(STOSS_KC_MAX_DAMAGE_POINTS == MAX_DAMAGE_POINTS);

/// Room for K&C's scalar constants in [`StossKc::constants`]: the family may gain constants up
/// to this many without a change of the block's size.
pub const STOSS_KC_MAX_CONSTANTS: usize = 16;

/// Number of K&C scalar constants the block holds: the kernel's descriptor
/// (`KcParameters::PARAMETERS`) without the shear modulus (the block's `shear_modulus`).
pub const KC_CONSTANTS: usize = section_length(KcParameters::PARAMETERS);

const _: () = assert!(
    KC_CONSTANTS <= STOSS_KC_MAX_CONSTANTS,
    "K&C has more constants than StossKc::constants holds: raise STOSS_KC_MAX_CONSTANTS \
     (a layout change)"
);

/// Flow-stress model (`StossMaterialBlock::strength_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossStrengthModel {
    /// Johnson-Cook, `strength.johnson_cook`.
    JohnsonCook = 1,
    /// Zerilli-Armstrong BCC, `strength.zerilli_armstrong`.
    ZerilliArmstrongBcc = 2,
    /// Zerilli-Armstrong FCC, `strength.zerilli_armstrong`.
    ZerilliArmstrongFcc = 3,
    /// Modified Johnson-Cook (power + two Voce, power-law rate), `strength.modified_johnson_cook`.
    ModifiedJohnsonCook = 4,
    /// Two-part-rate Johnson-Cook, `strength.two_rate_johnson_cook`.
    TwoRateJohnsonCook = 5,
    /// Free composition of hardening x rate x thermal terms, `strength.composed`.
    Composed = 6,
    /// RHT concrete (Riedel-Hiermaier-Thoma, seed 001 chapter 4), `strength.rht`, over the
    /// block's EoS (P-alpha for the elastic cap); not a J2 metal: heating must be isothermal,
    /// the rate treatment implicit and Johnson-Cook failure and the pressure cut-off off
    /// (RHT has its own damage and tensile limit). Layout 3.
    Rht = 7,
    /// K&C concrete (Karagozian & Case release III, seed 001 chapter 5), `strength.kc`, over
    /// the block's EoS (seed 001 uses tabulated compaction); not a J2 metal: heating must be
    /// isothermal, the rate treatment implicit, and Johnson-Cook failure, erosion and the
    /// pressure cut-off off (K&C has its own damage and tensile cut-off). Layout 5.
    Kc = 8,
    /// Preston-Tonks-Wallace, `strength.preston_tonks_wallace`. Layout 6.
    PrestonTonksWallace = 9,
    /// Khan-Huang-Liang, `strength.khan_huang_liang`. Layout 6.
    KhanHuangLiang = 10,
    /// Voce-Kocks, `strength.voce_kocks`. Layout 6.
    VoceKocks = 11,
    /// Mechanical Threshold Stress (Follansbee-Kocks), `strength.mechanical_threshold_stress`.
    /// Layout 7.
    MechanicalThresholdStress = 12,
}

/// K&C rate enhancement (`StossKc::rate`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossKcRate {
    /// Rate independent.
    None = 1,
    /// CEB-FIP dynamic increase factors (compression and tension, blended in between).
    CebFip = 2,
}

/// RHT tensile failure (`StossRht::tensile_failure`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossRhtTensileFailure {
    /// Autodyn's hydro tensile limit: the point fails when its pressure would fall below
    /// `p_min` (seed 001 table 4.4).
    HydroTensileLimit = 1,
    /// LS-DYNA `*MAT_RHT`: the pressure is held at `p_min`, damage grows from plastic strain.
    PressureCutoff = 2,
    /// Autodyn "principal stress": fails when the largest principal stress reaches `F_t ft`.
    PrincipalStress = 3,
}

/// Shape of the RHT compressive meridian at low pressure (`StossRht::meridian`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossRhtMeridian {
    /// Seed eq. 4.1 over the whole pressure range, `A (p* - p*_spall)^N`.
    PowerLaw = 1,
    /// Through the characteristic points `FT*`, `FS*`, 1 at low pressure (Autodyn's option).
    CharacteristicPoints = 2,
}

/// How the RHT rate factor enters the failure surface (`StossRht::rate_scaling`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossRhtRateScaling {
    /// Seed eqs. 4.1 and 4.5 as printed (Autodyn 4.2).
    SeedEquation = 1,
    /// The meridian scaled homothetically (Riedel 2000, LS-DYNA `*MAT_RHT`).
    Homothetic = 2,
}

/// Hardening term of a composed model (`StossComposed::hardening_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossHardeningModel {
    /// `A + B eps^n`.
    Power = 1,
    /// `A + Q1 (1 - exp(-c1 eps)) + Q2 (1 - exp(-c2 eps))`.
    Voce2 = 2,
    /// `A + B eps^n + Q1 (1 - exp(-c1 eps)) + Q2 (1 - exp(-c2 eps))`.
    PowerVoce2 = 3,
}

/// Rate term of a composed model (`StossComposed::rate_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossRateModel {
    /// Rate independent.
    None = 1,
    /// `1 + C ln(rate/e0)` (1 below `e0`): `rate_sensitivity`, `reference_rate`.
    JohnsonCookLog = 2,
    /// `(1 + rate/e0)^beta`: `exponent`, `reference_rate`.
    Power = 3,
    /// `(1 + rate/e01)^beta1 (1 + rate/e02)^beta2`: `exponent`, `reference_rate`,
    /// `exponent_2`, `reference_rate_2`.
    TwoPart = 4,
    /// `1 + (rate/D)^(1/q)`: `cowper_symonds_d`, `cowper_symonds_q`.
    CowperSymonds = 5,
    /// JC log with a high-rate upturn, `(1 + C ln(rate/e0)) (1 + rate/e_up)^beta`:
    /// `rate_sensitivity`, `reference_rate`, `upturn_exponent`, `upturn_rate` (layout 2).
    LogUpturn = 6,
    /// JC log with a temperature-dependent sensitivity, `1 + C (1 + kappa T*) ln(rate/e0)`:
    /// `rate_sensitivity`, `reference_rate`, `coupling`, `coupling_reference_temperature`,
    /// `coupling_melting_temperature` (layout 2).
    LogThermal = 7,
}

/// Thermal term of a composed model (`StossComposed::thermal_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossThermalModel {
    /// No thermal softening.
    None = 1,
    /// `1 - T*^m`.
    HomologousPower = 2,
    /// `1 - T*`.
    Linear = 3,
    /// `(1 - T*^m)(1 - d S(T))`: Johnson-Cook with a second softening stage (the fields
    /// `drop`, `drop_start_temperature`, `drop_end_temperature`; layout 4). Block only: a
    /// card has no slots for it.
    HomologousPowerDrop = 4,
}

/// Plastic-work heating (`StossMaterialBlock::heating_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossHeatingModel {
    /// Temperature stays constant.
    Isothermal = 1,
    /// `dT = chi sigma_y deps_p / (rho c_p)`, `heating.taylor_quinney`.
    Adiabatic = 2,
    /// Rate-dependent isothermal-to-adiabatic transition (all three `heating` fields).
    Transition = 3,
}

/// Rate in the flow stress (`StossMaterialBlock::rate_treatment`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossRateTreatment {
    /// Implicit in strain and rate (seed 001 eq. 3.8).
    Implicit = 1,
    /// Rate lagged by one step (seed 001 eq. 3.7; reproduces the rate-insensitivity defect).
    Lagged = 2,
}

/// Equation of state (`StossMaterialBlock::eos_model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StossEosModel {
    /// `p = K mu`, `eos.linear`.
    Linear = 1,
    /// Mie-Grüneisen (LS-DYNA `*EOS_GRUNEISEN` form), `eos.mie_gruneisen`.
    MieGruneisen = 2,
    /// Polynomial, `eos.polynomial`.
    Polynomial = 3,
    /// Jones-Wilkins-Lee, `eos.jwl`.
    Jwl = 4,
    /// Tabulated compaction, `eos.tabulated_compaction`.
    TabulatedCompaction = 5,
    /// P-alpha porous compaction over a polynomial matrix, `eos.p_alpha`.
    PAlpha = 6,
}

/// Heating constants (read according to `heating_model`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossHeating {
    /// Taylor-Quinney coefficient `chi` in [0, 1] (adiabatic, transition).
    pub taylor_quinney: f64,
    /// Rate below which heating is off (1/s, transition).
    pub isothermal_rate: f64,
    /// Rate above which heating is fully adiabatic (1/s, transition).
    pub adiabatic_rate: f64,
}

/// Johnson-Cook constants (SI).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossJohnsonCook {
    /// `A` (Pa).
    pub yield_stress: f64,
    /// `B` (Pa).
    pub hardening_modulus: f64,
    /// `n` (-).
    pub hardening_exponent: f64,
    /// `C` (-).
    pub rate_sensitivity: f64,
    /// `m` (-).
    pub thermal_exponent: f64,
    /// `e0` (1/s).
    pub reference_rate: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
}

crate::described_section!(
    StossJohnsonCook,
    JohnsonCook,
    [
        yield_stress,
        hardening_modulus,
        hardening_exponent,
        rate_sensitivity,
        thermal_exponent,
        reference_rate,
        reference_temperature,
        melting_temperature,
    ]
);

/// Zerilli-Armstrong constants (SI); BCC or FCC is chosen by `strength_model`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossZerilliArmstrong {
    /// `sigma_a` (Pa).
    pub athermal_stress: f64,
    /// `C1` (Pa), BCC.
    pub c1: f64,
    /// `C2` (Pa), FCC.
    pub c2: f64,
    /// `C3` (1/K).
    pub c3: f64,
    /// `C4` (1/K).
    pub c4: f64,
    /// `C5` (Pa), BCC.
    pub c5: f64,
    /// `n` (-), BCC.
    pub exponent: f64,
    /// `e0` (1/s).
    pub reference_rate: f64,
}

crate::described_section!(
    StossZerilliArmstrong,
    ZerilliArmstrong,
    [
        athermal_stress,
        c1,
        c2,
        c3,
        c4,
        c5,
        exponent,
        reference_rate,
    ]
);

/// Modified Johnson-Cook constants (SI).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossModifiedJohnsonCook {
    /// `A` (Pa).
    pub yield_stress: f64,
    /// `B` (Pa).
    pub hardening_modulus: f64,
    /// `n` (-).
    pub hardening_exponent: f64,
    /// `Q1` (Pa).
    pub saturation_stress_1: f64,
    /// `c1` (-).
    pub saturation_rate_1: f64,
    /// `Q2` (Pa).
    pub saturation_stress_2: f64,
    /// `c2` (-).
    pub saturation_rate_2: f64,
    /// `beta` (-).
    pub rate_exponent: f64,
    /// `e0` (1/s).
    pub reference_rate: f64,
    /// `m` (-).
    pub thermal_exponent: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
}

crate::described_section!(
    StossModifiedJohnsonCook,
    ModifiedJohnsonCook,
    [
        yield_stress,
        hardening_modulus,
        hardening_exponent,
        saturation_stress_1,
        saturation_rate_1,
        saturation_stress_2,
        saturation_rate_2,
        rate_exponent,
        reference_rate,
        thermal_exponent,
        reference_temperature,
        melting_temperature,
    ]
);

/// Two-part-rate Johnson-Cook constants (SI).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossTwoRateJohnsonCook {
    /// `A` (Pa).
    pub yield_stress: f64,
    /// `B` (Pa).
    pub hardening_modulus: f64,
    /// `n` (-).
    pub hardening_exponent: f64,
    /// `Q1` (Pa).
    pub saturation_stress_1: f64,
    /// `c1` (-).
    pub saturation_rate_1: f64,
    /// `Q2` (Pa).
    pub saturation_stress_2: f64,
    /// `c2` (-).
    pub saturation_rate_2: f64,
    /// `beta1` (-).
    pub rate_exponent_1: f64,
    /// `e01` (1/s).
    pub reference_rate_1: f64,
    /// `beta2` (-).
    pub rate_exponent_2: f64,
    /// `e02` (1/s).
    pub reference_rate_2: f64,
    /// `m` (-).
    pub thermal_exponent: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
}

crate::described_section!(
    StossTwoRateJohnsonCook,
    TwoRateJohnsonCook,
    [
        yield_stress,
        hardening_modulus,
        hardening_exponent,
        saturation_stress_1,
        saturation_rate_1,
        saturation_stress_2,
        saturation_rate_2,
        rate_exponent_1,
        reference_rate_1,
        rate_exponent_2,
        reference_rate_2,
        thermal_exponent,
        reference_temperature,
        melting_temperature,
    ]
);

/// Preston-Tonks-Wallace constants (SI; the scaled stresses dimensionless).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossPrestonTonksWallace {
    /// `theta` (-).
    pub theta: f64,
    /// `p` (-).
    pub p: f64,
    /// `s0` (-).
    pub s0: f64,
    /// `s_inf` (-).
    pub s_inf: f64,
    /// `kappa` (-).
    pub kappa: f64,
    /// `gamma` (-).
    pub gamma: f64,
    /// `y0` (-).
    pub y0: f64,
    /// `y_inf` (-).
    pub y_inf: f64,
    /// `y1` (-).
    pub y1: f64,
    /// `y2` (-).
    pub y2: f64,
    /// `beta` (-).
    pub beta: f64,
    /// `G0` (Pa), shear modulus at 0 K in the flow stress.
    pub shear_modulus_0: f64,
    /// `alpha` (-), its softening with `T / Tm`.
    pub alpha: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
    /// `rho` (kg/m^3) in the atomic vibration rate.
    pub density: f64,
    /// `M` (g/mol), atomic mass.
    pub atomic_mass: f64,
}

crate::described_section!(
    StossPrestonTonksWallace,
    PrestonTonksWallace,
    [
        theta,
        p,
        s0,
        s_inf,
        kappa,
        gamma,
        y0,
        y_inf,
        y1,
        y2,
        beta,
        shear_modulus_0,
        alpha,
        melting_temperature,
        density,
        atomic_mass,
    ]
);

/// Khan-Huang-Liang constants (SI).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossKhanHuangLiang {
    /// `A` (Pa).
    pub yield_stress: f64,
    /// `B` (Pa).
    pub hardening_modulus: f64,
    /// `n0` (-).
    pub hardening_exponent: f64,
    /// `n1` (-), exponent of the rate coupling `(1 - ln(rate)/ln(D0p))`.
    pub coupling_exponent: f64,
    /// `C` (-).
    pub rate_sensitivity: f64,
    /// `e0` (1/s).
    pub reference_rate: f64,
    /// `D0p` (1/s), upper bound of the strain rates.
    pub upper_rate: f64,
    /// `m` (-).
    pub thermal_exponent: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
}

crate::described_section!(
    StossKhanHuangLiang,
    KhanHuangLiang,
    [
        yield_stress,
        hardening_modulus,
        hardening_exponent,
        coupling_exponent,
        rate_sensitivity,
        reference_rate,
        upper_rate,
        thermal_exponent,
        reference_temperature,
        melting_temperature,
    ]
);

/// Voce-Kocks constants (SI).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossVoceKocks {
    /// `sigma_0` (Pa).
    pub yield_stress: f64,
    /// `theta_0` (Pa).
    pub initial_hardening: f64,
    /// `sigma_s0` (Pa).
    pub saturation_stress: f64,
    /// `e_s0` (1/s).
    pub saturation_reference_rate: f64,
    /// `T_A` (K).
    pub activation_temperature: f64,
}

crate::described_section!(
    StossVoceKocks,
    VoceKocks,
    [
        yield_stress,
        initial_hardening,
        saturation_stress,
        saturation_reference_rate,
        activation_temperature,
    ]
);

/// Mechanical Threshold Stress constants (SI; Follansbee & Kocks' names).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossMechanicalThresholdStress {
    /// `sigma_a` (Pa).
    pub athermal_stress: f64,
    /// `sigma_i` (Pa); 0 switches the intrinsic term off.
    pub intrinsic_stress: f64,
    /// `g_0i` (-).
    pub intrinsic_activation_energy: f64,
    /// `e_0i` (1/s).
    pub intrinsic_reference_rate: f64,
    /// `p_i` (-).
    pub intrinsic_p: f64,
    /// `q_i` (-).
    pub intrinsic_q: f64,
    /// `g_0e` (-).
    pub structure_activation_energy: f64,
    /// `e_0e` (1/s).
    pub structure_reference_rate: f64,
    /// `p_e` (-).
    pub structure_p: f64,
    /// `q_e` (-).
    pub structure_q: f64,
    /// `sigma_es0` (Pa).
    pub saturation_stress: f64,
    /// `g_0es` (-).
    pub saturation_activation_energy: f64,
    /// `e_es0` (1/s).
    pub saturation_reference_rate: f64,
    /// `a_0` (Pa).
    pub hardening_a0: f64,
    /// `a_1` (Pa).
    pub hardening_a1: f64,
    /// `a_2` (Pa).
    pub hardening_a2: f64,
    /// `a_3` (Pa/K).
    pub hardening_a3: f64,
    /// `alpha` (-).
    pub hardening_shape: f64,
    /// `mu_0` (Pa).
    pub shear_modulus_0: f64,
    /// Varshni's `D` (Pa).
    pub shear_modulus_drop: f64,
    /// Varshni's `T_0` (K).
    pub varshni_temperature: f64,
    /// `k/b^3` (Pa/K).
    pub boltzmann_per_burgers_cubed: f64,
}

crate::described_section!(
    StossMechanicalThresholdStress,
    MechanicalThresholdStress,
    [
        athermal_stress,
        intrinsic_stress,
        intrinsic_activation_energy,
        intrinsic_reference_rate,
        intrinsic_p,
        intrinsic_q,
        structure_activation_energy,
        structure_reference_rate,
        structure_p,
        structure_q,
        saturation_stress,
        saturation_activation_energy,
        saturation_reference_rate,
        hardening_a0,
        hardening_a1,
        hardening_a2,
        hardening_a3,
        hardening_shape,
        shear_modulus_0,
        shear_modulus_drop,
        varshni_temperature,
        boltzmann_per_burgers_cubed,
    ]
);

/// Hardening constants of a composed model (read according to `hardening_model`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossHardening {
    /// `A` (Pa).
    pub yield_stress: f64,
    /// `B` (Pa), power and power+Voce.
    pub hardening_modulus: f64,
    /// `n` (-), power and power+Voce.
    pub exponent: f64,
    /// `Q1` (Pa).
    pub saturation_stress_1: f64,
    /// `c1` (-).
    pub saturation_rate_1: f64,
    /// `Q2` (Pa).
    pub saturation_stress_2: f64,
    /// `c2` (-).
    pub saturation_rate_2: f64,
}

/// Rate constants of a composed model (read according to `rate_model`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossRateTerm {
    /// `C` (-), JC log.
    pub rate_sensitivity: f64,
    /// `beta` / `beta1` (-), power and two-part.
    pub exponent: f64,
    /// `e0` / `e01` (1/s), JC log, power, two-part.
    pub reference_rate: f64,
    /// `beta2` (-), two-part.
    pub exponent_2: f64,
    /// `e02` (1/s), two-part.
    pub reference_rate_2: f64,
    /// Cowper-Symonds `D` (1/s).
    pub cowper_symonds_d: f64,
    /// Cowper-Symonds `q` (-).
    pub cowper_symonds_q: f64,
    /// Upturn exponent `beta` (-), log-upturn.
    pub upturn_exponent: f64,
    /// Upturn rate `e_up` (1/s), log-upturn.
    pub upturn_rate: f64,
    /// Rate-temperature coupling `kappa` (-), log-thermal.
    pub coupling: f64,
    /// `Tr` (K) of the log-thermal `T*`.
    pub coupling_reference_temperature: f64,
    /// `Tm` (K) of the log-thermal `T*`.
    pub coupling_melting_temperature: f64,
}

/// Thermal constants of a composed model (read according to `thermal_model`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossThermalTerm {
    /// `m` (-), homologous power.
    pub exponent: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
    /// Strength fraction `d` lost in the drop (-), homologous power with drop.
    pub drop: f64,
    /// Temperature `Ts` where the drop starts (K).
    pub drop_start_temperature: f64,
    /// Temperature `Te` where the drop ends (K).
    pub drop_end_temperature: f64,
}

/// A composed flow stress `hardening(eps_p) * rate(deps_p) * thermal(T)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossComposed {
    /// [`StossHardeningModel`] code.
    pub hardening_model: i32,
    /// [`StossRateModel`] code.
    pub rate_model: i32,
    /// [`StossThermalModel`] code.
    pub thermal_model: i32,
    /// Padding; set to 0.
    pub reserved: i32,
    /// Hardening constants.
    pub hardening: StossHardening,
    /// Rate constants.
    pub rate: StossRateTerm,
    /// Thermal constants.
    pub thermal: StossThermalTerm,
}

/// RHT concrete constants (SI; seed 001 table 4.1 names, Autodyn names in brackets). The
/// shear modulus is the block's `shear_modulus`, the density its `density` (the porous
/// reference density).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossRht {
    /// [`StossRhtTensileFailure`] code.
    pub tensile_failure: i32,
    /// [`StossRhtMeridian`] code.
    pub meridian: i32,
    /// [`StossRhtRateScaling`] code.
    pub rate_scaling: i32,
    /// Cap on the elastic surface at the P-alpha crush pressure: 0 or 1.
    pub elastic_cap: u32,
    /// Uniaxial compressive strength `f'c` (Pa).
    pub compressive_strength: f64,
    /// `FT* = ft/fc` (-).
    pub tensile_strength_ratio: f64,
    /// `FS* = fs/fc` (-).
    pub shear_strength_ratio: f64,
    /// Failure surface constant `A` (-).
    pub failure_a: f64,
    /// Failure surface exponent `N` (-).
    pub failure_n: f64,
    /// Tensile-to-compressive meridian ratio `Q2,0` (-).
    pub tensile_meridian_ratio: f64,
    /// Brittle-to-ductile transition `BQ` (-).
    pub brittle_ductile_transition: f64,
    /// `PREFACT` (-), `>= 1`.
    pub shear_modulus_ratio: f64,
    /// `TENSRAT` (-).
    pub tensile_elastic_ratio: f64,
    /// `COMPRAT` (-).
    pub compressive_elastic_ratio: f64,
    /// Residual surface constant `B` (-).
    pub residual_b: f64,
    /// Residual surface exponent `M` (-).
    pub residual_m: f64,
    /// Compressive rate exponent `alpha` (-).
    pub compressive_rate_exponent: f64,
    /// Tensile rate exponent `delta` (-).
    pub tensile_rate_exponent: f64,
    /// Compressive reference strain rate (1/s).
    pub compressive_reference_rate: f64,
    /// Tensile reference strain rate (1/s).
    pub tensile_reference_rate: f64,
    /// Damage constant `D1` (-).
    pub damage_d1: f64,
    /// Damage exponent `D2` (-).
    pub damage_d2: f64,
    /// Minimum plastic strain to failure `EFMIN` (-).
    pub minimum_failure_strain: f64,
    /// `SHRATD` (-).
    pub residual_shear_modulus_ratio: f64,
}

crate::described_section!(
    StossRht,
    RhtParameters,
    [
        compressive_strength,
        tensile_strength_ratio,
        shear_strength_ratio,
        failure_a,
        failure_n,
        tensile_meridian_ratio,
        brittle_ductile_transition,
        shear_modulus_ratio,
        tensile_elastic_ratio,
        compressive_elastic_ratio,
        residual_b,
        residual_m,
        compressive_rate_exponent,
        tensile_rate_exponent,
        compressive_reference_rate,
        tensile_reference_rate,
        damage_d1,
        damage_d2,
        minimum_failure_strain,
        residual_shear_modulus_ratio,
    ]
);

/// K&C concrete constants (SI). The shear modulus is the block's `shear_modulus`, the
/// density its `density`.
///
/// `constants` holds the family's scalar constants in the order of the kernel's descriptor
/// (`KcParameters::PARAMETERS` in kernel/src/kc/parameters.rs, without the shear modulus;
/// docs/user-material.md lists them); the slots past them are ignored (set them to 0). The surfaces are `Delta sigma = a0 + p/(a1 + a2 p)` (maximum,
/// yield) and `p/(a1f + a2f p)` (residual).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossKc {
    /// [`StossKcRate`] code.
    pub rate: i32,
    /// 1: crack band on (`crack_band_reference_width`, `crack_band_width`); 0: off.
    pub crack_band_enabled: u32,
    /// Points of the damage function used, 2..=16.
    pub damage_point_count: u32,
    /// Padding; set to 0.
    pub reserved: u32,
    /// Maximum surface `a0` (Pa), `a1` (-), `a2` (1/Pa).
    pub maximum_surface: [f64; 3],
    /// Yield surface `a0y` (Pa), `a1y` (-), `a2y` (1/Pa).
    pub yield_surface: [f64; 3],
    /// Residual surface `a1f` (-), `a2f` (1/Pa).
    pub residual_surface: [f64; 2],
    /// Damage function: damage parameter `lambda` of each point (-), first 0, increasing.
    pub damage_lambda: [f64; STOSS_KC_MAX_DAMAGE_POINTS],
    /// Damage function: `eta` of each point (-), from 0 up to 1 at the peak, then down.
    pub damage_eta: [f64; STOSS_KC_MAX_DAMAGE_POINTS],
    /// Crack band: the element size at which the softening is the table's own (m).
    pub crack_band_reference_width: f64,
    /// Crack band: the element size of this material's elements (m).
    pub crack_band_width: f64,
    /// The scalar constants in the descriptor's order (see above).
    pub constants: [f64; STOSS_KC_MAX_CONSTANTS],
}

/// Constants of every strength family; `strength_model` says which one is read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossStrength {
    /// Johnson-Cook.
    pub johnson_cook: StossJohnsonCook,
    /// Zerilli-Armstrong (BCC and FCC).
    pub zerilli_armstrong: StossZerilliArmstrong,
    /// Modified Johnson-Cook.
    pub modified_johnson_cook: StossModifiedJohnsonCook,
    /// Two-part-rate Johnson-Cook.
    pub two_rate_johnson_cook: StossTwoRateJohnsonCook,
    /// Free composition.
    pub composed: StossComposed,
    /// RHT concrete (layout 3).
    pub rht: StossRht,
    /// K&C concrete (layout 5).
    pub kc: StossKc,
    /// Preston-Tonks-Wallace (layout 6).
    pub preston_tonks_wallace: StossPrestonTonksWallace,
    /// Khan-Huang-Liang (layout 6).
    pub khan_huang_liang: StossKhanHuangLiang,
    /// Voce-Kocks (layout 6).
    pub voce_kocks: StossVoceKocks,
    /// Mechanical Threshold Stress (layout 7).
    pub mechanical_threshold_stress: StossMechanicalThresholdStress,
}

/// Linear EoS.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossLinearEos {
    /// `K` (Pa).
    pub bulk_modulus: f64,
}

/// Mie-Grüneisen EoS (LS-DYNA `*EOS_GRUNEISEN` form).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossMieGruneisen {
    /// `rho0` (kg/m^3).
    pub reference_density: f64,
    /// `C` (m/s).
    pub sound_speed: f64,
    /// `S1` (-).
    pub s1: f64,
    /// `S2` (-).
    pub s2: f64,
    /// `S3` (-).
    pub s3: f64,
    /// `gamma0` (-).
    pub gamma0: f64,
    /// `a` (-).
    pub volume_correction: f64,
}

/// Polynomial EoS.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossPolynomial {
    /// `A1` (Pa).
    pub a1: f64,
    /// `A2` (Pa).
    pub a2: f64,
    /// `A3` (Pa).
    pub a3: f64,
    /// `B0` (-).
    pub b0: f64,
    /// `B1` (-).
    pub b1: f64,
    /// `T1` (Pa).
    pub t1: f64,
    /// `T2` (Pa).
    pub t2: f64,
}

/// JWL EoS.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossJwl {
    /// `A` (Pa).
    pub a: f64,
    /// `B` (Pa).
    pub b: f64,
    /// `R1` (-).
    pub r1: f64,
    /// `R2` (-).
    pub r2: f64,
    /// `omega` (-).
    pub omega: f64,
    /// `rho0` (kg/m^3).
    pub reference_density: f64,
    /// `E0` (J/m^3 of reference volume).
    pub detonation_energy: f64,
    /// CJ detonation velocity (m/s), informative.
    pub detonation_velocity: f64,
    /// CJ pressure (Pa), informative.
    pub cj_pressure: f64,
}

/// Tabulated compaction EoS: `point_count` points (2 to 16) of (`eps = -ln V`, `p`, `K_unload`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossTabulatedCompaction {
    /// Number of points used, 2..=16.
    pub point_count: u32,
    /// Padding; set to 0.
    pub reserved: u32,
    /// Volumetric strain `-ln V` of each point (-), first 0, increasing.
    pub volumetric_strain: [f64; 16],
    /// Loading pressure of each point (Pa).
    pub pressure: [f64; 16],
    /// Unloading bulk modulus of each point (Pa).
    pub unloading_bulk_modulus: [f64; 16],
}

/// P-alpha EoS over a polynomial matrix.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossPAlpha {
    /// Matrix EoS.
    pub solid: StossPolynomial,
    /// `alpha0 >= 1` (-).
    pub initial_distension: f64,
    /// Crush pressure (Pa).
    pub crush_pressure: f64,
    /// Lock (full compaction) pressure (Pa).
    pub lock_pressure: f64,
    /// Compaction exponent `n` (-).
    pub exponent: f64,
}

/// Constants of every EoS; `eos_model` says which one is read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossEos {
    /// Linear.
    pub linear: StossLinearEos,
    /// Mie-Grüneisen.
    pub mie_gruneisen: StossMieGruneisen,
    /// Polynomial.
    pub polynomial: StossPolynomial,
    /// JWL.
    pub jwl: StossJwl,
    /// Tabulated compaction.
    pub tabulated_compaction: StossTabulatedCompaction,
    /// P-alpha.
    pub p_alpha: StossPAlpha,
}

/// Johnson-Cook failure constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossJohnsonCookFailure {
    /// `D1` (-).
    pub d1: f64,
    /// `D2` (-).
    pub d2: f64,
    /// `D3` (-).
    pub d3: f64,
    /// `D4` (-).
    pub d4: f64,
    /// `D5` (-).
    pub d5: f64,
    /// `e0` (1/s).
    pub reference_rate: f64,
    /// `Tr` (K).
    pub reference_temperature: f64,
    /// `Tm` (K).
    pub melting_temperature: f64,
}

/// Damage, failure and erosion. The four switches are 0 (off) or 1 (on).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossFailure {
    /// 1: cumulative Johnson-Cook damage with `johnson_cook`.
    pub johnson_cook_enabled: u32,
    /// 1: erode (not only fail) when damage reaches 1.
    pub erode_on_failure: u32,
    /// 1: erode when `eps_p >= erosion_plastic_strain`.
    pub erosion_enabled: u32,
    /// 1: hold the pressure of intact material at or above `pressure_cutoff`.
    pub pressure_cutoff_enabled: u32,
    /// Erosion plastic strain (-), used if `erosion_enabled`.
    pub erosion_plastic_strain: f64,
    /// Hydrodynamic tensile limit `p_min <= 0` (Pa), used if `pressure_cutoff_enabled`.
    pub pressure_cutoff: f64,
    /// Johnson-Cook failure constants.
    pub johnson_cook: StossJohnsonCookFailure,
}

/// A complete material for the C ABI. Fill it once (e.g. start from
/// `stoss_material_defaults_4340`), check it with `stoss_material_validate`, then pass it to
/// every update call. SI units throughout.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StossMaterialBlock {
    /// Must be `STOSS_LAYOUT_VERSION`.
    pub layout_version: u32,
    /// Must be `sizeof(StossMaterialBlock)`.
    pub struct_size: u32,
    /// [`StossStrengthModel`] code.
    pub strength_model: i32,
    /// [`StossRateTreatment`] code.
    pub rate_treatment: i32,
    /// [`StossEosModel`] code.
    pub eos_model: i32,
    /// [`StossHeatingModel`] code.
    pub heating_model: i32,
    /// Reference density `rho0` (kg/m^3).
    pub density: f64,
    /// Shear modulus `G` (Pa).
    pub shear_modulus: f64,
    /// Specific heat `c_p` (J/kg/K).
    pub specific_heat: f64,
    /// Temperature of the initial state (K), used by `stoss_state_init` and by the adapters
    /// for history arrays the host zero-initialised.
    pub initial_temperature: f64,
    /// Heating constants.
    pub heating: StossHeating,
    /// Strength constants.
    pub strength: StossStrength,
    /// EoS constants.
    pub eos: StossEos,
    /// Failure constants.
    pub failure: StossFailure,
}

/// `size_of::<StossMaterialBlock>()` as stored in `struct_size`.
pub(crate) const BLOCK_SIZE: u32 = std::mem::size_of::<StossMaterialBlock>() as u32;

const _: () = assert!(std::mem::size_of::<StossMaterialBlock>() < u32::MAX as usize);

/// A J2 strength family read from its section, with its validation's outcome, as the block's
/// strength and the section's name; a validation error names the section.
fn described<M: Into<Strength>>(
    validated: Result<M, ParameterError>,
    section: &'static str,
) -> Result<(Strength, &'static str), FfiError> {
    let model = validated.map_err(|e| FfiError::parameter(section, e))?;
    Ok((model.into(), section))
}

fn invalid(field: &str, message: impl std::fmt::Display) -> FfiError {
    FfiError::new(StossStatus::InvalidParameter, format!("{field}: {message}"))
}

fn switch(field: &str, value: u32) -> Result<bool, FfiError> {
    match value {
        0 => Ok(false),
        1 => Ok(true),
        other => Err(invalid(field, format_args!("must be 0 or 1, got {other}"))),
    }
}

macro_rules! code_enum {
    ($name:ident, $field:literal, [$($variant:ident),+ $(,)?]) => {
        impl $name {
            /// The variant with code `code`, or an `INVALID_PARAMETER` error naming the field.
            pub fn from_code(code: i32) -> Result<Self, FfiError> {
                $(if code == $name::$variant as i32 {
                    return Ok($name::$variant);
                })+
                Err(invalid($field, format_args!("unknown code {code}")))
            }
        }
    };
}

code_enum!(
    StossStrengthModel,
    "strength_model",
    [
        JohnsonCook,
        ZerilliArmstrongBcc,
        ZerilliArmstrongFcc,
        ModifiedJohnsonCook,
        TwoRateJohnsonCook,
        Composed,
        Rht,
        Kc,
        PrestonTonksWallace,
        KhanHuangLiang,
        VoceKocks,
        MechanicalThresholdStress
    ]
);
code_enum!(StossKcRate, "strength.kc.rate", [None, CebFip]);
code_enum!(
    StossRhtTensileFailure,
    "strength.rht.tensile_failure",
    [HydroTensileLimit, PressureCutoff, PrincipalStress]
);
code_enum!(
    StossRhtMeridian,
    "strength.rht.meridian",
    [PowerLaw, CharacteristicPoints]
);
code_enum!(
    StossRhtRateScaling,
    "strength.rht.rate_scaling",
    [SeedEquation, Homothetic]
);
code_enum!(
    StossHardeningModel,
    "strength.composed.hardening_model",
    [Power, Voce2, PowerVoce2]
);
code_enum!(
    StossRateModel,
    "strength.composed.rate_model",
    [
        None,
        JohnsonCookLog,
        Power,
        TwoPart,
        CowperSymonds,
        LogUpturn,
        LogThermal
    ]
);
code_enum!(
    StossThermalModel,
    "strength.composed.thermal_model",
    [None, HomologousPower, Linear, HomologousPowerDrop]
);
code_enum!(
    StossHeatingModel,
    "heating_model",
    [Isothermal, Adiabatic, Transition]
);
code_enum!(StossRateTreatment, "rate_treatment", [Implicit, Lagged]);
code_enum!(
    StossEosModel,
    "eos_model",
    [
        Linear,
        MieGruneisen,
        Polynomial,
        Jwl,
        TabulatedCompaction,
        PAlpha
    ]
);

impl StossPolynomial {
    fn to_kernel(self) -> Polynomial {
        Polynomial {
            a1: self.a1,
            a2: self.a2,
            a3: self.a3,
            b0: self.b0,
            b1: self.b1,
            t1: self.t1,
            t2: self.t2,
        }
    }
}

impl StossComposed {
    fn to_kernel(self) -> Result<ComposedStrength, FfiError> {
        let h = self.hardening;
        let hardening = match StossHardeningModel::from_code(self.hardening_model)? {
            StossHardeningModel::Power => Hardening::Power {
                yield_stress: h.yield_stress,
                hardening_modulus: h.hardening_modulus,
                exponent: h.exponent,
            },
            StossHardeningModel::Voce2 => Hardening::Voce2 {
                yield_stress: h.yield_stress,
                saturation_stress_1: h.saturation_stress_1,
                saturation_rate_1: h.saturation_rate_1,
                saturation_stress_2: h.saturation_stress_2,
                saturation_rate_2: h.saturation_rate_2,
            },
            StossHardeningModel::PowerVoce2 => Hardening::PowerVoce2 {
                yield_stress: h.yield_stress,
                hardening_modulus: h.hardening_modulus,
                exponent: h.exponent,
                saturation_stress_1: h.saturation_stress_1,
                saturation_rate_1: h.saturation_rate_1,
                saturation_stress_2: h.saturation_stress_2,
                saturation_rate_2: h.saturation_rate_2,
            },
        };
        let r = self.rate;
        let rate = match StossRateModel::from_code(self.rate_model)? {
            StossRateModel::None => RateTerm::None,
            StossRateModel::JohnsonCookLog => RateTerm::JohnsonCookLog {
                rate_sensitivity: r.rate_sensitivity,
                reference_rate: r.reference_rate,
            },
            StossRateModel::Power => RateTerm::Power {
                exponent: r.exponent,
                reference_rate: r.reference_rate,
            },
            StossRateModel::TwoPart => RateTerm::TwoPart {
                exponent_1: r.exponent,
                reference_rate_1: r.reference_rate,
                exponent_2: r.exponent_2,
                reference_rate_2: r.reference_rate_2,
            },
            StossRateModel::CowperSymonds => RateTerm::CowperSymonds {
                rate_constant: r.cowper_symonds_d,
                exponent: r.cowper_symonds_q,
            },
            StossRateModel::LogUpturn => RateTerm::LogUpturn {
                rate_sensitivity: r.rate_sensitivity,
                reference_rate: r.reference_rate,
                upturn_exponent: r.upturn_exponent,
                upturn_rate: r.upturn_rate,
            },
            StossRateModel::LogThermal => RateTerm::LogThermal {
                rate_sensitivity: r.rate_sensitivity,
                reference_rate: r.reference_rate,
                coupling: r.coupling,
                reference_temperature: r.coupling_reference_temperature,
                melting_temperature: r.coupling_melting_temperature,
            },
        };
        let t = self.thermal;
        let thermal = match StossThermalModel::from_code(self.thermal_model)? {
            StossThermalModel::None => ThermalTerm::None,
            StossThermalModel::HomologousPower => ThermalTerm::HomologousPower {
                exponent: t.exponent,
                reference_temperature: t.reference_temperature,
                melting_temperature: t.melting_temperature,
            },
            StossThermalModel::Linear => ThermalTerm::Linear {
                reference_temperature: t.reference_temperature,
                melting_temperature: t.melting_temperature,
            },
            StossThermalModel::HomologousPowerDrop => ThermalTerm::HomologousPowerDrop {
                exponent: t.exponent,
                reference_temperature: t.reference_temperature,
                melting_temperature: t.melting_temperature,
                drop: t.drop,
                drop_start_temperature: t.drop_start_temperature,
                drop_end_temperature: t.drop_end_temperature,
            },
        };
        Ok(ComposedStrength {
            hardening,
            rate,
            thermal,
        })
    }
}

impl StossMaterialBlock {
    /// Check `layout_version` and `struct_size` (done before anything else is read).
    pub fn check_header(layout_version: u32, struct_size: u32) -> Result<(), FfiError> {
        if layout_version != STOSS_LAYOUT_VERSION {
            return Err(FfiError::new(
                StossStatus::BadLayoutVersion,
                format!(
                    "layout_version: block has {layout_version}, this library expects \
                     {STOSS_LAYOUT_VERSION} (rebuild the host against this stoss_kernel.h)"
                ),
            ));
        }
        if struct_size != BLOCK_SIZE {
            return Err(FfiError::new(
                StossStatus::BadStructSize,
                format!(
                    "struct_size: block says {struct_size} bytes, this library's \
                     StossMaterialBlock has {BLOCK_SIZE}"
                ),
            ));
        }
        Ok(())
    }

    /// A zeroed block with the header filled in (every selector 0, i.e. not yet valid).
    pub fn empty() -> Self {
        Self {
            layout_version: STOSS_LAYOUT_VERSION,
            struct_size: BLOCK_SIZE,
            ..Self::default()
        }
    }

    /// 4340 steel: the kernel's `Material::STEEL_4340` (Johnson & Cook 1985 strength, linear
    /// EoS K 159 GPa, G 81.8 GPa, rho 7830 kg/m^3, c_p 477 J/kg/K, adiabatic heating chi 0.9,
    /// implicit rate), initial temperature 298 K, Johnson-Cook failure constants of 4340
    /// filled in but switched off, no erosion, no pressure cut-off.
    pub fn steel_4340() -> Self {
        let jc = JohnsonCook::STEEL_4340;
        let failure = JohnsonCookFailure::STEEL_4340;
        let mut block = Self::empty();
        block.strength_model = StossStrengthModel::JohnsonCook as i32;
        block.rate_treatment = StossRateTreatment::Implicit as i32;
        block.eos_model = StossEosModel::Linear as i32;
        block.heating_model = StossHeatingModel::Adiabatic as i32;
        block.density = 7830.0;
        block.shear_modulus = 81.8e9;
        block.specific_heat = 477.0;
        block.initial_temperature = 298.0;
        block.heating = StossHeating {
            taylor_quinney: 0.9,
            isothermal_rate: 0.0,
            adiabatic_rate: 0.0,
        };
        block.strength.johnson_cook = StossJohnsonCook {
            yield_stress: jc.yield_stress,
            hardening_modulus: jc.hardening_modulus,
            hardening_exponent: jc.hardening_exponent,
            rate_sensitivity: jc.rate_sensitivity,
            thermal_exponent: jc.thermal_exponent,
            reference_rate: jc.reference_rate,
            reference_temperature: jc.reference_temperature,
            melting_temperature: jc.melting_temperature,
        };
        block.eos.linear.bulk_modulus = 159.0e9;
        block.failure.johnson_cook = StossJohnsonCookFailure {
            d1: failure.d1,
            d2: failure.d2,
            d3: failure.d3,
            d4: failure.d4,
            d5: failure.d5,
            reference_rate: failure.reference_rate,
            reference_temperature: failure.reference_temperature,
            melting_temperature: failure.melting_temperature,
        };
        block
    }

    fn strength(&self) -> Result<(Strength, &'static str), FfiError> {
        let s = &self.strength;
        Ok(match StossStrengthModel::from_code(self.strength_model)? {
            StossStrengthModel::JohnsonCook => {
                // Every described constant of the base is overwritten by name.
                let model = to_model(&s.johnson_cook, JohnsonCook::STEEL_4340);
                described(model.validate().map(|()| model), "strength.johnson_cook")?
            }
            model @ (StossStrengthModel::ZerilliArmstrongBcc
            | StossStrengthModel::ZerilliArmstrongFcc) => {
                let structure = if model == StossStrengthModel::ZerilliArmstrongBcc {
                    CrystalStructure::Bcc
                } else {
                    CrystalStructure::Fcc
                };
                let base = ZerilliArmstrong {
                    structure,
                    ..ZerilliArmstrong::ARMCO_IRON
                };
                let model = to_model(&s.zerilli_armstrong, base);
                described(
                    model.validate().map(|()| model),
                    "strength.zerilli_armstrong",
                )?
            }
            StossStrengthModel::ModifiedJohnsonCook => {
                let model = to_model(&s.modified_johnson_cook, ModifiedJohnsonCook::default());
                described(
                    model.validate().map(|()| model),
                    "strength.modified_johnson_cook",
                )?
            }
            StossStrengthModel::TwoRateJohnsonCook => {
                let model = to_model(&s.two_rate_johnson_cook, TwoRateJohnsonCook::default());
                described(
                    model.validate().map(|()| model),
                    "strength.two_rate_johnson_cook",
                )?
            }
            StossStrengthModel::PrestonTonksWallace => {
                // Every described constant of the base is overwritten by name.
                let model = to_model(&s.preston_tonks_wallace, PrestonTonksWallace::TANTALUM);
                described(
                    model.validate().map(|()| model),
                    "strength.preston_tonks_wallace",
                )?
            }
            StossStrengthModel::KhanHuangLiang => {
                // Every described constant of the base is overwritten by name.
                let model = to_model(&s.khan_huang_liang, KhanHuangLiang::ILLUSTRATIVE);
                described(
                    model.validate().map(|()| model),
                    "strength.khan_huang_liang",
                )?
            }
            StossStrengthModel::VoceKocks => {
                // Every described constant of the base is overwritten by name.
                let model = to_model(&s.voce_kocks, VoceKocks::ILLUSTRATIVE);
                described(model.validate().map(|()| model), "strength.voce_kocks")?
            }
            StossStrengthModel::MechanicalThresholdStress => {
                // Every described constant of the base is overwritten by name.
                let model = to_model(
                    &s.mechanical_threshold_stress,
                    MechanicalThresholdStress::COPPER,
                );
                described(
                    model.validate().map(|()| model),
                    "strength.mechanical_threshold_stress",
                )?
            }
            StossStrengthModel::Rht => {
                return Err(invalid(
                    "strength_model",
                    "7 (RHT concrete) is not a J2 metal: read the block with to_model",
                ))
            }
            StossStrengthModel::Kc => {
                return Err(invalid(
                    "strength_model",
                    "8 (K&C concrete) is not a J2 metal: read the block with to_model",
                ))
            }
            StossStrengthModel::Composed => {
                let model = s.composed.to_kernel()?;
                let section = "strength.composed";
                model
                    .validate()
                    .map_err(|e| FfiError::parameter(section, e))?;
                (model.into(), section)
            }
        })
    }

    fn eos(&self) -> Result<Eos, FfiError> {
        let e = &self.eos;
        let (eos, section): (Eos, &str) = match StossEosModel::from_code(self.eos_model)? {
            StossEosModel::Linear => (
                LinearEos {
                    bulk_modulus: e.linear.bulk_modulus,
                }
                .into(),
                "eos.linear",
            ),
            StossEosModel::MieGruneisen => {
                let p = e.mie_gruneisen;
                (
                    MieGruneisen {
                        reference_density: p.reference_density,
                        sound_speed: p.sound_speed,
                        s1: p.s1,
                        s2: p.s2,
                        s3: p.s3,
                        gamma0: p.gamma0,
                        volume_correction: p.volume_correction,
                    }
                    .into(),
                    "eos.mie_gruneisen",
                )
            }
            StossEosModel::Polynomial => (e.polynomial.to_kernel().into(), "eos.polynomial"),
            StossEosModel::Jwl => {
                let p = e.jwl;
                (
                    Jwl {
                        a: p.a,
                        b: p.b,
                        r1: p.r1,
                        r2: p.r2,
                        omega: p.omega,
                        reference_density: p.reference_density,
                        detonation_energy: p.detonation_energy,
                        detonation_velocity: p.detonation_velocity,
                        cj_pressure: p.cj_pressure,
                    }
                    .into(),
                    "eos.jwl",
                )
            }
            StossEosModel::TabulatedCompaction => {
                let p = &e.tabulated_compaction;
                let section = "eos.tabulated_compaction";
                let count = p.point_count as usize;
                if !(2..=STOSS_MAX_COMPACTION_POINTS).contains(&count) {
                    return Err(invalid(
                        "eos.tabulated_compaction.point_count",
                        format_args!("{count} is outside [2, {STOSS_MAX_COMPACTION_POINTS}]"),
                    ));
                }
                let mut points = [CompactionPoint::new(0.0, 0.0, 0.0); STOSS_MAX_COMPACTION_POINTS];
                for (i, point) in points.iter_mut().enumerate().take(count) {
                    *point = CompactionPoint::new(
                        p.volumetric_strain[i],
                        p.pressure[i],
                        p.unloading_bulk_modulus[i],
                    );
                }
                let table = TabulatedCompaction::new(&points[..count])
                    .map_err(|e| FfiError::parameter(section, e))?;
                (table.into(), section)
            }
            StossEosModel::PAlpha => {
                let p = e.p_alpha;
                (
                    PAlpha {
                        solid: p.solid.to_kernel(),
                        initial_distension: p.initial_distension,
                        crush_pressure: p.crush_pressure,
                        lock_pressure: p.lock_pressure,
                        exponent: p.exponent,
                    }
                    .into(),
                    "eos.p_alpha",
                )
            }
        };
        eos.validate()
            .map_err(|error| FfiError::parameter(section, error))?;
        Ok(eos)
    }

    fn heating(&self) -> Result<Heating, FfiError> {
        let h = self.heating;
        let heating = match StossHeatingModel::from_code(self.heating_model)? {
            StossHeatingModel::Isothermal => Heating::Isothermal,
            StossHeatingModel::Adiabatic => Heating::Adiabatic {
                taylor_quinney: h.taylor_quinney,
            },
            StossHeatingModel::Transition => Heating::Transition {
                taylor_quinney: h.taylor_quinney,
                isothermal_rate: h.isothermal_rate,
                adiabatic_rate: h.adiabatic_rate,
            },
        };
        heating
            .validate()
            .map_err(|error| FfiError::parameter("heating", error))?;
        Ok(heating)
    }

    fn failure(&self) -> Result<Failure, FfiError> {
        let f = &self.failure;
        let johnson_cook = if switch("failure.johnson_cook_enabled", f.johnson_cook_enabled)? {
            let p = f.johnson_cook;
            Some(JohnsonCookFailure {
                d1: p.d1,
                d2: p.d2,
                d3: p.d3,
                d4: p.d4,
                d5: p.d5,
                reference_rate: p.reference_rate,
                reference_temperature: p.reference_temperature,
                melting_temperature: p.melting_temperature,
            })
        } else {
            None
        };
        let failure = Failure {
            johnson_cook,
            erosion_plastic_strain: switch("failure.erosion_enabled", f.erosion_enabled)?
                .then_some(f.erosion_plastic_strain),
            erode_on_failure: switch("failure.erode_on_failure", f.erode_on_failure)?,
            erosion_geometric_strain: None,
            failure_principal_strain: None,
            pressure_cutoff: switch("failure.pressure_cutoff_enabled", f.pressure_cutoff_enabled)?
                .then_some(f.pressure_cutoff),
        };
        let section = if johnson_cook.is_some() {
            "failure.johnson_cook"
        } else {
            "failure"
        };
        // Failure::validate checks the JC constants first, then erosion and cut-off, whose
        // field names already say which they are.
        failure
            .validate()
            .map_err(|error| FfiError::parameter(section, error))?;
        Ok(failure)
    }

    /// The header, the rate treatment and the four positive scalars every family reads.
    fn common(&self) -> Result<RateTreatment, FfiError> {
        Self::check_header(self.layout_version, self.struct_size)?;
        let rate_treatment = match StossRateTreatment::from_code(self.rate_treatment)? {
            StossRateTreatment::Implicit => RateTreatment::Implicit,
            StossRateTreatment::Lagged => RateTreatment::Lagged,
        };
        for (field, value) in [
            ("density", self.density),
            ("shear_modulus", self.shear_modulus),
            ("specific_heat", self.specific_heat),
            ("initial_temperature", self.initial_temperature),
        ] {
            if !value.is_finite() {
                return Err(invalid(field, "value is not finite"));
            }
            if value <= 0.0 {
                return Err(invalid(field, format_args!("must be > 0, got {value}")));
            }
        }
        Ok(rate_treatment)
    }

    /// The point model this block describes, of any family (a J2 metal, RHT or K&C
    /// concrete), fully validated; the error names the first offending field.
    pub fn to_model(&self) -> Result<PartMaterial, FfiError> {
        // Every branch checks the header first.
        if self.strength_model == StossStrengthModel::Rht as i32 {
            self.to_rht().map(PartMaterial::Rht)
        } else if self.strength_model == StossStrengthModel::Kc as i32 {
            self.to_kc().map(PartMaterial::Kc)
        } else {
            self.to_material().map(PartMaterial::J2)
        }
    }

    /// The common checks ([`Self::common`]), that `strength_model` is `model`, and what a
    /// concrete block (RHT, K&C) must not have: a rate treatment other than implicit,
    /// heating, Johnson-Cook failure, erosion on failure, the pressure cut-off, and (if
    /// `erosion` is false) plastic-strain erosion. `name` names the family in messages.
    fn concrete_common(
        &self,
        model: StossStrengthModel,
        name: &str,
        erosion: bool,
    ) -> Result<(), FfiError> {
        let rate_treatment = self.common()?;
        if StossStrengthModel::from_code(self.strength_model)? != model {
            return Err(invalid(
                "strength_model",
                format_args!("{} is not {name} ({})", self.strength_model, model as i32),
            ));
        }
        if rate_treatment != RateTreatment::Implicit {
            return Err(invalid(
                "rate_treatment",
                format_args!("{name} takes the step's own strain rate: must be implicit (1)"),
            ));
        }
        if StossHeatingModel::from_code(self.heating_model)? != StossHeatingModel::Isothermal {
            return Err(invalid(
                "heating_model",
                format_args!("{name} has no plastic-work heating: must be isothermal (1)"),
            ));
        }
        let f = &self.failure;
        let mut off = vec![
            ("failure.johnson_cook_enabled", f.johnson_cook_enabled),
            ("failure.erode_on_failure", f.erode_on_failure),
            ("failure.pressure_cutoff_enabled", f.pressure_cutoff_enabled),
        ];
        if !erosion {
            off.push(("failure.erosion_enabled", f.erosion_enabled));
        }
        for (field, value) in off {
            if switch(field, value)? {
                return Err(invalid(
                    field,
                    format_args!("{name} has its own damage and tensile limit: must be 0"),
                ));
            }
        }
        Ok(())
    }

    /// The K&C concrete this block describes (`strength_model` = K&C), fully validated.
    pub fn to_kc(&self) -> Result<KcMaterial, FfiError> {
        self.concrete_common(StossStrengthModel::Kc, "K&C concrete", false)?;
        let k = &self.strength.kc;
        let count = k.damage_point_count as usize;
        if !(2..=STOSS_KC_MAX_DAMAGE_POINTS).contains(&count) {
            return Err(invalid(
                "strength.kc.damage_point_count",
                format_args!("{count} is outside [2, {STOSS_KC_MAX_DAMAGE_POINTS}]"),
            ));
        }
        for (field, value) in k
            .maximum_surface
            .iter()
            .chain(&k.yield_surface)
            .chain(&k.residual_surface)
            .chain(&k.damage_lambda[..count])
            .chain(&k.damage_eta[..count])
            .chain(&k.constants[..KC_CONSTANTS])
            .map(|value| ("strength.kc", *value))
        {
            if !value.is_finite() {
                return Err(invalid(field, format_args!("{value} is not finite")));
            }
        }
        // Every field of the template is overwritten below: the named ones here, the
        // described scalars by `read_section`.
        let mut parameters = KcParameters {
            shear_modulus: self.shear_modulus,
            maximum_surface: k.maximum_surface,
            yield_surface: k.yield_surface,
            residual_surface: k.residual_surface,
            damage: DamageFunction {
                lambda: k.damage_lambda,
                eta: k.damage_eta,
                count,
            },
            rate: match StossKcRate::from_code(k.rate)? {
                StossKcRate::None => RateEnhancement::None,
                StossKcRate::CebFip => RateEnhancement::CebFip,
            },
            crack_band: switch("strength.kc.crack_band_enabled", k.crack_band_enabled)?.then_some(
                CrackBand {
                    reference_width: k.crack_band_reference_width,
                    width: k.crack_band_width,
                },
            ),
            ..KcParameters::HPC_100MPA_FOI
        };
        read_section(&mut parameters, &k.constants[..KC_CONSTANTS]);
        // The unused table points are zero in a kernel table (from_points), whatever the
        // block holds past `count`.
        for i in count..STOSS_KC_MAX_DAMAGE_POINTS {
            parameters.damage.lambda[i] = 0.0;
            parameters.damage.eta[i] = 0.0;
        }
        parameters
            .validate()
            .map_err(|error| FfiError::parameter("strength.kc", error))?;
        let material = KcMaterial {
            density: self.density,
            parameters,
            eos: self.eos()?,
            erosion_geometric_strain: None,
        };
        material
            .validate()
            .map_err(|error| FfiError::parameter("material", error))?;
        Ok(material)
    }

    /// The RHT concrete this block describes (`strength_model` = RHT), fully validated.
    pub fn to_rht(&self) -> Result<RhtMaterial, FfiError> {
        self.concrete_common(StossStrengthModel::Rht, "RHT concrete", true)?;
        let f = &self.failure;
        let r = &self.strength.rht;
        // Every field of the template is overwritten: the options and the shear modulus
        // here, the described constants by name (`to_model`).
        let parameters = RhtParameters {
            shear_modulus: self.shear_modulus,
            elastic_cap: switch("strength.rht.elastic_cap", r.elastic_cap)?,
            tensile_failure: match StossRhtTensileFailure::from_code(r.tensile_failure)? {
                StossRhtTensileFailure::HydroTensileLimit => TensileFailure::HydroTensileLimit,
                StossRhtTensileFailure::PressureCutoff => TensileFailure::PressureCutoff,
                StossRhtTensileFailure::PrincipalStress => TensileFailure::PrincipalStress,
            },
            meridian: match StossRhtMeridian::from_code(r.meridian)? {
                StossRhtMeridian::PowerLaw => FailureMeridian::PowerLaw,
                StossRhtMeridian::CharacteristicPoints => FailureMeridian::CharacteristicPoints,
            },
            rate_scaling: match StossRhtRateScaling::from_code(r.rate_scaling)? {
                StossRhtRateScaling::SeedEquation => RateScaling::SeedEquation,
                StossRhtRateScaling::Homothetic => RateScaling::Homothetic,
            },
            ..RhtParameters::HPC_92MPA
        };
        let parameters = to_model(r, parameters);
        parameters
            .validate()
            .map_err(|error| FfiError::parameter("strength.rht", error))?;
        let material = RhtMaterial {
            density: self.density,
            parameters,
            eos: self.eos()?,
            erosion_plastic_strain: switch("failure.erosion_enabled", f.erosion_enabled)?
                .then_some(f.erosion_plastic_strain),
            erosion_geometric_strain: None,
        };
        material
            .validate()
            .map_err(|error| FfiError::parameter("material", error))?;
        Ok(material)
    }

    /// The kernel material this block describes, fully validated; the error names the first
    /// offending field (with its section, e.g. `strength.johnson_cook: yield_stress: ...`).
    pub fn to_material(&self) -> Result<Material, FfiError> {
        let rate_treatment = self.common()?;
        let (strength, _) = self.strength()?;
        let material = Material {
            density: self.density,
            shear_modulus: self.shear_modulus,
            specific_heat: self.specific_heat,
            strength,
            heating: self.heating()?,
            eos: self.eos()?,
            failure: self.failure()?,
            rate_treatment,
        };
        // Everything was checked part by part above; this is the kernel's own final word.
        material
            .validate()
            .map_err(|error| FfiError::parameter("material", error))?;
        Ok(material)
    }

    /// Initial state of a point of this material (undeformed, stress free, at
    /// `initial_temperature`, EoS history at its initial value).
    pub fn initial_state(&self, model: &impl PointModel) -> MaterialState {
        model.initial_state(self.initial_temperature)
    }

    /// The 92 MPa high-performance concrete of seed 001 table 4.4 over its illustrative
    /// P-alpha EoS: the kernel's `RhtMaterial::HPC_92MPA`, initial temperature 293 K, no
    /// erosion. Specific heat 880 J/kg/K (a typical concrete; RHT does not read it).
    pub fn concrete_hpc_92() -> Self {
        crate::export::from_rht(&RhtMaterial::HPC_92MPA, 293.0, 880.0)
            .map(|(block, _)| block)
            .unwrap_or_else(|_| Self::empty())
    }

    /// The 100 MPa high-performance concrete of seed 001 chapter 5 with K&C: the kernel's
    /// `KcMaterial::HPC_100MPA_FOI` (tables 5.1 to 5.3: tabulated EoS, CEB-FIP rates, no
    /// crack band), initial temperature 293 K. Specific heat 880 J/kg/K (a typical concrete;
    /// K&C does not read it).
    pub fn concrete_kc_100() -> Self {
        crate::export::from_kc(&KcMaterial::HPC_100MPA_FOI, 293.0, 880.0)
            .map(|(block, _)| block)
            .unwrap_or_else(|_| Self::empty())
    }
}

/// Bulk modulus the host should use for its time step, contact and hourglass stiffness: the
/// EoS slope `dp/dmu` at the reference state (`mu = 0`, `E = 0`, initial EoS history). For the
/// linear EoS this is `K`; for Mie-Grüneisen `rho0 C^2`; for the polynomial `A1`.
pub fn initial_bulk_modulus(eos: &Eos) -> f64 {
    let (terms, _) = eos.evaluate(0.0, eos.initial_history());
    terms.d_base_d_mu
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_kernel_4340() {
        let material = StossMaterialBlock::steel_4340().to_material().unwrap();
        assert_eq!(material, Material::STEEL_4340);
        assert_eq!(initial_bulk_modulus(&material.eos), 159.0e9);
    }

    #[test]
    fn a_zeroed_block_is_rejected_with_a_message() {
        let error = StossMaterialBlock::empty().to_material().unwrap_err();
        assert_eq!(error.status, StossStatus::InvalidParameter);
        assert!(
            error.message.contains("rate_treatment"),
            "{}",
            error.message
        );
    }

    #[test]
    fn header_is_checked_first() {
        let mut block = StossMaterialBlock::steel_4340();
        block.layout_version = 0;
        block.density = f64::NAN;
        assert_eq!(
            block.to_material().unwrap_err().status,
            StossStatus::BadLayoutVersion
        );
        block.layout_version = STOSS_LAYOUT_VERSION;
        block.struct_size -= 8;
        assert_eq!(
            block.to_material().unwrap_err().status,
            StossStatus::BadStructSize
        );
    }

    #[test]
    fn messages_name_section_and_field() {
        let mut block = StossMaterialBlock::steel_4340();
        block.strength.johnson_cook.yield_stress = -1.0;
        let error = block.to_material().unwrap_err();
        assert_eq!(error.status, StossStatus::InvalidParameter);
        assert_eq!(
            error.message,
            "strength.johnson_cook: yield_stress: must be > 0, got -1"
        );

        let mut block = StossMaterialBlock::steel_4340();
        block.density = f64::INFINITY;
        assert_eq!(
            block.to_material().unwrap_err().message,
            "density: value is not finite"
        );

        let mut block = StossMaterialBlock::steel_4340();
        block.eos_model = 42;
        assert_eq!(
            block.to_material().unwrap_err().message,
            "eos_model: unknown code 42"
        );

        let mut block = StossMaterialBlock::steel_4340();
        block.failure.johnson_cook_enabled = 2;
        assert!(block
            .to_material()
            .unwrap_err()
            .message
            .starts_with("failure.johnson_cook_enabled"));

        let mut block = StossMaterialBlock::steel_4340();
        block.eos_model = StossEosModel::TabulatedCompaction as i32;
        block.eos.tabulated_compaction.point_count = 1;
        assert!(block
            .to_material()
            .unwrap_err()
            .message
            .starts_with("eos.tabulated_compaction.point_count"));
    }

    #[test]
    fn every_strength_family_converts_like_the_kernel_structs() {
        let mut block = StossMaterialBlock::steel_4340();
        // MJC with the JC constants and no Voce terms.
        block.strength_model = StossStrengthModel::ModifiedJohnsonCook as i32;
        block.strength.modified_johnson_cook = StossModifiedJohnsonCook {
            yield_stress: 792.0e6,
            hardening_modulus: 510.0e6,
            hardening_exponent: 0.26,
            saturation_stress_1: 100.0e6,
            saturation_rate_1: 20.0,
            saturation_stress_2: 0.0,
            saturation_rate_2: 0.0,
            rate_exponent: 0.01,
            reference_rate: 1.0,
            thermal_exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        };
        let material = block.to_material().unwrap();
        let expected: Strength = ModifiedJohnsonCook {
            yield_stress: 792.0e6,
            hardening_modulus: 510.0e6,
            hardening_exponent: 0.26,
            saturation_stress_1: 100.0e6,
            saturation_rate_1: 20.0,
            saturation_stress_2: 0.0,
            saturation_rate_2: 0.0,
            rate_exponent: 0.01,
            reference_rate: 1.0,
            thermal_exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        }
        .into();
        assert_eq!(material.strength, expected);

        // The same law written as a composition gives the same kernel strength.
        block.strength_model = StossStrengthModel::Composed as i32;
        block.strength.composed = StossComposed {
            hardening_model: StossHardeningModel::PowerVoce2 as i32,
            rate_model: StossRateModel::Power as i32,
            thermal_model: StossThermalModel::HomologousPower as i32,
            reserved: 0,
            hardening: StossHardening {
                yield_stress: 792.0e6,
                hardening_modulus: 510.0e6,
                exponent: 0.26,
                saturation_stress_1: 100.0e6,
                saturation_rate_1: 20.0,
                saturation_stress_2: 0.0,
                saturation_rate_2: 0.0,
            },
            rate: StossRateTerm {
                exponent: 0.01,
                reference_rate: 1.0,
                ..StossRateTerm::default()
            },
            thermal: StossThermalTerm {
                exponent: 1.03,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
                ..StossThermalTerm::default()
            },
        };
        assert_eq!(block.to_material().unwrap().strength, expected);

        // TJC keeps its own consistency check (e02 >= e01).
        block.strength_model = StossStrengthModel::TwoRateJohnsonCook as i32;
        block.strength.two_rate_johnson_cook = StossTwoRateJohnsonCook {
            yield_stress: 792.0e6,
            hardening_modulus: 510.0e6,
            hardening_exponent: 0.26,
            rate_exponent_1: 0.01,
            reference_rate_1: 10.0,
            rate_exponent_2: 0.02,
            reference_rate_2: 1.0,
            thermal_exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
            ..StossTwoRateJohnsonCook::default()
        };
        let error = block.to_material().unwrap_err();
        assert!(
            error.message.contains("reference_rate_2: inconsistent"),
            "{}",
            error.message
        );

        // ZA FCC.
        block.strength_model = StossStrengthModel::ZerilliArmstrongFcc as i32;
        block.strength.zerilli_armstrong = StossZerilliArmstrong {
            athermal_stress: 46.5e6,
            c2: 890.0e6,
            c3: 0.0028,
            c4: 0.000115,
            reference_rate: 1.0,
            ..StossZerilliArmstrong::default()
        };
        match block.to_material().unwrap().strength {
            Strength::ZerilliArmstrong(za) => assert_eq!(za.structure, CrystalStructure::Fcc),
            other => panic!("{other:?}"),
        }
    }
}
