//! The blast loads' figures (docs/solver.md, "Blast load", Verification): the Euler load of
//! seed 000's two charges at two cell sizes (impulse on the exposed plate and at its centre),
//! and the reflected impulse of 1 kg of TNT at 1, 2 and 3 m against Kingery–Bulmash on grids
//! wide enough not to confine the wave. Used by the `blast-load-*` and `blast-tnt-*` rows of
//! `stoss validate` and by `cargo bench -p stoss --bench blast`.

use crate::blast::kingery_bulmash;
use crate::blast::near_field::{
    Air, BlastRun, Charge, ChargeShape, Detonation, EulerSettings, Explosive, NearFieldBlast,
};
use crate::experiment::blast_plate::total_impulse;
use crate::experiment::{Experiment, Setup};
use std::path::Path;

/// The density of TNT the sphere's radius follows from (kg/m^3).
const TNT_DENSITY: f64 = 1630.0;

/// One charge's Euler load.
#[derive(Clone, Debug)]
pub struct ChargeLoad {
    /// The run (wall pressures, cells, steps, cell updates).
    pub run: BlastRun,
    /// Impulse on the exposed plate (N s).
    pub impulse: f64,
    /// Impulse per area at the centre (Pa s).
    pub centre_impulse: f64,
}

/// The Euler load of the blast-plate experiment `experiment` (a file under `fixtures`) on
/// `cell` cells, on the grid the experiment's plate uses (1.25 x its exposed radius).
pub fn charge_load(fixtures: &Path, experiment: &str, cell: f64) -> Result<ChargeLoad, String> {
    let path = fixtures.join(experiment);
    let loaded = Experiment::load(&path).map_err(|e| e.to_string())?;
    let Setup::BlastPlate(spec) = &loaded.file.setup else {
        return Err(format!("{}: not a blast-plate experiment", path.display()));
    };
    let mut blast = spec.blast();
    blast.euler.cell_size = cell;
    let run = blast
        .solve(1.25 * spec.exposed_radius, &mut |_| {})
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(ChargeLoad {
        impulse: total_impulse(&run.wall, spec.exposed_radius),
        centre_impulse: run.wall.impulse(0.0),
        run,
    })
}

/// The positive-phase reflected impulse at the axis (Pa s) of a 1 kg TNT sphere whose centre
/// is `height` (m) above a rigid wall, on 10 mm cells and a grid of radius 1.2 `height`, and
/// Kingery–Bulmash's at that distance: `(euler, kingery_bulmash)`.
pub fn tnt_reflected_impulse(height: f64) -> Result<(f64, f64), String> {
    let radius = libm::cbrt(3.0 / (4.0 * core::f64::consts::PI * TNT_DENSITY));
    let grid_radius = 1.2 * height;
    let blast = NearFieldBlast {
        charge: Charge {
            mass: 1.0,
            explosive: Explosive::Tnt,
            shape: ChargeShape::Sphere,
            diameter: None,
            standoff: height - radius,
            detonation: Detonation::Centre,
        },
        air: Air::default(),
        euler: EulerSettings {
            cell_size: 0.01,
            radius: grid_radius,
            headroom: 0.5 * height,
            end_time: 1.0e-3 + 3.0e-3 * height,
            output_interval: 5.0e-6,
            ..EulerSettings::default()
        },
    };
    let run = blast
        .solve(grid_radius, &mut |_| {})
        .map_err(|e| e.to_string())?;
    // The positive phase only, as the fit.
    let positive = run
        .wall
        .values
        .iter()
        .map(|row| row[0].max(0.0))
        .sum::<f64>()
        * run.wall.interval;
    let expected = kingery_bulmash::reflected_impulse(1.0, height).map_err(|e| e.to_string())?;
    Ok((positive, expected))
}
