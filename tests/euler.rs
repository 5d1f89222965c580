//! The multi-material Eulerian solver (host/src/euler): conservation, interface advection,
//! elastic-plastic waves and penetration limits against closed forms. The heavy cases (the
//! seed's shots at 0.2 / 0.1 mm, the strength sweep, the smooth-objective check) are in the
//! `euler` benchmark and docs/euler.md.

use std::path::{Path, PathBuf};
use stoss::analytic::penetration::spherical_cavity_pressure;
use stoss::blast::euler::{Geometry, Grid};
use stoss::euler::{
    CavityDrive, EulerError, EulerMaterial, EulerSettings, EulerSolver, Region, Wall, Walls,
    MAX_MATERIALS, MAX_PHASES,
};
use stoss::input::material;
use stoss_kernel::Material;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
}

/// An elastic-perfectly plastic, rate-independent, isothermal metal with a linear EoS.
fn perfectly_plastic(density: f64, shear: f64, bulk: f64, yield_stress: f64) -> Material {
    let text = format!(
        "name = \"test\"\nsource = \"test\"\ndensity = {density:e}\nshear_modulus = {shear:e}\n\
         specific_heat = 477.0\nrate_treatment = \"implicit\"\n[strength]\n\
         model = \"johnson-cook\"\nyield_stress = {yield_stress:e}\nhardening_modulus = 0.0\n\
         hardening_exponent = 0.5\nrate_sensitivity = 0.0\nthermal_exponent = 1.0\n\
         reference_rate = 1.0\nreference_temperature = 298.0\nmelting_temperature = 1793.0\n\
         [heating]\nkind = \"isothermal\"\n[eos]\nkind = \"linear\"\nbulk_modulus = {bulk:e}\n"
    );
    material::parse(Path::new("test.toml"), &text).unwrap().1
}

fn named(name: &str, model: Material) -> EulerMaterial<Material> {
    EulerMaterial {
        name: name.into(),
        model,
        fracture_pressure: None,
    }
}

const SLIP: Walls = Walls {
    outer: Wall::Slip,
    bottom: Wall::Slip,
    top: Wall::Slip,
};

/// The 40 x 60 axisymmetric grid of 0.5 mm cells the colliding blocks are run on.
fn colliding_grid() -> Grid {
    Grid {
        cells_r: 40,
        cells_z: 60,
        spacing_r: 0.5e-3,
        spacing_z: 0.5e-3,
        geometry: Geometry::Axisymmetric,
    }
}

/// A steel block at rest and a tungsten-like block at 400 m/s onto it, with void around them,
/// in a closed axisymmetric `grid` (cells of at most 1 mm: the blocks span r < 12 mm and
/// 4 mm < z < 24 mm).
fn colliding_blocks(grid: Grid, settings: EulerSettings) -> EulerSolver<Material> {
    let below = |p: [f64; 2]| p[0] < 12e-3 && (4e-3..14e-3).contains(&p[1]);
    let above = |p: [f64; 2]| p[0] < 6e-3 && (14e-3..24e-3).contains(&p[1]);
    let regions = [
        Region {
            material: 0,
            inside: &below,
            velocity: [0.0, 0.0],
            temperature: 293.0,
        },
        Region {
            material: 1,
            inside: &above,
            velocity: [0.0, -400.0],
            temperature: 293.0,
        },
    ];
    EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![
            named("steel", perfectly_plastic(7850.0, 80e9, 160e9, 1e9)),
            named("heavy", perfectly_plastic(17600.0, 145e9, 285e9, 1.5e9)),
        ],
        &regions,
        settings,
    )
    .unwrap()
}

#[test]
fn leaving_the_far_void_out_of_a_cycle_changes_no_bit() {
    // GOAL: the cycle's skip of the void far from all material (`EulerSettings::
    // skip_far_void`) is exact: volumes, masses, states, velocities, time and energy booking
    // the same to the bit as a run that works every cell in every cycle.
    // SETUP: the colliding blocks below on 40 x 60 cells, 10 us: the blocks reach 24 cells
    // from the axis and splash sideways, so the skipped columns move with the material.
    // REFERENCE: the same run with `skip_far_void = false`, at one and two threads.
    let grid = colliding_grid();
    let run = |skip_far_void: bool, threads: usize| {
        let mut solver = colliding_blocks(
            grid,
            EulerSettings {
                threads: Some(threads),
                skip_far_void,
                ..EulerSettings::default()
            },
        );
        solver
            .run(10e-6, 1e-6, &mut |_| std::ops::ControlFlow::Continue(()))
            .unwrap();
        // Debug prints every float so that it reads back to the same bits.
        format!(
            "{:?} {:?} {:?} {:?} {:?} {:?} {:?}",
            solver.volume,
            solver.mass,
            solver.state,
            solver.velocity,
            solver.time,
            solver.cycles,
            solver.energy
        )
    };
    let reference = run(false, 1);
    assert!(
        run(true, 1) == reference,
        "one thread: the skip changed the run"
    );
    assert!(
        run(true, 2) == reference,
        "two threads: the skip changed the run"
    );
}

/// The colliding blocks run for 4 us with `settings`, mass of each material and axial momentum
/// asserted exact to round-off and the energy balanced to 1 %; the solver at the end.
fn collide_conserving(settings: EulerSettings) -> EulerSolver<Material> {
    let mut solver = colliding_blocks(colliding_grid(), settings);
    let masses = [solver.material_mass(0), solver.material_mass(1)];
    let momentum = solver.momentum()[1];
    solver
        .run(4e-6, 1e-6, &mut |_| std::ops::ControlFlow::Continue(()))
        .unwrap();
    for (k, m0) in masses.iter().enumerate() {
        let m = solver.material_mass(k);
        eprintln!("material {k}: relative mass change {:.2e}", (m - m0) / m0);
        assert!(
            (m - m0).abs() <= 1e-13 * m0,
            "material {k}: {m} against {m0}"
        );
    }
    let p = solver.momentum()[1];
    assert!(
        (p - momentum).abs() <= 1e-12 * momentum.abs(),
        "axial momentum {p:e} against {momentum:e}"
    );
    let error = solver.energy.relative_error();
    eprintln!(
        "axial momentum change {:.2e} (relative), energy error {error:.2e}",
        (p - momentum) / momentum
    );
    assert!(error.abs() < 0.01, "energy error {error}");
    solver
}

#[test]
fn a_closed_grid_conserves_mass_and_axial_momentum_to_round_off_and_books_its_energy() {
    // GOAL: two blocks colliding inside a closed axisymmetric grid, with void around them:
    // mass of each material and axial momentum exact to round-off, energy balanced.
    // SETUP: a steel block at rest, a tungsten-like block at 400 m/s onto it, 40 x 60 cells.
    let solver = collide_conserving(EulerSettings {
        threads: Some(2),
        ..EulerSettings::default()
    });
    assert!(solver.energy.internal > 0.01 * solver.energy.initial);
    assert!(solver.cycles > 20);
}

