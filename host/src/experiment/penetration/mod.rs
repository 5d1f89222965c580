//! Long-rod penetration against time (seed 000 experiments 1 and 2; Anderson, Hohler, Walker &
//! Stilp, IJIE 16 (1995) 1-18): a rod strikes a target plate along its axis; flash radiographs
//! give the position of the rod's nose inside the target at several times after impact.
//!
//! Quantities (`position` is the time after impact, s, for the histories; 0 otherwise):
//! - `nose_depth` (m): the depth of the rod's nose below the target's original front face: the
//!   lowest point of the rod's remaining (not eroded) elements;
//! - `rod_length` (m): the remaining rod length, tail to nose;
//! - `residual_velocity` (m/s, at the end of the run): the mass-averaged axial velocity of the
//!   rod's remaining elements, positive along the direction of flight;
//! - `residual_mass` (kg, at the end of the run): the mass of the rod's remaining elements.
//!
//! # Model (axisymmetric, [`crate::solver`])
//!
//! - Target (part `target`, the calibrated material): `z in [-T, 0]`, `r in [0, R_t]`; square
//!   elements of `element_size` out to `fine_radius` (default four rod radii, the cavity zone),
//!   then elements growing by `grading_ratio` per element to the rim; the rim clamped
//!   (`v_r = v_z = 0`, seed 000) or free.
//! - Rod (part `rod`, the material file `rod_material`, fixed during a calibration):
//!   `z in [gap, gap + L]`, `r in [0, D/2]`, square elements of `rod_element_size` (default
//!   `element_size`, rounded to fit the radius), moving at `-velocity`; a flat nose, or a
//!   hemispherical or tangent-ogive one mapped onto the same structured mesh and blunted to a
//!   flat tip of `tip_radius`. Time zero of the recording is the impact,
//!   `gap / velocity` after the start of the run.
//! - Eroding contact ([`crate::solver::ErodingContact`]) between rod and target with Coulomb
//!   friction `friction` (default 0: seed 000 does not give its coefficient), eroded mass kept
//!   as free contact nodes (LS-DYNA ENMASS) unless `keep_eroded_mass = false`; single-surface
//!   (each part also meets its own surface, the free nodes every surface) with
//!   `self_contact = true`.
//! - Erosion and failure come from each material file's `[failure]` table (for example
//!   `erosion_geometric_strain = 1.5`, seed 001's Autodyn setting). A run without erosion in
//!   either material stops with an inverted element: the cavity needs erosion.
//! - Tracked states (seed 000 sec. 5): the target elements of two columns, one on the axis and
//!   one at the rod's outer radius, at up to 24 depths each.

pub mod euler;

use super::default_temperature;
use super::{
    check_bulk_viscosity, check_positive, check_run_budget, undeformed_time_step, Check,
    FieldOutput, Outcome, SimulationError,
};
use crate::analytic::penetration::{
    tate_history, tate_resistance_estimate, walker_anderson_history, PenetrationSample, RodTarget,
    STEEL_HUGONIOT, TUNGSTEN_ALLOY_HUGONIOT,
};
use crate::experiment::SummaryValue;
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::{interpolate, StateHistory};
use crate::mesh::{pointed_rod, PointedRod, QuadMesh};
use crate::solver::{
    Amplitude, BulkViscosity, ErodingContact, ExplicitModel, ExplicitRun, HourglassControl,
    Snapshot, SolverError, SolverSettings, VelocityConstraint,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::ops::ControlFlow;
use stoss_kernel::{Material, PartMaterial, PointModel};

/// Quantities a penetration experiment records.
pub const QUANTITIES: &[&str] = &[
    "nose_depth",
    "rod_length",
    "residual_velocity",
    "residual_mass",
];

/// Interval of the nose-position history (s).
pub const SAMPLING: f64 = 0.25e-6;

/// Largest mesh accepted (elements).
const MAXIMUM_ELEMENTS: f64 = 2.0e6;

/// Tracked target elements per column, at most.
const TRACKED_PER_COLUMN: usize = 24;

/// The solver a penetration runs on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PenetrationSolver {
    /// The eroding Lagrangian model ([`crate::solver`], eroding contact).
    #[default]
    Lagrange,
    /// The multi-material Eulerian model ([`crate::euler`]; [`euler`]).
    Euler,
}

/// Boundary condition of the target's outer rim.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rim {
    /// Rim nodes fixed (seed 000).
    #[default]
    Clamped,
    /// Rim free.
    Free,
}

/// Shape of the rod's nose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Nose {
    /// Flat (seed 000's long rods).
    #[default]
    Flat,
    /// Hemispherical: nose length = radius.
    Hemispherical,
    /// Tangent ogive of length `nose_length` (ogive radius `S = (L_n^2 + a^2) / 2a`, caliber
    /// radius head `CRH = S / D`).
    Ogive,
}

/// The nose profile `r(y) / a` at distance `y` behind the tip, `0 <= y <= L_n`, for a rod of
/// radius `a` (0 at the tip, 1 at the shoulder).
fn nose_profile(nose: Nose, y: f64, nose_length: f64, radius: f64) -> f64 {
    let y = y.clamp(0.0, nose_length);
    match nose {
        Nose::Flat => 1.0,
        Nose::Hemispherical => {
            let from_shoulder = radius - y;
            libm::sqrt((radius * radius - from_shoulder * from_shoulder).max(0.0)) / radius
        }
        Nose::Ogive => {
            let ogive_radius = (nose_length * nose_length + radius * radius) / (2.0 * radius);
            let from_shoulder = nose_length - y;
            (libm::sqrt((ogive_radius * ogive_radius - from_shoulder * from_shoulder).max(0.0))
                - (ogive_radius - radius))
                .max(0.0)
                / radius
        }
    }
}

fn default_element_size() -> f64 {
    0.4e-3
}
fn default_grading_ratio() -> f64 {
    1.1
}
fn default_keep_eroded_mass() -> bool {
    true
}
/// Penetration-type runs use the solver's default (viscous) form; the stiffness form is an
/// option whose effect is measured in docs/solver.md, "Hourglass control under a penetrator".
pub(crate) fn default_hourglass() -> HourglassControl {
    HourglassControl::Viscous
}

