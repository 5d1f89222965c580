//! FOI's Autodyn ballistic tables (seed 001 tables 3.4-3.9, code to code) predicted with a
//! core identified from table 3.4 (docs/solver.md, "The core from FOI's own tables"): each
//! table's exit velocities simulated at FOI's impact velocities with the core and no further
//! fitting, their RMS difference from FOI's, and both codes' Lambert–Jonas limits (the
//! `foi-fine-core-*` rows of `stoss validate`, with [`FINE_MESH_CORE`]); single shots of the
//! mesh study (the `foi-core-mesh-*` rows); and the spread between two of FOI's tables.
//!
//! The shots: FOI's impact velocities, one more [`BRACKET_BELOW`] under the lowest of them
//! (a stop for every table, so that a limit below FOI's lowest shot is bracketed), then the
//! experiment's own bisection ([`BallisticLimitSpec::search`]) down to its
//! `bisection_tolerance`. The limit is the Lambert–Jonas fit (free `p`) over all of them; FOI's
//! is the same fit over FOI's rows.

use crate::analytic::ballistic::{fit_lambert_jonas, FitBound};
use crate::experiment::ballistic::{recorded_shots, ShotOutcome};
use crate::experiment::{Experiment, Setup};
use crate::input::material;
use crate::solver::SolverSettings;
use std::path::Path;
use stoss_kernel::strength::{Hardening, Strength};
use stoss_kernel::PartMaterial;

/// The core `stoss calibrate fixtures/campaigns/ballistic-geometry.toml` identified from table
/// 3.4 (2026-11-28; docs/solver.md): length, diameter and ogive nose length (m).
pub const IDENTIFIED_CORE: Core = Core {
    length: 0.012_343_3,
    diameter: 0.003_509_17,
    nose_length: 0.008_688_88,
};

/// The core the same campaign identified from table 3.4 with the core meshed at 0.1 mm (plate
/// 0.2 mm; 2026-11-29, docs/solver.md, "The core identified on a resolved core mesh").
pub const FINE_MESH_CORE: Core = Core {
    length: 0.012,
    diameter: 0.004_575_555_555_555_556,
    nose_length: 0.008_444_444_444_437_295,
};

/// How far below FOI's lowest impact velocity the extra bracketing shot is fired (m/s).
pub const BRACKET_BELOW: f64 = 100.0;

/// A core's geometry (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Core {
    /// Tip to base.
    pub length: f64,
    /// Diameter.
    pub diameter: f64,
    /// Ogive nose length.
    pub nose_length: f64,
}

/// One table predicted.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// `(impact, FOI's exit, stoss' exit)` at FOI's impact velocities (m/s).
    pub exits: Vec<(f64, f64, f64)>,
    /// RMS of stoss' exit minus FOI's over those shots (m/s).
    pub rms: f64,
    /// stoss' Lambert–Jonas limit over all its shots (m/s).
    pub limit: f64,
    /// Where stoss' fit ended on an edge of the law's box or on a stop (empty: free).
    pub limit_bounds: Vec<FitBound>,
    /// FOI's Lambert–Jonas limit over FOI's rows (m/s).
    pub foi_limit: f64,
    /// Every shot stoss fired `(impact, exit)`, by increasing impact velocity (m/s).
    pub shots: Vec<(f64, f64)>,
}

/// A FOI table's experiment loaded with `core` in place of its file's: the loaded file, its
/// ballistic set-up with the core's geometry, and the plate's material.
struct WithCore {
    path: std::path::PathBuf,
    loaded: Experiment,
    spec: crate::experiment::ballistic::BallisticLimitSpec,
    plate: PartMaterial,
}

/// Load `experiment` (a `ballistic-foi-t3*.toml` under `fixtures`) and put `core` in it.
fn with_core(fixtures: &Path, experiment: &str, core: Core) -> Result<WithCore, String> {
    let path = fixtures.join(experiment);
    let loaded = Experiment::load(&path).map_err(|e| e.to_string())?;
    let Setup::BallisticLimit(base) = &loaded.file.setup else {
        return Err(format!(
            "{}: not a ballistic-limit experiment",
            path.display()
        ));
    };
    let mut spec = base.clone();
    spec.projectile_length = core.length;
    spec.projectile_diameter = core.diameter;
    spec.nose_length = Some(core.nose_length);
    let material_path = loaded
        .default_material_path()
        .ok_or_else(|| format!("{}: no material", path.display()))?;
    let (_, plate) = material::load_part(&material_path).map_err(|e| e.to_string())?;
    Ok(WithCore {
        path,
        loaded,
        spec,
        plate,
    })
}

