//! A kernel [`Material`] written as a [`StossMaterialBlock`]: the inverse of
//! [`StossMaterialBlock::to_material`], so that every model stoss calibrates or diagnoses gets
//! a user-material block and card. A composed strength in Johnson-Cook form (power hardening,
//! JC log rate, homologous-power thermal term) is written with the Johnson-Cook code, every
//! other composed strength with the composed code, Zerilli-Armstrong with its own; the block
//! gives back the same kernel material, field for field (tested).
//!
//! Not carried (host-only criteria, see docs/solver.md): the geometric erosion strain and the
//! principal-strain failure of `Failure`; [`from_material`] reports whether it dropped them.

use stoss_kernel::eos::Eos;
use stoss_kernel::kc::{KcMaterial, KcParameters, RateEnhancement};
use stoss_kernel::rht::{FailureMeridian, RateScaling, RhtMaterial, RhtParameters, TensileFailure};
use stoss_kernel::strength::{
    ComposedStrength, CrystalStructure, Hardening, JohnsonCook, RateTerm, Strength, ThermalTerm,
};
use stoss_kernel::{Heating, Material, RateTreatment};

use crate::block::{
    StossComposed, StossEosModel, StossHardening, StossHardeningModel, StossHeatingModel,
    StossJohnsonCookFailure, StossKc, StossKcRate, StossMaterialBlock, StossRateModel,
    StossRateTerm, StossRateTreatment, StossRht, StossRhtMeridian, StossRhtRateScaling,
    StossRhtTensileFailure, StossStrengthModel, StossThermalModel, StossThermalTerm,
};
use crate::section::{from_model, write_section};
use crate::status::FfiError;

/// The block of `material` at `initial_temperature` (K), and whether host-only failure
/// criteria (geometric erosion strain, principal-strain failure) were left out. The block is
/// validated by [`StossMaterialBlock::to_material`] before it is returned.
pub fn from_material(
    material: &Material,
    initial_temperature: f64,
) -> Result<(StossMaterialBlock, bool), FfiError> {
    let mut block = StossMaterialBlock::empty();
    block.density = material.density;
    block.shear_modulus = material.shear_modulus;
    block.specific_heat = material.specific_heat;
    block.initial_temperature = initial_temperature;
    block.rate_treatment = match material.rate_treatment {
        RateTreatment::Implicit => StossRateTreatment::Implicit,
        RateTreatment::Lagged => StossRateTreatment::Lagged,
    } as i32;
    let (heating_model, heating) = match material.heating {
        Heating::Isothermal => (StossHeatingModel::Isothermal, (0.0, 0.0, 0.0)),
        Heating::Adiabatic { taylor_quinney } => {
            (StossHeatingModel::Adiabatic, (taylor_quinney, 0.0, 0.0))
        }
        Heating::Transition {
            taylor_quinney,
            isothermal_rate,
            adiabatic_rate,
        } => (
            StossHeatingModel::Transition,
            (taylor_quinney, isothermal_rate, adiabatic_rate),
        ),
    };
    block.heating_model = heating_model as i32;
    (
        block.heating.taylor_quinney,
        block.heating.isothermal_rate,
        block.heating.adiabatic_rate,
    ) = heating;
    write_strength(&mut block, &material.strength);
    write_eos(&mut block, &material.eos);
    let failure = &material.failure;
    let f = &mut block.failure;
    if let Some(jc) = failure.johnson_cook {
        f.johnson_cook_enabled = 1;
        f.johnson_cook = StossJohnsonCookFailure {
            d1: jc.d1,
            d2: jc.d2,
            d3: jc.d3,
            d4: jc.d4,
            d5: jc.d5,
            reference_rate: jc.reference_rate,
            reference_temperature: jc.reference_temperature,
            melting_temperature: jc.melting_temperature,
        };
    }
    f.erode_on_failure = u32::from(failure.erode_on_failure);
    if let Some(strain) = failure.erosion_plastic_strain {
        f.erosion_enabled = 1;
        f.erosion_plastic_strain = strain;
    }
    if let Some(cutoff) = failure.pressure_cutoff {
        f.pressure_cutoff_enabled = 1;
        f.pressure_cutoff = cutoff;
    }
    let dropped =
        failure.erosion_geometric_strain.is_some() || failure.failure_principal_strain.is_some();
    block.to_material()?;
    Ok((block, dropped))
}

