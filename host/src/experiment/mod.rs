//! Functional experiments as data. One TOML file per experiment (under
//! `fixtures/experiments/`) gives its geometry, mesh, loading and what is recorded; the
//! recording itself is a CSV beside it (see [`crate::input::recording`]):
//!
//! ```toml
//! name = "4340 Taylor test, 208 m/s"
//! source = "Johnson & Cook (1983); digitised by B. Banerjee (MIT licence)"
//! recording = "taylor-4340-208.csv"        # relative to this file
//! material = "../materials/4340-jc.toml"   # default material; `--material` overrides
//!
//! [setup]
//! kind = "taylor"                          # uniaxial | tension | taylor | shpb | penetration | ballistic-limit | perforation | blast-plate | drop-weight-beam
//! length = 25.4e-3
//! ...
//! ```
//!
//! [`Experiment::simulate`] runs the experiment with a material and returns the prediction of
//! every recorded point, in the recording's order, with the energy balance and the state
//! histories of the points that drive the measurements.

pub mod ballistic;
pub mod blast_plate;
pub mod drop_weight_beam;
pub mod penetration;
pub mod perforation;
pub mod plausibility;
pub mod shpb;
pub mod taylor;
pub mod tension;
pub mod uniaxial;

// The data an outcome carries for figures and VTK: defined in `figure`, drawn by `report`.
pub use crate::figure::{Chart, ExperimentReport, FieldMap, FieldOutput, HexFieldOutput};
use crate::input::recording::{self, RecordedPoint};
use crate::input::{self, InputError};
use crate::measure::StateHistory;
use crate::solver::{EnergyBalance, SolverError, SolverSettings};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stoss_kernel::{Material, PartMaterial};

pub use ballistic::BallisticLimitSpec;
pub use blast_plate::BlastPlateSpec;
pub use drop_weight_beam::DropWeightBeamSpec;
pub use penetration::PenetrationSpec;
pub use shpb::ShpbSpec;
pub use taylor::TaylorSpec;
pub use tension::TensionSpec;
pub use uniaxial::UniaxialSpec;

/// The experiment's set-up, by kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Setup {
    /// Homogeneous stress-strain at a rate and temperature (characterisation curves), through
    /// the kernel's uniaxial-stress driver.
    Uniaxial(UniaxialSpec),
    /// The seed 001 sec. 3.4.1 FE tension cylinder.
    Tension(TensionSpec),
    /// Taylor rod-on-anvil.
    Taylor(TaylorSpec),
    /// Split Hopkinson compression bar.
    Shpb(ShpbSpec),
    /// Long-rod penetration against time.
    Penetration(PenetrationSpec),
    /// Ballistic limit: residual against impact velocity of a core through a plate.
    BallisticLimit(BallisticLimitSpec),
    /// Perforation of a concrete slab (RHT): exit against impact velocity, with the concrete
    /// penetration cross-checks ([`perforation`]).
    Perforation(BallisticLimitSpec),
    /// Near-field blast-bulged plate: the permanent deflection profile.
    BlastPlate(BlastPlateSpec),
    /// Reinforced-concrete beam under a drop weight (K&C): striker, accelerations, bar strains
    /// and where damage localises ([`drop_weight_beam`]).
    DropWeightBeam(DropWeightBeamSpec),
}

/// The quantities of every experiment kind (each kind's `QUANTITIES`).
pub const QUANTITIES_OF_EVERY_KIND: [&[&str]; 9] = [
    uniaxial::QUANTITIES,
    shpb::QUANTITIES,
    tension::QUANTITIES,
    taylor::QUANTITIES,
    penetration::QUANTITIES,
    ballistic::QUANTITIES,
    perforation::QUANTITIES,
    blast_plate::QUANTITIES,
    drop_weight_beam::QUANTITIES,
];

impl Setup {
    /// Quantities this kind can predict.
    pub fn quantities(&self) -> &'static [&'static str] {
        match self {
            Setup::Uniaxial(_) => uniaxial::QUANTITIES,
            Setup::Tension(_) => tension::QUANTITIES,
            Setup::Taylor(_) => taylor::QUANTITIES,
            Setup::Shpb(_) => shpb::QUANTITIES,
            Setup::Penetration(_) => penetration::QUANTITIES,
            Setup::BallisticLimit(_) => ballistic::QUANTITIES,
            Setup::Perforation(_) => perforation::QUANTITIES,
            Setup::BlastPlate(_) => blast_plate::QUANTITIES,
            Setup::DropWeightBeam(_) => drop_weight_beam::QUANTITIES,
        }
    }
}

