//! Eroding contact: penalty node-to-segment contact whose surfaces follow element erosion
//! (2D axisymmetric; the idea of LS-DYNA's `*CONTACT_ERODING_SURFACE_TO_SURFACE` and
//! OpenRadioss `/INTER/TYPE25` with `Idel`).
//!
//! **Surfaces.** The surface of each part in the contact is its *exposed boundary*: the
//! element edges owned by exactly one live element of the part. Edges on the symmetry axis
//! (both nodes at `r = 0` in the reference configuration) are never surfaces. When elements
//! erode, the surfaces are rebuilt: the edges behind an eroded element become master
//! segments, their nodes slave nodes. A boundary edge is oriented as in its live element
//! (counter-clockwise), so its outward normal is the tangent turned clockwise, as for
//! [`super::ContactPair`].
//!
//! **Two-way.** Every part is both slave and master: the slave nodes of each part are checked
//! against the segments of the *other* parts of the contact. By default a part does not
//! contact itself.
//!
//! **Single surface (`self_contact`, LS-DYNA `*CONTACT_ERODING_SINGLE_SURFACE`).** A part's
//! surface nodes also meet the part's own segments, except those of the elements the node
//! belongs to (a folding crater lip, a mushrooming head folding onto the shank), and the free
//! mass points meet every part's segments, their own part's included (a rod's eroded mass
//! stays in front of the rod's face instead of passing through it).
//!
//! **Eroded mass (LS-DYNA ENMASS).** With `keep_eroded_mass` (the default), a node whose
//! elements have all eroded keeps its mass and momentum and becomes a free mass point that
//! still meets the other parts' surfaces as a slave node (through the kinematic stop below);
//! its kinetic energy stays in the balance's kinetic energy. Without it, the node's mass is
//! removed and its kinetic energy is booked as eroded.
//!
//! **Penetrations found on exposure (LS-DYNA `IGNORE = 1` style).** When a node's penetration
//! grows by more than the relative normal approach of the step can explain (twice `v_n dt`),
//! the node was already inside when erosion exposed the segment (or took away the one it
//! touched). Pushing it out with the full penalty would launch it (the spring holds
//! `k d^2/2`); instead the unexplained depth is *tolerated*: the force acts on the penetration
//! beyond it, and the tolerance ratchets down as the node comes out, so the node is released,
//! not fired. A node leaving contact forgets its tolerance.
//!
//! **Search.** Each step the segments are binned into a uniform grid (cell size the longest
//! segment; every segment in the cells its bounding box, grown by its length, covers), so a
//! slave node only meets the segments of its own cell: `O(slaves + segments)`, not all pairs.
//! Within the candidates the force law is [`super::PenaltyLaw`] on the nearest penetrated
//! segment. Everything runs serially in the fixed order of nodes and segments: results are
//! bit-identical for any thread count.
//!
//! **Kinematic stop.** A penalty that keeps the stable time step cannot hold the interface
//! pressures of hypervelocity penetration (tens of GPa) to a small overlap: its working
//! penetration is `p dt^2 / m*`, a fifth to a quarter of an element there. So after the
//! penalty, each contact gets the normal impulse (and its Coulomb share) that keeps the
//! node's penetration from growing past [`STOP_DEPTH_FRACTION`] of the contact's shortest
//! element edge over the step, from the velocities the forces so far would give (elements,
//! penalty, earlier impulses); it only pushes apart, and it is solved by
//! [`STOP_SWEEPS`] Gauss-Seidel sweeps in the fixed order of the contacts. The impulses are
//! momentum-conserving (distributed as the penalty's forces are) and dissipative (a plastic
//! impact), and their work is booked with the contact's. Free mass points get the stop at
//! zero depth and no penalty: a piece of eroded material meeting a surface stops against it
//! (a plastic impact, as strengthless debris does), and however many of them pile onto one
//! segment, they add no stiffness to it (with the penalty they did, and at 0.1 mm the pile
//! drove the 1700 m/s shot unstable). A velocity prescribed by a constraint (an axis node's
//! radial one) is infinitely heavy for the impulses, so the stop also holds at the axis,
//! where the contact normal is inclined and half of an unconstrained impulse would be lost.
//! This is the constraint-method side of LS-DYNA's and Autodyn's contact families, added to
//! the penalty rather than replacing it.
//!
//! **Penalty (LS-DYNA SOFT = 1 style).** The stiffness `k = s m* / max(dt, dt0)^2` on the
//! reduced mass, with `dt0` the first step and `dt` the current one, bounds the contact
//! frequency at `omega dt <= sqrt(s)` whatever the materials, so the stable time step is
//! unchanged. (Stiffening as distorted elements pull the step down was tried: the contact
//! then crushes the distorted elements it presses on.) The default scale
//! ([`DEFAULT_ERODING_PENALTY_SCALE`]) is larger than the pair contact's because hypervelocity
//! interfaces carry pressures of tens of GPa. Its work is booked as it is done, so the energy
//! balance stays exact.

use super::{
    absorbed_work, add_coulomb, distribute, penetrating_nearest, project, Hit, PenaltyLaw,
};
use crate::solver::explicit::Vector;
use crate::solver::SolverError;
use std::collections::HashMap;

/// Default penalty scale of the eroding contact: `omega dt <= 1` for one contact spring. A
/// node of a two-way interface carries its own slave spring and the reactions of up to two
/// opposite slaves (about `1.5 s` in all), and the element's own frequency (at most
/// `2 x 0.67 = 1.34`, the solver holding the safety factor at
/// [`crate::solver::ERODING_CONTACT_TIME_STEP_SAFETY`] with this contact) adds in quadrature:
/// `sqrt(1.34^2 + 1.5) = 1.82 < 2`. A scale
/// of 1.5 (the first choice, to keep the interpenetration under 15 % of an element) reaches 2
/// by that count and did blow up at the 0.1 mm mesh (energy error 375 % at 35 us).
pub const DEFAULT_ERODING_PENALTY_SCALE: f64 = 1.0;

/// Largest penalty scale accepted.
pub const MAXIMUM_ERODING_PENALTY_SCALE: f64 = 2.0;

/// Penetration of a surface node beyond which the kinematic stop holds it, as a fraction of
/// the shortest element edge of the contact's parts at set-up.
pub const STOP_DEPTH_FRACTION: f64 = 0.1;

/// Gauss-Seidel sweeps of the kinematic stop over a step's contacts.
const STOP_SWEEPS: usize = 4;

/// Largest number of search-grid cells; beyond it the cells grow.
const MAXIMUM_CELLS: usize = 1 << 22;

