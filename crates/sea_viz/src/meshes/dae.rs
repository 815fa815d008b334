//! COLLADA (`.dae`) geometry, read with the `roxmltree` XML parser: the triangles, polylists
//! and polygons of every `<instance_geometry>` of the visual scene, placed by the transforms of
//! their nodes (`<matrix>`, `<translate>`, `<rotate>`, `<scale>`, nested, `<instance_node>`
//! followed) and scaled to metres by `<asset><unit meter>`. A file without a visual scene gives
//! its geometries as they are.
//!
//! `<up_axis>` is ignored, as RViz does: URDF authors place DAE meshes with the visual's
//! `<origin>` as RViz shows them (e.g. icub-models' `Y_UP` meshes have a rotated origin).
//! Materials are not read: the URDF's colour is drawn. Lines, tristrips and trifans are
//! skipped.
//!
//! The instanced geometry is bounded: nodes that instance each other repeatedly (each the next
//! twice, 40 levels deep, is 2^40 instances) would otherwise read without end. A file is
//! refused when its scene visits more than [`MAX_NODE_VISITS`] nodes or places more than
//! [`MAX_TRIANGLES`] triangles or [`MAX_POSITIONS`] vertices.

use super::TriangleMesh;
use roxmltree::Node;
use std::cell::Cell;
use std::collections::HashMap;

/// A 4x4 homogeneous transform, rows first.
type Matrix = [[f64; 4]; 4];

/// The identity transform.
const IDENTITY: Matrix = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// Instances deeper than this are a cycle of `<instance_node>`s.
const MAX_NODE_DEPTH: usize = 64;

/// Most nodes the visual scene may visit, instances counted each time (a robot part's file has
/// tens to thousands).
pub const MAX_NODE_VISITS: usize = 100_000;

/// Most triangles a file may place, instances counted each time (a detailed robot part has
/// about 10^5; the visuals are decimated after reading anyway).
pub const MAX_TRIANGLES: usize = 5_000_000;

/// Most vertices a file may place, instances counted each time.
pub const MAX_POSITIONS: usize = 5_000_000;

/// The mesh of the COLLADA file `bytes`, in metres.
///
/// Errors: a message when the bytes are not XML, when an index points past its source, when
/// the file has no triangles, or when its instanced geometry is over the bounds of the module.
pub fn read(bytes: &[u8]) -> Result<TriangleMesh, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not UTF-8 text: {e}"))?;
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let document =
        roxmltree::Document::parse_with_options(text.trim_start_matches('\u{feff}'), options)
            .map_err(|e| format!("not XML: {e}"))?;
    let reader = Reader::new(&document);
    let unit = reader.unit_scale();
    let root = scale_matrix([unit; 3]);
    let mut mesh = TriangleMesh::default();
    match reader.visual_scene() {
        Some(scene) => {
            for node in elements(scene, "node") {
                reader.add_node(node, &root, 0, &mut mesh)?;
            }
        }
        None => {
            for geometry in document
                .descendants()
                .filter(|n| n.tag_name().name() == "geometry")
            {
                reader.add_geometry(geometry, &root, &mut mesh)?;
            }
        }
    }
    if mesh.triangles.is_empty() {
        return Err("no triangles in the file's visual scene".into());
    }
    Ok(mesh)
}

/// The document with its elements by id.
struct Reader<'a, 'input> {
    document: &'a roxmltree::Document<'input>,
    by_id: HashMap<&'a str, Node<'a, 'input>>,
    /// Nodes visited so far, instances counted each time.
    visits: Cell<usize>,
}