/// The set-up fields a campaign may calibrate beside the material constants (nuisance
/// parameters, `[models.setup]`): the physical quantities of a test that its report may leave
/// uncertain (a projectile's geometry, a striking velocity, a friction, a temperature), never
/// the model's discretisation (element sizes, end times, counts). Each is an `f64` of the
/// kind's spec (or an `Option<f64>` the file gives).
impl Setup {
    /// The fields of this kind a campaign may calibrate, in the order the docs list them.
    pub fn calibratable_fields(&self) -> &'static [&'static str] {
        match self {
            Setup::Uniaxial(_) => &["strain_rate", "temperature"],
            Setup::Tension(_) => &["radius", "length", "strain_rate", "temperature"],
            Setup::Taylor(_) => &[
                "length",
                "diameter",
                "velocity",
                "temperature",
                "anvil_friction",
            ],
            Setup::Shpb(_) => &[
                "specimen_diameter",
                "specimen_length",
                "striker_velocity",
                "striker_length",
                "rise_time",
                "friction",
                "temperature",
            ],
            Setup::Penetration(_) => &[
                "rod_length",
                "rod_diameter",
                "nose_length",
                "tip_radius",
                "velocity",
                "target_thickness",
                "friction",
                "temperature",
            ],
            Setup::BallisticLimit(_) | Setup::Perforation(_) => &[
                "projectile_length",
                "projectile_diameter",
                "nose_length",
                "tip_radius",
                "plate_thickness",
                "gap",
                "friction",
                "temperature",
            ],
            Setup::BlastPlate(_) => &["thickness", "exposed_radius", "temperature"],
            Setup::DropWeightBeam(_) => &["drop_mass", "impact_velocity", "striker_friction"],
        }
    }

    /// The calibratable field `name` (one of [`Setup::calibratable_fields`]), if this kind has
    /// it and the file gives it a value.
    pub fn calibratable_mut(&mut self, name: &str) -> Option<&mut f64> {
        if !self.calibratable_fields().contains(&name) {
            return None;
        }
        match (self, name) {
            (Setup::Uniaxial(s), "strain_rate") => Some(&mut s.strain_rate),
            (Setup::Uniaxial(s), "temperature") => Some(&mut s.temperature),
            (Setup::Tension(s), "radius") => Some(&mut s.radius),
            (Setup::Tension(s), "length") => Some(&mut s.length),
            (Setup::Tension(s), "strain_rate") => Some(&mut s.strain_rate),
            (Setup::Tension(s), "temperature") => Some(&mut s.temperature),
            (Setup::Taylor(s), "length") => Some(&mut s.length),
            (Setup::Taylor(s), "diameter") => Some(&mut s.diameter),
            (Setup::Taylor(s), "velocity") => Some(&mut s.velocity),
            (Setup::Taylor(s), "temperature") => Some(&mut s.temperature),
            (Setup::Taylor(s), "anvil_friction") => Some(&mut s.anvil_friction),
            (Setup::Shpb(s), "specimen_diameter") => Some(&mut s.specimen_diameter),
            (Setup::Shpb(s), "specimen_length") => Some(&mut s.specimen_length),
            (Setup::Shpb(s), "striker_velocity") => Some(&mut s.striker_velocity),
            (Setup::Shpb(s), "striker_length") => Some(&mut s.striker_length),
            (Setup::Shpb(s), "rise_time") => Some(&mut s.rise_time),
            (Setup::Shpb(s), "friction") => Some(&mut s.friction),
            (Setup::Shpb(s), "temperature") => Some(&mut s.temperature),
            (Setup::Penetration(s), "rod_length") => Some(&mut s.rod_length),
            (Setup::Penetration(s), "rod_diameter") => Some(&mut s.rod_diameter),
            (Setup::Penetration(s), "nose_length") => s.nose_length.as_mut(),
            (Setup::Penetration(s), "tip_radius") => s.tip_radius.as_mut(),
            (Setup::Penetration(s), "velocity") => Some(&mut s.velocity),
            (Setup::Penetration(s), "target_thickness") => Some(&mut s.target_thickness),
            (Setup::Penetration(s), "friction") => Some(&mut s.friction),
            (Setup::Penetration(s), "temperature") => Some(&mut s.temperature),
            (Setup::BallisticLimit(s) | Setup::Perforation(s), field) => match field {
                "projectile_length" => Some(&mut s.projectile_length),
                "projectile_diameter" => Some(&mut s.projectile_diameter),
                "nose_length" => s.nose_length.as_mut(),
                "tip_radius" => s.tip_radius.as_mut(),
                "plate_thickness" => Some(&mut s.plate_thickness),
                "gap" => Some(&mut s.gap),
                "friction" => Some(&mut s.friction),
                "temperature" => Some(&mut s.temperature),
                _ => None,
            },
            (Setup::BlastPlate(s), "thickness") => Some(&mut s.thickness),
            (Setup::BlastPlate(s), "exposed_radius") => Some(&mut s.exposed_radius),
            (Setup::BlastPlate(s), "temperature") => Some(&mut s.temperature),
            (Setup::DropWeightBeam(s), "drop_mass") => Some(&mut s.drop_mass),
            (Setup::DropWeightBeam(s), "impact_velocity") => s.impact_velocity.as_mut(),
            (Setup::DropWeightBeam(s), "striker_friction") => Some(&mut s.striker_friction),
            _ => None,
        }
    }

    /// The kind's own checks of a set-up (the ones its file passes when it loads).
    pub fn validate(&self, check: &Check<'_>) -> Result<(), InputError> {
        match self {
            Setup::Uniaxial(spec) => spec.validate(check),
            Setup::Tension(spec) => spec.validate(check),
            Setup::Taylor(spec) => spec.validate(check),
            Setup::Shpb(spec) => spec.validate(check),
            Setup::Penetration(spec) => spec.validate(check),
            Setup::BallisticLimit(spec) | Setup::Perforation(spec) => spec.validate(check),
            Setup::BlastPlate(spec) => spec.validate(check),
            Setup::DropWeightBeam(spec) => spec.validate(check),
        }
    }
}

/// The same experiment simulated another way, to tell a numerical misfit from a material one
/// (`stoss diagnose`, "Simulation or material?"): the discretisation refined, and, where the
/// kind has a second solver, the other solver.
impl Setup {
    /// The set-up with every element size of the model halved (twice the elements across a
    /// Taylor rod), and what changed in words; none for the single-element drivers (uniaxial,
    /// the Hopkinson bar's specimen), whose result does not depend on a mesh, and for the
    /// blast plate (its mesh error is measured in docs/solver.md; a refined plate costs 8x).
    pub fn refined(&self) -> Option<(String, Setup)> {
        if matches!(self, Setup::BlastPlate(_)) {
            return None;
        }
        self.with_element_scale(0.5).ok()
    }

