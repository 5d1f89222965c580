//! The smooth objective of the Eulerian penetration (issue 47): the final nose depth of seed
//! 000's 1250 m/s shot (`fixtures/experiments/penetration-hzb-1250.toml` on the Eulerian
//! solver, 0.4 mm) over striking velocities 1244 / 1250 / 1256 m/s and over the target's `A`
//! times 0.99 / 1 / 1.01 must be monotone and close to a straight line (the eroding model's
//! depth scatters by 7-10 % over such steps). Used by the `euler-smooth-*` rows of `stoss
//! validate` and by `cargo bench -p stoss --bench euler` (`smooth`).

use crate::experiment::penetration::PenetrationSolver;
use crate::experiment::PenetrationSpec;
use crate::input::material;
use crate::solver::SolverSettings;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use stoss_kernel::PartMaterial;

/// Final depths against a varied input, and how straight they lie.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// `(input, final nose depth in m)`, in the input's order.
    pub points: Vec<(f64, f64)>,
    /// Whether the depths rise (or fall) throughout.
    pub monotone: bool,
    /// The largest distance of a point from the straight line through the ends, relative to
    /// its depth.
    pub largest_deviation: f64,
}

impl Line {
    fn of(points: Vec<(f64, f64)>) -> Self {
        let monotone = points.windows(2).all(|w| w[1].1 > w[0].1)
            || points.windows(2).all(|w| w[1].1 < w[0].1);
        let (x0, y0) = points[0];
        let (x1, y1) = points[points.len() - 1];
        let largest_deviation = points
            .iter()
            .map(|&(x, y)| ((y - (y0 + (y1 - y0) * (x - x0) / (x1 - x0))) / y).abs())
            .fold(0.0, f64::max);
        Self {
            points,
            monotone,
            largest_deviation,
        }
    }
}

/// The shot on the Eulerian solver and its target's material file.
fn shot(fixtures: &Path) -> Result<(PenetrationSpec, material::MaterialFile), String> {
    let (mut spec, file) = super::semi_infinite::fixture(fixtures)?;
    spec.solver = PenetrationSolver::Euler;
    Ok((spec, file))
}

/// The final nose depth (m) of `spec` into `target`.
fn final_depth(
    spec: &PenetrationSpec,
    target: &PartMaterial,
    threads: Option<usize>,
) -> Result<f64, String> {
    let settings = SolverSettings {
        threads,
        ..SolverSettings::default()
    };
    let run = spec
        .run_euler(target, &settings)
        .map_err(|e| e.to_string())?;
    run.result
        .nose_depth
        .last()
        .map(|p| p.1)
        .ok_or_else(|| "the run recorded no depth".to_string())
}

/// The unvaried shot's final depth, keyed by the fixtures folder: both lines pass through it,
/// so `stoss validate` running both rows in one process simulates it once.
static UNVARIED_DEPTH: Mutex<Option<(PathBuf, f64)>> = Mutex::new(None);

/// [`final_depth`] of the fixture's own shot into its own target, computed once per process
/// and fixtures folder.
fn unvaried_depth(
    fixtures: &Path,
    spec: &PenetrationSpec,
    target: &PartMaterial,
    threads: Option<usize>,
) -> Result<f64, String> {
    let mut cached = UNVARIED_DEPTH
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some((folder, depth)) = cached.as_ref() {
        if folder == fixtures {
            return Ok(*depth);
        }
    }
    let depth = final_depth(spec, target, threads)?;
    *cached = Some((fixtures.to_path_buf(), depth));
    Ok(depth)
}

/// The final depth at striking velocities 1244, 1250 and 1256 m/s.
pub fn by_velocity(fixtures: &Path, threads: Option<usize>) -> Result<Line, String> {
    let (base, file) = shot(fixtures)?;
    let target = PartMaterial::J2(file.material().map_err(|e| e.to_string())?);
    let mut points = Vec::new();
    for velocity in [1244.0, 1250.0, 1256.0] {
        let depth = if velocity == base.velocity {
            unvaried_depth(fixtures, &base, &target, threads)?
        } else {
            let spec = PenetrationSpec {
                velocity,
                ..base.clone()
            };
            final_depth(&spec, &target, threads)?
        };
        points.push((velocity, depth));
    }
    Ok(Line::of(points))
}

/// The final depth with the target's Johnson-Cook `A` times 0.99, 1 and 1.01.
pub fn by_strength(fixtures: &Path, threads: Option<usize>) -> Result<Line, String> {
    let (base, file) = shot(fixtures)?;
    let yield_stress = file
        .strength
        .constant_named("yield_stress")
        .ok_or("the target has no yield stress A")?;
    let mut points = Vec::new();
    for factor in [0.99, 1.0, 1.01] {
        if factor == 1.0 {
            let target = PartMaterial::J2(file.material().map_err(|e| e.to_string())?);
            points.push((factor, unvaried_depth(fixtures, &base, &target, threads)?));
            continue;
        }
        let mut varied = file.clone();
        varied
            .set_constant("strength.yield_stress", yield_stress * factor)
            .ok_or("the target is not a Johnson-Cook file")?;
        let target = PartMaterial::J2(varied.material().map_err(|e| e.to_string())?);
        points.push((factor, final_depth(&base, &target, threads)?));
    }
    Ok(Line::of(points))
}
