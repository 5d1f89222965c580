//! The 1250 m/s long-rod comparison the penetration studies share
//! (`stoss::validate::semi_infinite`): seed 000's rod into an 80 mm, semi-infinite HzB-W
//! target to 30 us, with both materials made elastic-perfectly plastic and isothermal so that
//! Tate's and Walker–Anderson's strengths are the materials' own.
// Each bench that includes this module uses only part of it.
#![allow(dead_code)]

use std::path::PathBuf;
use stoss::input::material::MaterialFile;
use stoss_kernel::Material;

pub use stoss::validate::semi_infinite::Shot;

/// Load the fixture shot as the studies run it.
pub fn shot() -> Shot {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    stoss::validate::semi_infinite::shot(&fixtures).expect("fixture loads")
}

/// The material file made elastic-perfectly plastic at `yield_stress` and isothermal, its
/// geometric erosion strain set to `erosion` if given (elasticity and EoS unchanged).
pub fn perfectly_plastic(file: MaterialFile, yield_stress: f64, erosion: Option<f64>) -> Material {
    stoss::validate::semi_infinite::perfectly_plastic(file, yield_stress, erosion)
        .expect("a Johnson-Cook file that erodes")
}
