//! Meshes: 2D axisymmetric 4-node quadrilaterals (`r`, `z`) and 3D 8-node hexahedra, with
//! parts, node sets and element sets; the O-grid of a pointed rod's nose ([`pointed_rod`]).

mod axisymmetric;
mod hexahedral;
mod nose;

pub use axisymmetric::{Grading, QuadMesh};
pub use hexahedral::HexMesh;
pub use nose::{pointed_rod, smallest_angle, PointedRod, MINIMUM_NOSE_ANGLE};

/// A named group of elements sharing one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Part name (e.g. `rod`, `anvil`, `specimen`).
    pub name: String,
    /// Index of the part's material in the model's material list.
    pub material: usize,
}
