//! The remap of the Eulerian cycle: the material the Lagrange step moved across the fixed
//! faces is carried back, one direction at a time (Strang-like alternation: `r` then `z` on
//! even cycles, `z` then `r` on odd ones).
//!
//! - **Cell-centred**: a face's swept volume is cut from its donor (upwind) cell as the strip
//!   next to the face holding that share of the donor's volume; each phase's part of it is the
//!   strip clipped against the phase's region of the donor's PLIC reconstruction
//!   ([`super::interface`]), scaled so the phases' parts sum to the swept volume. Mass moves
//!   with the donor material's density; internal energy, stress, plastic strain and its rate,
//!   temperature, damage and EoS history move with the mass (mass-weighted averages, donor
//!   values: first order within a material; the interfaces are second order through PLIC).
//! - **Node-centred momentum** (Benson 1992 sec. 5.3): each nodal control volume exchanges
//!   with its neighbour along the sweep the quarter-sums of the four cell faces' mass fluxes it
//!   straddles, which change the nodal masses exactly as the cell masses change; the velocity
//!   carried is the donor node's with van Leer's limited slope. Momentum is conserved exactly;
//!   the kinetic energy lost is booked ([`super::EulerEnergy::remap`]).

// Cells hold fixed-size arrays per phase, indexed together across several of them.
#![allow(clippy::needless_range_loop)]

use super::interface::{block_cells, line_level, youngs_normal, Interface, Polygon};
use super::lagrange::{apply_walls, FaceFluxes};
use super::{EulerSolver, ACTIVE_FRACTION, MAX_MATERIALS, MAX_PHASES};
use rayon::prelude::*;
use stoss_kernel::{MaterialState, PointModel, StateFlags};

/// Fraction of a cell below which a phase is left out of its reconstruction (it moves with
/// no flux until it grows).
const PRESENT_FRACTION: f64 = 1e-10;

/// Share of a cell below which a material is removed from it by the remap (its volume
/// becomes void, its mass is dropped). Slivers below [`PRESENT_FRACTION`] are not
/// reconstructed and leave a cell in proportion to their volume, so without a floor a sliver
/// spreads a geometrically shrinking tail across the grid, cell by cell, every cycle: a
/// tungsten rod's tail reached the far wall of a 150 mm grid at 1e-307 of a cell after 140 us,
/// where the subnormal volumes and masses give ratios that are not finite. The mass dropped is
/// at most 1e-20 of a cell's per event, far below the conservation checks' 1e-13.
const NEGLIGIBLE_MATERIAL_FRACTION: f64 = 1e-20;

/// A direction of the split remap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Along `r`.
    R,
    /// Along `z`.
    Z,
}

/// The reconstruction of a cell: its present phases in dissection order and the interfaces
/// of all but the last.
#[derive(Clone, Copy, Debug)]
struct Reconstruction {
    phases: [usize; MAX_PHASES],
    count: usize,
    lines: [Interface; MAX_PHASES],
}

/// The remap's work buffers (their contents between sweeps mean nothing).
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    moves: Vec<FaceMove>,
    carried: Vec<FaceCarried>,
}

/// [`Reconstructions::single`] of a cell holding more than one phase.
const MIXED: u8 = u8::MAX;

/// The reconstruction of every cell: a pure cell's phase, or its interfaces.
struct Reconstructions {
    /// The cell's only phase, or [`MIXED`].
    single: Vec<u8>,
    /// Index into `cells` of a mixed cell.
    index: Vec<u32>,
    /// The mixed cells' reconstructions.
    cells: Vec<Reconstruction>,
}

/// What one face moves: its donor cell, each phase's volume and each material's mass. Kept
/// apart from the carried values ([`FaceCarried`]) so that the receipts' scan of every cell's
/// two faces reads one cache line per face (64 bytes).
#[derive(Clone, Copy, Debug, Default)]
struct FaceMove {
    donor: usize,
    volume: [f64; MAX_PHASES],
    mass: [f64; MAX_MATERIALS],
}