/// Geometry, materials, loading and discretisation of a long-rod penetration test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PenetrationSpec {
    /// Rod length `L` (m).
    pub rod_length: f64,
    /// Rod diameter `D` (m).
    pub rod_diameter: f64,
    /// The rod's material file, relative to the experiment file (the calibrated material is
    /// the target's).
    pub rod_material: String,
    /// Striking velocity (m/s).
    pub velocity: f64,
    /// Target thickness `T` (m).
    pub target_thickness: f64,
    /// Target radius `R_t` (m).
    pub target_radius: f64,
    /// Rim condition.
    #[serde(default)]
    pub target_rim: Rim,
    /// The solver: `"lagrange"` (eroding Lagrangian) or `"euler"` (multi-material Eulerian;
    /// `element_size` is then its cell size, and the Lagrangian mesh and contact fields are
    /// not used).
    #[serde(default)]
    pub solver: PenetrationSolver,
    /// Element edge in the rod and the cavity zone (m): 0.4 mm for calibration, 0.2 mm as in
    /// seed 000.
    #[serde(default = "default_element_size")]
    pub element_size: f64,
    /// Element edge in the rod (m); default `element_size` (seed 001's ballistic model meshes
    /// the core at 0.4 mm against a 0.2 mm plate).
    #[serde(default)]
    pub rod_element_size: Option<f64>,
    /// Nose shape.
    #[serde(default)]
    pub nose: Nose,
    /// Nose length (m): required for an ogive (at least the rod radius: a tangent ogive);
    /// the radius for a hemisphere.
    #[serde(default)]
    pub nose_length: Option<f64>,
    /// Radius of the flat tip (meplat) that blunts a pointed nose (m); default a fifth of the
    /// rod radius. The profile is `r(y) = r_tip + (a - r_tip) r_nose(y) / a`: a mesh needs a
    /// tip of finite width (the elements at a sharp point have no area).
    #[serde(default)]
    pub tip_radius: Option<f64>,
    /// Radius of the target's uniformly fine zone (m); default four rod radii.
    #[serde(default)]
    pub fine_radius: Option<f64>,
    /// Growth of the target's element size per element outside the fine zone.
    #[serde(default = "default_grading_ratio")]
    pub grading_ratio: f64,
    /// Initial gap between the rod's nose and the target (m); default a tenth of an element.
    #[serde(default)]
    pub gap: Option<f64>,
    /// Coulomb friction between rod and target.
    #[serde(default)]
    pub friction: f64,
    /// Keep the mass of eroded elements as free contact nodes (LS-DYNA ENMASS).
    #[serde(default = "default_keep_eroded_mass")]
    pub keep_eroded_mass: bool,
    /// Single-surface contact: each part also meets its own surface (a mushrooming head
    /// folding onto the shank, a crater lip folding over), and the free mass points meet every
    /// surface, their own part's included. Default `false`: rod against target only
    /// (docs/solver.md gives the measured effect of both).
    #[serde(default)]
    pub self_contact: bool,
    /// Move the rod as a rigid body (LS-DYNA `*MAT_RIGID`): its material gives only its
    /// density; it neither deforms nor erodes, and its elements set no time step.
    #[serde(default)]
    pub rigid_rod: bool,
    /// Hourglass control of the one-point quads: `"viscous"` (the default; LS-DYNA `IHQ = 1`)
    /// or `"stiffness"` (`IHQ = 4`), with the solver's coefficient 0.1.
    #[serde(default = "default_hourglass")]
    pub hourglass: HourglassControl,
    /// Bulk-viscosity coefficients, `[setup.bulk_viscosity]` with `quadratic` and `linear`
    /// (LS-DYNA `*CONTROL_BULK_VISCOSITY` Q1 and Q2; Autodyn's quadratic and linear
    /// viscosity); absent: the run's settings (LS-DYNA's 1.5 and 0.06).
    #[serde(default)]
    pub bulk_viscosity: Option<BulkViscosity>,
    /// Void insertion on the Eulerian grid (`solver = "euler"` only): a material with a
    /// hydrodynamic tensile limit (`[failure] pressure_cutoff`) fractures there, and void opens
    /// beside it instead of the material stretching at the limit (CTH's fracture model; the
    /// Eulerian counterpart of erosion by spall). Default `false`.
    #[serde(default)]
    pub void_insertion: bool,
    /// Frictionless sliding between rod and target on the Eulerian grid (`solver = "euler"`
    /// only): in the cells along their interface each material's shear on the interface plane
    /// is released, so neither resists nor heats by sliding past the other
    /// ([`crate::euler::EulerSettings::sliding_interfaces`]; docs/euler.md, "A rod that does
    /// not erode"). Default `false`: the one velocity field welds them.
    #[serde(default)]
    pub sliding_interface: bool,
    /// End of the simulated time after impact (s).
    pub end_time: f64,
    /// Initial temperature (K).
    #[serde(default = "default_temperature")]
    pub temperature: f64,
    /// The rod's material (either model family), loaded from `rod_material` with the
    /// experiment.
    #[serde(skip)]
    pub rod: Option<Box<PartMaterial>>,
}

/// Measured histories of a penetration run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PenetrationResult {
    /// `(time after impact, nose depth)`.
    pub nose_depth: Vec<(f64, f64)>,
    /// `(time after impact, remaining rod length)`.
    pub rod_length: Vec<(f64, f64)>,
    /// `(time after impact, mass-averaged rod velocity along the flight)`.
    pub rod_velocity: Vec<(f64, f64)>,
    /// Remaining rod mass at the end (kg).
    pub residual_mass: f64,
    /// Mass-averaged rod velocity at the end (m/s).
    pub residual_velocity: f64,
}

