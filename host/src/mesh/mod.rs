//! Meshes: 2D axisymmetric 4-node quadrilaterals (`r`, `z`) and 3D 8-node hexahedra, with
//! parts, node sets and element sets.

mod axisymmetric;
mod hexahedral;

pub use axisymmetric::{Grading, QuadMesh};
pub use hexahedral::HexMesh;

/// A named group of elements sharing one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Part name (e.g. `rod`, `anvil`, `specimen`).
    pub name: String,
    /// Index of the part's material in the model's material list.
    pub material: usize,
}
