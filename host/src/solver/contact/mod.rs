//! Penalty contact between deformable parts: node-to-segment, **2D only** (axisymmetric
//! `(r, z)` models; a 3D model with contact pairs is rejected); and the node-to-node contact of
//! two faces meshed on the same planes, 2D or 3D ([`node_to_node`]).
//!
//! A [`ContactPair`] lists *slave* nodes and the *master* segments they may not cross. One pass:
//! only slave nodes are checked against master segments (make the finer surface the slave).
//!
//! **Segment orientation.** A master segment `[a, b]` follows the master body's boundary
//! **counter-clockwise in the `(r, z)` plane** (the body on the left when walking from `a` to
//! `b`), the orientation of the mesh's own element edges. Its outward normal is then the
//! tangent turned clockwise: `t = (x_b - x_a) / |x_b - x_a|`, `n = (t_z, -t_r)`. For a
//! [`crate::mesh::QuadMesh::block`] the top face runs from the outer radius to the axis
//! (`n = +z`) and the bottom face from the axis outwards (`n = -z`).
//!
//! **Detection.** Each step, for every slave node in order, the nearest master segment (the
//! smallest distance to the node's projection, clamped to the segment; projections more than
//! 0.1 % of the segment length beyond its ends do not count) gives the signed gap
//! `g = (x_s - x_p) . n` with `x_p = (1 - xi) x_a + xi x_b`. The node is in contact when
//! `-L_segment < g < 0`.
//!
//! **Normal force: penalty on the nodal mass (LS-DYNA SOFT = 1 style)**, not on the element
//! stiffness (SOFT = 0): `f_n = k (-g)` with `k = s m* / dt0^2`, `s` the penalty scale
//! (default 0.1), `dt0` the run's first time step and `m* = m_s m_seg / (m_s + m_seg)` the
//! reduced mass of the slave node and the segment (`m_seg` the mean of its two nodal masses).
//! The contact spring's frequency is then `sqrt(k/m*) = sqrt(s)/dt0`, so `omega dt <= sqrt(s)`
//! (0.32 for the default) whatever the materials: far inside central-difference stability
//! (`omega dt < 2`), with penetrations of about 1-3 % of an element under steel flow
//! stresses. `k` is fixed for the run, so the normal force is conservative.
//!
//! **Friction: Coulomb with a stick limit.** The tangential force opposes the relative
//! tangential velocity `v_t` of the node and the segment point (at `v_{n-1/2}`), with magnitude
//! `min(mu f_n, |v_t| / (w dt))`; the second term, `w = 1/m_s + (1-xi)^2/m_a + xi^2/m_b` the
//! inverse effective mass, is the force that just stops the sliding within the step (stick),
//! so friction never reverses the slip.
//!
//! The reaction goes to the segment's nodes in the proportions `1 - xi` and `xi`, so forces
//! (and momentum) balance exactly. Forces are computed serially in the fixed order of the
//! pairs and of their slave nodes and segments: bit-identical for any thread count.
//!
//! **Energy.** The time loop adds the forces before the velocity update and books their work
//! as `EnergyBalance::contact` in the central-difference-consistent form
//! `-dt_avg sum f . (v_{n-1/2} + v_{n+1/2}) / 2` (the same form as the walls'), so the penalty
//! energy stored while in contact and the friction dissipation close the balance.

mod eroding;
pub mod node_to_node;

pub(crate) use eroding::ErodingSurfaces;
pub use eroding::{ContactStatistics, PartImpulse};
pub use eroding::{ErodingContact, DEFAULT_ERODING_PENALTY_SCALE};
pub use node_to_node::NodeToNodeContact;

use super::explicit::Vector;
use super::SolverError;

/// Penalty scale `s` of LS-DYNA's SOFT = 1 style stiffness `k = s m / dt^2`.
pub const DEFAULT_PENALTY_SCALE: f64 = 0.1;

/// Projections beyond a segment's ends by more than this fraction of its length do not count.
const END_TOLERANCE: f64 = 1.0e-3;