impl PenetrationResult {
    /// The run against time as `stoss simulate` writes it (`penetration.svg` and its numbers,
    /// `penetration.csv`): the nose depth and the rod's length, Walker–Anderson's and Tate's
    /// semi-infinite nose depths beside them (when `target` is a J2 metal and the cross-check
    /// applies; [`PenetrationSpec::cross_check`]), and the recorded points with their
    /// uncertainty.
    pub fn report(
        &self,
        spec: &PenetrationSpec,
        target: &PartMaterial,
        recording: &[RecordedPoint],
    ) -> crate::figure::ExperimentReport {
        use crate::figure::{Chart, ExperimentReport, Series, Style};
        let in_units = |history: &[(f64, f64)]| -> Vec<(f64, f64)> {
            history.iter().map(|&(t, x)| (t * 1e6, x * 1e3)).collect()
        };
        let line = |label: &str, points, style, colour| Series {
            label: label.into(),
            points,
            style,
            colour,
            errors: Vec::new(),
        };
        let mut series = vec![
            line("FE nose depth", in_units(&self.nose_depth), Style::Line, 0),
            line("FE rod length", in_units(&self.rod_length), Style::Line, 2),
        ];
        if let Some(check) = target.j2().and_then(|m| spec.cross_check(m).ok()) {
            let depth = |history: &[crate::analytic::penetration::PenetrationSample]| {
                history
                    .iter()
                    .map(|s| (s.time * 1e6, s.nose_depth * 1e3))
                    .collect()
            };
            series.push(line(
                "Walker-Anderson nose depth (semi-infinite)",
                depth(&check.walker_anderson),
                Style::Dashed,
                3,
            ));
            series.push(line(
                "Tate nose depth (semi-infinite)",
                depth(&check.tate),
                Style::Dashed,
                4,
            ));
        }
        for (quantity, label, colour) in [
            ("nose_depth", "recorded nose depth", 1),
            ("rod_length", "recorded rod length", 5),
        ] {
            let points: Vec<&RecordedPoint> = recording
                .iter()
                .filter(|p| p.quantity == quantity)
                .collect();
            if !points.is_empty() {
                series.push(Series {
                    label: label.into(),
                    points: points
                        .iter()
                        .map(|p| (p.position * 1e6, p.value * 1e3))
                        .collect(),
                    style: Style::Markers,
                    colour,
                    errors: points.iter().map(|p| p.uncertainty * 1e3).collect(),
                });
            }
        }
        ExperimentReport {
            text: "penetration against time: penetration.svg (numbers: penetration.csv)\n".into(),
            charts: vec![Chart {
                file: "penetration.svg".into(),
                title: format!(
                    "Rod into a {:.1} mm plate at {:.0} m/s",
                    spec.target_thickness * 1e3,
                    spec.velocity
                ),
                x_label: "time after impact (us)".into(),
                y_label: "nose depth and rod length (mm)".into(),
                series,
            }],
            snapshots: Vec::new(),
            maps: Vec::new(),
            shot_fields: Vec::new(),
        }
    }

    /// The prediction of each recorded point, in the recording's order.
    pub fn predictions(&self, recording: &[RecordedPoint]) -> Vec<f64> {
        recording
            .iter()
            .map(|point| match point.quantity.as_str() {
                "nose_depth" => interpolate(&self.nose_depth, point.position),
                "rod_length" => interpolate(&self.rod_length, point.position),
                "residual_velocity" => self.residual_velocity,
                "residual_mass" => self.residual_mass,
                _ => f64::NAN,
            })
            .collect()
    }
}

/// The meshed model and the element and node sets the measurements use.
#[derive(Clone, Debug)]
pub struct PenetrationModel {
    /// The explicit model; each part has its own model family (a J2 rod against a J2 plate,
    /// or an elastic steel projectile against RHT concrete).
    pub model: ExplicitModel<QuadMesh, PartMaterial>,
    /// The rod's elements.
    pub rod_elements: Vec<usize>,
    /// Time of impact in the run (s).
    pub impact_time: f64,
    /// Smallest element edge (m).
    pub smallest_element: f64,
}

/// A constant-velocity penetration ([`PenetrationSpec::run_driven`]).
pub struct DrivenPenetration {
    /// The target's mean axial resistance `(nose depth (m), force (N))` over each window of
    /// travel.
    pub resistance: Vec<(f64, f64)>,
    /// The run.
    pub run: ExplicitRun,
    /// The model, its rod made rigid and driven.
    pub model: PenetrationModel,
}

impl PenetrationModel {
    /// The rod's nodes, in increasing order.
    pub fn rod_nodes(&self) -> Vec<usize> {
        let mut nodes: Vec<usize> = self
            .rod_elements
            .iter()
            .flat_map(|&e| self.model.mesh.elements[e])
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// Axial position of the rod's tip in the reference configuration (m).
    pub fn rod_tip(&self) -> f64 {
        self.rod_nodes()
            .iter()
            .map(|&n| self.model.mesh.nodes[n][1])
            .fold(f64::INFINITY, f64::min)
    }
}

/// The check of a spec built in code rather than read from a file: the error names `what`
/// and the field, without a line.
fn in_code(what: &str) -> impl Fn(&str, bool, &str) -> Result<(), InputError> + '_ {
    move |field, ok, message| {
        if ok {
            Ok(())
        } else {
            Err(InputError::Field {
                path: what.into(),
                line: None,
                field: field.into(),
                message: message.into(),
            })
        }
    }
}