/// What a face's moving materials carry: the donor materials' carried variables (see
/// [`carried`]), flags and wave speeds; a material's entries are read only where its
/// [`FaceMove::mass`] is positive.
#[derive(Clone, Copy, Debug, Default)]
struct FaceCarried {
    values: [[f64; CARRIED]; MAX_MATERIALS],
    flags: [u32; MAX_MATERIALS],
    wave: [f64; MAX_MATERIALS],
}

/// Number of state variables the remap carries with the mass.
const CARRIED: usize = 10;

/// The state variables carried with the mass: stress `rr zz tt rz`, plastic strain and rate,
/// temperature, damage, internal energy (per reference volume: with one reference density
/// per material, a mass average) and EoS history.
fn carried(state: &MaterialState) -> [f64; CARRIED] {
    [
        state.stress[0],
        state.stress[1],
        state.stress[2],
        state.stress[3],
        state.plastic_strain,
        state.plastic_strain_rate,
        state.temperature,
        state.damage,
        state.internal_energy,
        state.eos_history,
    ]
}

/// Remap the material moved by `fluxes` (the swept volumes of the Lagrange step).
pub fn remap<P: PointModel + Sync + Send + Clone>(
    s: &mut EulerSolver<P>,
    fluxes: &FaceFluxes,
    _dt: f64,
) {
    let order = if s.cycles.is_multiple_of(2) {
        [Direction::R, Direction::Z]
    } else {
        [Direction::Z, Direction::R]
    };
    for direction in order {
        sweep(s, fluxes, direction);
    }
    finish(s);
}

impl<P: PointModel + Sync + Send + Clone> EulerSolver<P> {
    /// Youngs' PLIC with nested dissection of every cell holding more than one phase.
    fn reconstruct(&self) -> Reconstructions {
        let cells_r = self.grid.cells_r;
        let cells_z = self.grid.cells_z;
        let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
        let planar = !self.axisymmetric();
        let phases_in_use: Vec<usize> = (0..self.materials.len())
            .chain(std::iter::once(MAX_PHASES - 1))
            .collect();
        let fractions: Vec<[f64; MAX_PHASES]> = self
            .volume
            .par_chunks(MAX_PHASES)
            .enumerate()
            .map(|(c, v)| {
                let mut f = [0.0; MAX_PHASES];
                if !super::cell_in_work(&self.active_end, cells_r, c) {
                    // Pure void, as `v / total` gives it.
                    f[MAX_PHASES - 1] = 1.0;
                    return f;
                }
                let total: f64 = v.iter().sum();
                if total > 0.0 {
                    for p in 0..MAX_PHASES {
                        f[p] = v[p] / total;
                    }
                }
                f
            })
            .collect();
        let fraction = |c: usize, p: usize| fractions[c][p];
        // Each cell's only phase, or MIXED.
        let single: Vec<u8> = (0..self.grid.cell_count())
            .into_par_iter()
            .map(|c| {
                let mut present = phases_in_use
                    .iter()
                    .filter(|&&p| fraction(c, p) > PRESENT_FRACTION);
                match (present.next(), present.next()) {
                    (Some(&p), None) => p as u8,
                    (None, _) => (MAX_PHASES - 1) as u8,
                    _ => MIXED,
                }
            })
            .collect();
        let mixed: Vec<usize> = (0..single.len()).filter(|&c| single[c] == MIXED).collect();
        let cells: Vec<Reconstruction> = mixed
            .par_iter()
            .with_max_len(16)
            .map(|&c| {
                let mut r = Reconstruction {
                    phases: [0; MAX_PHASES],
                    count: 0,
                    lines: [Interface {
                        normal: [0.0, 1.0],
                        level: 0.0,
                    }; MAX_PHASES],
                };
                for &p in &phases_in_use {
                    if fraction(c, p) > PRESENT_FRACTION {
                        r.phases[r.count] = p;
                        r.count += 1;
                    }
                }
                if r.count < 2 {
                    return r;
                }
                let (i, j) = (c % cells_r, c / cells_r);
                let corner = self.corner(i, j);
                let mut remaining =
                    Polygon::rectangle(corner[0], corner[0] + h_r, corner[1], corner[1] + h_z);
                let rectangle_volume = remaining.volume(planar);
                for slot in 0..r.count - 1 {
                    let p = r.phases[slot];
                    let block =
                        block_cells(i, j, cells_r, cells_z).map(|row| row.map(|n| fraction(n, p)));
                    let normal = youngs_normal(block, h_r, h_z).unwrap_or([0.0, 1.0]);
                    let level = line_level(
                        &remaining,
                        normal,
                        fraction(c, p) * rectangle_volume,
                        planar,
                    );
                    r.lines[slot] = Interface { normal, level };
                    remaining = remaining.clip_outside(normal, level);
                }
                r
            })
            .collect();
        let mut index = vec![u32::MAX; single.len()];
        for (k, &c) in mixed.iter().enumerate() {
            index[c] = k as u32;
        }
        Reconstructions {
            single,
            index,
            cells,
        }
    }

