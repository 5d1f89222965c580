//! Reference histories for the C and Fortran link tests (`.ci/ffi.sh`).
//!
//! Runs the kernel's own single-element drivers (`stoss_kernel::drivers`) — not the C ABI —
//! with materials built directly from the kernel's structs, and writes one file per case into
//! the directory given as the first argument. Each line is one step: 20 values as 16-digit
//! lower-case hex bit patterns of the `f64`, separated by single spaces:
//!
//! `time strain(xx yy zz xy yz zx) stress(xx yy zz xy yz zx) eps_p rate T D E wave_speed flags`
//!
//! `tests/ffi/c/uniaxial_strain.c` and `tests/ffi/fortran/umat_driver.f90` write the same
//! cases through the C ABI in the same format; the script compares the files byte for byte.
//! The cases (material, path) are defined identically in the three programs:
//!
//! | file | interface | material | path |
//! |---|---|---|---|
//! | `batch_jc_tension` | batch, point 0 of 2 | JC 4340 + JC failure | uniaxial strain +0.3, 300 steps, 1e4 /s |
//! | `batch_jc_compression` | batch, point 1 of 2 | same | uniaxial strain -0.3 |
//! | `batch_mg_lagged` | batch | JC 4340, Mie-Grüneisen, lagged rate | uniaxial strain -0.2, 400 steps, 1e5 /s |
//! | `vumat_za_compression` | VUMAT, point 0 of 2 | ZA BCC | uniaxial strain -0.2, 200 steps, 1e3 /s |
//! | `vumat_za_tension` | VUMAT, point 1 of 2 | same | uniaxial strain +0.2 |
//! | `umat_tjc_tension` | LS-DYNA umat (Fortran) | TJC + JC failure | uniaxial strain +0.25, 250 steps, 1e4 /s |
//! | `umat_jc_simple_shear` | LS-DYNA umat (Fortran) | JC 4340 | simple shear eps_xy 0.3, 300 steps, 1e3 /s |
//! | `batch_jc_upturn_tension` | batch (block, layout 2) | JC 4340 + high-rate upturn (the diagnosis' term) | uniaxial strain +0.3, 300 steps, 1e4 /s |
//! | `umat_jc_upturn_tension` | LS-DYNA umat (Fortran, card version 2) | same | uniaxial strain +0.25, 250 steps, 1e4 /s |
//! | `batch_rht_compression` | batch (layout 3) | RHT HPC 92 MPa over P-alpha (`stoss_material_defaults_hpc92`) | uniaxial strain -0.05, 250 steps, 1e3 /s |
//! | `batch_rht_tension` | batch | same | uniaxial strain +0.002, 200 steps, 1e3 /s (fails at the hydro tensile limit) |
//! | `umat_rht_compression` | LS-DYNA umat (Fortran, card version 3) | same | uniaxial strain -0.08, 200 steps, 1e4 /s |
//! | `batch_kc_compression` | batch (layout 5) | K&C HPC 100 MPa over the tabulated EoS (`stoss_material_defaults_kc100`) | uniaxial strain -0.03, 250 steps, 1e2 /s |
//! | `batch_kc_tension` | batch | same | uniaxial strain +0.0005, 250 steps, 1e2 /s (past the tensile peak) |
//! | `umat_kc_compression` | LS-DYNA umat (Fortran, card version 5) | same | uniaxial strain -0.03, 200 steps, 1e3 /s |
//!
//! RHT and K&C points start from the material's initial state at 293 K (P-alpha distension
//! `alpha0`), as `stoss_state_init` and the adapters give them.
//!
//! Usage: `cargo run --release -p stoss-kernel-ffi --example reference_histories -- <dir>`

use std::fmt::Write as _;
use std::path::PathBuf;

use stoss_kernel::damage::JohnsonCookFailure;
use stoss_kernel::drivers::{
    simple_shear, uniaxial_strain, DriverError, HistorySink, Record, SimpleShearLoading,
    UniaxialStrainLoading,
};
use stoss_kernel::eos::MieGruneisen;
use stoss_kernel::kc::KcMaterial;
use stoss_kernel::rht::RhtMaterial;
use stoss_kernel::strength::{JohnsonCook, RateTerm, TwoRateJohnsonCook, ZerilliArmstrong};
use stoss_kernel::{Material, MaterialState, PointModel, RateTreatment};

/// Collects the hex lines of a driver run.
#[derive(Default)]
struct HexLines(String);

impl HistorySink for HexLines {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        let values = [
            record.time,
            record.strain[0],
            record.strain[1],
            record.strain[2],
            record.strain[3],
            record.strain[4],
            record.strain[5],
            record.stress[0],
            record.stress[1],
            record.stress[2],
            record.stress[3],
            record.stress[4],
            record.stress[5],
            record.plastic_strain,
            record.plastic_strain_rate,
            record.temperature,
            record.damage,
            record.internal_energy,
            record.wave_speed,
            f64::from(record.flags),
        ];
        let line: Vec<String> = values
            .iter()
            .map(|v| format!("{:016x}", v.to_bits()))
            .collect();
        writeln!(self.0, "{}", line.join(" ")).expect("write to String");
        Ok(())
    }
}

fn jc_with_failure() -> Material {
    let mut material = Material::STEEL_4340;
    material.failure.johnson_cook = Some(JohnsonCookFailure::STEEL_4340);
    material
}

/// Illustrative Mie-Grüneisen constants for a steel (test data, not a published set).
fn jc_mie_gruneisen_lagged() -> Material {
    let mut material = Material::STEEL_4340;
    material.eos = MieGruneisen {
        reference_density: 7830.0,
        sound_speed: 4570.0,
        s1: 1.49,
        s2: 0.0,
        s3: 0.0,
        gamma0: 1.93,
        volume_correction: 0.5,
    }
    .into();
    material.rate_treatment = RateTreatment::Lagged;
    material
}

