//! The 1250 m/s long-rod comparison the penetration studies share: seed 000's rod
//! (`fixtures/experiments/penetration-hzb-1250.toml`) into an 80 mm, semi-infinite HzB-W target
//! to 30 us, and the materials made elastic-perfectly plastic and isothermal so that Tate's and
//! Walker–Anderson's strengths are the materials' own; and the crater of the Eulerian shot
//! ([`euler_crater`]). Used by the `euler-strength-*` and `euler-crater-*` rows of
//! `stoss validate` and by the penetration benches (`host/benches/semi_infinite`).

use crate::analytic::penetration::depth_at;
use crate::experiment::penetration::euler::{rod_extent, ROD, TARGET};
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

/// The Eulerian penetration rate over 10-30 us against Walker–Anderson's, the rod striking at
/// `velocity` (m/s) and perfectly plastic at its own `A`, the target at `target_yield` (Pa), on
/// 0.4 mm cells.
pub fn strength_ratio(
    fixtures: &Path,
    velocity: f64,
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
    spec.velocity = velocity;
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

/// The Eulerian crater over 10-30 us after impact (docs/euler.md, "Where the crater is
/// read"), in rod radii `a`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerCrater {
    /// The penetration rate over Walker–Anderson's, 10-30 us.
    pub rate_ratio: f64,
    /// `R_c / a` one to three rod radii above the nose: the radius at which the target's
    /// volume fraction crosses one half (interpolated between cell centres), averaged over
    /// the rows and the output times.
    pub behind_head: f64,
    /// The same within one rod radius above the nose.
    pub at_head: f64,
}

/// The shot's crater on the Eulerian solver with `element` cells, the rod striking at
/// `velocity` (m/s), the target the fixture's HzB-W file as it is or made isothermal (its
/// thermal softening off).
pub fn euler_crater(
    fixtures: &Path,
    element: f64,
    velocity: f64,
    isothermal: bool,
    threads: Option<usize>,
) -> Result<EulerCrater, String> {
    let (_, mut file) = fixture(fixtures)?;
    if isothermal {
        file.heating = Heating::Isothermal;
    }
    euler_crater_at(fixtures, file, element, velocity, threads)
}

/// The shot's crater on the Eulerian solver with `element` cells, the rod striking a target of
/// material `file` at `velocity` (m/s) (the [`shot`] set-up: 80 mm, 30 us).
pub fn euler_crater_at(
    fixtures: &Path,
    file: MaterialFile,
    element: f64,
    velocity: f64,
    threads: Option<usize>,
) -> Result<EulerCrater, String> {
    let shot = shot(fixtures)?;
    let a = 0.5 * shot.spec.rod_diameter;
    let target = file.material().map_err(|e| e.to_string())?;
    let mut spec = shot.spec;
    spec.solver = PenetrationSolver::Euler;
    spec.element_size = element;
    spec.velocity = velocity;
    let check = spec.cross_check(&target).map_err(|e| e.to_string())?;
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let mut solver = spec
        .euler_model(&target.into(), &settings)
        .map_err(|e| e.to_string())?;
    let impact = spec.gap() / spec.velocity;
    let (start, end) = (impact + 10.0e-6, impact + 30.0e-6);
    let mut noses: Vec<(f64, f64)> = Vec::new();
    let (mut behind, mut head): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    solver
        .run(end, 0.5e-6, &mut |s| {
            let (nose, _) = rod_extent(s, ROD);
            noses.push((s.time, -nose));
            if s.time >= start && nose.is_finite() {
                let (hr, hz, cells_r) = (s.grid.spacing_r, s.grid.spacing_z, s.grid.cells_r);
                for j in 0..s.grid.cells_z {
                    let z = s.origin_z + (j as f64 + 0.5) * hz;
                    let into = if z >= nose + a && z <= nose + 3.0 * a {
                        &mut behind
                    } else if z >= nose && z < nose + a {
                        &mut head
                    } else {
                        continue;
                    };
                    let f = |i: usize| s.fraction(j * cells_r + i, TARGET);
                    if let Some(i) = (1..cells_r).find(|&i| f(i) >= 0.5) {
                        let (f0, f1) = (f(i - 1), f(i));
                        let r0 = (i as f64 - 0.5) * hr;
                        into.push(r0 + hr * (0.5 - f0) / (f1 - f0));
                    }
                }
            }
            std::ops::ControlFlow::Continue(())
        })
        .map_err(|e| e.to_string())?;
    let fe_rate = (interpolate(&noses, end) - interpolate(&noses, start)) / (end - start);
    let wa = |t: f64| depth_at(&check.walker_anderson, t - impact);
    let wa_rate = (wa(end) - wa(start)) / (end - start);
    let mean = |radii: &[f64]| {
        (!radii.is_empty())
            .then(|| radii.iter().sum::<f64>() / radii.len() as f64 / a)
            .ok_or("the crater was never read: no target row near the nose")
    };
    Ok(EulerCrater {
        rate_ratio: fe_rate / wa_rate,
        behind_head: mean(&behind)?,
        at_head: mean(&head)?,
    })
}

/// The eroding Lagrangian model on the shot with the target's Johnson–Cook `A` set
/// (docs/solver.md, "The bias grows with the target's strength").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LagrangeStrength {
    /// Nose depth at 10 and 30 us, FE and Walker–Anderson `((fe, wa), (fe, wa))` (m).
    pub depths: ((f64, f64), (f64, f64)),
    /// The penetration rate over Walker–Anderson's, 10-30 us.
    pub rate_ratio: f64,
    /// The rod's length at 30 us (m).
    pub rod_length: f64,
    /// The largest tolerated exposure (a node found inside the other part when erosion
    /// exposes a surface) over the smallest element.
    pub exposure: f64,
    /// The energy balance's error (%).
    pub energy_error: f64,
}

