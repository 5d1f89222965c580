//! Golden histories: driver outputs of every reference material stored as exact IEEE-754
//! binary64 bit patterns (hex), compared bit for bit. They catch *change*; correctness is the
//! job of [`super::checks`].
//!
//! File format (`fixtures/golden/<material>__<driver>.golden`, text):
//! ```text
//! # stoss golden history v1
//! # material: jc-4340
//! # driver: uniaxial-stress
//! # columns: time strain_xx ... flags
//! 3e45798ee2308c3a 0000000000000000 ...   <- one line per step, 23 hex words
//! ```
//! Regenerate with `stoss verify --bless`; every commit that changes a golden file says why.

use super::materials::reference_materials;
use crate::history::History;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stoss_kernel::drivers::{
    hydrostatic, simple_shear, strain_path, uniaxial_strain, uniaxial_stress, DriverError,
    HydrostaticLoading, PathPoint, Record, SimpleShearLoading, UniaxialStrainLoading,
    UniaxialStressLoading,
};
use stoss_kernel::eos::{Eos, MieGruneisen, TabulatedCompaction};
use stoss_kernel::kc::{KcMaterial, KcParameters};
use stoss_kernel::rht::RhtMaterial;
use stoss_kernel::{
    Material, MaterialState, PointModel, StepInput, StepOutput, UpdateError, LANES,
};

/// A material point model of a golden case: a J2 metal, RHT or K&C concrete.
#[derive(Clone, Copy, Debug)]
pub enum GoldenModel {
    /// J2 metal (any strength model and EoS).
    Metal(Material),
    /// RHT concrete.
    Concrete(RhtMaterial),
    /// K&C concrete.
    KcConcrete(KcMaterial),
}

impl GoldenModel {
    fn initial_state(&self) -> MaterialState {
        match self {
            GoldenModel::Metal(material) => {
                let mut state = MaterialState::initial(298.0);
                state.eos_history = material.eos.initial_history();
                state
            }
            GoldenModel::Concrete(material) => material.initial_state(293.0),
            GoldenModel::KcConcrete(material) => material.initial_state(293.0),
        }
    }
}

/// A model whose every step goes through its group update ([`PointModel::update_lanes`]):
/// the driver's point in the first lane, and lane-mates that take other ways through the
/// group from the same state (half, reversed, doubled and nearly equal increments, a hold, a
/// NaN increment, a negative time step). The first lane's result is the step's.
pub struct Grouped<'a, M>(pub &'a M);

impl<M: PointModel> Grouped<'_, M> {
    /// Lane `lane`'s input beside the driver's `input`.
    fn lane_mate(input: &StepInput, lane: usize) -> StepInput {
        let scale = [1.0, 0.5, -1.0, 2.0, 0.0, f64::NAN, 1.0, 1.0001][lane % 8];
        StepInput {
            strain_increment: input.strain_increment.map(|e| scale * e),
            dt: if lane % 8 == 6 { -input.dt } else { input.dt },
            relative_volume: input.relative_volume,
        }
    }
}

impl<M: PointModel> PointModel for Grouped<'_, M> {
    fn validate(&self) -> Result<(), stoss_kernel::ParameterError> {
        self.0.validate()
    }
    fn shear_modulus(&self) -> f64 {
        self.0.shear_modulus()
    }
    fn density(&self) -> f64 {
        self.0.density()
    }
    fn initial_state(&self, temperature: f64) -> MaterialState {
        self.0.initial_state(temperature)
    }
    fn kinematic_strain_bound(&self) -> Option<f64> {
        self.0.kinematic_strain_bound()
    }
    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> stoss_kernel::StateFlags {
        self.0.kinematic_flags(principal_strains)
    }
    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        let mut states = [*state; LANES];
        let inputs = core::array::from_fn(|lane| Self::lane_mate(input, lane));
        let mut results = [Err(UpdateError::NonFiniteInput); LANES];
        self.0.update_lanes(&mut states, &inputs, &mut results);
        if results[0].is_ok() {
            *state = states[0];
        }
        results[0]
    }
    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut stoss_kernel::tensor::Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        self.0.update_with_tangent(state, input, tangent)
    }
}