    /// The set-up with every element size of the model multiplied by `factor` (counts of
    /// elements across a length divided by it, rounded, at least one), and what changed in
    /// words: 2 is the coarse fidelity of a multi-fidelity calibration, 0.5 the refinement of
    /// the diagnosis. The blast plate's layers through the thickness scale (its in-plane
    /// elements follow them through `aspect_ratio`), and so do its Euler load grid's cells,
    /// up to the largest cell that keeps the grid check's cells across the charge and never
    /// below the file's cell (a refinement leaves the grid as it is). An error
    /// for the single-element drivers, which have no mesh; the result is not validated (the
    /// caller checks it with the kind's own rules).
    pub fn with_element_scale(&self, factor: f64) -> Result<(String, Setup), String> {
        let mut scaled = self.clone();
        let count = |n: usize| ((n as f64 / factor).round() as usize).max(1);
        let size = |before: f64, after: f64| {
            format!(
                "elements of {:.3} mm instead of {:.3}",
                after * 1e3,
                before * 1e3
            )
        };
        let change = match &mut scaled {
            Setup::Uniaxial(_) | Setup::Shpb(_) => {
                return Err(format!(
                    "a {} experiment is a single-element driver: it has no mesh to scale",
                    kind_name(self)
                ))
            }
            Setup::Taylor(s) => {
                let before = s.radial_elements;
                s.radial_elements = count(before);
                format!(
                    "{} elements across the radius instead of {before}",
                    s.radial_elements
                )
            }
            Setup::Tension(s) => {
                let before = s.element_size;
                s.element_size *= factor;
                size(before, s.element_size)
            }
            Setup::Penetration(s) => {
                let before = s.element_size;
                s.element_size *= factor;
                if let Some(rod) = s.rod_element_size.as_mut() {
                    *rod *= factor;
                }
                size(before, s.element_size)
            }
            Setup::BallisticLimit(s) | Setup::Perforation(s) => {
                let (plate, core) = (s.element_size, s.projectile_element_size);
                s.element_size *= factor;
                s.projectile_element_size *= factor;
                format!(
                    "plate and projectile elements of {:.3} and {:.3} mm instead of {:.3} and {:.3}",
                    s.element_size * 1e3,
                    s.projectile_element_size * 1e3,
                    plate * 1e3,
                    core * 1e3
                )
            }
            Setup::DropWeightBeam(s) => {
                let before = s.element_size;
                s.element_size *= factor;
                s.end_element_size *= factor;
                format!(
                    "elements of {:.1} mm instead of {:.1}",
                    s.element_size * 1e3,
                    before * 1e3
                )
            }
            Setup::BlastPlate(s) => {
                // The plate's layers and the load grid's cells both coarsen by the factor; the
                // grid no further than the charge allows (the blast set-up's own check), and
                // never finer than the file's.
                let before = s.layers;
                s.layers = count(before);
                let cell = s.euler.cell_size;
                s.euler.cell_size = (cell * factor).min(s.charge.largest_cell_size()).max(cell);
                format!(
                    "{} elements through the thickness instead of {before}, load cells of {:.3} \
                     mm instead of {:.3}",
                    s.layers,
                    s.euler.cell_size * 1e3,
                    cell * 1e3
                )
            }
        };
        Ok((change, scaled))
    }

    /// The set-up on the kind's other solver, and its name; none for kinds with one solver.
    pub fn other_solver(&self) -> Option<(String, Setup)> {
        let Setup::Penetration(spec) = self else {
            return None;
        };
        let mut other = spec.clone();
        other.solver = match spec.solver {
            penetration::PenetrationSolver::Lagrange => penetration::PenetrationSolver::Euler,
            penetration::PenetrationSolver::Euler => penetration::PenetrationSolver::Lagrange,
        };
        let name = match other.solver {
            penetration::PenetrationSolver::Lagrange => "the eroding Lagrangian solver",
            penetration::PenetrationSolver::Euler => "the multi-material Eulerian solver",
        };
        Some((name.to_string(), Setup::Penetration(other)))
    }
}

impl Setup {
    /// Whether this kind can use `material` as its calibrated part: the uniaxial driver and
    /// the penetration and ballistic kinds take either model family, the perforation kind RHT
    /// concrete, the drop-weight beam K&C concrete, every other kind only a J2 metal.
    pub fn accepts(&self, material: &PartMaterial) -> Result<(), SimulationError> {
        let (ok, needs) = match self {
            Setup::Uniaxial(_) | Setup::Penetration(_) | Setup::BallisticLimit(_) => (true, ""),
            Setup::Perforation(_) => (material.rht().is_some(), "an RHT concrete"),
            Setup::DropWeightBeam(_) => (material.kc().is_some(), "a K&C concrete"),
            _ => (material.j2().is_some(), "a J2 metal"),
        };
        if ok {
            Ok(())
        } else {
            Err(SimulationError::Family {
                kind: kind_name(self),
                needs,
                given: material.family(),
            })
        }
    }
}