impl PenetrationSpec {
    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        let positive =
            |field: &str, value: f64, unit: &str| check_positive(check, field, value, unit);
        positive("rod_length", self.rod_length, "m")?;
        positive("rod_diameter", self.rod_diameter, "m")?;
        positive("velocity", self.velocity, "m/s")?;
        positive("target_thickness", self.target_thickness, "m")?;
        positive("target_radius", self.target_radius, "m")?;
        positive("element_size", self.element_size, "m")?;
        positive("end_time", self.end_time, "s")?;
        positive("temperature", self.temperature, "K")?;
        if let Some(gap) = self.gap {
            positive("gap", gap, "m")?;
            check(
                "gap",
                gap < self.rod_length,
                "must be smaller than the rod (m)",
            )?;
        }
        check(
            "target_radius",
            self.target_radius > 0.5 * self.rod_diameter,
            "must exceed the rod radius: the rod would overlap the rim",
        )?;
        check(
            "element_size",
            self.element_size <= 0.25 * self.target_thickness,
            "must fit at least four elements through the target",
        )?;
        if let Some(size) = self.rod_element_size {
            positive("rod_element_size", size, "m")?;
        }
        check(
            if self.rod_element_size.is_some() {
                "rod_element_size"
            } else {
                "element_size"
            },
            self.rod_element_size() <= 0.25 * self.rod_diameter,
            "must fit at least two elements across the rod radius",
        )?;
        let radius = 0.5 * self.rod_diameter;
        match self.nose {
            Nose::Flat => check(
                "nose_length",
                self.nose_length.is_none() && self.tip_radius.is_none(),
                "a flat nose has no nose_length or tip_radius",
            )?,
            Nose::Hemispherical => check(
                "nose_length",
                self.nose_length.is_none(),
                "a hemispherical nose is one radius long: leave nose_length out",
            )?,
            Nose::Ogive => {
                let length = self.nose_length.unwrap_or(f64::NAN);
                check(
                    "nose_length",
                    length >= radius && length.is_finite(),
                    "an ogive needs nose_length >= the rod radius (a tangent ogive), in m",
                )?;
            }
        }
        check(
            "nose_length",
            self.nose_length() <= 0.8 * self.rod_length,
            "must be at most 80 % of the rod length",
        )?;
        if let Some(tip) = self.tip_radius {
            check(
                "tip_radius",
                tip > 0.0 && tip < radius,
                "must be between 0 and the rod radius (m)",
            )?;
        }
        if self.nose_length() > 0.0 && self.element_count_estimate() <= MAXIMUM_ELEMENTS {
            if let Err(why) = self.rod_mesh(0.0) {
                check(
                    if self.rod_element_size.is_some() {
                        "rod_element_size"
                    } else {
                        "element_size"
                    },
                    false,
                    &format!("cannot mesh the nose: {why}"),
                )?;
            }
        }
        if let Some(fine) = self.fine_radius {
            positive("fine_radius", fine, "m")?;
        }
        check(
            "grading_ratio",
            (1.0..=1.5).contains(&self.grading_ratio),
            "must be in 1..=1.5",
        )?;
        check(
            "friction",
            self.friction >= 0.0 && self.friction.is_finite(),
            "must be >= 0",
        )?;
        if self.solver == PenetrationSolver::Euler {
            return self.validate_euler(check);
        }
        check(
            "void_insertion",
            !self.void_insertion,
            "applies to the Eulerian solver only (solver = \"euler\"): the Lagrangian model \
             fails and erodes elements instead",
        )?;
        check(
            "sliding_interface",
            !self.sliding_interface,
            "applies to the Eulerian solver only (solver = \"euler\"): the Lagrangian model's \
             contact slides already (with `friction`)",
        )?;
        // A run must stay affordable: the element count at the given size, and the steps to
        // `end_time` at the undeformed stable step (distortion near the erosion strain makes
        // the real count several times larger).
        let elements = self.element_count_estimate();
        check(
            "element_size",
            elements <= MAXIMUM_ELEMENTS,
            &format!(
                "gives about {elements:.0} elements (more than {MAXIMUM_ELEMENTS:.0}): check the \
                 units (m)"
            ),
        )?;
        check_bulk_viscosity(check, self.bulk_viscosity.as_ref())?;
        check_run_budget(check, self.end_time, self.undeformed_time_step(), elements)
    }

    /// The stable step of the smallest undeformed element (the target's, the rod's or, for a
    /// pointed nose, the O-grid's smallest, whose edges are at least a fifth of the rod's
    /// element size) (s).
    fn undeformed_time_step(&self) -> f64 {
        let viscosity = self
            .bulk_viscosity
            .map_or(1.0, |viscosity| viscosity.linear_step_factor());
        if self.rigid_rod {
            return viscosity * undeformed_time_step(self.element_size, true);
        }
        let tip = if self.nose_length() > 0.0 {
            0.2 * self.rod_element_size()
        } else {
            self.rod_element_size()
        };
        viscosity
            * undeformed_time_step(
                self.element_size.min(self.rod_element_size()).min(tip),
                true,
            )
    }

    /// Rough element count of the mesh (for the size guard).
    fn element_count_estimate(&self) -> f64 {
        let h = self.element_size;
        let h_rod = self.rod_element_size();
        let rod = (0.5 * self.rod_diameter / h_rod).ceil() * (self.rod_length / h_rod).ceil();
        let fine = self.fine_radius().min(self.target_radius);
        let graded = if self.grading_ratio > 1.0 {
            libm::log((self.target_radius - fine) / h * (self.grading_ratio - 1.0) + 1.0)
                / libm::log(self.grading_ratio)
        } else {
            (self.target_radius - fine) / h
        };
        rod + (fine / h + graded.max(0.0)).ceil() * (self.target_thickness / h).ceil()
    }

    /// Element edge in the rod (m).
    pub fn rod_element_size(&self) -> f64 {
        self.rod_element_size.unwrap_or(self.element_size)
    }

    /// Nose length (m): 0 for a flat nose.
    pub fn nose_length(&self) -> f64 {
        match self.nose {
            Nose::Flat => 0.0,
            Nose::Hemispherical => 0.5 * self.rod_diameter,
            Nose::Ogive => self.nose_length.unwrap_or(0.0),
        }
    }

    /// Tip (meplat) radius of a pointed nose (m).
    pub fn tip_radius(&self) -> f64 {
        match self.nose {
            Nose::Flat => 0.5 * self.rod_diameter,
            _ => self.tip_radius.unwrap_or(0.1 * self.rod_diameter),
        }
    }

    /// Radius of the uniformly fine zone of the target (m).
    pub fn fine_radius(&self) -> f64 {
        self.fine_radius.unwrap_or(2.0 * self.rod_diameter)
    }

    /// Initial gap (m).
    pub fn gap(&self) -> f64 {
        self.gap.unwrap_or(0.1 * self.element_size)
    }

    /// Radial node coordinates of the target: uniform to the fine radius, then growing by the
    /// grading ratio, the last element closing on the rim.
    fn target_radii(&self) -> Vec<f64> {
        let h = self.element_size;
        let fine = self.fine_radius().min(self.target_radius);
        let uniform = ((fine / h).round() as usize).max(1);
        let mut radii: Vec<f64> = (0..=uniform)
            .map(|i| fine * i as f64 / uniform as f64)
            .collect();
        let mut size = fine / uniform as f64;
        let mut r = fine;
        while self.target_radius - r > 1e-9 * self.target_radius {
            size *= self.grading_ratio;
            let remaining = self.target_radius - r;
            // Close on the rim rather than leave a sliver below half an element.
            r = if remaining < 1.5 * size {
                self.target_radius
            } else {
                r + size
            };
            radii.push(r);
        }
        radii
    }

    /// The rod's mesh, its tip at `z = tip`: a structured block for a flat nose, an O-grid
    /// following the blunted profile for a pointed one ([`pointed_rod`]); `Err` says why a
    /// pointed nose cannot be meshed at the rod's element size.
    fn rod_mesh(&self, tip: f64) -> Result<QuadMesh, String> {
        let radius = 0.5 * self.rod_diameter;
        let h_rod = self.rod_element_size();
        let nose_length = self.nose_length();
        if nose_length > 0.0 {
            let meplat = self.tip_radius();
            let nose = self.nose;
            let profile = move |y: f64| {
                meplat + (radius - meplat) * nose_profile(nose, y, nose_length, radius)
            };
            return pointed_rod(
                "rod",
                1,
                &PointedRod {
                    radius,
                    length: self.rod_length,
                    nose_length,
                    profile: &profile,
                    element_size: h_rod,
                    tip,
                },
            );
        }
        let rod_radial = ((radius / h_rod).round() as usize).max(2);
        let rod_axial = ((self.rod_length / h_rod).round() as usize).max(4);
        let rod_rs: Vec<f64> = (0..=rod_radial)
            .map(|i| radius * i as f64 / rod_radial as f64)
            .collect();
        let rod_zs: Vec<f64> = (0..=rod_axial)
            .map(|j| tip + self.rod_length * j as f64 / rod_axial as f64)
            .collect();
        Ok(QuadMesh::structured("rod", 1, &rod_rs, &rod_zs))
    }

    /// The finite-element model with `target` the calibrated material and `rod` the rod's;
    /// `Err` if the pointed nose cannot be meshed at the rod's element size.
    pub fn model(
        &self,
        target: &PartMaterial,
        rod: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<PenetrationModel, SolverError> {
        // Every run path builds here, so a spec edited in code gets a file's up-front checks
        // (sizes, run budget) and is refused with the field named instead of running away.
        self.validate(&in_code("penetration spec"))
            .map_err(|error| SolverError::Model(error.to_string()))?;
        let h = self.element_size;
        let radius = 0.5 * self.rod_diameter;
        let thickness = self.target_thickness;
        let axial = ((thickness / h).round() as usize).max(4);
        let zs: Vec<f64> = (0..=axial)
            .map(|j| -thickness + thickness * j as f64 / axial as f64)
            .collect();
        let mut mesh = QuadMesh::structured("target", 0, &self.target_radii(), &zs);
        let target_radial = mesh.node_set("target.bottom").map_or(0, |s| s.len() - 1);
        let target_elements = mesh.elements.len();
        let gap = self.gap();
        let rod_first_node = mesh.nodes.len();
        let rod_mesh = self
            .rod_mesh(gap)
            .map_err(|why| SolverError::Model(format!("the rod's nose mesh: {why}")))?;
        mesh.append(rod_mesh);
        let rod_elements: Vec<usize> = (target_elements..mesh.elements.len()).collect();
        let mut initial_velocity = vec![[0.0; 3]; mesh.nodes.len()];
        for velocity in initial_velocity.iter_mut().skip(rod_first_node) {
            velocity[1] = -self.velocity;
        }
        let set = |name: &str| mesh.node_set(name).unwrap_or(&[]).to_vec();
        let fixed = |nodes: Vec<usize>, dof: usize| VelocityConstraint {
            nodes,
            dof,
            velocity: Amplitude::constant(0.0),
        };
        let mut constraints = vec![fixed(set("target.axis"), 0), fixed(set("rod.axis"), 0)];
        if self.target_rim == Rim::Clamped {
            constraints.push(fixed(set("target.outer"), 0));
            constraints.push(fixed(set("target.outer"), 1));
        }
        // Two target columns (axis; rod's outer radius), up to 24 depths each, front first.
        let radii = self.target_radii();
        let outer_column = radii
            .windows(2)
            .position(|w| w[1] >= radius)
            .unwrap_or(0)
            .min(target_radial.saturating_sub(1));
        let stride = axial.div_ceil(TRACKED_PER_COLUMN).max(1);
        let mut tracked_elements = Vec::new();
        for column in [0, outer_column] {
            for row in (0..axial).rev().step_by(stride) {
                tracked_elements.push(row * target_radial + column);
            }
        }
        let impact_time = gap / self.velocity;
        let end_time = impact_time + self.end_time;
        let model = ExplicitModel {
            mesh,
            materials: vec![*target, *rod],
            initial_temperature: self.temperature,
            initial_velocity,
            constraints,
            walls: Vec::new(),
            contacts: Vec::new(),
            eroding_contact: Some(ErodingContact {
                keep_eroded_mass: self.keep_eroded_mass,
                self_contact: self.self_contact,
                ..ErodingContact::new(vec![0, 1], self.friction)
            }),
            rigid_parts: if self.rigid_rod { vec![1] } else { Vec::new() },
            pressure_loads: Vec::new(),
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time,
                hourglass: self.hourglass,
                bulk_viscosity: self.bulk_viscosity.unwrap_or(settings.bulk_viscosity),
                damping: None,
                output_interval: SAMPLING,
                ..settings.clone()
            },
            tracked_elements,
        };
        let smallest_element = model.mesh.smallest_edge();
        Ok(PenetrationModel {
            model,
            rod_elements,
            impact_time,
            smallest_element,
        })
    }

    /// Run the model to `end_time` and measure the rod's histories.
    pub fn run(
        &self,
        target: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<(PenetrationResult, ExplicitRun, PenetrationModel), SolverError> {
        self.run_until(target, settings, &mut |_, _, _| ControlFlow::Continue(()))
    }

    /// Run the model and measure the rod's histories until `decided` breaks (it sees the mesh,
    /// each output snapshot and the histories so far) or `end_time`.
    pub fn run_until(
        &self,
        target: &PartMaterial,
        settings: &SolverSettings,
        decided: &mut (dyn FnMut(&QuadMesh, &Snapshot, &PenetrationResult) -> ControlFlow<()>
                  + Send),
    ) -> Result<(PenetrationResult, ExplicitRun, PenetrationModel), SolverError> {
        let rod = self.rod.as_deref().copied().ok_or_else(|| {
            SolverError::Model(format!(
                "the rod material `{}` was not loaded",
                self.rod_material
            ))
        })?;
        let built = self.model(target, &rod, settings)?;
        let mesh = &built.model.mesh;
        let rod_density = rod.density();
        let reference_mass: Vec<f64> = built
            .rod_elements
            .iter()
            .map(|&e| {
                let nodes = mesh.elements[e].map(|n| mesh.nodes[n]);
                let mean_radius = 0.25 * nodes.iter().map(|p| p[0]).sum::<f64>();
                2.0 * PI * rod_density * mesh.area(e) * mean_radius
            })
            .collect();
        let mut result = PenetrationResult::default();
        let impact_time = built.impact_time;
        let mut body = ConnectedBody::new(mesh, &built.rod_elements);
        let mut measure = |snapshot: &Snapshot, result: &mut PenetrationResult| {
            let mut low = f64::INFINITY;
            let mut high = f64::NEG_INFINITY;
            let mut mass = 0.0;
            let mut momentum = 0.0;
            body.find(mesh, snapshot.eroded);
            for ((&e, &m), &in_body) in built
                .rod_elements
                .iter()
                .zip(&reference_mass)
                .zip(&body.member)
            {
                if !in_body {
                    continue;
                }
                let nodes = &mesh.elements[e];
                for &n in nodes {
                    low = low.min(snapshot.positions[n][1]);
                    high = high.max(snapshot.positions[n][1]);
                }
                let v_z = 0.25
                    * nodes
                        .iter()
                        .map(|&n| snapshot.velocities[n][1])
                        .sum::<f64>();
                mass += m;
                momentum += m * v_z;
            }
            let time = snapshot.time - impact_time;
            let velocity = if mass > 0.0 { -momentum / mass } else { 0.0 };
            if low.is_finite() {
                result.nose_depth.push((time, (-low).max(0.0)));
                result.rod_length.push((time, high - low));
            } else {
                result.nose_depth.push((time, f64::NAN));
                result.rod_length.push((time, 0.0));
            }
            result.rod_velocity.push((time, velocity));
            result.residual_mass = mass;
            result.residual_velocity = velocity;
        };
        let run = built.model.run_observed(&mut |snapshot| {
            measure(snapshot, &mut result);
            decided(mesh, snapshot, &result)
        })?;
        Ok((result, run, built))
    }

    /// A constant-velocity penetration: the rod, made rigid, is pushed at the striking
    /// velocity for the whole run, and the target's axial resistance is read off the drive's
    /// reaction. This is the set-up of cavity-expansion resistance checks (Forrestal, Okajima &
    /// Luk, J. Appl. Mech. 55 (1988) 755): the target's side of a penetration without the
    /// rod's. The resistance is averaged over every `window` of travel (m). The spec and
    /// the window are checked before anything runs ([`Self::model`]).
    pub fn run_driven(
        &self,
        target: &PartMaterial,
        settings: &SolverSettings,
        window: f64,
    ) -> Result<DrivenPenetration, SolverError> {
        let rod = self.rod.as_deref().copied().ok_or_else(|| {
            SolverError::Model(format!(
                "the rod material `{}` was not loaded",
                self.rod_material
            ))
        })?;
        let speed = self.velocity;
        let driven = Self {
            rigid_rod: true,
            ..self.clone()
        };
        check_positive(&in_code("driven penetration"), "window", window, "m")
            .map_err(|error| SolverError::Model(error.to_string()))?;
        let mut built = driven.model(target, &rod, settings)?;
        let rod_nodes = built.rod_nodes();
        let tip = built.rod_tip();
        let model = &mut built.model;
        model.constraints.push(VelocityConstraint {
            nodes: rod_nodes,
            dof: 1,
            velocity: Amplitude::constant(-speed),
        });
        let drive = model.constraints.len() - 1;
        let run = model.run(&mut |_, _| {})?;
        let mut resistance = Vec::new();
        let (mut sum, mut count, mut from) = (0.0, 0, 0.0);
        for &(time, force) in &run.constraint_forces[drive] {
            sum += force;
            count += 1;
            if time - from >= window / speed {
                resistance.push((speed * time - tip, -sum / f64::from(count)));
                (sum, count, from) = (0.0, 0, time);
            }
        }
        Ok(DrivenPenetration {
            resistance,
            run,
            model: built,
        })
    }

    pub(super) fn simulate(
        &self,
        material: &PartMaterial,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        if self.solver == PenetrationSolver::Euler {
            return self.simulate_euler(material, settings, recording);
        }
        let (result, run, built) = self.run(material, settings)?;
        let predicted = result.predictions(recording);
        let final_depth = result.nose_depth.last().map_or(f64::NAN, |p| p.1);
        let final_length = result.rod_length.last().map_or(f64::NAN, |p| p.1);
        let states: Vec<StateHistory> = run
            .tracked
            .iter()
            .zip(&built.model.tracked_elements)
            .map(|(history, &e)| {
                let mesh = &built.model.mesh;
                let depth = -mesh.elements[e]
                    .iter()
                    .map(|&n| mesh.nodes[n][1])
                    .sum::<f64>()
                    / 4.0;
                let column = if mesh.elements[e].iter().any(|&n| mesh.nodes[n][0] == 0.0) {
                    "axis"
                } else {
                    "rod-radius"
                };
                StateHistory {
                    label: format!(
                        "target {column} column element {e}, depth {:.2} mm",
                        depth * 1e3
                    ),
                    samples: history.samples.clone(),
                }
            })
            .collect();
        Ok(Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("final_nose_depth", final_depth, "m"),
                SummaryValue::new("final_rod_length", final_length, "m"),
                SummaryValue::new("residual_velocity", result.residual_velocity, "m/s"),
                SummaryValue::new("residual_mass", result.residual_mass, "kg"),
                SummaryValue::new(
                    "largest_surface_penetration",
                    run.contact.largest_penetration,
                    "m",
                ),
                SummaryValue::new(
                    "largest_debris_penetration",
                    run.contact.largest_free_node_penetration,
                    "m",
                ),
                // The deepest overlap the eroding contact found on exposure and tolerated
                // (docs/solver.md, "Accuracy"): several elements here means material of one
                // part overlaps the other without resisting.
                SummaryValue::new(
                    "largest_tolerated_overlap",
                    run.contact.largest_initial_penetration,
                    "m",
                ),
                SummaryValue::new("smallest_element", built.smallest_element, "m"),
            ],
            energy: Some(run.energy()),
            states,
            element_cycles: run.element_cycles,
            report: Some(result.report(self, material, recording)),
            field: Some(FieldOutput {
                time: run.final_time(),
                mesh: built.model.mesh,
                positions: run.positions,
                states: run.states,
                cell_data: Vec::new(),
                eroded: run.eroded,
            }),
        })
    }
}