/// A slave node set and the master segments it may not cross (see the module notes for the
/// segment orientation).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair {
    /// Slave node indices.
    pub slave_nodes: Vec<usize>,
    /// Master segments `[a, b]`, counter-clockwise along the master body's boundary, so that
    /// the outward normal is `(t_z, -t_r)`.
    pub master_segments: Vec<[usize; 2]>,
    /// Coulomb friction coefficient (0 = frictionless).
    pub friction: f64,
    /// Penalty scale `s` in `k = s m* / dt0^2` (0 < s <= 1; default 0.1).
    pub penalty_scale: f64,
}

impl ContactPair {
    /// A frictionless pair with the default penalty scale.
    pub fn new(slave_nodes: Vec<usize>, master_segments: Vec<[usize; 2]>) -> Self {
        Self {
            slave_nodes,
            master_segments,
            friction: 0.0,
            penalty_scale: DEFAULT_PENALTY_SCALE,
        }
    }

    /// The same pair with Coulomb friction `mu`.
    pub fn with_friction(mut self, mu: f64) -> Self {
        self.friction = mu;
        self
    }

    /// The same pair with penalty scale `s` (`0 < s <= 1`).
    pub fn with_penalty_scale(mut self, s: f64) -> Self {
        self.penalty_scale = s;
        self
    }
}

/// The contact of one run: the pairs, the nodal masses and the first time step, and the force
/// buffer of the current step.
#[derive(Debug)]
pub(crate) struct PenaltyContact<'a> {
    pairs: &'a [ContactPair],
    mass: Vec<f64>,
    /// `1 / dt0^2`.
    inverse_dt2: f64,
    /// Nodes that can carry a contact force, sorted and unique.
    nodes: Vec<usize>,
    /// Contact forces of the current step (per node; zero outside `nodes`).
    forces: Vec<Vector>,
}

impl<'a> PenaltyContact<'a> {
    /// Check the pairs against the model and prepare the buffers (nothing is allocated when
    /// there are no pairs).
    pub(crate) fn new(
        pairs: &'a [ContactPair],
        mass: &[f64],
        dt0: f64,
        dimension: usize,
    ) -> Result<Self, SolverError> {
        let node_count = mass.len();
        if !pairs.is_empty() && dimension != 2 {
            return Err(SolverError::Model(
                "penalty contact is implemented for 2D (axisymmetric) models only".into(),
            ));
        }
        let mut nodes = Vec::new();
        for (p, pair) in pairs.iter().enumerate() {
            let bad = |what: String| SolverError::Model(format!("contact pair {p}: {what}"));
            if !(pair.friction >= 0.0 && pair.friction.is_finite()) {
                return Err(bad(format!("friction must be >= 0, got {}", pair.friction)));
            }
            if !(pair.penalty_scale > 0.0 && pair.penalty_scale <= 1.0) {
                return Err(bad(format!(
                    "penalty scale must be in (0, 1], got {}",
                    pair.penalty_scale
                )));
            }
            for &n in pair
                .slave_nodes
                .iter()
                .chain(pair.master_segments.iter().flatten())
            {
                if n >= node_count {
                    return Err(bad(format!("node {n} does not exist")));
                }
                nodes.push(n);
            }
            if let Some(segment) = pair.master_segments.iter().find(|s| s[0] == s[1]) {
                return Err(bad(format!("degenerate segment {segment:?}")));
            }
        }
        nodes.sort_unstable();
        nodes.dedup();
        let active = !pairs.is_empty();
        Ok(Self {
            pairs,
            mass: if active { mass.to_vec() } else { Vec::new() },
            inverse_dt2: 1.0 / (dt0 * dt0),
            nodes,
            forces: if active {
                vec![[0.0; 3]; node_count]
            } else {
                Vec::new()
            },
        })
    }

    /// Whether the model has contact pairs.
    pub(crate) fn is_active(&self) -> bool {
        !self.pairs.is_empty()
    }

