//! The reference materials that `stoss verify` and the golden histories exercise: one per
//! strength model family and rate treatment.

use stoss_kernel::damage::{Failure, JohnsonCookFailure};
use stoss_kernel::strength::{
    CrystalStructure, JohnsonCook, KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook,
    PrestonTonksWallace, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};
use stoss_kernel::{Heating, Material, RateTreatment};

/// A named material for verification.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceMaterial {
    /// Short identifier (file names, table rows).
    pub name: &'static str,
    /// Where the constants come from.
    pub source: &'static str,
    /// The material, isothermal (heating is switched on per check where wanted).
    pub material: Material,
}

/// Zerilli & Armstrong (1987) BCC constants for Armco iron: C1 1033 MPa, C3 0.00698 /K,
/// C4 0.000415 /K, C5 266 MPa, n 0.289; athermal stress 65 MPa (grain-size term, typical).
pub const ZA_ARMCO_IRON: ZerilliArmstrong = ZerilliArmstrong::ARMCO_IRON;

/// Zerilli & Armstrong (1987) FCC constants for OFHC copper: C2 890 MPa, C3 0.0028 /K,
/// C4 0.000115 /K; athermal stress 65 MPa.
pub const ZA_OFHC_COPPER: ZerilliArmstrong = ZerilliArmstrong {
    structure: CrystalStructure::Fcc,
    athermal_stress: 65.0e6,
    c1: 0.0,
    c2: 890.0e6,
    c3: 0.0028,
    c4: 0.000115,
    c5: 0.0,
    exponent: 0.5,
    reference_rate: 1.0,
};

/// Illustrative MJC constants in the HHA-steel range of seed 000 (its table 2 did not
/// survive extraction): A 1200 MPa, B 500 MPa, n 0.3, Q1 300 MPa c1 20, Q2 100 MPa c2 200,
/// beta 0.01, m 1.0.
pub const MJC_HHA_ILLUSTRATIVE: ModifiedJohnsonCook = ModifiedJohnsonCook {
    yield_stress: 1200.0e6,
    hardening_modulus: 500.0e6,
    hardening_exponent: 0.3,
    saturation_stress_1: 300.0e6,
    saturation_rate_1: 20.0,
    saturation_stress_2: 100.0e6,
    saturation_rate_2: 200.0,
    rate_exponent: 0.01,
    reference_rate: 1.0,
    thermal_exponent: 1.0,
    reference_temperature: 298.0,
    melting_temperature: 1793.0,
};

/// Illustrative TJC constants: MJC hardening with a two-part rate term, e01 1e-3 /s,
/// beta1 0.005, e02 1e3 /s, beta2 0.05 (a high-rate upturn).
pub const TJC_HHA_ILLUSTRATIVE: TwoRateJohnsonCook = TwoRateJohnsonCook {
    yield_stress: 1200.0e6,
    hardening_modulus: 500.0e6,
    hardening_exponent: 0.3,
    saturation_stress_1: 300.0e6,
    saturation_rate_1: 20.0,
    saturation_stress_2: 100.0e6,
    saturation_rate_2: 200.0,
    rate_exponent_1: 0.005,
    reference_rate_1: 1.0e-3,
    rate_exponent_2: 0.05,
    reference_rate_2: 1.0e3,
    thermal_exponent: 1.0,
    reference_temperature: 298.0,
    melting_temperature: 1793.0,
};

fn steel(strength: impl Into<stoss_kernel::strength::Strength>) -> Material {
    let mut material = Material::STEEL_4340.with_strength(strength);
    material.heating = Heating::Isothermal;
    material
}