/// The child elements of `node` named `tag` (any namespace).
fn elements<'a, 'input>(
    node: Node<'a, 'input>,
    tag: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

/// The first child element of `node` named `tag`.
fn element<'a, 'input>(node: Node<'a, 'input>, tag: &'static str) -> Option<Node<'a, 'input>> {
    elements(node, tag).next()
}

/// The numbers of an element's text.
fn numbers<T: std::str::FromStr>(node: Node<'_, '_>) -> Result<Vec<T>, String> {
    node.text()
        .unwrap_or("")
        .split_ascii_whitespace()
        .map(|word| {
            word.parse()
                .map_err(|_| format!("<{}>: '{word}' is not a number", node.tag_name().name()))
        })
        .collect()
}

impl<'a, 'input> Reader<'a, 'input> {
    fn new(document: &'a roxmltree::Document<'input>) -> Self {
        let by_id = document
            .descendants()
            .filter_map(|n| n.attribute("id").map(|id| (id, n)))
            .collect();
        Self {
            document,
            by_id,
            visits: Cell::new(0),
        }
    }

    /// The element a URL `#id` names.
    fn target(&self, url: Option<&str>) -> Option<Node<'a, 'input>> {
        self.by_id.get(url?.trim_start_matches('#')).copied()
    }

    /// Metres per unit of the file (`<asset><unit meter>`, 1 when absent).
    fn unit_scale(&self) -> f64 {
        let root = self.document.root_element();
        element(root, "asset")
            .and_then(|asset| element(asset, "unit"))
            .and_then(|unit| unit.attribute("meter"))
            .and_then(|meter| meter.trim().parse().ok())
            .filter(|meter: &f64| meter.is_finite() && *meter > 0.0)
            .unwrap_or(1.0)
    }

    /// The scene's `<instance_visual_scene>`, else the first `<visual_scene>`.
    fn visual_scene(&self) -> Option<Node<'a, 'input>> {
        let root = self.document.root_element();
        element(root, "scene")
            .and_then(|scene| element(scene, "instance_visual_scene"))
            .and_then(|instance| self.target(instance.attribute("url")))
            .or_else(|| {
                self.document
                    .descendants()
                    .find(|n| n.tag_name().name() == "visual_scene")
            })
    }

    /// Adds the geometry under `node`, placed by `parent` times the node's own transform.
    fn add_node(
        &self,
        node: Node<'a, 'input>,
        parent: &Matrix,
        depth: usize,
        mesh: &mut TriangleMesh,
    ) -> Result<(), String> {
        if depth > MAX_NODE_DEPTH {
            return Err("the nodes instance each other in a cycle".into());
        }
        self.visits.set(self.visits.get() + 1);
        if self.visits.get() > MAX_NODE_VISITS {
            return Err(format!(
                "the visual scene instances more than {MAX_NODE_VISITS} nodes (nodes that \
                 instance each other repeatedly); the file is not read"
            ));
        }
        let placement = multiply(parent, &node_transform(node)?);
        for child in node.children().filter(|c| c.is_element()) {
            match child.tag_name().name() {
                "node" => self.add_node(child, &placement, depth + 1, mesh)?,
                "instance_node" => {
                    if let Some(target) = self.target(child.attribute("url")) {
                        self.add_node(target, &placement, depth + 1, mesh)?;
                    }
                }
                "instance_geometry" => {
                    if let Some(geometry) = self.target(child.attribute("url")) {
                        self.add_geometry(geometry, &placement, mesh)?;
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Adds the triangles of the `<geometry>` element `geometry`, placed by `placement`.
    fn add_geometry(
        &self,
        geometry: Node<'a, 'input>,
        placement: &Matrix,
        mesh: &mut TriangleMesh,
    ) -> Result<(), String> {
        let Some(source_mesh) = element(geometry, "mesh") else {
            return Ok(()); // splines and convex meshes: nothing to draw
        };
        let mut positions_by_source: HashMap<&str, u32> = HashMap::new();
        for primitive in source_mesh.children().filter(|c| c.is_element()) {
            let polygons = match primitive.tag_name().name() {
                "triangles" | "polylist" | "polygons" => polygon_lists(primitive)?,
                _ => continue,
            };
            let (position_source, position_offset, stride) = self.position_input(primitive)?;
            let source_id = position_source.attribute("id").unwrap_or("");
            let base = match positions_by_source.get(source_id) {
                Some(base) => *base,
                None => {
                    let base = mesh.positions.len() as u32;
                    let points = source_points(position_source)?;
                    mesh.positions
                        .extend(points.iter().map(|p| transform_point(placement, *p)));
                    positions_by_source.insert(source_id, base);
                    base
                }
            };
            let count = mesh.positions.len() as u32 - base;
            for polygon in polygons {
                let corners: Vec<u32> = polygon
                    .chunks_exact(stride)
                    .map(|vertex| vertex[position_offset])
                    .collect();
                if let Some(bad) = corners.iter().find(|&&i| i >= count) {
                    return Err(format!(
                        "<{}>: vertex index {bad} past the {count} positions of its source",
                        primitive.tag_name().name()
                    ));
                }
                // A fan: polygons are convex in practice (exporters write triangles or quads).
                for k in 1..corners.len().saturating_sub(1) {
                    mesh.triangles.push([
                        base + corners[0],
                        base + corners[k],
                        base + corners[k + 1],
                    ]);
                }
            }
            check_size(mesh)?;
        }
        Ok(())
    }

    /// The `<source>` of a primitive's positions, the offset of its index in each vertex and
    /// the number of indices per vertex.
    fn position_input(
        &self,
        primitive: Node<'a, 'input>,
    ) -> Result<(Node<'a, 'input>, usize, usize), String> {
        let inputs: Vec<Node> = elements(primitive, "input").collect();
        let offset = |input: &Node| -> usize {
            input
                .attribute("offset")
                .and_then(|o| o.parse().ok())
                .unwrap_or(0)
        };
        let stride = inputs.iter().map(|i| offset(i) + 1).max().unwrap_or(1);
        for input in &inputs {
            let source = self.target(input.attribute("source"));
            match (input.attribute("semantic"), source) {
                (Some("VERTEX"), Some(vertices)) => {
                    let position = elements(vertices, "input")
                        .find(|i| i.attribute("semantic") == Some("POSITION"))
                        .and_then(|i| self.target(i.attribute("source")));
                    if let Some(position) = position {
                        return Ok((position, offset(input), stride));
                    }
                }
                (Some("POSITION"), Some(source)) => return Ok((source, offset(input), stride)),
                _ => {}
            }
        }
        Err(format!(
            "<{}> has no VERTEX input with positions",
            primitive.tag_name().name()
        ))
    }
}

/// The index lists of each polygon of a `<triangles>`, `<polylist>` or `<polygons>` element
/// (all inputs interleaved, as in the file).
fn polygon_lists(primitive: Node<'_, '_>) -> Result<Vec<Vec<u32>>, String> {
    let stride = elements(primitive, "input")
        .filter_map(|i| i.attribute("offset").and_then(|o| o.parse::<usize>().ok()))
        .max()
        .map_or(1, |m| m + 1);
    match primitive.tag_name().name() {
        "polygons" => elements(primitive, "p").map(numbers).collect(),
        name => {
            let indices: Vec<u32> = element(primitive, "p")
                .map(numbers)
                .transpose()?
                .unwrap_or_default();
            let counts: Vec<usize> = if name == "polylist" {
                element(primitive, "vcount")
                    .map(numbers)
                    .transpose()?
                    .unwrap_or_default()
            } else {
                vec![3; indices.len() / (3 * stride)]
            };
            let mut polygons = Vec::with_capacity(counts.len());
            let mut start = 0;
            for count in counts {
                let end = start + count * stride;
                let polygon = indices
                    .get(start..end)
                    .ok_or_else(|| format!("<{name}>: <p> is shorter than its polygons"))?;
                polygons.push(polygon.to_vec());
                start = end;
            }
            Ok(polygons)
        }
    }
}

/// The 3D points of a `<source>` (its `<float_array>` read through its accessor's stride and
/// offset).
fn source_points(source: Node<'_, '_>) -> Result<Vec<[f64; 3]>, String> {
    let values: Vec<f64> = element(source, "float_array")
        .map(numbers)
        .transpose()?
        .unwrap_or_default();
    let accessor = element(source, "technique_common").and_then(|t| element(t, "accessor"));
    let attribute = |name: &str, default: usize| {
        accessor
            .and_then(|a| a.attribute(name))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (stride, offset) = (attribute("stride", 3).max(3), attribute("offset", 0));
    let count = attribute("count", values.len().saturating_sub(offset) / stride);
    (0..count)
        .map(|i| {
            let start = offset + i * stride;
            values
                .get(start..start + 3)
                .map(|p| [p[0], p[1], p[2]])
                .ok_or_else(|| {
                    format!(
                        "<source id='{}'>: too few values",
                        source.attribute("id").unwrap_or("")
                    )
                })
        })
        .collect()
}

/// The product of a node's transform elements, in document order.
fn node_transform(node: Node<'_, '_>) -> Result<Matrix, String> {
    let mut transform = IDENTITY;
    for child in node.children().filter(|c| c.is_element()) {
        let tag = child.tag_name().name();
        if !matches!(tag, "matrix" | "translate" | "rotate" | "scale") {
            continue;
        }
        let v: Vec<f64> = numbers(child)?;
        let expected = match tag {
            "matrix" => 16,
            "rotate" => 4,
            _ => 3,
        };
        if v.len() != expected {
            return Err(format!("<{tag}> has {} numbers, not {expected}", v.len()));
        }
        let local = match tag {
            "matrix" => std::array::from_fn(|r| std::array::from_fn(|c| v[4 * r + c])),
            "translate" => {
                let mut m = IDENTITY;
                (0..3).for_each(|i| m[i][3] = v[i]);
                m
            }
            "rotate" => rotation_matrix([v[0], v[1], v[2]], v[3].to_radians()),
            _ => scale_matrix([v[0], v[1], v[2]]),
        };
        transform = multiply(&transform, &local);
    }
    Ok(transform)
}

/// An error when `mesh` holds more than [`MAX_TRIANGLES`] triangles or [`MAX_POSITIONS`]
/// vertices.
fn check_size(mesh: &TriangleMesh) -> Result<(), String> {
    let (triangles, positions) = (mesh.triangles.len(), mesh.positions.len());
    if triangles > MAX_TRIANGLES || positions > MAX_POSITIONS {
        return Err(format!(
            "the instanced geometry is over {MAX_TRIANGLES} triangles or {MAX_POSITIONS} \
             vertices ({triangles} triangles, {positions} vertices so far); the file is not read"
        ));
    }
    Ok(())
}

/// A scale along the axes.
fn scale_matrix([x, y, z]: [f64; 3]) -> Matrix {
    let mut m = IDENTITY;
    m[0][0] = x;
    m[1][1] = y;
    m[2][2] = z;
    m
}

/// The rotation by `angle` [rad] about `axis` (normalised here; a zero axis is no rotation).
fn rotation_matrix(axis: [f64; 3], angle: f64) -> Matrix {
    let norm = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    if norm == 0.0 {
        return IDENTITY;
    }
    let [x, y, z] = axis.map(|a| a / norm);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// `a b`.
fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// `m p` for a point `p`.
fn transform_point(m: &Matrix, p: [f64; 3]) -> [f32; 3] {
    std::array::from_fn(|r| (m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3]) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quad (polylist) and a triangle (triangles with a normal input) of one geometry,
    /// instanced by a node scaled by 2 then moved by (0, 0, 1), in centimetres.
    const DAE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.0">
  <asset><unit meter="0.01" name="centimeter"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g">
      <mesh>
        <source id="g-pos">
          <float_array id="g-pos-array" count="15">0 0 0 1 0 0 1 1 0 0 1 0 0 0 1</float_array>
          <technique_common><accessor source="#g-pos-array" count="5" stride="3"/></technique_common>
        </source>
        <source id="g-nor">
          <float_array id="g-nor-array" count="3">0 0 1</float_array>
          <technique_common><accessor source="#g-nor-array" count="1" stride="3"/></technique_common>
        </source>
        <vertices id="g-vtx"><input semantic="POSITION" source="#g-pos"/></vertices>
        <polylist count="1">
          <input semantic="VERTEX" source="#g-vtx" offset="0"/>
          <vcount>4</vcount>
          <p>0 1 2 3</p>
        </polylist>
        <triangles count="1">
          <input semantic="VERTEX" source="#g-vtx" offset="0"/>
          <input semantic="NORMAL" source="#g-nor" offset="1"/>
          <p>0 0 1 0 4 0</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="outer">
        <translate>0 0 1</translate>
        <node id="inner">
          <scale>2 2 2</scale>
          <instance_geometry url="#g"/>
        </node>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##;

    #[test]
    fn polylists_and_triangles_are_placed_by_their_nodes_and_the_unit() {
        let mesh = read(DAE.as_bytes()).unwrap();
        assert_eq!(mesh.triangles.len(), 3, "the quad gives two triangles");
        assert_eq!(mesh.positions.len(), 5, "the source is read once");
        let point = |t: usize, k: usize| mesh.positions[mesh.triangles[t][k] as usize];
        // (1, 1, 0) scaled by 2 and moved by (0, 0, 1), in cm: (0.02, 0.02, 0.01) m.
        assert_eq!(point(0, 2), [0.02, 0.02, 0.01]);
        // The triangle's third corner (0, 0, 1): (0, 0, 0.03) m.
        assert_eq!(point(2, 2), [0.0, 0.0, 0.03]);
    }

    #[test]
    fn rotate_and_matrix_transforms_compose_in_document_order() {
        let node = r#"<node xmlns="x"><rotate>0 0 1 90</rotate><matrix>1 0 0 1  0 1 0 0  0 0 1 0  0 0 0 1</matrix></node>"#;
        let document = roxmltree::Document::parse(node).unwrap();
        let m = node_transform(document.root_element()).unwrap();
        // Move by x, then turn a quarter about z: the origin lands on +y.
        let p = transform_point(&m, [0.0; 3]);
        assert!(
            (p[0] - 0.0).abs() < 1e-7 && (p[1] - 1.0).abs() < 1e-7,
            "{p:?}"
        );
    }

    /// `levels` nodes each instancing the next twice, the last instancing the geometry of
    /// [`DAE`]: 2^levels instances.
    fn doubling_instances(levels: usize) -> String {
        let nodes: String = (0..levels)
            .map(|k| {
                let next = format!(r##"<instance_node url="#n{}"/>"##, k + 1);
                format!(r#"<node id="n{k}">{next}{next}</node>"#)
            })
            .collect();
        let last = format!(r##"<node id="n{levels}"><instance_geometry url="#g"/></node>"##);
        let library = format!("<library_nodes>{nodes}{last}</library_nodes>");
        DAE.replace(
            r#"<node id="inner">"#,
            r##"<instance_node url="#n0"/><node id="inner">"##,
        )
        .replace(
            "<library_visual_scenes>",
            &format!("{library}<library_visual_scenes>"),
        )
    }

    #[test]
    fn doubling_instances_are_read_up_to_a_bound() {
        let few = read(doubling_instances(3).as_bytes()).unwrap();
        assert_eq!(few.triangles.len(), 3 * (1 + 8));
        let start = std::time::Instant::now();
        let message = read(doubling_instances(40).as_bytes()).unwrap_err();
        assert!(message.contains("more than 100000 nodes"), "{message}");
        assert!(start.elapsed().as_secs_f64() < 5.0, "{:?}", start.elapsed());
        // A big geometry instanced over and over: the triangle bound.
        let big: String = (0..30_000).map(|_| " 0 0 1 0 2 0").collect();
        let many = doubling_instances(15)
            .replace("<p>0 0 1 0 4 0</p>", &format!("<p>0 0 1 0 4 0{big}</p>"));
        let message = read(many.as_bytes()).unwrap_err();
        assert!(message.contains("over 5000000 triangles"), "{message}");
    }

    #[test]
    fn a_file_of_doubling_instances_is_refused_promptly_naming_the_file() {
        let dir = std::env::temp_dir().join(format!("sea_sim_dae_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("nested_40.dae");
        std::fs::write(&path, doubling_instances(40)).unwrap();
        let start = std::time::Instant::now();
        let message = crate::meshes::read_mesh(&path).unwrap_err().to_string();
        assert!(start.elapsed().as_secs_f64() < 5.0, "{:?}", start.elapsed());
        assert!(message.contains("nested_40.dae"), "{message}");
        assert!(message.contains("instances more than"), "{message}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(read(b"<COLLADA><unclosed></COLLADA>").is_err());
        let empty = r#"<COLLADA><library_geometries/></COLLADA>"#;
        assert!(read(empty.as_bytes()).unwrap_err().contains("no triangles"));
        let past = DAE.replace("<p>0 1 2 3</p>", "<p>0 1 2 9</p>");
        assert!(read(past.as_bytes()).unwrap_err().contains("index 9"));
    }
}