    /// Compute the contact forces at positions `x` with velocities `v` (`v_{n-1/2}`) for a
    /// velocity update over `dt`, and add them to `force`.
    pub(crate) fn add_forces(&mut self, x: &[Vector], v: &[Vector], dt: f64, force: &mut [Vector]) {
        if !self.is_active() {
            return;
        }
        for &n in &self.nodes {
            self.forces[n] = [0.0; 3];
        }
        for pair in self.pairs {
            for &s in &pair.slave_nodes {
                if let Some(hit) = nearest(pair, s, x) {
                    self.apply(pair, s, &hit, v, dt);
                }
            }
        }
        for &n in &self.nodes {
            force[n][0] += self.forces[n][0];
            force[n][1] += self.forces[n][1];
        }
    }

    /// Energy absorbed by contact over the step (the negative of the contact forces' work),
    /// per unit integration measure: `-dt sum f . (v_old + v_new) / 2`.
    pub(crate) fn absorbed(&self, v_old: &[Vector], v_new: &[Vector], dt: f64) -> f64 {
        absorbed_work(&self.forces, &self.nodes, v_old, v_new, dt)
    }

    fn apply(&mut self, pair: &ContactPair, s: usize, hit: &Hit, v: &[Vector], dt: f64) {
        let [a, b] = pair.master_segments[hit.segment];
        let law = PenaltyLaw {
            penalty_scale: pair.penalty_scale,
            friction: pair.friction,
            inverse_dt2: self.inverse_dt2,
        };
        if let Some(f) = law.force(&self.mass, [s, a, b], hit, v, dt) {
            distribute(&mut self.forces, [s, a, b], hit.xi, f);
        }
    }
}

/// The penalty and friction law of one slave node against one master segment (see the
/// module notes): `k = s m* / dt0^2` on the reduced mass, Coulomb friction up to the stick
/// limit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PenaltyLaw {
    /// Penalty scale `s`.
    pub penalty_scale: f64,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// `1 / dt0^2`.
    pub inverse_dt2: f64,
}

impl PenaltyLaw {
    /// The force on slave node `s` penetrating segment `[a, b]` (`nodes = [s, a, b]`), or
    /// `None` if a node carries no mass.
    pub(crate) fn force(
        &self,
        mass: &[f64],
        nodes: [usize; 3],
        hit: &Hit,
        v: &[Vector],
        dt: f64,
    ) -> Option<[f64; 2]> {
        let [s, a, b] = nodes;
        let (m_s, m_a, m_b) = (mass[s], mass[a], mass[b]);
        if m_s <= 0.0 || m_a <= 0.0 || m_b <= 0.0 {
            return None;
        }
        let xi = hit.xi;
        let m_segment = 0.5 * (m_a + m_b);
        let reduced = m_s * m_segment / (m_s + m_segment);
        let normal_force = self.penalty_scale * reduced * self.inverse_dt2 * (-hit.gap);
        let n = hit.normal;
        let t = [-n[1], n[0]];
        let mut f = [normal_force * n[0], normal_force * n[1]];
        if self.friction > 0.0 && dt > 0.0 {
            let relative: [f64; 2] =
                core::array::from_fn(|d| v[s][d] - (1.0 - xi) * v[a][d] - xi * v[b][d]);
            let slip = relative[0] * t[0] + relative[1] * t[1];
            let inverse_mass = 1.0 / m_s + (1.0 - xi) * (1.0 - xi) / m_a + xi * xi / m_b;
            add_coulomb(
                &mut f,
                self.friction,
                normal_force,
                slip,
                inverse_mass,
                dt,
                t,
            );
        }
        Some(f)
    }
}

/// Add to contact force `f` its Coulomb share along tangent `t`: `mu f_n` against the slip
/// velocity `slip`, but never more than the force that stops the slip over `dt` through the
/// tangential compliance `t . M^-1 t` at the contact point (so friction never reverses it).
pub(crate) fn add_coulomb(
    f: &mut [f64; 2],
    friction: f64,
    normal_force: f64,
    slip: f64,
    compliance: f64,
    dt: f64,
    t: [f64; 2],
) {
    let stick = slip.abs() / (compliance * dt);
    let magnitude = (friction * normal_force).min(stick);
    let sign = if slip > 0.0 { -1.0 } else { 1.0 };
    f[0] += sign * magnitude * t[0];
    f[1] += sign * magnitude * t[1];
}