/// An eroding contact between parts.
#[derive(Clone, Debug, PartialEq)]
pub struct ErodingContact {
    /// Part indices of the mesh that meet each other (each both slave and master).
    pub parts: Vec<usize>,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Penalty scale `s` in `k = s m* / max(dt, dt0)^2` (0 < s <= 2).
    pub penalty_scale: f64,
    /// Keep the mass and momentum of eroded elements on their nodes (LS-DYNA ENMASS).
    pub keep_eroded_mass: bool,
    /// Single-surface contact: a part's surface nodes also meet the part's own segments
    /// (except those of the elements they belong to), and the free mass points meet every
    /// part's surface, their own part's included (LS-DYNA
    /// `*CONTACT_ERODING_SINGLE_SURFACE`). Off: each part meets only the other parts.
    pub self_contact: bool,
}

impl ErodingContact {
    /// A contact between `parts` with friction `mu`, the default penalty scale, eroded mass
    /// kept.
    pub fn new(parts: Vec<usize>, friction: f64) -> Self {
        Self {
            parts,
            friction,
            penalty_scale: DEFAULT_ERODING_PENALTY_SCALE,
            keep_eroded_mass: true,
            self_contact: false,
        }
    }
}

const NONE: usize = usize::MAX;

/// An element edge: its nodes as traversed by its first owner, and its owners.
#[derive(Clone, Copy, Debug)]
struct Edge {
    nodes: [usize; 2],
    owners: [usize; 2],
    /// On the symmetry axis: never a surface.
    on_axis: bool,
}

/// A master segment of the current surfaces.
#[derive(Clone, Copy, Debug)]
struct Segment {
    nodes: [usize; 2],
    part: usize,
    /// The live element the segment bounds.
    element: usize,
}

/// A contact the kinematic stop holds: slave and segment nodes, the hit (its gap the acting
/// penetration), and the penetration down to which it may still approach (m).
#[derive(Clone, Copy, Debug)]
struct Stop {
    nodes: [usize; 3],
    hit: Hit,
    limit: f64,
}

/// The impulse the contact gave the live nodes of one part over a run, split by what met
/// them (per unit integration measure, as the forces: per radian on an axisymmetric mesh).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PartImpulse {
    /// Mesh part index.
    pub part: usize,
    /// From contacts between live surfaces (penalty and kinematic stop), `(r, z)` (N s).
    pub surfaces: [f64; 2],
    /// From free mass points (eroded debris) stopped against the part's surface (N s).
    pub debris: [f64; 2],
}

/// Book the impulse `f dt` of a contact distributed over `nodes` (`s` gets `f`, the segment's
/// `a` and `b` their shares of `-f`) on the parts of the live nodes among them (`node_part`,
/// `live_around` of the surfaces); `debris`: the slave is a free mass point.
#[allow(clippy::too_many_arguments)]
fn book(
    impulse: &mut [[f64; 4]],
    node_part: &[usize],
    live_around: &[u32],
    nodes: [usize; 3],
    xi: f64,
    f: [f64; 2],
    dt: f64,
    debris: bool,
) {
    let [s, a, b] = nodes;
    let offset = if debris { 2 } else { 0 };
    for (node, share) in [(s, 1.0), (a, -(1.0 - xi)), (b, -xi)] {
        let part = node_part[node];
        if part == NONE || live_around[node] == 0 {
            continue;
        }
        for d in 0..2 {
            impulse[part][offset + d] += share * f[d] * dt;
        }
    }
}

/// Statistics of a run's eroding contact.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactStatistics {
    /// Largest penetration of a surface node (a node of a live element) the penalty acted on
    /// at any step, beyond tolerated initial penetrations (m): the interpenetration of the
    /// surfaces, which the penalty stiffness controls.
    pub largest_penetration: f64,
    /// Largest penetration of a free mass point (a node of eroded elements only) (m): debris
    /// squeezed between the surfaces.
    pub largest_free_node_penetration: f64,
    /// Largest penetration of a surface node found on exposure and tolerated (m).
    pub largest_initial_penetration: f64,
    /// Times a surface node's penetration jumped on exposure.
    pub exposures: u64,
    /// Surface rebuilds after erosion.
    pub rebuilds: u64,
    /// Master segments at the end.
    pub segments: usize,
    /// Slave nodes at the end (free mass points included).
    pub slave_nodes: usize,
    /// Wall time spent in the contact (s): a measurement of this run, not a result (it is
    /// not written into outputs that must be byte-identical).
    pub seconds: f64,
    /// The impulse on each contact part's live nodes, surfaces and debris apart (the share of
    /// a penetrator's momentum loss that eroded material delivers).
    pub impulses: Vec<PartImpulse>,
}

/// The state of an eroding contact during a run.
#[derive(Debug)]
pub(crate) struct ErodingSurfaces {
    law: PenaltyLaw,
    /// `1 / dt0^2`.
    inverse_dt0_squared: f64,
    keep_eroded_mass: bool,
    self_contact: bool,
    /// Nodes of each element of the contact's parts (unused corners `NONE`), for the
    /// single-surface exclusion of a node's own elements.
    element_nodes: Vec<[usize; 4]>,
    edges: Vec<Edge>,
    /// Part of each node in the contact (`NONE` outside it).
    node_part: Vec<usize>,
    /// Live elements around each node (all elements, for the eroded mass).
    live_around: Vec<u32>,
    segments: Vec<Segment>,
    slaves: Vec<usize>,
    forces: Vec<Vector>,
    touched: Vec<usize>,
    /// Per node: its penetration at the last step (0: not in contact).
    depth: Vec<f64>,
    /// Per node: the tolerated initial penetration (m).
    tolerated: Vec<f64>,
    /// This step's contacts to be held by the kinematic stop.
    stops: Vec<Stop>,
    /// Per mesh part: the contact impulse on its live nodes, `[surfaces r, z, debris r, z]`.
    impulse: Vec<[f64; 4]>,
    /// Penetration of a surface node beyond which its approach is stopped (m).
    stop_depth: f64,
    /// Per node: the degrees of freedom whose velocity a constraint prescribes (an axis
    /// node's radial one): the stopping impulses see them as infinitely heavy.
    prescribed: Vec<[bool; 2]>,
    cell_start: Vec<usize>,
    cell_items: Vec<usize>,
    /// Work arrays of the binning: grown segment boxes, fill cursors.
    boxes: Vec<[[f64; 2]; 2]>,
    fill: Vec<usize>,
    statistics: ContactStatistics,
}