/// The TOML file of an experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    /// Display name.
    pub name: String,
    /// Where the recording comes from; "synthetic" recordings say so and name their truth.
    #[serde(default)]
    pub source: String,
    /// Recording CSV, relative to the experiment file.
    pub recording: String,
    /// Default material file, relative to the experiment file.
    #[serde(default)]
    pub material: Option<String>,
    /// The source group of the recording (a laboratory, a test series): recordings of one
    /// group share the per-source scale a campaign may search (`[models.setup]`
    /// `"<group>.recorded_scale"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source_group: Option<String>,
    /// The factor at which the recording reads the material's response (a source's systematic
    /// offset: a load cell reading 3 % high is 1.03): every prediction is multiplied by it
    /// before it is compared with the recording. Default 1.
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit_scale")]
    pub recorded_scale: f64,
    /// Geometry, mesh and loading.
    pub setup: Setup,
}

/// The name of the per-source scale as a set-up parameter's field.
pub const RECORDED_SCALE: &str = "recorded_scale";

/// Plausible range of [`ExperimentFile::recorded_scale`]: a source that reads more than a
/// factor 2 off is a unit slip, not an offset.
pub const RECORDED_SCALE_RANGE: [f64; 2] = [0.5, 2.0];

fn unit_scale() -> f64 {
    1.0
}

fn is_unit_scale(scale: &f64) -> bool {
    *scale == 1.0
}

/// A loaded experiment: file, recording and paths.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// The experiment file's path.
    pub path: PathBuf,
    /// Its contents.
    pub file: ExperimentFile,
    /// The recorded points.
    pub recording: Vec<RecordedPoint>,
}

/// A named scalar result of a run (what `stoss simulate` prints and `summary.json` holds).
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryValue {
    /// Name (snake case).
    pub name: String,
    /// Value (SI).
    pub value: f64,
    /// Its SI unit: `-` dimensionless, `1` a count, `index` a code (a failure mode's place
    /// in its list), `deg` an angle.
    pub unit: &'static str,
}

impl SummaryValue {
    /// A result `name` of `value` in `unit`.
    pub fn new(name: impl Into<String>, value: f64, unit: &'static str) -> Self {
        Self {
            name: name.into(),
            value,
            unit,
        }
    }
}

impl Outcome {
    /// The summary value named `name`, if the run produced one.
    pub fn summary_value(&self, name: &str) -> Option<f64> {
        self.summary
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.value)
    }
}

/// What a simulation of an experiment produced.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The prediction of each recorded point, in the recording's order.
    pub predicted: Vec<f64>,
    /// Named scalar results (e.g. final length), SI, with their units.
    pub summary: Vec<SummaryValue>,
    /// Energy balance (FE runs).
    pub energy: Option<EnergyBalance>,
    /// State histories of the material points that drive the measurements.
    pub states: Vec<StateHistory>,
    /// Final fields (axisymmetric FE runs).
    pub field: Option<FieldOutput>,
    /// Final fields (3D FE runs).
    pub field_3d: Option<HexFieldOutput>,
    /// Element-cycles of the run (0 for driver runs).
    pub element_cycles: u64,
    /// A protocol's own report (e.g. the ballistic-limit table and fit), printed by
    /// `stoss simulate` and written beside its other outputs.
    pub report: Option<ExperimentReport>,
}

/// Why a simulation failed.
#[derive(Debug, thiserror::Error)]
pub enum SimulationError {
    /// The solver failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// The kernel driver failed.
    #[error(transparent)]
    Driver(stoss_kernel::drivers::DriverError),
    /// The Eulerian solver failed.
    #[error(transparent)]
    Euler(#[from] crate::euler::EulerError),
    /// The material's model family is not one this experiment kind can use.
    #[error("a {kind} experiment needs {needs} material, not {given}")]
    Family {
        /// The experiment kind.
        kind: &'static str,
        /// The family it needs, with its article ("a J2 metal").
        needs: &'static str,
        /// The family it was given.
        given: &'static str,
    },
}

impl Experiment {
    /// Load an experiment file and its recording. Errors name the file, line and field; a
    /// recording its experiment could not have produced is refused ([`plausibility`]).
    pub fn load(path: &Path) -> Result<Self, InputError> {
        Self::load_checked(path, true)
    }

    /// Load an experiment whose recording is a template of positions to be filled by `stoss
    /// synthesize` (its values are placeholders): every check of [`Self::load`] but the
    /// plausibility of the recorded values.
    pub fn load_template(path: &Path) -> Result<Self, InputError> {
        Self::load_checked(path, false)
    }

