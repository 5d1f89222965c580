//! VTK XML unstructured grid (`.vtu`, ASCII) of a run's final state, with per-element plastic
//! strain, rate, temperature, pressure, von Mises stress, damage and an eroded flag, and nodal
//! displacements: an axisymmetric run's deformed `(r, z)` mesh as quads in the x-y plane, a 3D
//! run's hexahedra as they are. ParaView opens it directly.

use crate::figure::{FieldOutput, HexFieldOutput};
use std::fmt::Write as _;
use stoss_kernel::MaterialState;

/// VTK cell types (VTK file formats, "Cell types").
const VTK_QUAD: u8 = 9;
const VTK_HEXAHEDRON: u8 = 12;

/// Render the `.vtu` text of an axisymmetric run.
pub fn render(field: &FieldOutput) -> String {
    let cells: Vec<&[usize]> = field.mesh.elements.iter().map(|e| e.as_slice()).collect();
    let reference: Vec<[f64; 3]> = field.mesh.nodes.iter().map(|n| [n[0], n[1], 0.0]).collect();
    let current: Vec<[f64; 3]> = field.positions.iter().map(|p| [p[0], p[1], 0.0]).collect();
    grid(
        &current,
        &reference,
        &cells,
        VTK_QUAD,
        &field.states,
        &field.eroded,
        &field.cell_data,
    )
}

/// Render the `.vtu` text of a 3D (hexahedral) run.
pub fn render_hexahedral(field: &HexFieldOutput) -> String {
    let cells: Vec<&[usize]> = field.mesh.elements.iter().map(|e| e.as_slice()).collect();
    grid(
        &field.positions,
        &field.mesh.nodes,
        &cells,
        VTK_HEXAHEDRON,
        &field.states,
        &field.eroded,
        &[],
    )
}

/// The `.vtu` text of cells of one type over nodes at `current` (reference `reference`).
fn grid(
    current: &[[f64; 3]],
    reference: &[[f64; 3]],
    cells: &[&[usize]],
    cell_type: u8,
    states: &[MaterialState],
    eroded: &[bool],
    cell_data: &[(String, Vec<f64>)],
) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        text,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(text, "<UnstructuredGrid>");
    let _ = writeln!(
        text,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        current.len(),
        cells.len()
    );
    let _ = writeln!(
        text,
        "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in current {
        let _ = writeln!(text, "{:e} {:e} {:e}", p[0], p[1], p[2]);
    }
    let _ = writeln!(text, "</DataArray></Points>");
    let _ = writeln!(
        text,
        "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    );
    for cell in cells {
        let nodes: Vec<String> = cell.iter().map(usize::to_string).collect();
        let _ = writeln!(text, "{}", nodes.join(" "));
    }
    let _ = writeln!(
        text,
        "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    );
    let mut offset = 0;
    for cell in cells {
        offset += cell.len();
        let _ = write!(text, "{offset} ");
    }
    let _ = writeln!(
        text,
        "\n</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    );
    for _ in cells {
        let _ = write!(text, "{cell_type} ");
    }
    let _ = writeln!(text, "\n</DataArray></Cells>");
    let _ = writeln!(text, "<CellData Scalars=\"plastic_strain\">");
    let scalar = |text: &mut String, name: &str, values: &mut dyn Iterator<Item = f64>| {
        let _ = writeln!(
            text,
            "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
        );
        for v in values {
            let _ = write!(text, "{v:e} ");
        }
        let _ = writeln!(text, "\n</DataArray>");
    };
    scalar(
        &mut text,
        "plastic_strain",
        &mut states.iter().map(|s| s.plastic_strain),
    );
    scalar(
        &mut text,
        "plastic_strain_rate",
        &mut states.iter().map(|s| s.plastic_strain_rate),
    );
    scalar(
        &mut text,
        "temperature",
        &mut states.iter().map(|s| s.temperature),
    );
    scalar(
        &mut text,
        "pressure",
        &mut states.iter().map(|s| s.pressure()),
    );
    scalar(
        &mut text,
        "von_mises",
        &mut states.iter().map(|s| s.equivalent_stress()),
    );
    scalar(&mut text, "damage", &mut states.iter().map(|s| s.damage));
    scalar(
        &mut text,
        "eroded",
        &mut eroded.iter().map(|&e| f64::from(u8::from(e))),
    );
    for (name, values) in cell_data {
        scalar(&mut text, name, &mut values.iter().copied());
    }
    let _ = writeln!(text, "</CellData>");
    let _ = writeln!(text, "<PointData Vectors=\"displacement\"><DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">");
    for (p, p0) in current.iter().zip(reference) {
        let _ = writeln!(
            text,
            "{:e} {:e} {:e}",
            p[0] - p0[0],
            p[1] - p0[1],
            p[2] - p0[2]
        );
    }
    let _ = writeln!(text, "</DataArray></PointData>");
    let _ = writeln!(text, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    text
}
