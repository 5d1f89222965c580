//! Taylor rod-on-anvil: a rod hits a rigid anvil; its final shape is measured. Quantities:
//! `final_length` (m), `footprint_diameter` (m, at the impact face), `diameter` (m) at
//! `position` = distance from the impact face in the deformed rod (m).
//!
//! **When the shape is final.** The plastic event is over within a few plastic-wave transits;
//! what follows is elastic ringing, damped by nodal damping from the first output at which the
//! summed plastic strain grew by less than [`PLASTIC_SETTLE`] of itself over
//! [`SETTLE_WINDOW_TRANSITS`] transits, at the latest from [`TaylorSpec::damping_start`].
//! The run stops at the first output at which, over the last [`SETTLE_WINDOW_TRANSITS`]
//! elastic transits, (1) the rod's length and its footprint diameter each varied by less than
//! [`SETTLE_FRACTION`] of the recording's smallest uncertainty on a shape quantity (or of
//! [`DEFAULT_SHAPE_UNCERTAINTY`] times `L0` without one), and (2) the plastic strain summed
//! over the elements grew by less than [`PLASTIC_SETTLE`] of itself: the measurement has
//! settled below what the recording can resolve, and no element still deforms plastically.
//! The cap is the former fixed end, damping start plus 40 transits; an explicit `end_time`
//! replaces both, and its damping starts at `damping_start` (the former behaviour). The run says which ended it (`ended_at`, `settled` in the summary).

use super::default_temperature;
use super::{Check, FieldOutput, Outcome, SimulationError};
use crate::experiment::SummaryValue;
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::interpolate;
use crate::mesh::{Grading, HexMesh, QuadMesh};
use crate::solver::{
    Amplitude, AxisymmetricModel, AxisymmetricRun, DampingStart, ExplicitRun, HexModel,
    NodalDamping, PlasticSettle, RigidWall, Snapshot, SolverError, SolverSettings,
    VelocityConstraint,
};
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow;
use stoss_kernel::Material;

/// Quantities a Taylor test records.
pub const QUANTITIES: &[&str] = &["final_length", "footprint_diameter", "diameter"];

fn default_radial() -> usize {
    8
}

/// Window over which the shape must have settled, in elastic transits `L0 / 5000 m/s` (two
/// periods of the rod's fundamental longitudinal mode, `2 L0 / c`).
pub const SETTLE_WINDOW_TRANSITS: f64 = 4.0;

/// The shape has settled when it varies by less than this fraction of the recording's
/// uncertainty over the window.
pub const SETTLE_FRACTION: f64 = 0.1;

/// Relative growth of the summed plastic strain over the window below which no element is
/// still deforming plastically.
pub const PLASTIC_SETTLE: f64 = 1e-4;

/// Uncertainty of a shape measurement, as a fraction of `L0`, when the run has no recording
/// to take it from (a caliper's 0.025 mm on a 25 mm rod).
pub const DEFAULT_SHAPE_UNCERTAINTY: f64 = 1e-3;

/// Geometry, loading and discretisation of a Taylor test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaylorSpec {
    /// Initial rod length `L0` (m).
    pub length: f64,
    /// Initial rod diameter `D0` (m).
    pub diameter: f64,
    /// Impact velocity (m/s).
    pub velocity: f64,
    /// Initial temperature (K).
    #[serde(default = "default_temperature")]
    pub temperature: f64,
    /// Coulomb friction between rod and anvil.
    #[serde(default)]
    pub anvil_friction: f64,
    /// Elements across the radius; the axial count follows from square elements.
    #[serde(default = "default_radial")]
    pub radial_elements: usize,
    /// The model: axisymmetric quads (the default, the calibration model) or a
    /// quarter-symmetric 3D model of hexahedra (to check the axisymmetric one; its `.vtu` is
    /// 3D).
    #[serde(default)]
    pub geometry: TaylorGeometry,
    /// Explicit end time (s) in place of the settling criterion (module documentation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_time: Option<f64>,
}