#[test]
fn sliding_interfaces_keep_mass_and_momentum_exact_and_the_bits_thread_independent() {
    // GOAL: the frictionless interface (EulerSettings::sliding_interfaces) changes only the
    //       materials' updates in the interface's cells: mass and axial momentum stay exact,
    //       the energy balanced, the run the same to the bit on one and two threads, and
    //       different from the welded run (the release acts).
    // SETUP: the colliding blocks of the conservation test, with the setting on.
    let run = |sliding: bool, threads: usize| {
        let solver = collide_conserving(EulerSettings {
            threads: Some(threads),
            sliding_interfaces: sliding,
            ..EulerSettings::default()
        });
        (solver.velocity.clone(), solver.volume.clone())
    };
    let sliding = run(true, 1);
    assert!(
        run(true, 2) == sliding,
        "two threads changed the sliding run"
    );
    assert!(run(false, 1) != sliding, "the release changed nothing");
}

#[test]
fn a_time_step_below_its_floor_ends_the_run_with_a_typed_error_naming_both_steps() {
    // GOAL: a run whose stable step falls below its floor (a fraction of the first cycle's)
    // stops with `TimeStepCollapse` instead of running on; a run that stays above it is not
    // stopped.
    // SETUP: two blocks colliding at 400 m/s in a closed grid, stepped by hand with the floor
    // off to find the smallest step relative to the first; then the same run with the floor
    // just above that ratio, and with it just below.
    // REFERENCE: the collapse is reported at the first cycle whose step is under the floor,
    // with that step and the first cycle's.
    let grid = Grid {
        cells_r: 20,
        cells_z: 30,
        spacing_r: 1e-3,
        spacing_z: 1e-3,
        geometry: Geometry::Axisymmetric,
    };
    let build = |fraction: f64| {
        colliding_blocks(
            grid,
            EulerSettings {
                threads: Some(1),
                minimum_time_step_fraction: fraction,
                ..EulerSettings::default()
            },
        )
    };
    let mut free = build(0.0);
    let steps: Vec<f64> = (0..60).map(|_| free.step().unwrap()).collect();
    let ratio = steps
        .iter()
        .fold(f64::INFINITY, |m, &dt| m.min(dt / steps[0]));
    assert!(ratio < 1.0, "the step never fell below the first: {ratio}");
    let collapse = steps.iter().position(|&dt| dt < (ratio + 1e-9) * steps[0]);
    let mut held = build(0.999_999 * ratio);
    for _ in 0..60 {
        held.step().expect("a floor below every step stops nothing");
    }
    let mut stopped = build(ratio + 1e-9);
    let error = (0..60)
        .find_map(|_| stopped.step().err())
        .expect("a floor above the smallest step stops the run");
    match error {
        EulerError::TimeStepCollapse {
            time_step,
            first_time_step,
            ..
        } => {
            assert_eq!(first_time_step, steps[0]);
            assert_eq!(time_step, steps[collapse.unwrap()]);
            assert_eq!(stopped.cycles as usize, collapse.unwrap());
        }
        other => panic!("expected a time-step collapse, got {other}"),
    }
}

/// The fraction of material 0 in each cell of a 64 x 64 planar unit grid.
fn fractions(solver: &EulerSolver<Material>) -> Vec<f64> {
    (0..solver.grid.cell_count())
        .map(|c| solver.fraction(c, 0))
        .collect()
}

/// Rider & Kothe's shape error: `sum |f - f_exact| A / perimeter`, in cell widths.
fn shape_error(
    solver: &EulerSolver<Material>,
    exact: &dyn Fn([f64; 2]) -> bool,
    perimeter: f64,
) -> f64 {
    let h = solver.grid.spacing_r;
    let got = fractions(solver);
    let mut error = 0.0;
    for (c, f) in got.iter().enumerate() {
        let (i, j) = (c % solver.grid.cells_r, c / solver.grid.cells_r);
        let mut inside = 0.0;
        const SUB: usize = 16;
        for a in 0..SUB {
            for b in 0..SUB {
                let p = [
                    (i as f64 + (a as f64 + 0.5) / SUB as f64) * h,
                    (j as f64 + (b as f64 + 0.5) / SUB as f64) * h,
                ];
                if exact(p) {
                    inside += 1.0;
                }
            }
        }
        error += (f - inside / (SUB * SUB) as f64).abs() * h * h;
    }
    error / perimeter / h
}

/// A region of the plane.
type Shape = Box<dyn Fn([f64; 2]) -> bool>;

fn advection_grid() -> Grid {
    Grid {
        cells_r: 64,
        cells_z: 64,
        spacing_r: 1.0 / 64.0,
        spacing_z: 1.0 / 64.0,
        geometry: Geometry::Planar,
    }
}

#[test]
fn two_material_advection_of_a_translating_and_a_rotating_shape_holds_volume_and_shape() {
    // GOAL: PLIC with nested dissection carries a body through another material without
    // losing volume (to 1e-12) and keeps its shape within one cell.
    // SETUP: Rider & Kothe (1998): a disc of radius 0.15 translated diagonally by 0.3;
    // a square rotated a quarter turn about the grid centre. Velocities held fixed.
    let a = perfectly_plastic(1000.0, 1e9, 2e9, 1e6);
    let b = perfectly_plastic(2000.0, 1e9, 2e9, 1e6);
    let everywhere = |_: [f64; 2]| true;
    let disc = |p: [f64; 2]| (p[0] - 0.3).powi(2) + (p[1] - 0.3).powi(2) < 0.15 * 0.15;
    for case in ["translation", "rotation"] {
        let square = |p: [f64; 2]| (0.55..0.8).contains(&p[0]) && (0.35..0.65).contains(&p[1]);
        let shape: &dyn Fn([f64; 2]) -> bool = if case == "translation" {
            &disc
        } else {
            &square
        };
        let regions = [
            Region {
                material: 0,
                inside: shape,
                velocity: [0.0, 0.0],
                temperature: 293.0,
            },
            Region {
                material: 1,
                inside: &everywhere,
                velocity: [0.0, 0.0],
                temperature: 293.0,
            },
        ];
        let mut solver = EulerSolver::new(
            advection_grid(),
            0.0,
            SLIP,
            vec![named("a", a), named("b", b)],
            &regions,
            EulerSettings::default(),
        )
        .unwrap();
        let nodes_r = solver.nodes_r();
        let omega = std::f64::consts::FRAC_PI_2;
        for (n, v) in solver.velocity.iter_mut().enumerate() {
            let x = (n % nodes_r) as f64 / 64.0;
            let y = (n / nodes_r) as f64 / 64.0;
            *v = if case == "translation" {
                [1.0, 1.0]
            } else {
                [-omega * (y - 0.5), omega * (x - 0.5)]
            };
        }
        let volume = solver.phase_volume(0);
        let steps = 160;
        for _ in 0..steps {
            solver.advect(
                0.3 / steps as f64
                    * if case == "translation" {
                        1.0
                    } else {
                        1.0 / 0.3
                    },
            );
        }
        let after = solver.phase_volume(0);
        assert!(
            (after - volume).abs() <= 1e-12 * volume,
            "{case}: volume {after} against {volume}"
        );
        let (exact, perimeter): (Shape, f64) = if case == "translation" {
            (
                Box::new(|p: [f64; 2]| (p[0] - 0.6).powi(2) + (p[1] - 0.6).powi(2) < 0.15 * 0.15),
                2.0 * std::f64::consts::PI * 0.15,
            )
        } else {
            // A quarter turn counter-clockwise about (0.5, 0.5): x' = 1 - y, y' = x.
            (
                Box::new(|p: [f64; 2]| (0.35..0.65).contains(&p[0]) && (0.55..0.8).contains(&p[1])),
                2.0 * (0.25 + 0.3),
            )
        };
        let error = shape_error(&solver, &*exact, perimeter);
        eprintln!(
            "{case}: volume change {:.2e} (relative), shape error {error:.3} cells",
            (after - volume) / volume
        );
        assert!(error < 1.0, "{case}: shape error {error} cells");
    }
}

