//! A reinforced-concrete beam under a drop weight (seed 001 chapter 5: the FOI drop tests of
//! 1999): a 718 kg weight strikes a steel pad at mid-span at 6.7 m/s; the striker's motion,
//! the beam's accelerations, the bottom bars' strains and the crack pattern are recorded.
//!
//! The model (3D, one-point hexahedra, a quarter by symmetry at mid-span and mid-width):
//! - the concrete is the calibrated part, K&C ([`stoss_kernel::kc`]) with its softening
//!   regularised by crack band: each group of elements of one size gets the band that
//!   releases `fracture_energy` in it (FOI defined one material per element size);
//! - graded along the beam from `element_size` over `fine_length` to `end_element_size` at
//!   the ends, `element_size` across the section; node planes through every bar, every
//!   stirrup, the support and the pad's edge;
//! - reinforcement as truss elements on the concrete's nodes (the seed's merged nodes): the
//!   2 + 2 longitudinal bars elastic-perfectly plastic, the stirrups with the 1 GPa hardening
//!   modulus (seed table 5.4 and its note), every bar breaking when its plastic strain reaches
//!   that at which the stirrups' law meets the tensile strength `fu`;
//! - the steel pad, elastic (its material file), tied to the beam by shared nodes;
//! - the drop weight (`striker = "elastic-head"`, the default): an elastic steel striker head
//!   of the pad's plan size and `head_length` long, in node-to-node contact with the pad
//!   (Coulomb friction; [`crate::solver::contact::node_to_node`]), under a rigid body that
//!   carries the rest of the weight's mass; or (`striker = "rigid-wall"`) a rigid moving wall
//!   with the whole mass on the pad's top face ([`crate::solver::moving_wall`]), which doubles
//!   the first contact stress (`rho c v` instead of the `rho c v / 2` of equal steels);
//! - gravity on everything;
//! - a line support across the bottom face at `support_inset` from the end (free to slide and
//!   rotate); the hydraulic dampers that stopped the weight after 90 mm are not modelled (nor
//!   were they in FOI's model).
//!
//! What is simplified against FOI's LS-DYNA model, and why: only the striker head is elastic,
//! the rest of the weight rigid (its 718 kg move as one body over the 20 ms); the head's
//! shape is a block of the pad's plan size, not the seed's cylinder (whose size is only in its
//! figure 5.1); its contact with the pad is a kinematic node-to-node constraint, not a
//! penalty surface-to-surface contact (the faces slide little); the pad is tied, not in
//! frictional contact with the beam; the longitudinal bars are trusses, not beams (their
//! bending stiffness, `E pi d^4/64`, is 0.001 % of the section's per bar).
//!
//! Quantities: `striker_displacement` (m) and `striker_velocity` (m/s) at `position` = time
//! after impact (s); `beam_acceleration` (m/s^2, vertical, positive up) of the bottom face at
//! `accelerometer_offset` from mid-span, the mean over one output interval ending at
//! `position`; `rebar_strain_midspan` and `rebar_strain_200mm` (the bottom bars' logarithmic
//! strain over the bar element at mid-span and at `gauge_offset`); `first_crack_time` (s) of
//! the bottom fibre ([`classify`]).

use super::{Check, HexFieldOutput, Outcome, SimulationError};
use crate::experiment::SummaryValue;
use crate::figure::{Series, Style};
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::{interpolate, StateHistory};
use crate::mesh::{HexMesh, Part};
use crate::solver::{
    Amplitude, ExplicitModel, NodeToNodeContact, NonlocalAveraging, RigidWall, SolverSettings,
    Truss, TrussMaterial, VelocityConstraint, WallMotion,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use stoss_kernel::{PartMaterial, PointModel};

/// Quantities a drop-weight beam test records.
pub const QUANTITIES: &[&str] = &[
    "striker_displacement",
    "striker_velocity",
    "beam_acceleration",
    "rebar_strain_midspan",
    "rebar_strain_200mm",
    "first_crack_time",
];

/// The damage measure at which a K&C element is cracked: past its peak strength (the state's
/// damage is LS-DYNA's scaled damage measure over 2: 0.5 at the peak, 1 at the residual).
pub const CRACKED: f64 = 0.5;

/// The damage measure at which a crack is open: the strength down to a fifth of the way from
/// the residual to the peak (`eta` = 0.2).
pub const OPEN: f64 = 0.9;

fn default_length() -> f64 {
    4.2
}
fn default_support_inset() -> f64 {
    0.1
}
fn default_width() -> f64 {
    0.17
}
fn default_depth() -> f64 {
    0.34
}
fn default_fracture_energy() -> f64 {
    156.0
}
fn default_element_size() -> f64 {
    0.01
}
fn default_end_element_size() -> f64 {
    0.1
}
fn default_fine_length() -> f64 {
    0.3
}
fn default_bar_diameter() -> f64 {
    0.012
}
fn default_top_bar_cover() -> f64 {
    0.071
}
fn default_bottom_bar_cover() -> f64 {
    0.031
}
fn default_stirrup_diameter() -> f64 {
    0.010
}
fn default_stirrup_count() -> usize {
    11
}
fn default_stirrup_spacing() -> f64 {
    0.15
}
fn default_first_stirrup() -> f64 {
    0.10
}
fn default_pad_length() -> f64 {
    0.10
}
fn default_pad_thickness() -> f64 {
    0.02
}
fn default_head_length() -> f64 {
    0.2
}
fn default_drop_mass() -> f64 {
    718.0
}
fn default_striker_friction() -> f64 {
    0.3
}
fn default_gravity() -> f64 {
    9.81
}
fn default_end_time() -> f64 {
    0.02
}
fn default_output_interval() -> f64 {
    2.0e-5
}
fn default_field_times() -> Vec<f64> {
    vec![6.0e-4]
}
fn default_accelerometer_offset() -> f64 {
    0.1
}
fn default_gauge_offset() -> f64 {
    0.2
}
fn default_rebar() -> Rebar {
    Rebar::default()
}

/// The reinforcing steel (seed 001 table 5.4, Ks 500 ST).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rebar {
    /// Density (kg/m^3).
    pub density: f64,
    /// Young's modulus (Pa).
    pub young_modulus: f64,
    /// Yield stress `fy` (Pa).
    pub yield_stress: f64,
    /// Tensile strength `fu` (Pa).
    pub tensile_strength: f64,
    /// The stirrups' hardening modulus (Pa); the longitudinal bars are perfectly plastic, as
    /// in FOI's model.
    pub stirrup_hardening_modulus: f64,
}

impl Default for Rebar {
    fn default() -> Self {
        Self {
            density: 7800.0,
            young_modulus: 207.0e9,
            yield_stress: 586.0e6,
            tensile_strength: 684.0e6,
            stirrup_hardening_modulus: 1.0e9,
        }
    }
}

impl Rebar {
    /// Plastic strain at which a bar breaks: where the stirrups' bilinear law reaches `fu`,
    /// `(fu - fy) / H` (0.098 for Ks 500 ST).
    pub fn failure_plastic_strain(&self) -> f64 {
        (self.tensile_strength - self.yield_stress) / self.stirrup_hardening_modulus
    }

    fn truss(&self, hardening_modulus: f64) -> TrussMaterial {
        TrussMaterial {
            density: self.density,
            young_modulus: self.young_modulus,
            yield_stress: self.yield_stress,
            hardening_modulus,
            failure_plastic_strain: self.failure_plastic_strain(),
        }
    }
}