/// Predict the table of `experiment` (a `ballistic-foi-t3*.toml` under `fixtures`) with `core`,
/// the core meshed at `core_element_size` (m; the file's when `None`), on `threads` threads.
pub fn predict(
    fixtures: &Path,
    experiment: &str,
    core: Core,
    core_element_size: Option<f64>,
    threads: Option<usize>,
) -> Result<Prediction, String> {
    let WithCore {
        path,
        loaded,
        mut spec,
        plate,
    } = with_core(fixtures, experiment, core)?;
    if let Some(size) = core_element_size {
        spec.projectile_element_size = size;
    }
    let foi = recorded_shots(&loaded.recording);
    let lowest = foi
        .first()
        .ok_or_else(|| format!("{}: no recorded exit velocities", path.display()))?
        .impact_velocity;
    let foi_limit = fit_lambert_jonas(&foi, None)
        .map_err(|e| format!("{}: FOI's rows: {e}", path.display()))?
        .ballistic_limit;

    spec.impact_velocities = std::iter::once(lowest - BRACKET_BELOW)
        .chain(foi.iter().map(|s| s.impact_velocity))
        .collect();
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let search = spec
        .search(&plate, &settings)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let fit = search
        .lambert_jonas
        .as_ref()
        .map_err(|e| format!("{}: stoss' shots: {e}", path.display()))?;
    let mut exits = Vec::with_capacity(foi.len());
    for shot in &foi {
        let fired = search
            .shots
            .iter()
            .find(|s| s.impact_velocity == shot.impact_velocity)
            .ok_or_else(|| format!("no shot at {} m/s", shot.impact_velocity))?;
        if fired.outcome == ShotOutcome::Undetermined {
            return Err(format!(
                "{}: the shot at {} m/s is still in the plate at the end",
                path.display(),
                shot.impact_velocity
            ));
        }
        exits.push((
            shot.impact_velocity,
            shot.residual_velocity,
            fired.residual_velocity,
        ));
    }
    let rms = libm::sqrt(
        exits.iter().map(|(_, f, s)| (s - f) * (s - f)).sum::<f64>() / exits.len() as f64,
    );
    Ok(Prediction {
        exits,
        rms,
        limit: fit.ballistic_limit,
        limit_bounds: fit.bounds.clone(),
        foi_limit,
        shots: search
            .shots
            .iter()
            .map(|s| (s.impact_velocity, s.residual_velocity))
            .collect(),
    })
}

/// The plate and core meshes of one shot of [`mesh_shot`] (m), and whether the core is kept
/// elastic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShotMesh {
    /// The plate's element size (m).
    pub plate: f64,
    /// The core's element size (m).
    pub core: f64,
    /// The core's yield stress raised tenfold (50 GPa for table 3.3's core): it stays elastic.
    pub elastic_core: bool,
}

/// Impact velocity of the mesh study's shot (m/s): well above every table's limit, so that the
/// exit velocity is settled and not a flip between stopped and perforated.
pub const MESH_SHOT_VELOCITY: f64 = 800.0;

/// The exit velocity of one shot at [`MESH_SHOT_VELOCITY`] with `core` on table 3.4's set-up
/// (`experiment`, a `ballistic-foi-t34.toml` under `fixtures`), the plate and core meshed as
/// `mesh` (the gap 0.019 mm with a 0.1 mm plate, seed 001's refined model; the file's
/// otherwise): 0 for a stopped core (docs/solver.md, "Why: the core's nose yields").
pub fn mesh_shot(
    fixtures: &Path,
    experiment: &str,
    core: Core,
    mesh: ShotMesh,
    threads: Option<usize>,
) -> Result<f64, String> {
    let WithCore {
        path,
        mut spec,
        plate,
        ..
    } = with_core(fixtures, experiment, core)?;
    spec.element_size = mesh.plate;
    spec.projectile_element_size = mesh.core;
    if mesh.plate <= 0.1e-3 {
        spec.gap = 0.019e-3;
    }
    if mesh.elastic_core {
        let Some(PartMaterial::J2(material)) = spec.projectile.as_deref_mut() else {
            return Err(format!("{}: the core is not a J2 material", path.display()));
        };
        let Strength::Composed(model) = &mut material.strength else {
            return Err(format!(
                "{}: the core has no composed strength",
                path.display()
            ));
        };
        let Hardening::Power { yield_stress, .. } = &mut model.hardening else {
            return Err(format!(
                "{}: the core's hardening is not a power law",
                path.display()
            ));
        };
        *yield_stress *= 10.0;
    }
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let shot = spec
        .fire(&plate, MESH_SHOT_VELOCITY, &settings)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    match shot.outcome {
        ShotOutcome::Perforated => Ok(shot.residual_velocity),
        ShotOutcome::Stopped => Ok(0.0),
        ShotOutcome::Undetermined => Err(format!(
            "{}: the shot is still in the plate at the end",
            path.display()
        )),
    }
}

/// The RMS difference of two recordings' exit velocities over the impact velocities both hold
/// (m/s): for two of FOI's tables of one model in two Autodyn versions (3.4 and 3.8, 3.7 and
/// 3.9), the code's own spread, against which a prediction's RMS can be read.
pub fn recordings_rms(first: &Experiment, second: &Experiment) -> Result<f64, String> {
    let second_shots = recorded_shots(&second.recording);
    let differences: Vec<f64> = recorded_shots(&first.recording)
        .iter()
        .filter_map(|a| {
            second_shots
                .iter()
                .find(|b| b.impact_velocity == a.impact_velocity)
                .map(|b| a.residual_velocity - b.residual_velocity)
        })
        .collect();
    if differences.is_empty() {
        return Err(format!(
            "{} and {}: no impact velocity in common",
            first.path.display(),
            second.path.display()
        ));
    }
    let sum: f64 = differences.iter().map(|d| d * d).sum();
    Ok((sum / differences.len() as f64).sqrt())
}
