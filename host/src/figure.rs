//! What the results show, as data: line charts and their series, maps of a field over a
//! section, the final fields of a run (for VTK), and an experiment's own report. Experiments
//! fill these in; `report` draws and writes them (plotters, VTK), so no experiment depends on
//! how a figure is drawn.

use crate::mesh::{HexMesh, QuadMesh};
use stoss_kernel::MaterialState;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A line through the points.
    Line,
    /// Markers at the points.
    Markers,
    /// A dashed line through the points (a model curve beside the main one: the starting
    /// constants').
    Dashed,
}

/// One series of a line chart.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
    /// Palette index.
    pub colour: usize,
    /// Half-width of each point's recorded uncertainty along the measured axis (y in a line
    /// chart, x in a parity chart), drawn as error bars on markers; empty for none.
    pub errors: Vec<f64>,
}

/// One cell of a [`FieldMap`]: its rectangle `[x0, x1, y0, y1]` and value.
pub type MapCell = ([f64; 4], f64);

/// Fields of the final state for visualisation (VTK).
#[derive(Clone, Debug)]
pub struct FieldOutput {
    /// The mesh (reference configuration).
    pub mesh: QuadMesh,
    /// Final nodal positions.
    pub positions: Vec<[f64; 3]>,
    /// Final element states.
    pub states: Vec<MaterialState>,
    /// Eroded elements.
    pub eroded: Vec<bool>,
    /// Further per-element arrays by name (an Eulerian run's volume fractions and density).
    pub cell_data: Vec<(String, Vec<f64>)>,
    /// The time of this state (s, the run's clock).
    pub time: f64,
}

/// The final state of a 3D (hexahedral) run, for its VTK file.
#[derive(Clone, Debug)]
pub struct HexFieldOutput {
    /// The mesh (reference configuration).
    pub mesh: HexMesh,
    /// Final nodal positions.
    pub positions: Vec<[f64; 3]>,
    /// Final element states.
    pub states: Vec<MaterialState>,
    /// Eroded elements.
    pub eroded: Vec<bool>,
    /// The time of this state (s, the run's clock).
    pub time: f64,
}

/// The text and figures of an experiment's own report.
#[derive(Clone, Debug, Default)]
pub struct ExperimentReport {
    /// Printed after the comparison with the recording.
    pub text: String,
    /// Figures written into the output folder.
    pub charts: Vec<Chart>,
    /// Fields at times during the run, written into the output folder as `.vtu` files
    /// (file name, field).
    pub snapshots: Vec<(String, HexFieldOutput)>,
    /// Maps of a field over a section, written as `.svg` figures.
    pub maps: Vec<FieldMap>,
    /// The final field of each shot of a sweep (impact velocity in m/s, field), written as
    /// one `.vtu` per shot and a `.pvd` collection.
    pub shot_fields: Vec<(f64, FieldOutput)>,
}

/// A map of a scalar field over a section (drawn by `report::plots::field_map`).
#[derive(Clone, Debug)]
pub struct FieldMap {
    /// File name in the output folder (`.svg`).
    pub file: String,
    /// Title.
    pub title: String,
    /// Axis labels.
    pub x_label: String,
    /// Axis labels.
    pub y_label: String,
    /// The cells: rectangle `[x0, x1, y0, y1]` and value.
    pub cells: Vec<MapCell>,
    /// The value range of the colour scale (white below its start).
    pub range: (f64, f64),
}

/// A line chart of an experiment's report (drawn by `report::plots::line_chart`).
#[derive(Clone, Debug)]
pub struct Chart {
    /// File name in the output folder (`.svg`).
    pub file: String,
    /// Title.
    pub title: String,
    /// Axis labels.
    pub x_label: String,
    /// Axis labels.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
}
