//! Output files: VTK for ParaView, CSV/JSON measurements, energy reports.

pub mod calibration;
pub mod cards;
pub mod plots;
pub mod units;
pub mod vtk;
