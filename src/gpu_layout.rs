//! Every layout the CPU shares with the shaders, as `#[repr(C)]` plain-old-data types whose
//! sizes and field offsets are checked at compile time. `glsl/include/gpu_layout.glsl`
//! declares the same structs with the same field names (std430); change both together.

use std::mem::{offset_of, size_of};

use ash::vk;
use bytemuck::{Pod, Zeroable};

/// One ellipsoid in the full instance format (GLSL `Instance`, 48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Instance {
    /// Centre relative to the scene origin.
    pub center: [f32; 3],
    /// sRGB-encoded RGBA8 in `packUnorm4x8` order (red in the low byte).
    pub color: u32,
    /// Unit quaternion `(x, y, z, w)` rotating local axes into world axes.
    pub rotation: [f32; 4],
    /// Semi-axes.
    pub radii: [f32; 3],
    /// Padding to the std430 array stride.
    pub unused: f32,
}

/// One ellipsoid in the compact instance format (GLSL `CompactInstance`, 32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CompactInstance {
    /// Centre relative to the scene origin.
    pub center: [f32; 3],
    /// As [`Instance::color`].
    pub color: u32,
    /// The quaternion as four snorm16: `x | y << 16`, `z | w << 16`.
    pub rotation: [u32; 2],
    /// Three float16 semi-axes in units of [`PushConstants::radius_unit`]: `x | y << 16`,
    /// `z` (the high half unused).
    pub radii: [u32; 2],
}

/// The push constants of every pipeline (GLSL block `PushConstants`, 128 bytes: the most
/// every device allows). Positions are relative to the scene origin.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PushConstants {
    /// The eye relative to the scene origin in view axes, rounded once from float64.
    pub eye_view: [f32; 3],
    /// View depth of the near plane.
    pub near_plane: f32,
    /// Camera right, world axes.
    pub right: [f32; 3],
    /// The shaders' NDC x to the screen plane at unit depth (orthographic: world units):
    /// `W / (2 fx)` (§3.2).
    pub ndc_scale_x: f32,
    /// Camera up, world axes.
    pub up: [f32; 3],
    /// The shaders' NDC y to the screen plane: `H / (2 fy)`.
    pub ndc_scale_y: f32,
    /// View direction, world axes.
    pub forward: [f32; 3],
    /// Depth map `a` of `depth = a + b d + c / d`.
    pub depth_a: f32,
    /// `2 / W`, `2 / H`: NDC units per pixel.
    pub ndc_per_pixel: [f32; 2],
    /// The shaders' NDC minus Vulkan's NDC of the image (y up), from the principal point and
    /// the jitter (`Camera::ndc_shift`); 0 for a centred camera.
    pub ndc_shift: [f32; 2],
    /// Depth map `b`.
    pub depth_b: f32,
    /// Material: ambient weight.
    pub ambient: f32,
    /// Material: diffuse weight.
    pub diffuse: f32,
    /// Material: specular weight.
    pub specular: f32,
    /// Material: colour of highlights.
    pub specular_color: [f32; 3],
    /// Material: Phong exponent.
    pub shininess: f32,
    /// Depth map `c`.
    pub depth_c: f32,
    /// The draw's first instance (scenes beyond one storage-buffer binding are drawn in
    /// chunks, and instance indices in the shaders are chunk-relative).
    pub first_instance: u32,
    /// The compact format's unit of semi-axes.
    pub radius_unit: f32,
    /// Where the camera's pixel `(0, 0)` lies in the attachments: `x | y << 16` (the
    /// fragment stages take it off `gl_FragCoord`).
    pub viewport_origin: u32,
}