/// Which model of the rod a Taylor test runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TaylorGeometry {
    /// 2D axisymmetric quads.
    #[default]
    Axisymmetric,
    /// A quarter of the rod in 8-node hexahedra, symmetry planes x = 0 and y = 0.
    #[serde(rename = "quarter-3d")]
    Quarter3d,
}

/// Elastic wave transit time estimate `L / 5000 m/s` (steel-like).
fn transit(length: f64) -> f64 {
    length / 5000.0
}

impl TaylorSpec {
    /// A rod test with default temperature, friction and mesh.
    pub fn new(length: f64, diameter: f64, velocity: f64, radial_elements: usize) -> Self {
        Self {
            length,
            diameter,
            velocity,
            temperature: default_temperature(),
            anvil_friction: 0.0,
            radial_elements,
            geometry: TaylorGeometry::Axisymmetric,
            end_time: None,
        }
    }

    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        check(
            "length",
            self.length > 0.0 && self.length.is_finite(),
            "must be > 0 (m)",
        )?;
        check(
            "diameter",
            self.diameter > 0.0 && self.diameter.is_finite(),
            "must be > 0 (m)",
        )?;
        check(
            "velocity",
            self.velocity > 0.0 && self.velocity.is_finite(),
            "must be > 0 (m/s)",
        )?;
        check("temperature", self.temperature > 0.0, "must be > 0 (K)")?;
        if let Some(end) = self.end_time {
            check(
                "end_time",
                end > 0.0 && end.is_finite(),
                "must be > 0 (s), or left out to end when the shape has settled",
            )?;
        }
        check("anvil_friction", self.anvil_friction >= 0.0, "must be >= 0")?;
        check(
            "radial_elements",
            (2..=200).contains(&self.radial_elements),
            "must be in 2..=200",
        )?;
        // A length in mm entered as m is a runaway, not a test: refuse it up front. The error
        // names the field that makes the run too large: `end_time` if the run would fit at the
        // settling cap, else `radial_elements` if the rod would fit at the default mesh, else
        // `length`.
        let (end_time, step, elements) = self.run_size(self.radial_elements);
        let (end, default_step, default_elements) = self.run_size(default_radial());
        let field = if end_time > self.settling_cap()
            && super::within_run_budget(self.settling_cap(), step, elements)
        {
            "end_time"
        } else if super::within_run_budget(end, default_step, default_elements) {
            "radial_elements"
        } else {
            "length"
        };
        super::check_run_budget_of(check, field, end_time, step, elements)
    }

    /// The end time, undeformed stable step and element count of the rod meshed with `radial`
    /// elements across its radius.
    fn run_size(&self, radial: usize) -> (f64, f64, f64) {
        let size = 0.5 * self.diameter / radial as f64;
        let section = match self.geometry {
            TaylorGeometry::Axisymmetric => radial as f64,
            // The quarter O-grid: a core of (n/2)^2 and two ring blocks of as many.
            TaylorGeometry::Quarter3d => 3.0 * ((radial / 2).max(1) as f64).powi(2),
        };
        let axial = ((self.length / size).round() as usize).max(4);
        (
            self.end_time_or_cap(),
            super::undeformed_time_step(size, false),
            section * axial as f64,
        )
    }

    /// The explicit `end_time`, else [`Self::settling_cap`].
    pub fn end_time_or_cap(&self) -> f64 {
        self.end_time.unwrap_or(self.settling_cap())
    }

    /// The latest end of a settling run: damping start plus 40 elastic transits.
    pub fn settling_cap(&self) -> f64 {
        self.damping_start() + 40.0 * transit(self.length)
    }

    /// The shape tolerance of the settling criterion for `recording`: [`SETTLE_FRACTION`] of
    /// its smallest positive uncertainty on a shape quantity, else of
    /// [`DEFAULT_SHAPE_UNCERTAINTY`] `L0`.
    pub fn shape_tolerance(&self, recording: &[RecordedPoint]) -> f64 {
        let smallest = recording
            .iter()
            .filter(|p| QUANTITIES.contains(&p.quantity.as_str()) && p.uncertainty > 0.0)
            .map(|p| p.uncertainty)
            .fold(f64::INFINITY, f64::min);
        let uncertainty = if smallest.is_finite() {
            smallest
        } else {
            DEFAULT_SHAPE_UNCERTAINTY * self.length
        };
        SETTLE_FRACTION * uncertainty
    }

    /// The observer that ends a run once its shape has settled (module documentation), fed
    /// each output's length, footprint radius and summed plastic strain; `None` with an
    /// explicit `end_time`.
    fn settling(&self, tolerance: f64) -> Option<Settling> {
        self.end_time.is_none().then(|| Settling {
            window: SETTLE_WINDOW_TRANSITS * transit(self.length),
            tolerance,
            records: Vec::new(),
            settled_at: None,
        })
    }

    /// Elements along the rod (square elements).
    pub fn axial_elements(&self) -> usize {
        let size = 0.5 * self.diameter / self.radial_elements as f64;
        ((self.length / size).round() as usize).max(4)
    }

    /// Time at which nodal damping starts: the plastic event is over after a few plastic-wave
    /// transits (at least 30 elastic transits, or 1.2 L0/U).
    pub fn damping_start(&self) -> f64 {
        (1.2 * self.length / self.velocity).max(30.0 * transit(self.length))
    }

    /// Nodal damping (coefficient 2 per elastic transit) from [`Self::damping_start`] at the
    /// latest, or from the end of the plastic event (the summed plastic strain grew by less than
    /// [`PLASTIC_SETTLE`] over [`SETTLE_WINDOW_TRANSITS`] transits) when the run ends by
    /// settling; with an explicit `end_time`, from `damping_start` as before.
    fn damping(&self) -> NodalDamping {
        NodalDamping {
            start_time: self.damping_start(),
            coefficient: 2.0 / transit(self.length),
            start: match self.end_time {
                None => DampingStart::SettledOrAt(PlasticSettle {
                    window: SETTLE_WINDOW_TRANSITS * transit(self.length),
                    fraction: PLASTIC_SETTLE,
                }),
                Some(_) => DampingStart::Fixed,
            },
        }
    }

    /// The finite-element model with `material` for the rod.
    pub fn model(&self, material: &Material, settings: &SolverSettings) -> AxisymmetricModel {
        let radius = 0.5 * self.diameter;
        let mesh = QuadMesh::block(
            "rod",
            0,
            (0.0, radius),
            (0.0, self.length),
            self.radial_elements,
            self.axial_elements(),
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let axis = mesh.node_set("rod.axis").unwrap_or(&[]).to_vec();
        let initial_velocity = vec![[0.0, -self.velocity, 0.0]; mesh.nodes.len()];
        // The elements of the outer column drive the profile measurement; the first rows
        // drive the footprint.
        let tracked = (0..self.axial_elements())
            .map(|row| row * self.radial_elements + self.radial_elements - 1)
            .collect();
        let end_time = self.end_time_or_cap();
        AxisymmetricModel {
            mesh,
            materials: vec![*material],
            initial_temperature: self.temperature,
            initial_velocity,
            constraints: vec![VelocityConstraint {
                nodes: axis,
                dof: 0,
                velocity: Amplitude::constant(0.0),
            }],
            walls: vec![RigidWall {
                point: vec![0.0, 0.0],
                normal: vec![0.0, 1.0],
                friction: self.anvil_friction,
                nodes: Vec::new(),
                motion: None,
            }],
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: Vec::new(),
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time,
                damping: Some(self.damping()),
                output_interval: end_time / 200.0,
                ..settings.clone()
            },
            tracked_elements: tracked,
        }
    }

    /// The same test as a quarter-symmetric 3D model of 8-node hexahedra (O-grid section with
    /// `radial_elements / 2` core and ring divisions; symmetry planes x = 0 and y = 0).
    pub fn model_3d(&self, material: &Material, settings: &SolverSettings) -> HexModel {
        let divisions = (self.radial_elements / 2).max(1);
        let mesh = HexMesh::quarter_rod(
            "rod",
            0,
            0.5 * self.diameter,
            self.length,
            divisions,
            divisions,
            self.axial_elements(),
        );
        let symmetry = |set: &str, dof: usize| VelocityConstraint {
            nodes: mesh.node_sets[&format!("rod.{set}")].clone(),
            dof,
            velocity: Amplitude::constant(0.0),
        };
        let constraints = vec![symmetry("x0", 0), symmetry("y0", 1)];
        let initial_velocity = vec![[0.0, 0.0, -self.velocity]; mesh.nodes.len()];
        let end_time = self.end_time_or_cap();
        HexModel {
            mesh,
            materials: vec![*material],
            initial_temperature: self.temperature,
            initial_velocity,
            constraints,
            walls: vec![RigidWall {
                point: vec![0.0, 0.0, 0.0],
                normal: vec![0.0, 0.0, 1.0],
                friction: self.anvil_friction,
                nodes: Vec::new(),
                motion: None,
            }],
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: Vec::new(),
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time,
                damping: Some(self.damping()),
                output_interval: end_time / 200.0,
                ..settings.clone()
            },
            tracked_elements: Vec::new(),
        }
    }

    /// Run the 3D model until its shape has settled (default tolerance); returns the final
    /// length and the run.
    pub fn run_3d(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<(f64, ExplicitRun), SolverError> {
        let model = self.model_3d(material, settings);
        let (run, _) = self.run_3d_settled(&model, self.shape_tolerance(&[]))?;
        let (low, high) = run
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[2]), hi.max(p[2]))
            });
        Ok((high - low, run))
    }

    /// Run the model until its shape has settled (default tolerance) and measure it.
    pub fn run(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<(TaylorResult, AxisymmetricRun, AxisymmetricModel), SolverError> {
        self.run_to_tolerance(material, settings, self.shape_tolerance(&[]))
    }

    /// [`Self::run`] with the settling criterion's shape tolerance given (m).
    pub fn run_to_tolerance(
        &self,
        material: &Material,
        settings: &SolverSettings,
        tolerance: f64,
    ) -> Result<(TaylorResult, AxisymmetricRun, AxisymmetricModel), SolverError> {
        let model = self.model(material, settings);
        let mut settling = self.settling(tolerance);
        let run = model.run_observed(&mut |snapshot| match settling.as_mut() {
            Some(settling) => settling.observe_rod(snapshot, 1, |p| p[0]),
            None => ControlFlow::Continue(()),
        })?;
        let mut result = TaylorResult::measure(&model.mesh, &run);
        result.ended_at = run.final_time();
        result.settled = settling.is_some_and(|s| s.settled_at.is_some());
        Ok((result, run, model))
    }

    /// Run the 3D model with the settling criterion's shape tolerance `tolerance` (m);
    /// returns the run and whether it settled.
    fn run_3d_settled(
        &self,
        model: &HexModel,
        tolerance: f64,
    ) -> Result<(ExplicitRun, bool), SolverError> {
        let mut settling = self.settling(tolerance);
        let run = model.run_observed(&mut |snapshot| match settling.as_mut() {
            Some(settling) => settling.observe_rod(snapshot, 2, |p| libm::hypot(p[0], p[1])),
            None => ControlFlow::Continue(()),
        })?;
        let settled = settling.is_some_and(|s| s.settled_at.is_some());
        Ok((run, settled))
    }

    pub(super) fn simulate(
        &self,
        material: &Material,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        if self.geometry == TaylorGeometry::Quarter3d {
            return self.simulate_3d(material, settings, recording);
        }
        let (result, run, model) =
            self.run_to_tolerance(material, settings, self.shape_tolerance(recording))?;
        Ok(Outcome {
            field_3d: None,
            predicted: Self::predictions(&result, recording),
            summary: self.summary(&result),
            energy: Some(run.energy()),
            states: run.tracked.clone(),
            element_cycles: run.element_cycles,
            report: None,
            field: Some(FieldOutput {
                time: run.final_time(),
                mesh: model.mesh,
                positions: run.positions,
                states: run.states,
                cell_data: Vec::new(),
                eroded: run.eroded,
            }),
        })
    }
}

