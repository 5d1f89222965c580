//! Static springback of an axisymmetric model: the equilibrium an explicit run's state relaxes
//! to once its load has ended and its material has stopped yielding, found by Newton's method
//! instead of by damping the ring-down out. This is LS-DYNA's explicit-to-implicit springback
//! (the explicit run's state handed to a static implicit run, `*INTERFACE_SPRINGBACK_LSDYNA`
//! then `*CONTROL_IMPLICIT_GENERAL`; Maker & Zhu, "A procedure for springback analysis using
//! LS-DYNA", 2001), on stoss's one-point axisymmetric quads.
//!
//! Each Newton iteration, on the free degrees of freedom:
//! - **residual**: the elements' internal forces `f = -sum V B^T sigma`, exactly the forces of
//!   the explicit solver ([`super::axisymmetric::stress_forces`]), and no external load; plus
//!   each element's hourglass force `-k gamma (gamma . u)`, `u` the nodes' displacement since
//!   the run's end: the stiffness form ([`super::HourglassControl::Stiffness`], `k = QH rho
//!   c^2 V sum |b|^2`) with the small [`HOURGLASS_SPRING`] for `QH`, from zero force at the
//!   run's end. The run's viscous control resists only the modes' rate; without any
//!   stiffness the nearly free modes take up zig-zags in the springback that the ring-down
//!   does not have, and with the run's own `QH` (0.1) they stiffen the plate's bending;
//! - **tangent**: per element `V (B^T W C B + K_sigma) + k gamma gamma^T` with `C` the elastic
//!   tangent at the element's state (its shear modulus, and its bulk modulus from the
//!   longitudinal wave speed the kernel reports: the springback unloads; the consistent
//!   tangent of a point that last yielded under thermal softening is indefinite), `W =
//!   diag(1, 1, 1, 2)` (tensor shear), and `K_sigma` the initial-stress (geometric) stiffness
//!   of the current stress (`b_a . sigma . b_b` per direction, `sigma_tt / (16 r_bar^2)` on
//!   the radial pair);
//! - **correction** `K du = f`, solved by a banded Cholesky factorisation, and applied through
//!   the explicit solver's own element step (`Discretisation::element_step`, with the
//!   velocities `du / T` over a pseudo-step `T`): midpoint strain increments, the Jaumann
//!   rotation and the kernel's update, so the stresses follow the kinematics of the run they
//!   continue.
//!
//! It converges when the largest correction falls below the tolerance. Fixed degrees of freedom
//! are the model's velocity constraints, which must hold zero velocity. A model with walls,
//! contact, rigid parts, trusses, a body load or a pressure load that still acts is refused:
//! the springback is that of a free, unloaded structure on its supports.
//!
//! What the run's ring-down would have done and this does not: any yielding during the
//! ring-down (the caller starts the springback only once the material has stopped yielding),
//! and the rate of the ring-down's strains (the pseudo-step `T` sets the strain rate the
//! kernel sees; elastic unloading does not depend on it).

use super::axisymmetric::{
    geometry, hourglass_shape, hourglass_stiffness, stress_forces, AxisymmetricModel,
};
use super::explicit::{Discretisation, ExplicitRun, Vector, MAX_NODES};
use super::SolverError;
use stoss_kernel::{MaterialState, PointModel, StepInput};

/// The springback's hourglass springs, as the stiffness form's coefficient `QH` (a fraction
/// of the element's longitudinal stiffness on its hourglass mode). A thin plate's bending
/// loads the one-point quad's hourglass mode, which the run's viscous control leaves free of
/// any stiffness, so a spring there stiffens the springback: on the clamped plate of
/// tests/solver.rs, the elastic springback stopped short of the stress-free shape by about 10
/// `QH` of its displacement (0.47 of it at 0.1, 1e-3 at 1e-4). Without a spring, the nearly
/// free modes took up zig-zags: the small blast plate of tests/blast.rs ended 2.2 um deeper at
/// the centre than its ring-down, against 13 nm at 1e-5 (10 um at the rim at 0.1, 4 um at
/// 1e-4 to 1e-2, of which the centre's part 3 nm at 1e-4).
pub const HOURGLASS_SPRING: f64 = 1.0e-5;