/// Geometry, reinforcement, loading and discretisation of a drop-weight beam test (SI).
/// Defaults are seed 001 chapter 5's beam and FOI's mesh; `stoss` chose the pad's size, the
/// bars' side cover and the striker's friction (the seed gives them only in figures or not at
/// all).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DropWeightBeamSpec {
    /// Beam length (m).
    #[serde(default = "default_length")]
    pub length: f64,
    /// Distance of each support from its end of the beam (m).
    #[serde(default = "default_support_inset")]
    pub support_inset: f64,
    /// Section width (m).
    #[serde(default = "default_width")]
    pub width: f64,
    /// Section depth (m).
    #[serde(default = "default_depth")]
    pub depth: f64,
    /// The concrete's fracture energy `Gf` (J/m^2), for the crack band of each element size.
    #[serde(default = "default_fracture_energy")]
    pub fracture_energy: f64,
    /// Element size at the impact and across the section (m).
    #[serde(default = "default_element_size")]
    pub element_size: f64,
    /// Element length along the beam at its ends (m).
    #[serde(default = "default_end_element_size")]
    pub end_element_size: f64,
    /// Distance from mid-span meshed at `element_size` (m); the size grows linearly beyond.
    #[serde(default = "default_fine_length")]
    pub fine_length: f64,
    /// Longitudinal bar diameter (m).
    #[serde(default = "default_bar_diameter")]
    pub bar_diameter: f64,
    /// Depth of the top bars' centres below the top face (m).
    #[serde(default = "default_top_bar_cover")]
    pub top_bar_cover: f64,
    /// Height of the bottom bars' centres above the bottom face (m).
    #[serde(default = "default_bottom_bar_cover")]
    pub bottom_bar_cover: f64,
    /// Distance of the bars' centres from the side faces (m); the seed's figure only, so
    /// `stoss` takes the bottom cover.
    #[serde(default = "default_bottom_bar_cover")]
    pub bar_side_cover: f64,
    /// Stirrup diameter (m).
    #[serde(default = "default_stirrup_diameter")]
    pub stirrup_diameter: f64,
    /// Stirrups in each half of the beam.
    #[serde(default = "default_stirrup_count")]
    pub stirrup_count: usize,
    /// Stirrup spacing (m).
    #[serde(default = "default_stirrup_spacing")]
    pub stirrup_spacing: f64,
    /// Distance of the first stirrup from the end (m).
    #[serde(default = "default_first_stirrup")]
    pub first_stirrup: f64,
    /// The pad's length along the beam (m); it spans the width.
    #[serde(default = "default_pad_length")]
    pub pad_length: f64,
    /// The pad's thickness (m).
    #[serde(default = "default_pad_thickness")]
    pub pad_thickness: f64,
    /// The elastic steel of the pad and the striker head: a material file relative to the
    /// experiment file.
    pub steel_material: String,
    /// How the drop weight is modelled.
    #[serde(default)]
    pub striker: Striker,
    /// The elastic striker head's length (m).
    #[serde(default = "default_head_length")]
    pub head_length: f64,
    /// The drop weight's mass (kg).
    #[serde(default = "default_drop_mass")]
    pub drop_mass: f64,
    /// Impact velocity (m/s); or give `drop_height`.
    #[serde(default)]
    pub impact_velocity: Option<f64>,
    /// Free-fall height (m): impact velocity `sqrt(2 g h)`.
    #[serde(default)]
    pub drop_height: Option<f64>,
    /// Coulomb friction between striker and pad.
    #[serde(default = "default_striker_friction")]
    pub striker_friction: f64,
    /// Gravity (m/s^2).
    #[serde(default = "default_gravity")]
    pub gravity: f64,
    /// The reinforcing steel.
    #[serde(default = "default_rebar")]
    pub rebar: Rebar,
    /// Simulated time after impact (s).
    #[serde(default = "default_end_time")]
    pub end_time: f64,
    /// Interval of the recorded histories (s).
    #[serde(default = "default_output_interval")]
    pub output_interval: f64,
    /// Times of the damage fields written besides the final one (s).
    #[serde(default = "default_field_times")]
    pub field_times: Vec<f64>,
    /// The accelerometers' distance from mid-span (m).
    #[serde(default = "default_accelerometer_offset")]
    pub accelerometer_offset: f64,
    /// The second strain gauge's distance from mid-span (m).
    #[serde(default = "default_gauge_offset")]
    pub gauge_offset: f64,
    /// Non-local averaging of the concrete's damage driver over this radius (m;
    /// [`crate::solver::nonlocal`]), seed 001 sec. 5.5's remedy; none: local. With it every
    /// concrete element's crack band is the averaging diameter `2 R`, the width its damage
    /// localises over, in place of its own size.
    #[serde(default)]
    pub nonlocal_radius: Option<f64>,
    /// The steel, loaded with the experiment.
    #[serde(skip)]
    pub steel: Option<Box<PartMaterial>>,
}

/// How a drop-weight test models its weight.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Striker {
    /// An elastic steel head in contact with the pad under a rigid body of the remaining mass.
    #[default]
    ElasticHead,
    /// A rigid moving wall of the whole mass on the pad's top face.
    RigidWall,
}

/// The built quarter model and where it is measured.
pub struct BeamModel {
    /// The model.
    pub model: ExplicitModel<HexMesh, PartMaterial>,
    /// The bottom-face node at mid-width under the accelerometer.
    pub accelerometer: usize,
    /// A node of the drop weight's rigid body (none: the weight is the model's wall 0).
    pub striker_node: Option<usize>,
    /// The bottom bar's element at mid-span and at the gauge offset (its two nodes).
    pub gauges: [[usize; 2]; 2],
    /// Parts of the mesh that are concrete (the others: the pad).
    pub concrete_parts: usize,
    /// The impact velocity (m/s).
    pub impact_velocity: f64,
}

/// Where damage first localised, and when.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FailureMode {
    /// First time an element of the bottom fibre (below the bottom bars) cracked (s).
    pub bottom_crack: Option<f64>,
    /// First time an element of the web near the load (mid-height half of the section within
    /// one depth of the load's edge, beyond the pad) cracked (s).
    pub web_crack: Option<f64>,
    /// First time an element under the pad (top quarter) cracked (s).
    pub crushing: Option<f64>,
    /// The same, for an open crack ([`OPEN`]).
    pub bottom_open: Option<f64>,
    /// The same, for an open crack ([`OPEN`]).
    pub web_open: Option<f64>,
    /// The same, for an open crack ([`OPEN`]).
    pub crushing_open: Option<f64>,
    /// First time open cracks crossed the web near the load: every element row of the zone
    /// holds an open element (s).
    pub web_crossed: Option<f64>,
    /// The median inclination of the cracks in the web near the load when it was crossed (at
    /// the end if it never was; NaN: nothing opened there): the angle of each open element's
    /// principal tension, at the time it cracked, from the beam's axis in the span's plane
    /// (degrees; 0 for a flexural crack, 45 for a diagonal shear crack).
    pub web_crack_angle: f64,
    /// The web was crossed by inclined cracks ([`SHEAR_ANGLE`]): a shear crack (s).
    pub shear_crack: Option<f64>,
    /// First time open cracks ran through the whole depth under the pad (every element row
    /// of the column under it holds an open element) (s).
    pub punched: Option<f64>,
    /// Whether the bottom bars at mid-span yielded: the beam bent.
    pub bars_yielded: bool,
    /// How wide the open cracks in the web near the load are, in elements: the median length
    /// of the runs of open elements along each of its rows (when it was crossed, else at the
    /// end; NaN: nothing open). 1 is a crack localised in one element.
    pub web_band_elements: f64,
}

/// The failure modes, by their code in an outcome's `failure_mode` summary value.
pub const MODES: [&str; 4] = ["none", "bending", "shear", "punching"];

/// Most history records a run keeps (`end_time / output_interval`): each scans every element.
pub const MAXIMUM_RECORDS: f64 = 1.0e5;

/// Most damage fields a run writes besides the final one.
pub const MAXIMUM_FIELDS: usize = 20;

/// Largest [`FailureMode::web_band_elements`] of damage localised within one element row.
pub const ONE_ELEMENT: f64 = 1.5;

