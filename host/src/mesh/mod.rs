//! Meshes: 2D axisymmetric 4-node quadrilaterals (`r`, `z`) and 3D 8-node hexahedra, with
//! parts, node sets and element sets; the O-grid of a pointed rod's nose ([`pointed_rod`]).

mod axisymmetric;
mod hexahedral;
mod nose;

pub use axisymmetric::{Grading, QuadMesh};
pub use hexahedral::HexMesh;
pub use nose::{pointed_rod, smallest_angle, PointedRod, MINIMUM_NOSE_ANGLE};

/// The `columns x rows` counter-clockwise quadrilaterals of a structured patch whose node
/// `(i, j)` (`i <= columns` along the first direction, `j <= rows` along the second, the pair
/// right-handed) is `node(i, j)`, row by row.
pub(crate) fn structured_quads(
    columns: usize,
    rows: usize,
    node: impl Fn(usize, usize) -> usize,
) -> Vec<[usize; 4]> {
    let mut quads = Vec::with_capacity(columns * rows);
    for j in 0..rows {
        for i in 0..columns {
            quads.push([
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            ]);
        }
    }
    quads
}

/// A named group of elements sharing one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Part name (e.g. `rod`, `anvil`, `specimen`).
    pub name: String,
    /// Index of the part's material in the model's material list.
    pub material: usize,
}
