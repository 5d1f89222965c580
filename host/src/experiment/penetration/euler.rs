//! Long-rod penetration on the Eulerian solver ([`crate::euler`]): the rod and the target
//! as two materials on one fixed axisymmetric grid, void around them; no erosion, no contact.
//!
//! - Grid: square cells of `element_size` from the axis to the target's rim (clamped or slip
//!   there, as `target_rim`), from below the target's rear face (a void layer of a fifth of
//!   the thickness, at least eight cells, so the rear face can bulge) to above the rod's tail.
//! - Measurements, from the rod's volume fraction in the column of cells on the axis:
//!   - `nose_depth`: the rod's lowest point, `z_nose = z_b + (1 - f_b) h - sum_{below} f h`
//!     with `b` the lowest cell at least half full of rod and the rod material below it counted
//!     as a length (continuous in the fractions, so the objective is smooth);
//!   - `rod_length`: the same from the top, tail to nose;
//!   - `residual_velocity`: the mass-averaged axial velocity of the rod material within one
//!     rod diameter of the tail (the undecelerated rod of Tate's model);
//!   - `residual_mass`: the rod material above the nose inside the rod's radius.

use super::{PenetrationResult, PenetrationSpec, SAMPLING};
use crate::blast::euler::{Geometry, Grid};
use crate::euler::{
    EulerError, EulerMaterial, EulerSettings, EulerSolver, Region, Wall, Walls, MAX_MATERIALS,
};
use crate::experiment::SummaryValue;
use crate::measure::StateHistory;
use crate::solver::SolverSettings;
use std::ops::ControlFlow;
use stoss_kernel::{PartMaterial, PointModel};

/// Largest Eulerian grid accepted (cells).
const MAXIMUM_CELLS: f64 = 4.0e6;

/// The rod's material index in the Eulerian model.
pub const ROD: usize = 0;
/// The target's material index.
pub const TARGET: usize = 1;

/// What an Eulerian penetration run produced besides the histories.
#[derive(Clone, Debug)]
pub struct EulerPenetration {
    /// The rod's histories.
    pub result: PenetrationResult,
    /// The solver at the end of the run.
    pub solver: EulerSolver<PartMaterial>,
    /// Time of impact in the run (s).
    pub impact_time: f64,
    /// Tracked target cells' state histories.
    pub tracked: Vec<StateHistory>,
}

impl PenetrationSpec {
    /// The checks of an Eulerian run: the options that only the Lagrangian model has are
    /// refused rather than ignored, and the grid must stay affordable.
    pub(super) fn validate_euler(
        &self,
        check: &crate::experiment::Check,
    ) -> Result<(), crate::input::InputError> {
        let lagrangian_only = "applies to the Lagrangian solver only (solver = \"lagrange\")";
        check(
            "rigid_rod",
            !self.rigid_rod,
            &format!("a rigid rod {lagrangian_only}: the Eulerian solver has no rigid bodies"),
        )?;
        check(
            "friction",
            self.friction == 0.0,
            &format!("friction {lagrangian_only}: the Eulerian solver has no contact"),
        )?;
        check(
            "self_contact",
            !self.self_contact,
            &format!("self_contact {lagrangian_only}: the Eulerian solver has no contact"),
        )?;
        check(
            "rod_element_size",
            self.rod_element_size.is_none(),
            &format!(
                "a separate rod mesh {lagrangian_only}: one grid of element_size holds both parts"
            ),
        )?;
        check(
            "hourglass",
            self.hourglass == crate::solver::HourglassControl::Viscous,
            "the Eulerian solver's hourglass control is the viscous form",
        )?;
        let (cells_r, cells_z) = self.euler_cells();
        let cells = (cells_r * cells_z) as f64;
        check(
            "element_size",
            cells <= MAXIMUM_CELLS,
            &format!(
                "gives an Eulerian grid of {cells_r} x {cells_z} cells (more than \
                 {MAXIMUM_CELLS:.0}): check the units (m)"
            ),
        )?;
        crate::experiment::check_bulk_viscosity(check, self.bulk_viscosity.as_ref())?;
        crate::experiment::check_run_budget(
            check,
            self.end_time,
            EulerSettings::default().courant
                * crate::experiment::undeformed_time_step(self.element_size, true),
            cells,
        )
    }

