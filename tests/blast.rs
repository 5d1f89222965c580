//! Verification of the blast-load solver (host/src/blast) and the blast-plate experiment:
//! the detonation of a C-4 column
//! against the JWL's Chapman-Jouguet state, Sod's shock tube against the exact Riemann
//! solution, the Sedov point blast against its self-similar solution, and the reflected
//! impulse of a free-air TNT burst against Kingery-Bulmash.

use stoss::blast::euler::{Boundaries, Boundary, Conserved, EulerSolver, Floors, Geometry, Grid};
use stoss::blast::fluid::Fluids;
use stoss_kernel::eos::Jwl;

/// Sod's shock tube along `z` (planar) with `cells` cells, scaled to `p_L = 1e5 Pa`
/// (velocities x sqrt(1e5)); returns the L1 error of the density against the exact solution
/// at unit-problem time 0.2, in units of the unit problem.
fn sod_density_error(cells: usize) -> f64 {
    use stoss::analytic::riemann::{solve, GasState};
    let fluids = Fluids {
        products: Jwl::C4,
        air_gamma: 1.4,
    };
    let grid = Grid {
        cells_r: 1,
        cells_z: cells,
        spacing_r: 1.0 / cells as f64,
        spacing_z: 1.0 / cells as f64,
        geometry: Geometry::Planar,
    };
    let cell = |rho: f64, p: f64| -> Conserved {
        [
            rho,
            0.0,
            0.0,
            rho * fluids.specific_energy(rho, p, 0.0),
            0.0,
        ]
    };
    let initial = (0..cells)
        .map(|j| {
            if grid.centre(0, j).1 < 0.5 {
                cell(1.0, 1e5)
            } else {
                cell(0.125, 1e4)
            }
        })
        .collect();
    let tube = Boundaries {
        inner: Boundary::Reflective,
        outer: Boundary::Reflective,
        bottom: Boundary::Transmissive,
        top: Boundary::Transmissive,
    };
    let floors = Floors {
        density: 1e-9,
        pressure: 1e-6,
    };
    let mut solver = EulerSolver::new(
        grid,
        tube,
        fluids,
        initial,
        vec![f64::NEG_INFINITY; cells],
        1.0,
        floors,
    )
    .unwrap();
    let scale = 1e5_f64.sqrt();
    let end = 0.2 / scale;
    while solver.time < end {
        solver.step(0.8, end - solver.time).unwrap();
    }
    let exact = solve(
        GasState {
            density: 1.0,
            velocity: 0.0,
            pressure: 1.0,
        },
        GasState {
            density: 0.125,
            velocity: 0.0,
            pressure: 0.1,
        },
        1.4,
    )
    .unwrap();
    (0..cells)
        .map(|j| {
            let x = grid.centre(0, j).1;
            let reference = exact.sample((x - 0.5) / 0.2).density;
            (solver.cells[j][0] - reference).abs() / cells as f64
        })
        .sum()
}

/// GOAL: the scheme converges to the exact solution of Sod's shock tube.
/// SETUP: 100, 200 and 400 cells, Courant 0.8, unit-problem time 0.2.
/// REFERENCE: the exact Riemann solution (`analytic::riemann`, Toro ch. 4). With a shock and
/// a contact a second-order scheme converges at order about 1 in L1. Measured: 5.0e-3, 2.6e-3,
/// 1.4e-3 (orders 0.95, 0.86); asserted: below 2e-3 at 400 cells, order above 0.7.
#[test]
fn sod_converges_to_the_exact_solution() {
    let errors: Vec<f64> = [100, 200, 400]
        .iter()
        .map(|&n| sod_density_error(n))
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("Sod L1 density errors {errors:?}, observed orders {orders:?}");
    assert!(errors[2] < 0.002, "{errors:?}");
    for order in orders {
        assert!(order > 0.7, "{order}");
    }
}

