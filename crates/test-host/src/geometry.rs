//! Meshes for the host to draw: a tilted plane and a cube, as flat-coloured triangle lists.

use glam::DVec3;

use crate::MeshVertex;

/// The two triangles of the quad `corners` (counter-clockwise), in one colour.
fn quad(corners: [DVec3; 4], color: [f32; 3]) -> impl Iterator<Item = MeshVertex> {
    [0, 1, 2, 0, 2, 3].into_iter().map(move |i| MeshVertex {
        position: corners[i].as_vec3().to_array(),
        color,
    })
}

/// A square of side `2 * half_size` centred on `center` in the plane with `normal`, as two
/// triangles of one colour.
pub fn tilted_plane(
    center: DVec3,
    normal: DVec3,
    half_size: f64,
    color: [f32; 3],
) -> Vec<MeshVertex> {
    let n = normal.normalize();
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = n.cross(helper).normalize() * half_size;
    let v = n.cross(u);
    let corners = [
        center - u - v,
        center + u - v,
        center + u + v,
        center - u + v,
    ];
    quad(corners, color).collect()
}

/// The grey levels of [`cube`]'s faces (+X, -X, +Y, -Y, +Z, -Z) when coloured per face: whole
/// multiples of 1/255, so an RGBA8 readback holds them exactly.
pub const CUBE_FACE_GREYS: [u8; 6] = [80, 112, 144, 176, 208, 240];
/// The grey of [`cube`] when not coloured per face.
pub const CUBE_GREY: u8 = 160;

/// An axis-aligned cube of 12 triangles. With `color_per_face`, each face has its own grey
/// ([`CUBE_FACE_GREYS`]); otherwise all are [`CUBE_GREY`].
pub fn cube(center: DVec3, half_size: f64, color_per_face: bool) -> Vec<MeshVertex> {
    let mut vertices = Vec::with_capacity(36);
    for (face, face_grey) in CUBE_FACE_GREYS.into_iter().enumerate() {
        let axis = face / 2;
        let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
        let mut n = DVec3::ZERO;
        n[axis] = sign;
        let mut u = DVec3::ZERO;
        u[(axis + 1) % 3] = 1.0;
        let mut v = DVec3::ZERO;
        v[(axis + 2) % 3] = 1.0;
        let grey = if color_per_face { face_grey } else { CUBE_GREY };
        let level = f32::from(grey) / 255.0;
        let corner = |a: f64, b: f64| center + (n + u * a + v * b) * half_size;
        let corners = [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        vertices.extend(quad(corners, [level; 3]));
    }
    vertices
}
