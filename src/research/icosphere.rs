//! Icosphere meshes for the `mesh-L0` ... `mesh-L4` benchmark methods: the classic alternative
//! to impostors, one instanced triangle mesh per ellipsoid.
//!
//! Level `L` starts from the regular icosahedron (12 vertices, 20 triangles) and splits every
//! triangle into four `L` times, sharing each edge midpoint between the two triangles of the edge
//! and projecting it onto the unit sphere. Level `L` has `20 * 4^L` triangles and
//! `10 * 4^L + 2` vertices:
//!
//! | level | vertices | triangles | sagitta |
//! |---|---|---|---|
//! | 0 | 12 | 20 | 0.205 |
//! | 1 | 42 | 80 | 0.066 |
//! | 2 | 162 | 320 | 0.018 |
//! | 3 | 642 | 1,280 | 0.0045 |
//! | 4 | 2,562 | 5,120 | 0.0011 |
//!
//! Positions are unit vectors, so they are also the parameter-space normals; an instance maps
//! them through its ellipsoid's `T = R diag(radii)`. Triangles wind counter-clockwise seen from
//! outside. The [`sagitta`] is how far the flat triangles sink below the sphere, in units of the
//! radius: the depth error a mesh method starts from.

use std::collections::HashMap;

/// Highest level [`icosphere`] builds (10,485,762 vertices); the benchmark uses 0 ..= 4.
pub const MAX_LEVEL: u32 = 10;

/// An indexed triangle mesh of the unit sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct Icosphere {
    /// Unit-length vertex positions (equal to the outward normals).
    pub positions: Vec<[f32; 3]>,
    /// Three indices into `positions` per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

impl Icosphere {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The three corners of triangle `t`, in float64.
    pub fn triangle(&self, t: usize) -> [[f64; 3]; 3] {
        [0, 1, 2].map(|k| self.positions[self.indices[3 * t + k] as usize].map(f64::from))
    }

    /// The largest distance between the unit sphere and the mesh's flat triangles:
    /// `1 - min` over triangles of the distance from the origin to the triangle's plane.
    pub fn sagitta(&self) -> f64 {
        let nearest = (0..self.triangle_count())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                let n = cross(sub(b, a), sub(c, a));
                dot(n, a).abs() / dot(n, n).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        1.0 - nearest
    }
}

