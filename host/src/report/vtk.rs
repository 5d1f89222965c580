//! VTK XML unstructured grid (`.vtu`, ASCII) of a run's state, as ParaView opens it without
//! filtering: an axisymmetric run's deformed `(r, z)` mesh as quads in the x-y plane, a 3D
//! run's hexahedra as they are.
//!
//! - Eroded cells (and an Eulerian grid's void cells) are left out of the geometry, so a
//!   crater shows as it is; their count is in the file's `eroded_cells` field.
//! - Per cell: `part_id` and `material_id` (1-based, the mesh's parts in order, named in a
//!   comment at the top), plastic strain, rate, temperature, pressure, von Mises stress,
//!   damage and any further arrays the run adds; per node: the displacement.
//! - The state's time is the field `TimeValue` (s), which ParaView reads as the time.
//!
//! A run's files are listed with their times in a `.pvd` collection ([`collection`]).

use crate::figure::{FieldOutput, HexFieldOutput};
use crate::mesh::Part;
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
    grid(&Grid {
        current: &current,
        reference: &reference,
        cells: &cells,
        cell_type: VTK_QUAD,
        element_part: &field.mesh.element_part,
        parts: &field.mesh.parts,
        states: &field.states,
        eroded: &field.eroded,
        cell_data: &field.cell_data,
        time: field.time,
    })
}

/// Render the `.vtu` text of a 3D (hexahedral) run.
pub fn render_hexahedral(field: &HexFieldOutput) -> String {
    let cells: Vec<&[usize]> = field.mesh.elements.iter().map(|e| e.as_slice()).collect();
    grid(&Grid {
        current: &field.positions,
        reference: &field.mesh.nodes,
        cells: &cells,
        cell_type: VTK_HEXAHEDRON,
        element_part: &field.mesh.element_part,
        parts: &field.mesh.parts,
        states: &field.states,
        eroded: &field.eroded,
        cell_data: &[],
        time: field.time,
    })
}

/// A `.pvd` collection of `(time, file)` entries (files relative to the `.pvd`): ParaView
/// opens it as one time series.
pub fn collection(entries: &[(f64, String)]) -> String {
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for (time, file) in entries {
        let _ = writeln!(
            text,
            "<DataSet timestep=\"{time:e}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    text.push_str("</Collection>\n</VTKFile>\n");
    text
}

/// What a `.vtu` file is made of.
struct Grid<'a> {
    /// Current nodal positions.
    current: &'a [[f64; 3]],
    /// Reference nodal positions.
    reference: &'a [[f64; 3]],
    /// Every element's nodes.
    cells: &'a [&'a [usize]],
    /// The VTK cell type of every element.
    cell_type: u8,
    /// Each element's part (index into `parts`).
    element_part: &'a [usize],
    /// The mesh's parts.
    parts: &'a [Part],
    /// Each element's state.
    states: &'a [MaterialState],
    /// Eroded elements (left out).
    eroded: &'a [bool],
    /// Further per-element arrays by name.
    cell_data: &'a [(String, Vec<f64>)],
    /// The state's time (s).
    time: f64,
}