#[test]
fn an_elastic_plastic_plate_impact_sends_the_hugoniot_elastic_limit_ahead_of_the_plastic_wave() {
    // GOAL: uniaxial strain in a symmetric plate impact: the elastic precursor travels at
    // c_L = sqrt((K + 4G/3)/rho) with amplitude sigma_HEL = Y (1 - nu)/(1 - 2 nu); the plastic
    // wave behind it at the bulk speed sqrt(K/rho) (perfect plasticity), up to the state of
    // particle velocity v/2 (Meyers 1994, ch. 7), each within 1 %.
    // SETUP: planar grid 2 x 1600 cells of 20 um, slip walls (uniaxial strain); a 12 mm flyer
    // at 200 m/s onto a 20 mm target of the same elastic-perfectly plastic steel.
    let (rho, g, k, y) = (7850.0, 80e9, 160e9, 1.0e9);
    let steel = perfectly_plastic(rho, g, k, y);
    let h = 20e-6;
    let grid = Grid {
        cells_r: 2,
        cells_z: 1600,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Planar,
    };
    let target = |p: [f64; 2]| p[1] < 20e-3;
    let flyer = |p: [f64; 2]| (20e-3..32e-3).contains(&p[1]);
    let regions = [
        Region {
            material: 0,
            inside: &target,
            velocity: [0.0, 0.0],
            temperature: 293.0,
        },
        Region {
            material: 0,
            inside: &flyer,
            velocity: [0.0, -200.0],
            temperature: 293.0,
        },
    ];
    let mut solver = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![named("steel", steel)],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    // Probes in the target at 4 and 8 mm below the impact face: sigma_zz histories.
    let probes = [16e-3, 12e-3];
    let mut histories = vec![Vec::new(); probes.len()];
    solver
        .run(2.2e-6, 2e-9, &mut |s| {
            for (history, z) in histories.iter_mut().zip(probes) {
                let c = ((z / h) as usize) * s.grid.cells_r;
                history.push((s.time, -s.state[c * MAX_MATERIALS].stress[1]));
            }
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
    // The exact two-wave structure of this material (the kernel's logarithmic strain and its
    // linear EoS p = K mu, mu = rho/rho0 - 1): the precursor ends at yield, |eps| = Y/2G, i.e.
    // mu_HEL = exp(Y/2G) - 1 and sigma_HEL = K mu_HEL + 2Y/3 (-> Y (1-nu)/(1-2nu) at small
    // strain); behind the plastic wave sigma = K mu + 2Y/3 at particle velocity v/2 (symmetric
    // impact). Both fronts obey the jump conditions in the fixed (Eulerian) frame.
    let mu_hel = (y / (2.0 * g)).exp() - 1.0;
    let hel = k * mu_hel + 2.0 * y / 3.0;
    let rho_1 = rho * (1.0 + mu_hel);
    let elastic_expected = (hel * rho_1 / (rho * (rho_1 - rho))).sqrt();
    let u_e = elastic_expected * (rho_1 - rho) / rho_1;
    let u_2 = 100.0;
    let plastic = |rho_2: f64| {
        let sigma_2 = k * (rho_2 / rho - 1.0) + 2.0 * y / 3.0;
        let speed = (rho_2 * u_2 - rho_1 * u_e) / (rho_2 - rho_1);
        (
            sigma_2,
            speed,
            sigma_2 - hel - rho_1 * (speed - u_e) * (u_2 - u_e),
        )
    };
    let (mut low, mut high) = (rho_1 * (1.0 + 1e-9), rho_1 * 1.2);
    for _ in 0..200 {
        let mid = 0.5 * (low + high);
        if plastic(mid).2 < 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    let (final_stress, plastic_expected, _) = plastic(0.5 * (low + high));
    // Small-strain forms, for the record: within 1 % of the exact ones here.
    let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
    let c_l = ((k + 4.0 * g / 3.0) / rho).sqrt();
    assert!((hel / (y * (1.0 - nu) / (1.0 - 2.0 * nu)) - 1.0).abs() < 0.01);
    assert!((elastic_expected / c_l - 1.0).abs() < 0.01);
    let crossing = |history: &[(f64, f64)], level: f64| -> f64 {
        let k = history
            .iter()
            .position(|p| p.1 >= level)
            .expect("level reached");
        let (a, b) = (history[k - 1], history[k]);
        a.0 + (level - a.1) / (b.1 - a.1) * (b.0 - a.0)
    };
    let gap = probes[0] - probes[1];
    let elastic_speed =
        gap / (crossing(&histories[1], 0.5 * hel) - crossing(&histories[0], 0.5 * hel));
    let plastic_level = 0.5 * (hel + final_stress);
    let plastic_speed =
        gap / (crossing(&histories[1], plastic_level) - crossing(&histories[0], plastic_level));
    eprintln!(
        "precursor {elastic_speed:.1} against {elastic_expected:.1} m/s, plastic wave \
         {plastic_speed:.1} against {plastic_expected:.1} m/s"
    );
    assert!(
        (elastic_speed / elastic_expected - 1.0).abs() < 0.01,
        "precursor {elastic_speed} against {elastic_expected}"
    );
    assert!(
        (plastic_speed / plastic_expected - 1.0).abs() < 0.01,
        "plastic {plastic_speed} against {plastic_expected}"
    );
    // The precursor's plateau between the two fronts, at the deeper probe.
    let t_elastic = crossing(&histories[1], 0.5 * hel);
    let t_plastic = crossing(&histories[1], plastic_level);
    let plateau: Vec<f64> = histories[1]
        .iter()
        .filter(|p| {
            p.0 > t_elastic + 0.3 * (t_plastic - t_elastic)
                && p.0 < t_elastic + 0.7 * (t_plastic - t_elastic)
        })
        .map(|p| p.1)
        .collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    assert!(
        (mean / hel - 1.0).abs() < 0.01,
        "HEL {mean:e} against {hel:e}"
    );
    let last = histories[1].last().unwrap().1;
    assert!(
        (last / final_stress - 1.0).abs() < 0.01,
        "final {last:e} against {final_stress:e}"
    );
}

#[test]
fn a_taylor_rod_on_the_eulerian_grid_ends_as_long_as_on_the_lagrangian_mesh() {
    // GOAL: strength, plastic flow and the free surface on the Eulerian grid: the rod-on-anvil
    //       final length within 2 % of the Lagrangian solver's on the same rod (issue 47),
    //       held here at 0.25 %, twice the figure docs/euler.md quotes.
    // SETUP: fixtures/experiments/taylor-4340-208.toml (25.4 x 7.62 mm 4340 rod at 208 m/s,
    //        Johnson-Cook 1985 constants) on the Lagrangian solver (8 elements across the
    //        radius) and on a 0.254 mm Eulerian grid (15 cells across the radius) with slip
    //        walls; the Eulerian length is the mean of the axis extents at 30-60 us (the
    //        event is over by 20 us; the elastic ringing left is +/- 0.3 %).
    // REFERENCE: the Lagrangian solver's final length, 22.554 mm (the Eulerian grid: 22.528
    //            mm, -0.12 %; energy error -0.38 %).
    let experiment =
        stoss::experiment::Experiment::load(&fixture("experiments/taylor-4340-208.toml")).unwrap();
    let (_, rod) = material::load(&experiment.default_material_path().unwrap()).unwrap();
    let lagrange = experiment
        .simulate(&rod.into(), &stoss::solver::SolverSettings::default())
        .unwrap()
        .summary_value("final_length")
        .unwrap();
    let (length, radius, h): (f64, f64, f64) = (25.4e-3, 3.81e-3, 0.254e-3);
    let grid = Grid {
        cells_r: 28,
        cells_z: ((length + 2.0 * h) / h).ceil() as usize,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let in_rod = move |p: [f64; 2]| p[0] < radius && (0.0..length).contains(&p[1]);
    let regions = [Region {
        material: 0,
        inside: &in_rod,
        velocity: [0.0, -208.0],
        temperature: 295.0,
    }];
    let mut solver = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![named("rod", rod)],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    let mut lengths = Vec::new();
    solver
        .run(60e-6, 10e-6, &mut |s| {
            if s.time >= 30e-6 - 1e-9 {
                let (nose, tail) = stoss::experiment::penetration::euler::rod_extent(s, 0);
                lengths.push(tail - nose);
            }
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
    let euler = lengths.iter().sum::<f64>() / lengths.len() as f64;
    let energy = solver.energy.relative_error();
    eprintln!(
        "Taylor final length: Euler {:.3} mm, Lagrange {:.3} mm; energy error {energy:.4}",
        euler * 1e3,
        lagrange * 1e3
    );
    assert!(lengths.len() >= 3, "{lengths:?}");
    // Measured -0.12 % (issue 47 asks 2 %); asserted at about twice the figure the docs quote.
    assert!(
        (euler / lagrange - 1.0).abs() < 0.0025,
        "Euler {euler} against Lagrange {lagrange}"
    );
    // Measured -0.38 %.
    assert!(energy.abs() < 0.01, "energy error {energy}");
}

/// Plastic work per radian and unit length of a rigid-perfectly plastic, incompressible
/// cylindrical shell whose inner radius closes from `a0` to `a` (outer `b0` at `a0`):
/// `W = (2 Y / sqrt 3) int_a^a0 x ln(b(x) / x) dx`, `b(x)^2 = x^2 + b0^2 - a0^2` (midpoint rule,
/// 20 000 intervals).
fn shell_work(yield_stress: f64, a0: f64, b0: f64, a: f64) -> f64 {
    let n = 20_000;
    let step = (a0 - a) / n as f64;
    let sum: f64 = (0..n)
        .map(|k| {
            let x = a + (k as f64 + 0.5) * step;
            let b = (x * x + b0 * b0 - a0 * a0).sqrt();
            x * (b / x).ln() * step
        })
        .sum();
    2.0 * yield_stress / 3.0_f64.sqrt() * sum
}

#[test]
fn a_collapsing_cylinder_stops_where_its_kinetic_energy_is_spent_in_plastic_work() {
    // GOAL: plastic work in a large converging flow on the fixed grid: a thick cylindrical
    //       shell thrown inward stops at the inner radius where its kinetic energy equals the
    //       plastic work of the collapse, within 2 % (the issue asks 5 %).
    // SETUP: a steel-density shell, inner radius 10 mm, outer 20 mm, Y 500 MPa, G 80 GPa,
    //        K 160 GPa (Y/G 0.6 %: near rigid-plastic), given the incompressible field
    //        v_r = -300 m/s x a0 / r; a 1 mm slab between slip walls (plane strain along z),
    //        0.5 mm cells; the inner radius from the void volume at 200 us (at rest by then).
    // REFERENCE: Verney (1968), Howell & Ball, J. Comput. Phys. 175 (2002) 128-167: the
    //   incompressible energy balance int KE = shell_work(a_f), solved by bisection from the
    //   solver's own initial kinetic energy (3.652 mm here; the solver gives 3.685 at 0.5 mm
    //   and 3.689 at 0.125 mm, the 0.9 % being mostly the elastic energy left in the shell).
    let (a0, b0, yield_stress, h) = (10e-3, 20e-3, 500e6, 0.5e-3);
    let rows = 2;
    let grid = Grid {
        cells_r: 48,
        cells_z: rows,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let in_shell = move |p: [f64; 2]| p[0] >= a0 && p[0] < b0;
    let regions = [Region {
        material: 0,
        inside: &in_shell,
        velocity: [0.0, 0.0],
        temperature: 293.0,
    }];
    let shell = perfectly_plastic(7850.0, 80e9, 160e9, yield_stress);
    let mut solver = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![named("shell", shell)],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    let nodes_r = solver.nodes_r();
    let masses = solver.node_masses();
    for (n, v) in solver.velocity.iter_mut().enumerate() {
        let r = (n % nodes_r) as f64 * h;
        if masses[n] > 0.0 && r > 0.0 {
            *v = [-300.0 * a0 / r, 0.0];
        }
    }
    let kinetic = solver.kinetic_energy();
    solver.energy.initial = kinetic;
    solver
        .run(200e-6, 50e-6, &mut |_| std::ops::ControlFlow::Continue(()))
        .unwrap();
    // The inner void: the cells inside 10 mm (the shell's inner part stays beyond 3.6 mm and
    // its outer edge at 18 mm).
    let void: f64 = (0..20)
        .map(|i| solver.fraction(i, MAX_PHASES - 1) * solver.cell_volume(i))
        .sum();
    let inner = (2.0 * void / h).sqrt();
    let target = kinetic / (2.0 * std::f64::consts::PI * rows as f64 * h);
    let (mut low, mut high) = (1e-6, a0);
    for _ in 0..100 {
        let middle = 0.5 * (low + high);
        if shell_work(yield_stress, a0, b0, middle) > target {
            low = middle;
        } else {
            high = middle;
        }
    }
    let predicted = 0.5 * (low + high);
    let energy = solver.energy.relative_error();
    eprintln!(
        "collapse: inner radius {:.4} mm against the energy balance's {:.4} mm; energy error {energy:.4}",
        inner * 1e3,
        predicted * 1e3
    );
    assert!(
        (inner / predicted - 1.0).abs() < 0.02,
        "inner radius {inner} against {predicted}"
    );
    // The drive works through the cavity wall's mixed cells, where the closure gives the
    // cell's volume change to the void first: -1.7 % here, -1.2 % at half the cell size.
    assert!(energy.abs() < 0.025, "energy error {energy}");
}

/// A rod of `rod` at `velocity` into a plate of `target` on an axisymmetric grid of `h`
/// cells, the target `thickness` thick and `width` in radius, the rod `length` long (m): the
/// nose depth history. The box must be large enough that no wave comes back from its rigid
/// walls inside the window measured (in a 30 x 40 mm box the walls confined a 20 us run: 1 %
/// volumetric strain from the rod's displaced volume, about 1.5 GPa back on the crater floor).
fn penetrate(
    rod: Material,
    target: Material,
    radius: f64,
    velocity: f64,
    h: f64,
    end_time: f64,
    (thickness, length, width): (f64, f64, f64),
) -> Vec<(f64, f64)> {
    let below = 2e-3;
    let grid = Grid {
        cells_r: (width / h).round() as usize,
        cells_z: ((below + thickness + length + 2.0 * h) / h).ceil() as usize,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let origin = -thickness - below;
    let in_rod = move |p: [f64; 2]| p[0] < radius && (0.0..length).contains(&p[1]);
    let in_target = move |p: [f64; 2]| (-thickness..0.0).contains(&p[1]);
    let regions = [
        Region {
            material: 0,
            inside: &in_rod,
            velocity: [0.0, -velocity],
            temperature: 293.0,
        },
        Region {
            material: 1,
            inside: &in_target,
            velocity: [0.0, 0.0],
            temperature: 293.0,
        },
    ];
    let mut solver = EulerSolver::new(
        grid,
        origin,
        Walls {
            outer: Wall::Fixed,
            bottom: Wall::Slip,
            top: Wall::Slip,
        },
        vec![named("rod", rod), named("target", target)],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    let mut depth = Vec::new();
    solver
        .run(end_time, 0.5e-6, &mut |s| {
            let (nose, _) = stoss::experiment::penetration::euler::rod_extent(s, 0);
            depth.push((s.time, -nose));
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
    let energy = solver.energy.relative_error();
    eprintln!("energy error {energy}");
    depth
}

/// Least-squares slope of `(t, y)` for `t` in `[from, to]`.
fn slope(history: &[(f64, f64)], from: f64, to: f64) -> f64 {
    let points: Vec<_> = history
        .iter()
        .filter(|p| p.0 >= from && p.0 <= to)
        .collect();
    let n = points.len() as f64;
    let (mt, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = points.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mt) * (p.0 - mt)).sum();
    sxy / sxx
}

#[test]
fn near_fluid_rod_and_target_penetrate_at_bernoullis_rate_once_the_flow_is_steady() {
    // GOAL: both materials near-fluid: the steady penetration rate is Bernoulli's,
    // (1/2) rho_p (v - u)^2 = (1/2) rho_t u^2, u = v / (1 + sqrt(rho_t / rho_p)), within 2 %.
    // Bernoulli's balance holds for a steady flow; the target's flow about the head reaches
    // it only after a transient that a short rod never leaves (docs/euler.md, "The Bernoulli
    // limit"): the rate is 0.95 of Bernoulli's over the first 20 us and climbs to 0.98-0.99
    // after 100 us (15 rod radii of penetration), on 1 and 2 mm cells alike.
    // SETUP: a 10 mm, 250 mm long tungsten-density rod at 1250 m/s into a steel-density
    // target 350 mm thick and 150 mm in radius (no wave back from its walls into the
    // window), 1 MPa strength each; 2 mm cells (2.5 across the rod's radius: the depth at
    // 250 us is within 0.2 % of 1 mm cells'); the rate fitted over 100-240 us.
    // REFERENCE: Bernoulli, 749.5 m/s. Measured 2026-11-28: 736 m/s (-1.8 %); with 1 mm cells
    // 738.5 m/s over 100-250 us (-1.5 %).
    let rod = perfectly_plastic(17600.0, 145e9, 285e9, 1e6);
    let target = perfectly_plastic(7850.0, 80e9, 160e9, 1e6);
    let depth = penetrate(
        rod,
        target,
        5e-3,
        1250.0,
        2e-3,
        240e-6,
        (350e-3, 250e-3, 150e-3),
    );
    let early = slope(&depth, 6e-6, 20e-6);
    let rate = slope(&depth, 100e-6, 240e-6);
    let bernoulli = 1250.0 / (1.0 + (7850.0_f64 / 17600.0).sqrt());
    eprintln!(
        "near-fluid rate {rate:.1} m/s over 100-240 us ({early:.1} over 6-20 us) against \
         Bernoulli {bernoulli:.1} m/s"
    );
    assert!(
        (rate / bernoulli - 1.0).abs() < 0.02,
        "rate {rate} against {bernoulli}"
    );
    // The transient: the early rate is measurably below the steady one.
    assert!(early < rate, "early {early}, steady {rate}");
}

#[test]
fn an_eulerian_penetration_refuses_lagrangian_only_options_and_oversized_grids_by_field() {
    // GOAL: bad input to an Eulerian penetration is an error naming the file and field,
    // before anything runs: options the Eulerian solver does not have are refused, not
    // ignored; a unit slip in the cell size is caught by the grid bound.
    // SETUP: the bundled 1250 m/s Eulerian experiment with one field changed at a time.
    let base = std::fs::read_to_string(fixture("experiments/penetration-hzb-1250-euler.toml"))
        .unwrap()
        .replace(
            "\"../materials/",
            &format!("\"{}/", fixture("materials").display()),
        )
        .replace(
            "recording = \"",
            &format!("recording = \"{}/", fixture("experiments").display()),
        );
    let folder = std::env::temp_dir().join(format!("stoss-euler-bad-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let cases = [
        ("friction = 0.1", "friction"),
        ("rigid_rod = true", "rigid_rod"),
        ("self_contact = true", "self_contact"),
        ("rod_element_size = 0.4e-3", "rod_element_size"),
        ("hourglass = \"stiffness\"", "hourglass"),
    ];
    for (line, field) in cases {
        let text = base.replace("solver = \"euler\"", &format!("solver = \"euler\"\n{line}"));
        let path = folder.join(format!("{field}.toml"));
        std::fs::write(&path, text).unwrap();
        let error = stoss::experiment::Experiment::load(&path)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(field) && error.contains(&path.display().to_string()),
            "{field}: {error}"
        );
    }
    // A spec edited in code gets the same up-front checks when its model is built.
    {
        let shot = stoss::validate::semi_infinite::shot(&fixture("")).unwrap();
        let mut spec = shot.spec.clone();
        spec.solver = stoss::experiment::penetration::PenetrationSolver::Euler;
        spec.element_size = 0.4e-5;
        let target: stoss_kernel::PartMaterial = shot.target.material().unwrap().into();
        let error = spec
            .euler_model(&target, &stoss::solver::SolverSettings::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains("element_size"), "{error}");
    }
    // The Eulerian-only options on the Lagrangian solver.
    for field in ["void_insertion", "sliding_interface"] {
        let path = folder.join(format!("{field}.toml"));
        std::fs::write(
            &path,
            base.replace(
                "solver = \"euler\"",
                &format!("solver = \"lagrange\"\n{field} = true"),
            ),
        )
        .unwrap();
        let error = stoss::experiment::Experiment::load(&path)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(field) && error.contains("Eulerian"),
            "{error}"
        );
    }
    let path = folder.join("cells.toml");
    std::fs::write(
        &path,
        base.replace("element_size = 0.4e-3", "element_size = 0.4e-5"),
    )
    .unwrap();
    let error = stoss::experiment::Experiment::load(&path)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("element_size") && error.contains("cells"),
        "{error}"
    );
    // The solver itself refuses a degenerate grid.
    let steel = perfectly_plastic(7850.0, 80e9, 160e9, 1e9);
    let grid = Grid {
        cells_r: 10,
        cells_z: 10,
        spacing_r: 0.0,
        spacing_z: 1e-3,
        geometry: Geometry::Axisymmetric,
    };
    let error = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![named("steel", steel)],
        &[],
        EulerSettings::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("spacing_r"), "{error}");
    std::fs::remove_dir_all(&folder).ok();
}

#[test]
fn a_thread_count_outside_its_bounds_is_refused_before_any_pool_is_built() {
    // GOAL: a runaway thread count (0, or 100 000 from a unit slip) is a typed error, not a
    //       pool of 100 000 threads.
    let grid = Grid {
        cells_r: 4,
        cells_z: 4,
        spacing_r: 1e-3,
        spacing_z: 1e-3,
        geometry: Geometry::Axisymmetric,
    };
    let inside = |p: [f64; 2]| p[1] < 2e-3;
    let regions = [Region {
        material: 0,
        inside: &inside,
        velocity: [0.0, 0.0],
        temperature: 293.0,
    }];
    for threads in [0, 100_000] {
        let mut solver = EulerSolver::new(
            grid,
            0.0,
            SLIP,
            vec![named("block", perfectly_plastic(7850.0, 80e9, 160e9, 1e9))],
            &regions,
            EulerSettings {
                threads: Some(threads),
                ..EulerSettings::default()
            },
        )
        .unwrap();
        let error = solver
            .run(1e-6, 1e-6, &mut |_| std::ops::ControlFlow::Continue(()))
            .unwrap_err();
        assert!(
            error.to_string().contains("threads must be in 1..="),
            "{error}"
        );
    }
}

#[test]
fn a_spherical_cavity_opens_at_hills_pressure() {
    // GOAL: the strength of material flowing through the fixed grid, against the closed form a
    //       penetration model rests on: a spherical cavity opened slowly in an elastic-perfectly
    //       plastic solid needs Hill's pressure (the issue asks 3 %), and the radial stress in
    //       the plastic zone falls off as 2Y ln r.
    // SETUP: Y 1 GPa, G 80 GPa, K 160 GPa, steel density; a cavity on the axis at a slip
    //        (symmetry) wall, driven open from 5 to 12 cells (0.25 mm) at 50 m/s by the
    //        solver's cavity drive (the material's cavity grows from 5 to 11 cells), in a 120 x 120 cell box with slip walls (2.2 plastic-zone radii).
    //        The radial stress of the pure cells between the cavity wall plus 3 cells and 0.7
    //        of the plastic zone's radius is fitted as alpha + beta ln(r / a); the box's
    //        uniform confinement (the displaced volume compresses it) is the mean pressure of
    //        the elastic zone, which a spherical elastic field leaves unchanged (it is pure
    //        shear), and is taken off; so is the inertial stress of the incompressible
    //        constant-speed field, rho V^2 (2a/r - a^4/(2 r^4)) (Forrestal & Luk 1988).
    // REFERENCE: Hill (The Mathematical Theory of Plasticity, 1950) for a cavity grown from
    //   radius a0 to a with an incompressible plastic zone: p = 2Y/3 [1 + ln(E/(3(1-nu)Y)
    //   (1 - (a0/a)^3))], slope 2Y, the plastic zone's radius c with c^3 = E/(3(1-nu)Y)
    //   (a^3 - a0^3); a and a0 are the cavity's own radii (from its void volume). The solver
    //   gives 3.576 GPa against 3.644 (-1.9 %), slope 1.92 GPa; at half the cell size 3.673
    //   against 3.652 (+0.6 %), slope 2.006 GPa.
    let h = 0.25e-3;
    let cells = 120;
    let (density, shear, bulk, yield_stress) = (7850.0, 80e9, 160e9, 1e9);
    let (a0, speed) = (5.0 * h, 50.0);
    let grid = Grid {
        cells_r: cells,
        cells_z: cells,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let outside = move |p: [f64; 2]| p[0] * p[0] + p[1] * p[1] > a0 * a0;
    let regions = [Region {
        material: 0,
        inside: &outside,
        velocity: [0.0, 0.0],
        temperature: 293.0,
    }];
    let solid = perfectly_plastic(density, shear, bulk, yield_stress);
    let mut solver = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![named("solid", solid)],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    let drive = CavityDrive {
        center_z: 0.0,
        initial_radius: a0,
        speed,
    };
    solver.drive = Some(drive);
    // The cavity's radius from its void volume (per radian, a half sphere: a^3 / 3): the
    // drive moves the nodes inside its sphere, and the material of the cells it cuts lags by
    // about a cell, so Hill's solution is taken at the cavity the material shows.
    let cavity_radius = |solver: &EulerSolver<Material>| {
        let void: f64 = (0..grid.cell_count())
            .map(|c| solver.fraction(c, MAX_PHASES - 1) * solver.cell_volume(c % cells))
            .sum();
        (3.0 * void).cbrt()
    };
    let a0 = cavity_radius(&solver);
    let end = 7.0 * h / speed;
    solver
        .run(end, end, &mut |_| std::ops::ControlFlow::Continue(()))
        .unwrap();
    let a = cavity_radius(&solver);
    let young = 9.0 * bulk * shear / (3.0 * bulk + shear);
    let poisson = (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear));
    let stiffness = young / (3.0 * (1.0 - poisson) * yield_stress);
    let plastic_radius = (stiffness * (a * a * a - a0 * a0 * a0)).cbrt();
    let expected = spherical_cavity_pressure(yield_stress, bulk, shear)
        + 2.0 / 3.0 * yield_stress * (1.0 - (a0 / a).powi(3)).ln();
    // Pure cells: their centre, distance and the stress of the one material.
    let mut samples = Vec::new();
    let (mut confinement, mut far_volume) = (0.0, 0.0);
    for c in 0..grid.cell_count() {
        if solver.fraction(c, 0) < 0.999 {
            continue;
        }
        let (i, j) = (c % cells, c / cells);
        let x = [(i as f64 + 0.5) * h, (j as f64 + 0.5) * h];
        let d = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let s = solver.state[c * MAX_MATERIALS].stress;
        if d > 1.3 * plastic_radius && d < (cells as f64 - 2.0) * h {
            let volume = solver.cell_volume(i);
            confinement += -(s[0] + s[1] + s[2]) / 3.0 * volume;
            far_volume += volume;
        }
        if d > a + 3.0 * h && d < 0.7 * plastic_radius {
            let n = [x[0] / d, x[1] / d];
            let radial = n[0] * n[0] * s[0] + n[1] * n[1] * s[1] + 2.0 * n[0] * n[1] * s[3];
            let inertial = -density * speed * speed * (2.0 * a / d - a.powi(4) / (2.0 * d.powi(4)));
            samples.push(((d / a).ln(), radial - inertial));
        }
    }
    let confinement = confinement / far_volume;
    let count = samples.len() as f64;
    let mean_x = samples.iter().map(|s| s.0).sum::<f64>() / count;
    let mean_y = samples.iter().map(|s| s.1 + confinement).sum::<f64>() / count;
    let slope = samples
        .iter()
        .map(|s| (s.0 - mean_x) * (s.1 + confinement - mean_y))
        .sum::<f64>()
        / samples.iter().map(|s| (s.0 - mean_x).powi(2)).sum::<f64>();
    let pressure = -(mean_y - slope * mean_x);
    let energy = solver.energy.relative_error();
    eprintln!(
        "cavity: a {:.3} mm, plastic zone {:.2} mm, {} samples; pressure {:.4} GPa against \
         Hill's {:.4} ({:+.2} %), slope {:.4} GPa against 2Y {:.4}; confinement {:.4} GPa; \
         energy error {energy:.4}",
        a * 1e3,
        plastic_radius * 1e3,
        samples.len(),
        pressure * 1e-9,
        expected * 1e-9,
        (pressure / expected - 1.0) * 100.0,
        slope * 1e-9,
        2.0 * yield_stress * 1e-9,
        confinement * 1e-9,
    );
    assert!(
        (pressure / expected - 1.0).abs() < 0.03,
        "cavity pressure {pressure} against Hill's {expected}"
    );
    assert!(
        (slope / (2.0 * yield_stress) - 1.0).abs() < 0.05,
        "slope {slope} against 2Y"
    );
    // The drive works through the cavity wall's mixed cells, where the closure gives the
    // cell's volume change to the void first: -1.7 % here, -1.2 % at half the cell size.
    assert!(energy.abs() < 0.025, "energy error {energy}");
}

/// The spall test's material: a near-fluid aluminium (Y 1 MPa, G 1 MPa, K 70 GPa) with a
/// hydrodynamic tensile limit `cutoff` (Pa; `None`: it holds any tension).
fn fluid_with_cutoff(cutoff: Option<f64>) -> Material {
    let mut material = perfectly_plastic(2700.0, 1e6, 70e9, 1e6);
    material.failure.pressure_cutoff = cutoff;
    material
}

/// A symmetric plate impact on a planar grid: a 2 mm flyer at 200 m/s onto a
/// 4 mm target with a free rear face; `fracture` is the material's tensile limit and its
/// fracture pressure on the grid (`None`: it holds any tension), `h` the cell size. Returns the solver at 3 us.
fn spall_run(fracture: Option<f64>, h: f64) -> EulerSolver<Material> {
    let grid = Grid {
        cells_r: 2,
        cells_z: (9e-3 / h).round() as usize,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Planar,
    };
    let target = |p: [f64; 2]| (1e-3..5e-3).contains(&p[1]);
    let flyer = |p: [f64; 2]| (5e-3..7e-3).contains(&p[1]);
    let regions = [
        Region {
            material: 0,
            inside: &target,
            velocity: [0.0, 0.0],
            temperature: 293.0,
        },
        Region {
            material: 0,
            inside: &flyer,
            velocity: [0.0, -200.0],
            temperature: 293.0,
        },
    ];
    // The grid's fracture pressure is the material's tensile limit, as a penetration run
    // with `void_insertion` sets it.
    let model = fluid_with_cutoff(fracture);
    let mut solver = EulerSolver::new(
        grid,
        0.0,
        SLIP,
        vec![EulerMaterial {
            name: "aluminium".into(),
            model,
            fracture_pressure: fracture,
        }],
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    solver
        .run(3e-6, 1e-6, &mut |_| std::ops::ControlFlow::Continue(()))
        .unwrap();
    solver
}

/// Per cell row (column i = 0): `(z, material mass, void fraction, axial velocity)`, the
/// velocity the mean of the cell's four nodes.
fn rows(solver: &EulerSolver<Material>) -> Vec<(f64, f64, f64, f64)> {
    let grid = &solver.grid;
    let nodes_r = grid.cells_r + 1;
    (0..grid.cells_z)
        .map(|j| {
            let c = j * grid.cells_r;
            let volume: f64 = solver.volume[c * MAX_PHASES..(c + 1) * MAX_PHASES]
                .iter()
                .sum();
            let void = solver.volume[c * MAX_PHASES + MAX_PHASES - 1] / volume;
            let nodes = [
                j * nodes_r,
                j * nodes_r + 1,
                (j + 1) * nodes_r,
                (j + 1) * nodes_r + 1,
            ];
            let v = nodes.iter().map(|&n| solver.velocity[n][1]).sum::<f64>() / 4.0;
            (
                (j as f64 + 0.5) * grid.spacing_z,
                solver.mass[c * MAX_MATERIALS],
                void,
                v,
            )
        })
        .collect()
}

#[test]
fn void_insertion_spalls_a_plate_at_half_the_pulse_length_and_the_scab_takes_the_momentum() {
    // GOAL: tensile failure on the grid (void insertion). In a symmetric impact of a flyer of
    //       thickness h on a target of 2h, the release from the flyer's back and the one
    //       reflected at the target's free rear face meet h from the rear face, where the
    //       rectangular pulse's tail turns into tension of the full pulse amplitude
    //       p = rho c v / 2 at once; a material weaker than that spalls there, and the scab
    //       (thickness h) leaves with the flyer's velocity v while flyer and the target's
    //       front come to rest (acoustic theory: Meyers 1994, ch. 16; Antoun et al. 2003,
    //       ch. 2). A material that holds the tension does not open.
    // SETUP: near-fluid aluminium, v 200 m/s (p 1.37 GPa), fracture pressure -0.3 GPa, 20 um
    //        cells, 3 us (spall at about 1.2 us).
    // REFERENCE: the scab's mean velocity -v and the rest's 0, within 5 % of v; the gap at
    //            z = 3 mm (the target's rear at 1 mm plus h) less the scab's travel
    //            (0.4 mm by 3 us); at a fracture pressure beyond the pulse's amplitude
    //            (-1.5 GPa) and without one, no cell of the plates holds more than 1e-3 void.
    //            Measured (docs/euler.md): scab -193.0 / -192.2 / -194.2 m/s at 40 / 20 /
    //            10 um; spall at -0.1 to -1.2 GPa, none at -1.5 GPa.
    let v = 200.0;
    let solver = spall_run(Some(-0.3e9), 20e-6);
    let cells = rows(&solver);
    // The gap: the row with the most void between material above and below.
    let inside: Vec<&(f64, f64, f64, f64)> = cells
        .iter()
        .filter(|row| row.0 > 1.5e-3 && row.0 < 4.5e-3)
        .collect();
    let gap = inside
        .iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .copied()
        .unwrap();
    eprintln!(
        "spall gap at z {:.3} mm, void fraction {:.3}",
        gap.0 * 1e3,
        gap.2
    );
    assert!(gap.2 > 0.5, "no gap opened: {:?}", gap);
    assert!(
        (gap.0 - 3e-3).abs() <= 3.0 * 20e-6 + 0.4e-3,
        "gap at {} mm",
        gap.0 * 1e3
    );
    let mean = |rows: &mut dyn Iterator<Item = &(f64, f64, f64, f64)>| {
        let (m, p) = rows.fold((0.0, 0.0), |(m, p), row| (m + row.1, p + row.1 * row.3));
        p / m
    };
    let scab = mean(&mut cells.iter().filter(|row| row.0 < gap.0));
    let rest = mean(&mut cells.iter().filter(|row| row.0 > gap.0));
    eprintln!("scab {scab:.1} m/s, flyer and target front {rest:.1} m/s");
    assert!((scab + v).abs() < 0.05 * v, "scab {scab} against {}", -v);
    assert!(rest.abs() < 0.05 * v, "rest {rest}");
    let error = solver.energy.relative_error();
    eprintln!("energy error {error:.2e}");
    assert!(error.abs() < 0.01, "energy error {error}");

    // A material stronger than the pulse (1.5 GPa > 1.37 GPa), and one without a limit,
    // hold together.
    for fracture in [Some(-1.5e9), None] {
        let holding = spall_run(fracture, 20e-6);
        let most = rows(&holding)
            .iter()
            .filter(|row| row.0 > 1.5e-3 && row.0 < 4.5e-3)
            .map(|row| row.2)
            .fold(0.0, f64::max);
        eprintln!("fracture {fracture:?}: largest void fraction {most:.2e}");
        assert!(most < 1e-3, "void opened at {fracture:?}: {most}");
    }
}

/// A near-fluid steel rod (radius 5 mm, 40 mm long) into a near-fluid steel half-space, closing
/// at 1250 m/s: the rod moves at `-1250 + frame` and the target at `frame` (m/s, along z).
/// `separate_target` gives the target its own material slot with the rod's constants (a
/// material interface the flow does not have physically); otherwise rod and target are one
/// material. Returns the depth, into the target's material, of a tracer that starts on the
/// axis at the impact face and moves with the nodal velocity (integrated every cycle).
fn steel_jet_tracer(frame: f64, separate_target: bool, h: f64, end_time: f64) -> Vec<(f64, f64)> {
    let (radius, length, thickness, width, headroom) = (5e-3, 40e-3, 60e-3, 50e-3, 20e-3);
    let below = 2e-3;
    let grid = Grid {
        cells_r: (width / h).round() as usize,
        cells_z: ((below + thickness + length + headroom) / h).ceil() as usize,
        spacing_r: h,
        spacing_z: h,
        geometry: Geometry::Axisymmetric,
    };
    let in_rod = move |p: [f64; 2]| p[0] < radius && (0.0..length).contains(&p[1]);
    let in_target = move |p: [f64; 2]| (-thickness..0.0).contains(&p[1]);
    let regions = [
        Region {
            material: 0,
            inside: &in_rod,
            velocity: [0.0, frame - 1250.0],
            temperature: 293.0,
        },
        Region {
            material: usize::from(separate_target),
            inside: &in_target,
            velocity: [0.0, frame],
            temperature: 293.0,
        },
    ];
    let steel = || perfectly_plastic(7850.0, 80e9, 160e9, 1e6);
    let mut materials = vec![named("rod", steel())];
    if separate_target {
        materials.push(named("target", steel()));
    }
    let mut solver = EulerSolver::new(
        grid,
        -thickness - below,
        Walls {
            outer: Wall::Fixed,
            bottom: Wall::Slip,
            top: Wall::Slip,
        },
        materials,
        &regions,
        EulerSettings::default(),
    )
    .unwrap();
    let (mut z, mut last) = (0.0_f64, 0.0);
    let mut history = Vec::new();
    solver
        .run(end_time, 1e-12, &mut |s| {
            let nodes_r = s.nodes_r();
            let x = (z - s.origin_z) / h;
            let j = x.floor() as usize;
            let f = x - j as f64;
            let w = (1.0 - f) * s.velocity[j * nodes_r][1] + f * s.velocity[(j + 1) * nodes_r][1];
            z += w * (s.time - last);
            last = s.time;
            history.push((s.time, -(z - frame * s.time)));
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
    history
}

/// The value of a history at time `t` (the first sample at or after it).
fn at(history: &[(f64, f64)], t: f64) -> f64 {
    history.iter().find(|p| p.0 >= t).map_or(f64::NAN, |p| p.1)
}

/// Two tracer depth histories agree within `tolerance` (relative) at 10 and 20 us.
fn assert_depths_agree(
    (label_a, a): (&str, &[(f64, f64)]),
    (label_b, b): (&str, &[(f64, f64)]),
    tolerance: f64,
) {
    for t in [10e-6, 20e-6] {
        let (a, b) = (at(a, t), at(b, t));
        eprintln!(
            "t {:.0} us: depth {:.4} mm ({label_a}), {:.4} mm ({label_b})",
            t * 1e6,
            a * 1e3,
            b * 1e3
        );
        assert!((a / b - 1.0).abs() < tolerance, "{a} against {b} at {t}");
    }
}

#[test]
fn a_penetration_on_the_eulerian_grid_does_not_depend_on_the_frame_it_is_computed_in() {
    // GOAL: Galilean invariance of the Lagrange-plus-remap cycle on a penetration: the rod
    // flying into a target at rest, and the target flying into a rod at rest, give the same
    // penetration into the target's material. A remap (advection) error depends on how fast
    // the material crosses the grid, so this bounds its share of a penetration rate.
    // SETUP: near-fluid steel rod (5 mm radius) into near-fluid steel, closing at 1250 m/s,
    // 1 mm cells; frame 0 (rod at -1250 m/s) against frame +1250 m/s (rod at rest); a
    // tracer on the axis at the stagnation point; 20 us.
    // REFERENCE: exact invariance of the continuum equations; measured 5.747 / 5.701 mm at
    // 10 us and 11.358 / 11.296 mm at 20 us (0.8 % and 0.55 %; docs/euler.md, "Verification").
    let lab = steel_jet_tracer(0.0, true, 1e-3, 20e-6);
    let moving = steel_jet_tracer(1250.0, true, 1e-3, 20e-6);
    assert_depths_agree(("target at rest", &lab), ("rod at rest", &moving), 0.015);
}

#[test]
fn a_material_interface_inside_one_material_leaves_its_flow_unchanged() {
    // GOAL: the interface machinery (PLIC reconstruction, the mixed-cell closure, the
    // per-material remap) adds nothing to a flow where the two sides are the same material:
    // the run with the target as a second material slot with the rod's constants follows the
    // single-material run.
    // SETUP: the near-fluid steel-on-steel penetration of the frame test, 1 mm cells, the
    // stagnation tracer's depth at 10 and 20 us.
    // REFERENCE: the single-material run; measured 5.743 / 5.747 mm at 10 us and 11.352 /
    // 11.358 mm at 20 us (0.07 % and 0.05 %; docs/euler.md).
    let one = steel_jet_tracer(0.0, false, 1e-3, 20e-6);
    let two = steel_jet_tracer(0.0, true, 1e-3, 20e-6);
    assert_depths_agree(("one material", &one), ("two", &two), 0.002);
}

#[test]
fn tates_rigid_body_regime_flags_a_rod_that_does_not_erode() {
    // GOAL: the Eulerian penetration warns of a rod that does not erode (docs/euler.md, "A rod
    //       that does not erode") by Tate's regime, decided before the run.
    // SETUP: seed 000's 1250 m/s shot (WHA rod, A 1.5 GPa, into HzB-W), then the same rod
    //        kept elastic (A 20 GPa), then that rod just above its bound.
    // REFERENCE: Tate (1967): a rod penetrates rigidly while Yp >= Rt + rho_t V0^2 / 2, i.e.
    //            up to V0 = sqrt(2 (Yp - Rt) / rho_t).
    use stoss::validate::semi_infinite::{perfectly_plastic, shot};
    use stoss_kernel::PartMaterial;
    let shot = shot(&fixture("")).unwrap();
    let target: PartMaterial = shot.target.material().unwrap().into();
    assert_eq!(shot.spec.rigid_in_tates_model(&target), None);
    let mut spec = shot.spec.clone();
    spec.rod = Some(Box::new(
        perfectly_plastic(shot.rod, 20.0e9, None).unwrap().into(),
    ));
    let bound = spec.rigid_in_tates_model(&target).unwrap();
    let case = spec.rod_target(target.j2().unwrap()).unwrap();
    let tate = (2.0 * (case.rod_strength - case.target_resistance) / case.target_density).sqrt();
    assert!((bound / tate - 1.0).abs() < 1e-14, "{bound} {tate}");
    assert!(bound > spec.velocity, "{bound}");
    spec.velocity = 1.01 * bound;
    assert_eq!(spec.rigid_in_tates_model(&target), None);
}
