//! Output files: VTK for ParaView, CSV/JSON measurements, energy reports.

pub mod vtk;