impl TaylorSpec {
    /// The named results `stoss simulate` prints: Lf, Df and the diameter at 0.2 L0.
    fn summary(&self, result: &TaylorResult) -> Vec<SummaryValue> {
        vec![
            SummaryValue::new("final_length", result.final_length, "m"),
            SummaryValue::new("footprint_diameter", result.footprint_diameter, "m"),
            SummaryValue::new(
                "diameter_at_0.2_L0",
                result.diameter_at(0.2 * self.length),
                "m",
            ),
            SummaryValue::new("ended_at", result.ended_at, "s"),
            SummaryValue::new("settled", if result.settled { 1.0 } else { 0.0 }, "1"),
        ]
    }

    /// The recorded quantities of `result`, in the recording's order.
    fn predictions(result: &TaylorResult, recording: &[RecordedPoint]) -> Vec<f64> {
        recording
            .iter()
            .map(|point| match point.quantity.as_str() {
                "final_length" => result.final_length,
                "footprint_diameter" => result.footprint_diameter,
                "diameter" => result.diameter_at(point.position),
                _ => f64::NAN,
            })
            .collect()
    }

    /// [`Self::simulate`] with the quarter-symmetric 3D model.
    fn simulate_3d(
        &self,
        material: &Material,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let model = self.model_3d(material, settings);
        let (run, settled) = self.run_3d_settled(&model, self.shape_tolerance(recording))?;
        let mut result = TaylorResult::measure_3d(&model.mesh, &run);
        result.ended_at = run.final_time();
        result.settled = settled;
        Ok(Outcome {
            predicted: Self::predictions(&result, recording),
            summary: self.summary(&result),
            energy: Some(run.energy()),
            states: run.tracked.clone(),
            element_cycles: run.element_cycles,
            report: None,
            field: None,
            field_3d: Some(super::HexFieldOutput {
                time: run.final_time(),
                positions: run.positions.iter().map(|p| [p[0], p[1], p[2]]).collect(),
                mesh: model.mesh,
                states: run.states,
                eroded: run.eroded,
            }),
        })
    }
}