/// Energy absorbed over a step by contact forces `forces` on `nodes` (the negative of their
/// work), per unit integration measure: `-dt sum f . (v_old + v_new) / 2`.
pub(crate) fn absorbed_work(
    forces: &[Vector],
    nodes: &[usize],
    v_old: &[Vector],
    v_new: &[Vector],
    dt: f64,
) -> f64 {
    let mut work = 0.0;
    for &n in nodes {
        let f = forces[n];
        work += f[0] * 0.5 * (v_old[n][0] + v_new[n][0]) + f[1] * 0.5 * (v_old[n][1] + v_new[n][1]);
    }
    -dt * work
}

/// Add force `f` on slave node `s` and its reaction on segment `[a, b]` in the proportions
/// `1 - xi` and `xi` (`nodes = [s, a, b]`): forces and momentum balance exactly.
pub(crate) fn distribute(forces: &mut [Vector], nodes: [usize; 3], xi: f64, f: [f64; 2]) {
    let [s, a, b] = nodes;
    for (d, &component) in f.iter().enumerate() {
        forces[s][d] += component;
        forces[a][d] -= (1.0 - xi) * component;
        forces[b][d] -= xi * component;
    }
}

/// A slave node's penetration of a master segment.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    /// Index of the segment in its list.
    pub segment: usize,
    /// Position of the projection along the segment, `0..=1` from `a` to `b`.
    pub xi: f64,
    /// Signed gap along the outward normal (negative: penetrating).
    pub gap: f64,
    /// Outward unit normal of the segment.
    pub normal: [f64; 2],
}

/// The projection of point `p` on segment `[x_a, x_b]`: `(distance, hit, segment length)`, or
/// `None` if the projection falls more than [`END_TOLERANCE`] beyond the segment's ends.
pub(crate) fn project(
    p: &Vector,
    x_a: &Vector,
    x_b: &Vector,
    segment: usize,
) -> Option<(f64, Hit, f64)> {
    let t = [x_b[0] - x_a[0], x_b[1] - x_a[1]];
    let length2 = t[0] * t[0] + t[1] * t[1];
    if length2 <= 0.0 {
        return None;
    }
    let offset = [p[0] - x_a[0], p[1] - x_a[1]];
    let xi = (offset[0] * t[0] + offset[1] * t[1]) / length2;
    if !(-END_TOLERANCE..=1.0 + END_TOLERANCE).contains(&xi) {
        return None;
    }
    let xi = xi.clamp(0.0, 1.0);
    let length = length2.sqrt();
    let normal = [t[1] / length, -t[0] / length];
    let d = [offset[0] - xi * t[0], offset[1] - xi * t[1]];
    let distance = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let gap = d[0] * normal[0] + d[1] * normal[1];
    Some((
        distance,
        Hit {
            segment,
            xi,
            gap,
            normal,
        },
        length,
    ))
}

/// Of the candidate projections, the nearest one if it penetrates (`-length < gap < 0`).
pub(crate) fn penetrating_nearest(
    candidates: impl Iterator<Item = (f64, Hit, f64)>,
) -> Option<Hit> {
    let mut best: Option<(f64, Hit, f64)> = None;
    for candidate in candidates {
        if best
            .as_ref()
            .is_none_or(|(closest, _, _)| candidate.0 < *closest)
        {
            best = Some(candidate);
        }
    }
    best.and_then(|(_, hit, length)| (hit.gap < 0.0 && -hit.gap < length).then_some(hit))
}