/// GOAL: a planar programmed-burn detonation of C-4 runs at the JWL's detonation velocity
/// and reaches its Chapman-Jouguet pressure.
/// SETUP: a 60 mm column of C-4 on a rigid wall at z = 0, detonated at the wall, 30 mm of air
/// above; 0.1 mm cells, burn width 2 cells. Front arrival (p > P_CJ/2) and peak pressure
/// recorded in every cell; D from a least-squares line through the arrivals over 20-55 mm,
/// P from the mean peak over the same cells.
/// REFERENCE: the CJ state of the kernel's `Jwl::C4`, `Jwl::chapman_jouguet` (P_CJ 28.0 GPa,
/// D 8193 m/s; Dobratz & Crawford 1985). Tolerances: D 1 %, P 5 % (programmed burn has no
/// von Neumann spike; the peak of a smeared front sits a little below P_CJ).
#[test]
fn c4_detonation_reaches_the_chapman_jouguet_state() {
    let jwl = Jwl::C4;
    let cj = jwl.chapman_jouguet();
    let fluids = Fluids {
        products: jwl,
        air_gamma: 1.4,
    };
    let cell = 1.0e-4;
    let column = 0.06;
    let cells_z = ((column + 0.03) / cell) as usize;
    let grid = Grid {
        cells_r: 1,
        cells_z,
        spacing_r: cell,
        spacing_z: cell,
        geometry: Geometry::Planar,
    };
    let air_energy = fluids.specific_energy(1.225, 101_325.0, 0.0);
    let mut cells: Vec<Conserved> = Vec::new();
    let mut burn = Vec::new();
    for j in 0..cells_z {
        let z = grid.centre(0, j).1;
        if z < column {
            cells.push([
                jwl.reference_density,
                0.0,
                0.0,
                jwl.detonation_energy,
                jwl.reference_density,
            ]);
            burn.push(z / jwl.detonation_velocity);
        } else {
            cells.push([1.225, 0.0, 0.0, 1.225 * air_energy, 0.0]);
            burn.push(f64::NEG_INFINITY);
        }
    }
    let walls = Boundaries {
        inner: Boundary::Reflective,
        outer: Boundary::Reflective,
        bottom: Boundary::Reflective,
        top: Boundary::Transmissive,
    };
    let floors = Floors {
        density: 1e-4,
        pressure: 10.0,
    };
    let mut solver = EulerSolver::new(
        grid,
        walls,
        fluids,
        cells,
        burn,
        2.0 * cell / jwl.detonation_velocity,
        floors,
    )
    .unwrap();
    let mut arrival = vec![f64::NAN; cells_z];
    let mut peak = vec![0.0_f64; cells_z];
    let end = column / jwl.detonation_velocity;
    while solver.time < end {
        solver.step(0.6, end - solver.time).unwrap();
        for j in 0..cells_z {
            let (w, _) = solver.cell_state(j);
            peak[j] = peak[j].max(w[3]);
            if arrival[j].is_nan() && w[3] > 0.5 * cj.pressure {
                arrival[j] = solver.time;
            }
        }
    }
    let window: Vec<usize> = (0..cells_z)
        .filter(|&j| {
            let z = grid.centre(0, j).1;
            (0.02..0.055).contains(&z)
        })
        .collect();
    let n = window.len() as f64;
    let (mut sz, mut st, mut szz, mut szt) = (0.0, 0.0, 0.0, 0.0);
    for &j in &window {
        let z = grid.centre(0, j).1;
        let t = arrival[j];
        sz += z;
        st += t;
        szz += z * z;
        szt += z * t;
    }
    let slowness = (n * szt - sz * st) / (n * szz - sz * sz);
    let speed = 1.0 / slowness;
    let mean_peak = window.iter().map(|&j| peak[j]).sum::<f64>() / n;
    println!(
        "C-4 column: D {speed:.1} m/s (CJ {:.1}), peak {:.3} GPa (CJ {:.3})",
        cj.detonation_velocity,
        mean_peak / 1e9,
        cj.pressure / 1e9
    );
    assert!((speed / cj.detonation_velocity - 1.0).abs() < 0.01);
    assert!((mean_peak / cj.pressure - 1.0).abs() < 0.05);
}

mod plate_support {
    pub use stoss::blast::near_field::{
        Air, Charge, ChargeShape, Detonation, EulerSettings, Explosive,
    };
    use stoss::experiment::blast_plate::Coupling;
    use stoss::experiment::BlastPlateSpec;
    use stoss_kernel::Material;

    pub fn steel() -> Material {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../fixtures/materials/synthetic-hha-truth.toml"
        );
        stoss::input::material::load(std::path::Path::new(path))
            .unwrap()
            .1
    }

    /// A 5 g C-4 sphere 10 mm above a 2 mm plate of radius 50 mm: small enough for CI.
    pub fn small_plate(cache_folder: &std::path::Path) -> BlastPlateSpec {
        BlastPlateSpec {
            thickness: 2.0e-3,
            exposed_radius: 0.05,
            layers: 4,
            aspect_ratio: 1.0,
            temperature: 298.0,
            charge: Charge {
                mass: 0.005,
                explosive: Explosive::C4,
                shape: ChargeShape::Sphere,
                diameter: None,
                standoff: 0.01,
                detonation: Detonation::Centre,
            },
            air: Air::default(),
            euler: EulerSettings {
                cell_size: 1.5e-3,
                headroom: 0.02,
                end_time: 6.0e-5,
                output_interval: 5.0e-7,
                ..EulerSettings::default()
            },
            coupling: Coupling::OneWay,
            impulse_scale: 1.0,
            damping_start: 2.0e-4,
            damping_after_yielding: false,
            damping_coefficient: None,
            end_time: Some(1.5e-3),
            steady_tolerance: Some(1.0e-5),
            springback: true,
            springback_quiet: None,
            load_cache: None,
            cache_folder: Some(cache_folder.to_path_buf()),
        }
    }

    pub fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("stoss-blast-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }
}