    fn load_checked(path: &Path, check_values: bool) -> Result<Self, InputError> {
        let text = input::read_text(path)?;
        let mut file: ExperimentFile = input::parse_toml(path, &text)?;
        let check = |field: &str, ok: bool, message: &str| {
            if ok {
                Ok(())
            } else {
                Err(InputError::field(path, &text, field, message))
            }
        };
        file.setup.validate(&check)?;
        let [low, high] = RECORDED_SCALE_RANGE;
        check(
            RECORDED_SCALE,
            file.recorded_scale.is_finite()
                && (low..=high).contains(&file.recorded_scale),
            &format!(
                "{} must lie in {low}..={high} (a source reading more than a factor 2 off is a unit slip)",
                file.recorded_scale
            ),
        )?;
        if let Some(group) = &file.source_group {
            check(
                "source_group",
                !group.trim().is_empty() && !group.contains('.'),
                "a source group needs a name without dots (it is the target of \"<group>.recorded_scale\")",
            )?;
        }
        if let Setup::BlastPlate(spec) = &mut file.setup {
            spec.cache_folder = Some(match &spec.load_cache {
                Some(folder) => path.parent().unwrap_or(Path::new(".")).join(folder),
                None => crate::blast::cache::default_folder(),
            });
        }
        if let Setup::Penetration(spec) = &mut file.setup {
            let rod_path = path
                .parent()
                .unwrap_or(Path::new("."))
                .join(&spec.rod_material);
            let (_, rod) = input::material::load_part(&rod_path)?;
            spec.rod = Some(Box::new(rod));
        }
        if let Setup::BallisticLimit(spec) | Setup::Perforation(spec) = &mut file.setup {
            let projectile_path = path
                .parent()
                .unwrap_or(Path::new("."))
                .join(&spec.projectile_material);
            let (_, projectile) = input::material::load_part(&projectile_path)?;
            spec.projectile = Some(Box::new(projectile));
        }
        if let Setup::DropWeightBeam(spec) = &mut file.setup {
            let steel_path = path
                .parent()
                .unwrap_or(Path::new("."))
                .join(&spec.steel_material);
            let (_, steel) = input::material::load_part(&steel_path)?;
            spec.steel = Some(Box::new(steel));
        }
        let recording_path = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&file.recording);
        // A recording that cannot be read is named with the field that points to it.
        let recording = recording::load(&recording_path).map_err(|error| match error {
            InputError::Io {
                path: missing,
                message,
            } => InputError::field(
                path,
                &text,
                "recording",
                format!("{}: {message}", missing.display()),
            ),
            other => other,
        })?;
        let known = file.setup.quantities();
        for (index, point) in recording.iter().enumerate() {
            if !known.contains(&point.quantity.as_str()) {
                return Err(InputError::Field {
                    path: recording_path.clone(),
                    line: recording::point_line(&recording_path, index),
                    field: "quantity".into(),
                    message: format!(
                        "point {}: `{}` is not measured by a {} experiment (known: {})",
                        index + 1,
                        point.quantity,
                        kind_name(&file.setup),
                        known.join(", ")
                    ),
                });
            }
        }
        // Values and positions the experiment could not have produced (docs/formats.md,
        // "Recordings checked against their experiment").
        if let Some(bad) = check_values
            .then(|| plausibility::check(&file.setup, &recording))
            .flatten()
        {
            return Err(InputError::Field {
                path: recording_path.clone(),
                line: recording::point_line(&recording_path, bad.index),
                field: bad.column.into(),
                message: format!("point {}: {}", bad.index + 1, bad.message),
            });
        }
        if let Setup::Penetration(spec) = &file.setup {
            for (index, point) in recording.iter().enumerate() {
                let history = matches!(point.quantity.as_str(), "nose_depth" | "rod_length");
                if history && !(point.position >= 0.0 && point.position <= spec.end_time) {
                    return Err(InputError::Field {
                        path: recording_path.clone(),
                        line: recording::point_line(&recording_path, index),
                        field: "position".into(),
                        message: format!(
                            "point {}: time {} s is outside the simulated 0..{} s after impact \
                             (setup.end_time)",
                            index + 1,
                            point.position,
                            spec.end_time
                        ),
                    });
                }
            }
        }
        if let Setup::Uniaxial(_) = &file.setup {
            for (index, point) in recording.iter().enumerate() {
                let curve = point.quantity == "true_stress";
                if curve && !(0.0..=uniaxial::MAXIMUM_PLASTIC_STRAIN).contains(&point.position) {
                    // A negative strain is not a unit slip: say what it is.
                    let why = if point.position < 0.0 {
                        "a strain below 0 (digitisation scatter near the curve's start? set \
                         it to 0 or drop the point)"
                    } else {
                        "above the range: a strain in percent? write `position [%]` in the \
                         header"
                    };
                    return Err(InputError::Field {
                        path: recording_path.clone(),
                        line: recording::point_line(&recording_path, index),
                        field: "position".into(),
                        message: format!(
                            "point {}: `true_stress` is recorded at a strain in 0..={}, not {} \
                             ({why})",
                            index + 1,
                            uniaxial::MAXIMUM_PLASTIC_STRAIN,
                            point.position
                        ),
                    });
                }
            }
        }
        // Converted and trimmed after the checks above, so their line numbers are the file's.
        let mut recording = recording;
        if let Setup::Uniaxial(spec) = &mut file.setup {
            if spec.recorded_measure == uniaxial::RecordedMeasure::Engineering {
                check(
                    "recorded_measure",
                    spec.recorded_strain == uniaxial::RecordedStrain::Total,
                    "an engineering strain is a total strain (elongation over initial \
                     length): set recorded_strain = \"total\" with it",
                )?;
                for (index, point) in recording.iter_mut().enumerate() {
                    if point.quantity != "true_stress" {
                        continue;
                    }
                    if spec.compression && point.position >= 1.0 {
                        return Err(InputError::Field {
                            path: recording_path.clone(),
                            line: recording::point_line(&recording_path, index),
                            field: "position".into(),
                            message: format!(
                                "an engineering compressive strain of {} (at least 1) has no \
                                 true strain",
                                point.position
                            ),
                        });
                    }
                    let converted = uniaxial::engineering_to_true(point, spec.compression);
                    // The range that bounds the driver's steps holds for the strain it runs to.
                    if !(0.0..=uniaxial::MAXIMUM_PLASTIC_STRAIN).contains(&converted.position) {
                        return Err(InputError::Field {
                            path: recording_path.clone(),
                            line: recording::point_line(&recording_path, index),
                            field: "position".into(),
                            message: format!(
                                "the engineering strain {} is a true strain of {:.3}, above \
                                 the {} a flow curve may reach",
                                point.position,
                                converted.position,
                                uniaxial::MAXIMUM_PLASTIC_STRAIN
                            ),
                        });
                    }
                    *point = converted;
                }
            }
            if spec.trim_at_maximum {
                let (kept, trimmed) = uniaxial::trimmed_at_maximum(recording);
                recording = kept;
                spec.trimmed = trimmed;
            }
        }
        if let Setup::BallisticLimit(spec) | Setup::Perforation(spec) = &file.setup {
            let wants_limit = recording.iter().any(|p| p.quantity == "ballistic_limit");
            check(
                "impact_velocities",
                !wants_limit || !spec.impact_velocities.is_empty(),
                "the recording asks for the ballistic_limit: give the impact velocities of the \
                 sweep that brackets it (m/s)",
            )?;
            let mut velocities: Vec<f64> = recording
                .iter()
                .filter(|p| p.quantity != "ballistic_limit")
                .map(|p| p.position)
                .collect();
            velocities.sort_by(f64::total_cmp);
            velocities.dedup();
            if velocities.len() > ballistic::MAXIMUM_SHOTS {
                return Err(InputError::Field {
                    path: recording_path.clone(),
                    line: None,
                    field: "position".into(),
                    message: format!(
                        "{} distinct impact velocities: each is a whole run; at most {}",
                        velocities.len(),
                        ballistic::MAXIMUM_SHOTS
                    ),
                });
            }
            for (index, point) in recording.iter().enumerate() {
                let per_shot = point.quantity != "ballistic_limit";
                if per_shot && !(point.position > 0.0 && point.position.is_finite()) {
                    return Err(InputError::Field {
                        path: recording_path.clone(),
                        line: None,
                        field: "position".into(),
                        message: format!(
                            "point {}: `{}` is recorded at an impact velocity (m/s, > 0), not \
                             {}",
                            index + 1,
                            point.quantity,
                            point.position
                        ),
                    });
                }
            }
        }
        Ok(Self {
            path: path.into(),
            file,
            recording,
        })
    }