    /// A material's fracture pressure on the grid: its hydrodynamic tensile limit if void
    /// insertion is on (J2 metals; the concrete models' tensile failure is their own).
    fn fracture_pressure(&self, material: &PartMaterial) -> Option<f64> {
        self.void_insertion
            .then(|| material.j2().and_then(|m| m.failure.pressure_cutoff))
            .flatten()
    }

    /// The void layer below the target's rear face (m).
    fn void_below(&self) -> f64 {
        (0.2 * self.target_thickness).max(8.0 * self.element_size)
    }

    /// Cells `(along r, along z)` of the Eulerian grid.
    pub fn euler_cells(&self) -> (usize, usize) {
        let h = self.element_size;
        let cells_r = (self.target_radius / h).round().max(2.0) as usize;
        let height =
            self.void_below() + self.target_thickness + self.gap() + self.rod_length + 2.0 * h;
        (cells_r, (height / h).ceil() as usize)
    }

    /// The Eulerian model of this test with `target` as the target's material.
    pub fn euler_model(
        &self,
        target: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<EulerSolver<PartMaterial>, EulerError> {
        // Every Eulerian run builds here, so a spec edited in code (a validation row, a
        // coarse fidelity) gets a file's up-front checks (grid bound, run budget) too.
        self.validate(&super::in_code("penetration spec"))
            .map_err(|error| EulerError::Setup(error.to_string()))?;
        let rod = self.rod.as_deref().copied().ok_or_else(|| {
            EulerError::Setup(format!(
                "the rod material `{}` was not loaded",
                self.rod_material
            ))
        })?;
        let h = self.element_size;
        let (cells_r, cells_z) = self.euler_cells();
        let spacing_r = self.target_radius / cells_r as f64;
        let grid = Grid {
            cells_r,
            cells_z,
            spacing_r,
            spacing_z: h,
            geometry: Geometry::Axisymmetric,
        };
        let origin_z = -self.target_thickness - self.void_below();
        let walls = Walls {
            outer: match self.target_rim {
                super::Rim::Clamped => Wall::Fixed,
                super::Rim::Free => Wall::Slip,
            },
            bottom: Wall::Slip,
            top: Wall::Slip,
        };
        let radius = 0.5 * self.rod_diameter;
        let gap = self.gap();
        let nose = self.nose;
        let nose_length = self.nose_length();
        let tip = self.tip_radius();
        let length = self.rod_length;
        let in_rod = move |p: [f64; 2]| {
            let y = p[1] - gap;
            if !(0.0..=length).contains(&y) {
                return false;
            }
            let profile = if y < nose_length {
                tip + (radius - tip) * super::nose_profile(nose, y, nose_length, radius)
            } else {
                radius
            };
            p[0] <= profile
        };
        let thickness = self.target_thickness;
        let in_target = move |p: [f64; 2]| (-thickness..=0.0).contains(&p[1]);
        let regions = [
            Region {
                material: ROD,
                inside: &in_rod,
                velocity: [0.0, -self.velocity],
                temperature: self.temperature,
            },
            Region {
                material: TARGET,
                inside: &in_target,
                velocity: [0.0, 0.0],
                temperature: self.temperature,
            },
        ];
        let euler_settings = EulerSettings {
            bulk_viscosity: self.bulk_viscosity.unwrap_or(settings.bulk_viscosity),
            hourglass_coefficient: settings.hourglass_coefficient,
            threads: settings.threads,
            sliding_interfaces: self.sliding_interface,
            ..EulerSettings::default()
        };
        EulerSolver::new(
            grid,
            origin_z,
            walls,
            vec![
                EulerMaterial {
                    name: "rod".into(),
                    model: rod,
                    fracture_pressure: self.fracture_pressure(&rod),
                },
                EulerMaterial {
                    name: "target".into(),
                    model: *target,
                    fracture_pressure: self.fracture_pressure(target),
                },
            ],
            &regions,
            euler_settings,
        )
    }

    /// Run the Eulerian model to `end_time` after impact and measure the rod.
    pub fn run_euler(
        &self,
        target: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<EulerPenetration, EulerError> {
        let mut solver = self.euler_model(target, settings)?;
        let impact_time = self.gap() / self.velocity;
        let tracked_cells = self.tracked_cells(&solver);
        let mut tracked: Vec<StateHistory> = tracked_cells
            .iter()
            .map(|(_, label)| StateHistory {
                label: label.clone(),
                samples: Vec::new(),
            })
            .collect();
        let mut result = PenetrationResult::default();
        let end = impact_time + self.end_time;
        let progress = settings.progress.clone();
        solver.run(end, SAMPLING, &mut |s| {
            let time = s.time - impact_time;
            let (nose, tail) = rod_extent(s, ROD);
            result.nose_depth.push((time, -nose));
            result.rod_length.push((time, tail - nose));
            let (velocity, mass) =
                rod_body(s, tail, nose, 0.5 * self.rod_diameter, self.rod_diameter);
            result.rod_velocity.push((time, velocity));
            result.residual_velocity = velocity;
            result.residual_mass = mass;
            for (history, (c, _)) in tracked.iter_mut().zip(&tracked_cells) {
                history
                    .samples
                    .push(crate::measure::StateSample::from_state(
                        s.time,
                        &s.state[c * MAX_MATERIALS + TARGET],
                        1,
                    ));
            }
            progress.report(s.time, end);
            ControlFlow::Continue(())
        })?;
        Ok(EulerPenetration {
            result,
            solver,
            impact_time,
            tracked,
        })
    }

    /// The target cells whose states are tracked (seed 000 sec. 5): the axis column and the
    /// column at the rod's radius, at up to 24 depths through the plate.
    fn tracked_cells(&self, solver: &EulerSolver<PartMaterial>) -> Vec<(usize, String)> {
        let h = solver.grid.spacing_z;
        let columns = [
            (0, "axis"),
            (
                ((0.5 * self.rod_diameter) / solver.grid.spacing_r) as usize,
                "rod-radius",
            ),
        ];
        let rows = (self.target_thickness / h).floor() as usize;
        let count = rows.clamp(1, super::TRACKED_PER_COLUMN.max(1));
        let mut cells = Vec::new();
        for (i, name) in columns {
            for k in 0..count {
                let depth = (k as f64 + 0.5) * self.target_thickness / count as f64;
                let j = ((-depth - solver.origin_z) / h) as usize;
                let c = j * solver.grid.cells_r + i.min(solver.grid.cells_r - 1);
                cells.push((
                    c,
                    format!("target {name} column cell {c}, depth {:.2} mm", depth * 1e3),
                ));
            }
        }
        cells
    }
}

/// The rod's lowest and highest points on the axis column: at the lowest (highest) cell at
/// least half full of rod, the fraction read as a length from that cell's far edge, and the
/// rod material beyond it added as length.
pub fn rod_extent<P: PointModel + Sync + Send + Clone>(
    s: &EulerSolver<P>,
    rod: usize,
) -> (f64, f64) {
    let h = s.grid.spacing_z;
    let cells_r = s.grid.cells_r;
    let fraction = |j: usize| s.fraction(j * cells_r, rod);
    let rows = s.grid.cells_z;
    let Some(low) = (0..rows).find(|&j| fraction(j) >= 0.5) else {
        return (f64::NAN, f64::NAN);
    };
    let high = (0..rows).rev().find(|&j| fraction(j) >= 0.5).unwrap_or(low);
    let below: f64 = (0..low).map(fraction).sum();
    let above: f64 = (high + 1..rows).map(fraction).sum();
    let nose = s.origin_z + low as f64 * h + (1.0 - fraction(low)) * h - below * h;
    let tail = s.origin_z + (high + 1) as f64 * h - (1.0 - fraction(high)) * h + above * h;
    (nose, tail)
}

/// `(velocity, mass)` of the rod: the mass-averaged velocity along the flight of the rod
/// material within `reach` of the tail, and the rod mass above the nose inside `radius`.
pub fn rod_body<P: PointModel + Sync + Send + Clone>(
    s: &EulerSolver<P>,
    tail: f64,
    nose: f64,
    radius: f64,
    reach: f64,
) -> (f64, f64) {
    let cells_r = s.grid.cells_r;
    let nodes_r = s.nodes_r();
    let (h_r, h_z) = (s.grid.spacing_r, s.grid.spacing_z);
    let mut momentum = 0.0;
    let mut tail_mass = 0.0;
    let mut body_mass = 0.0;
    for c in 0..s.grid.cell_count() {
        let m = s.mass[c * MAX_MATERIALS + ROD];
        if m <= 0.0 {
            continue;
        }
        let (i, j) = (c % cells_r, c / cells_r);
        let r = (i as f64 + 0.5) * h_r;
        let z = s.origin_z + (j as f64 + 0.5) * h_z;
        if r > radius || z < nose {
            continue;
        }
        body_mass += m;
        if z >= tail - reach {
            let w = 0.25
                * (s.velocity[j * nodes_r + i][1]
                    + s.velocity[j * nodes_r + i + 1][1]
                    + s.velocity[(j + 1) * nodes_r + i][1]
                    + s.velocity[(j + 1) * nodes_r + i + 1][1]);
            momentum += m * w;
            tail_mass += m;
        }
    }
    let velocity = if tail_mass > 0.0 {
        -momentum / tail_mass
    } else {
        0.0
    };
    (velocity, body_mass * s.body_factor())
}

impl EulerPenetration {
    /// The run's energy balance in the Lagrangian solver's form.
    pub fn energy(&self) -> crate::solver::EnergyBalance {
        let e = self.solver.energy;
        crate::solver::EnergyBalance {
            time: self.solver.time,
            kinetic: e.kinetic,
            internal: e.internal,
            hourglass: e.hourglass,
            viscous: e.viscous,
            remap: e.remap,
            initial: e.initial,
            ..Default::default()
        }
    }
}

impl PenetrationSpec {
    /// [`PenetrationSpec::run_euler`] with the recording's predictions and the outcome
    /// `stoss simulate` prints.
    pub(super) fn simulate_euler(
        &self,
        material: &PartMaterial,
        settings: &SolverSettings,
        recording: &[crate::input::recording::RecordedPoint],
    ) -> Result<super::super::Outcome, super::super::SimulationError> {
        let run = self.run_euler(material, settings)?;
        let result = &run.result;
        let predicted = result.predictions(recording);
        let last = |h: &[(f64, f64)]| h.last().map_or(f64::NAN, |p| p.1);
        let s = &run.solver;
        let mut report = result.report(self, material, recording);
        if let (Some(velocity), false) =
            (self.rigid_in_tates_model(material), self.sliding_interface)
        {
            report.text.push_str(&format!(
                "WARNING: Tate's model has this rod penetrate as a rigid body (at striking \
                 velocities up to {velocity:.0} m/s), without eroding. On the Eulerian grid the \
                 one velocity field welds the target to such a rod, which holds it back: an \
                 elastic hemispherical-nosed rod striking a perfectly plastic steel at 800 m/s \
                 reaches 0.78 of the rigid-projectile model's depth at 40 us on 0.4 mm cells. \
                 With sliding_interface = true in [setup] it reaches 0.95 (0.99 on 0.2 mm \
                 cells); the Lagrangian solver reaches 1.06 (docs/euler.md, \"A rod that does \
                 not erode\").\n"
            ));
        }
        Ok(super::super::Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("final_nose_depth", last(&result.nose_depth), "m"),
                SummaryValue::new("final_rod_length", last(&result.rod_length), "m"),
                SummaryValue::new("residual_velocity", result.residual_velocity, "m/s"),
                SummaryValue::new("residual_mass", result.residual_mass, "kg"),
                SummaryValue::new("cell_size", s.grid.spacing_z, "m"),
                SummaryValue::new("cells", s.grid.cell_count() as f64, "1"),
                SummaryValue::new("cycles", s.cycles as f64, "1"),
            ],
            energy: Some(run.energy()),
            states: run.tracked.clone(),
            element_cycles: s.material_updates,
            report: Some(report),
            field: Some(field(&run.solver)),
        })
    }
}