/// Every reference material, in a fixed order.
pub fn reference_materials() -> Vec<ReferenceMaterial> {
    let mut lagged = steel(JohnsonCook::STEEL_4340);
    lagged.rate_treatment = RateTreatment::Lagged;
    let mut copper = steel(ZA_OFHC_COPPER);
    copper.density = 8960.0;
    copper.shear_modulus = 46.0e9;
    copper.specific_heat = 383.0;
    copper.eos = stoss_kernel::eos::Eos::Linear(stoss_kernel::eos::LinearEos {
        bulk_modulus: 137.0e9,
    });
    // Tantalum's elasticity: Steinberg (1996) via Uintah SCG_Tantalum.xml, rho 16690 kg/m^3,
    // G 69.0 GPa, K = rho C0^2 with C0 3410 m/s (194 GPa), c_p 135 J/kg/K.
    let mut tantalum = steel(PrestonTonksWallace::TANTALUM);
    tantalum.density = 16690.0;
    tantalum.shear_modulus = 69.0e9;
    tantalum.specific_heat = 135.0;
    tantalum.eos = stoss_kernel::eos::Eos::Linear(stoss_kernel::eos::LinearEos {
        bulk_modulus: 16690.0 * 3410.0 * 3410.0,
    });
    let mut jc_failure = steel(JohnsonCook::STEEL_4340);
    jc_failure.heating = Heating::ADIABATIC;
    jc_failure.failure = Failure {
        johnson_cook: Some(JohnsonCookFailure::STEEL_4340),
        erosion_plastic_strain: None,
        erode_on_failure: true,
        erosion_geometric_strain: None,
        failure_principal_strain: None,
        pressure_cutoff: None,
    };
    vec![
        ReferenceMaterial {
            name: "jc-4340",
            source: "Johnson & Cook (1985) 4340 steel, implicit rate (seed 001 eq. 3.8)",
            material: steel(JohnsonCook::STEEL_4340),
        },
        ReferenceMaterial {
            name: "jc-4340-lagged",
            source: "Johnson & Cook (1985) 4340 steel, lagged rate (seed 001 eq. 3.7)",
            material: lagged,
        },
        ReferenceMaterial {
            name: "jc-4340-adiabatic-failure",
            source: "4340, adiabatic heating chi 0.9 and JC failure D1..D5 (1985)",
            material: jc_failure,
        },
        ReferenceMaterial {
            name: "za-bcc-armco",
            source: "Zerilli & Armstrong (1987) Armco iron, on 4340 elasticity",
            material: steel(ZA_ARMCO_IRON),
        },
        ReferenceMaterial {
            name: "za-fcc-copper",
            source: "Zerilli & Armstrong (1987) OFHC copper",
            material: copper,
        },
        ReferenceMaterial {
            name: "mjc-hha",
            source: "illustrative HHA-range MJC constants (seed 000 form)",
            material: steel(MJC_HHA_ILLUSTRATIVE),
        },
        ReferenceMaterial {
            name: "tjc-hha",
            source: "illustrative HHA-range TJC constants (seed 000 form)",
            material: steel(TJC_HHA_ILLUSTRATIVE),
        },
        ReferenceMaterial {
            name: "ptw-tantalum",
            source: "Preston, Tonks & Wallace (2003) tantalum, Steinberg (1996) elasticity",
            material: tantalum,
        },
        ReferenceMaterial {
            name: "khl-illustrative",
            source: "illustrative Khan-Huang-Liang constants (titanium-alloy range), on 4340 \
                     elasticity",
            material: steel(KhanHuangLiang::ILLUSTRATIVE),
        },
        ReferenceMaterial {
            name: "vk-illustrative",
            source: "illustrative Voce-Kocks constants (annealed-copper range), on copper \
                     elasticity",
            material: Material {
                strength: VoceKocks::ILLUSTRATIVE.into(),
                ..copper
            },
        },
        ReferenceMaterial {
            name: "mts-copper",
            source: "Follansbee & Kocks (1988) copper, Mechanical Threshold Stress (Uintah's \
                     tabulation), on copper elasticity",
            material: Material {
                strength: MechanicalThresholdStress::COPPER.into(),
                ..copper
            },
        },
    ]
}