mod plate {
    use super::plate_support::*;
    use stoss::blast::cache::{self, Source};
    use stoss::blast::near_field::NearFieldBlast;
    use stoss::mesh::{Grading, QuadMesh};
    use stoss::solver::{shared, AxisymmetricModel, PressureHistory, PressureLoad, SolverSettings};

    /// GOAL: a plate whose default end, fixed by its material, would run away is refused
    /// before anything is computed, with an error that says why and what to change (the check
    /// at load assumed a metal's plate wave speed).
    /// SETUP: the small plate without `end_time`, its steel a million times as dense (plate
    /// wave speed about 5 m/s: a fundamental period of seconds).
    /// REFERENCE: an error naming `end_time` and the plate wave speed; no blast load computed
    /// (the cache folder is never created); with `end_time` set the same plate is accepted.
    #[test]
    fn a_plate_whose_material_makes_the_run_too_long_is_refused_before_it_runs() {
        let folder = scratch("slow-plate");
        let mut spec = small_plate(&folder);
        spec.end_time = None;
        let mut slow = steel();
        slow.density *= 1.0e6;
        let error = match spec.run(&slow, &SolverSettings::default()) {
            Err(error) => error.to_string(),
            Ok(_) => panic!("a run of seconds was not refused"),
        };
        println!("{error}");
        assert!(
            error.contains("`end_time`") && error.contains("plate wave speed"),
            "{error}"
        );
        assert!(!folder.exists(), "the load was computed before the refusal");
        spec.end_time = Some(3.0e-4);
        assert!(spec.run(&slow, &SolverSettings::default()).is_ok());
        let _ = std::fs::remove_dir_all(&folder);
    }

    /// GOAL: a pressure load delivers the impulse its history integrates to.
    /// SETUP: a free elastic disc (radius 10 mm, 2 mm thick, 2 x 20 elements), a uniform
    /// 10 MPa on its top face for 2 us, no constraints; momentum read at 10 us.
    /// REFERENCE: Newton: `P_z = -p pi R^2 t` (the disc is free); energy balance closes.
    #[test]
    fn a_uniform_pressure_gives_its_impulse() {
        let radius = 0.01;
        let mesh = QuadMesh::block(
            "disc",
            0,
            (0.0, radius),
            (-2.0e-3, 0.0),
            20,
            2,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let top = mesh.node_set("disc.top").unwrap().to_vec();
        let segments = top.windows(2).map(|w| [w[1], w[0]]).collect();
        let history = PressureHistory {
            radii: vec![0.0, radius],
            interval: 1.0e-6,
            values: vec![vec![1.0e7, 1.0e7], vec![1.0e7, 1.0e7]],
        };
        let model = AxisymmetricModel {
            mesh,
            materials: vec![steel()],
            initial_temperature: 298.0,
            initial_velocity: Vec::new(),
            constraints: Vec::new(),
            walls: Vec::new(),
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: vec![PressureLoad {
                segments,
                history: shared(history),
                scale: 1.0,
            }],
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time: 1.0e-5,
                ..SolverSettings::default()
            },
            tracked_elements: Vec::new(),
        };
        let run = model.run(&mut |_, _| {}).unwrap();
        // Lumped masses per radian: recompute from the element volumes.
        let density = model.materials[0].density;
        let mut mass = vec![0.0; model.mesh.nodes.len()];
        for element in &model.mesh.elements {
            let c: Vec<[f64; 2]> = element.iter().map(|&n| model.mesh.nodes[n]).collect();
            let area = 0.5
                * ((c[2][0] - c[0][0]) * (c[3][1] - c[1][1])
                    - (c[3][0] - c[1][0]) * (c[2][1] - c[0][1]));
            let r = c.iter().map(|p| p[0]).sum::<f64>() / 4.0;
            for &n in element {
                mass[n] += density * area * r / 4.0;
            }
        }
        let momentum: f64 = 2.0
            * std::f64::consts::PI
            * run
                .velocities
                .iter()
                .zip(&mass)
                .map(|(v, m)| v[1] * m)
                .sum::<f64>();
        let expected = -1.0e7 * std::f64::consts::PI * radius * radius * 2.0e-6;
        println!("momentum {momentum:.6e} N s, expected {expected:.6e}");
        assert!((momentum / expected - 1.0).abs() < 1e-4);
        let energy = run.energy();
        assert!(energy.error_percent().abs() < 0.5, "{}", energy.report());
    }