    /// The default material file named by the experiment, resolved against its folder.
    pub fn default_material_path(&self) -> Option<PathBuf> {
        self.file
            .material
            .as_ref()
            .map(|m| self.path.parent().unwrap_or(Path::new(".")).join(m))
    }

    /// Simulate with `material`, the experiment's calibrated part (the target of the
    /// penetration kinds, the specimen otherwise). Kinds that only know J2 metals refuse
    /// another family with [`SimulationError::Family`].
    pub fn simulate(
        &self,
        material: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<Outcome, SimulationError> {
        let setup = &self.file.setup;
        setup.accepts(material)?;
        let j2 = || -> Result<&Material, SimulationError> {
            material.j2().ok_or(SimulationError::Family {
                kind: kind_name(setup),
                needs: "a J2 metal",
                given: material.family(),
            })
        };
        let mut outcome = match setup {
            Setup::Uniaxial(spec) => spec.simulate(material, &self.recording),
            Setup::Tension(spec) => spec.simulate(j2()?, settings, &self.recording),
            Setup::Taylor(spec) => spec.simulate(j2()?, settings, &self.recording),
            Setup::Shpb(spec) => spec.simulate(j2()?, settings, &self.recording),
            Setup::Penetration(spec) => spec.simulate(material, settings, &self.recording),
            Setup::BallisticLimit(spec) => spec.simulate(material, settings, &self.recording),
            Setup::Perforation(spec) => {
                perforation::simulate(spec, material, settings, &self.recording)
            }
            Setup::BlastPlate(spec) => spec.simulate(j2()?, settings, &self.recording),
            Setup::DropWeightBeam(spec) => spec.simulate(material, settings, &self.recording),
        }?;
        // The source's systematic offset: the recording reads the response times its scale.
        if self.file.recorded_scale != 1.0 {
            for value in &mut outcome.predicted {
                *value *= self.file.recorded_scale;
            }
        }
        Ok(outcome)
    }
}

/// The `kind` string of a set-up.
pub fn kind_name(setup: &Setup) -> &'static str {
    match setup {
        Setup::Uniaxial(_) => "uniaxial",
        Setup::Tension(_) => "tension",
        Setup::Taylor(_) => "taylor",
        Setup::Shpb(_) => "shpb",
        Setup::Penetration(_) => "penetration",
        Setup::BallisticLimit(_) => "ballistic-limit",
        Setup::Perforation(_) => "perforation",
        Setup::BlastPlate(_) => "blast-plate",
        Setup::DropWeightBeam(_) => "drop-weight-beam",
    }
}

/// Initial temperature of an experiment file that gives none: room temperature (K).
pub(crate) fn default_temperature() -> f64 {
    298.0
}

/// A validation callback: `(field, ok, message)`.
pub type Check<'a> = dyn Fn(&str, bool, &str) -> Result<(), InputError> + 'a;

/// Check that `value` is finite and > 0; the message names its unit.
pub(crate) fn check_positive(
    check: &Check,
    field: &str,
    value: f64,
    unit: &str,
) -> Result<(), InputError> {
    check(
        field,
        value > 0.0 && value.is_finite(),
        &format!("must be > 0 ({unit})"),
    )
}

/// Largest quadratic bulk-viscosity coefficient an experiment may ask for (LS-DYNA's default is
/// 1.5, Autodyn's 1.0): beyond it a shock is smeared over many elements.
pub(crate) const MAXIMUM_QUADRATIC_VISCOSITY: f64 = 4.0;

/// Largest linear bulk-viscosity coefficient an experiment may ask for (LS-DYNA's default is
/// 0.06, Autodyn's 0.2): at 1 the stable step is already 0.41 of the inviscid one.
pub(crate) const MAXIMUM_LINEAR_VISCOSITY: f64 = 1.0;