/// Zerilli & Armstrong (1987) Armco-iron activation/hardening constants with a 65 MPa
/// athermal stress (as in the kernel's benchmarks); elasticity etc. of 4340.
fn za_bcc() -> Material {
    Material::STEEL_4340.with_strength(ZerilliArmstrong::ARMCO_IRON)
}

/// Illustrative TJC constants (test data) with JC 4340 failure.
fn tjc_with_failure() -> Material {
    let mut material = Material::STEEL_4340.with_strength(TwoRateJohnsonCook {
        yield_stress: 792.0e6,
        hardening_modulus: 510.0e6,
        hardening_exponent: 0.26,
        saturation_stress_1: 100.0e6,
        saturation_rate_1: 20.0,
        saturation_stress_2: 50.0e6,
        saturation_rate_2: 200.0,
        rate_exponent_1: 0.01,
        reference_rate_1: 0.01,
        rate_exponent_2: 0.05,
        reference_rate_2: 1000.0,
        thermal_exponent: 1.03,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    });
    material.failure.johnson_cook = Some(JohnsonCookFailure::STEEL_4340);
    material
}

/// JC 4340 written as composed terms with the diagnosis' high-rate upturn
/// `(1 + C ln e*) (1 + rate/e_up)^beta`, beta 0.08, e_up 2000 /s (test constants).
fn jc_upturn() -> Material {
    let mut composed = JohnsonCook::STEEL_4340.composed();
    composed.rate = RateTerm::LogUpturn {
        rate_sensitivity: 0.014,
        reference_rate: 1.0,
        upturn_exponent: 0.08,
        upturn_rate: 2.0e3,
    };
    Material::STEEL_4340.with_strength(composed)
}

fn strain_case(material: &Material, final_strain: f64, steps: u32, strain_rate: f64) -> String {
    strain_case_from(
        material,
        MaterialState::initial(298.0),
        final_strain,
        steps,
        strain_rate,
    )
}

fn rht_case(final_strain: f64, steps: u32, strain_rate: f64) -> String {
    let material = RhtMaterial::HPC_92MPA;
    let state = material.initial_state(293.0);
    strain_case_from(&material, state, final_strain, steps, strain_rate)
}

fn kc_case(final_strain: f64, steps: u32, strain_rate: f64) -> String {
    let material = KcMaterial::HPC_100MPA_FOI;
    let state = material.initial_state(293.0);
    strain_case_from(&material, state, final_strain, steps, strain_rate)
}

fn strain_case_from(
    material: &impl PointModel,
    mut state: MaterialState,
    final_strain: f64,
    steps: u32,
    strain_rate: f64,
) -> String {
    let mut lines = HexLines::default();
    let loading = UniaxialStrainLoading {
        strain_rate,
        final_strain,
        steps,
    };
    uniaxial_strain(material, &mut state, &loading, &mut lines).expect("driver run");
    lines.0
}

fn shear_case(material: &Material, final_shear_strain: f64, steps: u32, shear_rate: f64) -> String {
    let mut state = MaterialState::initial(298.0);
    let mut lines = HexLines::default();
    let loading = SimpleShearLoading {
        shear_rate,
        final_shear_strain,
        steps,
    };
    simple_shear(material, &mut state, &loading, &mut lines).expect("driver run");
    lines.0
}

fn main() {
    let directory = PathBuf::from(
        std::env::args()
            .nth(1)
            .expect("usage: reference_histories <output directory>"),
    );
    std::fs::create_dir_all(&directory).expect("create output directory");
    let cases = [
        (
            "batch_jc_tension",
            strain_case(&jc_with_failure(), 0.3, 300, 1.0e4),
        ),
        (
            "batch_jc_compression",
            strain_case(&jc_with_failure(), -0.3, 300, 1.0e4),
        ),
        (
            "batch_mg_lagged",
            strain_case(&jc_mie_gruneisen_lagged(), -0.2, 400, 1.0e5),
        ),
        (
            "vumat_za_compression",
            strain_case(&za_bcc(), -0.2, 200, 1.0e3),
        ),
        ("vumat_za_tension", strain_case(&za_bcc(), 0.2, 200, 1.0e3)),
        (
            "umat_tjc_tension",
            strain_case(&tjc_with_failure(), 0.25, 250, 1.0e4),
        ),
        (
            "umat_jc_simple_shear",
            shear_case(&Material::STEEL_4340, 0.3, 300, 1.0e3),
        ),
        (
            "batch_jc_upturn_tension",
            strain_case(&jc_upturn(), 0.3, 300, 1.0e4),
        ),
        (
            "umat_jc_upturn_tension",
            strain_case(&jc_upturn(), 0.25, 250, 1.0e4),
        ),
        ("batch_rht_compression", rht_case(-0.05, 250, 1.0e3)),
        ("batch_rht_tension", rht_case(0.002, 200, 1.0e3)),
        ("umat_rht_compression", rht_case(-0.08, 200, 1.0e4)),
        ("batch_kc_compression", kc_case(-0.03, 250, 1.0e2)),
        ("batch_kc_tension", kc_case(0.0005, 250, 1.0e2)),
        ("umat_kc_compression", kc_case(-0.03, 200, 1.0e3)),
    ];
    for (name, text) in cases {
        let path = directory.join(format!("{name}.hex"));
        std::fs::write(&path, text).expect("write history");
        println!("wrote {}", path.display());
    }
}