    /// GOAL: the blast-plate experiment reaches a steady shape with its energy balanced, does
    /// not depend on the thread count, and reuses its cached load.
    /// SETUP: `small_plate`; 1 and 2 solver threads; the load computed once into a fresh
    /// folder, then read from memory.
    /// REFERENCE: energy error <= 1 % (seed 000's runs: 0-2 %); bit-identical profiles.
    #[test]
    fn blast_plate_settles_balanced_and_thread_independent() {
        let folder = scratch("plate");
        let spec = small_plate(&folder);
        let first = spec.load().unwrap();
        assert_eq!(first.source, Source::Computed);
        let again = spec.load().unwrap();
        assert_eq!(again.source, Source::Memory);
        assert_eq!(first.wall, again.wall);
        assert!(first.path.exists());
        let material = steel();
        let mut profiles = Vec::new();
        for threads in [1, 2] {
            let settings = SolverSettings {
                threads: Some(threads),
                ..SolverSettings::default()
            };
            let (result, run, _) = spec.run(&material, &settings).unwrap();
            let energy = run.energy();
            println!(
                "{threads} threads: peak {:.3} mm, settled at {:.3} ms (steady {}), {}",
                result.peak() * 1e3,
                result.settled_at * 1e3,
                result.steady,
                energy.report()
            );
            assert!(result.steady);
            assert!(result.peak() > 1.0e-4, "the plate must bulge");
            assert!(energy.error_percent().abs() < 1.0);
            assert!(energy.external_work > 0.0);
            profiles.push(result.profile);
        }
        assert_eq!(profiles[0], profiles[1]);
        let _ = std::fs::remove_dir_all(&folder);
    }

    /// GOAL: the plate's final shape found by the static springback, once the damped plate
    /// has stopped yielding, is the shape its damped ring-down settles to, in a fraction of
    /// the cycles.
    /// SETUP: `small_plate` (damping from 0.2 ms, flat-plate period about 0.5 ms) with the
    /// springback (the default), and without it run to 3 ms with a steady tolerance of 1e-12 m
    /// (the ring-down run out).
    /// REFERENCE: the ring-down's final profile, the same discrete model's equilibrium.
    /// Tolerance: every rear-face deflection within a tenth of the steady tolerance the
    /// experiments use (1e-6 m; measured 0.26 um), the peak within 0.1 um (13 nm), the radii
    /// within 10 um (the hourglass zig-zags the two ways leave differ by 2 um), at most half
    /// the element-cycles (measured: a sixth).
    #[test]
    fn the_springback_gives_the_shape_the_damped_ring_down_settles_to() {
        use stoss::experiment::BlastPlateSpec;
        let folder = scratch("springback");
        let springback = small_plate(&folder);
        let ring_down = BlastPlateSpec {
            springback: false,
            steady_tolerance: Some(1.0e-12),
            end_time: Some(3.0e-3),
            ..springback.clone()
        };
        let material = steel();
        let settings = SolverSettings::default();
        let (quick, quick_run, _) = springback.run(&material, &settings).unwrap();
        let (settled, settled_run, _) = ring_down.run(&material, &settings).unwrap();
        let found = quick.springback.expect("the springback ran");
        println!(
            "springback from {:.3} ms ({} iterations, {:.3} mm): peak {:.6} mm in {} cycles; \
             ring-down to {:.3} ms: peak {:.6} mm in {} cycles",
            found.from * 1e3,
            found.iterations,
            found.displacement * 1e3,
            quick.peak() * 1e3,
            quick_run.element_cycles,
            settled.settled_at * 1e3,
            settled.peak() * 1e3,
            settled_run.element_cycles
        );
        assert!(quick.steady);
        let (radii, deflections) = quick
            .profile
            .iter()
            .zip(&settled.profile)
            .fold((0.0_f64, 0.0_f64), |(r, w), (a, b)| {
                (r.max((a.0 - b.0).abs()), w.max((a.1 - b.1).abs()))
            });
        assert!(
            deflections < 1.0e-6,
            "the deflections differ by {deflections} m"
        );
        assert!(radii < 1.0e-5, "the radii differ by {radii} m");
        assert!((quick.peak() - settled.peak()).abs() < 1.0e-7);
        assert!(quick_run.element_cycles * 2 < settled_run.element_cycles);
        let _ = std::fs::remove_dir_all(&folder);
    }

