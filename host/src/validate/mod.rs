//! `stoss validate`: the headline figures of README.md and docs/*.md, re-run and compared with
//! the value each document states.
//!
//! A figure a document quotes is a claim about what stoss computes. Each [`Row`] names the
//! figure, where it is quoted, the stated value and the tolerance it is quoted to (one unit
//! of its last printed digit for a deterministic simulation, or the bound the document
//! claims), and how to measure it: an experiment of `fixtures/` simulated with its own
//! material (optionally with one set-up field changed), or an analytic evaluation of bundled
//! data. Rows are fast (seconds to a minute; CI runs them), slow (minutes) or full (a whole
//! campaign, an hour or more; `--full`).
//!
//! The figures that tests assert already (the verification tables) are not repeated here:
//! this is for the validation figures, which are too slow for the test suite or rest on a
//! whole run.

pub mod blast;
pub mod euler;
pub mod finish;
pub mod foi_tables;
pub mod identification;
pub mod perforation;
pub mod semi_infinite;

use crate::analytic::ballistic::fit_lambert_jonas;
use crate::experiment::{Experiment, Setup};
use crate::fit::result::ModelResult;
use crate::input::material;
use crate::solver::SolverSettings;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How long a row takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Speed {
    /// Seconds to about a minute on 2 cores: run in CI (`stoss validate --fast`).
    Fast,
    /// Minutes to about half an hour: run by `stoss validate` without `--fast`.
    Slow,
    /// An hour or more (a whole campaign): run only with `--full` or by name.
    Full,
}

/// How a row's figure is measured.
#[derive(Clone, Copy, Debug)]
pub enum Measure {
    /// Simulate `experiment` (a path under the fixtures folder) with its own material, after
    /// `adjust` changes its set-up, and read the named summary value (SI).
    Summary {
        /// Experiment file, relative to the fixtures folder.
        experiment: &'static str,
        /// Summary key of the outcome.
        key: &'static str,
        /// A change to the set-up (e.g. the element size), or none.
        adjust: Option<fn(&mut Setup)>,
    },
    /// Simulate `experiment` and read the prediction of its recorded point of `quantity` at
    /// `position` (SI; one simulation per process serves every row that reads it).
    Predicted {
        /// Experiment file, relative to the fixtures folder.
        experiment: &'static str,
        /// Recorded quantity.
        quantity: &'static str,
        /// The point's position (its time, impact velocity...), SI.
        position: f64,
    },
    /// Run `stoss calibrate` on `campaign` (relative to the fixtures folder) into a fresh
    /// temporary folder and read one of `model`'s figures from its `report/result.json` (the
    /// folder is removed afterwards).
    Calibration {
        /// Campaign file, relative to the fixtures folder.
        campaign: &'static str,
        /// Model name in the campaign.
        model: &'static str,
        /// Which figure.
        figure: CalibrationFigure,
    },
    /// How many of [`identification::SEEDS`] noise seeds `stoss diagnose` names a concealed
    /// effect in (`fixtures/diagnosis/<case>`, the `level`-th of
    /// [`identification::NOISE_LEVELS`]; one run per case and level in a process).
    Identification {
        /// The case, a name of [`identification::CASES`].
        case: &'static str,
        /// The noise level's position in [`identification::NOISE_LEVELS`].
        level: usize,
        /// What is counted.
        count: Count,
    },
    /// The median over [`finish::SEEDS`] seeds of the simulations ten Bayesian steps and the
    /// least-squares finish need to bring the synthetic flow campaign within `factor` times its
    /// noise floor ([`finish::simulations_to_target`]).
    Finish {
        /// The target as a multiple of the noise floor.
        factor: f64,
    },
    /// The median over [`finish::SEEDS`] seeds of the simulations `baseline` alone needs to
    /// bring the synthetic flow campaign within `factor` times its noise floor, within `budget`
    /// ([`finish::baseline_to_target`]), or how many seeds got there (`count`).
    Baseline {
        /// Count the seeds that reached the target (else the median simulations).
        count: bool,
        /// The optimiser.
        baseline: finish::Baseline,
        /// The target as a multiple of the noise floor.
        factor: f64,
        /// Most simulations per seed.
        budget: usize,
    },
    /// The Euler load of a blast-plate experiment (a file under the fixtures folder) on `cell`
    /// cells ([`blast::charge_load`]): the impulse on the exposed plate (N s) or at its centre
    /// (`centre`, Pa s).
    BlastLoad {
        /// Experiment file, relative to the fixtures folder.
        experiment: &'static str,
        /// Cell size (m).
        cell: f64,
        /// The centre's impulse per area (else the plate's impulse).
        centre: bool,
    },
    /// The Euler reflected impulse at the axis of 1 kg of TNT `height` (m) above a wall
    /// ([`blast::tnt_reflected_impulse`]), Pa s.
    TntImpulse {
        /// Height of the charge's centre (m).
        height: f64,
    },
    /// The exit velocity (m/s) of one of FOI's perforation runs rebuilt on the bundled model
    /// ([`perforation::RUNS`], by FOI's run number), fired at 459 m/s.
    FoiPerforation {
        /// FOI's run number (`B99036`...).
        run: &'static str,
    },
    /// How far the Eulerian 1250 m/s shot's final depths lie from a straight line when the
    /// striking velocity (`strength: false`) or the target's `A` (`true`) moves by a few
    /// parts in a thousand ([`euler::by_velocity`], [`euler::by_strength`]); an error if the
    /// depths are not monotone.
    EulerSmooth {
        /// Vary the target's `A` (else the striking velocity).
        strength: bool,
    },
    /// The Eulerian penetration rate over 10-30 us against Walker–Anderson's, the rod and a
    /// semi-infinite target made perfectly plastic, the rod at `velocity` (m/s), the target at
    /// `target_yield` (Pa) ([`semi_infinite::strength_ratio`]).
    EulerStrength {
        /// The striking velocity (m/s).
        velocity: f64,
        /// The target's yield stress (Pa).
        target_yield: f64,
    },
    /// A rod kept elastic, with a hemispherical nose, into the perfectly plastic semi-infinite
    /// target at 800 m/s: its nose depth at 40 us over the rigid-projectile cavity-expansion
    /// model's ([`semi_infinite::rigid_rod`]).
    RigidRod {
        /// The Eulerian solver (else the eroding Lagrangian one).
        euler: bool,
        /// Cell or element size (m).
        element: f64,
        /// The Eulerian solver's sliding interface (`sliding_interface`).
        sliding: bool,
    },
    /// One of FOI's ballistic tables predicted with a core identified from table 3.4
    /// ([`foi_tables::predict`]): the RMS exit difference from FOI's (`limit: false`) or
    /// stoss' Lambert–Jonas limit (`true`), m/s (one run per table, core and mesh in a
    /// process).
    FoiCore {
        /// The table's experiment file, relative to the fixtures folder.
        experiment: &'static str,
        /// The core.
        core: foi_tables::Core,
        /// The core's element size (m; the file's when `None`).
        core_mesh: Option<f64>,
        /// The limit (else the RMS exit difference).
        limit: bool,
    },
    /// One shot at 800 m/s with the core identified from table 3.4, the plate and core meshed
    /// as given, the core elastic-plastic or kept elastic ([`foi_tables::mesh_shot`]): its
    /// exit velocity, m/s (0 when stopped).
    FoiCoreMesh {
        /// Table 3.4's experiment file, relative to the fixtures folder.
        experiment: &'static str,
        /// The core.
        core: foi_tables::Core,
        /// The plate and core meshes and the core's strength.
        mesh: foi_tables::ShotMesh,
    },
    /// The Eulerian shot's crater radius over the rod radius, 10-30 us
    /// ([`semi_infinite::euler_crater`]): one to three rod radii above the nose, or within one
    /// (`at_head`); one run per velocity, cell size and heating in a process.
    EulerCrater {
        /// Striking velocity (m/s).
        velocity: f64,
        /// Cell size (m).
        element: f64,
        /// The target made isothermal.
        isothermal: bool,
        /// Within one rod radius of the nose (else one to three).
        at_head: bool,
    },
    /// The eroding Lagrangian penetration rate over 10-30 us against Walker–Anderson's, the
    /// fixture's HzB-W target with its `A` at `target_a` (Pa)
    /// ([`semi_infinite::lagrange_strength`]).
    LagrangeStrength {
        /// The target's Johnson–Cook `A` (Pa).
        target_a: f64,
    },
    /// The Lambert–Jonas limit (free `p`) of a bundled ballistic recording's shots (m/s).
    LambertJonas {
        /// Experiment file whose recording holds the shots, relative to the fixtures folder.
        experiment: &'static str,
    },
    /// The RMS difference of two bundled ballistic recordings' exit velocities over the impact
    /// velocities both hold (m/s): how far two of FOI's Autodyn tables of one model disagree
    /// ([`foi_tables::recordings_rms`]).
    RecordingsRms {
        /// Experiment files whose recordings hold the shots, relative to the fixtures folder.
        experiments: (&'static str, &'static str),
    },
}