/// Check an experiment's bulk-viscosity coefficients: finite, `0 <= quadratic <=`
/// [`MAXIMUM_QUADRATIC_VISCOSITY`], `0 <= linear <=` [`MAXIMUM_LINEAR_VISCOSITY`].
pub(crate) fn check_bulk_viscosity(
    check: &Check,
    viscosity: Option<&crate::solver::BulkViscosity>,
) -> Result<(), InputError> {
    let Some(viscosity) = viscosity else {
        return Ok(());
    };
    for (field, value, largest) in [
        (
            "bulk_viscosity.quadratic",
            viscosity.quadratic,
            MAXIMUM_QUADRATIC_VISCOSITY,
        ),
        (
            "bulk_viscosity.linear",
            viscosity.linear,
            MAXIMUM_LINEAR_VISCOSITY,
        ),
    ] {
        check(
            field,
            (0.0..=largest).contains(&value),
            &format!("must be in [0, {largest}] (-)"),
        )?;
    }
    Ok(())
}

/// Largest number of time steps a run may need (estimated at the undeformed stable step).
pub(crate) const MAXIMUM_STEPS: f64 = 1.0e6;

/// Largest estimated run (element-cycles): about 2 hours at 2.5 M element-cycles/s.
pub(crate) const MAXIMUM_ELEMENT_CYCLES: f64 = 2.0e10;

/// Most elements of a mesh stoss builds without `--force`.
pub(crate) const MAXIMUM_ELEMENTS: f64 = 2.0e6;

/// Fastest elastic wave a metal carries, for up-front step estimates (m/s).
const FASTEST_METAL_WAVE: f64 = 6000.0;

/// Stable step of an undeformed square element of side `size` at [`FASTEST_METAL_WAVE`], with
/// the default safety factor, or the eroding contact's if `eroding_contact` (s): the
/// characteristic length is the side over `sqrt 2` (area over the diagonal). Distortion makes
/// the real step smaller, never larger.
pub(crate) fn undeformed_time_step(size: f64, eroding_contact: bool) -> f64 {
    crate::solver::SolverSettings::default().effective_time_step_safety(eroding_contact) * size
        / std::f64::consts::SQRT_2
        / FASTEST_METAL_WAVE
}

/// Refuse a run whose `end_time` (field `end_time`) needs more than [`MAXIMUM_STEPS`] steps of
/// `time_step` or more than [`MAXIMUM_ELEMENT_CYCLES`] with `elements` elements, before anything
/// is built: an end time in the wrong unit is an error naming the field, not a runaway.
pub(crate) fn check_run_budget(
    check: &Check,
    end_time: f64,
    time_step: f64,
    elements: f64,
) -> Result<(), InputError> {
    check_run_budget_of(check, "end_time", end_time, time_step, elements)
}