impl FailureMode {
    /// `shear` if a shear crack crossed the web near the load (it then governs, as in FOI's
    /// simulation); else `punching` if cracks ran through the whole depth under the pad
    /// while the bottom bars at mid-span stayed elastic (the striker went through the beam
    /// without bending it); else `bending` if the bottom fibre opened; else `none`.
    pub fn name(&self) -> &'static str {
        match (self.shear_crack, self.punched, self.bottom_open) {
            (Some(_), _, _) => "shear",
            (None, Some(_), _) if !self.bars_yielded => "punching",
            (None, _, Some(_)) => "bending",
            (None, _, None) => "none",
        }
    }
}

/// The median crack inclination (degrees) above which cracks crossing the web are a shear
/// crack: 30, between a flexural crack's 0 (tension along the axis, the crack vertical) and
/// the 45 of diagonal tension under pure shear (Rankine's principal-stress orientation of a
/// smeared crack).
pub const SHEAR_ANGLE: f64 = 30.0;

/// The inclination (degrees, 0 to 90) of the largest principal stress of `stress` (Voigt
/// `xx yy zz xy yz zx`) from the x axis in the x-z plane: `theta = atan2(2 s_xz, s_xx - s_zz)
/// / 2`.
pub fn tension_angle(stress: &[f64; 6]) -> f64 {
    let theta = 0.5 * libm::atan2(2.0 * stress[5], stress[0] - stress[2]);
    theta.abs().to_degrees()
}

impl DropWeightBeamSpec {
    /// The impact velocity from `impact_velocity` or `drop_height` (m/s).
    pub fn impact_velocity(&self) -> f64 {
        match (self.impact_velocity, self.drop_height) {
            (Some(v), _) => v,
            (None, Some(h)) => (2.0 * self.gravity * h).sqrt(),
            (None, None) => f64::NAN,
        }
    }