/// The block of RHT concrete `material` at `initial_temperature` (K), and whether the host-only
/// geometric erosion strain was left out. Specific heat: `specific_heat` (RHT does not read
/// it; the block requires a positive value). Validated by [`StossMaterialBlock::to_rht`].
pub fn from_rht(
    material: &RhtMaterial,
    initial_temperature: f64,
    specific_heat: f64,
) -> Result<(StossMaterialBlock, bool), FfiError> {
    let mut block = concrete_block(
        StossStrengthModel::Rht,
        material.density,
        material.parameters.shear_modulus,
        (initial_temperature, specific_heat),
    );
    block.strength.rht = rht_block(&material.parameters);
    write_eos(&mut block, &material.eos);
    if let Some(strain) = material.erosion_plastic_strain {
        block.failure.erosion_enabled = 1;
        block.failure.erosion_plastic_strain = strain;
    }
    block.to_rht()?;
    Ok((block, material.erosion_geometric_strain.is_some()))
}

/// The fields a concrete block (RHT, K&C) shares: its strength model, implicit and isothermal,
/// density, shear modulus, and the `(initial temperature, specific heat)` the block requires.
fn concrete_block(
    model: StossStrengthModel,
    density: f64,
    shear_modulus: f64,
    (initial_temperature, specific_heat): (f64, f64),
) -> StossMaterialBlock {
    let mut block = StossMaterialBlock::empty();
    block.strength_model = model as i32;
    block.rate_treatment = StossRateTreatment::Implicit as i32;
    block.heating_model = StossHeatingModel::Isothermal as i32;
    block.density = density;
    block.shear_modulus = shear_modulus;
    block.specific_heat = specific_heat;
    block.initial_temperature = initial_temperature;
    block
}

/// The block form of kernel RHT constants (the shear modulus goes to the block's
/// `shear_modulus`; the described constants through the descriptor).
fn rht_block(p: &RhtParameters) -> StossRht {
    let mut section = StossRht {
        tensile_failure: match p.tensile_failure {
            TensileFailure::HydroTensileLimit => StossRhtTensileFailure::HydroTensileLimit,
            TensileFailure::PressureCutoff => StossRhtTensileFailure::PressureCutoff,
            TensileFailure::PrincipalStress => StossRhtTensileFailure::PrincipalStress,
        } as i32,
        meridian: match p.meridian {
            FailureMeridian::PowerLaw => StossRhtMeridian::PowerLaw,
            FailureMeridian::CharacteristicPoints => StossRhtMeridian::CharacteristicPoints,
        } as i32,
        rate_scaling: match p.rate_scaling {
            RateScaling::SeedEquation => StossRhtRateScaling::SeedEquation,
            RateScaling::Homothetic => StossRhtRateScaling::Homothetic,
        } as i32,
        elastic_cap: u32::from(p.elastic_cap),
        ..StossRht::default()
    };
    from_model(&mut p.clone(), &mut section);
    section
}

/// The block of K&C concrete `material` at `initial_temperature` (K), and whether the host-only
/// geometric erosion strain was left out. Specific heat: `specific_heat` (K&C does not read
/// it; the block requires a positive value). Validated by [`StossMaterialBlock::to_kc`].
pub fn from_kc(
    material: &KcMaterial,
    initial_temperature: f64,
    specific_heat: f64,
) -> Result<(StossMaterialBlock, bool), FfiError> {
    let mut block = concrete_block(
        StossStrengthModel::Kc,
        material.density,
        material.parameters.shear_modulus,
        (initial_temperature, specific_heat),
    );
    block.strength.kc = kc_block(&material.parameters);
    write_eos(&mut block, &material.eos);
    block.to_kc()?;
    Ok((block, material.erosion_geometric_strain.is_some()))
}