    /// GOAL: a damping start that waits for the plate to stop yielding starts only once it has,
    /// and the run's measure of yielding under damping tells it from a fixed early start.
    /// SETUP: `small_plate` (flat-plate period about 0.5 ms), to its default latest end; the
    /// damping at 0.2 ms (while the plate still yields in its rebound) and, second, with
    /// `damping_after_yielding`.
    /// REFERENCE: a plate that has shaken down does not yield at all, so after a start that
    /// waited the summed plastic strain grows by no more than the report's warning level
    /// (`YIELDING_UNDER_DAMPING`); the early start's growth is above it.
    #[test]
    fn damping_after_yielding_waits_for_the_plate_to_stop_yielding() {
        use stoss::experiment::blast_plate::YIELDING_UNDER_DAMPING;
        use stoss::experiment::BlastPlateSpec;
        let folder = scratch("after-yielding");
        let fixed = BlastPlateSpec {
            end_time: None,
            ..small_plate(&folder)
        };
        let waiting = BlastPlateSpec {
            damping_after_yielding: true,
            ..fixed.clone()
        };
        let material = steel();
        let settings = SolverSettings::default();
        let (early, _, _) = fixed.run(&material, &settings).unwrap();
        let (late, _, _) = waiting.run(&material, &settings).unwrap();
        for (name, result) in [("fixed", &early), ("after yielding", &late)] {
            println!(
                "{name}: damping from {:.3} ms, plastic growth after it {:.2e}, peak {:.4} mm, \
                 settled at {:.3} ms (steady {})",
                result.damping_from * 1e3,
                result.plastic_after_damping,
                result.peak() * 1e3,
                result.settled_at * 1e3,
                result.steady
            );
            assert!(result.steady, "{name}");
        }
        assert!((early.damping_from - fixed.damping_start).abs() < 1.0e-5);
        assert!(early.plastic_after_damping > YIELDING_UNDER_DAMPING);
        assert!(late.damping_from > fixed.damping_start + fixed.steady_window(&material));
        assert!(late.plastic_after_damping <= YIELDING_UNDER_DAMPING);
        let _ = std::fs::remove_dir_all(&folder);
    }

    /// GOAL: bad blast inputs are refused with the field named, never a silent zero load or
    /// a runaway.
    /// SETUP: a charge overlapping the plate, a negative mass, a grid with fewer than 10 cells
    /// across the charge, a burn front 1e-9 cells wide, a cache folder that cannot be created.
    /// REFERENCE: the bad-input list.
    #[test]
    fn bad_blast_input_is_refused() {
        let folder = scratch("bad");
        let spec = small_plate(&folder);
        let blast = spec.blast();
        let mut overlapping = blast;
        overlapping.charge.standoff = -1.0e-3;
        let error = overlapping.validate(0.0625).unwrap_err().to_string();
        assert!(error.contains("charge.standoff"), "{error}");
        let mut negative = blast;
        negative.charge.mass = -0.005;
        assert!(negative
            .validate(0.0625)
            .unwrap_err()
            .to_string()
            .contains("charge.mass"));
        let mut coarse = blast;
        coarse.euler.cell_size = 3.0e-3;
        let error = coarse.validate(0.0625).unwrap_err().to_string();
        assert!(
            error.contains("euler.cell_size") && error.contains("cells across"),
            "{error}"
        );
        // A burn width slip (cells read as metres the other way) would make the burn's
        // bounded steps a runaway: refused up front, naming the field.
        let mut thin_burn = blast;
        thin_burn.euler.burn_width = 1.0e-9;
        let error = thin_burn.validate(0.0625).unwrap_err().to_string();
        assert!(error.contains("euler.burn_width"), "{error}");
        let sphere_with_diameter = NearFieldBlast {
            charge: Charge {
                diameter: Some(0.02),
                ..blast.charge
            },
            ..blast
        };
        assert!(sphere_with_diameter.validate(0.0625).is_err());
        // A cache "folder" under a regular file cannot be created.
        std::fs::create_dir_all(&folder).unwrap();
        let file = folder.join("not-a-folder");
        std::fs::write(&file, b"x").unwrap();
        let error = cache::load(&blast, 0.0625, &file.join("cache"), &mut |_| {})
            .unwrap_err()
            .to_string();
        assert!(error.contains("blast-load cache"), "{error}");
        let _ = EulerSettings::default();
        let _ = std::fs::remove_dir_all(&folder);
    }
}

