//! Truss (axial bar) elements on the nodes of a 3D mesh: reinforcement bars merged with the
//! concrete's nodes, as seed 001 chapter 5 models the beam's Ks 500 ST bars and stirrups
//! (LS-DYNA `*ELEMENT_TRUSS` or `*SECTION_BEAM` with `ELFORM = 3` and a bilinear
//! `*MAT_PLASTIC_KINEMATIC` with isotropic hardening).
//!
//! Per step and bar, from the new nodal positions: logarithmic strain increment
//! `d eps = ln(l_n+1 / l_n)`, elastic predictor `sigma + E d eps`, return onto `fy + H eps_p`
//! (`eps_p += f / (E + H)`), axial force `N = sigma A` with the area constant (small-strain
//! bars), nodal forces `+-N e` along the bar, internal energy `(N_n + N_n+1)/2 (l_n+1 - l_n)`,
//! stable step `l / sqrt(E / rho)`. Half the bar's mass `rho A l0` goes to each node. A bar
//! whose plastic strain reaches its failure strain breaks: from then on it carries no force
//! (LS-DYNA `*MAT_PLASTIC_KINEMATIC`'s `FS`); the energy it absorbed stays booked.

use super::explicit::Vector;
use super::SolverError;

/// A bilinear elastic-plastic bar material with isotropic hardening.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrussMaterial {
    /// Density (kg/m^3).
    pub density: f64,
    /// Young's modulus `E` (Pa).
    pub young_modulus: f64,
    /// Initial yield stress `fy` (Pa).
    pub yield_stress: f64,
    /// Plastic hardening modulus `H = d sigma / d eps_p` (Pa).
    pub hardening_modulus: f64,
    /// Plastic strain at which the bar breaks (`f64::INFINITY`: never).
    pub failure_plastic_strain: f64,
}

impl TrussMaterial {
    /// Ks 500 ST reinforcing steel of seed 001 table 5.4, as the seed models its stirrups:
    /// 7800 kg/m^3, E 207 GPa, fy 586 MPa, hardening modulus 1.0 GPa; unbreakable.
    pub const KS_500_ST: TrussMaterial = TrussMaterial {
        density: 7800.0,
        young_modulus: 207.0e9,
        yield_stress: 586.0e6,
        hardening_modulus: 1.0e9,
        failure_plastic_strain: f64::INFINITY,
    };
}

/// One bar between two nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truss {
    /// Its two nodes.
    pub nodes: [usize; 2],
    /// Cross-section area (m^2).
    pub area: f64,
    /// Material.
    pub material: TrussMaterial,
}

#[derive(Clone, Copy, Debug, Default)]
struct BarState {
    length: f64,
    stress: f64,
    plastic_strain: f64,
    force: f64,
    energy: f64,
    broken: bool,
}

/// The bars of a run: their states and the nodal forces they exert.
pub(crate) struct Trusses<'a> {
    bars: &'a [Truss],
    states: Vec<BarState>,
    /// Force on each node from the bars at the current positions.
    pub(crate) node_force: Vec<Vector>,
    touched: Vec<usize>,
}

fn length(x: &[Vector], [a, b]: [usize; 2]) -> (f64, Vector) {
    let d: Vector = core::array::from_fn(|i| x[b][i] - x[a][i]);
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (l, d)
}