    /// What the face with swept volume `swept` (positive along the sweep) between cells
    /// `low` and `high` carries.
    fn transfer(
        &self,
        reconstruction: &Reconstructions,
        direction: Direction,
        (low, high, swept): (usize, usize, f64),
        t: &mut FaceMove,
        out: &mut FaceCarried,
    ) {
        let donor = if swept > 0.0 { low } else { high };
        // Only the volumes and masses are reset: the carried values of a material are read
        // only where it moves.
        t.donor = donor;
        t.volume = [0.0; MAX_PHASES];
        t.mass = [0.0; MAX_MATERIALS];
        if swept == 0.0 {
            return;
        }
        let amount = swept.abs();
        let volumes = &self.volume[donor * MAX_PHASES..(donor + 1) * MAX_PHASES];
        let total: f64 = volumes.iter().sum();
        if total <= 0.0 {
            return;
        }
        let mut shares = [0.0; MAX_PHASES];
        if reconstruction.single[donor] != MIXED {
            shares[reconstruction.single[donor] as usize] = 1.0;
        } else {
            let recon = &reconstruction.cells[reconstruction.index[donor] as usize];
            let planar = !self.axisymmetric();
            let cells_r = self.grid.cells_r;
            let (i, j) = (donor % cells_r, donor / cells_r);
            let (h_r, h_z) = (self.grid.spacing_r, self.grid.spacing_z);
            let corner = self.corner(i, j);
            let cell = Polygon::rectangle(corner[0], corner[0] + h_r, corner[1], corner[1] + h_z);
            let fraction = (amount / total).min(1.0);
            let strip_volume = fraction * cell.volume(planar);
            // The strip next to the face, on the donor's downstream side.
            let (normal, cut, keep_high) = match direction {
                Direction::R => {
                    let (r_w, r_e) = (corner[0], corner[0] + h_r);
                    if swept > 0.0 {
                        let cut = if planar {
                            r_e - fraction * h_r
                        } else {
                            libm::sqrt((r_e * r_e - 2.0 * strip_volume / h_z).max(0.0))
                        };
                        ([1.0, 0.0], cut, true)
                    } else {
                        let cut = if planar {
                            r_w + fraction * h_r
                        } else {
                            libm::sqrt(r_w * r_w + 2.0 * strip_volume / h_z)
                        };
                        ([1.0, 0.0], cut, false)
                    }
                }
                Direction::Z => {
                    if swept > 0.0 {
                        ([0.0, 1.0], corner[1] + h_z - fraction * h_z, true)
                    } else {
                        ([0.0, 1.0], corner[1] + fraction * h_z, false)
                    }
                }
            };
            let mut remaining = cell;
            for slot in 0..recon.count {
                let region = if slot + 1 < recon.count {
                    let line = recon.lines[slot];
                    let region = remaining.clip(line.normal, line.level);
                    remaining = remaining.clip_outside(line.normal, line.level);
                    region
                } else {
                    remaining
                };
                let in_strip = if keep_high {
                    region.clip_outside(normal, cut)
                } else {
                    region.clip(normal, cut)
                };
                shares[recon.phases[slot]] = in_strip.volume(planar).max(0.0);
            }
            // Phases too thin to reconstruct leave in proportion to their volume, so no
            // sliver is stranded in a cell.
            let strip = fraction * total;
            for p in 0..MAX_PHASES {
                if shares[p] == 0.0 && volumes[p] > 0.0 && !recon.phases[..recon.count].contains(&p)
                {
                    shares[p] = volumes[p] / total * strip * (cell.volume(planar) / total);
                }
            }
        }
        let sum: f64 = shares.iter().sum();
        if sum <= 0.0 {
            return;
        }
        for p in 0..MAX_PHASES {
            t.volume[p] = (amount * shares[p] / sum).min(volumes[p]);
        }
        // The cells upstream of the donor and downstream of the face, for the slopes.
        let (upstream, downstream) = if swept > 0.0 {
            (self.neighbour(donor, direction, -1), Some(high))
        } else {
            (self.neighbour(donor, direction, 1), Some(low))
        };
        for k in 0..self.materials.len() {
            if t.volume[k] > 0.0 && volumes[k] > 0.0 {
                let slot = donor * MAX_MATERIALS + k;
                let mass = self.mass[slot];
                let density = mass / volumes[k];
                let mut values = carried(&self.state[slot]);
                let mut face_density = density;
                // Second order inside a material (van Leer 1977, MUSCL): where the donor and
                // both neighbours along the sweep are full of it, the density and the carried
                // variables at the face are the donor's plus half its limited slope over the
                // part of the cell not swept.
                if let (Some(up), Some(down)) = (upstream, downstream) {
                    let full = |c: usize| {
                        self.fraction(c, k) >= 1.0 - ACTIVE_FRACTION
                            && self.mass[c * MAX_MATERIALS + k] > 0.0
                    };
                    if full(donor) && full(up) && full(down) {
                        let courant = (t.volume[k] / volumes[k]).min(1.0);
                        let weight = 0.5 * (1.0 - courant);
                        let rho = |c: usize| {
                            self.mass[c * MAX_MATERIALS + k] / self.volume[c * MAX_PHASES + k]
                        };
                        face_density =
                            density + weight * van_leer(density - rho(up), rho(down) - density);
                        let before = carried(&self.state[up * MAX_MATERIALS + k]);
                        let after = carried(&self.state[down * MAX_MATERIALS + k]);
                        for ((v, b), a) in values.iter_mut().zip(before).zip(after) {
                            *v += weight * van_leer(*v - b, a - *v);
                        }
                    }
                }
                t.mass[k] = (face_density * t.volume[k]).min(mass);
                out.values[k] = values;
                out.flags[k] = self.state[slot].flags.0;
                out.wave[k] = self.wave_speed[slot];
            }
        }
    }