/// The culled draw's `VkDrawIndirectCommand`, the chunk's instance count, the frame's stamp
/// and the visible-first splat's `VkDispatchIndirectCommand` (GLSL buffer `IndirectDraw`, 40
/// bytes), which the pre-pass starts from.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct IndirectDraw {
    /// Vertices per instance (the footprint's corners).
    pub vertex_count: u32,
    /// Instances kept (the pre-pass counts them).
    pub instance_count: u32,
    /// Always 0.
    pub first_vertex: u32,
    /// Always 0: instance indices come from the kept list.
    pub first_instance: u32,
    /// Instances in the chunk.
    pub total: u32,
    /// The frame's stamp for the glyph stamps (never 0).
    pub frame: u32,
    /// The stamp of the last frame that stamped the glyphs it showed: those are splatted
    /// first (0: none).
    pub shown: u32,
    /// The visible-first splat's dispatch over the pre-pass's list (the SCAN step writes it):
    /// workgroups in x (a `VkDispatchIndirectCommand` from here on)...
    pub dispatch_x: u32,
    /// ... in y ...
    pub dispatch_y: u32,
    /// ... and in z.
    pub dispatch_z: u32,
}

/// The pre-pass's set-up of one impostor for the vertex stage (GLSL `FootprintRecord`,
/// 32 bytes). Written and read only by shaders; declared here for its size.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FootprintRecord {
    /// Footprint centre (NDC).
    pub centre: [f32; 2],
    /// First axis of the footprint.
    pub axis1: [f32; 2],
    /// Second axis.
    pub axis2: [f32; 2],
    /// Constant depth-buffer value at the nearest point.
    pub quad_z: f32,
    /// `FOOTPRINT_CULLED`, `FOOTPRINT_SCREEN`.
    pub flags: u32,
}

/// The pre-pass's set-up of one impostor for the fragment stage (GLSL `ShadingRecord`,
/// 128 bytes). Written and read only by shaders; declared here for its size.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadingRecord {
    /// Ray per unit of NDC x.
    pub ray_x: [f32; 3],
    /// `r = sqrt(1 - u^2)`.
    pub radius: f32,
    /// Ray per unit of NDC y.
    pub ray_y: [f32; 3],
    /// `u = 1 / |e~|`.
    pub inv_eye_dist: f32,
    /// The projected centre's NDC (0 without offset mode).
    pub ray_origin: [f32; 2],
    /// `cz`.
    pub centre_depth: f32,
    /// Fragment flags.
    pub flags: u32,
    /// Constant ray term (without offset mode).
    pub ray_c: [f32; 3],
    /// `|e~|` (without offset mode).
    pub eye_dist: f32,
    /// `g`: depth = `cz + g.p`.
    pub depth_gradient: [f32; 3],
    /// Padding.
    pub unused: f32,
    /// Frame point to world normal, first column.
    pub to_normal_x: [f32; 3],
    /// Linear red.
    pub color_r: f32,
    /// Second column.
    pub to_normal_y: [f32; 3],
    /// Linear green.
    pub color_g: f32,
    /// Third column.
    pub to_normal_z: [f32; 3],
    /// Linear blue.
    pub color_b: f32,
}

/// Bytes of the visible-first splat's glyph stamps for `glyphs` glyphs (GLSL `GlyphStamps`):
/// per glyph the last frame that showed it and the last frame a splat pass left it to the
/// draw.
pub fn glyph_stamps_bytes(glyphs: u32) -> u64 {
    8 * glyphs as u64
}

/// Side in pixels of the compute splat's resolve tiles (GLSL `RESOLVE_TILE`): the resolve
/// draws one square per tile that a splatted glyph touched, so the pixels no glyph covers
/// cost nothing.
pub const RESOLVE_TILE: u32 = 32;

/// Bytes of the compute splat's visibility buffer for a `width` x `height` image (GLSL
/// `Visibility`): one 64-bit key per pixel, row-major, then one 64-bit word per resolve tile,
/// row-major, saying whether a glyph touched it.
pub fn visibility_bytes(width: u32, height: u32) -> u64 {
    8 * (width as u64 * height as u64 + resolve_tiles(width, height) as u64)
}

/// Resolve tiles of a `width` x `height` image (the resolve draws one instance per tile).
pub fn resolve_tiles(width: u32, height: u32) -> u32 {
    width.div_ceil(RESOLVE_TILE) * height.div_ceil(RESOLVE_TILE)
}