/// The `.vtu` text of `g`'s cells that are not eroded.
fn grid(g: &Grid<'_>) -> String {
    let (current, reference) = (g.current, g.reference);
    let kept: Vec<usize> = (0..g.cells.len())
        .filter(|&e| !g.eroded.get(e).copied().unwrap_or(false))
        .collect();
    let cells: Vec<&[usize]> = kept.iter().map(|&e| g.cells[e]).collect();
    let states: Vec<MaterialState> = kept
        .iter()
        .filter_map(|&e| g.states.get(e).copied())
        .collect();
    let mut text = String::new();
    let _ = writeln!(text, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        text,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let parts: Vec<String> = g
        .parts
        .iter()
        .enumerate()
        .map(|(k, part)| format!("{} {} (material {})", k + 1, part.name, part.material + 1))
        .collect();
    let _ = writeln!(
        text,
        "<!-- stoss; parts (part_id name): {} -->",
        parts.join(", ")
    );
    let _ = writeln!(text, "<UnstructuredGrid>");
    let _ = writeln!(
        text,
        "<FieldData><DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
         format=\"ascii\">{:e}</DataArray><DataArray type=\"Int64\" Name=\"eroded_cells\" \
         NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray></FieldData>",
        g.time,
        g.cells.len() - kept.len()
    );
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
    for cell in &cells {
        let nodes: Vec<String> = cell.iter().map(usize::to_string).collect();
        let _ = writeln!(text, "{}", nodes.join(" "));
    }
    let _ = writeln!(
        text,
        "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    );
    let mut offset = 0;
    for cell in &cells {
        offset += cell.len();
        let _ = write!(text, "{offset} ");
    }
    let _ = writeln!(
        text,
        "\n</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    );
    for _ in &cells {
        let _ = write!(text, "{} ", g.cell_type);
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
    let part_of = |e: usize| g.element_part.get(e).copied().unwrap_or(0);
    let ids = |text: &mut String, name: &str, id: &dyn Fn(usize) -> usize| {
        let _ = writeln!(
            text,
            "<DataArray type=\"Int32\" Name=\"{name}\" format=\"ascii\">"
        );
        for &e in &kept {
            let _ = write!(text, "{} ", id(e) + 1);
        }
        let _ = writeln!(text, "\n</DataArray>");
    };
    ids(&mut text, "part_id", &part_of);
    ids(&mut text, "material_id", &|e| {
        g.parts.get(part_of(e)).map_or(0, |part| part.material)
    });
    for (name, values) in g.cell_data {
        scalar(
            &mut text,
            name,
            &mut kept
                .iter()
                .map(|&e| values.get(e).copied().unwrap_or(f64::NAN)),
        );
    }
    let _ = writeln!(text, "</CellData>");
    let _ = writeln!(text, "<PointData Vectors=\"displacement\"><DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">");
    for (p, p0) in current.iter().zip(reference.iter()) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Grading, QuadMesh};

    #[test]
    fn eroded_cells_are_left_out_and_the_series_lists_each_file_at_its_time() {
        // GOAL: issue 51 item 4: what ParaView opens shows no eroded cell, names each cell's
        //       part and material, carries the time, and a run's files form one series.
        // SETUP: a 3 x 1 block (part "rod", material 0) with its middle element eroded at
        //        t = 2e-5 s; a collection of two files.
        // REFERENCE: two cells written (element 0 and 2, connectivity as in the mesh), part
        //        and material id 1, TimeValue 2e-5, eroded_cells 1; the collection's
        //        timesteps and files in order.
        let mesh = QuadMesh::block(
            "rod",
            0,
            (0.0, 3.0),
            (0.0, 1.0),
            3,
            1,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let field = FieldOutput {
            positions: mesh.nodes.iter().map(|n| [n[0], n[1], 0.0]).collect(),
            states: vec![MaterialState::initial(298.0); 3],
            eroded: vec![false, true, false],
            cell_data: vec![("density".into(), vec![1.0, 2.0, 3.0])],
            time: 2.0e-5,
            mesh,
        };
        let text = render(&field);
        assert!(text.contains("NumberOfCells=\"2\""), "{text}");
        let expected: Vec<String> = [0, 2]
            .iter()
            .map(|&e| {
                field.mesh.elements[e]
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect();
        assert!(text.contains(&expected.join("\n")), "{text}");
        assert!(text.contains("Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">2e-5<"));
        assert!(text.contains("Name=\"eroded_cells\" NumberOfTuples=\"1\" format=\"ascii\">1<"));
        assert!(
            text.contains("Name=\"part_id\" format=\"ascii\">\n1 1 \n"),
            "{text}"
        );
        assert!(text.contains("Name=\"material_id\" format=\"ascii\">\n1 1 \n"));
        assert!(text.contains("Name=\"density\" format=\"ascii\">\n1e0 3e0 \n"));
        assert!(text.contains("parts (part_id name): 1 rod (material 1)"));
        let series = collection(&[(0.0, "a.vtu".into()), (1.5e-5, "final.vtu".into())]);
        let a = series
            .find("timestep=\"0e0\" group=\"\" part=\"0\" file=\"a.vtu\"")
            .unwrap();
        let b = series
            .find("timestep=\"1.5e-5\" group=\"\" part=\"0\" file=\"final.vtu\"")
            .unwrap();
        assert!(a < b && series.contains("type=\"Collection\""));
    }
}
