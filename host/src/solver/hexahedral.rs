//! 3D 8-node hexahedra, one-point integration.
//!
//! - gradients at the centroid, `B_a = J^-T dN_a/dxi (0)`, volume `V = 8 det J(0)` (exact for
//!   parallelepipeds); forces `f_a = -V sigma B_a`, the derivative of the internal power
//!   computed with the same `B` and `V`, so work and kinetic energy balance;
//! - Flanagan-Belytschko viscous hourglass control with the four base vectors
//!   `eta zeta, zeta xi, xi eta, xi eta zeta`: `f = -QH/4 rho c V^(2/3) sum q gamma`;
//! - linear + quadratic bulk viscosity with `L = V^(1/3)`;
//! - Jaumann rotation `sigma += (W sigma - sigma W) dt` before the kernel update;
//! - stable length `V / largest face area` (LS-DYNA's solid element choice).
//!
//! Node order: bottom face counter-clockwise seen from +z (xi, eta, zeta signs
//! (-,-,-) (+,-,-) (+,+,-) (-,+,-)), then the top face in the same order.

use super::explicit::{
    Discretisation, ElementStep, ExplicitModel, ExplicitRun, HourglassStress, Vector, MAX_NODES,
};
use super::{SolverError, SolverSettings};
use crate::mesh::HexMesh;
use stoss_kernel::{MaterialState, PointModel, StepInput};

/// A 3D model.
pub type HexModel = ExplicitModel<HexMesh>;

/// The result of a 3D run.
pub type HexRun = ExplicitRun;

/// Natural-coordinate signs of the nodes.
const SIGNS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Hourglass base vectors `eta zeta, zeta xi, xi eta, xi eta zeta` at the nodes.
const HOURGLASS: [[f64; 8]; 4] = [
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
];

const FACES: [[usize; 4]; 6] = [
    [0, 1, 2, 3],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

struct Geometry {
    volume: f64,
    /// `b[a][i] = dN_a / dx_i` at the centroid.
    b: [[f64; 3]; 8],
}

fn geometry(x: &[Vector; 8]) -> Geometry {
    let mut j = [[0.0; 3]; 3];
    for (a, sign) in SIGNS.iter().enumerate() {
        for (i, row) in j.iter_mut().enumerate() {
            for (k, entry) in row.iter_mut().enumerate() {
                *entry += 0.125 * sign[k] * x[a][i];
            }
        }
    }
    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    // inverse[k][i] = (J^-1)_{k i}
    let inverse = [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
        ],
    ];
    let mut b = [[0.0; 3]; 8];
    for (a, sign) in SIGNS.iter().enumerate() {
        for i in 0..3 {
            // dN_a/dx_i = sum_k dN_a/dxi_k (J^-1)_{k i}, dN_a/dxi_k = sign_k / 8.
            b[a][i] = (0..3).map(|k| 0.125 * sign[k] * inverse[k][i]).sum();
        }
    }
    Geometry {
        volume: 8.0 * det,
        b,
    }
}

fn largest_face_area(x: &[Vector; 8]) -> f64 {
    FACES
        .iter()
        .map(|f| {
            let d1: Vector = core::array::from_fn(|i| x[f[2]][i] - x[f[0]][i]);
            let d2: Vector = core::array::from_fn(|i| x[f[3]][i] - x[f[1]][i]);
            let c = [
                d1[1] * d2[2] - d1[2] * d2[1],
                d1[2] * d2[0] - d1[0] * d2[2],
                d1[0] * d2[1] - d1[1] * d2[0],
            ];
            0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
        })
        .fold(0.0, f64::max)
}

/// Symmetric stress in Voigt order as a 3x3 matrix, and back.
fn matrix(s: &[f64; 6]) -> [[f64; 3]; 3] {
    [[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]]
}

impl HexMesh {
    fn corners(&self, e: usize, x: &[Vector]) -> [Vector; 8] {
        self.elements[e].map(|n| x[n])
    }
}

impl Discretisation for HexMesh {
    const DIMENSION: usize = 3;
    const NODES: usize = 8;
    const MEASURE: f64 = 1.0;
    const AXIAL_COMPONENT: usize = 2;

    fn reference_positions(&self) -> Vec<Vector> {
        self.nodes.clone()
    }

    fn element_count(&self) -> usize {
        self.elements.len()
    }

    fn element_nodes(&self, e: usize) -> &[usize] {
        &self.elements[e]
    }

    fn element_material(&self, e: usize) -> (usize, &str) {
        let part = &self.parts[self.element_part[e]];
        (part.material, &part.name)
    }

    fn element_part(&self, e: usize) -> usize {
        self.element_part[e]
    }

    fn part_count(&self) -> usize {
        self.parts.len()
    }

    fn element_volume(&self, e: usize, x: &[Vector]) -> f64 {
        geometry(&self.corners(e, x)).volume
    }

    fn element_time_step(&self, e: usize, x: &[Vector], wave_speed: f64) -> f64 {
        let corners = self.corners(e, x);
        geometry(&corners).volume / largest_face_area(&corners) / wave_speed
    }

