//! Decimation of a triangle mesh to a target triangle count with the `meshopt` crate
//! (meshoptimizer): equal positions are welded, then edges are collapsed by quadric error
//! (`simplify`, keeps the shape and the topology); when the topology stops it above the target
//! (meshes made of many loose parts), vertex clustering (`simplify_sloppy`) finishes the job.
//! Unused vertices are dropped. Normals are dropped (they would no longer match).

use super::TriangleMesh;

/// Largest relative error (fraction of the mesh's extent) the topology-keeping pass may
/// introduce: 2 % of a 0.3 m thigh is 6 mm, invisible in a picture or a 3D view.
const TOPOLOGY_KEEPING_ERROR: f32 = 0.02;

/// Relative error allowed to the clustering pass: none in effect, the triangle budget rules
/// (a bound would leave small meshes above their share of the budget).
const CLUSTERING_ERROR: f32 = 1.0;

/// `mesh` with at most about `target_triangles` triangles (fewer triangles are kept as they
/// are; a target of 0 is taken as 1). The result can have a few more triangles than asked when
/// even clustering cannot reach the target.
pub fn decimate(mesh: &TriangleMesh, target_triangles: usize) -> TriangleMesh {
    let target = target_triangles.max(1);
    if mesh.triangles.len() <= target {
        return mesh.clone();
    }
    let (positions, indices) = welded(mesh);
    let mut simplified = meshopt::simplify_decoder(
        &indices,
        &positions,
        3 * target,
        TOPOLOGY_KEEPING_ERROR,
        meshopt::SimplifyOptions::None,
        None,
    );
    if simplified.len() > 3 * target {
        simplified = meshopt::simplify_sloppy_decoder(
            &simplified,
            &positions,
            3 * target,
            CLUSTERING_ERROR,
            None,
        );
    }
    let positions = meshopt::optimize_vertex_fetch(&mut simplified, &positions);
    TriangleMesh {
        positions,
        triangles: simplified
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        normals: None,
    }
}

/// The positions with equal ones merged and the index buffer on them.
fn welded(mesh: &TriangleMesh) -> (Vec<[f32; 3]>, Vec<u32>) {
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let (count, remap) = meshopt::generate_vertex_remap(&mesh.positions, Some(&indices));
    let positions = meshopt::remap_vertex_buffer(&mesh.positions, count, &remap);
    let indices = meshopt::remap_index_buffer(Some(&indices), mesh.positions.len(), &remap);
    (positions, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit sphere of `rings` x `segments` quads (two triangles each), poles included.
    fn sphere(rings: u32, segments: u32) -> TriangleMesh {
        let mut mesh = TriangleMesh::default();
        for r in 0..=rings {
            let polar = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..segments {
                let azimuth = std::f32::consts::TAU * s as f32 / segments as f32;
                mesh.positions.push([
                    polar.sin() * azimuth.cos(),
                    polar.sin() * azimuth.sin(),
                    polar.cos(),
                ]);
            }
        }
        let at = |r: u32, s: u32| r * segments + s % segments;
        for r in 0..rings {
            for s in 0..segments {
                mesh.triangles
                    .push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
                mesh.triangles
                    .push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
            }
        }
        mesh
    }

    #[test]
    fn a_fine_sphere_is_cut_to_the_target_and_keeps_its_shape() {
        let fine = sphere(60, 80);
        assert_eq!(fine.triangles.len(), 9600);
        let coarse = decimate(&fine, 500);
        assert!(coarse.triangles.len() <= 500, "{}", coarse.triangles.len());
        assert!(coarse.triangles.len() >= 100, "{}", coarse.triangles.len());
        // Every vertex kept is a vertex of the sphere, and every one is used.
        for p in &coarse.positions {
            let radius = p.iter().map(|v| v * v).sum::<f32>().sqrt();
            assert!((radius - 1.0).abs() < 1e-5, "{radius}");
        }
        let mut used = vec![false; coarse.positions.len()];
        coarse
            .triangles
            .iter()
            .flatten()
            .for_each(|&i| used[i as usize] = true);
        assert!(used.iter().all(|u| *u));
    }

    #[test]
    fn small_meshes_are_kept_as_they_are() {
        let small = sphere(4, 6);
        assert_eq!(decimate(&small, 1000), small);
    }
}
