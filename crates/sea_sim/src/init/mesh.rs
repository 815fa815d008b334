//! Vertices of a mesh file, for measuring a foot: STL (binary or ASCII) and Wavefront OBJ.
//! Other formats (COLLADA .dae) are refused with a message saying which are read.

use std::path::Path;

/// The vertices of the mesh `file` in its own units, or why they cannot be read.
pub fn vertices(file: &Path) -> Result<Vec<[f64; 3]>, String> {
    let bytes = std::fs::read(file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    let extension = file
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    match extension.as_str() {
        "stl" => stl(&bytes).ok_or_else(|| format!("{} is not a valid STL file", file.display())),
        "obj" => Ok(obj(&String::from_utf8_lossy(&bytes))),
        _ => Err(format!(
            "the mesh {} is neither STL nor OBJ (the formats read to measure a foot)",
            file.display()
        )),
    }
}

/// Binary STL (80-byte header, triangle count, 50 bytes per triangle) or ASCII STL.
fn stl(bytes: &[u8]) -> Option<Vec<[f64; 3]>> {
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes(bytes[80..84].try_into().ok()?) as usize;
        if bytes.len() == 84 + 50 * count {
            let mut out = Vec::with_capacity(3 * count);
            for triangle in bytes[84..].chunks_exact(50) {
                for v in 0..3 {
                    let at = 12 + 12 * v;
                    let read = |k: usize| {
                        let start = at + 4 * k;
                        f32::from_le_bytes(
                            triangle[start..start + 4].try_into().unwrap_or_default(),
                        ) as f64
                    };
                    out.push([read(0), read(1), read(2)]);
                }
            }
            return Some(out);
        }
    }
    let text = std::str::from_utf8(bytes).ok()?;
    text.trim_start()
        .starts_with("solid")
        .then(|| prefixed_triples(text, "vertex"))
}

/// The `v x y z` lines of an OBJ file.
fn obj(text: &str) -> Vec<[f64; 3]> {
    prefixed_triples(text, "v")
}

/// The three numbers after `prefix` on each line that starts with it.
fn prefixed_triples(text: &str, prefix: &str) -> Vec<[f64; 3]> {
    text.lines()
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            (words.next()? == prefix).then_some(())?;
            let mut next = || words.next()?.parse::<f64>().ok();
            Some([next()?, next()?, next()?])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_and_ascii_stl_and_obj_vertices_are_read() {
        let mut binary = vec![0u8; 80];
        binary.extend(1u32.to_le_bytes());
        for value in [
            0.0f32, 0.0, 1.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0,
        ] {
            binary.extend(value.to_le_bytes());
        }
        binary.extend([0u8; 2]);
        let read = stl(&binary).unwrap();
        assert_eq!(
            read,
            vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]
        );
        let ascii = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\nvertex 4 5 6\n";
        assert_eq!(stl(ascii.as_bytes()).unwrap().len(), 2);
        assert_eq!(obj("v 1 2 3\nvn 0 0 1\nv 4 5 6\n").len(), 2);
    }
}