impl<'a> Trusses<'a> {
    /// Check the bars against the mesh (`node_count` nodes at `x`, `dimension` 3) and set
    /// them up stress-free.
    pub(crate) fn new(
        bars: &'a [Truss],
        x: &[Vector],
        dimension: usize,
    ) -> Result<Self, SolverError> {
        if !bars.is_empty() && dimension != 3 {
            return Err(SolverError::Model(
                "truss elements are implemented for 3D models only".into(),
            ));
        }
        let mut states = Vec::with_capacity(bars.len());
        for (i, bar) in bars.iter().enumerate() {
            let m = &bar.material;
            let valid = bar.nodes.iter().all(|&n| n < x.len())
                && bar.nodes[0] != bar.nodes[1]
                && bar.area > 0.0
                && m.density > 0.0
                && m.young_modulus > 0.0
                && m.yield_stress > 0.0
                && m.hardening_modulus >= 0.0
                && m.failure_plastic_strain > 0.0
                && [
                    bar.area,
                    m.density,
                    m.young_modulus,
                    m.yield_stress,
                    m.hardening_modulus,
                ]
                .iter()
                .all(|v| v.is_finite());
            let (l, _) = if valid {
                length(x, bar.nodes)
            } else {
                (0.0, [0.0; 3])
            };
            if !valid || l.is_nan() || l <= 0.0 {
                return Err(SolverError::Model(format!(
                    "truss {i}: nodes {:?} must be two distinct nodes of the mesh ({} nodes) \
                     apart, with a positive area and material constants ({bar:?})",
                    bar.nodes,
                    x.len()
                )));
            }
            states.push(BarState {
                length: l,
                ..BarState::default()
            });
        }
        let mut touched: Vec<usize> = bars.iter().flat_map(|b| b.nodes).collect();
        touched.sort_unstable();
        touched.dedup();
        Ok(Self {
            bars,
            states,
            node_force: vec![[0.0; 3]; x.len()],
            touched,
        })
    }

    /// Add half of each bar's mass to each of its nodes.
    pub(crate) fn add_masses(&self, mass: &mut [f64]) {
        for (bar, state) in self.bars.iter().zip(&self.states) {
            let half = 0.5 * bar.material.density * bar.area * state.length;
            for &n in &bar.nodes {
                mass[n] += half;
            }
        }
    }

    /// The smallest stable step of the bars, `l / sqrt(E / rho)` (infinite without bars).
    pub(crate) fn stable_time_step(&self) -> f64 {
        self.bars
            .iter()
            .zip(&self.states)
            .map(|(bar, state)| {
                state.length / (bar.material.young_modulus / bar.material.density).sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Advance every bar to the positions `x`, in bar order, and recompute the nodal forces
    /// (each node's sum in bar order: the same for any thread count). Returns the bars'
    /// stable step.
    pub(crate) fn step(&mut self, x: &[Vector]) -> Result<f64, SolverError> {
        for &n in &self.touched {
            self.node_force[n] = [0.0; 3];
        }
        for (i, (bar, state)) in self.bars.iter().zip(self.states.iter_mut()).enumerate() {
            let (l, d) = length(x, bar.nodes);
            if state.broken {
                continue;
            }
            if l.is_nan() || l <= 0.0 || !l.is_finite() {
                return Err(SolverError::Model(format!(
                    "truss {i} (nodes {:?}) collapsed to length {l}",
                    bar.nodes
                )));
            }
            let m = &bar.material;
            let increment = libm::log(l / state.length);
            let trial = state.stress + m.young_modulus * increment;
            let flow = m.yield_stress + m.hardening_modulus * state.plastic_strain;
            let excess = trial.abs() - flow;
            let stress = if excess > 0.0 {
                let plastic = excess / (m.young_modulus + m.hardening_modulus);
                state.plastic_strain += plastic;
                trial - trial.signum() * m.young_modulus * plastic
            } else {
                trial
            };
            let mut force = stress * bar.area;
            if state.plastic_strain >= m.failure_plastic_strain {
                state.broken = true;
                force = 0.0;
            }
            state.energy += 0.5 * (state.force + force) * (l - state.length);
            state.stress = stress;
            state.force = force;
            state.length = l;
            let [a, b] = bar.nodes;
            for (k, direction) in d.iter().enumerate() {
                let component = force * direction / l;
                self.node_force[a][k] += component;
                self.node_force[b][k] -= component;
            }
        }
        Ok(self.stable_time_step())
    }

    /// Energy stored and dissipated in the bars (J).
    pub(crate) fn internal_energy(&self) -> f64 {
        self.states.iter().map(|s| s.energy).sum()
    }
}