/// GOAL: far from the charge, the Euler solver's reflected impulse matches the
/// Kingery-Bulmash fit.
/// SETUP: 1 kg TNT sphere (Jwl::TNT), centre 1.0 m above a rigid wall; 10 mm cells
/// (10.5 across the charge), grid radius 0.25 m, detonated at the centre; the impulse on the
/// wall cell at the axis to 3.5 ms.
/// REFERENCE: UFC 3-340-02 Fig. 2-7 (`blast::kingery_bulmash`): Ir = 559 Pa s at Z = 1
/// (normal reflection). Measured: 529 Pa s (-5.3 %), asserted within 10 % (the 15 %
/// is the bound at 1-3 m; the bench measures 2 and 3 m on a wider grid, -5.2 and -9.6 %: at 2
/// m this narrow grid does not yet give the impulse; docs/solver.md, "Blast load").
#[test]
fn tnt_reflected_impulse_matches_kingery_bulmash() {
    use stoss::blast::kingery_bulmash;
    use stoss::blast::near_field::{
        Air, Charge, ChargeShape, Detonation, EulerSettings, Explosive, NearFieldBlast,
    };
    {
        let centre_height = 1.0;
        let radius = libm::cbrt(3.0 / (4.0 * std::f64::consts::PI * 1630.0));
        let blast = NearFieldBlast {
            charge: Charge {
                mass: 1.0,
                explosive: Explosive::Tnt,
                shape: ChargeShape::Sphere,
                diameter: None,
                standoff: centre_height - radius,
                detonation: Detonation::Centre,
            },
            air: Air::default(),
            euler: EulerSettings {
                cell_size: 0.01,
                radius: 0.25,
                headroom: 0.1,
                end_time: 3.5e-3,
                output_interval: 5.0e-6,
                ..EulerSettings::default()
            },
        };
        let run = blast.solve(0.25, &mut |_| {}).unwrap();
        let impulse = run.wall.impulse(0.0);
        let expected = kingery_bulmash::reflected_impulse(1.0, centre_height).unwrap();
        println!(
            "1 kg TNT at {centre_height} m: Euler {impulse:.1} Pa s, Kingery-Bulmash {expected:.1} \
             ({:+.1} %), {} steps",
            100.0 * (impulse / expected - 1.0),
            run.steps
        );
        assert!((impulse / expected - 1.0).abs() < 0.10);
    }
}

/// GOAL: the axisymmetric scheme propagates a point blast as the Sedov-Taylor solution does.
/// SETUP: ideal gas (gamma 1.4, rho0 1 kg/m^3, p0 1 Pa) in the quarter plane r, z in [0, 1] m,
/// 80 x 80 cells, reflective on all sides (the wall z = 0 mirrors the half-space blast into a
/// full sphere of energy E = 1 MJ); half of E deposited uniformly in the cells within 3.5
/// cells of the origin. Run to the time the exact shock radius is 0.8 m; shock radius read as
/// the position of the largest pressure along the axis, along the wall and along the 45°
/// ray (cell centres).
/// REFERENCE: Sedov (1959); `R(t) = (E t^2/(alpha rho0))^(1/5)` with alpha = 0.851072 for
/// gamma = 1.4, spherical (Kamm & Timmes 2007, LA-UR-07-2849, Table 1). Tolerance: 2 cells
/// (the shock is captured over 2-3 cells). Energy conserved to 1e-9 (closed box, no floors hit).
#[test]
fn sedov_blast_wave_radius() {
    let fluids = Fluids {
        products: Jwl::C4,
        air_gamma: 1.4,
    };
    let n = 80;
    let h = 1.0 / n as f64;
    let grid = Grid {
        cells_r: n,
        cells_z: n,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let energy_total = 1.0e6;
    let alpha = 0.851072;
    let (rho0, p0) = (1.0, 1.0);
    let ambient = rho0 * fluids.specific_energy(rho0, p0, 0.0);
    let source_radius = 3.5 * h;
    let inside = |i: usize, j: usize| {
        let (r, z) = grid.centre(i, j);
        r.hypot(z) < source_radius
    };
    // Per radian: half of E in the half space, divided by 2 pi.
    let source_volume: f64 = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .filter(|&(i, j)| inside(i, j))
        .map(|(i, _)| grid.cell_volume(i))
        .sum();
    let density_of_energy = 0.5 * energy_total / (2.0 * std::f64::consts::PI) / source_volume;
    let mut cells: Vec<Conserved> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let e = if inside(i, j) {
                density_of_energy
            } else {
                ambient
            };
            cells.push([rho0, 0.0, 0.0, e, 0.0]);
        }
    }
    let closed = Boundaries {
        inner: Boundary::Reflective,
        outer: Boundary::Reflective,
        bottom: Boundary::Reflective,
        top: Boundary::Reflective,
    };
    let floors = Floors {
        density: 1e-12,
        pressure: 1e-12,
    };
    let mut solver = EulerSolver::new(
        grid,
        closed,
        fluids,
        cells,
        vec![f64::NEG_INFINITY; n * n],
        1.0,
        floors,
    )
    .unwrap();
    let (_, energy_before) = solver.totals();
    let radius: f64 = 0.8;
    let end = (alpha * rho0 * radius.powi(5) / energy_total).sqrt();
    while solver.time < end {
        solver.step(0.6, end - solver.time).unwrap();
    }
    let (_, energy_after) = solver.totals();
    assert_eq!(solver.floor_count, 0);
    assert!(((energy_after - energy_before) / energy_before).abs() < 1e-9);
    let pressure = |i: usize, j: usize| solver.cell_state(grid.index(i, j)).0[3];
    let peak_along = |cells: &dyn Fn(usize) -> (usize, usize)| -> f64 {
        let (mut best, mut at) = (0.0, 0.0);
        for k in 0..n {
            let (i, j) = cells(k);
            if i >= n || j >= n {
                break;
            }
            let p = pressure(i, j);
            if p > best {
                best = p;
                let (r, z) = grid.centre(i, j);
                at = r.hypot(z);
            }
        }
        at
    };
    let axis = peak_along(&|k| (0, k));
    let wall = peak_along(&|k| (k, 0));
    let diagonal = peak_along(&|k| (k, k));
    println!(
        "Sedov: shock radius {radius} m exact; axis {axis:.4}, wall {wall:.4}, 45 deg {diagonal:.4} \
         ({} steps)",
        solver.steps
    );
    for measured in [axis, wall, diagonal] {
        assert!((measured - radius).abs() < 2.0 * h, "{measured}");
    }
}

