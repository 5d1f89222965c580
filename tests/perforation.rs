//! Concrete perforation (seed 001 sec. 4) and RHT concrete in the explicit solver: the
//! solver passes the kernel's state through unchanged, a coarse perforation run perforates with
//! a closed energy balance and thread-independent results, the bundled 10 mm model exits as the
//! tests and as FOI's Autodyn run with the same constants, and bad input names file, line and
//! field.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use stoss::experiment::{Experiment, Setup};
use stoss::input::material;
use stoss::mesh::{Grading, QuadMesh};
use stoss::solver::{Amplitude, BulkViscosity, ExplicitModel, SolverSettings, VelocityConstraint};
use stoss_kernel::drivers::{uniaxial_strain, UniaxialStrainLoading};
use stoss_kernel::rht::{self, RhtMaterial, RhtParameters};
use stoss_kernel::tensor::Matrix6;
use stoss_kernel::{
    MaterialState, ParameterError, PartMaterial, PointModel, StateFlags, StepInput, StepOutput,
    UpdateError,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
}

/// RHT concrete that records every update the solver asks of it: the state it was given,
/// the input and the state it returned.
struct Recorder {
    material: RhtMaterial,
    calls: Mutex<Vec<(MaterialState, StepInput, MaterialState)>>,
}

impl PointModel for Recorder {
    fn validate(&self) -> Result<(), ParameterError> {
        self.material.validate()
    }
    fn shear_modulus(&self) -> f64 {
        PointModel::shear_modulus(&self.material)
    }
    fn density(&self) -> f64 {
        self.material.density
    }
    fn initial_state(&self, temperature: f64) -> MaterialState {
        self.material.initial_state(temperature)
    }
    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        let before = *state;
        let output = rht::update(&self.material, state, input)?;
        self.calls.lock().unwrap().push((before, *input, *state));
        Ok(output)
    }
    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        rht::update_with_tangent(&self.material, state, input, tangent)
    }
}

