//! The Rust side of the mirror: each shared `#[repr(C)]` type's fields in declaration order
//! with their offsets and sizes. Rust cannot list a struct's fields, so the names are written
//! here; `tables_cover_every_byte` proves no field is left out (the fields must tile the type
//! without a gap).

use std::mem::{offset_of, size_of, size_of_val};

use bytemuck::Zeroable;

use crate::gpu_layout::{
    CompactInstance, FootprintRecord, IndirectDraw, Instance, PushConstants, ShadingRecord,
    SpecConstants,
};

/// One field of a Rust layout.
#[derive(Debug)]
pub struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
}

/// A Rust layout: the type's name (the GLSL struct's), its size and its fields in order.
#[derive(Debug)]
pub struct Layout {
    pub name: &'static str,
    pub size: usize,
    pub fields: Vec<Field>,
}

/// The layout of `$ty` with the fields named, in declaration order.
macro_rules! layout {
    ($ty:ident { $($field:ident),* $(,)? }) => {{
        let zero = <$ty as Zeroable>::zeroed();
        Layout {
            name: stringify!($ty),
            size: size_of::<$ty>(),
            fields: vec![$(Field {
                name: stringify!($field),
                offset: offset_of!($ty, $field),
                size: size_of_val(&zero.$field),
            }),*],
        }
    }};
}

/// Every struct `gpu_layout.glsl` declares, as Rust lays it out.
pub fn shared_layouts() -> Vec<Layout> {
    vec![
        layout!(PushConstants {
            eye_view,
            near_plane,
            right,
            ndc_scale_x,
            up,
            ndc_scale_y,
            forward,
            depth_a,
            ndc_per_pixel,
            ndc_shift,
            depth_b,
            ambient,
            diffuse,
            specular,
            specular_color,
            shininess,
            depth_c,
            first_instance,
            radius_unit,
            viewport_origin,
        }),
        layout!(Instance {
            center,
            color,
            rotation,
            radii,
            unused,
        }),
        layout!(CompactInstance {
            center,
            color,
            rotation,
            radii,
        }),
        layout!(FootprintRecord {
            centre,
            axis1,
            axis2,
            quad_z,
            flags,
        }),
        layout!(ShadingRecord {
            ray_x,
            radius,
            ray_y,
            inv_eye_dist,
            ray_origin,
            centre_depth,
            flags,
            ray_c,
            eye_dist,
            depth_gradient,
            unused,
            to_normal_x,
            color_r,
            to_normal_y,
            color_g,
            to_normal_z,
            color_b,
        }),
        layout!(IndirectDraw {
            vertex_count,
            instance_count,
            first_vertex,
            first_instance,
            total,
            frame,
            shown,
            dispatch_x,
            dispatch_y,
            dispatch_z,
        }),
    ]
}

/// `SpecConstants`' fields: each is the GLSL constant of its name in capitals.
pub fn spec_constant_fields() -> Layout {
    layout!(SpecConstants {
        orthographic,
        textbook,
        bounds,
        corners,
        fast_normal,
        cull_frustum,
        cull_pixel_centres,
        culled,
        cull_step,
        cull_occlusion,
        cull_setup,
        no_caps,
        compact,
        reversed_z,
        splat_floor,
        splat_max_box_pixels,
        coverage_samples,
        sample_grid,
        far_plane,
        count_ray_casts,
        cull_select,
        splat_list,
        splat_setup_once,
    })
}

#[test]
fn tables_cover_every_byte() {
    for layout in shared_layouts().iter().chain([&spec_constant_fields()]) {
        let mut end = 0;
        for field in &layout.fields {
            assert_eq!(
                field.offset, end,
                "{}: a field between byte {end} and `{}` is missing from the table, or out \
                 of order",
                layout.name, field.name
            );
            end = field.offset + field.size;
        }
        assert_eq!(
            end, layout.size,
            "{}: fields after byte {end} are missing from the table",
            layout.name
        );
    }
}