/// The block form of kernel K&C constants (the shear modulus goes to the block's
/// `shear_modulus`; the described scalars through the descriptor).
fn kc_block(p: &KcParameters) -> StossKc {
    let damage = &p.damage;
    let mut section = StossKc {
        rate: match p.rate {
            RateEnhancement::None => StossKcRate::None,
            RateEnhancement::CebFip => StossKcRate::CebFip,
        } as i32,
        crack_band_enabled: u32::from(p.crack_band.is_some()),
        damage_point_count: damage.used() as u32,
        reserved: 0,
        maximum_surface: p.maximum_surface,
        yield_surface: p.yield_surface,
        residual_surface: p.residual_surface,
        crack_band_reference_width: p.crack_band.map_or(0.0, |band| band.reference_width),
        crack_band_width: p.crack_band.map_or(0.0, |band| band.width),
        ..StossKc::default()
    };
    let used = damage.used();
    section.damage_lambda[..used].copy_from_slice(&damage.lambda[..used]);
    section.damage_eta[..used].copy_from_slice(&damage.eta[..used]);
    write_section(&mut p.clone(), &mut section.constants);
    section
}

fn write_strength(block: &mut StossMaterialBlock, strength: &Strength) {
    match strength {
        Strength::ZerilliArmstrong(za) => {
            block.strength_model = match za.structure {
                CrystalStructure::Bcc => StossStrengthModel::ZerilliArmstrongBcc,
                CrystalStructure::Fcc => StossStrengthModel::ZerilliArmstrongFcc,
            } as i32;
            let mut model = *za;
            from_model(&mut model, &mut block.strength.zerilli_armstrong);
        }
        Strength::PrestonTonksWallace(ptw) => {
            block.strength_model = StossStrengthModel::PrestonTonksWallace as i32;
            let mut model = *ptw;
            from_model(&mut model, &mut block.strength.preston_tonks_wallace);
        }
        Strength::KhanHuangLiang(khl) => {
            block.strength_model = StossStrengthModel::KhanHuangLiang as i32;
            let mut model = *khl;
            from_model(&mut model, &mut block.strength.khan_huang_liang);
        }
        Strength::VoceKocks(vk) => {
            block.strength_model = StossStrengthModel::VoceKocks as i32;
            let mut model = *vk;
            from_model(&mut model, &mut block.strength.voce_kocks);
        }
        Strength::MechanicalThresholdStress(mts) => {
            block.strength_model = StossStrengthModel::MechanicalThresholdStress as i32;
            let mut model = *mts;
            from_model(&mut model, &mut block.strength.mechanical_threshold_stress);
        }
        Strength::Composed(composed) => {
            if let Some(mut jc) = JohnsonCook::from_composed(composed) {
                block.strength_model = StossStrengthModel::JohnsonCook as i32;
                from_model(&mut jc, &mut block.strength.johnson_cook);
            } else {
                block.strength_model = StossStrengthModel::Composed as i32;
                block.strength.composed = composed_block(composed);
            }
        }
    }
}

