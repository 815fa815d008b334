//! The support polygon on flat ground ([`SupportPolygon`]): a sole's rectangle
//! ([`sea_dyn::ContactSurface`]'s `foot_x`, `foot_y`) placed at its pose, or the convex hull
//! of both soles' rectangles; the signed distance of a point to its edge and the closest
//! point inside.

use super::footstep::{SolePose, Stance};
use nalgebra::Vector2;
use sea_dyn::ContactSurface;

/// A convex polygon in world (x, y), vertices counter-clockwise.
#[derive(Clone, Debug, PartialEq)]
pub struct SupportPolygon {
    vertices: Vec<Vector2<f64>>,
}

impl SupportPolygon {
    /// The rectangle of `surface` under the sole at `pose`.
    pub fn of_sole(pose: SolePose, surface: &ContactSurface) -> Self {
        let ([x0, x1], [y0, y1]) = (surface.foot_x, surface.foot_y);
        let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
        Self {
            vertices: corners
                .iter()
                .map(|&(x, y)| pose.to_world(Vector2::new(x, y)))
                .collect(),
        }
    }

    /// The convex hull of both soles' rectangles.
    pub fn of_stance(stance: &Stance, surface: &ContactSurface) -> Self {
        let mut points = Self::of_sole(stance.left, surface).vertices;
        points.extend(Self::of_sole(stance.right, surface).vertices);
        Self {
            vertices: convex_hull(points),
        }
    }

    /// The vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Vector2<f64>] {
        &self.vertices
    }

    /// The edges as (start, end) pairs.
    fn edges(&self) -> impl Iterator<Item = (Vector2<f64>, Vector2<f64>)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// The distance of `p` to the polygon's edge [m]: positive inside, negative outside.
    pub fn signed_margin(&self, p: Vector2<f64>) -> f64 {
        let inside = self
            .edges()
            .map(|(a, b)| inward_distance(a, b, p))
            .fold(f64::INFINITY, f64::min);
        if inside >= 0.0 {
            inside
        } else {
            -(p - self.closest_point(p)).norm()
        }
    }

    /// The point of the polygon closest to `p` (`p` itself inside).
    pub fn closest_point(&self, p: Vector2<f64>) -> Vector2<f64> {
        if self.edges().all(|(a, b)| inward_distance(a, b, p) >= 0.0) {
            return p;
        }
        self.edges()
            .map(|(a, b)| closest_on_segment(a, b, p))
            .min_by(|u, v| (u - p).norm().total_cmp(&(v - p).norm()))
            .unwrap_or(p)
    }
}

/// The distance of `p` from the line `a -> b`, positive on its left (inside for a
/// counter-clockwise polygon).
fn inward_distance(a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>) -> f64 {
    let edge = b - a;
    (edge.x * (p.y - a.y) - edge.y * (p.x - a.x)) / edge.norm()
}

/// The point of segment `a b` closest to `p`.
fn closest_on_segment(a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>) -> Vector2<f64> {
    let edge = b - a;
    let s = ((p - a).dot(&edge) / edge.norm_squared()).clamp(0.0, 1.0);
    a + edge * s
}

/// The convex hull, counter-clockwise (Andrew's monotone chain; collinear points dropped).
fn convex_hull(mut points: Vec<Vector2<f64>>) -> Vec<Vector2<f64>> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>| {
        (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
    };
    let mut hull: Vec<Vector2<f64>> = Vec::with_capacity(2 * points.len());
    for pass in 0..2 {
        let floor = hull.len();
        let ordered: Box<dyn Iterator<Item = &Vector2<f64>>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= floor + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}