/// The main body of a part: its live elements connected (through shared nodes) to the last
/// live element of its list. For the rod (numbered nose to tail) that is the rod behind its
/// nose: fragments that broke off the nose or flew back from the crater are not the rod whose
/// nose a radiograph shows. For the target (numbered front face outward, the rim last) it is
/// the plate held at the rim, without a plug or debris.
pub struct ConnectedBody {
    /// The part's elements, in the order that puts the seed last.
    elements: Vec<usize>,
    /// Positions in `elements` of the elements around each node.
    around: std::collections::HashMap<usize, Vec<usize>>,
    /// Whether each element (in the order of the list given to [`ConnectedBody::new`])
    /// belongs to the body.
    pub member: Vec<bool>,
    stack: Vec<usize>,
}

impl ConnectedBody {
    /// The body of the part made of `elements` (its last element the seed).
    pub fn new(mesh: &QuadMesh, elements: &[usize]) -> Self {
        let mut around: std::collections::HashMap<usize, Vec<usize>> = Default::default();
        for (k, &e) in elements.iter().enumerate() {
            for &n in &mesh.elements[e] {
                around.entry(n).or_default().push(k);
            }
        }
        Self {
            elements: elements.to_vec(),
            around,
            member: vec![false; elements.len()],
            stack: Vec::new(),
        }
    }