fn composed_block(composed: &ComposedStrength) -> StossComposed {
    let mut c = StossComposed::default();
    let h = &mut c.hardening;
    c.hardening_model = match composed.hardening {
        Hardening::Power {
            yield_stress,
            hardening_modulus,
            exponent,
        } => {
            *h = StossHardening {
                yield_stress,
                hardening_modulus,
                exponent,
                ..StossHardening::default()
            };
            StossHardeningModel::Power
        }
        Hardening::Voce2 {
            yield_stress,
            saturation_stress_1,
            saturation_rate_1,
            saturation_stress_2,
            saturation_rate_2,
        } => {
            *h = StossHardening {
                yield_stress,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
                ..StossHardening::default()
            };
            StossHardeningModel::Voce2
        }
        Hardening::PowerVoce2 {
            yield_stress,
            hardening_modulus,
            exponent,
            saturation_stress_1,
            saturation_rate_1,
            saturation_stress_2,
            saturation_rate_2,
        } => {
            *h = StossHardening {
                yield_stress,
                hardening_modulus,
                exponent,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            };
            StossHardeningModel::PowerVoce2
        }
    } as i32;
    let r = &mut c.rate;
    c.rate_model = match composed.rate {
        RateTerm::None => StossRateModel::None,
        RateTerm::JohnsonCookLog {
            rate_sensitivity,
            reference_rate,
        } => {
            (r.rate_sensitivity, r.reference_rate) = (rate_sensitivity, reference_rate);
            StossRateModel::JohnsonCookLog
        }
        RateTerm::Power {
            exponent,
            reference_rate,
        } => {
            (r.exponent, r.reference_rate) = (exponent, reference_rate);
            StossRateModel::Power
        }
        RateTerm::TwoPart {
            exponent_1,
            reference_rate_1,
            exponent_2,
            reference_rate_2,
        } => {
            *r = StossRateTerm {
                exponent: exponent_1,
                reference_rate: reference_rate_1,
                exponent_2,
                reference_rate_2,
                ..StossRateTerm::default()
            };
            StossRateModel::TwoPart
        }
        RateTerm::LogUpturn {
            rate_sensitivity,
            reference_rate,
            upturn_exponent,
            upturn_rate,
        } => {
            *r = StossRateTerm {
                rate_sensitivity,
                reference_rate,
                upturn_exponent,
                upturn_rate,
                ..StossRateTerm::default()
            };
            StossRateModel::LogUpturn
        }
        RateTerm::LogThermal {
            rate_sensitivity,
            reference_rate,
            coupling,
            reference_temperature,
            melting_temperature,
        } => {
            *r = StossRateTerm {
                rate_sensitivity,
                reference_rate,
                coupling,
                coupling_reference_temperature: reference_temperature,
                coupling_melting_temperature: melting_temperature,
                ..StossRateTerm::default()
            };
            StossRateModel::LogThermal
        }
        RateTerm::CowperSymonds {
            rate_constant,
            exponent,
        } => {
            (r.cowper_symonds_d, r.cowper_symonds_q) = (rate_constant, exponent);
            StossRateModel::CowperSymonds
        }
    } as i32;
    c.thermal_model = match composed.thermal {
        ThermalTerm::None => StossThermalModel::None,
        ThermalTerm::HomologousPower {
            exponent,
            reference_temperature,
            melting_temperature,
        } => {
            c.thermal = StossThermalTerm {
                exponent,
                reference_temperature,
                melting_temperature,
                ..StossThermalTerm::default()
            };
            StossThermalModel::HomologousPower
        }
        ThermalTerm::HomologousPowerDrop {
            exponent,
            reference_temperature,
            melting_temperature,
            drop,
            drop_start_temperature,
            drop_end_temperature,
        } => {
            c.thermal = StossThermalTerm {
                exponent,
                reference_temperature,
                melting_temperature,
                drop,
                drop_start_temperature,
                drop_end_temperature,
            };
            StossThermalModel::HomologousPowerDrop
        }
        ThermalTerm::Linear {
            reference_temperature,
            melting_temperature,
        } => {
            c.thermal = StossThermalTerm {
                exponent: 0.0,
                reference_temperature,
                melting_temperature,
                ..StossThermalTerm::default()
            };
            StossThermalModel::Linear
        }
    } as i32;
    c
}