/// The nearest master segment of slave node `s`, if the node penetrates it.
fn nearest(pair: &ContactPair, s: usize, x: &[Vector]) -> Option<Hit> {
    penetrating_nearest(
        pair.master_segments
            .iter()
            .enumerate()
            .filter(|(_, &[a, b])| s != a && s != b)
            .filter_map(|(k, &[a, b])| project(&x[s], &x[a], &x[b], k)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A master segment along z = 0 from r = 1 to r = 0 (outward normal +z), slave node 2.
    fn setup(slave: Vector) -> (Vec<Vector>, ContactPair) {
        let x = vec![[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], slave];
        (x, ContactPair::new(vec![2], vec![[0, 1]]))
    }

    #[test]
    fn penetration_gives_the_penalty_force_and_an_equal_and_opposite_reaction() {
        // GOAL: a penetrating node is pushed out along the master's outward normal with
        //       k = s m*/dt0^2 times the penetration; the reaction splits by xi.
        // SETUP: segment (1,0)-(0,0), slave at (0.25, -0.01); masses 2, 2, 1; dt0 0.1.
        // REFERENCE: m* = 1 * 2 / 3, k = 0.1 m* / 0.01, f_z = k 0.01 on the slave;
        //   master shares 0.25 and 0.75 of -f (xi = 0.75 from node 0); sum of forces 0.
        let (x, pair) = setup([0.25, -0.01, 0.0]);
        let pairs = [pair];
        let mut contact = PenaltyContact::new(&pairs, &[2.0, 2.0, 1.0], 0.1, 2).unwrap();
        let mut force = vec![[0.0; 3]; 3];
        contact.add_forces(&x, &[[0.0; 3]; 3], 0.1, &mut force);
        let expected = 0.1 * (2.0 / 3.0) / 0.01 * 0.01;
        assert!((force[2][1] - expected).abs() < 1e-15, "{force:?}");
        assert!(force[2][0].abs() < 1e-15);
        assert!((force[0][1] + 0.25 * expected).abs() < 1e-15);
        assert!((force[1][1] + 0.75 * expected).abs() < 1e-15);
        assert!((force[0][1] + force[1][1] + force[2][1]).abs() < 1e-15);
        // A node above the surface feels nothing.
        let (x, _) = setup([0.25, 0.01, 0.0]);
        let mut force = vec![[0.0; 3]; 3];
        contact.add_forces(&x, &[[0.0; 3]; 3], 0.1, &mut force);
        assert!(force.iter().all(|f| f == &[0.0; 3]));
    }

    #[test]
    fn friction_is_coulomb_up_to_the_stick_limit() {
        // GOAL: friction opposes the slip with mu f_n, but never more than the force that
        //       stops the slip within the step.
        // SETUP: the penetrating node above sliding in +r at 10 (fast) and 1e-4 (slow);
        //        mu 0.3; dt 0.1.
        // REFERENCE: fast: f_r = -0.3 f_n; slow: f_r = -1e-4 / (w dt) with
        //   w = 1/1 + 0.25^2/2 + 0.75^2/2.
        let (x, pair) = setup([0.25, -0.01, 0.0]);
        let pairs = [pair.with_friction(0.3)];
        let mut contact = PenaltyContact::new(&pairs, &[2.0, 2.0, 1.0], 0.1, 2).unwrap();
        let normal = 0.1 * (2.0 / 3.0) / 0.01 * 0.01;
        for (speed, expected) in [
            (10.0, -0.3 * normal),
            (1e-4, -1e-4 / ((1.0 + 0.0625 / 2.0 + 0.5625 / 2.0) * 0.1)),
        ] {
            let mut v = [[0.0; 3]; 3];
            v[2][0] = speed;
            let mut force = vec![[0.0; 3]; 3];
            contact.add_forces(&x, &v, 0.1, &mut force);
            assert!((force[2][0] - expected).abs() < 1e-12 * normal, "{force:?}");
            let sum: f64 = force.iter().map(|f| f[0]).sum();
            assert!(sum.abs() < 1e-15);
        }
    }

    #[test]
    fn bad_pairs_and_three_dimensional_models_are_rejected() {
        // GOAL: contact input errors are reported, not ignored. REFERENCE: SolverError::Model.
        let pair = ContactPair::new(vec![5], vec![[0, 1]]);
        assert!(PenaltyContact::new(std::slice::from_ref(&pair), &[1.0; 3], 0.1, 2).is_err());
        let pair = ContactPair::new(vec![2], vec![[0, 1]]);
        assert!(PenaltyContact::new(std::slice::from_ref(&pair), &[1.0; 3], 0.1, 3).is_err());
        let mut negative = pair.clone();
        negative.friction = -0.1;
        assert!(PenaltyContact::new(&[negative], &[1.0; 3], 0.1, 2).is_err());
        assert!(!PenaltyContact::new(&[], &[1.0; 3], 0.1, 3)
            .unwrap()
            .is_active());
    }
}