std::thread_local! {
    /// The largest element-cycles a run-budget check computed since the last
    /// [`Experiment::estimated_element_cycles`] began (this thread's; a set-up may check its
    /// one run twice, nominal and as built).
    static RUN_SIZE_TALLY: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

impl Experiment {
    /// The element-cycles one simulation of this experiment is estimated to need: the largest
    /// of what its set-up's run-budget checks ([`check_run_budget_of`]) compute from the mesh
    /// and the end time at the undeformed stable step (so the estimate and the per-run refusal are
    /// one computation), times the shots of a ballistic experiment
    /// ([`ballistic::BallisticLimitSpec::estimated_shots`]). 0 for the single-element drivers.
    /// An underestimate: distortion shrinks the real step.
    pub fn estimated_element_cycles(&self) -> f64 {
        RUN_SIZE_TALLY.with(|tally| tally.set(0.0));
        // Every check passes: the set-up was validated when it was loaded; this walks the
        // same computation for its sizes.
        let _ = self.file.setup.validate(&|_, _, _| Ok(()));
        let one = RUN_SIZE_TALLY.with(|tally| tally.replace(0.0));
        match &self.file.setup {
            Setup::BallisticLimit(spec) | Setup::Perforation(spec) => {
                one * spec.estimated_shots(&self.recording) as f64
            }
            _ => one,
        }
    }
}

/// Whether a run to `end_time` at `time_step` with `elements` elements stays within
/// [`MAXIMUM_STEPS`], [`MAXIMUM_ELEMENTS`] and [`MAXIMUM_ELEMENT_CYCLES`].
pub(crate) fn within_run_budget(end_time: f64, time_step: f64, elements: f64) -> bool {
    let steps = end_time / time_step;
    steps <= MAXIMUM_STEPS
        && elements <= MAXIMUM_ELEMENTS
        && steps * elements <= MAXIMUM_ELEMENT_CYCLES
}

/// [`check_run_budget`] for a run whose end time follows from other fields; the error names
/// `field` (the one a unit slip would have made too large).
pub(crate) fn check_run_budget_of(
    check: &Check,
    field: &str,
    end_time: f64,
    time_step: f64,
    elements: f64,
) -> Result<(), InputError> {
    let steps = end_time / time_step;
    RUN_SIZE_TALLY.with(|tally| tally.set(tally.get().max(steps * elements)));
    check(
        field,
        crate::input::implausible_allowed() || within_run_budget(end_time, time_step, elements),
        &format!(
            "needs at least {steps:.0} steps of {elements:.0} elements ({:.1e} \
             element-cycles; at most {MAXIMUM_STEPS:.0} steps, {MAXIMUM_ELEMENTS:.0e} elements \
             and {MAXIMUM_ELEMENT_CYCLES:.0e} element-cycles, several hours on 2 cores): check \
             the units (SI: m, s), or pass --force to run it anyway",
            steps * elements
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;
    use stoss_kernel::ParameterError;

    /// A set-up check that reports a failed rule as a field error of the file at `path`.
    fn field_check(
        path: &std::path::Path,
        field: &str,
        ok: bool,
        message: &str,
    ) -> Result<(), InputError> {
        if ok {
            Ok(())
        } else {
            Err(InputError::Field {
                path: path.to_path_buf(),
                line: None,
                field: field.into(),
                message: message.into(),
            })
        }
    }

    #[test]
    fn a_refined_set_up_passes_the_same_size_checks_as_a_loaded_file() {
        // GOAL: the diagnosis' refined variants (`Setup::refined`) cannot become a runaway:
        //       each halving is checked against the run budget before it runs.
        // SETUP: seed 000's 1250 m/s shot (0.4 mm), refined again and again.
        // REFERENCE: the first refinement (0.2 mm) passes; within five halvings (0.0125 mm,
        //            far over 2e6 elements) the check refuses, naming the budget.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/experiments/penetration-hzb-1250.toml");
        let experiment = Experiment::load(&path).unwrap();
        let check = |field: &str, ok: bool, message: &str| field_check(&path, field, ok, message);
        let mut setup = experiment.file.setup.clone();
        let mut refusal = None;
        for halving in 1..=5 {
            let (_, refined) = setup.refined().unwrap();
            setup = refined;
            if let Err(error) = setup.validate(&check) {
                refusal = Some((halving, error.to_string()));
                break;
            }
        }
        let (halving, message) = refusal.expect("a five-fold refinement is refused");
        assert!(halving > 1, "{message}");
        assert!(message.contains("elements"), "{message}");
    }

    #[test]
    fn a_coarse_blast_plate_coarsens_its_load_grid_as_far_as_the_charge_allows() {
        // GOAL: the coarse fidelity of a blast plate coarsens the Euler load grid with the
        //       plate, without ever producing a grid the blast set-up's own check refuses.
        // SETUP: seed 000's two plates (1 mm cells; discs 50 mm across, 11.93 and 18.29 mm
        //        tall), coarse factors 1.1, 1.5 and 2 (4 leaves the plate 2 layers, which its
        //        own check refuses), and the refinement (0.5).
        // REFERENCE: cell = min(factor x 1 mm, smallest dimension / 10), never below 1 mm;
        //            every coarse set-up passes `validate`; the refinement keeps 1 mm.
        for (file, height) in [
            ("blast-hha-37g-13mm.toml", 11.929e-3),
            ("blast-hha-57g-25mm.toml", 18.291e-3),
        ] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../fixtures/experiments")
                .join(file);
            let experiment = Experiment::load(&path).unwrap();
            let check =
                |field: &str, ok: bool, message: &str| field_check(&path, field, ok, message);
            let cell = |setup: &Setup| match setup {
                Setup::BlastPlate(spec) => spec.euler.cell_size,
                _ => unreachable!(),
            };
            assert_eq!(cell(&experiment.file.setup), 1.0e-3);
            for factor in [1.1, 1.5, 2.0] {
                let (change, coarse) = experiment.file.setup.with_element_scale(factor).unwrap();
                let expected = (factor * 1.0e-3).min(height / 10.0);
                assert!(
                    (cell(&coarse) - expected).abs() < 1e-3 * expected,
                    "{file} x{factor}: {} against {expected} ({change})",
                    cell(&coarse)
                );
                assert!(change.contains("load cells"), "{change}");
                coarse.validate(&check).unwrap();
            }
            let (_, refined) = experiment.file.setup.with_element_scale(0.5).unwrap();
            assert_eq!(cell(&refined), 1.0e-3);
        }
    }

    #[test]
    fn simulation_error_exposes_its_cause_through_source() {
        // GOAL: a wrapping SimulationError keeps the chain of causes reachable through
        //       `std::error::Error::source()`, and a leaf variant has no source.
        // SETUP: Solver(Material { error: NotPositive }) (a solver error with a kernel
        //        cause); Solver(Model(..)) (a solver error without one); Family (a leaf).
        // REFERENCE: thiserror's `#[error(transparent)]` forwards both the message and
        //   `source()` to the wrapped error, and `#[source]` returns the marked field;
        //   so the first source is the kernel's ParameterError, with its own message.
        let cause = ParameterError::NotPositive {
            field: "density",
            value: -1.0,
        };
        let wrapped = SimulationError::Solver(SolverError::Material {
            part: "plate".into(),
            error: cause,
        });
        assert_eq!(
            wrapped.to_string(),
            "part plate: density: must be > 0, got -1"
        );
        let source = wrapped.source().expect("the kernel error is the source");
        assert_eq!(source.to_string(), cause.to_string());
        assert_eq!(
            source.downcast_ref::<ParameterError>(),
            Some(&cause),
            "the source is the kernel's error itself"
        );
        assert!(
            source.source().is_none(),
            "the kernel error is the end of the chain"
        );

        let without_cause = SimulationError::from(SolverError::Model("no parts".into()));
        assert_eq!(without_cause.to_string(), "no parts");
        assert!(without_cause.source().is_none());

        let leaf = SimulationError::Family {
            kind: "Taylor",
            needs: "a J2 metal",
            given: "RHT concrete",
        };
        assert_eq!(
            leaf.to_string(),
            "a Taylor experiment needs a J2 metal material, not RHT concrete"
        );
        assert!(leaf.source().is_none());
    }
}