/// The 1250 m/s shot on the eroding Lagrangian model (0.4 mm), the target the fixture's
/// HzB-W with its `A` set to `target_a` (Pa), everything else as in the fixture; the time-step
/// safety factor `safety` if given.
pub fn lagrange_strength(
    fixtures: &Path,
    target_a: f64,
    safety: Option<f64>,
    threads: Option<usize>,
) -> Result<LagrangeStrength, String> {
    let shot = shot(fixtures)?;
    let mut file = shot.target;
    file.set_constant("strength.yield_stress", target_a)
        .ok_or_else(|| format!("{}: not a Johnson-Cook file", file.name))?;
    let target = file.material().map_err(|e| e.to_string())?;
    let mut settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    if let Some(safety) = safety {
        settings.time_step_safety = safety;
    }
    let spec = shot.spec;
    let check = spec.cross_check(&target).map_err(|e| e.to_string())?;
    let (result, run, built) = spec
        .run(&target.into(), &settings)
        .map_err(|e| e.to_string())?;
    let fe = |t: f64| interpolate(&result.nose_depth, t);
    let wa = |t: f64| depth_at(&check.walker_anderson, t);
    Ok(LagrangeStrength {
        depths: ((fe(10e-6), wa(10e-6)), (fe(30e-6), wa(30e-6))),
        rate_ratio: (fe(30e-6) - fe(10e-6)) / (wa(30e-6) - wa(10e-6)),
        rod_length: interpolate(&result.rod_length, 30e-6),
        exposure: run.contact.largest_initial_penetration / built.smallest_element,
        energy_error: run.energy().error_percent(),
    })
}

/// A rod that stays elastic, striking with a hemispherical nose, against the rigid-projectile
/// cavity-expansion model (docs/euler.md, "A rod that does not erode").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidRod {
    /// The FE nose depth at [`RIGID_ROD_TIME`] (m).
    pub depth: f64,
    /// The model's depth at the same time (m).
    pub analytic: f64,
}

/// Striking velocity of [`rigid_rod`] (m/s).
pub const RIGID_ROD_VELOCITY: f64 = 800.0;
/// Time after impact at which [`rigid_rod`] compares the depths (s).
pub const RIGID_ROD_TIME: f64 = 40.0e-6;
/// The yield stress that keeps [`rigid_rod`]'s tungsten rod elastic (Pa): above any stress of
/// the shot.
const ELASTIC_ROD_YIELD: f64 = 20.0e9;

/// The [`shot`] set-up (80 mm target) with the rod made elastic ([`ELASTIC_ROD_YIELD`]), a
/// hemispherical nose, [`RIGID_ROD_VELOCITY`], the target perfectly plastic at its own `A`
/// (1.5 GPa) and isothermal, on `solver` with `element` cells (the Eulerian interface sliding
/// if `sliding`); and the depth of Forrestal's
/// rigid projectile of the rod's mass in that target (`sigma_s` Hill's static cavity pressure
/// of the target's `A`, `K` and `G`; `B` = 3/2; `N` = 1/2).
pub fn rigid_rod(
    fixtures: &Path,
    solver: PenetrationSolver,
    element: f64,
    sliding: bool,
    threads: Option<usize>,
) -> Result<RigidRod, String> {
    use crate::analytic::penetration::{
        ogive_nose_factor, rigid_projectile_history, spherical_cavity_pressure, RigidProjectile,
        INCOMPRESSIBLE_INERTIAL_COEFFICIENT,
    };
    let shot = shot(fixtures)?;
    let target_yield = shot
        .target
        .strength
        .constant_named("yield_stress")
        .ok_or("the target has no yield stress A")?;
    let rod = perfectly_plastic(shot.rod, ELASTIC_ROD_YIELD, None)?;
    let target = perfectly_plastic(shot.target, target_yield, None)?;
    let mut spec = shot.spec;
    spec.solver = solver;
    spec.element_size = element;
    spec.velocity = RIGID_ROD_VELOCITY;
    spec.nose = crate::experiment::penetration::Nose::Hemispherical;
    spec.end_time = RIGID_ROD_TIME;
    spec.sliding_interface = sliding;
    let a = 0.5 * spec.rod_diameter;
    let rod_volume = std::f64::consts::PI * a * a * (spec.rod_length - a)
        + 2.0 / 3.0 * std::f64::consts::PI * a * a * a;
    spec.rod = Some(Box::new(rod.into()));
    let (bulk, shear) = crate::experiment::penetration::moduli(&target, spec.temperature)?;
    let projectile = RigidProjectile {
        mass: rod.density * rod_volume,
        radius: a,
        // The hemisphere is the ogive of caliber-radius-head 1/2.
        nose_factor: ogive_nose_factor(0.5),
        target_density: target.density,
        static_resistance: spherical_cavity_pressure(target_yield, bulk, shear),
        inertial_coefficient: INCOMPRESSIBLE_INERTIAL_COEFFICIENT,
        striking_velocity: RIGID_ROD_VELOCITY,
    };
    let analytic =
        rigid_projectile_history(&projectile, RIGID_ROD_TIME, 1.0e-6).map_err(|e| e.to_string())?;
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let target = PartMaterial::from(target);
    let history = match solver {
        PenetrationSolver::Euler => {
            spec.run_euler(&target, &settings)
                .map_err(|e| e.to_string())?
                .result
                .nose_depth
        }
        PenetrationSolver::Lagrange => {
            spec.run(&target, &settings)
                .map_err(|e| e.to_string())?
                .0
                .nose_depth
        }
    };
    Ok(RigidRod {
        depth: interpolate(&history, RIGID_ROD_TIME),
        analytic: depth_at(&analytic, RIGID_ROD_TIME),
    })
}