mod coupling {
    use super::plate_support::*;
    use stoss::experiment::blast_plate::Coupling;
    use stoss::solver::SolverSettings;

    /// GOAL: two-way coupling relieves the load as the plate moves away, and its run keeps
    /// the energy balance and the thread independence.
    /// SETUP: the small plate of `plate_support`, one-way and two-way, 1 and 2 threads.
    /// REFERENCE: a receding wall reflects a weaker shock (the piston problem), so the two-way
    /// impulse is below the rigid-wall one; energy error <= 1 %; bit-identical profiles.
    #[test]
    fn two_way_coupling_relieves_the_load() {
        let folder = scratch("coupling");
        let mut spec = small_plate(&folder);
        let material = steel();
        let (one_way, _, _) = spec.run(&material, &SolverSettings::default()).unwrap();
        spec.coupling = Coupling::TwoWay;
        let mut profiles = Vec::new();
        for threads in [1, 2] {
            let settings = SolverSettings {
                threads: Some(threads),
                ..SolverSettings::default()
            };
            let (two_way, run, _) = spec.run(&material, &settings).unwrap();
            println!(
                "one-way: impulse {:.4} N s, peak {:.3} mm; two-way: impulse {:.4} N s, peak {:.3} mm, energy error {:+.3} %",
                one_way.load_impulse,
                one_way.peak() * 1e3,
                two_way.load_impulse,
                two_way.peak() * 1e3,
                run.energy().error_percent()
            );
            assert!(two_way.steady);
            assert!(two_way.load_impulse < one_way.load_impulse);
            assert!(two_way.peak() < one_way.peak());
            assert!(run.energy().error_percent().abs() < 1.0);
            profiles.push(two_way.profile);
        }
        assert_eq!(profiles[0], profiles[1]);
        let _ = std::fs::remove_dir_all(&folder);
    }
}

/// GOAL: a blast-plate experiment whose sizes would run away (a plate end time, an Euler end
/// time or a record interval in the wrong unit) is refused before anything runs, with an
/// error naming the file, the line and the field.
/// SETUP: variants of fixtures/experiments/blast-hha-37g-13mm.toml in a scratch folder, each
/// loaded (validated) only.
/// REFERENCE: `experiment.toml:<line>: field `<field>`` in the message (the line of a
/// `[setup.euler]` key found inside its section).
#[test]
fn runaway_blast_plate_sizes_name_the_file_line_and_field() {
    let fixtures = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let original =
        std::fs::read_to_string(fixtures.join("experiments/blast-hha-37g-13mm.toml")).unwrap();
    let scratch = std::env::temp_dir().join(format!("stoss-blast-sizes-{}", std::process::id()));
    let cases = [
        // 3 s of plate response (3 ms meant): 5e7 steps.
        ("layers = 8", "layers = 8\nend_time = 3.0", "end_time"),
        // 0.15 s of Euler flow (1.5e-4 s meant).
        ("end_time = 1.5e-4", "end_time = 0.15", "euler.end_time"),
        // Elements 100x shorter radially than thick (4.0 meant): 1.6e5 x 8 elements.
        ("aspect_ratio = 4.0", "aspect_ratio = 0.04", "aspect_ratio"),
        ("aspect_ratio = 4.0", "aspect_ratio = nan", "aspect_ratio"),
        // A record every 2.5e-13 s: 6e8 records.
        (
            "output_interval = 2.5e-7",
            "output_interval = 2.5e-13",
            "euler.output_interval",
        ),
    ];
    for (k, (from, to, field)) in cases.iter().enumerate() {
        let folder = scratch.join(format!("case-{k}"));
        std::fs::create_dir_all(&folder).unwrap();
        assert!(original.contains(from), "{from}");
        let text = original.replace(from, to).replace(
            "../materials",
            &fixtures.join("materials").display().to_string(),
        );
        std::fs::copy(
            fixtures.join("experiments/blast-hha-37g-13mm.csv"),
            folder.join("blast-hha-37g-13mm.csv"),
        )
        .unwrap();
        let path = folder.join("experiment.toml");
        std::fs::write(&path, text).unwrap();
        let error = stoss::experiment::Experiment::load(&path)
            .unwrap_err()
            .to_string();
        // `experiment.toml:<line>: field `<field>``.
        let line = error
            .split("experiment.toml:")
            .nth(1)
            .and_then(|rest| rest.split(':').next())
            .and_then(|number| number.parse::<usize>().ok());
        assert!(
            line.is_some() && error.contains(&format!("{field}`")),
            "{to}: {error}"
        );
    }
    let _ = std::fs::remove_dir_all(&scratch);
}