/// What an [`Measure::Identification`] row counts over the noise seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Count {
    /// The concealed term accepted.
    Identified,
    /// The concealed term or another of the same physics accepted.
    IdentifiedOrSamePhysics,
    /// An unrelated term accepted (any term, on the control).
    FalseAlarms,
}

/// One headline figure.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    /// Short name, used on the command line and cited beside the figure in the documents.
    pub name: &'static str,
    /// What the figure is.
    pub figure: &'static str,
    /// Where it is quoted.
    pub quoted_in: &'static str,
    /// The stated value, in `unit`.
    pub stated: f64,
    /// The tolerance it is quoted to, in `unit`.
    pub tolerance: f64,
    /// Unit of `stated` and `tolerance`.
    pub unit: &'static str,
    /// SI value times `scale` is the value in `unit`.
    pub scale: f64,
    /// Fast or slow.
    pub speed: Speed,
    /// How to measure it.
    pub measure: Measure,
}

fn square_plate_elements(setup: &mut Setup) {
    if let Setup::BlastPlate(spec) = setup {
        spec.aspect_ratio = 1.0;
    }
}

fn damping_after_yielding(setup: &mut Setup) {
    if let Setup::BlastPlate(spec) = setup {
        spec.damping_after_yielding = true;
    }
}

fn beam_at_20_mm(setup: &mut Setup) {
    if let Setup::DropWeightBeam(spec) = setup {
        spec.element_size = 0.02;
    }
}

fn element_size_0_2_mm(setup: &mut Setup) {
    if let Setup::Penetration(spec) = setup {
        spec.element_size = 0.2e-3;
    }
}

/// The penetration plate made twice as thick: over the recorded run the rear face is then
/// further ahead of the nose than the target's plastic zone reaches, so the shot is the
/// semi-infinite one Walker–Anderson models.
fn target_twice_as_thick(setup: &mut Setup) {
    if let Setup::Penetration(spec) = setup {
        spec.target_thickness *= 2.0;
    }
}

fn element_size_0_1_mm(setup: &mut Setup) {
    if let Setup::Penetration(spec) = setup {
        spec.element_size = 0.1e-3;
    }
}

/// A row of the diagnosis' identification rate (docs/diagnosis.md): `(case, noise level,
/// what is counted)` over [`identification::SEEDS`] seeds, stated as a count of 10. Always a
/// slow row: an identification rate is a validation figure, not a CI check (CI's diagnosis
/// checks are `tests/diagnose.rs`).
const fn identify(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (case, level, count): (&'static str, usize, Count),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/diagnosis.md, Identification rate; README.md, Status",
        stated,
        tolerance: 0.5,
        unit: "of 10",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Identification { case, level, count },
    }
}

/// A row of FOI's perforation run `run` rebuilt (docs/solver.md): its exit velocity, m/s.
const fn foi_perforation(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    run: &'static str,
) -> Row {
    Row {
        name,
        figure,
        quoted_in:
            "docs/solver.md, Concrete perforation, Results: seed 001's Lagrange model rebuilt",
        stated,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::FoiPerforation { run },
    }
}

/// A fast row: the RMS exit difference between two of FOI's tables of one model
/// ([`Measure::RecordingsRms`]), m/s.
const fn foi_tables_rms(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    experiments: (&'static str, &'static str),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/solver.md, Ballistic limit, The core from FOI's own tables",
        stated,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::RecordingsRms { experiments },
    }
}

/// A row of FOI's table `experiment` predicted with [`foi_tables::FINE_MESH_CORE`], the core
/// identified from table 3.4 on a 0.1 mm core mesh, meshed at 0.1 mm in every table
/// (docs/solver.md, "Every table predicted with the core identified on the resolved core
/// mesh"): the RMS exit difference (`limit: false`) or stoss' limit, m/s.
const fn foi_fine_core(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (experiment, limit): (&'static str, bool),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/solver.md, Ballistic limit, The core from FOI's own tables",
        stated,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::FoiCore {
            experiment,
            core: foi_tables::FINE_MESH_CORE,
            core_mesh: Some(0.1e-3),
            limit,
        },
    }
}

/// A row of the ballistic mesh study (docs/solver.md): the exit velocity at 800 m/s with the
/// identified core, plate and core meshed `(plate, core)` (m), the core elastic or not.
const fn foi_core_mesh(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (plate, core_mesh, elastic_core): (f64, f64, bool),
) -> Row {
    foi_core_mesh_with(
        name,
        figure,
        stated,
        foi_tables::IDENTIFIED_CORE,
        (plate, core_mesh, elastic_core),
    )
}

/// [`foi_core_mesh`] with another core.
const fn foi_core_mesh_with(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    core: foi_tables::Core,
    (plate, core_mesh, elastic_core): (f64, f64, bool),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/solver.md, Ballistic limit, The core from FOI's own tables",
        stated,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::FoiCoreMesh {
            experiment: "experiments/ballistic-foi-t34.toml",
            core,
            mesh: foi_tables::ShotMesh {
                plate,
                core: core_mesh,
                elastic_core,
            },
        },
    }
}

/// A row of the Eulerian crater (docs/euler.md), `R_c / a` with the bundled HzB-W target
/// (adiabatic) struck at `velocity` on `element` cells, behind the head or at it.
const fn euler_crater_row(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (velocity, element, at_head): (f64, f64, bool),
    speed: Speed,
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/euler.md, Validation",
        stated,
        tolerance: 0.005,
        unit: "a",
        scale: 1.0,
        speed,
        measure: Measure::EulerCrater {
            velocity,
            element,
            isothermal: false,
            at_head,
        },
    }
}

/// A row of the eroding Lagrangian strength sweep (docs/solver.md): the rate over
/// Walker–Anderson's with the HzB-W target's `A` at `target_a` (Pa).
const fn lagrange_strength(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    target_a: f64,
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/solver.md, Accuracy",
        stated,
        tolerance: 0.005,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::LagrangeStrength { target_a },
    }
}

/// A row of a blast charge's Euler load (docs/solver.md): the impulse on the exposed plate
/// (N s) or at its centre (Pa s) on `cell` cells.
const fn blast_load(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (experiment, cell, centre): (&'static str, f64, bool),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/solver.md, Blast load, Verification",
        stated,
        tolerance: if centre { 1.0 } else { 0.01 },
        unit: if centre { "Pa s" } else { "N s" },
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::BlastLoad {
            experiment,
            cell,
            centre,
        },
    }
}

/// A row of a blast plate's peak permanent deflection (mm), two-way, synthetic HHA, with the
/// set-up changed by `adjust`.
const fn blast_peak(
    name: &'static str,
    figure: &'static str,
    quoted_in: &'static str,
    stated: f64,
    (experiment, adjust): (&'static str, fn(&mut Setup)),
) -> Row {
    Row {
        name,
        figure,
        quoted_in,
        stated,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment,
            key: "peak_deflection",
            adjust: Some(adjust),
        },
    }
}

/// A row of the Eulerian strength sweep (docs/euler.md): the rate over Walker–Anderson's
/// against a perfectly plastic target at `target_yield` (Pa).
const fn euler_strength(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (velocity, target_yield): (f64, f64),
    speed: Speed,
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/euler.md, Validation",
        stated,
        tolerance: 0.005,
        unit: "-",
        scale: 1.0,
        speed,
        measure: Measure::EulerStrength {
            velocity,
            target_yield,
        },
    }
}

/// A row of the elastic-rod comparison (docs/euler.md, "A rod that does not erode").
const fn rigid_rod(
    name: &'static str,
    figure: &'static str,
    stated: f64,
    (euler, element, sliding): (bool, f64, bool),
) -> Row {
    Row {
        name,
        figure,
        quoted_in: "docs/euler.md, A rod that does not erode",
        stated,
        tolerance: 0.005,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::RigidRod {
            euler,
            element,
            sliding,
        },
    }
}