    /// Mark the body among the live elements, seeded at the last live one of the list.
    pub fn find(&mut self, mesh: &QuadMesh, eroded: &[bool]) {
        self.member.iter_mut().for_each(|m| *m = false);
        let Some(seed) = (0..self.elements.len())
            .rev()
            .find(|&k| !eroded[self.elements[k]])
        else {
            return;
        };
        self.stack.clear();
        self.stack.push(seed);
        self.member[seed] = true;
        while let Some(k) = self.stack.pop() {
            for n in mesh.elements[self.elements[k]] {
                for &other in &self.around[&n] {
                    if !self.member[other] && !eroded[self.elements[other]] {
                        self.member[other] = true;
                        self.stack.push(other);
                    }
                }
            }
        }
    }
}

/// The analytic cross-checks of a penetration test (`stoss simulate` prints them beside the FE
/// result): Walker–Anderson's time history and Tate–Alekseevskii's, for a semi-infinite target
/// ([`crate::analytic::penetration`]).
///
/// Inputs from the two materials: the strengths are each material's flow stress at zero
/// plastic strain, zero rate and the initial temperature (the quasi-static yield that users of
/// these models insert); the target's bulk modulus from its longitudinal wave speed at rest
/// (`K = rho c_L^2 - 4G/3`); Tate's `R_t` from Tate's (1986) cavity-expansion estimate; the
/// Hugoniots from Mie-Grüneisen EoS where given (else the steel and tungsten-alloy defaults);
/// the rod's bar wave speed `sqrt(E/rho)`.
#[derive(Clone, Debug)]
pub struct CrossCheck {
    /// The inputs used.
    pub case: RodTarget,
    /// Walker–Anderson history.
    pub walker_anderson: Vec<PenetrationSample>,
    /// Tate–Alekseevskii history.
    pub tate: Vec<PenetrationSample>,
}