/// The specialization constants of every pipeline (GLSL `layout(constant_id = N)` in
/// `gpu_layout.glsl`; ids in [`SpecConstants::IDS`]). Each stage reads those it declares.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct SpecConstants {
    /// `ORTHOGRAPHIC` (0).
    pub orthographic: vk::Bool32,
    /// `TEXTBOOK` (2): the benchmark's textbook intersection.
    pub textbook: vk::Bool32,
    /// `BOUNDS` (3): `BOUNDS_TIGHT`, `BOUNDS_AXIS_RECT` or `BOUNDS_WORLD_QUAD`.
    pub bounds: u32,
    /// `CORNERS` (4): the footprint polygon's vertices.
    pub corners: u32,
    /// `FAST_NORMAL` (5).
    pub fast_normal: vk::Bool32,
    /// `CULL_FRUSTUM` (6).
    pub cull_frustum: vk::Bool32,
    /// `CULL_PIXEL_CENTRES` (7).
    pub cull_pixel_centres: vk::Bool32,
    /// `CULLED` (8): the draw reads the pre-pass's kept instances.
    pub culled: vk::Bool32,
    /// `CULL_STEP` (9).
    pub cull_step: u32,
    /// `CULL_OCCLUSION` (10).
    pub cull_occlusion: vk::Bool32,
    /// `CULL_SETUP` (11): the pre-pass writes set-up records.
    pub cull_setup: vk::Bool32,
    /// `NO_CAPS` (14).
    pub no_caps: vk::Bool32,
    /// `COMPACT` (15).
    pub compact: vk::Bool32,
    /// `REVERSED_Z` (16): larger depth is nearer (the compute splat keeps the largest).
    pub reversed_z: vk::Bool32,
    /// `SPLAT_FLOOR` (17): 0 the compute splat; the benchmark's floors: 1 only reads every
    /// instance (memory), 2 ray casts every pixel centre without keeping hits (arithmetic).
    pub splat_floor: u32,
    /// `SPLAT_MAX_BOX_PIXELS` (18): the most pixel centres a glyph's box may hold for the
    /// compute splat to walk it; larger glyphs are drawn.
    pub splat_max_box_pixels: u32,
    /// `COVERAGE_SAMPLES` (19): on a multisampled target shaded once per pixel, its sample
    /// count (the fragment stage tests each standard sample position); 1 otherwise.
    pub coverage_samples: u32,
    /// `SAMPLE_GRID` (20): where the culling pre-pass finds a pixel's samples (see
    /// `FramePlan::sample_grid`).
    pub sample_grid: u32,
    /// `FAR_PLANE` (21): the camera has a finite far plane (pixel-rate coverage tests every
    /// sample in full).
    pub far_plane: vk::Bool32,
    /// `COUNT_RAY_CASTS` (22): the compute splat counts its ray casts (the benchmark's
    /// counting frames).
    pub count_ray_casts: vk::Bool32,
    /// `CULL_SELECT` (23): which glyphs CLASSIFY lists (see [`crate::culling::CullSelect`]).
    pub cull_select: u32,
    /// `SPLAT_LIST` (24): the compute splat takes its glyphs from the pre-pass's list.
    pub splat_list: vk::Bool32,
}

impl Default for SpecConstants {
    /// The shaders' own defaults.
    fn default() -> Self {
        Self {
            orthographic: 0,
            textbook: 0,
            bounds: 0,
            corners: 4,
            fast_normal: 0,
            cull_frustum: 1,
            cull_pixel_centres: 1,
            culled: 0,
            cull_step: 1,
            cull_occlusion: 0,
            cull_setup: 0,
            no_caps: 0,
            compact: 0,
            reversed_z: 1,
            splat_floor: 0,
            splat_max_box_pixels: 4096,
            coverage_samples: 1,
            sample_grid: 1,
            far_plane: 0,
            count_ray_casts: 0,
            cull_select: 0,
            splat_list: 0,
        }
    }
}