const HEADER: &str = "# stoss golden history v1";

/// A single-element driver run whose history is kept bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoldenDriver {
    /// Uniaxial tension, 1000 /s to 0.1, 100 steps.
    UniaxialStress,
    /// Uniaxial-strain compression, 1e4 /s to -0.05, 100 steps.
    UniaxialStrain,
    /// Hydrostatic compression to 3 % and release, 50 + 50 steps.
    Hydrostatic,
    /// Simple shear, 500 /s to eps_xy 0.1, 100 steps.
    SimpleShear,
    /// Non-proportional path (tension, then shear, then compression) with an imposed
    /// temperature ramp 298 K -> 700 K, 3 x 40 steps.
    StrainPathWithTemperature,
    /// Hydrostatic compaction to 10 % and release, 100 + 100 steps (porous EoS).
    HydrostaticCompaction,
    /// Concrete uniaxial compression, 1 /s to -0.4 %, 200 steps (RHT, seed 001 sec. 4.3.2).
    ConcreteCompression,
    /// Concrete uniaxial tension, 1 /s to +0.03 %, 150 steps.
    ConcreteTension,
    /// Concrete uniaxial strain, 100 /s to -2 %, 200 steps.
    ConcreteUniaxialStrain,
}

impl GoldenDriver {
    /// File-name identifier.
    pub fn name(self) -> &'static str {
        match self {
            GoldenDriver::UniaxialStress => "uniaxial-stress",
            GoldenDriver::UniaxialStrain => "uniaxial-strain",
            GoldenDriver::Hydrostatic => "hydrostatic",
            GoldenDriver::SimpleShear => "simple-shear",
            GoldenDriver::StrainPathWithTemperature => "strain-path-temperature",
            GoldenDriver::HydrostaticCompaction => "hydrostatic-compaction",
            GoldenDriver::ConcreteCompression => "uniaxial-compression",
            GoldenDriver::ConcreteTension => "uniaxial-tension",
            GoldenDriver::ConcreteUniaxialStrain => "uniaxial-strain",
        }
    }

    /// Run the driver on `model` from its initial state.
    pub fn run(self, model: &GoldenModel) -> Result<Vec<Record>, DriverError> {
        match model {
            GoldenModel::Metal(material) => self.run_with(material, model.initial_state()),
            GoldenModel::Concrete(material) => self.run_with(material, model.initial_state()),
            GoldenModel::KcConcrete(material) => self.run_with(material, model.initial_state()),
        }
    }

    /// [`GoldenDriver::run`] with every step taken through the model's group update
    /// ([`Grouped`]).
    pub fn run_grouped(self, model: &GoldenModel) -> Result<Vec<Record>, DriverError> {
        let state = model.initial_state();
        match model {
            GoldenModel::Metal(material) => self.run_with(&Grouped(material), state),
            GoldenModel::Concrete(material) => self.run_with(&Grouped(material), state),
            GoldenModel::KcConcrete(material) => self.run_with(&Grouped(material), state),
        }
    }

    fn run_with(
        self,
        material: &impl PointModel,
        mut state: MaterialState,
    ) -> Result<Vec<Record>, DriverError> {
        let mut history = History::default();
        let stress = |rate: f64, strain: f64, steps: u32| UniaxialStressLoading {
            strain_rate: rate,
            final_strain: strain,
            steps,
        };
        match self {
            GoldenDriver::UniaxialStress => uniaxial_stress(
                material,
                &mut state,
                &UniaxialStressLoading {
                    strain_rate: 1000.0,
                    final_strain: 0.1,
                    steps: 100,
                },
                &mut history,
            ),
            GoldenDriver::UniaxialStrain => uniaxial_strain(
                material,
                &mut state,
                &UniaxialStrainLoading {
                    strain_rate: 1.0e4,
                    final_strain: -0.05,
                    steps: 100,
                },
                &mut history,
            ),
            GoldenDriver::Hydrostatic => hydrostatic(
                material,
                &mut state,
                &HydrostaticLoading {
                    peak_compression: 0.03,
                    strain_rate: 1000.0,
                    loading_steps: 50,
                    unloading_steps: 50,
                },
                &mut history,
            ),
            GoldenDriver::SimpleShear => simple_shear(
                material,
                &mut state,
                &SimpleShearLoading {
                    shear_rate: 500.0,
                    final_shear_strain: 0.1,
                    steps: 100,
                },
                &mut history,
            ),
            GoldenDriver::StrainPathWithTemperature => {
                let point = |time: f64, strain: [f64; 6], temperature: f64| PathPoint {
                    time,
                    strain,
                    temperature: Some(temperature),
                };
                let path = [
                    point(0.0, [0.0; 6], 298.0),
                    point(1.0e-4, [0.05, -0.025, -0.025, 0.0, 0.0, 0.0], 400.0),
                    point(2.0e-4, [0.05, -0.025, -0.025, 0.04, 0.0, 0.02], 550.0),
                    point(3.0e-4, [-0.02, 0.01, 0.01, 0.04, 0.01, 0.02], 700.0),
                ];
                strain_path(material, &mut state, &path, 40, &mut history)
            }
            GoldenDriver::HydrostaticCompaction => hydrostatic(
                material,
                &mut state,
                &HydrostaticLoading {
                    peak_compression: 0.1,
                    strain_rate: 100.0,
                    loading_steps: 100,
                    unloading_steps: 100,
                },
                &mut history,
            ),
            GoldenDriver::ConcreteCompression => uniaxial_stress(
                material,
                &mut state,
                &stress(1.0, -0.004, 200),
                &mut history,
            ),
            GoldenDriver::ConcreteTension => uniaxial_stress(
                material,
                &mut state,
                &stress(1.0, 3.0e-4, 150),
                &mut history,
            ),
            GoldenDriver::ConcreteUniaxialStrain => uniaxial_strain(
                material,
                &mut state,
                &UniaxialStrainLoading {
                    strain_rate: 100.0,
                    final_strain: -0.02,
                    steps: 200,
                },
                &mut history,
            ),
        }?;
        Ok(history.0)
    }
}

