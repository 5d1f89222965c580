//! Verification of the blast-load solver (host/src/blast): the detonation of a C-4 column
//! against the JWL's Chapman-Jouguet state, Sod's shock tube against the exact Riemann
//! solution, the Sedov point blast against its self-similar solution, and the reflected
//! impulse of a free-air TNT burst against Kingery-Bulmash.

use stoss::blast::euler::{Boundaries, Boundary, Conserved, EulerSolver, Floors, Geometry, Grid};
use stoss::blast::fluid::Fluids;
use stoss_kernel::eos::Jwl;

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