#[test]
fn rht_through_the_solver_is_the_kernel_update_bit_for_bit() {
    // GOAL: the solver's element loop calls the RHT update with the strains it computes and
    //       keeps the kernel's state unchanged between steps (no host-side edits), so an RHT
    //       element in the solver is the kernel, bit for bit; and the element follows the
    //       kernel's own uniaxial-strain driver.
    // SETUP: one axisymmetric element of table 4.4 concrete (10 x 10 mm, r in [10, 20] mm),
    //        radial velocity held at 0, the top pressed down at 2 m/s (200 /s, no spin) to 2 %
    //        compressive strain: elastic, then the cap and pore crush of the P-alpha EoS.
    // REFERENCE: (a) each recorded call replayed through stoss_kernel::rht::update gives the
    //   recorded state exactly (to_bits), and each call starts from the previous call's state
    //   exactly (the first call's reference state aside, which is the zero-strain probe of
    //   the first time step); (b) the solver's final axial stress and distension equal those
    //   of the kernel's uniaxial_strain driver at the same strain within 1e-3 relative
    //   (measured 1.1e-4 for the stress): the driver takes its own equal logarithmic
    //   increments, the solver those of its mid-step geometry (v dt / h_mid), so the
    //   path-dependent pore crush differs by that much.
    let material = RhtMaterial::HPC_92MPA;
    let recorder = Recorder {
        material,
        calls: Mutex::new(Vec::new()),
    };
    let height = 10.0e-3;
    let mesh = QuadMesh::block(
        "cube",
        0,
        (10.0e-3, 20.0e-3),
        (0.0, height),
        1,
        1,
        Grading::UNIFORM,
        Grading::UNIFORM,
    );
    let all: Vec<usize> = (0..mesh.nodes.len()).collect();
    let bottom = mesh.node_set("cube.bottom").unwrap().to_vec();
    let top = mesh.node_set("cube.top").unwrap().to_vec();
    let speed = 2.0;
    let end_time = 0.02 * height / speed;
    let model = ExplicitModel {
        mesh,
        materials: vec![recorder],
        initial_temperature: 293.0,
        initial_velocity: Vec::new(),
        constraints: vec![
            VelocityConstraint {
                nodes: all,
                dof: 0,
                velocity: Amplitude::constant(0.0),
            },
            VelocityConstraint {
                nodes: bottom,
                dof: 1,
                velocity: Amplitude::constant(0.0),
            },
            VelocityConstraint {
                nodes: top,
                dof: 1,
                velocity: Amplitude::constant(-speed),
            },
        ],
        walls: Vec::new(),
        contacts: Vec::new(),
        eroding_contact: None,
        rigid_parts: Vec::new(),
        pressure_loads: Vec::new(),
        body_acceleration: None,
        trusses: Vec::new(),
        node_contacts: Vec::new(),
        settings: SolverSettings {
            end_time,
            bulk_viscosity: BulkViscosity {
                quadratic: 0.0,
                linear: 0.0,
            },
            hourglass_coefficient: 0.0,
            output_interval: end_time,
            threads: Some(1),
            ..SolverSettings::default()
        },
        tracked_elements: vec![0],
    };
    let run = model.run(&mut |_, _| {}).unwrap();
    let calls = model.materials[0].calls.lock().unwrap();
    assert!(calls.len() > 50, "{} calls", calls.len());
    let bits = |s: &MaterialState| {
        let mut v: Vec<u64> = s.stress.iter().map(|x| x.to_bits()).collect();
        v.extend(
            [
                s.plastic_strain,
                s.damage,
                s.relative_volume,
                s.internal_energy,
                s.eos_history,
            ]
            .map(f64::to_bits),
        );
        v
    };
    // The first call is the solver's zero-strain probe for the first time step.
    for (k, (before, input, after)) in calls.iter().enumerate() {
        let mut replay = *before;
        rht::update(&material, &mut replay, input).unwrap();
        assert_eq!(bits(&replay), bits(after), "call {k}");
        if k >= 2 {
            assert_eq!(
                bits(before),
                bits(&calls[k - 1].2),
                "state handed on at call {k}"
            );
        }
    }
    let last = calls.last().unwrap().2;
    assert_eq!(bits(&last), bits(&run.states[0]));
    assert!(last.flags.contains(StateFlags::PLASTIC) || last.plastic_strain > 0.0);
    assert!(
        last.eos_history < material.eos.initial_history(),
        "the pores crushed"
    );
    // The kernel's own driver to the same logarithmic strain.
    let strain = libm::log(last.relative_volume);
    let steps = calls.len() as u32 - 1;
    let mut state = material.initial_state(293.0);
    let mut sink = stoss_kernel::drivers::LastRecord::default();
    uniaxial_strain(
        &material,
        &mut state,
        &UniaxialStrainLoading {
            strain_rate: speed / height,
            final_strain: strain,
            steps,
        },
        &mut sink,
    )
    .unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b.abs().max(1.0);
    // The driver loads along x, the solver's element along z.
    assert!(
        close(last.stress[1], state.stress[0]),
        "{} {}",
        last.stress[1],
        state.stress[0]
    );
    assert!(close(last.eos_history, state.eos_history));
}

/// The bundled perforation experiment on a coarse mesh: 30 mm concrete, 30 mm projectile.
fn coarse_perforation() -> (Experiment, PartMaterial) {
    let mut experiment =
        Experiment::load(&fixture("experiments/perforation-concrete-152mm.toml")).unwrap();
    let (_, target) = material::load_part(&experiment.default_material_path().unwrap()).unwrap();
    let Setup::Perforation(spec) = &mut experiment.file.setup else {
        panic!("not a perforation experiment");
    };
    spec.element_size = 30.0e-3;
    spec.projectile_element_size = 30.0e-3;
    spec.fine_radius = Some(0.3);
    spec.grading_ratio = 1.2;
    experiment.recording.truncate(1);
    (experiment, target)
}