    /// The x planes (from mid-span) the bars, stirrups, support and pad need.
    fn stirrup_positions(&self) -> Vec<f64> {
        (0..self.stirrup_count)
            .map(|k| 0.5 * self.length - self.first_stirrup - k as f64 * self.stirrup_spacing)
            .collect()
    }

    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        let positive =
            |field: &str, value: f64, unit: &str| super::check_positive(check, field, value, unit);
        positive("length", self.length, "m")?;
        positive("width", self.width, "m")?;
        positive("depth", self.depth, "m")?;
        positive("fracture_energy", self.fracture_energy, "J/m^2")?;
        positive("element_size", self.element_size, "m")?;
        positive("end_element_size", self.end_element_size, "m")?;
        positive("bar_diameter", self.bar_diameter, "m")?;
        positive("stirrup_diameter", self.stirrup_diameter, "m")?;
        positive("pad_length", self.pad_length, "m")?;
        positive("pad_thickness", self.pad_thickness, "m")?;
        positive("head_length", self.head_length, "m")?;
        if let Some(radius) = self.nonlocal_radius {
            positive("nonlocal_radius", radius, "m")?;
            check(
                "nonlocal_radius",
                radius < 0.25 * self.depth && radius <= 5.0 * self.element_size,
                "must be below a quarter of the depth and at most 5 element sizes (each element \
                 averages over the neighbours within it: about 500 at 5 sizes) (m)",
            )?;
        }
        positive("drop_mass", self.drop_mass, "kg")?;
        positive("end_time", self.end_time, "s")?;
        positive("output_interval", self.output_interval, "s")?;
        positive("stirrup_spacing", self.stirrup_spacing, "m")?;
        let half = 0.5 * self.length;
        check(
            "support_inset",
            self.support_inset >= 0.0 && self.support_inset < half,
            "must lie in [0, length/2) (m)",
        )?;
        check(
            "fine_length",
            self.fine_length >= 0.0 && self.fine_length < half - self.support_inset,
            "must lie in [0, length/2 - support_inset) (m)",
        )?;
        check(
            "end_element_size",
            self.end_element_size >= self.element_size,
            "must be at least element_size (m)",
        )?;
        check(
            "element_size",
            self.element_size <= 0.25 * self.depth.min(0.5 * self.width),
            "must give at least 4 elements over the depth and 2 over the half width (m)",
        )?;
        match (self.impact_velocity, self.drop_height) {
            (Some(v), None) => positive("impact_velocity", v, "m/s")?,
            (None, Some(h)) => positive("drop_height", h, "m")?,
            _ => check(
                "impact_velocity",
                false,
                "give exactly one of impact_velocity (m/s) and drop_height (m)",
            )?,
        }
        check(
            "striker_friction",
            self.striker_friction >= 0.0 && self.striker_friction.is_finite(),
            "must be >= 0",
        )?;
        check(
            "gravity",
            self.gravity >= 0.0 && self.gravity.is_finite(),
            "must be >= 0 (m/s^2)",
        )?;
        // Every bar must lie inside the concrete, off its symmetry plane.
        check(
            "bottom_bar_cover",
            self.bottom_bar_cover > 0.0 && self.bottom_bar_cover < self.depth,
            "a bottom bar must lie inside the concrete: 0 < cover < depth (m)",
        )?;
        check(
            "top_bar_cover",
            self.top_bar_cover > 0.0 && self.top_bar_cover < self.depth - self.bottom_bar_cover,
            "a top bar must lie inside the concrete, above the bottom bars (m)",
        )?;
        check(
            "bar_side_cover",
            self.bar_side_cover > 0.0 && self.bar_side_cover < 0.5 * self.width,
            "a bar must lie inside the concrete: 0 < side cover < width/2 (m)",
        )?;
        check(
            "stirrup_count",
            self.first_stirrup >= 0.0
                && self.first_stirrup
                    + self.stirrup_count.saturating_sub(1) as f64 * self.stirrup_spacing
                    <= half,
            "the stirrups must lie inside the beam: first_stirrup + (stirrup_count - 1) \
             stirrup_spacing <= length/2 (m)",
        )?;
        check(
            "pad_length",
            self.pad_length < self.length - 2.0 * self.support_inset,
            "the pad must lie between the supports (m)",
        )?;
        check(
            "accelerometer_offset",
            self.accelerometer_offset >= 0.0 && self.accelerometer_offset < half,
            "must lie in [0, length/2) (m)",
        )?;
        check(
            "gauge_offset",
            self.gauge_offset >= 0.0 && self.gauge_offset < half,
            "must lie in [0, length/2) (m)",
        )?;
        check(
            "field_times",
            self.field_times
                .iter()
                .all(|&t| t > 0.0 && t <= self.end_time),
            "each must lie in (0, end_time] (s)",
        )?;
        let rebar = &self.rebar;
        check(
            "rebar",
            rebar.density > 0.0
                && rebar.young_modulus > 0.0
                && rebar.yield_stress > 0.0
                && rebar.tensile_strength > rebar.yield_stress
                && rebar.stirrup_hardening_modulus > 0.0
                && [
                    rebar.density,
                    rebar.young_modulus,
                    rebar.tensile_strength,
                    rebar.stirrup_hardening_modulus,
                ]
                .iter()
                .all(|v| v.is_finite()),
            "needs density, young_modulus, yield_stress > 0, tensile_strength > yield_stress \
             and stirrup_hardening_modulus > 0 (SI)",
        )?;
        // Sizes that would run away, refused before anything is built: the records and
        // fields kept in memory, and the stirrups (each forces a node plane).
        check(
            "output_interval",
            self.end_time / self.output_interval <= MAXIMUM_RECORDS,
            &format!(
                "gives {:.0} records of every element over end_time; at most {MAXIMUM_RECORDS:.0} \
                 (s)",
                self.end_time / self.output_interval
            ),
        )?;
        check(
            "field_times",
            self.field_times.len() <= MAXIMUM_FIELDS,
            &format!("at most {MAXIMUM_FIELDS} damage fields (each a copy of the model)"),
        )?;
        check(
            "stirrup_spacing",
            self.stirrup_count <= 1 || self.stirrup_spacing >= self.element_size,
            "stirrups closer than element_size would each force their own element (m)",
        )?;
        // A size in mm entered as m: refused from the nominal mesh before any plane is laid.
        let columns = self.fine_length / self.element_size
            + (half - self.fine_length) / self.end_element_size
                * libm::log(self.end_element_size / self.element_size).max(1.0);
        let section = (0.5 * self.width / self.element_size) * (self.depth / self.element_size);
        let nominal_step = super::undeformed_time_step(self.element_size, false) / 3f64.sqrt();
        super::check_run_budget(check, self.end_time, nominal_step, columns * section)?;
        // The mesh as it will be built: its smallest element sets the time step. Two required
        // planes a sliver apart are refused, not run.
        let planes = self.beam_planes();
        let smallest_gap = |p: &[f64]| {
            p.windows(2)
                .map(|w| w[1] - w[0])
                .fold(f64::INFINITY, f64::min)
        };
        let smallest = planes
            .iter()
            .map(|p| smallest_gap(p))
            .fold(self.pad_thickness.min(self.element_size), f64::min)
            .min(self.head_length.min(self.element_size));
        check(
            "element_size",
            smallest >= 0.1 * self.element_size,
            &format!(
                "two required node planes (bar covers, stirrups, the support, the pad's edge, \
                 the gauge or accelerometer position) or the pad's thickness leave an element \
                 {smallest:.3e} m thin, under a tenth of element_size: move them apart (m)"
            ),
        )?;
        let elements = planes.iter().map(|p| p.len() as f64 - 1.0).product::<f64>();
        let step = super::undeformed_time_step(smallest, false) / 3f64.sqrt();
        super::check_run_budget(check, self.end_time, step, 1.2 * elements)?;
        Ok(())
    }

    /// The beam's node planes along x (from mid-span), y (from mid-width) and z (from the
    /// bottom): graded along the beam from `element_size` over `fine_length` to
    /// `end_element_size` at the support, `element_size` across the section, through every
    /// bar, stirrup, the support, the pad's edge, the gauge and the accelerometer.
    fn beam_planes(&self) -> [Vec<f64>; 3] {
        let half = 0.5 * self.length;
        let support = half - self.support_inset;
        let (fine, coarse) = (self.element_size, self.end_element_size);
        let grown = (support - self.fine_length).max(f64::MIN_POSITIVE);
        let along = |x: f64| {
            if x <= self.fine_length {
                fine
            } else {
                fine + (coarse - fine) * ((x - self.fine_length) / grown).min(1.0)
            }
        };
        let mut fixed_x = vec![0.0, 0.5 * self.pad_length, self.fine_length, support, half];
        fixed_x.extend(self.stirrup_positions());
        if self.gauge_offset > 0.0 {
            fixed_x.push(self.gauge_offset);
        }
        if self.accelerometer_offset > 0.0 {
            fixed_x.push(self.accelerometer_offset);
        }
        let bar_y = 0.5 * self.width - self.bar_side_cover;
        let top_bar = self.depth - self.top_bar_cover;
        [
            HexMesh::planes_through(&fixed_x, along),
            HexMesh::planes_through(&[0.0, bar_y, 0.5 * self.width], |_| fine),
            HexMesh::planes_through(&[0.0, self.bottom_bar_cover, top_bar, self.depth], |_| fine),
        ]
    }

    /// Build the quarter model with `concrete` (K&C: its crack band is set per element size)
    /// and the pad's material.
    pub fn model(
        &self,
        concrete: &PartMaterial,
        settings: &SolverSettings,
    ) -> Result<BeamModel, SimulationError> {
        let model_error =
            |message: String| SimulationError::Solver(crate::solver::SolverError::Model(message));
        let steel = self.steel.as_deref().ok_or_else(|| {
            model_error(format!(
                "the steel material `{}` was not loaded",
                self.steel_material
            ))
        })?;
        let half = 0.5 * self.length;
        let support = half - self.support_inset;
        let pad_half = 0.5 * self.pad_length;
        let fine = self.element_size;
        let [xs, ys, zs] = self.beam_planes();
        let bar_y = 0.5 * self.width - self.bar_side_cover;
        let bottom_bar = self.bottom_bar_cover;
        let top_bar = self.depth - self.top_bar_cover;
        let mut mesh = HexMesh::block_on_planes("beam", 0, [&xs, &ys, &zs]);
        let plane = |planes: &[f64], value: f64| {
            planes
                .iter()
                .position(|&p| p == value)
                .expect("the planes pass through every fixed coordinate")
        };
        let node = |i: usize, j: usize, k: usize| (k * ys.len() + j) * xs.len() + i;

        // One concrete material per element size, with its crack band.
        let kc = concrete.kc().ok_or_else(|| SimulationError::Family {
            kind: "drop-weight-beam",
            needs: "a K&C concrete",
            given: concrete.family(),
        })?;
        let mut sizes: Vec<f64> = Vec::new();
        let mut group = Vec::with_capacity(mesh.elements.len());
        for e in 0..mesh.elements.len() {
            // Sizes within 1 % share a material; with averaging, the averaging diameter.
            let size = match self.nonlocal_radius {
                Some(radius) => 2.0 * radius,
                None => libm::cbrt(mesh.volume(e)),
            };
            let index = match sizes.iter().position(|&s| (s / size - 1.0).abs() < 0.01) {
                Some(index) => index,
                None => {
                    sizes.push(size);
                    sizes.len() - 1
                }
            };
            group.push(index);
        }
        mesh.parts = sizes
            .iter()
            .enumerate()
            .map(|(index, size)| Part {
                name: format!("concrete-{:.1}mm", size * 1e3),
                material: index,
            })
            .collect();
        mesh.element_part = group;
        let mut materials: Vec<PartMaterial> = sizes
            .iter()
            .map(|&size| {
                let mut material = *kc;
                material.parameters = material
                    .parameters
                    .with_fracture_energy(self.fracture_energy, size);
                PartMaterial::Kc(material)
            })
            .collect();
        let concrete_parts = sizes.len();
        materials.push(*steel);

        // The pad on the top face, tied through its coincident nodes.
        let pad_xs: Vec<f64> = xs.iter().copied().filter(|&x| x <= pad_half).collect();
        let pad_zs =
            HexMesh::planes_through(&[self.depth, self.depth + self.pad_thickness], |_| fine);
        let pad_mesh = HexMesh::block_on_planes("pad", concrete_parts, [&pad_xs, &ys, &pad_zs]);
        mesh.merge(pad_mesh, 1e-9 * self.length);
        let pad_top = mesh.node_sets["pad.z1"].clone();
        let impact_velocity = self.impact_velocity();
        let quarter_mass = 0.25 * self.drop_mass;
        let mut walls = Vec::new();
        let mut node_contacts = Vec::new();
        let mut rigid_parts = Vec::new();
        let mut initial_velocity = Vec::new();
        let mut striker_node = None;
        match self.striker {
            Striker::RigidWall => walls.push(RigidWall {
                point: vec![0.0, 0.0, self.depth + self.pad_thickness],
                normal: vec![0.0, 0.0, -1.0],
                friction: self.striker_friction,
                nodes: pad_top.clone(),
                motion: Some(WallMotion {
                    mass: quarter_mass,
                    velocity: impact_velocity,
                }),
            }),
            Striker::ElasticHead => {
                // The head on the pad's planes (its own nodes), the rigid rest of the weight
                // on the head (tied), one element thick.
                let head_bottom = self.depth + self.pad_thickness;
                let head_zs =
                    HexMesh::planes_through(&[head_bottom, head_bottom + self.head_length], |_| {
                        fine
                    });
                let head =
                    HexMesh::block_on_planes("head", concrete_parts, [&pad_xs, &ys, &head_zs]);
                let head_volume: f64 = (0..head.elements.len()).map(|e| head.volume(e)).sum();
                let first_head_node = mesh.nodes.len();
                mesh.append(head);
                let top = head_bottom + self.head_length;
                let rest = HexMesh::block_on_planes(
                    "weight",
                    concrete_parts + 1,
                    [&pad_xs, &ys, &[top, top + fine]],
                );
                let rest_volume: f64 = (0..rest.elements.len()).map(|e| rest.volume(e)).sum();
                mesh.merge(rest, 1e-9 * self.length);
                let rest_mass = quarter_mass - steel.density() * head_volume;
                if rest_mass <= 0.0 {
                    return Err(model_error(format!(
                        "the striker head ({:.1} kg in the quarter model) outweighs the drop                          weight's quarter ({quarter_mass:.1} kg): shorten head_length",
                        steel.density() * head_volume
                    )));
                }
                let PartMaterial::J2(mut rigid) = *steel else {
                    return Err(model_error(format!(
                        "the steel material `{}` must be a J2 metal (elastic steel), not {}",
                        self.steel_material,
                        steel.family()
                    )));
                };
                rigid.density = rest_mass / rest_volume;
                materials.push(PartMaterial::J2(rigid));
                rigid_parts.push(mesh.parts.len() - 1);
                // Pair each pad top node with the head's bottom node above it.
                let bottom = &mesh.node_sets["head.z0"];
                let pairs: Vec<[usize; 2]> = pad_top
                    .iter()
                    .zip(bottom)
                    .map(|(&lower, &upper)| [lower, upper])
                    .collect();
                if pairs.len() != bottom.len()
                    || pairs.iter().any(|&[a, b]| mesh.nodes[a] != mesh.nodes[b])
                {
                    return Err(model_error(
                        "the striker head's face does not match the pad's node for node".into(),
                    ));
                }
                node_contacts.push(NodeToNodeContact {
                    pairs,
                    normal: vec![0.0, 0.0, 1.0],
                    friction: self.striker_friction,
                });
                initial_velocity = (0..mesh.nodes.len())
                    .map(|n| {
                        if n >= first_head_node {
                            [0.0, 0.0, -impact_velocity]
                        } else {
                            [0.0; 3]
                        }
                    })
                    .collect();
                striker_node = mesh.node_sets["weight.z1"].first().copied();
            }
        }

        // Reinforcement on the concrete's nodes.
        let (j_bar, k_bottom, k_top) = (
            plane(&ys, bar_y),
            plane(&zs, bottom_bar),
            plane(&zs, top_bar),
        );
        let bar_area = 0.25 * PI * self.bar_diameter * self.bar_diameter;
        let stirrup_area = 0.25 * PI * self.stirrup_diameter * self.stirrup_diameter;
        let bars = self.rebar.truss(0.0);
        let stirrups = self.rebar.truss(self.rebar.stirrup_hardening_modulus);
        let mut trusses = Vec::new();
        for k in [k_bottom, k_top] {
            for i in 0..xs.len() - 1 {
                trusses.push(Truss {
                    nodes: [node(i, j_bar, k), node(i + 1, j_bar, k)],
                    area: bar_area,
                    material: bars,
                });
            }
        }
        for x in self.stirrup_positions() {
            let i = plane(&xs, x);
            let link = |a: usize, b: usize| Truss {
                nodes: [a, b],
                area: stirrup_area,
                material: stirrups,
            };
            for k in k_bottom..k_top {
                trusses.push(link(node(i, j_bar, k), node(i, j_bar, k + 1)));
            }
            for k in [k_bottom, k_top] {
                for j in 0..j_bar {
                    trusses.push(link(node(i, j, k), node(i, j + 1, k)));
                }
            }
        }
        let gauge = |x: f64| {
            let i = plane(&xs, x);
            [node(i, j_bar, k_bottom), node(i + 1, j_bar, k_bottom)]
        };
        let gauges = [gauge(0.0), gauge(self.gauge_offset)];
        let accelerometer = node(plane(&xs, self.accelerometer_offset), 0, 0);

        // Symmetry, the support and the striker.
        let on = |test: &dyn Fn(&[f64; 3]) -> bool| -> Vec<usize> {
            (0..mesh.nodes.len())
                .filter(|&n| test(&mesh.nodes[n]))
                .collect()
        };
        let tolerance = 1e-9 * self.length;
        let held = |nodes: Vec<usize>, dof: usize| VelocityConstraint {
            nodes,
            dof,
            velocity: Amplitude::constant(0.0),
        };
        let constraints = vec![
            held(on(&|p| p[0].abs() < tolerance), 0),
            held(on(&|p| p[1].abs() < tolerance), 1),
            held(
                on(&|p| (p[0] - support).abs() < tolerance && p[2].abs() < tolerance),
                2,
            ),
        ];
        // Tracked: the bottom-fibre element at mid-span and the concrete under the pad's
        // centre.
        let element_at =
            |i: usize, j: usize, k: usize| (k * (ys.len() - 1) + j) * (xs.len() - 1) + i;
        let tracked_elements = vec![element_at(0, 0, 0), element_at(0, 0, zs.len() - 2)];
        mesh.node_sets.clear();
        let model = ExplicitModel {
            mesh,
            materials,
            initial_temperature: 293.0,
            initial_velocity,
            constraints,
            walls,
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts,
            pressure_loads: Vec::new(),
            body_acceleration: Some([0.0, 0.0, -self.gravity]),
            trusses,
            node_contacts,
            settings: SolverSettings {
                end_time: self.end_time,
                output_interval: self.output_interval,
                nonlocal: self.nonlocal_radius.map(|radius| NonlocalAveraging {
                    radius,
                    parts: (0..concrete_parts).collect(),
                }),
                ..settings.clone()
            },
            tracked_elements,
        };
        Ok(BeamModel {
            model,
            accelerometer,
            striker_node,
            gauges,
            concrete_parts,
            impact_velocity,
        })
    }

    /// Run the test with `concrete` and predict each recorded point.
    pub(super) fn simulate(
        &self,
        concrete: &PartMaterial,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let built = self.model(concrete, settings)?;
        let model = &built.model;
        let mesh = &model.mesh;
        let element_count = mesh.elements.len();
        let concrete_element: Vec<bool> = (0..element_count)
            .map(|e| mesh.element_part[e] < built.concrete_parts)
            .collect();
        let centroid = |e: usize| -> [f64; 3] {
            let mut c = [0.0; 3];
            for &n in &mesh.elements[e] {
                for (sum, coordinate) in c.iter_mut().zip(mesh.nodes[n]) {
                    *sum += 0.125 * coordinate;
                }
            }
            c
        };
        let centroids: Vec<[f64; 3]> = (0..element_count).map(centroid).collect();
        let gauge_length = |[a, b]: [usize; 2], x: &[[f64; 3]]| {
            let d: Vec<f64> = (0..3).map(|k| x[b][k] - x[a][k]).collect();
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        };
        let reference_lengths = built.gauges.map(|g| gauge_length(g, &mesh.nodes));
        let mut histories = Histories::default();
        let mut cracked_at = vec![f64::NAN; element_count];
        let mut opened_at = vec![f64::NAN; element_count];
        let mut crack_angle = vec![f64::NAN; element_count];
        let mut fields: Vec<(f64, HexFieldOutput)> = Vec::new();
        let mut pending_fields: Vec<f64> = self.field_times.clone();
        pending_fields.sort_by(f64::total_cmp);
        pending_fields.dedup();
        pending_fields.reverse();
        let mut previous_velocity = 0.0;
        let mut previous_time = 0.0;
        let mut previous_striker = built.impact_velocity;
        let striker_height = built.striker_node.map_or(0.0, |n| mesh.nodes[n][2]);
        let striker = |snapshot: &crate::solver::Snapshot| -> (f64, f64) {
            match built.striker_node {
                Some(n) => (
                    striker_height - snapshot.positions[n][2],
                    -snapshot.velocities[n][2],
                ),
                None => (snapshot.walls[0].displacement, snapshot.walls[0].velocity),
            }
        };
        let run = model.run_observed(&mut |snapshot| {
            let time = snapshot.time;
            let (displacement, speed) = striker(snapshot);
            histories.striker_displacement.push((time, displacement));
            histories.striker_velocity.push((time, speed));
            // M dw/dt = M g - F: the striker's push on the beam from its deceleration.
            let deceleration = (previous_striker - speed) / (time - previous_time);
            histories
                .contact_force
                .push((time, self.drop_mass * (self.gravity + deceleration)));
            previous_striker = speed;
            let velocity = snapshot.velocities[built.accelerometer][2];
            let acceleration = (velocity - previous_velocity) / (time - previous_time);
            histories.acceleration.push((time, acceleration));
            previous_velocity = velocity;
            previous_time = time;
            for (history, (gauge, length)) in
                [&mut histories.strain_midspan, &mut histories.strain_gauge]
                    .into_iter()
                    .zip(built.gauges.iter().zip(&reference_lengths))
            {
                let current = gauge_length(*gauge, snapshot.positions);
                history.push((time, libm::log(current / length)));
            }
            for e in 0..element_count {
                if !concrete_element[e] {
                    continue;
                }
                let damage = snapshot.states[e].damage;
                if damage >= CRACKED && cracked_at[e].is_nan() {
                    cracked_at[e] = time;
                    crack_angle[e] = tension_angle(&snapshot.states[e].stress);
                }
                if damage >= OPEN && opened_at[e].is_nan() {
                    opened_at[e] = time;
                }
            }
            while pending_fields.last().is_some_and(|&t| time >= t) {
                pending_fields.pop();
                fields.push((
                    time,
                    HexFieldOutput {
                        mesh: mesh.clone(),
                        positions: snapshot.positions.to_vec(),
                        states: snapshot.states.to_vec(),
                        eroded: snapshot.eroded.to_vec(),
                        time,
                    },
                ));
            }
            ControlFlow::Continue(())
        })?;
        let peak_bar_strain = histories
            .strain_midspan
            .iter()
            .map(|p| p.1)
            .fold(f64::NAN, f64::max);
        let mode = classify(
            self,
            &centroids,
            &concrete_element,
            &cracked_at,
            &opened_at,
            &crack_angle,
            peak_bar_strain >= self.rebar.yield_stress / self.rebar.young_modulus,
        );
        let first_crack = mode.bottom_crack.unwrap_or(self.end_time);
        let predicted = recording
            .iter()
            .map(|point| {
                let at = |table: &[(f64, f64)]| interpolate(table, point.position);
                match point.quantity.as_str() {
                    "striker_displacement" => at(&histories.striker_displacement),
                    "striker_velocity" => at(&histories.striker_velocity),
                    "beam_acceleration" => at(&histories.acceleration),
                    "rebar_strain_midspan" => at(&histories.strain_midspan),
                    "rebar_strain_200mm" => at(&histories.strain_gauge),
                    "first_crack_time" => first_crack,
                    _ => f64::NAN,
                }
            })
            .collect();
        let energy = run.energy();
        let maximum = |table: &[(f64, f64)]| table.iter().map(|p| p.1).fold(f64::NAN, f64::max);
        let peak_force = maximum(&histories.contact_force);
        let last = |table: &[(f64, f64)]| table.last().map_or(f64::NAN, |p| p.1);
        let mut summary = vec![
            SummaryValue::new("impact_velocity", built.impact_velocity, "m/s"),
            SummaryValue::new(
                "striker_displacement_final",
                last(&histories.striker_displacement),
                "m",
            ),
            SummaryValue::new(
                "striker_velocity_final",
                last(&histories.striker_velocity),
                "m/s",
            ),
            SummaryValue::new("peak_contact_force", peak_force, "N"),
            SummaryValue::new("first_crack_time", first_crack, "s"),
            SummaryValue::new("elements", element_count as f64, "1"),
            SummaryValue::new("trusses", model.trusses.len() as f64, "1"),
        ];
        for (name, time) in [
            ("bottom_crack_time", mode.bottom_crack),
            ("web_crack_time", mode.web_crack),
            ("crushing_time", mode.crushing),
            ("bottom_open_time", mode.bottom_open),
            ("web_open_time", mode.web_open),
            ("crushing_open_time", mode.crushing_open),
            ("web_crossed_time", mode.web_crossed),
            ("shear_crack_time", mode.shear_crack),
            ("punched_time", mode.punched),
        ] {
            summary.push(SummaryValue::new(name, time.unwrap_or(f64::NAN), "s"));
        }
        summary.push(SummaryValue::new(
            "web_crack_angle",
            mode.web_crack_angle,
            "deg",
        ));
        summary.push(SummaryValue::new(
            "bar_strain_midspan_peak",
            peak_bar_strain,
            "-",
        ));
        summary.push(SummaryValue::new(
            "web_band_elements",
            mode.web_band_elements,
            "1",
        ));
        summary.push(SummaryValue::new(
            "failure_mode",
            MODES.iter().position(|&m| m == mode.name()).unwrap_or(0) as f64,
            "index",
        ));
        let final_field = HexFieldOutput {
            time: run.final_time(),
            mesh: mesh.clone(),
            positions: run.positions,
            states: run.states,
            eroded: run.eroded,
        };
        let report = self.report(
            &built,
            &histories,
            &mode,
            &fields,
            Some(&final_field),
            energy.error_percent(),
        );
        let states: Vec<StateHistory> = run
            .tracked
            .iter()
            .zip(["bottom fibre at mid-span", "under the pad"])
            .map(|(history, label)| StateHistory {
                label: label.into(),
                samples: history.samples.clone(),
            })
            .collect();
        Ok(Outcome {
            predicted,
            summary,
            energy: Some(energy),
            states,
            field: None,
            field_3d: Some(final_field),
            element_cycles: run.element_cycles,
            report: Some(report),
        })
    }

    fn report(
        &self,
        built: &BeamModel,
        histories: &Histories,
        mode: &FailureMode,
        fields: &[(f64, HexFieldOutput)],
        final_field: Option<&HexFieldOutput>,
        energy_error: f64,
    ) -> super::ExperimentReport {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "\ndrop weight {:.0} kg at {:.2} m/s on a {:.2} m beam ({} elements, {} bars, a \
             quarter by symmetry; damage {}); energy error {energy_error:+.2} %",
            self.drop_mass,
            built.impact_velocity,
            self.length,
            built.model.mesh.elements.len(),
            built.model.trusses.len(),
            self.nonlocal_radius
                .map_or("local".to_string(), |r| format!(
                    "non-local over {:.0} mm",
                    r * 1e3
                ))
        );
        let _ = writeln!(
            text,
            "{:>8} {:>14} {:>12} {:>13} {:>14} {:>14}",
            "t (ms)", "striker (mm)", "v (m/s)", "force (kN)", "bar mid (%)", "bar 200 (%)"
        );
        let rows = 10;
        for r in 1..=rows {
            let time = self.end_time * r as f64 / rows as f64;
            let at = |table: &[(f64, f64)]| interpolate(table, time);
            let _ = writeln!(
                text,
                "{:>8.2} {:>14.2} {:>12.3} {:>13.1} {:>14.3} {:>14.3}",
                time * 1e3,
                at(&histories.striker_displacement) * 1e3,
                at(&histories.striker_velocity),
                at(&histories.contact_force) * 1e-3,
                at(&histories.strain_midspan) * 1e2,
                at(&histories.strain_gauge) * 1e2
            );
        }
        let peak_strain = histories
            .strain_midspan
            .iter()
            .map(|p| p.1)
            .fold(f64::NAN, f64::max);
        let yield_strain = self.rebar.yield_stress / self.rebar.young_modulus;
        let _ = writeln!(
            text,
            "bottom bars at mid-span: peak strain {:.3} % ({} at fy/E = {:.3} %)",
            peak_strain * 1e2,
            if peak_strain >= yield_strain {
                "yielded"
            } else {
                "elastic: yield"
            },
            yield_strain * 1e2
        );
        let ms = |t: Option<f64>| t.map_or("never".to_string(), |t| format!("{:.3} ms", t * 1e3));
        let _ = writeln!(
            text,
            "first cracked (damage >= {CRACKED}) / open (>= {OPEN}): bottom fibre {} / {}; web \
             near the load {} / {}; under the pad {} / {}\nweb near the load crossed by open \
             cracks: {}, their median inclination {:.0} degrees (a shear crack above \
             {SHEAR_ANGLE}), {:.1} elements wide; cracks through the depth under the pad: {}\nfailure mode: \
             {} (the test: bending, the first mode-I crack at about 0.3 ms, then crushing under \
             the striker; FOI's simulation: a shear crack 50 mm from the impact)",
            ms(mode.bottom_crack),
            ms(mode.bottom_open),
            ms(mode.web_crack),
            ms(mode.web_open),
            ms(mode.crushing),
            ms(mode.crushing_open),
            ms(mode.web_crossed),
            mode.web_crack_angle,
            mode.web_band_elements,
            ms(mode.punched),
            mode.name()
        );
        let to_ms = |table: &[(f64, f64)], scale: f64| -> Vec<(f64, f64)> {
            table.iter().map(|&(t, v)| (t * 1e3, v * scale)).collect()
        };
        let line = |label: &str, points: Vec<(f64, f64)>, colour: usize| Series {
            errors: Vec::new(),
            label: label.into(),
            points,
            style: Style::Line,
            colour,
        };
        let charts = vec![
            super::Chart {
                file: "striker.svg".into(),
                title: "Drop-weight striker".into(),
                x_label: "time after impact (ms)".into(),
                y_label: "displacement (mm), velocity (m/s x 10)".into(),
                series: vec![
                    line(
                        "displacement (mm)",
                        to_ms(&histories.striker_displacement, 1e3),
                        0,
                    ),
                    line(
                        "velocity (m/s x 10)",
                        to_ms(&histories.striker_velocity, 10.0),
                        1,
                    ),
                ],
            },
            super::Chart {
                file: "contact-force.svg".into(),
                title: "Striker contact force (whole beam)".into(),
                x_label: "time after impact (ms)".into(),
                y_label: "force (kN)".into(),
                series: vec![line("force", to_ms(&histories.contact_force, 1e-3), 0)],
            },
            super::Chart {
                file: "acceleration.svg".into(),
                title: format!(
                    "Beam acceleration {:.0} mm from mid-span (both sides by symmetry)",
                    self.accelerometer_offset * 1e3
                ),
                x_label: "time after impact (ms)".into(),
                y_label: "acceleration (m/s^2)".into(),
                series: vec![line("acceleration", to_ms(&histories.acceleration, 1.0), 0)],
            },
            super::Chart {
                file: "rebar-strain.svg".into(),
                title: "Bottom bar strain".into(),
                x_label: "time after impact (ms)".into(),
                y_label: "strain (%)".into(),
                series: vec![
                    line("mid-span", to_ms(&histories.strain_midspan, 1e2), 0),
                    line(
                        &format!("{:.0} mm from mid-span", self.gauge_offset * 1e3),
                        to_ms(&histories.strain_gauge, 1e2),
                        1,
                    ),
                ],
            },
        ];
        let snapshots: Vec<(String, HexFieldOutput)> = fields
            .iter()
            .map(|(time, field)| (format!("damage-{:.2}ms.vtu", time * 1e3), field.clone()))
            .collect();
        let maps = fields
            .iter()
            .map(|(time, field)| (*time, field))
            .chain(final_field.map(|field| (self.end_time, field)))
            .map(|(time, field)| super::FieldMap {
                file: format!("damage-map-{:.2}ms.svg", time * 1e3),
                title: format!(
                    "Damage at mid-width, {:.2} ms (white: uncracked; yellow: at the peak \
                     strength; red to black: open to fully softened)",
                    time * 1e3
                ),
                x_label: "distance from mid-span (mm)".into(),
                y_label: "height (mm)".into(),
                cells: self.damage_section(field),
                range: (CRACKED, 1.0),
            })
            .collect();
        super::ExperimentReport {
            text,
            charts,
            snapshots,
            maps,
            shot_fields: Vec::new(),
        }
    }

    /// The damage of the concrete elements on the mid-width symmetry plane, within three
    /// depths of mid-span, as map cells in mm (reference positions).
    fn damage_section(&self, field: &HexFieldOutput) -> Vec<crate::figure::MapCell> {
        let mesh = &field.mesh;
        let reach = (3.0 * self.depth).min(0.5 * self.length);
        (0..mesh.elements.len())
            .filter_map(|e| {
                let corners = mesh.elements[e].map(|n| mesh.nodes[n]);
                let bound = |d: usize, f: fn(f64, f64) -> f64, start: f64| {
                    corners.iter().map(|p| p[d]).fold(start, f)
                };
                let (x0, x1) = (bound(0, f64::min, f64::INFINITY), bound(0, f64::max, 0.0));
                let (z0, z1) = (bound(2, f64::min, f64::INFINITY), bound(2, f64::max, 0.0));
                let on_plane = bound(1, f64::min, f64::INFINITY) == 0.0;
                let concrete = z1 <= self.depth * (1.0 + 1e-12);
                (on_plane && concrete && x0 < reach).then(|| {
                    (
                        [x0 * 1e3, x1 * 1e3, z0 * 1e3, z1 * 1e3],
                        field.states[e].damage,
                    )
                })
            })
            .collect()
    }
}