/// The icosphere of subdivision `level`: `20 * 4^level` triangles, `10 * 4^level + 2` vertices.
///
/// # Panics
/// If `level > MAX_LEVEL`.
pub fn icosphere(level: u32) -> Icosphere {
    assert!(
        level <= MAX_LEVEL,
        "icosphere level {level} exceeds {MAX_LEVEL}"
    );
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(normalize)
    .to_vec();
    let mut indices: Vec<u32> = vec![
        0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, //
        1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, //
        3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, //
        4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1,
    ];

    let final_vertices = 10 * 4usize.pow(level) + 2;
    positions.reserve_exact(final_vertices - positions.len());
    for _ in 0..level {
        // Each edge of the current mesh gets one midpoint, shared by its two triangles.
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() / 2);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<[f64; 3]>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (positions[a as usize], positions[b as usize]);
                positions.push(normalize([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(indices.len() * 4);
        for tri in indices.chunks_exact(3) {
            let (a, b, c) = (tri[0], tri[1], tri[2]);
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend_from_slice(&[a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca]);
        }
        indices = next;
    }
    debug_assert_eq!(positions.len(), final_vertices);

    Icosphere {
        positions: positions.iter().map(|p| p.map(|x| x as f32)).collect(),
        indices,
    }
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    v.map(|x| x / n)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    use std::collections::HashSet;

    fn meshes() -> Vec<Icosphere> {
        (0..=4).map(icosphere).collect()
    }

    #[test]
    fn counts_follow_the_subdivision_formulas() {
        let expected = [(12, 20), (42, 80), (162, 320), (642, 1280), (2562, 5120)];
        for (level, (mesh, (v, t))) in meshes().iter().zip(expected).enumerate() {
            assert_eq!(mesh.vertex_count(), v, "level {level} vertices");
            assert_eq!(mesh.triangle_count(), t, "level {level} triangles");
            assert_eq!(mesh.indices.len(), 3 * t);
            let l = level as u32;
            assert_eq!(v, 10 * 4usize.pow(l) + 2);
            assert_eq!(t, 20 * 4usize.pow(l));
            assert!(mesh.indices.iter().all(|&i| (i as usize) < v));
        }
    }

    #[test]
    fn positions_are_unit_vectors() {
        for (level, mesh) in meshes().iter().enumerate() {
            for p in &mesh.positions {
                let len = dot(p.map(f64::from), p.map(f64::from)).sqrt();
                assert!((len - 1.0).abs() < 1e-6, "level {level}: |{p:?}| = {len}");
            }
        }
    }

    #[test]
    fn closed_manifold_with_consistent_winding() {
        for (level, mesh) in meshes().iter().enumerate() {
            // Every directed edge exactly once and its reverse exactly once: each undirected edge
            // has exactly two triangles, which traverse it in opposite directions.
            let mut directed = HashSet::new();
            for tri in mesh.indices.chunks_exact(3) {
                assert!(
                    tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0],
                    "level {level}: degenerate triangle {tri:?}"
                );
                for k in 0..3 {
                    let edge = (tri[k], tri[(k + 1) % 3]);
                    assert!(directed.insert(edge), "level {level}: edge {edge:?} twice");
                }
            }
            for &(a, b) in &directed {
                assert!(
                    directed.contains(&(b, a)),
                    "level {level}: edge ({a}, {b}) has one triangle"
                );
            }
            // Euler characteristic of the sphere: V - E + F = 2.
            let (v, e, f) = (
                mesh.vertex_count() as i64,
                directed.len() as i64 / 2,
                mesh.triangle_count() as i64,
            );
            assert_eq!(v - e + f, 2, "level {level}");
        }
    }

    #[test]
    fn triangles_face_outward() {
        for (level, mesh) in meshes().iter().enumerate() {
            for t in 0..mesh.triangle_count() {
                let [a, b, c] = mesh.triangle(t);
                let n = cross(sub(b, a), sub(c, a));
                let centroid = [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0);
                let cos = dot(n, centroid) / (dot(n, n) * dot(centroid, centroid)).sqrt();
                assert!(cos > 0.9, "level {level} triangle {t}: cos {cos}");
            }
        }
    }

    #[test]
    fn no_duplicate_vertices() {
        for (level, mesh) in meshes().iter().enumerate() {
            let p: Vec<[f64; 3]> = mesh.positions.iter().map(|p| p.map(f64::from)).collect();
            let mut closest = f64::INFINITY;
            for i in 0..p.len() {
                for j in i + 1..p.len() {
                    let d = sub(p[i], p[j]);
                    closest = closest.min(dot(d, d).sqrt());
                }
            }
            // The shortest edge at level 4 is about 0.069; a duplicate would be ~0.
            assert!(closest > 0.02, "level {level}: vertices {closest} apart");
        }
    }

    #[test]
    fn sagitta_matches_the_analytic_values() {
        // Inradius of the icosahedron with unit circumradius: sqrt((5 + 2 sqrt 5) / 15).
        let level0 = 1.0 - ((5.0 + 2.0 * 5f64.sqrt()) / 15.0).sqrt();
        assert!((level0 - 0.2054).abs() < 1e-4);
        let s: Vec<f64> = (0..=4).map(|level| icosphere(level).sagitta()).collect();
        assert!(
            (s[0] - level0).abs() < 1e-6,
            "level 0: {} vs {level0}",
            s[0]
        );
        for l in 1..s.len() {
            let ratio = s[l] / s[l - 1];
            // Halving every edge quarters the sagitta of a small cap (s ~ chord^2 / 8); the
            // projected midpoints make the triangles slightly uneven, hence the band.
            assert!(
                (0.2..0.35).contains(&ratio),
                "level {l}: sagitta {} / {} = {ratio}",
                s[l],
                s[l - 1]
            );
        }
        assert!(s[4] < 1.5e-3, "level 4 sagitta {}", s[4]);
    }
}