/// Every row, fast ones first.
pub const ROWS: &[Row] = &[
    Row {
        name: "foi-t34-limit",
        figure: "Lambert-Jonas V_bl of FOI's Autodyn table 3.4 (implicit rate)",
        quoted_in: "docs/solver.md, Ballistic limit (seed 001 sec. 3.5: 754 m/s)",
        stated: 754.0,
        tolerance: 2.0,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::LambertJonas {
            experiment: "experiments/ballistic-foi-t34.toml",
        },
    },
    Row {
        name: "foi-t35-limit",
        figure: "Lambert-Jonas V_bl of FOI's Autodyn table 3.5 (lagged rate)",
        quoted_in: "docs/solver.md, Ballistic limit (seed 001 sec. 3.5: 688 m/s)",
        stated: 688.0,
        tolerance: 2.0,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::LambertJonas {
            experiment: "experiments/ballistic-foi-t35.toml",
        },
    },
    foi_tables_rms(
        "foi-t34-t38-rms",
        "RMS exit difference between FOI's Autodyn tables 3.4 (4.1.13c) and 3.8 (4.2.02), one model at 0.2 / 0.4 mm, over their common impact velocities",
        48.4,
        ("experiments/ballistic-foi-t34.toml", "experiments/ballistic-foi-t38.toml"),
    ),
    foi_tables_rms(
        "foi-t37-t39-rms",
        "RMS exit difference between FOI's Autodyn tables 3.7 (4.1.13c) and 3.9 (4.2.02), one model at 0.1 / 0.1 mm, over their common impact velocities",
        76.7,
        ("experiments/ballistic-foi-t37.toml", "experiments/ballistic-foi-t39.toml"),
    ),
    Row {
        name: "taylor-208",
        figure: "final length, 4340 Taylor rod at 208 m/s, published JC",
        quoted_in: "docs/solver.md, Real 4340 Taylor tests",
        stated: 22.554,
        tolerance: 0.001,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/taylor-4340-208.toml",
            key: "final_length",
            adjust: None,
        },
    },
    Row {
        name: "taylor-282",
        figure: "final length, 4340 Taylor rod at 282 m/s, published JC",
        quoted_in: "docs/solver.md, Real 4340 Taylor tests",
        stated: 10.338,
        tolerance: 0.001,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/taylor-4340-282.toml",
            key: "final_length",
            adjust: None,
        },
    },
    Row {
        name: "taylor-343",
        figure: "final length, 4340 Taylor rod at 343 m/s, published JC",
        quoted_in: "docs/solver.md, Real 4340 Taylor tests",
        stated: 6.088,
        tolerance: 0.001,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/taylor-4340-343.toml",
            key: "final_length",
            adjust: None,
        },
    },
    Row {
        name: "euler-1250",
        figure: "nose depth at 55 us, 1250 m/s shot, Eulerian, 0.4 mm",
        quoted_in: "docs/euler.md, Validation",
        stated: 24.75,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250-euler.toml",
            key: "final_nose_depth",
            adjust: None,
        },
    },
    Row {
        name: "euler-1700",
        figure: "nose depth at 60.3 us, 1700 m/s shot, Eulerian, 0.4 mm",
        quoted_in: "docs/euler.md, Validation",
        stated: 45.92,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1700-euler.toml",
            key: "final_nose_depth",
            adjust: None,
        },
    },
    Row {
        name: "lagrange-1250",
        figure: "nose depth at 55 us, 1250 m/s shot, eroding Lagrangian, 0.4 mm",
        quoted_in: "docs/solver.md, Validation runs and throughput",
        stated: 29.21,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250.toml",
            key: "final_nose_depth",
            adjust: None,
        },
    },
    Row {
        name: "lagrange-1700",
        figure: "nose depth at 60.3 us, 1700 m/s shot, eroding Lagrangian, 0.4 mm",
        quoted_in: "docs/solver.md, Validation runs and throughput",
        stated: 51.72,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1700.toml",
            key: "final_nose_depth",
            adjust: None,
        },
    },
    Row {
        name: "drop-weight-mode",
        figure: "failure mode of the RC beam under the drop weight, 20 mm, local (code: 1 \
                 bending, 2 shear, 3 punching; FOI's LS-DYNA: shear)",
        quoted_in: "docs/solver.md, The reinforced-concrete beam, Results",
        stated: 2.0,
        tolerance: 0.1,
        unit: "code",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/rc-beam-drop-weight.toml",
            key: "failure_mode",
            adjust: Some(beam_at_20_mm),
        },
    },
    Row {
        name: "drop-weight-angle",
        figure: "median inclination of the open cracks crossing the web near the load, RC beam \
                 under the drop weight, 20 mm, local (a shear crack above 30 degrees)",
        quoted_in: "docs/solver.md, The reinforced-concrete beam, Results",
        stated: 52.0,
        tolerance: 1.0,
        unit: "degrees",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/rc-beam-drop-weight.toml",
            key: "web_crack_angle",
            adjust: Some(beam_at_20_mm),
        },
    },
    Row {
        name: "drop-weight-striker",
        figure: "striker travel at 20 ms, RC beam under the drop weight, 20 mm, local",
        quoted_in: "docs/solver.md, The reinforced-concrete beam, Results",
        stated: 114.9,
        tolerance: 0.1,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Fast,
        measure: Measure::Summary {
            experiment: "experiments/rc-beam-drop-weight.toml",
            key: "striker_displacement_final",
            adjust: Some(beam_at_20_mm),
        },
    },
    Row {
        name: "euler-1250-fine",
        figure: "nose depth at 55 us, 1250 m/s shot, Eulerian, 0.2 mm",
        quoted_in: "docs/euler.md, Validation",
        stated: 25.70,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250-euler.toml",
            key: "final_nose_depth",
            adjust: Some(element_size_0_2_mm),
        },
    },
    Row {
        name: "euler-1700-fine",
        figure: "nose depth at 60.3 us, 1700 m/s shot, Eulerian, 0.2 mm",
        quoted_in: "docs/euler.md, Validation",
        stated: 46.64,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1700-euler.toml",
            key: "final_nose_depth",
            adjust: Some(element_size_0_2_mm),
        },
    },
    Row {
        name: "lagrange-1250-fine",
        figure: "nose depth at 55 us, 1250 m/s shot, eroding Lagrangian, 0.2 mm",
        quoted_in: "docs/solver.md, Validation runs and throughput; README.md, Status",
        stated: 27.99,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250.toml",
            key: "final_nose_depth",
            adjust: Some(element_size_0_2_mm),
        },
    },
    Row {
        name: "lagrange-1700-fine",
        figure: "nose depth at 60.3 us, 1700 m/s shot, eroding Lagrangian, 0.2 mm",
        quoted_in: "docs/solver.md, Validation runs and throughput; README.md, Status",
        stated: 48.47,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1700.toml",
            key: "final_nose_depth",
            adjust: Some(element_size_0_2_mm),
        },
    },
    Row {
        name: "ballistic-implicit",
        figure: "V_bl, WC core through 10.8 mm HNS, implicit rate update",
        quoted_in: "docs/solver.md, Ballistic limit, Results; README.md",
        stated: 592.6,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/ballistic-hns-wc.toml",
            key: "ballistic_limit",
            adjust: None,
        },
    },
    Row {
        name: "ballistic-lagged",
        figure: "V_bl, WC core through 10.8 mm HNS, lagged rate update",
        quoted_in: "docs/solver.md, Ballistic limit, Results; README.md",
        stated: 539.5,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/ballistic-hns-wc-lagged.toml",
            key: "ballistic_limit",
            adjust: None,
        },
    },
    Row {
        name: "main-job-jc",
        figure: "held-out error of the JC calibration of the main job (4340, real recordings)",
        quoted_in: "docs/benchmarks.md, main job",
        stated: 2.6597,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "jc",
            figure: CalibrationFigure::HeldOutError,
        },
    },
    Row {
        name: "main-job-mjc",
        figure: "held-out error of the MJC calibration of the main job (4340, real recordings)",
        quoted_in: "docs/benchmarks.md, main job",
        stated: 3.0247,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "mjc",
            figure: CalibrationFigure::HeldOutError,
        },
    },
    Row {
        name: "main-job-jc-starting",
        figure: "held-out error of the published JC constants (the main job's recommendation)",
        quoted_in: "docs/calibration.md, The recommendation",
        stated: 2.1380,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "jc",
            figure: CalibrationFigure::StartingHeldOutError,
        },
    },
    Row {
        name: "main-job-mjc-starting",
        figure: "held-out error of the published MJC constants in the main job",
        quoted_in: "docs/calibration.md, The recommendation",
        stated: 2.3445,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "mjc",
            figure: CalibrationFigure::StartingHeldOutError,
        },
    },
    Row {
        name: "main-job-jc-band-fitted",
        figure: "95 % prediction band of the calibrated JC constants, fitted experiments, main job",
        quoted_in: "docs/calibration.md, Posterior",
        stated: 2.97,
        tolerance: 0.01,
        unit: "%",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "jc",
            figure: CalibrationFigure::FittedBand,
        },
    },
    Row {
        name: "main-job-jc-band-held-out",
        figure: "95 % prediction band of the calibrated JC constants, held-out experiments, main job",
        quoted_in: "docs/calibration.md, Posterior",
        stated: 3.18,
        tolerance: 0.01,
        unit: "%",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Calibration {
            campaign: "campaigns/4340-real.toml",
            model: "jc",
            figure: CalibrationFigure::HeldOutBand,
        },
    },
    Row {
        name: "perforation-455",
        figure: "exit velocity, 152 mm ogive through 0.75 m RHT concrete at 455.5 m/s",
        quoted_in: "docs/solver.md, Concrete perforation, Against the tests; README.md",
        stated: 209.1,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Predicted {
            experiment: "experiments/perforation-concrete-152mm.toml",
            quantity: "residual_velocity",
            position: 455.5,
        },
    },
    Row {
        name: "perforation-459",
        figure: "exit velocity, 152 mm ogive through 0.75 m RHT concrete at 458.8 m/s",
        quoted_in: "docs/solver.md, Concrete perforation, Against the tests; README.md",
        stated: 211.3,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Predicted {
            experiment: "experiments/perforation-concrete-152mm.toml",
            quantity: "residual_velocity",
            position: 458.8,
        },
    },
    Row {
        name: "perforation-460",
        figure: "exit velocity, 152 mm ogive through 0.75 m RHT concrete at 460.0 m/s",
        quoted_in: "docs/solver.md, Concrete perforation, Against the tests; README.md",
        stated: 224.1,
        tolerance: 0.1,
        unit: "m/s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Predicted {
            experiment: "experiments/perforation-concrete-152mm.toml",
            quantity: "residual_velocity",
            position: 460.0,
        },
    },
    blast_peak(
        "blast-37g",
        "peak deflection, 37.5 g PE4 at 13 mm, two-way, synthetic HHA, square elements",
        "docs/solver.md, Blast load, Results on seed 000's two shots",
        26.96,
        ("experiments/blast-hha-37g-13mm.toml", square_plate_elements),
    ),
    blast_peak(
        "blast-57g",
        "peak deflection, 57.5 g PE4 at 25 mm, two-way, synthetic HHA, square elements",
        "docs/solver.md, Blast load, Results on seed 000's two shots",
        30.14,
        ("experiments/blast-hha-57g-25mm.toml", square_plate_elements),
    ),
    blast_peak(
        "blast-37g-after-yielding",
        "peak deflection, 37.5 g PE4 at 13 mm, two-way, synthetic HHA, damping once the plate has stopped yielding",
        "docs/solver.md, Blast load, When the damping starts",
        25.199,
        ("experiments/blast-hha-37g-13mm.toml", damping_after_yielding),
    ),
    blast_peak(
        "blast-57g-after-yielding",
        "peak deflection, 57.5 g PE4 at 25 mm, two-way, synthetic HHA, damping once the plate has stopped yielding",
        "docs/solver.md, Blast load, When the damping starts",
        28.948,
        ("experiments/blast-hha-57g-25mm.toml", damping_after_yielding),
    ),
    identify(
        "identify-control",
        "false alarms of the diagnosis on the control case, 1 % noise, 10 seeds",
        0.0,
        ("control", 0, Count::FalseAlarms),
    ),
    identify(
        "identify-heating",
        "diagnoses naming adiabatic heating (case `heating`), 1 % noise, 10 seeds",
        10.0,
        ("heating", 0, Count::Identified),
    ),
    identify(
        "identify-upturn",
        "diagnoses naming the high-rate upturn (case `upturn`), 1 % noise, 10 seeds",
        10.0,
        ("upturn", 0, Count::Identified),
    ),
    identify(
        "identify-saturation",
        "diagnoses naming Voce saturation (case `saturation`), 1 % noise, 10 seeds",
        10.0,
        ("saturation", 0, Count::Identified),
    ),
    identify(
        "identify-coupling",
        "diagnoses naming rate-temperature coupling (case `coupling`), 1 % noise, 10 seeds",
        10.0,
        ("coupling", 0, Count::Identified),
    ),
    identify(
        "identify-friction",
        "diagnoses naming anvil friction (case `friction`), 1 % noise, 10 seeds",
        10.0,
        ("friction", 0, Count::Identified),
    ),
    identify(
        "identify-za-bcc",
        "diagnoses naming the Zerilli-Armstrong BCC family (case `za-bcc`), 1 % noise, 10 seeds",
        10.0,
        ("za-bcc", 0, Count::Identified),
    ),
    identify(
        "identify-thermal-drop",
        "diagnoses naming a thermal drop (case `thermal-drop`), 1 % noise, 10 seeds",
        10.0,
        ("thermal-drop", 0, Count::Identified),
    ),
    identify(
        "identify-heating-window",
        "diagnoses naming a heating transition (case `heating-window`, any window), 1 % noise, 10 seeds",
        10.0,
        ("heating-window", 0, Count::IdentifiedOrSamePhysics),
    ),
    identify(
        "identify-heating-window-exact",
        "diagnoses naming the concealed heating window 1-100 /s exactly, 1 % noise, 10 seeds",
        4.0,
        ("heating-window", 0, Count::Identified),
    ),
    identify(
        "identify-upturn-3pct",
        "diagnoses naming the high-rate upturn, 3 % noise, 10 seeds",
        4.0,
        ("upturn", 1, Count::Identified),
    ),
    identify(
        "identify-saturation-3pct",
        "diagnoses naming Voce saturation, 3 % noise, 10 seeds",
        1.0,
        ("saturation", 1, Count::Identified),
    ),
    Row {
        name: "finish-1.5",
        figure: "median simulations to 1.5 x the noise floor of the synthetic flow campaign, 10 Bayesian + least squares, 10 seeds",
        quoted_in: "docs/calibration.md, The least-squares finish; README.md, Status",
        stated: 28.0,
        tolerance: 0.5,
        unit: "simulations",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::Finish { factor: 1.5 },
    },
    Row {
        name: "finish-1.1",
        figure: "median simulations to 1.1 x the noise floor of the synthetic flow campaign, 10 Bayesian + least squares, 10 seeds",
        quoted_in: "docs/calibration.md, The least-squares finish; README.md, Status",
        stated: 35.0,
        tolerance: 0.5,
        unit: "simulations",
        scale: 1.0,
        speed: Speed::Fast,
        measure: Measure::Finish { factor: 1.1 },
    },
    Row {
        name: "seed000-jc-fit",
        figure: "fit error of JC, seed 000's six-experiment campaign (eroding Lagrangian penetration), about an hour",
        quoted_in: "docs/calibration.md, Seed 000's campaign, Results",
        stated: 0.5321,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Full,
        measure: Measure::Calibration {
            campaign: "campaigns/seed000-hha.toml",
            model: "jc",
            figure: CalibrationFigure::FitError,
        },
    },
    Row {
        name: "seed000-jc-held-out",
        figure: "held-out error of JC (two SHPB tests), seed 000's campaign",
        quoted_in: "docs/calibration.md, Seed 000's campaign, Results",
        stated: 0.6421,
        tolerance: 0.0001,
        unit: "-",
        scale: 1.0,
        speed: Speed::Full,
        measure: Measure::Calibration {
            campaign: "campaigns/seed000-hha.toml",
            model: "jc",
            figure: CalibrationFigure::HeldOutError,
        },
    },
    foi_perforation(
        "perforation-b99036",
        "exit velocity at 459 m/s with the constants of FOI's run B99036 (10 mm slab; FOI's Autodyn: 189 m/s)",
        208.2,
        "B99036",
    ),
    foi_perforation(
        "perforation-b99008",
        "exit velocity at 459 m/s with the constants of FOI's run B99008 (10 mm slab; FOI's Autodyn: 247 m/s)",
        264.9,
        "B99008",
    ),
    foi_perforation(
        "perforation-b99035",
        "exit velocity at 459 m/s with the constants of FOI's run B99035 (10 mm slab; FOI's Autodyn: 194 m/s)",
        172.2,
        "B99035",
    ),
    foi_perforation(
        "perforation-b99038",
        "exit velocity at 459 m/s with the constants of FOI's run B99038 (10 mm slab; FOI's Autodyn: 212 m/s)",
        219.1,
        "B99038",
    ),
    foi_perforation(
        "perforation-b99055",
        "exit velocity at 459 m/s with the constants of FOI's run B99055 (5 mm slab; FOI's Autodyn: 269 m/s)",
        277.1,
        "B99055",
    ),
    foi_perforation(
        "perforation-b99056",
        "exit velocity at 459 m/s with the constants of FOI's run B99056 (5 mm slab; FOI's Autodyn: 237 m/s)",
        224.2,
        "B99056",
    ),
    foi_perforation(
        "perforation-b99057",
        "exit velocity at 459 m/s with the constants of FOI's run B99057 (5 mm slab; FOI's Autodyn: 207 m/s)",
        189.4,
        "B99057",
    ),
    Row {
        name: "euler-smooth-velocity",
        figure: "largest deviation from a straight line of the Eulerian 1250 m/s shot's final depth at 1244 / 1250 / 1256 m/s (monotone required)",
        quoted_in: "docs/euler.md, Validation",
        stated: 0.00,
        tolerance: 0.01,
        unit: "%",
        scale: 100.0,
        speed: Speed::Fast,
        measure: Measure::EulerSmooth { strength: false },
    },
    Row {
        name: "euler-smooth-strength",
        figure: "largest deviation from a straight line of the Eulerian 1250 m/s shot's final depth with the target's A x 0.99 / 1 / 1.01 (monotone required)",
        quoted_in: "docs/euler.md, Validation",
        stated: 0.02,
        tolerance: 0.01,
        unit: "%",
        scale: 100.0,
        speed: Speed::Fast,
        measure: Measure::EulerSmooth { strength: true },
    },
    euler_strength(
        "euler-strength-0.5",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 0.5 GPa, 0.4 mm",
        0.98,
        (1250.0, 0.5e9),
        Speed::Fast,
    ),
    euler_strength(
        "euler-strength-1.0",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 1.0 GPa, 0.4 mm",
        1.01,
        (1250.0, 1.0e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-1.5",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 1.5 GPa, 0.4 mm",
        1.06,
        (1250.0, 1.5e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-2.0",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 2.0 GPa, 0.4 mm",
        1.08,
        (1250.0, 2.0e9),
        Speed::Fast,
    ),
    euler_strength(
        "euler-strength-3.0",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 3.0 GPa, 0.4 mm",
        0.98,
        (1250.0, 3.0e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-4.0",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, perfectly plastic rod and target, target A 4.0 GPa, 0.4 mm",
        0.69,
        (1250.0, 4.0e9),
        Speed::Fast,
    ),
    rigid_rod(
        "euler-rigid-rod",
        "Elastic hemispherical-nosed rod into a perfectly plastic target, 800 m/s: Eulerian nose depth at 40 us over the rigid-projectile model's, 0.4 mm",
        0.785,
        (true, 0.4e-3, false),
    ),
    rigid_rod(
        "euler-rigid-rod-sliding",
        "Elastic hemispherical-nosed rod into a perfectly plastic target, 800 m/s: Eulerian nose depth at 40 us over the rigid-projectile model's, 0.4 mm, sliding interface",
        0.947,
        (true, 0.4e-3, true),
    ),
    rigid_rod(
        "euler-rigid-rod-sliding-fine",
        "Elastic hemispherical-nosed rod into a perfectly plastic target, 800 m/s: Eulerian nose depth at 40 us over the rigid-projectile model's, 0.2 mm, sliding interface",
        0.989,
        (true, 0.2e-3, true),
    ),
    rigid_rod(
        "lagrange-rigid-rod",
        "Elastic hemispherical-nosed rod into a perfectly plastic target, 800 m/s: eroding Lagrangian nose depth at 40 us over the rigid-projectile model's, 0.4 mm",
        1.059,
        (false, 0.4e-3, false),
    ),
    euler_strength(
        "euler-strength-0.5-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 0.5 GPa, 0.4 mm",
        0.987,
        (1700.0, 0.5e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-1.0-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 1.0 GPa, 0.4 mm",
        0.990,
        (1700.0, 1.0e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-1.5-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 1.5 GPa, 0.4 mm",
        1.001,
        (1700.0, 1.5e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-2.0-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 2.0 GPa, 0.4 mm",
        1.018,
        (1700.0, 2.0e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-3.0-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 3.0 GPa, 0.4 mm",
        1.052,
        (1700.0, 3.0e9),
        Speed::Slow,
    ),
    euler_strength(
        "euler-strength-4.0-1700",
        "Eulerian penetration rate 10-30 us over Walker-Anderson's, 1700 m/s, perfectly plastic rod and target, target A 4.0 GPa, 0.4 mm",
        1.046,
        (1700.0, 4.0e9),
        Speed::Fast,
    ),
    foi_core_mesh(
        "foi-core-mesh-0.2-0.4",
        "exit velocity at 800 m/s, the core identified from table 3.4, plate 0.2 mm, core 0.4 mm (FOI table 3.4: 243)",
        244.0,
        (0.2e-3, 0.4e-3, false),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.1-0.4",
        "exit velocity at 800 m/s, the core identified from table 3.4, plate 0.1 mm, core 0.4 mm",
        337.1,
        (0.1e-3, 0.4e-3, false),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.2-0.1",
        "exit velocity at 800 m/s, the core identified from table 3.4, plate 0.2 mm, core 0.1 mm (0: stopped, its nose blunted)",
        0.0,
        (0.2e-3, 0.1e-3, false),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.1-0.1",
        "exit velocity at 800 m/s, the core identified from table 3.4, plate and core 0.1 mm (FOI table 3.7: 289)",
        209.2,
        (0.1e-3, 0.1e-3, false),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.2-0.4-elastic",
        "exit velocity at 800 m/s, the core identified from table 3.4 kept elastic, plate 0.2 mm, core 0.4 mm",
        327.4,
        (0.2e-3, 0.4e-3, true),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.2-0.1-elastic",
        "exit velocity at 800 m/s, the core identified from table 3.4 kept elastic, plate 0.2 mm, core 0.1 mm",
        328.6,
        (0.2e-3, 0.1e-3, true),
    ),
    foi_core_mesh(
        "foi-core-mesh-0.1-0.1-elastic",
        "exit velocity at 800 m/s, the core identified from table 3.4 kept elastic, plate and core 0.1 mm",
        342.0,
        (0.1e-3, 0.1e-3, true),
    ),
    foi_core_mesh_with(
        "foi-fine-core-mesh-0.2-0.1",
        "exit velocity at 800 m/s, the core identified from table 3.4 on a 0.1 mm core mesh, plate 0.2 mm, core 0.1 mm (FOI table 3.4: 243)",
        234.9,
        foi_tables::FINE_MESH_CORE,
        (0.2e-3, 0.1e-3, false),
    ),
    foi_core_mesh_with(
        "foi-fine-core-mesh-0.1-0.1",
        "exit velocity at 800 m/s, the core identified from table 3.4 on a 0.1 mm core mesh, plate and core 0.1 mm (FOI table 3.7: 289)",
        297.7,
        foi_tables::FINE_MESH_CORE,
        (0.1e-3, 0.1e-3, false),
    ),
    foi_fine_core(
        "foi-fine-core-t34-rms",
        "RMS exit difference from FOI's Autodyn table 3.4 (fitted: implicit rate, 0.2 mm plate), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        8.6,
        ("experiments/ballistic-foi-t34.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t34-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.4 (fitted: implicit rate, 0.2 mm plate), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        754.3,
        ("experiments/ballistic-foi-t34.toml", true),
    ),
    foi_fine_core(
        "foi-fine-core-t35-rms",
        "RMS exit difference from FOI's Autodyn table 3.5 (original JC, lagged rate), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        60.8,
        ("experiments/ballistic-foi-t35.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t35-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.5 (original JC, lagged rate), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        673.1,
        ("experiments/ballistic-foi-t35.toml", true),
    ),
    foi_fine_core(
        "foi-fine-core-t36-rms",
        "RMS exit difference from FOI's Autodyn table 3.6 (lagged rate, rate term off), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        59.6,
        ("experiments/ballistic-foi-t36.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t36-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.6 (lagged rate, rate term off), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        662.5,
        ("experiments/ballistic-foi-t36.toml", true),
    ),
    foi_fine_core(
        "foi-fine-core-t37-rms",
        "RMS exit difference from FOI's Autodyn table 3.7 (implicit rate, 0.1 / 0.1 mm), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        33.4,
        ("experiments/ballistic-foi-t37.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t37-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.7 (implicit rate, 0.1 / 0.1 mm), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        732.3,
        ("experiments/ballistic-foi-t37.toml", true),
    ),
    foi_fine_core(
        "foi-fine-core-t38-rms",
        "RMS exit difference from FOI's Autodyn table 3.8 (Autodyn 4.2.02, 0.2 mm plate; stoss: the 3.4 model), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        53.0,
        ("experiments/ballistic-foi-t38.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t38-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.8 (Autodyn 4.2.02, 0.2 mm plate; stoss: the 3.4 model), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        753.6,
        ("experiments/ballistic-foi-t38.toml", true),
    ),
    foi_fine_core(
        "foi-fine-core-t39-rms",
        "RMS exit difference from FOI's Autodyn table 3.9 (Autodyn 4.2.02, 0.1 / 0.1 mm), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        100.4,
        ("experiments/ballistic-foi-t39.toml", false),
    ),
    foi_fine_core(
        "foi-fine-core-t39-limit",
        "Lambert-Jonas V_bl of stoss' shots on FOI's table 3.9 (Autodyn 4.2.02, 0.1 / 0.1 mm), the core identified from table 3.4 on a 0.1 mm core mesh, core meshed at 0.1 mm",
        733.3,
        ("experiments/ballistic-foi-t39.toml", true),
    ),
    euler_crater_row(
        "euler-crater-behind",
        "Eulerian 1250 m/s shot's crater radius 1-3 rod radii above the nose, 10-30 us, HzB-W target, 0.4 mm (Walker-Anderson 1.59 a)",
        1.84,
        (1250.0, 0.4e-3, false),
        Speed::Fast,
    ),
    euler_crater_row(
        "euler-crater-head",
        "Eulerian 1250 m/s shot's crater radius within one rod radius of the nose, 10-30 us, HzB-W target, 0.4 mm",
        1.26,
        (1250.0, 0.4e-3, true),
        Speed::Fast,
    ),
    euler_crater_row(
        "euler-crater-behind-fine",
        "Eulerian 1250 m/s shot's crater radius 1-3 rod radii above the nose, 10-30 us, HzB-W target, 0.2 mm",
        1.82,
        (1250.0, 0.2e-3, false),
        Speed::Slow,
    ),
    euler_crater_row(
        "euler-crater-head-fine",
        "Eulerian 1250 m/s shot's crater radius within one rod radius of the nose, 10-30 us, HzB-W target, 0.2 mm",
        1.29,
        (1250.0, 0.2e-3, true),
        Speed::Slow,
    ),
    euler_crater_row(
        "euler-crater-behind-1700",
        "Eulerian 1700 m/s shot's crater radius 1-3 rod radii above the nose, 10-30 us, HzB-W target, 0.4 mm (Walker-Anderson 1.92 a)",
        1.92,
        (1700.0, 0.4e-3, false),
        Speed::Fast,
    ),
    euler_crater_row(
        "euler-crater-behind-1700-fine",
        "Eulerian 1700 m/s shot's crater radius 1-3 rod radii above the nose, 10-30 us, HzB-W target, 0.2 mm",
        1.93,
        (1700.0, 0.2e-3, false),
        Speed::Slow,
    ),
    Row {
        name: "euler-1250-thick",
        figure: "nose depth at 55 us, 1250 m/s shot, Eulerian, 0.4 mm, the plate twice as thick \
                 (58 mm: no rear-face phase)",
        quoted_in: "docs/euler.md, Validation",
        stated: 22.73,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250-euler.toml",
            key: "final_nose_depth",
            adjust: Some(target_twice_as_thick),
        },
    },
    Row {
        name: "euler-1700-thick",
        figure: "nose depth at 60.3 us, 1700 m/s shot, Eulerian, 0.4 mm, the plate twice as \
                 thick (99 mm: no rear-face phase)",
        quoted_in: "docs/euler.md, Validation",
        stated: 41.24,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1700-euler.toml",
            key: "final_nose_depth",
            adjust: Some(target_twice_as_thick),
        },
    },
    Row {
        name: "euler-1250-finest",
        figure: "nose depth at 55 us, 1250 m/s shot, Eulerian, 0.1 mm (half an hour)",
        quoted_in: "docs/euler.md, Validation",
        stated: 26.01,
        tolerance: 0.01,
        unit: "mm",
        scale: 1e3,
        speed: Speed::Slow,
        measure: Measure::Summary {
            experiment: "experiments/penetration-hzb-1250-euler.toml",
            key: "final_nose_depth",
            adjust: Some(element_size_0_1_mm),
        },
    },
    lagrange_strength(
        "lagrange-strength-0.5",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 0.5 GPa, 0.4 mm",
        0.98,
        0.5e9,
    ),
    lagrange_strength(
        "lagrange-strength-1.0",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 1.0 GPa, 0.4 mm",
        0.99,
        1.0e9,
    ),
    lagrange_strength(
        "lagrange-strength-1.5",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 1.5 GPa, 0.4 mm",
        1.23,
        1.5e9,
    ),
    lagrange_strength(
        "lagrange-strength-2.0",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 2.0 GPa, 0.4 mm",
        1.19,
        2.0e9,
    ),
    lagrange_strength(
        "lagrange-strength-3.0",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 3.0 GPa, 0.4 mm",
        1.84,
        3.0e9,
    ),
    lagrange_strength(
        "lagrange-strength-4.0",
        "eroding Lagrangian penetration rate 10-30 us over Walker-Anderson's, 1250 m/s, HzB-W target with A 4.0 GPa, 0.4 mm",
        1.65,
        4.0e9,
    ),
    identify(
        "identify-control-3pct",
        "false alarms of the diagnosis on the control case, 3 % noise, 10 seeds",
        0.0,
        ("control", 1, Count::FalseAlarms),
    ),
    identify(
        "identify-control-5pct",
        "false alarms of the diagnosis on the control case, 5 % noise, 10 seeds",
        0.0,
        ("control", 2, Count::FalseAlarms),
    ),
    identify(
        "identify-heating-3pct",
        "diagnoses naming adiabatic heating (case `heating`), 3 % noise, 10 seeds",
        9.0,
        ("heating", 1, Count::Identified),
    ),
    identify(
        "identify-heating-5pct",
        "diagnoses naming adiabatic heating (case `heating`), 5 % noise, 10 seeds",
        5.0,
        ("heating", 2, Count::Identified),
    ),
    identify(
        "identify-upturn-5pct",
        "diagnoses naming the high-rate upturn, 5 % noise, 10 seeds",
        2.0,
        ("upturn", 2, Count::Identified),
    ),
    identify(
        "identify-saturation-5pct",
        "diagnoses naming Voce saturation, 5 % noise, 10 seeds",
        0.0,
        ("saturation", 2, Count::Identified),
    ),
    identify(
        "identify-coupling-3pct",
        "diagnoses naming rate-temperature coupling (case `coupling`), 3 % noise, 10 seeds",
        3.0,
        ("coupling", 1, Count::Identified),
    ),
    identify(
        "identify-coupling-5pct",
        "diagnoses naming rate-temperature coupling (case `coupling`), 5 % noise, 10 seeds",
        0.0,
        ("coupling", 2, Count::Identified),
    ),
    identify(
        "identify-friction-3pct",
        "diagnoses naming anvil friction (case `friction`), 3 % noise, 10 seeds",
        10.0,
        ("friction", 1, Count::Identified),
    ),
    identify(
        "identify-friction-5pct",
        "diagnoses naming anvil friction (case `friction`), 5 % noise, 10 seeds",
        9.0,
        ("friction", 2, Count::Identified),
    ),
    identify(
        "identify-za-bcc-3pct",
        "diagnoses naming the Zerilli-Armstrong BCC family (case `za-bcc`), 3 % noise, 10 seeds",
        9.0,
        ("za-bcc", 1, Count::Identified),
    ),
    identify(
        "identify-za-bcc-5pct",
        "diagnoses naming the Zerilli-Armstrong BCC family (case `za-bcc`), 5 % noise, 10 seeds",
        1.0,
        ("za-bcc", 2, Count::Identified),
    ),
    identify(
        "identify-heating-window-3pct",
        "diagnoses naming a heating transition (case `heating-window`, any window), 3 % noise, 10 seeds",
        2.0,
        ("heating-window", 1, Count::IdentifiedOrSamePhysics),
    ),
    identify(
        "identify-heating-window-5pct",
        "diagnoses naming a heating transition (case `heating-window`, any window), 5 % noise, 10 seeds",
        0.0,
        ("heating-window", 2, Count::IdentifiedOrSamePhysics),
    ),
    identify(
        "identify-thermal-drop-3pct",
        "diagnoses naming a thermal drop (case `thermal-drop`), 3 % noise, 10 seeds",
        9.0,
        ("thermal-drop", 1, Count::Identified),
    ),
    identify(
        "identify-thermal-drop-5pct",
        "diagnoses naming a thermal drop (case `thermal-drop`), 5 % noise, 10 seeds",
        6.0,
        ("thermal-drop", 2, Count::Identified),
    ),
    Row {
        name: "optimiser-bayesian-1.5",
        figure: "seeds in which the Bayesian optimiser alone brings the synthetic flow campaign within 1.5 x its noise floor in 100 simulations",
        quoted_in: "docs/calibration.md, The least-squares finish",
        stated: 4.0,
        tolerance: 0.5,
        unit: "of 10",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Baseline {
            count: true,
            baseline: finish::Baseline::Bayesian,
            factor: 1.5,
            budget: 100,
        },
    },
    Row {
        name: "optimiser-cmaes-1.1",
        figure: "median simulations to 1.1 x the noise floor of the synthetic flow campaign, CMA-ES alone, budget 2000, 10 seeds",
        quoted_in: "docs/calibration.md, The least-squares finish",
        stated: 570.0,
        tolerance: 0.5,
        unit: "simulations",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::Baseline {
            count: false,
            baseline: finish::Baseline::CmaEs,
            factor: 1.1,
            budget: 2000,
        },
    },
    blast_load(
        "blast-load-37g-1mm",
        "Euler impulse on the exposed plate, 37.5 g PE4 at 13 mm, 1.0 mm cells",
        62.74,
        ("experiments/blast-hha-37g-13mm.toml", 1.0e-3, false),
    ),
    blast_load(
        "blast-load-37g-1mm-centre",
        "Euler impulse per area at the plate's centre, 37.5 g PE4 at 13 mm, 1.0 mm cells",
        25587.0,
        ("experiments/blast-hha-37g-13mm.toml", 1.0e-3, true),
    ),
    blast_load(
        "blast-load-37g-0.5mm",
        "Euler impulse on the exposed plate, 37.5 g PE4 at 13 mm, 0.5 mm cells",
        63.56,
        ("experiments/blast-hha-37g-13mm.toml", 0.5e-3, false),
    ),
    blast_load(
        "blast-load-37g-0.5mm-centre",
        "Euler impulse per area at the plate's centre, 37.5 g PE4 at 13 mm, 0.5 mm cells",
        26201.0,
        ("experiments/blast-hha-37g-13mm.toml", 0.5e-3, true),
    ),
    blast_load(
        "blast-load-57g-1mm",
        "Euler impulse on the exposed plate, 57.5 g PE4 at 25 mm, 1.0 mm cells",
        81.71,
        ("experiments/blast-hha-57g-25mm.toml", 1.0e-3, false),
    ),
    blast_load(
        "blast-load-57g-1mm-centre",
        "Euler impulse per area at the plate's centre, 57.5 g PE4 at 25 mm, 1.0 mm cells",
        28023.0,
        ("experiments/blast-hha-57g-25mm.toml", 1.0e-3, true),
    ),
    blast_load(
        "blast-load-57g-0.5mm",
        "Euler impulse on the exposed plate, 57.5 g PE4 at 25 mm, 0.5 mm cells",
        82.26,
        ("experiments/blast-hha-57g-25mm.toml", 0.5e-3, false),
    ),
    blast_load(
        "blast-load-57g-0.5mm-centre",
        "Euler impulse per area at the plate's centre, 57.5 g PE4 at 25 mm, 0.5 mm cells",
        28837.0,
        ("experiments/blast-hha-57g-25mm.toml", 0.5e-3, true),
    ),
    Row {
        name: "blast-tnt-1m",
        figure: "Euler positive-phase reflected impulse at the axis, 1 kg TNT sphere 1 m above a wall, 10 mm cells (Kingery-Bulmash in the docs beside it)",
        quoted_in: "docs/solver.md, Blast load, Verification",
        stated: 536.0,
        tolerance: 0.5,
        unit: "Pa s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::TntImpulse { height: 1.0 },
    },
    Row {
        name: "blast-tnt-2m",
        figure: "Euler positive-phase reflected impulse at the axis, 1 kg TNT sphere 2 m above a wall, 10 mm cells (Kingery-Bulmash in the docs beside it)",
        quoted_in: "docs/solver.md, Blast load, Verification",
        stated: 224.0,
        tolerance: 0.5,
        unit: "Pa s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::TntImpulse { height: 2.0 },
    },
    Row {
        name: "blast-tnt-3m",
        figure: "Euler positive-phase reflected impulse at the axis, 1 kg TNT sphere 3 m above a wall, 10 mm cells (Kingery-Bulmash in the docs beside it)",
        quoted_in: "docs/solver.md, Blast load, Verification",
        stated: 133.0,
        tolerance: 0.5,
        unit: "Pa s",
        scale: 1.0,
        speed: Speed::Slow,
        measure: Measure::TntImpulse { height: 3.0 },
    },
];

/// A measured row.
#[derive(Clone, Debug)]
pub struct Validation {
    /// The row.
    pub row: Row,
    /// The measured value in the row's unit, or why it could not be measured.
    pub measured: Result<f64, String>,
    /// Wall time (s).
    pub seconds: f64,
}

impl Validation {
    /// Whether the measured value is within the tolerance of the stated one.
    pub fn passed(&self) -> bool {
        matches!(&self.measured, Ok(value) if (value - self.row.stated).abs() <= self.row.tolerance)
    }
}

/// Measure `row` with the experiments under `fixtures`, on `threads` threads (all if none).
pub fn validate(row: &Row, fixtures: &Path, threads: Option<usize>) -> Validation {
    let started = Instant::now();
    let measured = measure(&row.measure, fixtures, threads).map(|si| si * row.scale);
    Validation {
        row: *row,
        measured,
        seconds: started.elapsed().as_secs_f64(),
    }
}

fn measure(measure: &Measure, fixtures: &Path, threads: Option<usize>) -> Result<f64, String> {
    match *measure {
        Measure::Summary {
            experiment,
            key,
            adjust,
        } => {
            let (summary, _) = outcome(fixtures, experiment, adjust, threads)?;
            summary
                .iter()
                .find(|s| s.name == *key)
                .map(|s| s.value)
                .filter(|value| value.is_finite())
                .ok_or_else(|| format!("{experiment}: no finite `{key}` in the outcome"))
        }
        Measure::Predicted {
            experiment,
            quantity,
            position,
        } => {
            let loaded = load(fixtures, experiment)?;
            let index = loaded
                .recording
                .iter()
                .position(|p| p.quantity == quantity && p.position == position)
                .ok_or_else(|| format!("{experiment}: no recorded `{quantity}` at {position}"))?;
            let (_, predicted) = outcome(fixtures, experiment, None, threads)?;
            predicted
                .get(index)
                .copied()
                .ok_or_else(|| format!("{experiment}: no prediction for point {}", index + 1))
        }
        Measure::Calibration {
            campaign,
            model,
            figure,
        } => calibration_error(&fixtures.join(campaign), model, figure),
        Measure::Identification { case, level, count } => {
            let tally = identified(fixtures, case, level)?;
            Ok(match count {
                Count::Identified => tally.identified,
                Count::IdentifiedOrSamePhysics => tally.identified + tally.same_physics,
                Count::FalseAlarms => tally.false_alarms,
            } as f64)
        }
        Measure::Finish { factor } => {
            let runs = finish::simulations_to_target(fixtures, factor, finish::SEEDS)?;
            finish::median(&runs)
                .map(|n| n as f64)
                .ok_or_else(|| format!("the median run missed {factor} x the noise floor"))
        }
        Measure::Baseline {
            count,
            baseline,
            factor,
            budget,
        } => {
            let runs =
                finish::baseline_to_target(fixtures, baseline, factor, budget, finish::SEEDS)?;
            if count {
                return Ok(runs.iter().flatten().count() as f64);
            }
            finish::median(&runs)
                .map(|n| n as f64)
                .ok_or_else(|| format!("the median run missed {factor} x the noise floor"))
        }
        Measure::BlastLoad {
            experiment,
            cell,
            centre,
        } => {
            let (impulse, centre_impulse) = computed_blast_load(fixtures, experiment, cell)?;
            Ok(if centre { centre_impulse } else { impulse })
        }
        Measure::TntImpulse { height } => blast::tnt_reflected_impulse(height).map(|(e, _)| e),
        Measure::FoiPerforation { run } => {
            let found = perforation::run(run).ok_or_else(|| format!("no FOI run `{run}`"))?;
            perforation::fire(fixtures, found, threads).map(|(_, shot)| shot.residual_velocity)
        }
        Measure::EulerSmooth { strength } => {
            let line = if strength {
                euler::by_strength(fixtures, threads)?
            } else {
                euler::by_velocity(fixtures, threads)?
            };
            if line.monotone {
                Ok(line.largest_deviation)
            } else {
                Err(format!(
                    "the final depths are not monotone: {:?}",
                    line.points
                ))
            }
        }
        Measure::EulerStrength {
            velocity,
            target_yield,
        } => semi_infinite::strength_ratio(fixtures, velocity, target_yield, threads),
        Measure::RigidRod {
            euler,
            element,
            sliding,
        } => {
            let solver = if euler {
                crate::experiment::penetration::PenetrationSolver::Euler
            } else {
                crate::experiment::penetration::PenetrationSolver::Lagrange
            };
            semi_infinite::rigid_rod(fixtures, solver, element, sliding, threads)
                .map(|r| r.depth / r.analytic)
        }
        Measure::FoiCore {
            experiment,
            core,
            core_mesh,
            limit,
        } => {
            let prediction = foi_core_prediction(fixtures, experiment, core, core_mesh, threads)?;
            Ok(if limit {
                prediction.limit
            } else {
                prediction.rms
            })
        }
        Measure::FoiCoreMesh {
            experiment,
            core,
            mesh,
        } => foi_tables::mesh_shot(fixtures, experiment, core, mesh, threads),
        Measure::EulerCrater {
            velocity,
            element,
            isothermal,
            at_head,
        } => {
            let crater = measured_crater(fixtures, velocity, element, isothermal, threads)?;
            Ok(if at_head {
                crater.at_head
            } else {
                crater.behind_head
            })
        }
        Measure::LagrangeStrength { target_a } => {
            semi_infinite::lagrange_strength(fixtures, target_a, None, threads)
                .map(|run| run.rate_ratio)
        }
        Measure::RecordingsRms {
            experiments: (first, second),
        } => {
            let first = load(fixtures, first)?;
            let second = load(fixtures, second)?;
            foi_tables::recordings_rms(&first, &second)
        }
        Measure::LambertJonas { experiment } => {
            let loaded = load(fixtures, experiment)?;
            let shots = crate::experiment::ballistic::recorded_shots(&loaded.recording);
            fit_lambert_jonas(&shots, None)
                .map(|fit| fit.ballistic_limit)
                .map_err(|e| format!("{experiment}: {e}"))
        }
    }
}

fn load(fixtures: &Path, experiment: &str) -> Result<Experiment, String> {
    let path: PathBuf = fixtures.join(experiment);
    Experiment::load(&path).map_err(|e| e.to_string())
}

fn simulate(
    experiment: &Experiment,
    threads: Option<usize>,
) -> Result<crate::experiment::Outcome, String> {
    let path = experiment
        .default_material_path()
        .ok_or_else(|| format!("{}: no material", experiment.path.display()))?;
    let (_, part) = material::load_part(&path).map_err(|e| e.to_string())?;
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    experiment
        .simulate(&part, &settings)
        .map_err(|e| format!("{}: {e}", experiment.path.display()))
}

/// A simulated experiment's summary and predictions.
type Simulated = (Vec<crate::experiment::SummaryValue>, Vec<f64>);

/// The experiments simulated in this process, by file and set-up change: rows that read one
/// run share it.
static SIMULATED: std::sync::Mutex<Vec<(String, Simulated)>> = std::sync::Mutex::new(Vec::new());

/// The summary and predictions of `experiment` with `adjust` applied, simulated once per
/// process.
fn outcome(
    fixtures: &Path,
    experiment: &str,
    adjust: Option<fn(&mut Setup)>,
    threads: Option<usize>,
) -> Result<Simulated, String> {
    let key = format!("{experiment} {:?}", adjust.map(|f| f as usize));
    let mut simulated = SIMULATED.lock().map_err(|_| "a simulation row panicked")?;
    if let Some((_, found)) = simulated.iter().find(|(k, _)| *k == key) {
        return Ok(found.clone());
    }
    let mut loaded = load(fixtures, experiment)?;
    if let Some(adjust) = adjust {
        adjust(&mut loaded.file.setup);
    }
    let result = simulate(&loaded, threads)?;
    let entry = (result.summary, result.predicted);
    simulated.push((key, entry.clone()));
    Ok(entry)
}

/// The identification tallies run in this process, by case and noise level.
static IDENTIFIED: std::sync::Mutex<Vec<((&str, usize), identification::Tally)>> =
    std::sync::Mutex::new(Vec::new());

/// The tally of `case` at the `level`-th noise level over [`identification::SEEDS`] seeds,
/// run once per process.
fn identified(
    fixtures: &Path,
    case: &'static str,
    level: usize,
) -> Result<identification::Tally, String> {
    let mut identified = IDENTIFIED
        .lock()
        .map_err(|_| "an identification row panicked")?;
    if let Some((_, tally)) = identified.iter().find(|(key, _)| *key == (case, level)) {
        return Ok(*tally);
    }
    let noise = *identification::NOISE_LEVELS
        .get(level)
        .ok_or_else(|| format!("no noise level {level}"))?;
    let tally = identification::identification(
        &fixtures.join("diagnosis"),
        case,
        noise,
        level,
        identification::SEEDS,
        &mut |_| {},
    )?;
    identified.push(((case, level), tally));
    Ok(tally)
}

/// A FOI table's prediction key: the experiment file, the core and the core's element size
/// (m; the file's when `None`).
pub type FoiKey = (&'static str, foi_tables::Core, Option<f64>);

/// The FOI tables predicted in this process.
static FOI_PREDICTED: std::sync::Mutex<Vec<(FoiKey, foi_tables::Prediction)>> =
    std::sync::Mutex::new(Vec::new());

/// Every FOI table predicted so far in this process, with every shot, in the order they ran
/// (what `stoss validate` lists under its table).
pub fn predicted_foi_tables() -> Vec<(FoiKey, foi_tables::Prediction)> {
    FOI_PREDICTED
        .lock()
        .map_or_else(|_| Vec::new(), |predicted| predicted.clone())
}

/// FOI's table `experiment` predicted with `core` meshed at `core_mesh`, once per process.
fn foi_core_prediction(
    fixtures: &Path,
    experiment: &'static str,
    core: foi_tables::Core,
    core_mesh: Option<f64>,
    threads: Option<usize>,
) -> Result<foi_tables::Prediction, String> {
    let mut predicted = FOI_PREDICTED
        .lock()
        .map_err(|_| "a FOI table row panicked")?;
    let key = (experiment, core, core_mesh);
    if let Some((_, found)) = predicted.iter().find(|(found, _)| *found == key) {
        return Ok(found.clone());
    }
    let prediction = foi_tables::predict(fixtures, experiment, core, core_mesh, threads)?;
    predicted.push((key, prediction.clone()));
    Ok(prediction)
}

/// The blast loads computed in this process, by experiment and cell size (bits): the impulse
/// on the exposed plate and at its centre.
static BLAST_LOADS: std::sync::Mutex<Vec<BlastLoadEntry>> = std::sync::Mutex::new(Vec::new());

/// A computed blast load: `((experiment, cell size bits), (plate impulse, centre impulse))`.
type BlastLoadEntry = ((&'static str, u64), (f64, f64));

/// The Euler load of `experiment` on `cell` cells, once per process.
fn computed_blast_load(
    fixtures: &Path,
    experiment: &'static str,
    cell: f64,
) -> Result<(f64, f64), String> {
    let mut loads = BLAST_LOADS.lock().map_err(|_| "a blast row panicked")?;
    let key = (experiment, cell.to_bits());
    if let Some((_, found)) = loads.iter().find(|(k, _)| *k == key) {
        return Ok(*found);
    }
    let load = blast::charge_load(fixtures, experiment, cell)?;
    let found = (load.impulse, load.centre_impulse);
    loads.push((key, found));
    Ok(found)
}

/// The Eulerian craters measured in this process, by velocity and cell size (bits) and
/// heating.
type CraterKey = (u64, u64, bool);
static CRATERS: std::sync::Mutex<Vec<(CraterKey, semi_infinite::EulerCrater)>> =
    std::sync::Mutex::new(Vec::new());

/// The Eulerian crater at `velocity` on `element` cells, once per process.
fn measured_crater(
    fixtures: &Path,
    velocity: f64,
    element: f64,
    isothermal: bool,
    threads: Option<usize>,
) -> Result<semi_infinite::EulerCrater, String> {
    let mut craters = CRATERS.lock().map_err(|_| "a crater row panicked")?;
    let key = (velocity.to_bits(), element.to_bits(), isothermal);
    if let Some((_, found)) = craters.iter().find(|(k, _)| *k == key) {
        return Ok(*found);
    }
    let crater = semi_infinite::euler_crater(fixtures, element, velocity, isothermal, threads)?;
    craters.push((key, crater));
    Ok(crater)
}

/// A figure of a model's calibration result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CalibrationFigure {
    /// The selected constants' error over the fitted experiments.
    FitError,
    /// Their error over the held-out experiments.
    HeldOutError,
    /// The starting constants' error over the held-out experiments.
    StartingHeldOutError,
    /// The posterior's 95 % prediction band, mean half-width over the fitted experiments
    /// relative to the recorded values (%).
    FittedBand,
    /// The same over the held-out experiments (%).
    HeldOutBand,
}

/// The results of the campaigns calibrated in this process (two rows may read one run).
static CALIBRATED: std::sync::Mutex<Vec<(PathBuf, Vec<ModelResult>)>> =
    std::sync::Mutex::new(Vec::new());

/// `model`'s held-out (or fit) error from a fresh `stoss calibrate` of `campaign` (once per
/// process), run as a child process of this binary into a temporary folder that is removed
/// afterwards.
fn calibration_error(
    campaign_path: &Path,
    model: &str,
    figure: CalibrationFigure,
) -> Result<f64, String> {
    let campaign = campaign_path;
    let mut calibrated = CALIBRATED
        .lock()
        .map_err(|_| "a calibration row panicked")?;
    if !calibrated.iter().any(|(path, _)| path == campaign) {
        let results = calibrate(campaign)?;
        calibrated.push((campaign.to_path_buf(), results));
    }
    let (_, results) = calibrated
        .iter()
        .find(|(path, _)| path == campaign)
        .ok_or("the calibration is not cached")?;
    let found = results
        .iter()
        .find(|r| r.model == model)
        .ok_or_else(|| format!("{}: no model `{model}`", campaign.display()))?;
    let missing = |what: &str| format!("{}: `{model}` has no {what}", campaign.display());
    match figure {
        CalibrationFigure::FitError => Ok(found.fit_error),
        CalibrationFigure::HeldOutError => {
            found.holdout_error.ok_or_else(|| missing("held-out error"))
        }
        CalibrationFigure::StartingHeldOutError => found
            .baseline
            .as_ref()
            .and_then(|b| b.holdout_error)
            .ok_or_else(|| missing("starting constants' held-out error")),
        CalibrationFigure::FittedBand | CalibrationFigure::HeldOutBand => {
            let loaded = crate::fit::Campaign::load(campaign_path).map_err(|e| e.to_string())?;
            let posterior = found
                .posterior
                .as_ref()
                .ok_or_else(|| missing("posterior"))?;
            let (fitted, held) = posterior.band_widths(&loaded);
            let width = if figure == CalibrationFigure::FittedBand {
                fitted
            } else {
                held
            };
            width
                .map(|w| 100.0 * w)
                .ok_or_else(|| missing("prediction band there"))
        }
    }
}

/// Run `stoss calibrate campaign` into a temporary folder and read its `result.json`.
fn calibrate(campaign: &Path) -> Result<Vec<ModelResult>, String> {
    let folder =
        std::env::temp_dir().join(format!("stoss-validate-{}-calibration", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    let executable = std::env::current_exe().map_err(|e| format!("this executable: {e}"))?;
    let output = std::process::Command::new(executable)
        .arg("calibrate")
        .arg(campaign)
        .arg("--output")
        .arg(&folder)
        .output()
        .map_err(|e| format!("stoss calibrate: {e}"))?;
    let result = if output.status.success() {
        let path = folder.join("report").join("result.json");
        std::fs::read_to_string(&path)
            .map_err(|e| format!("{}: {e}", path.display()))
            .and_then(|text| {
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
            })
    } else {
        Err(format!(
            "stoss calibrate {}: {}",
            campaign.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        ))
    };
    let _ = std::fs::remove_dir_all(&folder);
    result
}