/// Measured final shape.
#[derive(Clone, Debug, PartialEq)]
pub struct TaylorResult {
    /// Final length `Lf` (m).
    pub final_length: f64,
    /// Footprint (mushroom) diameter `Df`: twice the largest radius (m).
    pub footprint_diameter: f64,
    /// Outer profile `(z, radius)` from the impact face, sorted by `z`.
    pub profile: Vec<(f64, f64)>,
    /// Time at which the shape was read (s).
    pub ended_at: f64,
    /// Whether the settling criterion ended the run (else its cap or an explicit `end_time`).
    pub settled: bool,
}

/// The settling criterion's record of a run (module documentation).
struct Settling {
    /// Window (s).
    window: f64,
    /// Shape tolerance (m).
    tolerance: f64,
    /// `(time, length, footprint radius, summed plastic strain)` at each output.
    records: Vec<(f64, f64, f64, f64)>,
    /// When the criterion was met.
    settled_at: Option<f64>,
}

impl Settling {
    /// Record an output of a rod whose axis is coordinate `axial` and whose nodes lie at
    /// `radius(position)` from it; `Break` once the shape has settled.
    fn observe_rod(
        &mut self,
        snapshot: &Snapshot,
        axial: usize,
        radius: fn(&[f64; 3]) -> f64,
    ) -> ControlFlow<()> {
        let (low, high, widest) = snapshot.positions.iter().fold(
            (f64::INFINITY, f64::NEG_INFINITY, 0.0f64),
            |(lo, hi, r), p| (lo.min(p[axial]), hi.max(p[axial]), r.max(radius(p))),
        );
        self.observe(snapshot, high - low, widest)
    }