#[test]
fn a_coarse_perforation_perforates_with_a_closed_energy_balance_and_thread_independent() {
    // GOAL: the perforation kind end to end: the ogive projectile leaves the slab, the energy
    //       balance closes with erosion booked, and the exit velocity does not depend on the
    //       thread count. (The eroded concrete's mass is kept on its nodes by default; that is
    //       checked here only through the balance, which books their kinetic energy: a mass
    //       deleted while moving would open it.)
    // SETUP: the bundled experiment (table 4.5 RHT, elastic steel projectile 46.2 kg at
    //        455.5 m/s, 0.75 m slab) on a coarse 30 mm mesh; 1 and 2 solver threads.
    // REFERENCE: perforation (0 < V_exit < V_i: NDRC's ballistic limit for this slab, 403
    //   m/s, lies below the impact velocity, and the test perforated); |energy error| <= 3 %
    //   (the bound; the seed's Lagrange runs reached 8.6 %); 1 vs 2 threads
    //   bit-identical; the projectile's meshed mass 46.2 kg within 0.5 %.
    let (experiment, target) = coarse_perforation();
    let run = |threads: usize| {
        experiment
            .simulate(
                &target,
                &SolverSettings {
                    threads: Some(threads),
                    ..SolverSettings::default()
                },
            )
            .unwrap()
    };
    let one = run(1);
    let exit = one.predicted[0];
    let impact = experiment.recording[0].position;
    assert!(exit > 0.0 && exit < impact, "exit {exit} m/s");
    let energy = one.energy.unwrap();
    assert!(energy.error_percent().abs() <= 3.0, "{}", energy.report());
    assert!(
        energy.eroded > 0.0,
        "no erosion booked: {}",
        energy.report()
    );
    let two = run(2);
    assert_eq!(exit.to_bits(), two.predicted[0].to_bits());
    let mass = one.summary_value("projectile_mass").unwrap();
    assert!((mass / 46.2 - 1.0).abs() < 0.005, "{mass} kg");
    let diameter = one.summary_value("rear_damage_diameter").unwrap();
    assert!(diameter > 0.0 && diameter <= 2.4, "{diameter} m");
    let report = one.report.unwrap().text;
    assert!(
        report.contains("NDRC") && report.contains("Forrestal"),
        "{report}"
    );
}

/// The exit velocity of one shot of the bundled 10 mm model at the tests' mean impact velocity
/// (458.1 m/s), with the slab's constants changed by `edit`; 2 solver threads.
fn ten_mm_exit(edit: impl Fn(&mut RhtParameters)) -> f64 {
    let experiment =
        Experiment::load(&fixture("experiments/perforation-concrete-152mm.toml")).unwrap();
    let (_, slab) = material::load_part(&experiment.default_material_path().unwrap()).unwrap();
    let Setup::Perforation(spec) = &experiment.file.setup else {
        panic!("not a perforation experiment");
    };
    let mut concrete = *slab.rht().unwrap();
    edit(&mut concrete.parameters);
    let settings = SolverSettings {
        threads: Some(2),
        ..SolverSettings::default()
    };
    spec.fire(&PartMaterial::from(concrete), 458.1, &settings)
        .unwrap()
        .residual_velocity
}

#[test]
#[ignore = "heavy validation, about 2 minutes in release: cargo test --release --test perforation -- --ignored"]
fn the_seeds_lagrange_model_exits_as_the_tests_and_as_fois_run_with_the_same_constants() {
    // GOAL: seed 001's Lagrange perforation model, rebuilt, reproduces the tests and, with the
    //       constants of one of FOI's own Autodyn runs, that run's exit velocity.
    // SETUP: the bundled experiment at 10 mm: table 4.4 with table 4.5's Lagrange values
    //        (B 1.60, M 0.61, D1 0.08, EFMIN 0.05), the tensile limit as a pressure cut-off,
    //        Autodyn's bulk viscosity (linear 0.2, quadratic 1.0), elastic projectile, one shot
    //        at the tests' mean 458.1 m/s; then the same with FOI's run B99008's damage
    //        constants (D1 0.04, EFMIN 0.01).
    // REFERENCE: tests 23-25, 190 +/- 14 m/s: within +/-25 % (twice the measured +13 %,
    //   docs/solver.md) and within the seed's own simulated spread 186-269 m/s; B99008 (seed
    //   table 4.6, Autodyn 2D 4.2.00v, 10 mm Lagrange): 247 m/s, within 15 %.
    let lagrange = ten_mm_exit(|_| {});
    assert!(
        (190.0 * 0.75..=190.0 * 1.25).contains(&lagrange) && (186.0..=269.0).contains(&lagrange),
        "table 4.5 constants: exit {lagrange:.1} m/s against 190 +/- 25 % and 186-269"
    );
    let b99008 = ten_mm_exit(|p| {
        p.damage_d1 = 0.04;
        p.minimum_failure_strain = 0.01;
    });
    assert!(
        (b99008 / 247.0 - 1.0).abs() <= 0.15,
        "B99008: exit {b99008:.1} m/s against FOI's 247"
    );
}

