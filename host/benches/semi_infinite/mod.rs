//! The 1250 m/s long-rod comparison the penetration studies share: seed 000's rod
//! (`fixtures/experiments/penetration-hzb-1250.toml`) into an 80 mm, semi-infinite HzB-W target
//! to 30 us, with both materials made elastic-perfectly plastic and isothermal so that Tate's
//! and Walker–Anderson's strengths are the materials' own.
// Each bench that includes this module uses only part of it.
#![allow(dead_code)]

use std::path::PathBuf;
use stoss::experiment::{Experiment, PenetrationSpec, Setup};
use stoss::input::material::{self, MaterialFile};
use stoss_kernel::Heating;
use stoss_kernel::Material;

/// The shot and the target's and rod's material files as loaded.
pub struct Shot {
    /// The fixture's set-up with an 80 mm target and a 30 us run.
    pub spec: PenetrationSpec,
    /// The target's material file (HzB-W).
    pub target: MaterialFile,
    /// The rod's material file (WHA).
    pub rod: MaterialFile,
}

/// Load the fixture shot as the studies run it.
pub fn shot() -> Shot {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let experiment = Experiment::load(&fixtures.join("experiments/penetration-hzb-1250.toml"))
        .expect("fixture loads");
    let Setup::Penetration(base) = &experiment.file.setup else {
        panic!("not a penetration experiment");
    };
    let (target, _) = material::load(&experiment.default_material_path().expect("material"))
        .expect("target loads");
    let (rod, _) = material::load(&fixtures.join("materials/wha-jc.toml")).expect("rod loads");
    let mut spec = base.clone();
    spec.target_thickness = 80.0e-3;
    spec.end_time = 30.0e-6;
    Shot { spec, target, rod }
}

/// The material file made elastic-perfectly plastic at `yield_stress` and isothermal, its
/// geometric erosion strain set to `erosion` if given (elasticity and EoS unchanged).
pub fn perfectly_plastic(
    mut file: MaterialFile,
    yield_stress: f64,
    erosion: Option<f64>,
) -> Material {
    for (name, value) in [
        ("strength.yield_stress", yield_stress),
        ("strength.hardening_modulus", 0.0),
        ("strength.rate_sensitivity", 0.0),
    ] {
        file.set_constant(name, value).expect("a Johnson-Cook file");
    }
    file.heating = Heating::Isothermal;
    if let Some(erosion) = erosion {
        file.failure
            .as_mut()
            .expect("the fixture erodes")
            .erosion_geometric_strain = Some(erosion);
    }
    file.material().expect("valid material")
}
