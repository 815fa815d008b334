//! STL, ASCII or binary, with the `stl_io` crate (it merges equal vertices into an indexed
//! mesh). The facet normals are not kept: they are face normals, which the drawing computes.

use super::TriangleMesh;

/// The mesh of the STL file `bytes`.
///
/// Errors: the reader's message when the bytes are not STL; bytes that are neither a binary
/// STL (84 bytes of header and count, then at least 50 per triangle) nor text starting with `solid` are
/// refused before `stl_io` sees them (its ASCII probe reads a file without line breaks as one
/// line, all into memory).
pub fn read(bytes: &[u8]) -> Result<TriangleMesh, String> {
    if !is_binary_stl(bytes) && !bytes.trim_ascii_start().starts_with(b"solid") {
        return Err(
            "neither binary STL (its size does not match its triangle count) nor ASCII STL \
             (it does not start with `solid`)"
                .into(),
        );
    }
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let index = |i: usize| u32::try_from(i).map_err(|_| "more than 2^32 vertices".to_string());
    let triangles = mesh
        .faces
        .iter()
        .map(|face| {
            let [a, b, c] = face.vertices;
            Ok([index(a)?, index(b)?, index(c)?])
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(TriangleMesh {
        positions: mesh.vertices.iter().map(|v| v.0).collect(),
        triangles,
        normals: None,
    })
}

/// Whether `bytes` hold a binary STL of the triangle count in its header (trailing bytes
/// allowed, as `stl_io` reads them).
fn is_binary_stl(bytes: &[u8]) -> bool {
    let Some(count) = bytes.get(80..84) else {
        return false;
    };
    let count = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as u64;
    bytes.len() as u64 >= 84 + 50 * count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit right tetrahedron's two faces, as ASCII STL.
    const ASCII: &str = "solid two
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 1 0
  vertex 1 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 0 1
 endloop
endfacet
endsolid two
";

    #[test]
    fn ascii_stl_reads_into_shared_vertices() {
        let mesh = read(ASCII.as_bytes()).unwrap();
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(mesh.positions.len(), 4, "the shared corners are merged");
        let corner = |t: usize, k: usize| mesh.positions[mesh.triangles[t][k] as usize];
        assert_eq!(corner(0, 1), [0.0, 1.0, 0.0]);
        assert_eq!(corner(1, 2), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn binary_stl_reads() {
        let mut bytes = vec![0u8; 80];
        bytes.extend(1u32.to_le_bytes());
        let floats = [
            0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0, 0.0,
        ];
        for f in floats {
            bytes.extend(f.to_le_bytes());
        }
        bytes.extend([0u8; 2]);
        let mesh = read(&bytes).unwrap();
        assert_eq!(mesh.triangles.len(), 1);
        assert_eq!(
            mesh.positions[mesh.triangles[0][2] as usize],
            [0.0, 3.0, 0.0]
        );
    }

    #[test]
    fn garbage_is_an_error() {
        assert!(read(b"solid x\nfacet oops\n").is_err());
        let error = read(&[b'x'; 200]).unwrap_err();
        assert!(error.contains("neither binary STL"), "{error}");
    }
}