/// One golden case: a reference material through one driver.
#[derive(Clone, Copy, Debug)]
pub struct GoldenCase {
    /// Reference material name.
    pub material_name: &'static str,
    /// The material point model.
    pub model: GoldenModel,
    /// The driver.
    pub driver: GoldenDriver,
}

/// 4340 JC with the Steinberg (1996) Mie-Grueneisen EoS for 4340 (rho0 7810, C 4578 m/s,
/// S1 1.33, gamma0 1.67, a 0.43), adiabatic.
pub fn steel_4340_gruneisen() -> Material {
    let mut material = Material::STEEL_4340;
    material.density = 7810.0;
    material.eos = Eos::MieGruneisen(MieGruneisen {
        reference_density: 7810.0,
        sound_speed: 4578.0,
        s1: 1.33,
        s2: 0.0,
        s3: 0.0,
        gamma0: 1.67,
        volume_correction: 0.43,
    });
    material
}

/// The FOI table 5.2 compaction EoS (concrete, rho0 2390) under a weak JC deviatoric
/// response; only its hydrostatic path matters.
pub fn table_5_2_compaction() -> Material {
    let mut material = Material::STEEL_4340;
    material.density = 2390.0;
    material.shear_modulus = 12.0e9;
    material.eos = Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2);
    material
}

impl GoldenCase {
    /// File name under the golden directory.
    pub fn file_name(&self) -> String {
        format!("{}__{}.golden", self.material_name, self.driver.name())
    }
}