/// Reads one of the digitised chart files: `(Z m/kg^(1/3), value)` rows under a header.
fn chart_points(file: &str) -> Vec<(f64, f64)> {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/real/ufc-3-340-02-fig-2-7")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .skip(1)
        .map(|line| {
            let (z, value) = line.split_once(',').unwrap();
            (z.parse().unwrap(), value.parse().unwrap())
        })
        .collect()
}

/// GOAL: the Kingery-Bulmash fits stoss evaluates are UFC 3-340-02's published curves, not
/// only a transcription of the same polynomials: the reflected pressure and impulse agree with
/// the design chart itself over the whole range of the fits.
/// SETUP: every point read off UFC 3-340-02 Figure 2-7 (spherical free-air burst) inside
/// 0.0531-40 m/kg^(1/3): 240 reflected-pressure and 135 reflected-impulse points
/// (`fixtures/real/ufc-3-340-02-fig-2-7/`, WebPlotDigitizer readings by Kochkarov and
/// Martyniuk, MIT), 1 kg TNT so that the scaled impulse is the impulse.
/// REFERENCE: the chart. Measured (2026-11-28): Pr from -0.7 to +3.3 % of the chart (RMS
/// 1.8 %), Ir from -2.2 to +1.9 % (RMS 0.9 %): the width of a chart line read on log-log axes.
/// Asserted: every point within 5 % (Pr) and 3.5 % (Ir), RMS within 2.5 % and 1.5 %. A wrong
/// coefficient (the defective public copies named in the research notes) misses by far more.
#[test]
fn kingery_bulmash_matches_the_ufc_chart() {
    use stoss::blast::kingery_bulmash::{
        reflected_impulse, reflected_pressure, MAXIMUM_SCALED_DISTANCE, MINIMUM_SCALED_DISTANCE,
    };
    let inside = |z: f64| (MINIMUM_SCALED_DISTANCE..=MAXIMUM_SCALED_DISTANCE).contains(&z);
    let check = |name: &str,
                 points: Vec<(f64, f64)>,
                 fit: &dyn Fn(f64) -> f64,
                 largest: f64,
                 rms_bound: f64| {
        let deviations: Vec<(f64, f64)> = points
            .iter()
            .filter(|(z, _)| inside(*z))
            .map(|&(z, chart)| (z, fit(z) / chart - 1.0))
            .collect();
        assert!(
            deviations.len() > 100,
            "{name}: {} points",
            deviations.len()
        );
        let rms =
            (deviations.iter().map(|(_, d)| d * d).sum::<f64>() / deviations.len() as f64).sqrt();
        let (z_worst, worst) = deviations
            .iter()
            .copied()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap();
        println!(
            "{name}: {} chart points, largest deviation {:+.2} % at Z {z_worst}, RMS {:.2} %",
            deviations.len(),
            100.0 * worst,
            100.0 * rms
        );
        assert!(worst.abs() < largest, "{name}: {worst} at Z {z_worst}");
        assert!(rms < rms_bound, "{name}: RMS {rms}");
    };
    // Pa against kPa; Pa s against kPa ms.
    check(
        "reflected pressure",
        chart_points("figure_2_7_wpd_pr.csv"),
        &|z| reflected_pressure(1.0, z).unwrap() / 1.0e3,
        0.05,
        0.025,
    );
    check(
        "reflected impulse",
        chart_points("figure_2_7_wpd_ir.csv"),
        &|z| reflected_impulse(1.0, z).unwrap(),
        0.035,
        0.015,
    );
}