    /// The cell `step` (+1 or -1) cells from `c` along `direction`, if inside the grid.
    fn neighbour(&self, c: usize, direction: Direction, step: isize) -> Option<usize> {
        let cells_r = self.grid.cells_r;
        let (i, j) = ((c % cells_r) as isize, (c / cells_r) as isize);
        let (i, j) = match direction {
            Direction::R => (i + step, j),
            Direction::Z => (i, j + step),
        };
        (i >= 0 && j >= 0 && (i as usize) < cells_r && (j as usize) < self.grid.cells_z)
            .then(|| j as usize * cells_r + i as usize)
    }
}

/// A face's cells below and above along the sweep (if inside the grid) and its swept volume.
type FaceCells<'a> = dyn Fn(usize) -> (Option<usize>, Option<usize>, f64) + Sync + 'a;

/// One directional sweep.
fn sweep<P: PointModel + Sync + Send + Clone>(
    s: &mut EulerSolver<P>,
    fluxes: &FaceFluxes,
    direction: Direction,
) {
    let cells_r = s.grid.cells_r;
    let cells_z = s.grid.cells_z;
    let nodes_r = s.nodes_r();
    let reconstruction = s.reconstruct();
    // Faces along the sweep: for R, `(cells_r + 1) x cells_z`; for Z, `cells_r x (cells_z + 1)`.
    let (face_count, face_cells): (usize, Box<FaceCells<'_>>) = match direction {
        Direction::R => (
            nodes_r * cells_z,
            Box::new(move |f: usize| {
                let (i, j) = (f % nodes_r, f / nodes_r);
                let low = (i > 0).then(|| j * cells_r + i - 1);
                let high = (i < cells_r).then(|| j * cells_r + i);
                (low, high, fluxes.r[f])
            }),
        ),
        Direction::Z => (
            cells_r * (cells_z + 1),
            Box::new(move |f: usize| {
                let (i, j) = (f % cells_r, f / cells_r);
                let low = (j > 0).then(|| (j - 1) * cells_r + i);
                let high = (j < cells_z).then(|| j * cells_r + i);
                (low, high, fluxes.z[f])
            }),
        ),
    };
    let mut moves = std::mem::take(&mut s.workspace.moves);
    let mut carries = std::mem::take(&mut s.workspace.carried);
    moves.resize(face_count, FaceMove::default());
    carries.resize(face_count, FaceCarried::default());
    let solver = &*s;
    moves
        .par_iter_mut()
        .zip(carries.par_iter_mut())
        .enumerate()
        .with_max_len(super::CELLS_PER_TASK)
        .for_each(|(f, (t, out))| match face_cells(f) {
            (Some(low), Some(high), swept) => {
                solver.transfer(&reconstruction, direction, (low, high, swept), t, out)
            }
            _ => {
                t.volume = [0.0; MAX_PHASES];
                t.mass = [0.0; MAX_MATERIALS];
                t.donor = usize::MAX;
            }
        });
    // The faces below and above each cell along the sweep.
    let faces_of = |c: usize| -> (usize, usize) {
        let (i, j) = (c % cells_r, c / cells_r);
        match direction {
            Direction::R => (j * nodes_r + i, j * nodes_r + i + 1),
            Direction::Z => (j * cells_r + i, (j + 1) * cells_r + i),
        }
    };
    let material_count = s.materials.len();
    let densities: Vec<f64> = s.materials.iter().map(|m| m.model.density()).collect();
    let old_mass = s.cell_masses();
    let active_end = &s.active_end;
    // In place: a cell reads only its own state and its faces' moves and carried values.
    s.volume
        .par_chunks_mut(MAX_PHASES)
        .zip(s.mass.par_chunks_mut(MAX_MATERIALS))
        .zip(s.state.par_chunks_mut(MAX_MATERIALS))
        .zip(s.wave_speed.par_chunks_mut(MAX_MATERIALS))
        .enumerate()
        .with_max_len(super::CELLS_PER_TASK)
        .for_each(|(c, (((volumes, masses), states), waves))| {
            if !super::cell_in_work(active_end, cells_r, c) {
                return;
            }
            let (below, above) = faces_of(c);
            let faces = [&moves[below], &moves[above]];
            if faces.iter().all(|t| t.volume.iter().all(|&v| v == 0.0)) {
                return;
            }
            let faces_carry = [&carries[below], &carries[above]];
            for t in faces {
                let sign = if t.donor == c { -1.0 } else { 1.0 };
                for p in 0..MAX_PHASES {
                    volumes[p] += sign * t.volume[p];
                }
            }
            for k in 0..material_count {
                let moved = faces.iter().any(|t| t.mass[k] > 0.0);
                if !moved {
                    continue;
                }
                // Mass-weighted: sum = m v - sum_out m_out v_out + sum_in m_in v_in.
                let own = carried(&states[k]);
                let mut sum = [0.0; CARRIED];
                for (s, v) in sum.iter_mut().zip(own) {
                    *s = masses[k] * v;
                }
                let mut total = masses[k];
                // Bounds of the blended values: every contributor's (round-off in a nearly
                // emptied cell cannot leave them).
                let mut low = [f64::INFINITY; CARRIED];
                let mut high = [f64::NEG_INFINITY; CARRIED];
                let mut bound = |values: &[f64; CARRIED]| {
                    for ((l, h), v) in low.iter_mut().zip(high.iter_mut()).zip(values) {
                        *l = l.min(*v);
                        *h = h.max(*v);
                    }
                };
                if masses[k] > 0.0 {
                    bound(&own);
                }
                for (t, out) in faces.iter().zip(faces_carry) {
                    if t.mass[k] > 0.0 {
                        bound(&out.values[k]);
                    }
                }
                let mut wave = if masses[k] > 0.0 { waves[k] } else { 0.0 };
                let mut flags = (masses[k] > 0.0).then_some(states[k].flags);
                for (t, out) in faces.iter().zip(faces_carry) {
                    if t.mass[k] <= 0.0 {
                        continue;
                    }
                    let sign = if t.donor == c { -1.0 } else { 1.0 };
                    for (s, v) in sum.iter_mut().zip(out.values[k]) {
                        *s += sign * t.mass[k] * v;
                    }
                    total += sign * t.mass[k];
                    if t.donor != c {
                        wave = wave.max(out.wave[k]);
                        flags.get_or_insert(StateFlags(out.flags[k]));
                    }
                }
                let state = &mut states[k];
                if total <= 0.0 || volumes[k] <= 0.0 {
                    masses[k] = 0.0;
                    continue;
                }
                if masses[k] == 0.0 {
                    // A material new to the cell: no stored yield check.
                    *state = MaterialState::initial(1.0);
                }
                state.flags = flags.unwrap_or_default();
                masses[k] = total;
                waves[k] = wave;
                for ((s, l), h) in sum.iter_mut().zip(low).zip(high) {
                    *s = (*s / total).clamp(l, h) * total;
                }
                set_blend(state, &sum, total);
                state.relative_volume = densities[k] * volumes[k] / total;
            }
            // Slivers leave: a material below a negligible share of the cell (or without
            // mass) becomes void, and its mass goes (at most 1e-20 of a cell's per event).
            let cell: f64 = volumes.iter().sum();
            for k in 0..material_count {
                if volumes[k] != 0.0
                    && (volumes[k] < NEGLIGIBLE_MATERIAL_FRACTION * cell || masses[k] <= 0.0)
                {
                    volumes[MAX_PHASES - 1] += volumes[k];
                    volumes[k] = 0.0;
                    masses[k] = 0.0;
                }
            }
        });
    remap_momentum(s, &moves, &old_mass, direction);
    s.workspace.moves = moves;
    s.workspace.carried = carries;
}