/// Largest number of entries of the banded stiffness (`degrees of freedom x (bandwidth + 1)`)
/// the springback factorises: 2e7 (160 MB).
pub const MAX_BAND_ENTRIES: usize = 20_000_000;

/// How a springback solve converges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringbackSettings {
    /// The largest nodal correction at which the shape is in equilibrium (m).
    pub tolerance: f64,
    /// Newton iterations allowed before the solve fails.
    pub iterations: usize,
    /// The pseudo-step over which each correction is applied (s): the strain rate the kernel
    /// sees is the correction's strain over it.
    pub pseudo_step: f64,
}

/// The equilibrium found.
#[derive(Clone, Debug)]
pub struct Springback {
    /// Nodal positions at equilibrium.
    pub positions: Vec<Vector>,
    /// Element states at equilibrium.
    pub states: Vec<MaterialState>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// The largest nodal displacement from the run's end to the equilibrium (m).
    pub displacement: f64,
    /// Largest nodal force of the last residual, per radian (N).
    pub residual: f64,
    /// The run's kinetic energy at its end, which the springback discards (J).
    pub kinetic_discarded: f64,
    /// Internal energy released by the springback (J): the run's ring-down would have
    /// dissipated it with the kinetic energy.
    pub internal_released: f64,
}

/// The equilibrium of `model` from the end of its explicit `run` (module documentation).
pub fn springback(
    model: &AxisymmetricModel,
    run: &ExplicitRun,
    settings: &SpringbackSettings,
) -> Result<Springback, SolverError> {
    check_model(model, run.final_time())?;
    if !(settings.tolerance > 0.0 && settings.pseudo_step > 0.0) || settings.iterations == 0 {
        return Err(SolverError::Model(format!(
            "springback: tolerance {} m, pseudo-step {} s and {} iterations must be positive",
            settings.tolerance, settings.pseudo_step, settings.iterations
        )));
    }
    let time = run.final_time();
    let structure = Structure::at(model, &run.positions, &run.states, &run.eroded, time)?;
    let Structure {
        fixed,
        active,
        reference_volume,
        springs,
        ..
    } = &structure;
    let measure = <crate::mesh::QuadMesh as Discretisation>::MEASURE;
    let internal = |states: &[MaterialState]| -> f64 {
        measure
            * states
                .iter()
                .zip(reference_volume.iter())
                .zip(active.iter())
                .filter(|(_, a)| **a)
                .map(|((s, v0), _)| s.internal_energy * v0)
                .sum::<f64>()
    };
    let mut x = run.positions.clone();
    let mut states = run.states.clone();
    let internal_before = internal(&states);
    let start = run.positions.as_slice();
    let mut residual = internal_forces(model, &x, start, &states, active, springs);
    let mut iterations = 0;
    loop {
        if iterations == settings.iterations {
            return Err(SolverError::Model(format!(
                "springback did not converge in {} iterations (largest residual force {:.3e} N \
                 per radian)",
                settings.iterations,
                largest_free(&residual, fixed)
            )));
        }
        iterations += 1;
        let stiffness = structure.tangent(model, &x, &states, time)?;
        let mut correction: Vec<f64> = (0..structure.dofs)
            .map(|i| if fixed[i] { 0.0 } else { residual[i] })
            .collect();
        stiffness.solve(&mut correction);
        let largest = correction.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
        if !largest.is_finite() {
            return Err(SolverError::Model(
                "springback: a correction is not finite".into(),
            ));
        }
        apply_correction(
            model,
            &mut x,
            &mut states,
            &correction,
            active,
            reference_volume,
            settings.pseudo_step,
            time,
        )?;
        residual = internal_forces(model, &x, start, &states, active, springs);
        if largest < settings.tolerance {
            break;
        }
    }
    let displacement = x
        .iter()
        .zip(&run.positions)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
        .fold(0.0, f64::max);
    Ok(Springback {
        residual: largest_free(&residual, fixed),
        internal_released: internal_before - internal(&states),
        kinetic_discarded: run.energy().kinetic,
        positions: x,
        states,
        iterations,
        displacement,
    })
}