/// Every golden case, in a fixed order: each reference metal through the five metal drivers,
/// then the EoS, RHT (seed 001 sec. 4.3.2 single-element tests) and K&C cases.
pub fn cases() -> Vec<GoldenCase> {
    let metal_drivers = [
        GoldenDriver::UniaxialStress,
        GoldenDriver::UniaxialStrain,
        GoldenDriver::Hydrostatic,
        GoldenDriver::SimpleShear,
        GoldenDriver::StrainPathWithTemperature,
    ];
    let mut all: Vec<GoldenCase> = reference_materials()
        .into_iter()
        .flat_map(|reference| {
            metal_drivers.into_iter().map(move |driver| GoldenCase {
                material_name: reference.name,
                model: GoldenModel::Metal(reference.material),
                driver,
            })
        })
        .collect();
    for driver in metal_drivers {
        all.push(GoldenCase {
            material_name: "jc-4340-gruneisen",
            model: GoldenModel::Metal(steel_4340_gruneisen()),
            driver,
        });
    }
    all.push(GoldenCase {
        material_name: "eos-table-5-2",
        model: GoldenModel::Metal(table_5_2_compaction()),
        driver: GoldenDriver::HydrostaticCompaction,
    });
    for driver in [
        GoldenDriver::HydrostaticCompaction,
        GoldenDriver::ConcreteCompression,
        GoldenDriver::ConcreteTension,
        GoldenDriver::ConcreteUniaxialStrain,
    ] {
        all.push(GoldenCase {
            material_name: "rht-hpc-92",
            model: GoldenModel::Concrete(RhtMaterial::HPC_92MPA),
            driver,
        });
    }
    // K&C (seed 001 chapter 5) with the crack band of a 10 mm element.
    let kc = KcMaterial {
        parameters: KcParameters::HPC_100MPA_FOI.with_fracture_energy(156.0, 0.01),
        ..KcMaterial::HPC_100MPA_FOI
    };
    for driver in [
        GoldenDriver::HydrostaticCompaction,
        GoldenDriver::ConcreteCompression,
        GoldenDriver::ConcreteTension,
        GoldenDriver::ConcreteUniaxialStrain,
    ] {
        all.push(GoldenCase {
            material_name: "kc-hpc-100",
            model: GoldenModel::KcConcrete(kc),
            driver,
        });
    }
    all
}

/// What went wrong with a golden file.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    /// The driver itself failed.
    #[error("{case}: driver failed: {error}")]
    Driver {
        /// Golden file name.
        case: String,
        /// The driver error.
        #[source]
        error: DriverError,
    },
    /// Reading or writing the file failed.
    #[error("{path}: {error}")]
    Io {
        /// File path.
        path: PathBuf,
        /// The I/O error.
        #[source]
        error: std::io::Error,
    },
    /// The file is malformed.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// File path.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The stored and computed histories differ.
    #[error(
        "{path}:{line}: column {column}: stored {expected:e} ({:016x}), computed {actual:e} ({:016x})",
        .expected.to_bits(),
        .actual.to_bits()
    )]
    Mismatch {
        /// File path.
        path: PathBuf,
        /// 1-based line of the first differing record.
        line: usize,
        /// Name of the first differing column.
        column: &'static str,
        /// Stored value.
        expected: f64,
        /// Computed value.
        actual: f64,
    },
    /// The stored and computed histories have different lengths.
    #[error("{path}: {expected} records stored, {actual} computed")]
    Length {
        /// File path.
        path: PathBuf,
        /// Records stored.
        expected: usize,
        /// Records computed.
        actual: usize,
    },
}

/// Render a history in the golden format.
pub fn render(case: &GoldenCase, records: &[Record]) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "{HEADER}");
    let _ = writeln!(text, "# material: {}", case.material_name);
    let _ = writeln!(text, "# driver: {}", case.driver.name());
    let _ = writeln!(text, "# columns: {}", Record::VALUE_NAMES.join(" "));
    for record in records {
        let words: Vec<String> = record
            .values()
            .iter()
            .map(|v| format!("{:016x}", v.to_bits()))
            .collect();
        let _ = writeln!(text, "{}", words.join(" "));
    }
    text
}