fn write_eos(block: &mut StossMaterialBlock, eos: &Eos) {
    let e = &mut block.eos;
    let polynomial = |p: &stoss_kernel::eos::Polynomial| crate::block::StossPolynomial {
        a1: p.a1,
        a2: p.a2,
        a3: p.a3,
        b0: p.b0,
        b1: p.b1,
        t1: p.t1,
        t2: p.t2,
    };
    block.eos_model = match eos {
        Eos::Linear(linear) => {
            e.linear.bulk_modulus = linear.bulk_modulus;
            StossEosModel::Linear
        }
        Eos::MieGruneisen(g) => {
            let m = &mut e.mie_gruneisen;
            m.reference_density = g.reference_density;
            m.sound_speed = g.sound_speed;
            m.s1 = g.s1;
            m.s2 = g.s2;
            m.s3 = g.s3;
            m.gamma0 = g.gamma0;
            m.volume_correction = g.volume_correction;
            StossEosModel::MieGruneisen
        }
        Eos::Polynomial(p) => {
            e.polynomial = polynomial(p);
            StossEosModel::Polynomial
        }
        Eos::Jwl(j) => {
            let b = &mut e.jwl;
            b.a = j.a;
            b.b = j.b;
            b.r1 = j.r1;
            b.r2 = j.r2;
            b.omega = j.omega;
            b.reference_density = j.reference_density;
            b.detonation_energy = j.detonation_energy;
            b.detonation_velocity = j.detonation_velocity;
            b.cj_pressure = j.cj_pressure;
            StossEosModel::Jwl
        }
        Eos::TabulatedCompaction(table) => {
            let t = &mut e.tabulated_compaction;
            let points = table.points();
            t.point_count = points.len() as u32;
            for (i, point) in points.iter().enumerate() {
                t.volumetric_strain[i] = point.volumetric_strain;
                t.pressure[i] = point.pressure;
                t.unloading_bulk_modulus[i] = point.unloading_bulk_modulus;
            }
            StossEosModel::TabulatedCompaction
        }
        Eos::PAlpha(p) => {
            let b = &mut e.p_alpha;
            b.solid = polynomial(&p.solid);
            b.initial_distension = p.initial_distension;
            b.crush_pressure = p.crush_pressure;
            b.lock_pressure = p.lock_pressure;
            b.exponent = p.exponent;
            StossEosModel::PAlpha
        }
    } as i32;
}

#[cfg(test)]
mod tests {
    use super::*;
    use stoss_kernel::damage::JohnsonCookFailure;
    use stoss_kernel::eos::{Jwl, MieGruneisen, PAlpha, Polynomial, TabulatedCompaction};
    use stoss_kernel::strength::{
        JohnsonCook, KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook,
        PrestonTonksWallace, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
    };