/// Set the carried variables of `state` to the mass-weighted averages `sum / total`.
fn set_blend(state: &mut MaterialState, sum: &[f64; CARRIED], total: f64) {
    let inverse = 1.0 / total;
    state.stress = [
        sum[0] * inverse,
        sum[1] * inverse,
        sum[2] * inverse,
        sum[3] * inverse,
        0.0,
        0.0,
    ];
    state.plastic_strain = (sum[4] * inverse).max(0.0);
    state.plastic_strain_rate = (sum[5] * inverse).max(0.0);
    state.temperature = sum[6] * inverse;
    state.damage = (sum[7] * inverse).clamp(0.0, 1.0);
    state.internal_energy = sum[8] * inverse;
    state.eos_history = sum[9] * inverse;
    if state.damage >= 1.0 {
        state.flags.insert(StateFlags::FAILED);
    } else {
        state.flags.remove(StateFlags::FAILED);
    }
}

/// Carry nodal momentum with the cell mass fluxes of one sweep.
fn remap_momentum<P: PointModel + Sync + Send + Clone>(
    s: &mut EulerSolver<P>,
    moves: &[FaceMove],
    old_mass: &[f64],
    direction: Direction,
) {
    // `old_mass`: each cell's total mass before the sweep.
    let cells_r = s.grid.cells_r;
    let cells_z = s.grid.cells_z;
    let nodes_r = s.nodes_r();
    let nodes_z = cells_z + 1;
    // Signed mass flux through each face along the sweep.
    let face_mass: Vec<f64> = moves
        .par_iter()
        .enumerate()
        .map(|(f, t)| {
            let m: f64 = t.mass.iter().sum();
            if m == 0.0 {
                return 0.0;
            }
            let positive = match direction {
                Direction::R => {
                    let i = f % nodes_r;
                    i > 0 && t.donor == (f / nodes_r) * cells_r + i - 1
                }
                Direction::Z => {
                    let j = f / cells_r;
                    j > 0 && t.donor == (j - 1) * cells_r + (f % cells_r)
                }
            };
            if positive {
                m
            } else {
                -m
            }
        })
        .collect();
    let node_mass = super::node_masses_of(old_mass, cells_r, cells_z);
    let active_end = &s.active_end;
    let node_in_work = |n: usize| super::node_in_work(active_end, n % nodes_r, n / nodes_r);
    // Flux from node n to its neighbour along the sweep (n, n + stride): the quarter-sum of
    // the four faces it straddles.
    let (stride, along, count_along) = match direction {
        Direction::R => (1, along_r as fn(usize, usize) -> usize, nodes_r),
        Direction::Z => (nodes_r, along_z as fn(usize, usize) -> usize, nodes_z),
    };
    let node_flux = |n: usize| -> f64 {
        let (i, j) = (n % nodes_r, n / nodes_r);
        let mut sum = 0.0;
        match direction {
            Direction::R => {
                // Faces i and i + 1 (of constant r) in rows j - 1 and j.
                for row in [j.wrapping_sub(1), j] {
                    if row < cells_z {
                        for face in [i, i + 1] {
                            if face < nodes_r {
                                sum += face_mass[row * nodes_r + face];
                            }
                        }
                    }
                }
            }
            Direction::Z => {
                for column in [i.wrapping_sub(1), i] {
                    if column < cells_r {
                        for face in [j, j + 1] {
                            if face < nodes_z {
                                sum += face_mass[face * cells_r + column];
                            }
                        }
                    }
                }
            }
        }
        0.25 * sum
    };
    let velocity = s.velocity.clone();
    let upwind = |a: usize, b: usize, flux: f64| -> [f64; 2] {
        // Flux from a to b (> 0) or back; the donor's velocity with a limited slope.
        let (donor, sign) = if flux > 0.0 { (a, 1.0) } else { (b, -1.0) };
        let m = node_mass[donor];
        let courant = if m > 0.0 {
            (flux.abs() / m).min(1.0)
        } else {
            1.0
        };
        let position = along(donor, nodes_r);
        let mut v = velocity[donor];
        if position > 0 && position + 1 < count_along {
            let (prev, next) = (donor - stride, donor + stride);
            if node_mass[prev] > 0.0 && node_mass[next] > 0.0 {
                for d in 0..2 {
                    let slope = van_leer(
                        velocity[donor][d] - velocity[prev][d],
                        velocity[next][d] - velocity[donor][d],
                    );
                    v[d] += sign * 0.5 * (1.0 - courant) * slope;
                }
            }
        }
        v
    };
    // Each link's flux and the velocity it carries, formed once for the two nodes it joins.
    let links: Vec<(f64, [f64; 2])> = (0..velocity.len())
        .into_par_iter()
        .with_max_len(super::CELLS_PER_TASK)
        .map(|n| {
            if along(n, nodes_r) + 1 < count_along && node_in_work(n) {
                let flux = node_flux(n);
                if flux != 0.0 {
                    return (flux, upwind(n, n + stride, flux));
                }
            }
            (0.0, [0.0; 2])
        })
        .collect();
    let new_mass: Vec<f64> = s
        .velocity
        .par_iter_mut()
        .enumerate()
        .map(|(n, v)| {
            if !node_in_work(n) {
                // No mass and no flux: the velocity stays at rest.
                return 0.0;
            }
            let position = along(n, nodes_r);
            let mut mass = node_mass[n];
            let mut momentum = [mass * velocity[n][0], mass * velocity[n][1]];
            if position > 0 {
                let (flux, carried) = links[n - stride];
                if flux != 0.0 {
                    mass += flux;
                    momentum[0] += flux * carried[0];
                    momentum[1] += flux * carried[1];
                }
            }
            if position + 1 < count_along {
                let (flux, carried) = links[n];
                if flux != 0.0 {
                    mass -= flux;
                    momentum[0] -= flux * carried[0];
                    momentum[1] -= flux * carried[1];
                }
            }
            *v = if mass > 0.0 {
                [momentum[0] / mass, momentum[1] / mass]
            } else {
                [0.0; 2]
            };
            mass
        })
        .collect();
    apply_walls(s);
    // Kinetic energy lost by the sweep (summed in a fixed order: independent of the threads).
    let kinetic = |masses: &[f64], velocity: &[[f64; 2]]| -> f64 {
        super::ordered_sum(masses.len(), |n| {
            let v = velocity[n];
            0.5 * masses[n] * (v[0] * v[0] + v[1] * v[1])
        })
    };
    let lost = kinetic(&node_mass, &velocity) - kinetic(&new_mass, &s.velocity);
    s.energy.remap += lost * s.body_factor();
}