/// The circular frequency (rad/s) of the slowest free vibration of `model` about the state
/// `positions`, `states` (`eroded` elements left out) at `time`: the smallest `omega^2` of
/// `K phi = omega^2 M phi` with the springback's tangent `K` (elastic, initial-stress and
/// hourglass-spring parts, module documentation) and the lumped nodal masses `M` (each
/// element's reference mass shared equally by its nodes, as the explicit solver lumps them),
/// both per radian, on the free degrees of freedom. Found by inverse iteration (Bathe,
/// *Finite Element Procedures*, 1996, sec. 11.2.1) from a uniform axial motion, with the
/// Rayleigh quotient `y.M.x / y.M.y` of each iterate `y = K^-1 M x`, an upper bound of
/// `omega^2` that falls to it; converged when it changes by less than
/// [`FREQUENCY_TOLERANCE`] relative. `None` if it does not converge in
/// [`FREQUENCY_ITERATIONS`], or if the tangent is not positive definite (a state that buckles
/// has no slowest vibration). A prescribed motion, walls, contact and the other features a
/// springback refuses are errors, as there.
pub fn fundamental_frequency(
    model: &AxisymmetricModel,
    positions: &[Vector],
    states: &[MaterialState],
    eroded: &[bool],
    time: f64,
) -> Result<Option<f64>, SolverError> {
    check_model(model, time)?;
    let mesh = &model.mesh;
    let structure = Structure::at(model, positions, states, eroded, time)?;
    let Ok(stiffness) = structure.tangent(model, positions, states, time) else {
        return Ok(None);
    };
    let mut mass = vec![0.0; structure.dofs];
    for e in (0..mesh.element_count()).filter(|&e| structure.active[e]) {
        let density = model.materials[mesh.element_material(e).0].density();
        let nodes = mesh.element_nodes(e);
        let share = density * structure.reference_volume[e] / nodes.len() as f64;
        for &n in nodes {
            for d in 0..2 {
                if !structure.fixed[2 * n + d] {
                    mass[2 * n + d] += share;
                }
            }
        }
    }
    let dot_mass = |a: &[f64], b: &[f64]| -> f64 {
        a.iter()
            .zip(b)
            .zip(&mass)
            .map(|((a, b), m)| a * m * b)
            .sum::<f64>()
    };
    let mut x: Vec<f64> = (0..structure.dofs)
        .map(|i| {
            if i % 2 == 1 && mass[i] > 0.0 {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let mut previous = f64::INFINITY;
    for _ in 0..FREQUENCY_ITERATIONS {
        let mut y: Vec<f64> = x.iter().zip(&mass).map(|(x, m)| m * x).collect();
        stiffness.solve(&mut y);
        let (across, norm) = (dot_mass(&y, &x), dot_mass(&y, &y));
        if !(across > 0.0 && norm > 0.0 && norm.is_finite()) {
            return Ok(None);
        }
        let quotient = across / norm;
        let scale = 1.0 / norm.sqrt();
        x = y.iter().map(|y| y * scale).collect();
        if (previous - quotient).abs() <= FREQUENCY_TOLERANCE * quotient {
            return Ok(Some(quotient.sqrt()));
        }
        previous = quotient;
    }
    Ok(None)
}

/// Inverse iterations [`fundamental_frequency`] allows.
pub const FREQUENCY_ITERATIONS: usize = 200;

/// Relative change of the Rayleigh quotient at which [`fundamental_frequency`] has converged.
pub const FREQUENCY_TOLERANCE: f64 = 1.0e-9;

/// What a static solve about a state of an axisymmetric model needs: its degrees of freedom
/// (two a node, `r` then `z`), which of them the model's constraints fix, the band of its
/// stiffness, its live elements with their reference volumes, and each element's hourglass
/// spring ([`HOURGLASS_SPRING`]) at that state.
struct Structure {
    dofs: usize,
    fixed: Vec<bool>,
    bandwidth: usize,
    active: Vec<bool>,
    reference_volume: Vec<f64>,
    springs: Vec<f64>,
}

impl Structure {
    /// The structure of `model` at `positions` and `states` (`eroded` elements left out) at
    /// `time`.
    fn at(
        model: &AxisymmetricModel,
        positions: &[Vector],
        states: &[MaterialState],
        eroded: &[bool],
        time: f64,
    ) -> Result<Self, SolverError> {
        let mesh = &model.mesh;
        let dofs = 2 * positions.len();
        let reference = mesh.reference_positions();
        let reference_volume: Vec<f64> = (0..mesh.element_count())
            .map(|e| mesh.element_volume(e, &reference))
            .collect();
        let active: Vec<bool> = (0..mesh.element_count())
            .map(|e| !eroded.get(e).copied().unwrap_or(false))
            .collect();
        let mut fixed = vec![false; dofs];
        for constraint in &model.constraints {
            for &n in &constraint.nodes {
                fixed[2 * n + constraint.dof] = true;
            }
        }
        let bandwidth = (0..mesh.element_count())
            .filter(|&e| active[e])
            .map(|e| {
                let n = mesh.element_nodes(e);
                let (lo, hi) = (n.iter().min(), n.iter().max());
                match (lo, hi) {
                    (Some(lo), Some(hi)) => 2 * (hi - lo) + 1,
                    _ => 0,
                }
            })
            .max()
            .unwrap_or(0);
        if dofs.saturating_mul(bandwidth + 1) > MAX_BAND_ENTRIES {
            return Err(SolverError::Model(format!(
                "springback: {dofs} degrees of freedom with a bandwidth of {bandwidth} exceed the \
                 {MAX_BAND_ENTRIES} entries the banded solve allows"
            )));
        }
        let mut springs = vec![0.0; mesh.element_count()];
        for e in (0..mesh.element_count()).filter(|&e| active[e]) {
            let material = &model.materials[mesh.element_material(e).0];
            let (longitudinal, _) = elastic_moduli(model, e, &states[e], material, time)?;
            let geom = geometry(mesh.corners(e, positions));
            springs[e] = hourglass_stiffness(
                HOURGLASS_SPRING,
                1.0,
                1.0,
                geom.area * geom.mean_radius,
                &geom,
            ) * longitudinal;
        }
        Ok(Self {
            dofs,
            fixed,
            bandwidth,
            active,
            reference_volume,
            springs,
        })
    }

    /// The tangent stiffness per radian at `x` and `states`, assembled over the live elements
    /// (unit diagonal on the fixed degrees of freedom) and factorised.
    fn tangent(
        &self,
        model: &AxisymmetricModel,
        x: &[Vector],
        states: &[MaterialState],
        time: f64,
    ) -> Result<Banded, SolverError> {
        let mesh = &model.mesh;
        let fixed = &self.fixed;
        let mut stiffness = Banded::new(self.dofs, self.bandwidth);
        for e in (0..mesh.element_count()).filter(|&e| self.active[e]) {
            let material = &model.materials[mesh.element_material(e).0];
            let k = element_stiffness(model, e, x, &states[e], material, time, self.springs[e])?;
            let n = mesh.element_nodes(e);
            for (a, row) in k.iter().enumerate() {
                for (b, &value) in row.iter().enumerate() {
                    let (i, j) = (2 * n[a / 2] + a % 2, 2 * n[b / 2] + b % 2);
                    if j <= i && !fixed[i] && !fixed[j] {
                        stiffness.add(i, j, value);
                    }
                }
            }
        }
        for i in (0..self.dofs).filter(|&i| fixed[i]) {
            stiffness.add(i, i, 1.0);
        }
        stiffness.factorise().map_err(|dof| {
            SolverError::Model(format!(
                "springback: the stiffness is not positive definite at node {} ({}; the \
                 structure is unsupported or buckles)",
                dof / 2,
                if dof % 2 == 0 { "r" } else { "z" }
            ))
        })?;
        Ok(stiffness)
    }
}

/// Refuse what the springback does not model (module documentation).
fn check_model(model: &AxisymmetricModel, time: f64) -> Result<(), SolverError> {
    let refuse = |what: &str| {
        Err(SolverError::Model(format!(
            "springback: the model has {what}, which a static springback does not model"
        )))
    };
    if !model.walls.is_empty() {
        return refuse("rigid walls");
    }
    if !model.contacts.is_empty() || model.eroding_contact.is_some() {
        return refuse("contact");
    }
    if !model.node_contacts.is_empty() {
        return refuse("node-to-node contact");
    }
    if !model.rigid_parts.is_empty() {
        return refuse("rigid parts");
    }
    if !model.trusses.is_empty() {
        return refuse("trusses");
    }
    if model.body_acceleration.is_some() {
        return refuse("a body load");
    }
    for constraint in &model.constraints {
        let moving = constraint.velocity.at(time) != 0.0
            || constraint
                .velocity
                .points
                .iter()
                .any(|p| p.0 > time && p.1 != 0.0);
        if moving {
            return refuse("a prescribed velocity that is not zero");
        }
    }
    for load in &model.pressure_loads {
        let history = load.history.read().map_err(|_| {
            SolverError::Model("springback: a pressure load's lock is poisoned".into())
        })?;
        let still_acting = history.values.iter().enumerate().any(|(k, row)| {
            (k + 1) as f64 * history.interval > time && row.iter().any(|&p| p != 0.0)
        });
        if still_acting && load.scale != 0.0 {
            return refuse("a pressure load that still acts");
        }
    }
    Ok(())
}

/// The assembled internal forces per radian (two entries a node, `r` then `z`) at `x`: the
/// stresses' and the hourglass springs' (`springs[e]`, stretched from `start`).
fn internal_forces(
    model: &AxisymmetricModel,
    x: &[Vector],
    start: &[Vector],
    states: &[MaterialState],
    active: &[bool],
    springs: &[f64],
) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut forces = vec![0.0; 2 * x.len()];
    let mut element = [[0.0; 3]; MAX_NODES];
    for e in (0..mesh.element_count()).filter(|&e| active[e]) {
        let s = states[e].stress;
        let corners = mesh.corners(e, x);
        let geom = geometry(corners);
        stress_forces(&geom, [s[0], s[1], s[2], s[3]], &mut element);
        let gamma = hourglass_shape(&corners, &geom);
        let nodes = mesh.element_nodes(e);
        let q: [f64; 2] = core::array::from_fn(|d| {
            (0..4)
                .map(|k| gamma[k] * (x[nodes[k]][d] - start[nodes[k]][d]))
                .sum::<f64>()
        });
        for (k, &n) in nodes.iter().enumerate() {
            forces[2 * n] += element[k][0] - springs[e] * q[0] * gamma[k];
            forces[2 * n + 1] += element[k][1] - springs[e] * q[1] * gamma[k];
        }
    }
    forces
}

/// The largest force of `residual` on a free degree of freedom.
fn largest_free(residual: &[f64], fixed: &[bool]) -> f64 {
    residual
        .iter()
        .zip(fixed)
        .filter(|(_, f)| !**f)
        .fold(0.0, |m, (r, _)| m.max(r.abs()))
}

/// Element `e`'s 8 x 8 tangent stiffness per radian at `x` (degrees of freedom `r0 z0 r1 z1
/// ...`; module documentation).
fn element_stiffness(
    model: &AxisymmetricModel,
    e: usize,
    x: &[Vector],
    state: &MaterialState,
    material: &stoss_kernel::Material,
    time: f64,
    spring: f64,
) -> Result<[[f64; 8]; 8], SolverError> {
    let geom = geometry(model.mesh.corners(e, x));
    let volume = geom.area * geom.mean_radius;
    let (longitudinal, shear) = elastic_moduli(model, e, state, material, time)?;
    let lame = longitudinal - 2.0 * shear;
    let mut c = [[0.0; 4]; 4];
    for (i, row) in c.iter_mut().enumerate().take(3) {
        for (j, value) in row.iter_mut().enumerate().take(3) {
            *value = lame + if i == j { 2.0 * shear } else { 0.0 };
        }
    }
    c[3][3] = 2.0 * shear;
    // Strain rows [rr, zz, tt, rz (tensor)] of each degree of freedom.
    let hoop = 0.25 / geom.mean_radius;
    let mut b = [[0.0; 8]; 4];
    for k in 0..4 {
        b[0][2 * k] = geom.b_r[k];
        b[1][2 * k + 1] = geom.b_z[k];
        b[2][2 * k] = hoop;
        b[3][2 * k] = 0.5 * geom.b_z[k];
        b[3][2 * k + 1] = 0.5 * geom.b_r[k];
    }
    let weight = [1.0, 1.0, 1.0, 2.0];
    // W C B (4 x 8).
    let mut wcb = [[0.0; 8]; 4];
    for (i, row) in wcb.iter_mut().enumerate() {
        for (a, value) in row.iter_mut().enumerate() {
            *value = weight[i] * (0..4).map(|j| c[i][j] * b[j][a]).sum::<f64>();
        }
    }
    let s = state.stress;
    let mut k = [[0.0; 8]; 8];
    for a in 0..8 {
        for bb in 0..8 {
            k[a][bb] = volume * (0..4).map(|i| b[i][a] * wcb[i][bb]).sum::<f64>();
        }
    }
    // Initial-stress stiffness.
    for p in 0..4 {
        for q in 0..4 {
            let g = volume
                * (s[0] * geom.b_r[p] * geom.b_r[q]
                    + s[3] * (geom.b_r[p] * geom.b_z[q] + geom.b_z[p] * geom.b_r[q])
                    + s[1] * geom.b_z[p] * geom.b_z[q]);
            k[2 * p][2 * q] += g + volume * s[2] * hoop * hoop;
            k[2 * p + 1][2 * q + 1] += g;
        }
    }
    // The hourglass spring.
    let gamma = hourglass_shape(&model.mesh.corners(e, x), &geom);
    for p in 0..4 {
        for q in 0..4 {
            let value = spring * gamma[p] * gamma[q];
            k[2 * p][2 * q] += value;
            k[2 * p + 1][2 * q + 1] += value;
        }
    }
    Ok(k)
}

/// Element `e`'s elastic moduli at `state`: the longitudinal `rho c^2` (from the wave speed
/// the kernel reports over a zero increment) and the shear modulus (Pa); `K = rho c^2 - 4G/3`.
fn elastic_moduli(
    model: &AxisymmetricModel,
    e: usize,
    state: &MaterialState,
    material: &stoss_kernel::Material,
    time: f64,
) -> Result<(f64, f64), SolverError> {
    let mut probe = *state;
    let output = material
        .update(
            &mut probe,
            &StepInput {
                strain_increment: [0.0; 6],
                dt: 1.0,
                relative_volume: state.relative_volume,
            },
        )
        .map_err(|error| SolverError::Update {
            element: e,
            part: model.mesh.parts[model.mesh.element_part[e]].name.clone(),
            time,
            relative_volume: state.relative_volume,
            error,
        })?;
    let density = material.density() / state.relative_volume;
    Ok((
        density * output.wave_speed * output.wave_speed,
        material.shear_modulus(),
    ))
}

/// Move the nodes by `correction` and advance every element's state through the explicit
/// solver's element step over the pseudo-step.
#[allow(clippy::too_many_arguments)]
fn apply_correction(
    model: &AxisymmetricModel,
    x: &mut [Vector],
    states: &mut [MaterialState],
    correction: &[f64],
    active: &[bool],
    reference_volume: &[f64],
    pseudo_step: f64,
    time: f64,
) -> Result<(), SolverError> {
    let mesh = &model.mesh;
    let x_new: Vec<Vector> = x
        .iter()
        .enumerate()
        .map(|(n, p)| [p[0] + correction[2 * n], p[1] + correction[2 * n + 1], p[2]])
        .collect();
    let v: Vec<Vector> = (0..x.len())
        .map(|n| {
            [
                correction[2 * n] / pseudo_step,
                correction[2 * n + 1] / pseudo_step,
                0.0,
            ]
        })
        .collect();
    let mut forces = [[0.0; 3]; MAX_NODES];
    for e in (0..mesh.element_count()).filter(|&e| active[e]) {
        let mut hourglass = [0.0; 2];
        mesh.element_step(
            e,
            x,
            &x_new,
            &v,
            &mut states[e],
            &mut hourglass,
            &model.materials[mesh.element_material(e).0],
            reference_volume[e],
            pseudo_step,
            &model.settings,
            time,
            &mut forces,
        )?;
    }
    x.copy_from_slice(&x_new);
    Ok(())
}

/// A symmetric banded matrix, its lower band stored by rows, factorised in place by Cholesky.
struct Banded {
    size: usize,
    bandwidth: usize,
    /// `values[i * (bandwidth + 1) + (i - j)]` = `A[i][j]`, `j <= i`, `i - j <= bandwidth`.
    values: Vec<f64>,
}

impl Banded {
    fn new(size: usize, bandwidth: usize) -> Self {
        Self {
            size,
            bandwidth,
            values: vec![0.0; size * (bandwidth + 1)],
        }
    }

    /// Index of `A[i][j]`, `j <= i <= j + bandwidth`.
    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        i * (self.bandwidth + 1) + (i - j)
    }

    /// `A[i][j] += value` for `j <= i` (callers keep within the band).
    fn add(&mut self, i: usize, j: usize, value: f64) {
        let k = self.at(i, j);
        self.values[k] += value;
    }

    /// `A = L L^T` in place; the degree of freedom whose pivot is not positive on failure.
    fn factorise(&mut self) -> Result<(), usize> {
        let w = self.bandwidth;
        for i in 0..self.size {
            let first = i.saturating_sub(w);
            for j in first..=i {
                let start = first.max(j.saturating_sub(w));
                let mut sum = self.values[self.at(i, j)];
                for k in start..j {
                    sum -= self.values[self.at(i, k)] * self.values[self.at(j, k)];
                }
                if j == i {
                    if sum.is_nan() || sum <= 0.0 {
                        return Err(i);
                    }
                    let at = self.at(i, i);
                    self.values[at] = sum.sqrt();
                } else {
                    let at = self.at(i, j);
                    self.values[at] = sum / self.values[self.at(j, j)];
                }
            }
        }
        Ok(())
    }

    /// Solve `L L^T y = b` in place (after [`Self::factorise`]).
    #[allow(clippy::needless_range_loop)] // the band's indices address `values` and `b` alike
    fn solve(&self, b: &mut [f64]) {
        let w = self.bandwidth;
        for i in 0..self.size {
            let mut sum = b[i];
            for k in i.saturating_sub(w)..i {
                sum -= self.values[self.at(i, k)] * b[k];
            }
            b[i] = sum / self.values[self.at(i, i)];
        }
        for i in (0..self.size).rev() {
            let mut sum = b[i];
            for k in i + 1..self.size.min(i + w + 1) {
                sum -= self.values[self.at(k, i)] * b[k];
            }
            b[i] = sum / self.values[self.at(i, i)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_banded_cholesky_solves_a_band_matrix() {
        // A tridiagonal SPD matrix with one second off-diagonal: band 2.
        let n = 7;
        let mut a = Banded::new(n, 2);
        let mut dense = vec![vec![0.0; n]; n];
        for i in 0..n {
            for (d, v) in [(0, 4.0 + i as f64), (1, -1.0), (2, 0.5)] {
                if i >= d {
                    a.add(i, i - d, v);
                    dense[i][i - d] = v;
                    dense[i - d][i] = v;
                }
            }
        }
        let x: Vec<f64> = (0..n).map(|i| 1.0 + 0.3 * i as f64).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| dense[i][j] * x[j]).sum())
            .collect();
        a.factorise().unwrap();
        a.solve(&mut b);
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-13, "{got} against {want}");
        }
    }

    #[test]
    fn an_indefinite_matrix_names_its_pivot() {
        let mut a = Banded::new(3, 1);
        a.add(0, 0, 1.0);
        a.add(1, 0, 2.0);
        a.add(1, 1, 1.0);
        a.add(2, 2, 1.0);
        assert_eq!(a.factorise(), Err(1));
    }
}