/// The recorded histories of a run.
#[derive(Default)]
struct Histories {
    striker_displacement: Vec<(f64, f64)>,
    striker_velocity: Vec<(f64, f64)>,
    /// The striker's force on the whole beam (N, positive pushing down).
    contact_force: Vec<(f64, f64)>,
    acceleration: Vec<(f64, f64)>,
    strain_midspan: Vec<(f64, f64)>,
    strain_gauge: Vec<(f64, f64)>,
}

/// Where damage first appeared, from each concrete element's first time cracked and open
/// (NaN: never), the inclination of its principal tension when it cracked
/// ([`tension_angle`]) and its reference centroid, in three zones: the bottom fibre (below the
/// bottom bars), the web near the load (the middle half of the depth, from the pad's edge to
/// one depth beyond it, where FOI's shear crack formed 50 mm from the impact) and the concrete
/// under the pad (its top quarter).
///
/// The web is crossed when every element row of its zone holds an open element; the cracks
/// that crossed it are a shear crack if their median inclination then exceeds
/// [`SHEAR_ANGLE`], flexural cracks grown up from the bottom otherwise.
pub fn classify(
    spec: &DropWeightBeamSpec,
    centroids: &[[f64; 3]],
    concrete: &[bool],
    cracked_at: &[f64],
    opened_at: &[f64],
    crack_angle: &[f64],
    bars_yielded: bool,
) -> FailureMode {
    let depth = spec.depth;
    let pad_half = 0.5 * spec.pad_length;
    let bottom = |c: &[f64; 3]| c[2] < spec.bottom_bar_cover;
    let web = |c: &[f64; 3]| {
        c[2] > 0.25 * depth && c[2] < 0.75 * depth && c[0] > pad_half && c[0] < pad_half + depth
    };
    let under_pad = |c: &[f64; 3]| c[2] > 0.75 * depth && c[0] < pad_half;
    let first = |zone: &dyn Fn(&[f64; 3]) -> bool, times: &[f64]| -> Option<f64> {
        let t = (0..centroids.len())
            .filter(|&e| concrete[e] && zone(&centroids[e]))
            .map(|e| times[e])
            .filter(|t| !t.is_nan())
            .fold(f64::INFINITY, f64::min);
        t.is_finite().then_some(t)
    };
    // The web zone's rows (distinct centroid heights) and their elements.
    let members: Vec<usize> = (0..centroids.len())
        .filter(|&e| concrete[e] && web(&centroids[e]))
        .collect();
    let mut heights: Vec<f64> = members.iter().map(|&e| centroids[e][2]).collect();
    heights.sort_by(f64::total_cmp);
    heights.dedup_by(|a, b| (*a - *b).abs() < 1e-9 * depth);
    let rows: Vec<usize> = members
        .iter()
        .map(|&e| {
            heights
                .iter()
                .position(|&h| (h - centroids[e][2]).abs() < 1e-9 * depth)
                .unwrap_or(0)
        })
        .collect();
    let crossed_by = |t: f64| {
        let mut open = vec![false; heights.len()];
        for (&e, &r) in members.iter().zip(&rows) {
            open[r] |= opened_at[e] <= t;
        }
        !open.is_empty() && open.iter().all(|&o| o)
    };
    let mut times: Vec<f64> = members
        .iter()
        .map(|&e| opened_at[e])
        .filter(|t| !t.is_nan())
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    let web_crossed = times.iter().copied().find(|&t| crossed_by(t));
    let until = web_crossed.unwrap_or(f64::INFINITY);
    let mut angles: Vec<f64> = members
        .iter()
        .filter(|&&e| opened_at[e] <= until && !crack_angle[e].is_nan())
        .map(|&e| crack_angle[e])
        .collect();
    angles.sort_by(f64::total_cmp);
    let web_crack_angle = match angles.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => angles[n / 2],
        n => 0.5 * (angles[n / 2 - 1] + angles[n / 2]),
    };
    let shear_crack = web_crossed.filter(|_| web_crack_angle > SHEAR_ANGLE);
    // Runs of open elements along each web row, in x order.
    let mut runs: Vec<usize> = Vec::new();
    for r in 0..heights.len() {
        let mut row: Vec<(f64, bool)> = members
            .iter()
            .zip(&rows)
            .filter(|(_, &row)| row == r)
            .map(|(&e, _)| (centroids[e][0], opened_at[e] <= until))
            .collect();
        row.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut length = 0;
        for (_, open) in row.iter().chain([&(0.0, false)]) {
            if *open {
                length += 1;
            } else if length > 0 {
                runs.push(length);
                length = 0;
            }
        }
    }
    runs.sort_unstable();
    let web_band_elements = match runs.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => runs[n / 2] as f64,
        n => 0.5 * (runs[n / 2 - 1] + runs[n / 2]) as f64,
    };
    // The column under the pad: its rows and when each first held an open element.
    let column: Vec<usize> = (0..centroids.len())
        .filter(|&e| concrete[e] && centroids[e][0] < pad_half)
        .collect();
    let mut levels: Vec<f64> = column.iter().map(|&e| centroids[e][2]).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup_by(|a, b| (*a - *b).abs() < 1e-9 * depth);
    let mut row_open = vec![f64::INFINITY; levels.len()];
    for &e in &column {
        if let Some(r) = levels
            .iter()
            .position(|&h| (h - centroids[e][2]).abs() < 1e-9 * depth)
        {
            if !opened_at[e].is_nan() {
                row_open[r] = row_open[r].min(opened_at[e]);
            }
        }
    }
    let through = row_open.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let punched = (!row_open.is_empty() && through.is_finite()).then_some(through);
    FailureMode {
        bottom_crack: first(&bottom, cracked_at),
        web_crack: first(&web, cracked_at),
        crushing: first(&under_pad, cracked_at),
        bottom_open: first(&bottom, opened_at),
        web_open: first(&web, opened_at),
        crushing_open: first(&under_pad, opened_at),
        web_crossed,
        web_crack_angle,
        shear_crack,
        punched,
        bars_yielded,
        web_band_elements,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> DropWeightBeamSpec {
        toml::from_str("steel_material = \"steel.toml\"\nimpact_velocity = 6.7").unwrap()
    }

    #[test]
    fn the_principal_tension_gives_the_crack_inclination() {
        // GOAL: the crack orientation read from the stress at cracking.
        // SETUP: uniaxial tension along the beam (x), pure shear in the x-z plane, vertical
        //        tension (z).
        // REFERENCE: Mohr's circle: 0, 45 and 90 degrees.
        assert_eq!(tension_angle(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]), 0.0);
        assert!((tension_angle(&[0.0, 0.0, 0.0, 0.0, 0.0, 1.0]) - 45.0).abs() < 1e-12);
        assert!((tension_angle(&[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]) - 90.0).abs() < 1e-12);
    }

    #[test]
    fn cracks_crossing_the_web_are_shear_if_inclined_and_bending_if_vertical() {
        // GOAL: the failure-mode classification tells a diagonal shear crack from flexural
        //       cracks.
        // SETUP: the default beam (depth 0.34 m, pad 0.1 m); a column of web elements at
        //        every 10 mm of height between 0.09 and 0.25 m, at x = 0.2 m, opening
        //        bottom-up from 1 ms, one row per 0.1 ms; a bottom-fibre element opening at
        //        0.5 ms. (a) cracked with principal tension at 45 degrees; (b) at 5 degrees.
        // REFERENCE: (a) the web is crossed when its last row opens (2.6 ms), median 45 > 30:
        //            shear; (b) the same crossing, median 5: bending (the bottom opened).
        //            (c) a column under the pad opening row by row to the top (3.4 ms) with the
        //            bars elastic: punching; with the bars yielded: bending.
        let spec = spec();
        let mut centroids = vec![[0.0, 0.0, 0.01]];
        let mut opened = vec![0.5e-3];
        for k in 0..17 {
            centroids.push([0.2, 0.0, 0.09 + 0.01 * k as f64]);
            opened.push(1.0e-3 + 0.1e-3 * k as f64);
        }
        let concrete = vec![true; centroids.len()];
        for (angle, mode) in [(45.0, "shear"), (5.0, "bending")] {
            let angles = vec![angle; centroids.len()];
            let result = classify(
                &spec, &centroids, &concrete, &opened, &opened, &angles, true,
            );
            assert_eq!(result.bottom_open, Some(0.5e-3));
            assert!((result.web_crossed.unwrap() - 2.6e-3).abs() < 1e-15);
            assert_eq!(result.web_crack_angle, angle);
            assert_eq!(result.web_band_elements, 1.0, "one element per row");
            assert_eq!(result.name(), mode);
        }
        // A web never crossed: no shear crack whatever the angle.
        let mut partial = opened.clone();
        partial[9] = f64::NAN;
        let result = classify(
            &spec,
            &centroids,
            &concrete,
            &partial,
            &partial,
            &vec![45.0; centroids.len()],
            true,
        );
        assert_eq!(result.web_crossed, None);
        assert_eq!(result.name(), "bending");
        // Cracks through the whole depth under the pad, the bars elastic: punching.
        let column: Vec<[f64; 3]> = (0..34)
            .map(|k| [0.01, 0.0, 0.005 + 0.01 * k as f64])
            .collect();
        let times: Vec<f64> = (0..34).map(|k| 1.0e-4 * (k + 1) as f64).collect();
        let punching = classify(
            &spec,
            &column,
            &[true; 34],
            &times,
            &times,
            &vec![0.0; 34],
            false,
        );
        assert!((punching.punched.unwrap() - 3.4e-3).abs() < 1e-15);
        assert_eq!(punching.name(), "punching");
        let bent = FailureMode {
            bars_yielded: true,
            ..punching
        };
        assert_eq!(bent.name(), "bending");
    }
}