impl SpecConstants {
    /// `(constant_id, byte offset)` of every field.
    pub const IDS: [(u32, usize); 22] = [
        (0, offset_of!(SpecConstants, orthographic)),
        (2, offset_of!(SpecConstants, textbook)),
        (3, offset_of!(SpecConstants, bounds)),
        (4, offset_of!(SpecConstants, corners)),
        (5, offset_of!(SpecConstants, fast_normal)),
        (6, offset_of!(SpecConstants, cull_frustum)),
        (7, offset_of!(SpecConstants, cull_pixel_centres)),
        (8, offset_of!(SpecConstants, culled)),
        (9, offset_of!(SpecConstants, cull_step)),
        (10, offset_of!(SpecConstants, cull_occlusion)),
        (11, offset_of!(SpecConstants, cull_setup)),
        (14, offset_of!(SpecConstants, no_caps)),
        (15, offset_of!(SpecConstants, compact)),
        (16, offset_of!(SpecConstants, reversed_z)),
        (17, offset_of!(SpecConstants, splat_floor)),
        (18, offset_of!(SpecConstants, splat_max_box_pixels)),
        (19, offset_of!(SpecConstants, coverage_samples)),
        (20, offset_of!(SpecConstants, sample_grid)),
        (21, offset_of!(SpecConstants, far_plane)),
        (22, offset_of!(SpecConstants, count_ray_casts)),
        (23, offset_of!(SpecConstants, cull_select)),
        (24, offset_of!(SpecConstants, splat_list)),
    ];

    /// The map entries of [`SpecConstants::IDS`], for a `VkSpecializationInfo` over
    /// `bytemuck::bytes_of(self)`.
    pub fn map_entries() -> [vk::SpecializationMapEntry; 22] {
        Self::IDS.map(|(constant_id, offset)| vk::SpecializationMapEntry {
            constant_id,
            offset: offset as u32,
            size: 4,
        })
    }
}

// Sizes and offsets the std430 declarations in gpu_layout.glsl give.
const _: () = {
    assert!(size_of::<Instance>() == 48);
    assert!(offset_of!(Instance, color) == 12);
    assert!(offset_of!(Instance, rotation) == 16);
    assert!(offset_of!(Instance, radii) == 32);
    assert!(size_of::<CompactInstance>() == 32);
    assert!(offset_of!(CompactInstance, rotation) == 16);
    assert!(offset_of!(CompactInstance, radii) == 24);
    assert!(size_of::<PushConstants>() == 128);
    assert!(offset_of!(PushConstants, right) == 16);
    assert!(offset_of!(PushConstants, up) == 32);
    assert!(offset_of!(PushConstants, forward) == 48);
    assert!(offset_of!(PushConstants, ndc_per_pixel) == 64);
    assert!(offset_of!(PushConstants, ndc_shift) == 72);
    assert!(offset_of!(PushConstants, ambient) == 84);
    assert!(offset_of!(PushConstants, specular_color) == 96);
    assert!(offset_of!(PushConstants, shininess) == 108);
    assert!(offset_of!(PushConstants, first_instance) == 116);
    assert!(offset_of!(PushConstants, viewport_origin) == 124);
    assert!(size_of::<IndirectDraw>() == 40);
    assert!(offset_of!(IndirectDraw, dispatch_x) == 28);
    assert!(size_of::<FootprintRecord>() == 32);
    assert!(offset_of!(FootprintRecord, quad_z) == 24);
    assert!(size_of::<ShadingRecord>() == 128);
    assert!(offset_of!(ShadingRecord, ray_origin) == 32);
    assert!(offset_of!(ShadingRecord, ray_c) == 48);
    assert!(offset_of!(ShadingRecord, depth_gradient) == 64);
    assert!(offset_of!(ShadingRecord, to_normal_x) == 80);
    assert!(size_of::<SpecConstants>() == 88);
};