fn stoss() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stoss"))
}

fn write_variant(folder: &Path, file: &str, from: &str, to: &str) -> PathBuf {
    std::fs::create_dir_all(folder).unwrap();
    let text = std::fs::read_to_string(fixture(file)).unwrap();
    assert!(text.contains(from), "{from}");
    let text = text
        .replace(from, to)
        .replace(
            "\"../materials/",
            &format!("\"{}/", fixture("materials").display()),
        )
        .replace(
            "\"perforation-concrete-152mm.csv\"",
            &format!(
                "\"{}\"",
                fixture("experiments/perforation-concrete-152mm.csv").display()
            ),
        )
        .replace(
            "\"taylor-4340-208.csv\"",
            &format!(
                "\"{}\"",
                fixture("experiments/taylor-4340-208.csv").display()
            ),
        );
    let path = folder.join(Path::new(file).file_name().unwrap());
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn bad_perforation_input_names_the_file_line_and_field() {
    // GOAL: a concrete material given to a J2-only experiment, a metal given as the slab of a
    //       perforation test, RHT constants that fail validation, and a projectile placed
    //       inside the slab at set-up each stop with an error naming the file, the line and
    //       the field, and a non-zero exit, before any simulation.
    // SETUP: `stoss simulate` on the Taylor fixture with the RHT file; on the perforation
    //        fixture with the 4340 file; on the perforation fixture with a negative
    //        compressive strength; the perforation fixture with a negative gap, and with a
    //        negative linear bulk viscosity.
    // REFERENCE: the messages below.
    let scratch = std::env::temp_dir().join(format!("stoss-perforation-{}", std::process::id()));
    let concrete = fixture("materials/hpc-92-rht.toml");
    let taylor = fixture("experiments/taylor-4340-208.toml");
    let output = stoss()
        .args(["simulate", taylor.to_str().unwrap(), "--material"])
        .arg(&concrete)
        .arg("--output")
        .arg(scratch.join("out-a"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("hpc-92-rht.toml:") && stderr.contains("field `model`"),
        "{stderr}"
    );
    assert!(
        stderr.contains("needs a J2 metal material, not RHT concrete"),
        "{stderr}"
    );
    assert!(!scratch.join("out-a").exists());

    let perforation = fixture("experiments/perforation-concrete-152mm.toml");
    let output = stoss()
        .args(["simulate", perforation.to_str().unwrap(), "--material"])
        .arg(fixture("materials/4340-jc.toml"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("4340-jc.toml") && stderr.contains("needs an RHT concrete material"),
        "{stderr}"
    );

    let bad = write_variant(
        &scratch.join("rht"),
        "materials/hpc-92-rht.toml",
        "compressive_strength = 92.0e6",
        "compressive_strength = -92.0e6",
    );
    let output = stoss()
        .args(["simulate", perforation.to_str().unwrap(), "--material"])
        .arg(&bad)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    let line = std::fs::read_to_string(&bad)
        .unwrap()
        .lines()
        .position(|l| l.starts_with("compressive_strength"))
        .unwrap()
        + 1;
    assert!(
        stderr.contains(&format!(
            "hpc-92-rht.toml:{line}: field `compressive_strength`"
        )),
        "{stderr}"
    );

    let inside = write_variant(
        &scratch.join("gap"),
        "experiments/perforation-concrete-152mm.toml",
        "gap = 1.0e-3",
        "gap = -5.0e-3",
    );
    let error = Experiment::load(&inside).unwrap_err().to_string();
    assert!(
        error.contains("perforation-concrete-152mm.toml:") && error.contains("field `gap`"),
        "{error}"
    );

    let viscous = write_variant(
        &scratch.join("viscosity"),
        "experiments/perforation-concrete-152mm.toml",
        "linear = 0.2",
        "linear = -0.2",
    );
    let error = Experiment::load(&viscous).unwrap_err().to_string();
    let line = std::fs::read_to_string(&viscous)
        .unwrap()
        .lines()
        .position(|l| l.starts_with("linear ="))
        .unwrap()
        + 1;
    assert!(
        error.contains(&format!(
            "perforation-concrete-152mm.toml:{line}: field `bulk_viscosity.linear`"
        )),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn runaway_sizes_are_refused_before_anything_runs() {
    // GOAL: the sizes a perforation or flow-curve run takes from its input are bounded up
    //       front: the thread count (checked before any pool is built), the number of shots
    //       a recording asks for, and the plastic strain a flow curve is driven to.
    // SETUP: `stoss simulate` of the perforation fixture with --threads 100000; the fixture
    //        with a recording of 65 impact velocities; a 4340 flow curve whose positions are
    //        in percent (19 instead of 0.19).
    // REFERENCE: each a non-zero exit or a load error naming the field, no output folder.
    let scratch = std::env::temp_dir().join(format!("stoss-runaway-{}", std::process::id()));
    let perforation = fixture("experiments/perforation-concrete-152mm.toml");
    let output = stoss()
        .args([
            "simulate",
            perforation.to_str().unwrap(),
            "--threads",
            "100000",
        ])
        .arg("--output")
        .arg(scratch.join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("threads must be in 1..=256, got 100000"),
        "{stderr}"
    );
    assert!(!scratch.join("out").exists());

    let many = write_variant(
        &scratch.join("many"),
        "experiments/perforation-concrete-152mm.toml",
        "\"perforation-concrete-152mm.csv\"",
        "\"many.csv\"",
    );
    let mut csv = String::from("quantity,position,value,uncertainty\n");
    for k in 0..65 {
        csv.push_str(&format!("residual_velocity,{},190,14\n", 400 + k));
    }
    std::fs::write(many.with_file_name("many.csv"), csv).unwrap();
    let error = Experiment::load(&many).unwrap_err().to_string();
    assert!(
        error.contains("many.csv") && error.contains("65 distinct impact velocities"),
        "{error}"
    );

    let folder = scratch.join("percent");
    std::fs::create_dir_all(&folder).unwrap();
    let flow = fixture("experiments/flow-4340-ly-compression-500s-298K.toml");
    let text = std::fs::read_to_string(&flow).unwrap().replace(
        "\"../materials/",
        &format!("\"{}/", fixture("materials").display()),
    );
    std::fs::write(folder.join("flow.toml"), text).unwrap();
    let recording = std::fs::read_to_string(flow.with_extension("csv")).unwrap();
    let percent: String = recording
        .lines()
        .map(|line| match line.split(',').collect::<Vec<_>>()[..] {
            ["true_stress", position, value, sigma] => {
                let position: f64 = position.parse().unwrap();
                format!("true_stress,{},{value},{sigma}\n", 100.0 * position)
            }
            _ => format!("{line}\n"),
        })
        .collect();
    std::fs::write(
        folder.join("flow-4340-ly-compression-500s-298K.csv"),
        percent,
    )
    .unwrap();
    let error = Experiment::load(&folder.join("flow.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("field `position`") && error.contains("in percent"),
        "{error}"
    );
    // A digitised curve's first strain scattered just below 0 (issue 54): named as such, at
    // its line, not as a percent slip.
    let mut first = true;
    let mut negative_line = 0;
    let scattered: String = recording
        .lines()
        .enumerate()
        .map(
            |(number, line)| match line.split(',').collect::<Vec<_>>()[..] {
                ["true_stress", _, value, sigma] if first => {
                    first = false;
                    negative_line = number + 1;
                    format!("true_stress,-0.000175,{value},{sigma}\n")
                }
                _ => format!("{line}\n"),
            },
        )
        .collect();
    std::fs::write(
        folder.join("flow-4340-ly-compression-500s-298K.csv"),
        scattered,
    )
    .unwrap();
    let error = Experiment::load(&folder.join("flow.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains(&format!(".csv:{negative_line}: field `position`"))
            && error.contains("below 0")
            && !error.contains("in percent"),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(&scratch);
}
