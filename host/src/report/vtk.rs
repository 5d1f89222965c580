//! VTK XML unstructured grid (`.vtu`, ASCII) of an axisymmetric run's final state: the
//! deformed `(r, z)` mesh as quads in the x-y plane, with per-element plastic strain, rate,
//! temperature, pressure, von Mises stress, damage and an eroded flag, and nodal
//! displacements. ParaView opens it directly.

use crate::experiment::FieldOutput;
use std::fmt::Write as _;

/// Render the `.vtu` text.
pub fn render(field: &FieldOutput) -> String {
    let mesh = &field.mesh;
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
        mesh.nodes.len(),
        mesh.elements.len()
    );
    let _ = writeln!(
        text,
        "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in &field.positions {
        let _ = writeln!(text, "{:e} {:e} 0", p[0], p[1]);
    }
    let _ = writeln!(text, "</DataArray></Points>");
    let _ = writeln!(
        text,
        "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    );
    for e in &mesh.elements {
        let _ = writeln!(text, "{} {} {} {}", e[0], e[1], e[2], e[3]);
    }
    let _ = writeln!(
        text,
        "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    );
    for k in 0..mesh.elements.len() {
        let _ = write!(text, "{} ", 4 * (k + 1));
    }
    let _ = writeln!(
        text,
        "\n</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    );
    for _ in 0..mesh.elements.len() {
        let _ = write!(text, "9 ");
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
    let states = &field.states;
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
        &mut field.eroded.iter().map(|&e| f64::from(u8::from(e))),
    );
    let _ = writeln!(text, "</CellData>");
    let _ = writeln!(text, "<PointData Vectors=\"displacement\"><DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">");
    for (p, p0) in field.positions.iter().zip(&mesh.nodes) {
        let _ = writeln!(text, "{:e} {:e} 0", p[0] - p0[0], p[1] - p0[1]);
    }
    let _ = writeln!(text, "</DataArray></PointData>");
    let _ = writeln!(text, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    text
}