/// A node's position along `r`.
fn along_r(n: usize, nodes_r: usize) -> usize {
    n % nodes_r
}

/// A node's position along `z`.
fn along_z(n: usize, nodes_r: usize) -> usize {
    n / nodes_r
}

/// van Leer's harmonic limiter of the one-sided differences `a` and `b`: `2ab / (a + b)`
/// where they have the same sign, else 0.
///
/// Without a branch: the quotient is always formed and masked to `+0.0` where the signs
/// differ (the signs of neighbouring differences are as good as random in a shocked flow, and
/// a mispredicted branch cost more than the division).
#[inline]
fn van_leer(a: f64, b: f64) -> f64 {
    let harmonic = 2.0 * a * b / (a + b);
    let keep = u64::from(a * b > 0.0).wrapping_neg();
    f64::from_bits(harmonic.to_bits() & keep)
}

/// After both sweeps: each cell's phases fill it exactly (void takes the round-off; an
/// overfull cell's materials are scaled to fit), and each material's relative volume is its
/// reference density over its density.
fn finish<P: PointModel + Sync + Send + Clone>(s: &mut EulerSolver<P>) {
    let cells_r = s.grid.cells_r;
    let material_count = s.materials.len();
    let densities: Vec<f64> = s.materials.iter().map(|m| m.model.density()).collect();
    let cell_volumes: Vec<f64> = (0..cells_r).map(|i| s.cell_volume(i)).collect();
    s.volume
        .par_chunks_mut(MAX_PHASES)
        .zip(s.mass.par_chunks_mut(MAX_MATERIALS))
        .zip(s.state.par_chunks_mut(MAX_MATERIALS))
        .enumerate()
        .for_each(|(c, ((volumes, masses), states))| {
            let cell = cell_volumes[c % cells_r];
            for k in 0..material_count {
                if masses[k] <= 0.0 || volumes[k] <= 0.0 {
                    masses[k] = masses[k].max(0.0);
                    if masses[k] == 0.0 {
                        volumes[k] = 0.0;
                    }
                }
            }
            let materials: f64 = volumes[..material_count].iter().sum();
            if materials > cell {
                let scale = cell / materials;
                for v in volumes[..material_count].iter_mut() {
                    *v *= scale;
                }
                volumes[MAX_PHASES - 1] = 0.0;
            } else {
                volumes[MAX_PHASES - 1] = cell - materials;
            }
            for k in 0..material_count {
                if masses[k] > 0.0 && volumes[k] > 0.0 {
                    states[k].relative_volume = densities[k] * volumes[k] / masses[k];
                }
            }
        });
}