    fn element_step<P: PointModel>(
        &self,
        e: usize,
        x: &[Vector],
        x_new: &[Vector],
        v: &[Vector],
        state: &mut MaterialState,
        _hourglass: &mut HourglassStress,
        material: &P,
        reference_volume: f64,
        dt: f64,
        settings: &SolverSettings,
        time: f64,
        forces: &mut [Vector; MAX_NODES],
    ) -> Result<ElementStep, SolverError> {
        let element = self.elements[e];
        let nodes_new = self.corners(e, x_new);
        let nodes_mid: [Vector; 8] =
            element.map(|n| core::array::from_fn(|i| 0.5 * (x[n][i] + x_new[n][i])));
        let vel: [Vector; 8] = element.map(|n| v[n]);
        let mid = geometry(&nodes_mid);
        let new = geometry(&nodes_new);
        if !(mid.volume > 0.0 && new.volume > 0.0) {
            return Err(SolverError::InvertedElement {
                element: e,
                part: self.parts[self.element_part[e]].name.clone(),
                time,
            });
        }
        // Velocity gradient L[i][j] = d v_i / d x_j at mid-step.
        let mut grad = [[0.0; 3]; 3];
        for (velocity, b) in vel.iter().zip(&mid.b) {
            for (row, v_i) in grad.iter_mut().zip(velocity) {
                for (entry, b_j) in row.iter_mut().zip(b) {
                    *entry += v_i * b_j;
                }
            }
        }
        let d = |i: usize, j: usize| 0.5 * (grad[i][j] + grad[j][i]);
        let w = |i: usize, j: usize| 0.5 * (grad[i][j] - grad[j][i]);
        let volumetric_rate = grad[0][0] + grad[1][1] + grad[2][2];
        let old_relative_volume = state.relative_volume;
        // Jaumann: sigma += (W sigma - sigma W) dt.
        let sigma = matrix(&state.stress);
        let mut rotated = sigma;
        for (i, row) in rotated.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                let spin: f64 = (0..3)
                    .map(|k| w(i, k) * sigma[k][j] - sigma[i][k] * w(k, j))
                    .sum();
                *entry += spin * dt;
            }
        }
        state.stress = [
            rotated[0][0],
            rotated[1][1],
            rotated[2][2],
            rotated[0][1],
            rotated[1][2],
            rotated[2][0],
        ];
        let input = StepInput {
            strain_increment: [
                d(0, 0) * dt,
                d(1, 1) * dt,
                d(2, 2) * dt,
                d(0, 1) * dt,
                d(1, 2) * dt,
                d(2, 0) * dt,
            ],
            dt,
            relative_volume: new.volume / reference_volume,
        };
        let output = material
            .update(state, &input)
            .map_err(|error| SolverError::Update {
                element: e,
                part: self.parts[self.element_part[e]].name.clone(),
                time,
                relative_volume: input.relative_volume,
                error,
            })?;
        let density = material.density() / input.relative_volume;
        let viscous_pressure = settings.bulk_viscosity.pressure(
            density,
            libm::cbrt(new.volume),
            volumetric_rate,
            output.wave_speed,
        );
        let mid_volume = 0.5 * (old_relative_volume + input.relative_volume) * reference_volume;
        let viscous_work = -viscous_pressure * volumetric_rate * dt * mid_volume;
        let mut stress = matrix(&state.stress);
        for (i, row) in stress.iter_mut().enumerate() {
            row[i] -= viscous_pressure;
        }
        for (a, force) in forces.iter_mut().enumerate() {
            for i in 0..3 {
                force[i] = -new.volume * (0..3).map(|j| stress[i][j] * new.b[a][j]).sum::<f64>();
            }
        }
        // Flanagan-Belytschko viscous hourglass control.
        let kappa = 0.25
            * settings.hourglass_coefficient
            * density
            * output.wave_speed
            * libm::pow(new.volume, 2.0 / 3.0);
        let mut hourglass_power = 0.0;
        for h in &HOURGLASS {
            let hx: [f64; 3] =
                core::array::from_fn(|i| (0..8).map(|a| h[a] * nodes_new[a][i]).sum());
            let gamma: [f64; 8] =
                core::array::from_fn(|a| h[a] - (0..3).map(|i| hx[i] * new.b[a][i]).sum::<f64>());
            let q: [f64; 3] = core::array::from_fn(|i| (0..8).map(|a| gamma[a] * vel[a][i]).sum());
            for (a, force) in forces.iter_mut().enumerate() {
                for i in 0..3 {
                    force[i] -= kappa * q[i] * gamma[a];
                }
            }
            hourglass_power += kappa * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        }
        let characteristic = new.volume / largest_face_area(&nodes_new);
        Ok(ElementStep {
            hourglass_power,
            viscous_work,
            stable_dt: settings.stable_time_step(
                characteristic,
                output.wave_speed,
                volumetric_rate,
            ),
        })
    }
}
