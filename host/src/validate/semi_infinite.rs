//! The 1250 m/s long-rod comparison the penetration studies share: seed 000's rod
//! (`fixtures/experiments/penetration-hzb-1250.toml`) into an 80 mm, semi-infinite HzB-W target
//! to 30 us, and the materials made elastic-perfectly plastic and isothermal so that Tate's and
//! Walker–Anderson's strengths are the materials' own. Used by the `euler-strength-*` rows of
//! `stoss validate` and by the penetration benches (`host/benches/semi_infinite`).

use crate::analytic::penetration::depth_at;
use crate::experiment::penetration::PenetrationSolver;
use crate::experiment::{Experiment, PenetrationSpec, Setup};
use crate::input::material::{self, MaterialFile};
use crate::measure::interpolate;
use crate::solver::SolverSettings;
use std::path::Path;
use stoss_kernel::{Heating, Material, PartMaterial};

/// The shot and the target's and rod's material files as loaded.
#[derive(Clone, Debug)]
pub struct Shot {
    /// The fixture's set-up with an 80 mm target and a 30 us run.
    pub spec: PenetrationSpec,
    /// The target's material file (HzB-W).
    pub target: MaterialFile,
    /// The rod's material file (WHA).
    pub rod: MaterialFile,
}

/// Seed 000's 1250 m/s shot under `fixtures` as its file sets it up, and its target's
/// material file.
pub fn fixture(fixtures: &Path) -> Result<(PenetrationSpec, MaterialFile), String> {
    let path = fixtures.join("experiments/penetration-hzb-1250.toml");
    let experiment = Experiment::load(&path).map_err(|e| e.to_string())?;
    let Setup::Penetration(spec) = &experiment.file.setup else {
        return Err(format!("{}: not a penetration experiment", path.display()));
    };
    let target_path = experiment
        .default_material_path()
        .ok_or_else(|| format!("{}: no material", path.display()))?;
    let (target, _) = material::load(&target_path).map_err(|e| e.to_string())?;
    Ok((spec.clone(), target))
}

/// Load the fixture shot under `fixtures` as the studies run it.
pub fn shot(fixtures: &Path) -> Result<Shot, String> {
    let (mut spec, target) = fixture(fixtures)?;
    let (rod, _) =
        material::load(&fixtures.join("materials/wha-jc.toml")).map_err(|e| e.to_string())?;
    spec.target_thickness = 80.0e-3;
    spec.end_time = 30.0e-6;
    Ok(Shot { spec, target, rod })
}

/// The material file made elastic-perfectly plastic at `yield_stress` and isothermal, its
/// geometric erosion strain set to `erosion` if given (elasticity and EoS unchanged).
pub fn perfectly_plastic(
    mut file: MaterialFile,
    yield_stress: f64,
    erosion: Option<f64>,
) -> Result<Material, String> {
    for (name, value) in [
        ("strength.yield_stress", yield_stress),
        ("strength.hardening_modulus", 0.0),
        ("strength.rate_sensitivity", 0.0),
    ] {
        file.set_constant(name, value)
            .ok_or_else(|| format!("{}: not a Johnson-Cook file", file.name))?;
    }
    file.heating = Heating::Isothermal;
    if let Some(erosion) = erosion {
        file.failure
            .as_mut()
            .ok_or_else(|| format!("{}: has no failure model to erode with", file.name))?
            .erosion_geometric_strain = Some(erosion);
    }
    file.material().map_err(|e| e.to_string())
}

/// The Eulerian penetration rate over 10-30 us against Walker–Anderson's, the rod perfectly
/// plastic at its own `A` and the target at `target_yield` (Pa), on 0.4 mm cells.
pub fn strength_ratio(
    fixtures: &Path,
    target_yield: f64,
    threads: Option<usize>,
) -> Result<f64, String> {
    let shot = shot(fixtures)?;
    let rod_yield = shot
        .rod
        .strength
        .constant_named("yield_stress")
        .ok_or("the rod has no yield stress A")?;
    let mut spec = shot.spec;
    spec.solver = PenetrationSolver::Euler;
    spec.rod = Some(Box::new(
        perfectly_plastic(shot.rod, rod_yield, None)?.into(),
    ));
    let target = perfectly_plastic(shot.target, target_yield, None)?;
    let check = spec.cross_check(&target).map_err(|e| e.to_string())?;
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let run = spec
        .run_euler(&PartMaterial::from(target), &settings)
        .map_err(|e| e.to_string())?;
    let fe = |t: f64| interpolate(&run.result.nose_depth, t);
    let wa = |t: f64| depth_at(&check.walker_anderson, t);
    Ok((fe(30e-6) - fe(10e-6)) / (wa(30e-6) - wa(10e-6)))
}