impl PenetrationSpec {
    /// Whether Tate's model has this rod penetrate `target` rigidly at impact
    /// (`Yp >= Rt + rho_t V0^2 / 2`, Tate 1967; the strengths of [`Self::rod_target`]):
    /// `Some(v)`, `v = sqrt(2 (Yp - Rt) / rho_t)` the striking velocity up to which it does;
    /// `None` if the rod erodes from impact or the model cannot be evaluated for these
    /// materials (not J2 metals).
    pub fn rigid_in_tates_model(&self, target: &PartMaterial) -> Option<f64> {
        let case = self.rod_target(target.j2()?).ok()?;
        let margin = case.rod_strength - case.target_resistance;
        (margin >= 0.5 * case.target_density * self.velocity * self.velocity)
            .then(|| (2.0 * margin / case.target_density).sqrt())
    }
}

/// The grid as a ParaView field: one quad per cell (part `rod`, `target` or `void` by the
/// phase with the most volume), the state of its heaviest material, void cells flagged as
/// eroded (the `.vtu` leaves them out), and per-cell volume fractions and density.
pub fn field(s: &EulerSolver<PartMaterial>) -> crate::figure::FieldOutput {
    use crate::euler::MAX_PHASES;
    use crate::mesh::{Part, QuadMesh};
    let nodes_r = s.nodes_r();
    let (h_r, h_z) = (s.grid.spacing_r, s.grid.spacing_z);
    let nodes: Vec<[f64; 2]> = (0..nodes_r * (s.grid.cells_z + 1))
        .map(|n| {
            [
                (n % nodes_r) as f64 * h_r,
                s.origin_z + (n / nodes_r) as f64 * h_z,
            ]
        })
        .collect();
    let cells = s.grid.cell_count();
    let names = ["rod", "target"];
    let mut elements = Vec::with_capacity(cells);
    let mut element_part = Vec::with_capacity(cells);
    let mut states = Vec::with_capacity(cells);
    let mut eroded = Vec::with_capacity(cells);
    let mut fractions: Vec<Vec<f64>> = (0..3).map(|_| Vec::with_capacity(cells)).collect();
    let mut density = Vec::with_capacity(cells);
    for c in 0..cells {
        let (i, j) = (c % s.grid.cells_r, c / s.grid.cells_r);
        let n0 = j * nodes_r + i;
        elements.push([n0, n0 + 1, n0 + 1 + nodes_r, n0 + nodes_r]);
        let f = [
            s.fraction(c, ROD),
            s.fraction(c, TARGET),
            s.fraction(c, MAX_PHASES - 1),
        ];
        let part = (0..3).fold(0, |best, k| if f[k] > f[best] { k } else { best });
        element_part.push(part);
        let heaviest = (0..2).fold(0, |best, k| {
            if s.mass[c * MAX_MATERIALS + k] > s.mass[c * MAX_MATERIALS + best] {
                k
            } else {
                best
            }
        });
        let mass: f64 = (0..2).map(|k| s.mass[c * MAX_MATERIALS + k]).sum();
        states.push(if mass > 0.0 {
            s.state[c * MAX_MATERIALS + heaviest]
        } else {
            stoss_kernel::MaterialState::initial(293.0)
        });
        eroded.push(mass == 0.0);
        for k in 0..3 {
            fractions[k].push(f[k]);
        }
        density.push(mass / s.cell_volume(i));
    }
    let mut cell_data: Vec<(String, Vec<f64>)> = names
        .iter()
        .chain(&["void"])
        .zip(fractions)
        .map(|(name, values)| (format!("fraction_{name}"), values))
        .collect();
    cell_data.push(("density".into(), density));
    let positions = nodes.iter().map(|p| [p[0], p[1], 0.0]).collect();
    crate::figure::FieldOutput {
        mesh: QuadMesh {
            nodes,
            elements,
            element_part,
            parts: ["rod", "target", "void"]
                .iter()
                .enumerate()
                .map(|(k, name)| Part {
                    name: (*name).into(),
                    material: k,
                })
                .collect(),
            node_sets: Default::default(),
            element_sets: Default::default(),
        },
        positions,
        states,
        eroded,
        cell_data,
        time: s.time,
    }
}
