//! Wavefront OBJ with the `tobj` crate: every object and group of the file in one mesh,
//! polygons triangulated, one index per vertex (a vertex with two normals is two vertices).
//! Materials (`.mtl`) are not read: the URDF's colour is drawn.

use super::TriangleMesh;

/// The mesh of the OBJ file `bytes`.
///
/// Errors: the reader's message when the bytes are not OBJ.
pub fn read(bytes: &[u8]) -> Result<TriangleMesh, String> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| e.to_string())?;
    let mut mesh = TriangleMesh::default();
    let mut normals = Vec::new();
    let mut every_vertex_has_a_normal = true;
    for model in &models {
        let m = &model.mesh;
        let offset = mesh.positions.len() as u32;
        mesh.positions
            .extend(m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        mesh.triangles.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
        every_vertex_has_a_normal &= m.normals.len() == m.positions.len();
        normals.extend(m.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]));
    }
    mesh.normals = (every_vertex_has_a_normal && !normals.is_empty()).then_some(normals);
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_is_triangulated_and_normals_kept() {
        let text = "# a unit square in z = 0 and a triangle above
o square
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vn 0 0 1
f 1//1 2//1 3//1 4//1
o triangle
v 0 0 1
v 1 0 1
v 0 1 1
f 5//1 6//1 7//1
";
        let mesh = read(text.as_bytes()).unwrap();
        assert_eq!(
            mesh.triangles.len(),
            3,
            "two for the square, one for the triangle"
        );
        let top = mesh.triangles[2];
        assert_eq!(mesh.positions[top[1] as usize], [1.0, 0.0, 1.0]);
        let normals = mesh.normals.expect("every vertex has vn");
        assert_eq!(normals.len(), mesh.positions.len());
        assert_eq!(normals[0], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn a_face_on_a_missing_vertex_is_an_error() {
        assert!(read(b"v 0 0 0\nf 1 2 3\n").is_err());
    }
}
