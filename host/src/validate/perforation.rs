//! FOI's Lagrange perforation runs (seed 001 tables 4.5-4.7) rebuilt on the bundled model of
//! `fixtures/experiments/perforation-concrete-152mm.toml`: each run's constants, slab element
//! and friction, fired at FOI's 459 m/s, against that run's Autodyn exit velocity (code to
//! code), and the variants docs/solver.md compares them with. Used by the `perforation-b99*`
//! rows of `stoss validate` and by `cargo bench -p stoss --bench perforation`.

use crate::experiment::ballistic::{BallisticLimitSpec, ShotResult};
use crate::experiment::{Experiment, Setup};
use crate::input::material;
use crate::solver::{BulkViscosity, SolverSettings};
use std::path::Path;
use stoss_kernel::rht::TensileFailure;
use stoss_kernel::PartMaterial;

/// The impact velocity of FOI's runs (m/s).
pub const FOI_VELOCITY: f64 = 459.0;

/// One run: FOI's (with its Autodyn exit velocity) or a variant of the bundled model.
#[derive(Clone, Copy, Debug)]
pub struct Run {
    /// FOI's run number, or what the variant changes.
    pub label: &'static str,
    /// FOI's exit velocity (m/s), for FOI's runs.
    pub foi_exit: Option<f64>,
    /// Slab element size (m).
    pub element: f64,
    /// RHT residual surface `(B, M)`.
    pub residual: (f64, f64),
    /// RHT damage `(D1, EFMIN)`.
    pub damage: (f64, f64),
    /// How the concrete fails in tension.
    pub tensile: TensileFailure,
    /// Projectile-slab friction coefficient.
    pub friction: f64,
    /// LS-DYNA's bulk viscosity (0.06, 1.5) instead of Autodyn's (0.2, 1.0).
    pub lsdyna_viscosity: bool,
}

/// The bundled model: table 4.4 with table 4.5's Lagrange values (FOI's B99036).
pub const LAGRANGE: Run = Run {
    label: "B99036 (the bundled constants)",
    foi_exit: Some(189.0),
    element: 10.0e-3,
    residual: (1.60, 0.61),
    damage: (0.08, 0.05),
    tensile: TensileFailure::PressureCutoff,
    friction: 0.0,
    lsdyna_viscosity: false,
};

/// FOI's seven Lagrange runs (seed tables 4.6, 10 mm, and 4.7, 5 mm), then the variants.
pub const RUNS: [Run; 11] = [
    LAGRANGE,
    Run {
        label: "B99008",
        foi_exit: Some(247.0),
        damage: (0.04, 0.01),
        ..LAGRANGE
    },
    Run {
        label: "B99035",
        foi_exit: Some(194.0),
        residual: (1.90, 0.60),
        ..LAGRANGE
    },
    Run {
        label: "B99038 (EFMIN cell blank in the seed: table 4.5's 0.05)",
        foi_exit: Some(212.0),
        damage: (0.04, 0.05),
        ..LAGRANGE
    },
    Run {
        label: "B99055",
        foi_exit: Some(269.0),
        element: 5.0e-3,
        damage: (0.04, 0.01),
        ..LAGRANGE
    },
    Run {
        label: "B99056",
        foi_exit: Some(237.0),
        element: 5.0e-3,
        ..LAGRANGE
    },
    Run {
        label: "B99057 (friction 0.05)",
        foi_exit: Some(207.0),
        element: 5.0e-3,
        friction: 0.05,
        ..LAGRANGE
    },
    Run {
        label: "table 4.4 as printed, cut-off",
        foi_exit: None,
        residual: (1.3, 0.65),
        damage: (0.04, 0.01),
        ..LAGRANGE
    },
    Run {
        label: "table 4.4 as printed, instant failure",
        foi_exit: None,
        residual: (1.3, 0.65),
        damage: (0.04, 0.01),
        tensile: TensileFailure::HydroTensileLimit,
        ..LAGRANGE
    },
    Run {
        label: "B99036, instant failure",
        foi_exit: None,
        tensile: TensileFailure::HydroTensileLimit,
        ..LAGRANGE
    },
    Run {
        label: "B99036, LS-DYNA's bulk viscosity (0.06, 1.5)",
        foi_exit: None,
        lsdyna_viscosity: true,
        ..LAGRANGE
    },
];

/// The run whose label starts with `name` (FOI's run number).
pub fn run(name: &str) -> Option<&'static Run> {
    RUNS.iter().find(|r| r.label.starts_with(name))
}

/// Fire `run` at [`FOI_VELOCITY`] on the bundled model under `fixtures`, on `threads`
/// threads; also returns the set-up it ran (for the rear damage zone).
pub fn fire(
    fixtures: &Path,
    run: &Run,
    threads: Option<usize>,
) -> Result<(BallisticLimitSpec, ShotResult), String> {
    let path = fixtures.join("experiments/perforation-concrete-152mm.toml");
    let experiment = Experiment::load(&path).map_err(|e| e.to_string())?;
    let material_path = experiment
        .default_material_path()
        .ok_or_else(|| format!("{}: no material", path.display()))?;
    let (_, slab) = material::load_part(&material_path).map_err(|e| e.to_string())?;
    let Setup::Perforation(base) = &experiment.file.setup else {
        return Err(format!("{}: not a perforation experiment", path.display()));
    };
    let mut spec = base.clone();
    spec.element_size = run.element;
    spec.friction = run.friction;
    if run.lsdyna_viscosity {
        spec.bulk_viscosity = Some(BulkViscosity::default());
    }
    let mut concrete = *slab
        .rht()
        .ok_or_else(|| format!("{}: not an RHT slab", material_path.display()))?;
    let parameters = &mut concrete.parameters;
    (parameters.residual_b, parameters.residual_m) = run.residual;
    (parameters.damage_d1, parameters.minimum_failure_strain) = run.damage;
    parameters.tensile_failure = run.tensile;
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let shot = spec
        .fire(&PartMaterial::from(concrete), FOI_VELOCITY, &settings)
        .map_err(|e| format!("{}: {e}", run.label))?;
    Ok((spec, shot))
}