/// Elastic moduli `(K, G)` of a material at rest, `K` from the kernel's wave speed.
/// The bulk and shear moduli `(K, G)` of `material` at rest at `temperature` (Pa), `K` from
/// the kernel's longitudinal wave speed.
pub(crate) fn moduli(material: &Material, temperature: f64) -> Result<(f64, f64), String> {
    let mut state = stoss_kernel::MaterialState::initial(temperature);
    state.eos_history = material.eos.initial_history();
    let output = stoss_kernel::update(
        material,
        &mut state,
        &stoss_kernel::StepInput {
            strain_increment: [0.0; 6],
            dt: 1.0,
            relative_volume: 1.0,
        },
    )
    .map_err(|e| e.to_string())?;
    let shear = material.shear_modulus;
    let bulk = material.density * output.wave_speed * output.wave_speed - 4.0 / 3.0 * shear;
    Ok((bulk, shear))
}

fn hugoniot(material: &Material, default: (f64, f64)) -> (f64, f64) {
    match material.eos {
        stoss_kernel::eos::Eos::MieGruneisen(m) => (m.sound_speed, m.s1),
        _ => default,
    }
}

impl PenetrationSpec {
    /// Walker–Anderson and Tate histories for this test with `target` as the target material,
    /// sampled every [`SAMPLING`] to `end_time`.
    pub fn cross_check(&self, target: &Material) -> Result<CrossCheck, String> {
        let case = self.rod_target(target)?;
        let walker_anderson = walker_anderson_history(&case, None, self.end_time, SAMPLING)
            .map_err(|e| e.to_string())?;
        let tate = tate_history(&case, self.end_time, SAMPLING).map_err(|e| e.to_string())?;
        Ok(CrossCheck {
            case,
            walker_anderson,
            tate,
        })
    }