impl ErodingSurfaces {
    /// Build the edges of the contact's parts and the initial surfaces. `element(e)` gives the
    /// element's counter-clockwise nodes and its part index.
    pub(crate) fn new<'m>(
        contact: &ErodingContact,
        element_count: usize,
        element: impl Fn(usize) -> (&'m [usize], usize),
        part_count: usize,
        reference: &[Vector],
        dt0: f64,
        dimension: usize,
    ) -> Result<Self, SolverError> {
        let bad = |what: String| SolverError::Model(format!("eroding contact: {what}"));
        if dimension != 2 {
            return Err(bad(
                "implemented for 2D (axisymmetric) models only".to_string()
            ));
        }
        if !(contact.friction >= 0.0 && contact.friction.is_finite()) {
            return Err(bad(format!(
                "friction must be >= 0, got {}",
                contact.friction
            )));
        }
        if !(contact.penalty_scale > 0.0 && contact.penalty_scale <= MAXIMUM_ERODING_PENALTY_SCALE)
        {
            return Err(bad(format!(
                "penalty scale must be in (0, {MAXIMUM_ERODING_PENALTY_SCALE}], got {}",
                contact.penalty_scale
            )));
        }
        if contact.parts.len() < 2 {
            return Err(bad("needs at least two parts".to_string()));
        }
        if let Some(&p) = contact.parts.iter().find(|&&p| p >= part_count) {
            return Err(bad(format!("part {p} does not exist")));
        }
        let node_count = reference.len();
        let mut node_part = vec![NONE; node_count];
        let mut live_around = vec![0u32; node_count];
        let mut edges: Vec<Edge> = Vec::new();
        let mut element_nodes = vec![[NONE; 4]; element_count];
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let axis_tolerance = 1e-12
            * reference
                .iter()
                .map(|p| p[0].abs().max(p[1].abs()))
                .fold(0.0, f64::max);
        for (e, corners) in element_nodes.iter_mut().enumerate() {
            let (nodes, part) = element(e);
            for &n in nodes {
                live_around[n] += 1;
            }
            if !contact.parts.contains(&part) {
                continue;
            }
            if nodes.len() > 4 {
                return Err(bad(format!(
                    "element {e} has {} nodes; 2D elements have at most 4",
                    nodes.len()
                )));
            }
            corners[..nodes.len()].copy_from_slice(nodes);
            for (k, &a) in nodes.iter().enumerate() {
                let b = nodes[(k + 1) % nodes.len()];
                node_part[a] = part;
                let key = (a.min(b), a.max(b));
                match index.get(&key) {
                    Some(&id) => edges[id].owners[1] = e,
                    None => {
                        index.insert(key, edges.len());
                        edges.push(Edge {
                            nodes: [a, b],
                            owners: [e, NONE],
                            on_axis: reference[a][0].abs() <= axis_tolerance
                                && reference[b][0].abs() <= axis_tolerance,
                        });
                    }
                }
            }
        }
        let shortest_edge = edges
            .iter()
            .map(|edge| {
                let [a, b] = edge.nodes;
                ((reference[a][0] - reference[b][0]).powi(2)
                    + (reference[a][1] - reference[b][1]).powi(2))
                .sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        let mut surfaces = Self {
            law: PenaltyLaw {
                penalty_scale: contact.penalty_scale,
                friction: contact.friction,
                inverse_dt2: 1.0 / (dt0 * dt0),
            },
            inverse_dt0_squared: 1.0 / (dt0 * dt0),
            keep_eroded_mass: contact.keep_eroded_mass,
            self_contact: contact.self_contact,
            element_nodes,
            edges,
            node_part,
            live_around,
            segments: Vec::new(),
            slaves: Vec::new(),
            forces: vec![[0.0; 3]; node_count],
            touched: Vec::new(),
            depth: vec![0.0; node_count],
            tolerated: vec![0.0; node_count],
            stops: Vec::new(),
            impulse: vec![[0.0; 4]; part_count],
            stop_depth: STOP_DEPTH_FRACTION * shortest_edge,
            prescribed: vec![[false; 2]; node_count],
            cell_start: Vec::new(),
            cell_items: Vec::new(),
            boxes: Vec::new(),
            fill: Vec::new(),
            statistics: ContactStatistics::default(),
        };
        let nobody_eroded = vec![false; element_count];
        surfaces.rebuild(&nobody_eroded);
        surfaces.statistics.rebuilds = 0;
        Ok(surfaces)
    }

    /// Mark degree of freedom `dof` of `nodes` as prescribed by a velocity constraint (the
    /// stop takes the prescribed velocity at its value of the last step, exact for the
    /// constant ones: the axis, a clamped rim, a driven body).
    pub(crate) fn prescribe(&mut self, nodes: &[usize], dof: usize) {
        if dof < 2 {
            for &n in nodes {
                if let Some(p) = self.prescribed.get_mut(n) {
                    p[dof] = true;
                }
            }
        }
    }

    /// The run's statistics so far.
    pub(crate) fn statistics(&self) -> ContactStatistics {
        let impulses = self
            .contact_parts()
            .into_iter()
            .map(|part| {
                let i = self.impulse[part];
                PartImpulse {
                    part,
                    surfaces: [i[0], i[1]],
                    debris: [i[2], i[3]],
                }
            })
            .collect();
        ContactStatistics {
            segments: self.segments.len(),
            slave_nodes: self.slaves.len(),
            impulses,
            ..self.statistics.clone()
        }
    }

    /// The mesh parts in the contact, in increasing order.
    fn contact_parts(&self) -> Vec<usize> {
        let mut parts: Vec<usize> = self
            .node_part
            .iter()
            .copied()
            .filter(|&p| p != NONE)
            .collect();
        parts.sort_unstable();
        parts.dedup();
        parts
    }

    /// Rebuild the surfaces from the live elements.
    fn rebuild(&mut self, eroded: &[bool]) {
        self.statistics.rebuilds += 1;
        self.segments.clear();
        self.slaves.clear();
        let live = |e: usize| e != NONE && !eroded[e];
        for edge in &self.edges {
            if edge.on_axis {
                continue;
            }
            let (nodes, element) = match (live(edge.owners[0]), live(edge.owners[1])) {
                (true, false) => (edge.nodes, edge.owners[0]),
                (false, true) => ([edge.nodes[1], edge.nodes[0]], edge.owners[1]),
                _ => continue,
            };
            self.segments.push(Segment {
                nodes,
                part: self.node_part[nodes[0]],
                element,
            });
            self.slaves.extend_from_slice(&nodes);
        }
        if self.keep_eroded_mass {
            for (n, (&part, &count)) in self.node_part.iter().zip(&self.live_around).enumerate() {
                if part != NONE && count == 0 {
                    self.slaves.push(n);
                }
            }
        }
        self.slaves.sort_unstable();
        self.slaves.dedup();
    }

    /// Elements `newly_eroded` have just eroded (`eroded` already marks them): update the
    /// live counts and the surfaces. Without `keep_eroded_mass`, nodes left without a live
    /// element lose their mass and velocity; the kinetic energy they carried (per unit
    /// integration measure) is returned.
    pub(crate) fn on_erosion<'m>(
        &mut self,
        newly_eroded: &[usize],
        element_nodes: impl Fn(usize) -> &'m [usize],
        eroded: &[bool],
        mass: &mut [f64],
        v: &mut [Vector],
    ) -> f64 {
        let mut removed_kinetic = 0.0;
        for &e in newly_eroded {
            for &n in element_nodes(e) {
                self.live_around[n] -= 1;
                if self.live_around[n] == 0 && !self.keep_eroded_mass {
                    let speed2: f64 = v[n].iter().map(|c| c * c).sum();
                    removed_kinetic += 0.5 * mass[n] * speed2;
                    mass[n] = 0.0;
                    v[n] = [0.0; 3];
                }
            }
        }
        self.rebuild(eroded);
        removed_kinetic
    }

    /// Bin the segments at positions `x` into the search grid. Returns the grid's origin,
    /// cell size and dimensions.
    fn bin(&mut self, x: &[Vector]) -> ([f64; 2], f64, [usize; 2]) {
        let mut low = [f64::INFINITY; 2];
        let mut high = [f64::NEG_INFINITY; 2];
        let mut cell: f64 = 0.0;
        // Each segment's bounding box grown by its length, computed once per step.
        self.boxes.clear();
        for segment in &self.segments {
            let [a, b] = segment.nodes;
            let length = ((x[b][0] - x[a][0]).powi(2) + (x[b][1] - x[a][1]).powi(2)).sqrt();
            cell = cell.max(length);
            let grown: [[f64; 2]; 2] = core::array::from_fn(|d| {
                [x[a][d].min(x[b][d]) - length, x[a][d].max(x[b][d]) + length]
            });
            for d in 0..2 {
                low[d] = low[d].min(grown[d][0]);
                high[d] = high[d].max(grown[d][1]);
            }
            self.boxes.push(grown);
        }
        if self.segments.is_empty() || cell.is_nan() || cell <= 0.0 || !cell.is_finite() {
            self.cell_start.clear();
            return ([0.0; 2], 1.0, [0, 0]);
        }
        let count = |cell: f64| -> [usize; 2] {
            core::array::from_fn(|d| (((high[d] - low[d]) / cell).floor() as usize + 1).max(1))
        };
        let mut dims = count(cell);
        while dims[0].saturating_mul(dims[1]) > MAXIMUM_CELLS {
            cell *= 2.0;
            dims = count(cell);
        }
        let cells = dims[0] * dims[1];
        let range = |grown: &[[f64; 2]; 2]| -> [[usize; 2]; 2] {
            core::array::from_fn(|d| {
                let first = ((grown[d][0] - low[d]) / cell).floor().max(0.0) as usize;
                let last = ((grown[d][1] - low[d]) / cell).floor().max(0.0) as usize;
                [first.min(dims[d] - 1), last.min(dims[d] - 1)]
            })
        };
        // Counting pass, then fill (compressed rows: cell_start[c]..cell_start[c + 1]).
        self.cell_start.clear();
        self.cell_start.resize(cells + 1, 0);
        for grown in &self.boxes {
            let [[i0, i1], [j0, j1]] = range(grown);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    self.cell_start[j * dims[0] + i + 1] += 1;
                }
            }
        }
        for c in 0..cells {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.cell_items.clear();
        self.cell_items.resize(self.cell_start[cells], 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.cell_start);
        for (k, grown) in self.boxes.iter().enumerate() {
            let [[i0, i1], [j0, j1]] = range(grown);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let c = j * dims[0] + i;
                    self.cell_items[self.fill[c]] = k;
                    self.fill[c] += 1;
                }
            }
        }
        (low, cell, dims)
    }

    /// Compute the contact forces at positions `x` with velocities `v` (`v_{n-1/2}`) and
    /// nodal masses `mass` for a velocity update over `dt`, and add them to `force`.
    pub(crate) fn add_forces(
        &mut self,
        x: &[Vector],
        v: &[Vector],
        mass: &[f64],
        dt: f64,
        force: &mut [Vector],
    ) {
        let started = std::time::Instant::now();
        // k = s m* / max(dt, dt0)^2: never stiffer than at the first step, and softer when
        // the step grows, so that omega dt <= sqrt(s) throughout.
        if dt > 0.0 {
            self.law.inverse_dt2 = self.inverse_dt0_squared.min(1.0 / (dt * dt));
        }
        for &n in &self.touched {
            self.forces[n] = [0.0; 3];
        }
        self.touched.clear();
        let (low, cell, dims) = self.bin(x);
        if dims[0] == 0 {
            return;
        }
        for &s in &self.slaves {
            let p = x[s];
            let i = ((p[0] - low[0]) / cell).floor();
            let j = ((p[1] - low[1]) / cell).floor();
            if !(i >= 0.0 && j >= 0.0 && (i as usize) < dims[0] && (j as usize) < dims[1]) {
                continue;
            }
            let c = j as usize * dims[0] + i as usize;
            let own = self.node_part[s];
            let free = self.live_around[s] == 0;
            let self_contact = self.self_contact;
            let element_nodes = &self.element_nodes;
            let segments = &self.segments;
            // The nearest of the segments the node is inside of (not the nearest overall: near
            // a crater's lip the nearest segment may be one the node is outside of).
            let hit: Option<Hit> = penetrating_nearest(
                self.cell_items[self.cell_start[c]..self.cell_start[c + 1]]
                    .iter()
                    .filter(|&&k| {
                        let segment = &segments[k];
                        segment.part != own
                            || (self_contact
                                && (free || !element_nodes[segment.element].contains(&s)))
                    })
                    .filter_map(|&k| {
                        let [a, b] = segments[k].nodes;
                        project(&p, &x[a], &x[b], k)
                    })
                    .filter(|(_, hit, length)| hit.gap < 0.0 && -hit.gap < *length),
            );
            let Some(mut hit) = hit else {
                self.depth[s] = 0.0;
                self.tolerated[s] = 0.0;
                continue;
            };
            let [a, b] = self.segments[hit.segment].nodes;
            let depth = -hit.gap;
            let xi = hit.xi;
            let approach: f64 = (0..2)
                .map(|d| (v[s][d] - (1.0 - xi) * v[a][d] - xi * v[b][d]) * hit.normal[d])
                .sum();
            let reach = 2.0 * (-approach).max(0.0) * dt;
            let jump = depth - self.depth[s] - reach;
            if jump > 0.0 {
                self.tolerated[s] += jump;
                if self.live_around[s] > 0 {
                    self.statistics.largest_initial_penetration = self
                        .statistics
                        .largest_initial_penetration
                        .max(self.tolerated[s]);
                    self.statistics.exposures += 1;
                }
            }
            self.tolerated[s] = self.tolerated[s].min(depth);
            self.depth[s] = depth;
            let acting = depth - self.tolerated[s];
            if acting <= 0.0 {
                continue;
            }
            hit.gap = -acting;
            if free {
                self.statistics.largest_free_node_penetration =
                    self.statistics.largest_free_node_penetration.max(acting);
                self.stops.push(Stop {
                    nodes: [s, a, b],
                    hit,
                    limit: 0.0,
                });
                continue;
            }
            if let Some(f) = self.law.force(mass, [s, a, b], &hit, v, dt) {
                self.statistics.largest_penetration =
                    self.statistics.largest_penetration.max(acting);
                distribute(&mut self.forces, [s, a, b], hit.xi, f);
                book(
                    &mut self.impulse,
                    &self.node_part,
                    &self.live_around,
                    [s, a, b],
                    hit.xi,
                    f,
                    dt,
                    false,
                );
                self.touched.extend_from_slice(&[s, a, b]);
                self.stops.push(Stop {
                    nodes: [s, a, b],
                    hit,
                    limit: self.stop_depth,
                });
            }
        }
        self.stop(v, mass, dt, force);
        self.touched.sort_unstable();
        self.touched.dedup();
        for &n in &self.touched {
            force[n][0] += self.forces[n][0];
            force[n][1] += self.forces[n][1];
        }
        self.statistics.seconds += started.elapsed().as_secs_f64();
    }

    /// The kinematic stop (see the module notes): for each of the step's stops, in order and
    /// [`STOP_SWEEPS`] times over, the normal impulse (with its Coulomb share) that keeps the
    /// node's penetration at `limit` after the velocity update, from the velocities the
    /// forces so far (elements, penalty, earlier stops) would give. It only ever pushes apart.
    fn stop(&mut self, v: &[Vector], mass: &[f64], dt: f64, force: &[Vector]) {
        if dt <= 0.0 {
            self.stops.clear();
            return;
        }
        let stops = std::mem::take(&mut self.stops);
        // Each sweep takes the surface nodes first, then the free mass points, so that the
        // debris meets the surfaces as the interface has left them.
        let surface = stops.iter().filter(|stop| stop.limit > 0.0);
        let debris = stops.iter().filter(|stop| stop.limit <= 0.0);
        for stop in (0..STOP_SWEEPS).flat_map(|_| surface.clone().chain(debris.clone())) {
            let Stop { nodes, hit, limit } = *stop;
            let [s, a, b] = nodes;
            if mass[s] <= 0.0 || mass[a] <= 0.0 || mass[b] <= 0.0 {
                continue;
            }
            let prescribed = &self.prescribed;
            let forces = &self.forces;
            let predicted = |k: usize, d: usize| {
                if prescribed[k][d] {
                    v[k][d]
                } else {
                    v[k][d] + dt * (force[k][d] + forces[k][d]) / mass[k]
                }
            };
            let xi = hit.xi;
            let relative: [f64; 2] = core::array::from_fn(|d| {
                predicted(s, d) - (1.0 - xi) * predicted(a, d) - xi * predicted(b, d)
            });
            let n = hit.normal;
            let t = [-n[1], n[0]];
            // The approach allowed over the step: down to the limit, never out by force.
            let allowed = ((-hit.gap - limit) / dt).min(0.0);
            let approach = relative[0] * n[0] + relative[1] * n[1];
            if approach >= allowed {
                continue;
            }
            // e . M^-1 e of the three nodes at the contact point; a prescribed direction is
            // infinitely heavy.
            let compliance = |e: [f64; 2]| -> f64 {
                let node = |k: usize| -> f64 {
                    (0..2)
                        .filter(|&d| !prescribed[k][d])
                        .map(|d| e[d] * e[d] / mass[k])
                        .sum()
                };
                node(s) + (1.0 - xi) * (1.0 - xi) * node(a) + xi * xi * node(b)
            };
            let normal_compliance = compliance(n);
            if normal_compliance <= 0.0 {
                continue;
            }
            let normal_force = (allowed - approach) / (normal_compliance * dt);
            let mut f = [normal_force * n[0], normal_force * n[1]];
            let friction = self.law.friction;
            if friction > 0.0 {
                let tangential_compliance = compliance(t);
                if tangential_compliance > 0.0 {
                    let slip = relative[0] * t[0] + relative[1] * t[1];
                    add_coulomb(
                        &mut f,
                        friction,
                        normal_force,
                        slip,
                        tangential_compliance,
                        dt,
                        t,
                    );
                }
            }
            distribute(&mut self.forces, nodes, xi, f);
            book(
                &mut self.impulse,
                &self.node_part,
                &self.live_around,
                nodes,
                xi,
                f,
                dt,
                limit <= 0.0,
            );
            self.touched.extend_from_slice(&nodes);
        }
        self.stops = stops;
        self.stops.clear();
    }

    /// Energy absorbed by the contact over the step, per unit integration measure:
    /// `-dt sum f . (v_old + v_new) / 2`.
    pub(crate) fn absorbed(&self, v_old: &[Vector], v_new: &[Vector], dt: f64) -> f64 {
        absorbed_work(&self.forces, &self.touched, v_old, v_new, dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two parts: a 2 x 2 block of unit quads (part 0, elements 0-3) on z in [0, 2], r in
    /// [0, 2], and a single quad (part 1) above it, r in [0.5, 1.5], z in [2, 3].
    fn two_blocks() -> (Vec<Vector>, Vec<[usize; 4]>, Vec<usize>) {
        let mut x = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                x.push([i as f64, j as f64, 0.0]);
            }
        }
        let node = |i: usize, j: usize| j * 3 + i;
        let mut elements = Vec::new();
        for j in 0..2 {
            for i in 0..2 {
                elements.push([
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ]);
            }
        }
        let base = x.len();
        x.extend([
            [0.5, 2.0, 0.0],
            [1.5, 2.0, 0.0],
            [1.5, 3.0, 0.0],
            [0.5, 3.0, 0.0],
        ]);
        elements.push([base, base + 1, base + 2, base + 3]);
        (x, elements, vec![0, 0, 0, 0, 1])
    }

    fn surfaces(x: &[Vector], elements: &[[usize; 4]], parts: &[usize]) -> ErodingSurfaces {
        surfaces_with(&ErodingContact::new(vec![0, 1], 0.0), x, elements, parts)
    }

    fn surfaces_with(
        contact: &ErodingContact,
        x: &[Vector],
        elements: &[[usize; 4]],
        parts: &[usize],
    ) -> ErodingSurfaces {
        ErodingSurfaces::new(
            contact,
            elements.len(),
            |e| (&elements[e][..], parts[e]),
            2,
            x,
            0.1,
            2,
        )
        .unwrap()
    }

    #[test]
    fn exposed_boundary_excludes_the_axis_and_follows_erosion() {
        // GOAL: the surfaces are the edges with one live element, not on the axis, oriented
        //       counter-clockwise; erosion exposes the edges behind the eroded element.
        // SETUP: the two blocks above; then element 3 (top right of part 0) erodes.
        // REFERENCE: by hand: part 0 has 8 boundary edges, 2 on the axis -> 6 segments; the
        //   quad of part 1 has 4, none on the axis (r >= 0.5) -> 10. After erosion part 0 loses
        //   the 2 outer edges of element 3 and gains its 2 inner ones: still 10; the new ones
        //   run counter-clockwise in elements 1 and 2.
        let (x, elements, parts) = two_blocks();
        let mut contact = surfaces(&x, &elements, &parts);
        assert_eq!(contact.segments.len(), 10);
        for segment in &contact.segments {
            let [a, b] = segment.nodes;
            assert!(!(x[a][0] == 0.0 && x[b][0] == 0.0), "axis edge {a}-{b}");
        }
        // Top face of part 0 runs from r = 2 to r = 0 (outward normal +z): [8, 7] and [7, 6].
        assert!(contact.segments.iter().any(|s| s.nodes == [8, 7]));
        let mut eroded = vec![false; 5];
        eroded[3] = true;
        let mut mass = vec![1.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        contact.on_erosion(&[3], |e| &elements[e][..], &eroded, &mut mass, &mut v);
        assert_eq!(contact.segments.len(), 10);
        // Element 1 = [1, 2, 5, 4]: its top edge runs 5 -> 4, outward normal +z.
        assert!(contact.segments.iter().any(|s| s.nodes == [5, 4]));
        // Element 2's right edge: element 2 = [3, 4, 7, 6], edge 4 -> 7, normal +r.
        assert!(contact.segments.iter().any(|s| s.nodes == [4, 7]));
        assert!(!contact.segments.iter().any(|s| s.nodes == [8, 7]));
        // Node 8 lost its only element: it stays as a free mass point among the slaves.
        assert!(contact.slaves.contains(&8));
        assert_eq!(mass[8], 1.0);
    }

    #[test]
    fn without_eroded_mass_free_nodes_lose_mass_and_book_their_kinetic_energy() {
        // GOAL: LS-DYNA ENMASS = 0: a node without live elements loses its mass; its kinetic
        //       energy is returned for the balance.
        // SETUP: element 3 erodes, node 8 (its only element) moves at (3, 4) with mass 2.
        // REFERENCE: 1/2 2 (9 + 16) = 25; mass and velocity of node 8 set to zero.
        let (x, elements, parts) = two_blocks();
        let mut contact = surfaces_with(
            &ErodingContact {
                keep_eroded_mass: false,
                ..ErodingContact::new(vec![0, 1], 0.0)
            },
            &x,
            &elements,
            &parts,
        );
        let mut eroded = vec![false; 5];
        eroded[3] = true;
        let mut mass = vec![2.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        v[8] = [3.0, 4.0, 0.0];
        let removed = contact.on_erosion(&[3], |e| &elements[e][..], &eroded, &mut mass, &mut v);
        assert_eq!(removed, 25.0);
        assert_eq!(mass[8], 0.0);
        assert_eq!(v[8], [0.0; 3]);
        assert!(!contact.slaves.contains(&8));
    }

    #[test]
    fn both_parts_are_slaves_and_masters_and_forces_balance() {
        // GOAL: two-way contact: a node of part 1 inside part 0 and a node of part 0 inside
        //       part 1 are both pushed out; forces sum to zero (momentum).
        // SETUP: the quad of part 1 moved down by 0.01 (its bottom nodes penetrate part 0's
        //        top face) and approaching at 1 (so the depth is explained by the approach,
        //        2 x 1 x 0.1 > 0.01, not found on exposure); masses 1; dt0 0.1.
        // REFERENCE: k = s m*/dt0^2 with m* = 1/2, penetration d = 0.01 both ways: part 1's
        //   bottom nodes 9, 10 get k d (+z) as slaves plus half the reaction of node 7 (which
        //   sits mid-segment and is pushed -z by k d): 1.5 k d; node 7 gets -k d and half the
        //   reactions of nodes 9 and 10: -2 k d; sum of z forces 0.
        let (mut x, elements, parts) = two_blocks();
        for p in x.iter_mut().skip(9) {
            p[1] -= 0.01;
        }
        let mut contact = surfaces(&x, &elements, &parts);
        let mass = vec![1.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        for velocity in v.iter_mut().skip(9) {
            velocity[1] = -1.0;
        }
        let mut force = vec![[0.0; 3]; x.len()];
        contact.add_forces(&x, &v, &mass, 0.1, &mut force);
        let k = DEFAULT_ERODING_PENALTY_SCALE * 0.5 / 0.01;
        let d = 0.01;
        assert!((force[9][1] - 1.5 * k * d).abs() < 1e-9, "{:?}", force[9]);
        assert!((force[10][1] - 1.5 * k * d).abs() < 1e-9, "{:?}", force[10]);
        assert!((force[7][1] + 2.0 * k * d).abs() < 1e-9, "{:?}", force[7]);
        let sum: f64 = force.iter().map(|f| f[1]).sum();
        assert!(sum.abs() < 1e-9);
        let statistics = contact.statistics();
        assert!((statistics.largest_penetration - d).abs() < 1e-9);
        // The booked impulses: part 1 (nodes 9 on) pushed +z by its bottom nodes' forces,
        // part 0 -z by node 7's, over dt 0.1; no debris; the two balance.
        let [lower, upper] = [&statistics.impulses[0], &statistics.impulses[1]];
        assert_eq!((lower.part, upper.part), (0, 1));
        let upper_z: f64 = force[9..].iter().map(|f| f[1]).sum::<f64>() * 0.1;
        assert!(
            upper_z > 0.0 && (upper.surfaces[1] - upper_z).abs() < 1e-12,
            "{upper:?}"
        );
        assert!(
            (lower.surfaces[1] + upper.surfaces[1]).abs() < 1e-12,
            "{lower:?}"
        );
        assert_eq!(lower.debris, [0.0; 2]);
    }

    #[test]
    fn single_surface_contact_meets_the_own_part_except_the_nodes_own_elements() {
        // GOAL: with self_contact, a free mass point meets its own part's surface and a surface
        //       node meets its own part's segments of other elements, never those of its own
        //       elements; without it, neither.
        // SETUP: the two blocks; element 3 (top right of part 0) erodes, so node 8 (its only
        //        element) becomes a free mass point; node 8 is then moved to (1.5, 0.99),
        //        0.01 inside the exposed top face of element 1 ([5, 4] at z = 1, normal +z), approaching
        //        at 1 (so the depth is explained, not found on exposure). Node 7 (top of
        //        element 2, a surface node) sits on its own elements' segments (gap 0): no
        //        force either way.
        // REFERENCE: self_contact: node 8, a free mass point, is stopped (kinematic stop at
        //   zero depth, no penalty): the force that ends its approach of 1 over dt = 0.1,
        //   1 / (w dt) with the compliance w = 1/m_8 + (1/2)^2/m_4 + (1/2)^2/m_5 = 1.5, and
        //   half of its reaction on each of nodes 4 and 5 (xi = 1/2); without: no force on 8.
        let (mut x, elements, parts) = two_blocks();
        let mut eroded = vec![false; 5];
        eroded[3] = true;
        let mass = vec![1.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        x[8] = [1.5, 0.99, 0.0];
        v[8] = [0.0, -1.0, 0.0];
        for self_contact in [true, false] {
            let mut contact = surfaces_with(
                &ErodingContact {
                    self_contact,
                    ..ErodingContact::new(vec![0, 1], 0.0)
                },
                &x,
                &elements,
                &parts,
            );
            let mut m = mass.clone();
            let mut velocity = v.clone();
            contact.on_erosion(&[3], |e| &elements[e][..], &eroded, &mut m, &mut velocity);
            let mut force = vec![[0.0; 3]; x.len()];
            contact.add_forces(&x, &v, &mass, 0.1, &mut force);
            let stopping = 1.0 / (1.5 * 0.1);
            if self_contact {
                assert!((force[8][1] - stopping).abs() < 1e-9, "{:?}", force[8]);
                assert!(
                    (force[4][1] + 0.5 * stopping).abs() < 1e-9,
                    "{:?}",
                    force[4]
                );
                assert!(
                    (force[5][1] + 0.5 * stopping).abs() < 1e-9,
                    "{:?}",
                    force[5]
                );
            } else {
                assert_eq!(force[8], [0.0; 3]);
            }
            assert_eq!(force[7], [0.0; 3], "node 7 against its own elements");
        }
    }

    #[test]
    fn a_penetration_found_on_exposure_is_tolerated_then_released() {
        // GOAL: LS-DYNA IGNORE-style exposure: a node found inside without having approached
        //       is not fired out; only deeper penetration is pushed back, and the tolerance
        //       ratchets down as the node comes out.
        // SETUP: part 1 moved down by 0.01 at rest (v = 0): found on exposure. Then moved
        //        down by a further 0.002 at 0.001 per step (explained), then back up to
        //        0.004 deep.
        // REFERENCE: first call: no force; second: 1.5 k 0.002 on node 9 (see the two-way
        //   test for 1.5); third: the tolerance has become 0.004, no force.
        let (mut x, elements, parts) = two_blocks();
        let shift = |x: &mut Vec<Vector>, dz: f64| {
            for p in x.iter_mut().skip(9) {
                p[1] -= dz;
            }
        };
        shift(&mut x, 0.01);
        let mut contact = surfaces(&x, &elements, &parts);
        let mass = vec![1.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        let mut force = vec![[0.0; 3]; x.len()];
        contact.add_forces(&x, &v, &mass, 0.1, &mut force);
        assert!(force.iter().all(|f| f == &[0.0; 3]), "{force:?}");
        shift(&mut x, 0.002);
        for velocity in v.iter_mut().skip(9) {
            velocity[1] = -0.01;
        }
        let mut force = vec![[0.0; 3]; x.len()];
        contact.add_forces(&x, &v, &mass, 0.1, &mut force);
        let k = DEFAULT_ERODING_PENALTY_SCALE * 0.5 / 0.01;
        assert!(
            (force[9][1] - 1.5 * k * 0.002).abs() < 1e-9,
            "{:?}",
            force[9]
        );
        shift(&mut x, -0.008);
        for velocity in v.iter_mut().skip(9) {
            velocity[1] = 0.08;
        }
        let mut force = vec![[0.0; 3]; x.len()];
        contact.add_forces(&x, &v, &mass, 0.1, &mut force);
        assert!(force.iter().all(|f| f[1].abs() < 1e-12), "{force:?}");
        assert!((contact.tolerated[9] - 0.004).abs() < 1e-12);
    }

    /// The velocities after the step that `force` gives (`v + dt f / m`), with the radial
    /// velocity of the nodes in `axis` held (as the axis constraint holds it).
    fn after_step(v: &[Vector], force: &[Vector], dt: f64, axis: &[usize]) -> Vec<Vector> {
        v.iter()
            .zip(force)
            .enumerate()
            .map(|(n, (v, f))| {
                let r = if axis.contains(&n) {
                    v[0]
                } else {
                    v[0] + dt * f[0]
                };
                [r, v[1] + dt * f[1], 0.0]
            })
            .collect()
    }

    #[test]
    fn the_stop_holds_a_surface_node_at_a_tenth_of_the_shortest_edge() {
        // GOAL: a surface node closing in faster than the penalty can stop is held at the
        //       stop depth; without the stop it is not.
        // SETUP: the two blocks (shortest edge 1, so the stop depth is 0.1), part 1 lowered
        //        by 0.05 into part 0's top face and closing at 2 over dt = 0.1 (0.2 a step);
        //        masses 1.
        // REFERENCE: the penetration after the step, `0.05 - dt (v_new . n)` with the
        //   relative velocity after the forces, is at most 0.1 for nodes 9 and 10 (in part
        //   0's top face) and node 7 (in part 1's bottom face); with the stop off, the penalty
        //   alone (k d = 0.5 x 100 x 0.05 = 2.5 per spring) leaves it well past 0.1.
        let (mut x, elements, parts) = two_blocks();
        for p in x.iter_mut().skip(9) {
            p[1] -= 0.05;
        }
        let mass = vec![1.0; x.len()];
        let mut v = vec![[0.0; 3]; x.len()];
        for velocity in v.iter_mut().skip(9) {
            velocity[1] = -2.0;
        }
        let dt = 0.1;
        let depth_after = |stop: bool| -> f64 {
            let mut contact = surfaces(&x, &elements, &parts);
            assert!((contact.stop_depth - 0.1).abs() < 1e-15);
            if !stop {
                contact.stop_depth = f64::INFINITY;
            }
            let mut force = vec![[0.0; 3]; x.len()];
            contact.add_forces(&x, &v, &mass, dt, &mut force);
            let sum: f64 = force.iter().map(|f| f[1]).sum();
            assert!(sum.abs() < 1e-9, "momentum: {sum}");
            let after = after_step(&v, &force, dt, &[]);
            // Node 9 at r = 0.5 over face [7, 6] (xi 1/2), node 10 over [8, 7], node 7 in the
            // middle of part 1's bottom face [9, 10].
            let deepest = |s: usize, a: usize, b: usize| {
                0.05 - dt * (after[s][1] - 0.5 * (after[a][1] + after[b][1]))
            };
            deepest(9, 7, 6)
                .max(deepest(10, 8, 7))
                .max(0.05 + dt * (after[7][1] - 0.5 * (after[9][1] + after[10][1])))
        };
        let held = depth_after(true);
        assert!(held <= 0.1 + 1e-12, "held at {held}");
        let free = depth_after(false);
        assert!(free > 0.15, "penalty alone: {free}");
    }

    #[test]
    fn the_stop_holds_at_the_axis_with_the_radial_velocity_prescribed() {
        // GOAL: a free mass point on the axis, meeting a face inclined to it, is stopped: the
        //       impulse accounts for the radial velocities the axis constraint holds, so
        //       none of it is lost there; counted as free, part of it would be.
        // SETUP: part 0 one quad (0,0) (1,0) (1,1) (0,1.5) (its top face descends from the axis,
        //        outward normal (1, 2)/sqrt 5); part 1 one quad (0,1.45) (0.5,1.6) (0.5,2.5)
        //        (0,2.5), eroded, so its nodes are free mass points; node 4 at (0, 1.45) is
        //        0.05 under the face at the axis, closing at 1 along -z; nodes 0, 3, 4, 7 on
        //        the axis; masses 1, dt 0.1.
        // REFERENCE: with the axis prescribed, the relative normal velocity of node 4 against
        //   the face after the step (radial velocities of axis nodes held) is 0 to rounding;
        //   without, the radial part of the impulse on nodes 3 and 4 is lost to the constraint
        //   and node 4 still closes in.
        let x: Vec<Vector> = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.5, 0.0],
            [0.0, 1.45, 0.0],
            [0.5, 1.6, 0.0],
            [0.5, 2.5, 0.0],
            [0.0, 2.5, 0.0],
        ];
        let elements = vec![[0, 1, 2, 3], [4, 5, 6, 7]];
        let parts = vec![0, 1];
        let axis = [0, 3, 4, 7];
        let normal = [1.0 / 5f64.sqrt(), 2.0 / 5f64.sqrt()];
        let dt = 0.1;
        let approach_after = |prescribe: bool| -> f64 {
            let mut contact = surfaces(&x, &elements, &parts);
            if prescribe {
                contact.prescribe(&axis, 0);
            }
            let mut mass = vec![1.0; x.len()];
            let mut v = vec![[0.0; 3]; x.len()];
            v[4] = [0.0, -1.0, 0.0];
            contact.on_erosion(
                &[1],
                |e| &elements[e][..],
                &[false, true],
                &mut mass,
                &mut v,
            );
            let mut force = vec![[0.0; 3]; x.len()];
            contact.add_forces(&x, &v, &mass, dt, &mut force);
            let after = after_step(&v, &force, dt, &axis);
            // Node 4's foot on face [2, 3]: xi from its projection.
            let t = [x[3][0] - x[2][0], x[3][1] - x[2][1]];
            let xi = ((x[4][0] - x[2][0]) * t[0] + (x[4][1] - x[2][1]) * t[1])
                / (t[0] * t[0] + t[1] * t[1]);
            (0..2)
                .map(|d| (after[4][d] - (1.0 - xi) * after[2][d] - xi * after[3][d]) * normal[d])
                .sum()
        };
        let held = approach_after(true);
        assert!(held.abs() < 1e-12, "relative normal velocity {held}");
        let lost = approach_after(false);
        assert!(lost < -0.1, "unprescribed: {lost}");
    }

    #[test]
    fn the_bucket_search_finds_what_a_search_of_all_segments_finds() {
        // GOAL: the grid search is a pure speed-up: every penetrating node finds the same
        //       nearest penetrated segment as a search over all segments.
        // SETUP: the two blocks with part 1 pushed 0.3 into part 0 and the nodes scattered by
        //        a deterministic pseudo-random 0.05; all nodes approaching at 10 (no exposure
        //        tolerance).
        // REFERENCE: brute force over every segment of the other part, same selection rule,
        //   same penalty law.
        let (mut x, elements, parts) = two_blocks();
        let mut state = 12345_u64;
        let mut random = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for (n, p) in x.iter_mut().enumerate() {
            if n >= 9 {
                p[1] -= 0.3;
            }
            if p[0] > 0.0 {
                p[0] += 0.1 * random();
            }
            p[1] += 0.1 * random();
        }
        let mut contact = surfaces(&x, &elements, &parts);
        // The penalty alone: the kinematic stop (tested on its own) is switched off.
        contact.stop_depth = f64::INFINITY;
        let mass = vec![1.0; x.len()];
        let v: Vec<Vector> = (0..x.len())
            .map(|n| if n >= 9 { [0.0, -10.0, 0.0] } else { [0.0; 3] })
            .collect();
        let mut force = vec![[0.0; 3]; x.len()];
        contact.add_forces(&x, &v, &mass, 0.1, &mut force);
        let mut expected = vec![[0.0; 3]; x.len()];
        let law = contact.law;
        for &s in &contact.slaves {
            let own = contact.node_part[s];
            let hit = penetrating_nearest(
                contact
                    .segments
                    .iter()
                    .enumerate()
                    .filter(|(_, segment)| segment.part != own)
                    .filter_map(|(k, segment)| {
                        let [a, b] = segment.nodes;
                        project(&x[s], &x[a], &x[b], k)
                    })
                    .filter(|(_, hit, length)| hit.gap < 0.0 && -hit.gap < *length),
            );
            if let Some(hit) = hit {
                let [a, b] = contact.segments[hit.segment].nodes;
                let f = law.force(&mass, [s, a, b], &hit, &v, 0.1).unwrap();
                distribute(&mut expected, [s, a, b], hit.xi, f);
            }
        }
        assert!(expected.iter().any(|f| f[1] != 0.0));
        for (got, want) in force.iter().zip(&expected) {
            assert!((got[0] - want[0]).abs() < 1e-12 && (got[1] - want[1]).abs() < 1e-12);
        }
    }
}