    #[test]
    fn every_strength_eos_and_heating_comes_back_from_its_block_and_card() {
        // GOAL: every kernel model a calibration or the diagnosis produces has a user-material
        //       block and card that give back the same kernel material.
        // SETUP: JC (with failure, erosion and cut-off), ZA BCC and FCC, MJC, TJC, PTW, KHL, VK, MTS, JC with
        //        each diagnosis rate term, a Voce + Cowper-Symonds + linear-thermal
        //        composition; every EoS; every heating; both rate treatments.
        // REFERENCE: the material itself (exact equality) after block -> material and after
        //            block -> card -> block -> material.
        let jc = JohnsonCook::STEEL_4340;
        let mut strengths: Vec<Strength> = vec![jc.into()];
        for structure in [CrystalStructure::Bcc, CrystalStructure::Fcc] {
            strengths.push(
                ZerilliArmstrong {
                    structure,
                    athermal_stress: 65.0e6,
                    c1: 1033.0e6,
                    c2: 890.0e6,
                    c3: 0.00698,
                    c4: 0.000415,
                    c5: 266.0e6,
                    exponent: 0.289,
                    reference_rate: 1.0,
                }
                .into(),
            );
        }
        strengths.push(
            ModifiedJohnsonCook {
                yield_stress: 750.0e6,
                hardening_modulus: 300.0e6,
                hardening_exponent: 0.4,
                saturation_stress_1: 150.0e6,
                saturation_rate_1: 30.0,
                saturation_stress_2: 50.0e6,
                saturation_rate_2: 500.0,
                rate_exponent: 0.012,
                reference_rate: 1.0e-3,
                thermal_exponent: 0.8,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            }
            .into(),
        );
        strengths.push(
            TwoRateJohnsonCook {
                yield_stress: 750.0e6,
                hardening_modulus: 300.0e6,
                hardening_exponent: 0.4,
                saturation_stress_1: 150.0e6,
                saturation_rate_1: 30.0,
                saturation_stress_2: 50.0e6,
                saturation_rate_2: 500.0,
                rate_exponent_1: 0.005,
                reference_rate_1: 1.0e-3,
                rate_exponent_2: 0.05,
                reference_rate_2: 3.0e3,
                thermal_exponent: 1.1,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            }
            .into(),
        );
        strengths.push(PrestonTonksWallace::TANTALUM.into());
        strengths.push(KhanHuangLiang::ILLUSTRATIVE.into());
        strengths.push(VoceKocks::ILLUSTRATIVE.into());
        strengths.push(MechanicalThresholdStress::COPPER.into());
        for rate in [
            RateTerm::LogUpturn {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                upturn_exponent: 0.08,
                upturn_rate: 2.0e3,
            },
            RateTerm::LogThermal {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                coupling: 2.0,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            },
        ] {
            let mut composed = jc.composed();
            composed.rate = rate;
            strengths.push(composed.into());
        }
        strengths.push(
            ComposedStrength {
                hardening: Hardening::Voce2 {
                    yield_stress: 700.0e6,
                    saturation_stress_1: 300.0e6,
                    saturation_rate_1: 20.0,
                    saturation_stress_2: 100.0e6,
                    saturation_rate_2: 800.0,
                },
                rate: RateTerm::CowperSymonds {
                    rate_constant: 4.0e4,
                    exponent: 5.0,
                },
                thermal: ThermalTerm::Linear {
                    reference_temperature: 298.0,
                    melting_temperature: 1793.0,
                },
            }
            .into(),
        );
        let solid = Polynomial {
            a1: 35.27e9,
            a2: 39.58e9,
            a3: 9.04e9,
            b0: 1.22,
            b1: 1.22,
            t1: 35.27e9,
            t2: 0.0,
        };
        let eoses: Vec<Eos> = vec![
            Material::STEEL_4340.eos,
            MieGruneisen {
                reference_density: 7830.0,
                sound_speed: 4570.0,
                s1: 1.49,
                s2: 0.0,
                s3: 0.0,
                gamma0: 1.93,
                volume_correction: 0.5,
            }
            .into(),
            solid.into(),
            Jwl::C4.into(),
            TabulatedCompaction::CONCRETE_FOI_TABLE_5_2.into(),
            PAlpha {
                solid,
                initial_distension: 1.1,
                crush_pressure: 60.0e6,
                lock_pressure: 6.0e9,
                exponent: 3.0,
            }
            .into(),
        ];
        let heatings = [
            Heating::Isothermal,
            Heating::ADIABATIC,
            Heating::Transition {
                taylor_quinney: 0.9,
                isothermal_rate: 0.01,
                adiabatic_rate: 10.0,
            },
        ];
        let mut checked = 0;
        for (i, strength) in strengths.iter().enumerate() {
            for (j, eos) in eoses.iter().enumerate() {
                let mut material = Material::STEEL_4340.with_strength(*strength);
                material.eos = *eos;
                material.heating = heatings[(i + j) % 3];
                if (i + j) % 2 == 1 {
                    material.rate_treatment = RateTreatment::Lagged;
                }
                if i == 0 {
                    material.failure.johnson_cook = Some(JohnsonCookFailure::STEEL_4340);
                    material.failure.erode_on_failure = true;
                    material.failure.erosion_plastic_strain = Some(1.5);
                    material.failure.pressure_cutoff = Some(-1.0e9);
                }
                let (block, dropped) = from_material(&material, 298.0).unwrap();
                assert!(!dropped);
                assert_eq!(block.to_material().unwrap(), material, "{i} {j}");
                let (card, length) = crate::card::card_from_block(&block).unwrap();
                let read = crate::card::block_from_card(&card[..length]).unwrap();
                assert_eq!(read.to_material().unwrap(), material, "{i} {j} (card)");
                checked += 1;
            }
        }
        assert_eq!(checked, 12 * 6);
        let mut material = Material::STEEL_4340;
        material.failure.erosion_geometric_strain = Some(1.5);
        assert!(from_material(&material, 298.0).unwrap().1);
    }
}