    /// The Tate and Walker–Anderson inputs of this test with `target` as the target material:
    /// each material's flow stress at zero strain and rate, its moduli and Hugoniot.
    pub fn rod_target(&self, target: &Material) -> Result<RodTarget, String> {
        let rod =
            self.rod.as_deref().copied().ok_or_else(|| {
                format!("the rod material `{}` was not loaded", self.rod_material)
            })?;
        let rod = *rod.j2().ok_or_else(|| {
            format!(
                "the rod material `{}` is {}; the Tate and Walker-Anderson estimates need a \
                 J2 metal's flow stress",
                self.rod_material,
                rod.family()
            )
        })?;
        let strength = |m: &Material| m.strength.flow_stress(0.0, 0.0, self.temperature).value;
        let (rod_bulk, rod_shear) = moduli(&rod, self.temperature)?;
        let (target_bulk, target_shear) = moduli(target, self.temperature)?;
        let young = |k: f64, g: f64| 9.0 * k * g / (3.0 * k + g);
        let target_strength = strength(target);
        let case = RodTarget {
            rod_density: rod.density,
            rod_strength: strength(&rod),
            rod_length: self.rod_length,
            rod_diameter: self.rod_diameter,
            rod_bar_wave_speed: (young(rod_bulk, rod_shear) / rod.density).sqrt(),
            rod_hugoniot: hugoniot(&rod, TUNGSTEN_ALLOY_HUGONIOT),
            target_density: target.density,
            target_strength,
            target_resistance: tate_resistance_estimate(
                target_strength,
                young(target_bulk, target_shear),
            )
            .map_err(|e| e.to_string())?,
            target_bulk_modulus: target_bulk,
            target_shear_modulus: target_shear,
            target_hugoniot: hugoniot(target, STEEL_HUGONIOT),
            striking_velocity: self.velocity,
        };
        Ok(case)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tangent_ogive_meets_the_shank_smoothly_and_its_mesh_has_the_profile_volume() {
        // GOAL: the ogive profile is a tangent ogive of the stated caliber radius head, and
        //       the mapped rod mesh has positive areas and the volume of the blunted profile;
        //       the model runs with the experiment's bulk viscosity when it names one.
        // SETUP: D 4 mm, CRH 3 (L_n = D sqrt(CRH - 1/4)), tip radius 0.4 mm, 0.2 mm elements.
        // REFERENCE: tangent ogive geometry: r(0) = 0, r(L_n) = a with zero slope, ogive radius
        //   S = (L_n^2 + a^2) / 2a = CRH D; volume = integral of pi R(y)^2 dy by Simpson's
        //   rule on 2000 intervals, within 1 % (mesh chords under-fill the curve).
        let diameter = 4.0e-3;
        let radius = 0.5 * diameter;
        let nose_length = diameter * (3.0_f64 - 0.25).sqrt();
        assert!(
            ((nose_length.powi(2) + radius * radius) / (2.0 * radius) / diameter - 3.0).abs()
                < 1e-12
        );
        assert_eq!(nose_profile(Nose::Ogive, 0.0, nose_length, radius), 0.0);
        assert!((nose_profile(Nose::Ogive, nose_length, nose_length, radius) - 1.0).abs() < 1e-12);
        let near = nose_profile(Nose::Ogive, nose_length - 1e-6, nose_length, radius);
        assert!((1.0 - near) / 1e-6 * radius < 1e-3, "slope at the shoulder");
        let spec = PenetrationSpec {
            rod_length: 15.0e-3,
            rod_diameter: diameter,
            rod_material: String::new(),
            velocity: 800.0,
            target_thickness: 10.0e-3,
            target_radius: 20.0e-3,
            target_rim: Rim::Clamped,
            solver: PenetrationSolver::Lagrange,
            element_size: 0.2e-3,
            rod_element_size: None,
            nose: Nose::Ogive,
            nose_length: Some(nose_length),
            tip_radius: Some(0.4e-3),
            fine_radius: None,
            grading_ratio: 1.1,
            gap: None,
            friction: 0.0,
            keep_eroded_mass: true,
            self_contact: false,
            rigid_rod: false,
            hourglass: default_hourglass(),
            bulk_viscosity: None,
            void_insertion: false,
            sliding_interface: false,
            end_time: 1.0e-6,
            temperature: 298.0,
            rod: None,
        };
        let material = PartMaterial::from(stoss_kernel::Material::STEEL_4340);
        let built = spec
            .model(&material, &material, &SolverSettings::default())
            .unwrap();
        let mesh = &built.model.mesh;
        let mut volume = 0.0;
        for &e in &built.rod_elements {
            assert!(mesh.area(e) > 0.0, "element {e} inverted");
            let mean_radius = 0.25
                * mesh.elements[e]
                    .iter()
                    .map(|&n| mesh.nodes[n][0])
                    .sum::<f64>();
            volume += 2.0 * PI * mean_radius * mesh.area(e);
        }
        let tip = 0.4e-3;
        let section = |y: f64| {
            let r = tip + (radius - tip) * nose_profile(Nose::Ogive, y, nose_length, radius);
            PI * r * r
        };
        let n = 2000;
        let step = nose_length / n as f64;
        let simpson: f64 = (0..=n)
            .map(|k| {
                let weight = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                weight * section(k as f64 * step)
            })
            .sum::<f64>()
            * step
            / 3.0;
        let expected = simpson + PI * radius * radius * (spec.rod_length - nose_length);
        assert!(
            (volume / expected - 1.0).abs() < 0.01,
            "mesh volume {volume:e} against {expected:e}"
        );
        // The experiment's bulk viscosity reaches the run; without one, the caller's does.
        assert_eq!(
            built.model.settings.bulk_viscosity,
            BulkViscosity::default()
        );
        let autodyn = BulkViscosity {
            quadratic: 1.0,
            linear: 0.2,
        };
        let viscous = PenetrationSpec {
            bulk_viscosity: Some(autodyn),
            ..spec
        };
        let built = viscous
            .model(&material, &material, &SolverSettings::default())
            .unwrap();
        assert_eq!(built.model.settings.bulk_viscosity, autodyn);
    }
}