/// Parse a golden file into rows of values; errors name the file and line.
pub fn parse(path: &Path, text: &str) -> Result<Vec<[f64; Record::VALUE_COUNT]>, GoldenError> {
    let mut rows = Vec::new();
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, first)) if first == HEADER => {}
        _ => {
            return Err(GoldenError::Parse {
                path: path.into(),
                line: 1,
                message: format!("expected header {HEADER:?}"),
            })
        }
    }
    for (index, line) in lines {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let mut row = [0.0; Record::VALUE_COUNT];
        let mut count = 0;
        for word in line.split_whitespace() {
            let bits = u64::from_str_radix(word, 16).map_err(|_| GoldenError::Parse {
                path: path.into(),
                line: index + 1,
                message: format!("column {}: {word:?} is not a 16-digit hex word", count + 1),
            })?;
            if count < Record::VALUE_COUNT {
                row[count] = f64::from_bits(bits);
            }
            count += 1;
        }
        if count != Record::VALUE_COUNT {
            return Err(GoldenError::Parse {
                path: path.into(),
                line: index + 1,
                message: format!("{count} values, expected {}", Record::VALUE_COUNT),
            });
        }
        rows.push(row);
    }
    Ok(rows)
}

fn run_case(case: &GoldenCase) -> Result<Vec<Record>, GoldenError> {
    case.driver
        .run(&case.model)
        .map_err(|error| GoldenError::Driver {
            case: case.file_name(),
            error,
        })
}

/// Compare one case with its stored file, bit for bit.
pub fn compare(directory: &Path, case: &GoldenCase) -> Result<usize, GoldenError> {
    compare_records(directory, case, run_case(case)?)
}

/// [`compare`] with the case run through the group update ([`GoldenDriver::run_grouped`]).
pub fn compare_grouped(directory: &Path, case: &GoldenCase) -> Result<usize, GoldenError> {
    let computed = case
        .driver
        .run_grouped(&case.model)
        .map_err(|error| GoldenError::Driver {
            case: case.file_name(),
            error,
        })?;
    compare_records(directory, case, computed)
}

/// `computed` against the case's stored file, bit for bit.
fn compare_records(
    directory: &Path,
    case: &GoldenCase,
    computed: Vec<Record>,
) -> Result<usize, GoldenError> {
    let path = directory.join(case.file_name());
    let text = std::fs::read_to_string(&path).map_err(|error| GoldenError::Io {
        path: path.clone(),
        error,
    })?;
    let stored = parse(&path, &text)?;
    if stored.len() != computed.len() {
        return Err(GoldenError::Length {
            path,
            expected: stored.len(),
            actual: computed.len(),
        });
    }
    // Data lines start after the four header lines.
    for (index, (row, record)) in stored.iter().zip(&computed).enumerate() {
        let values = record.values();
        for (column, (expected, actual)) in row.iter().zip(values.iter()).enumerate() {
            if expected.to_bits() != actual.to_bits() {
                return Err(GoldenError::Mismatch {
                    path,
                    line: index + 5,
                    column: Record::VALUE_NAMES[column],
                    expected: *expected,
                    actual: *actual,
                });
            }
        }
    }
    Ok(computed.len())
}

/// Write every golden file (atomically: a temporary file renamed into place).
pub fn bless(directory: &Path) -> Result<usize, GoldenError> {
    std::fs::create_dir_all(directory).map_err(|error| GoldenError::Io {
        path: directory.into(),
        error,
    })?;
    let all = cases();
    // Run everything first, so that a failing case leaves no file half-updated.
    let mut rendered = Vec::with_capacity(all.len());
    for case in &all {
        rendered.push((case.file_name(), render(case, &run_case(case)?)));
    }
    for (name, text) in &rendered {
        let path = directory.join(name);
        let temporary = directory.join(format!(".{name}.tmp"));
        std::fs::write(&temporary, text).map_err(|error| GoldenError::Io {
            path: temporary.clone(),
            error,
        })?;
        std::fs::rename(&temporary, &path).map_err(|error| GoldenError::Io { path, error })?;
    }
    Ok(rendered.len())
}