    /// Record an output's rod length and footprint radius; `Break` once the shape has settled.
    fn observe(&mut self, snapshot: &Snapshot, length: f64, radius: f64) -> ControlFlow<()> {
        let plastic: f64 = snapshot
            .states
            .iter()
            .zip(snapshot.eroded)
            .filter(|(_, gone)| !**gone)
            .map(|(s, _)| s.plastic_strain)
            .sum();
        let time = snapshot.time;
        self.records.push((time, length, radius, plastic));
        let start = time - self.window;
        if start <= 0.0 {
            return ControlFlow::Continue(());
        }
        // The records of the window: from the last output at or before its start.
        let first = self.records.iter().rposition(|r| r.0 <= start).unwrap_or(0);
        let window = &self.records[first..];
        let spread = |value: fn(&(f64, f64, f64, f64)) -> f64| {
            let (lo, hi) = window
                .iter()
                .map(value)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
            hi - lo
        };
        let grown = plastic - window[0].3;
        if spread(|r| r.1) < self.tolerance
            && 2.0 * spread(|r| r.2) < self.tolerance
            && grown <= PLASTIC_SETTLE * plastic
        {
            self.settled_at = Some(time);
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

impl TaylorResult {
    /// Measure the final shape from the outer-surface nodes.
    pub fn measure(mesh: &QuadMesh, run: &AxisymmetricRun) -> Self {
        let (low, high) = run
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[1]), hi.max(p[1]))
            });
        // Positions are measured from the impact face (the rod may have rebounded).
        let outer = mesh.node_set("rod.outer").unwrap_or(&[]);
        let mut profile: Vec<(f64, f64)> = outer
            .iter()
            .map(|&n| (run.positions[n][1] - low, run.positions[n][0]))
            .collect();
        profile.sort_by(|a, b| a.0.total_cmp(&b.0));
        let footprint = run.positions.iter().map(|p| p[0]).fold(0.0, f64::max);
        Self {
            final_length: high - low,
            footprint_diameter: 2.0 * footprint,
            profile,
            ended_at: run.final_time(),
            settled: false,
        }
    }

    /// The final shape of the quarter-symmetric 3D rod: length along `z`; the profile is the
    /// mean radius `sqrt(x^2 + y^2)` of the outer surface's nodes of each axial layer (they
    /// differ around the circumference by the mesh's faceting only), at the layer's mean
    /// distance from the impact face; the footprint twice the largest radius of any node.
    pub fn measure_3d(mesh: &HexMesh, run: &crate::solver::ExplicitRun) -> Self {
        let (low, high) = run
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[2]), hi.max(p[2]))
            });
        let radius = |p: &[f64]| libm::hypot(p[0], p[1]);
        // Group the outer nodes by their reference axial position (layers are exact multiples
        // of the element size, so equal bit patterns).
        let mut layers: std::collections::BTreeMap<u64, (f64, f64, usize)> =
            std::collections::BTreeMap::new();
        for &n in mesh
            .node_sets
            .get("rod.outer")
            .map_or(&[][..], Vec::as_slice)
        {
            let p = &run.positions[n];
            let layer = layers.entry(mesh.nodes[n][2].to_bits()).or_default();
            layer.0 += p[2] - low;
            layer.1 += radius(p);
            layer.2 += 1;
        }
        let mut profile: Vec<(f64, f64)> = layers
            .values()
            .map(|&(z, r, count)| (z / count as f64, r / count as f64))
            .collect();
        profile.sort_by(|a, b| a.0.total_cmp(&b.0));
        let footprint = run.positions.iter().map(|p| radius(p)).fold(0.0, f64::max);
        Self {
            final_length: high - low,
            footprint_diameter: 2.0 * footprint,
            profile,
            ended_at: run.final_time(),
            settled: false,
        }
    }

    /// Diameter of the outer profile at distance `z` from the impact face.
    pub fn diameter_at(&self, z: f64) -> f64 {
        2.0 * interpolate(&self.profile, z)
    }
}
