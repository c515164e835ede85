//! Every layout the CPU shares with the shaders, as `#[repr(C)]` plain-old-data types whose
//! sizes and field offsets are checked at compile time. `glsl/include/gpu_layout.glsl`
//! declares the same structs with the same field names (std430; every shader includes it through
//! `ellipsoid_common.glsl`); change both together. Scalars are 4 bytes and native-endian
//! (little-endian on every supported target).
//!
//! The mirror is checked on the compiled shaders (`src/spirv_mirror/`, a unit test): each struct
//! of `gpu_layout.glsl` must have a Rust type in the test's table (`rust_layouts.rs`, whose
//! fields must tile the type without a gap) and, wherever a shader lays it out, the same member
//! names in the same order at the same offsets with the same sizes, and an array stride or block
//! size equal to `size_of`; each specialization constant the same `constant_id` in
//! [`SpecConstants::map_entries`] as the field of its name (`CORNERS` and `corners`), the same
//! width and the same default as `SpecConstants::default()`; each storage buffer a binding of
//! set 0 that `Binding` (`src/renderer/buffers.rs`, which holds the table of bindings) has as a
//! storage buffer, a block named as the variant (or one of the few other views listed in the
//! test), and, where the stage uses it, that stage in `Binding::stages`; each uniform texel
//! buffer one of the set's two texel views by binding and name; the instance records, which
//! no shader lays out (they are read as texels), at the byte offsets of a table copied by hand
//! from `load_instance` (a drift on the shader's side shows in the drawing tests instead); and
//! each compute shader the workgroup size
//! its dispatches are counted in. A drift on either side fails `cargo test`, whatever the GPU.
//!
//! `GlyphStamps` (binding 10), 8 bytes per glyph of the chunk: the stamp of the last frame that
//! showed it (MARK_SHOWN) and of the last frame a splat pass left it to the draw (design §5.7).
//! `FloorPixels` (binding 9, `research` use, host-visible): the visible-pixel floor's lists
//! (design §5.7).
//!
//! Without set-up once, the set-up travels as flat varyings (`impostor_vert.glsl`): location 0
//! `ray_x`, 10 `ray_y`, 11 `ray_c`, 12 `ray_origin`, 1 `k`, 2 `depth` (`g`, `cz`), 3 `misc` (`u`,
//! `|e~|`, `r^2`, depth scale), 4-6 `to_normal`, 7 `id`, 8 `flags`, 9 linear colour. The
//! `SETUP_ONCE` vertex stage passes location 7 `id` only.
//!
//! Compile-time variants: `build.rs` defines `AUX_OUTPUTS` and (with `research`) `COUNT_FRAGMENTS`
//! for fragment shaders (design §2.4); `SETUP_ONCE` (`ellipsoid_setup_once.vert`, `.frag`), `FLAT_DEPTH`
//! (`research/ellipsoid_flat_depth.frag`), `CULL_PASS` (`cull.comp`), `SPLAT_PASS`
//! (`splat.comp`) and `VISIBILITY_WRITER` (`research/ellipsoid_visibility.frag`; with
//! `SPLAT_PASS` it makes the visibility buffer writable) are defined by the shader files that
//! select them.

use std::mem::{offset_of, size_of};

use ash::vk;
use bytemuck::{Pod, Zeroable};

/// One ellipsoid in the full instance format (GLSL `Instance`, 48 bytes).
///
/// Written by `pack_relative` in `src/instances.rs`; read by `load_instance` in
/// `glsl/include/ellipsoid_common.glsl`, which returns an `Instance` for either format.
///
/// | offset | field | Rust / GLSL type | meaning |
/// |---:|---|---|---|
/// | 0 | `center` | `[f32; 3]` / `vec3` | centre relative to the scene origin (design §4.1) |
/// | 12 | `color` | `u32` / `uint` | sRGB RGBA8, `packUnorm4x8` order (R in the low byte), A = 255 |
/// | 16 | `rotation` | `[f32; 4]` / `vec4` | unit quaternion `(x, y, z, w)`, local axes to world; identity for spheres |
/// | 32 | `radii` | `[f32; 3]` / `vec3` | semi-axes |
/// | 44 | `unused` | `f32` / `float` | 0; pads to the 48-byte array stride |
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
///
/// | offset | field | Rust / GLSL type | meaning |
/// |---:|---|---|---|
/// | 0 | `center` | `[f32; 3]` / `vec3` | as above |
/// | 12 | `color` | `u32` / `uint` | as above |
/// | 16 | `rotation` | `[u32; 2]` / `uvec2` | the quaternion as four snorm16: `x \| y << 16`, `z \| w << 16`; renormalised after unpacking |
/// | 24 | `radii` | `[u32; 2]` / `uvec2` | three float16 semi-axes in units of `PushConstants::radius_unit` (the scene's largest semi-axis): `x \| y << 16`, `z` (high half unused) |
///
/// The compact format moves the surface by at most about `2^-11` of a semi-axis (float16
/// rounding) plus `2^-15` rad of rotation; packing refuses semi-axes outside float16's range
/// relative to the largest.
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
///
/// Written by `push_constants` in `src/renderer/push.rs` (one per chunk), read as `cam` (the block
/// `PushConstants` in `gpu_layout.glsl`). The graphics pipeline layout declares the range for the
/// vertex and fragment stages (`DRAW_PUSH_STAGES`); the pre-pass has its own layout with a
/// compute-only range (`src/renderer/pipelines.rs`: lavapipe 22.3.6 crashes dispatching with a
/// range shared between graphics and compute stages).
///
/// | offset | field | type | meaning |
/// |---:|---|---|---|
/// | 0 | `eye_view` | `vec3` | `V`, the eye relative to the scene origin in view axes, rounded once from float64 (design §4.1) |
/// | 12 | `near_plane` | `float` | `near` |
/// | 16 | `right` | `vec3` | `r` |
/// | 28 | `ndc_scale_x` | `float` | `sx` (design §3.2) |
/// | 32 | `up` | `vec3` | `u` |
/// | 44 | `ndc_scale_y` | `float` | `sy` |
/// | 48 | `forward` | `vec3` | `f` |
/// | 60 | `depth_a` | `float` | depth map `a` (design §3.4) |
/// | 64 | `ndc_per_pixel` | `vec2` | `2/W`, `2/H` (the shaders' `image_size()` recovers `W`, `H` by rounding `2 / ndc_per_pixel`) |
/// | 72 | `ndc_shift` | `vec2` | the principal point's and the jitter's shift of the shaders' NDC (design §3.2, `Camera::ndc_shift`); 0 for a centred camera |
/// | 80 | `depth_b` | `float` | depth map `b` |
/// | 84 | `ambient` | `float` | `Material::ambient` (design §4.8) |
/// | 88 | `diffuse` | `float` | `Material::diffuse` |
/// | 92 | `specular` | `float` | `Material::specular` |
/// | 96 | `specular_color` | `vec3` | `Material::specular_color` |
/// | 108 | `shininess` | `float` | `Material::shininess` |
/// | 112 | `depth_c` | `float` | depth map `c` |
/// | 116 | `first_instance` | `uint` | the chunk's first instance (design §5.4) |
/// | 120 | `radius_unit` | `float` | the compact format's unit of semi-axes (`CompactInstance`) |
/// | 124 | `viewport_origin` | `uint` | the attachment pixel of the camera's pixel (0, 0) (design §3.1), `x \| y << 16`; the fragment stages subtract it from `gl_FragCoord` (`camera_pixel`) |
///
/// The footprint margin (`QUAD_MARGIN_PX` = 0.01 pixels, design §5.1) is a GLSL constant in
/// `ellipsoid_common.glsl`, not a push constant.
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
    /// `W / (2 fx)` (design §3.2).
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
///
/// `IndirectDraw` (binding 3), 40 bytes: a `VkDrawIndirectCommand` (`vertex_count`,
/// `instance_count`, `first_vertex`, `first_instance`) followed by `total`, the chunk's instance
/// count, `frame` (the pre-pass's stamp, never 0), `shown` (the stamp of the last frame that
/// stamped what it showed; 0 none) and a `VkDispatchIndirectCommand` (`dispatch_x`, `dispatch_y`,
/// `dispatch_z` at offset 28: three words, since a `uvec3` would start at the next multiple of
/// 16 bytes). The pre-pass writes it from the CPU's struct with `vkCmdUpdateBuffer`
/// (`instance_count = 0`), and SCAN writes `instance_count` and the dispatch (the splat's
/// workgroups of 64 over the list); one per chunk at `256 k` (`SLICE_ALIGN`). GLSL declares it as
/// a buffer block in `gpu_layout.glsl` (every stage sees it; only the compute shaders use it).
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
///
/// Written by `store_setup` (`cull.comp` with `CULL_SETUP`) and read by the `SETUP_ONCE` builds
/// (`load_footprint` in the vertex stage, `load_setup` and `load_shading` in the fragment stage),
/// at the instance's chunk-relative index; the GLSL side is in `glsl/include/setup_records.glsl`,
/// the buffers are sized from `size_of::<FootprintRecord>()` and `size_of::<ShadingRecord>()`
/// (`src/renderer/mod.rs`, `descriptors.rs`). Shaders alone write and read them; the Rust types
/// exist for their sizes.
///
/// Binding 7.
///
/// | offset | field | type | meaning |
/// |---:|---|---|---|
/// | 0 | `centre` | `vec2` | footprint centre (NDC) |
/// | 8 | `axis1` | `vec2` | first axis: corners are `centre + dir.x axis1 + dir.y axis2` |
/// | 16 | `axis2` | `vec2` | second axis |
/// | 24 | `quad_z` | `float` | the constant depth-buffer value at the nearest point (design §4.7) |
/// | 28 | `flags` | `uint` | bits: 1 `FOOTPRINT_CULLED`, 2 `FOOTPRINT_SCREEN` (the whole screen's polygon) |
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
///
/// `ShadingRecord` (binding 6), 128 bytes; in perspective offset mode (design §4.3) the hit and its depth
/// need the first 48 bytes only:
///
/// | offset | field | type | meaning |
/// |---:|---|---|---|
/// | 0 | `ray_x` | `vec3` | ray per unit of NDC x |
/// | 12 | `radius` | `float` | `r = sqrt(1 - u^2)` |
/// | 16 | `ray_y` | `vec3` | ray per unit of NDC y |
/// | 28 | `inv_eye_dist` | `float` | `u = 1/\|e~\|` |
/// | 32 | `ray_origin` | `vec2` | `o`, the projected centre's NDC (0 without offset mode) |
/// | 40 | `centre_depth` | `float` | `cz` |
/// | 44 | `flags` | `uint` | bits: 1 `FLAG_EYE_INSIDE`, 2 `FLAG_MAY_CAP`, 4 `FLAG_OFFSET_ORIGIN` (offset mode: `ray_c` is 0 and not read) |
/// | 48 | `ray_c` | `vec3` | constant ray term (read only without offset mode) |
/// | 60 | `eye_dist` | `float` | `\|e~\|`, the eye's distance from the centre in parameter space (likewise) |
/// | 64 | `depth_gradient` | `vec3` | `g` of `depth = cz + g.p` (read only by orthographic depth) |
/// | 76 | `unused` | `float` | 0 |
/// | 80 | `to_normal_x` | `vec3` | frame point to world normal, column 0 |
/// | 92 | `color_r` | `float` | linear colour, red |
/// | 96 | `to_normal_y` | `vec3` | column 1 |
/// | 108 | `color_g` | `float` | green |
/// | 112 | `to_normal_z` | `vec3` | column 2 |
/// | 124 | `color_b` | `float` | blue |
///
/// The fragment stage derives `k`, `r^2` and the depth scale from these with the same operations
/// as `instance_setup.glsl` (design §5.3), and loads `to_normal_*` and `color_*` only for fragments that
/// hit.
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
///
/// `SpecConstants` in `src/gpu_layout.rs`: one 4-byte field per constant (`vk::Bool32` or `u32`),
/// 88 bytes; `SpecConstants::IDS` pairs each `constant_id` with its field's offset, and
/// `map_entries()` turns that into the `VkSpecializationMapEntry` list. `PipelineKey` and
/// `CullKey` and `SplatKey` (`src/renderer/pipelines/keys.rs`, each derived from the frame plan) fill in the constants of a graphics pipeline and of a pre-pass
/// step (the rest keep the shaders' defaults, which `SpecConstants::default()` repeats), and every
/// stage receives the whole set. `gpu_layout.glsl` declares them all; each stage reads those it
/// needs. IDs 1, 12 and 13 are unused.
///
/// | id | GLSL | field | type | default | meaning | set by |
/// |---:|---|---|---|---|---|---|
/// | 0 | `ORTHOGRAPHIC` | `orthographic` | bool | false | orthographic camera | graphics, pre-pass |
/// | 2 | `TEXTBOOK` | `textbook` | bool | false | textbook intersection (`research`) | graphics, pre-pass set-up |
/// | 3 | `BOUNDS` | `bounds` | int | 0 | `BOUNDS_TIGHT` (n-gon), `BOUNDS_AXIS_RECT`, `BOUNDS_WORLD_QUAD` | graphics, pre-pass set-up |
/// | 4 | `CORNERS` | `corners` | int | 4 | footprint vertices: 3, 4, 6 or 8 | graphics, pre-pass set-up |
/// | 5 | `FAST_NORMAL` | `fast_normal` | bool | false | modulus-normalised normal (`research`) | graphics |
/// | 6 | `CULL_FRUSTUM` | `cull_frustum` | bool | true | frustum culling | pre-pass |
/// | 7 | `CULL_PIXEL_CENTRES` | `cull_pixel_centres` | bool | true | pixel-centre culling | pre-pass |
/// | 8 | `CULLED` | `culled` | bool | false | the draw reads the visible list | graphics |
/// | 9 | `CULL_STEP` | `cull_step` | int | 1 | 0 OCCLUDERS, 1 CLASSIFY, 2 SCAN, 3 SCATTER, 4 KEY_TILES, 5 MARK_SHOWN (design §5.7) | pre-pass |
/// | 10 | `CULL_OCCLUSION` | `cull_occlusion` | bool | false | occlusion culling | pre-pass |
/// | 11 | `CULL_SETUP` | `cull_setup` | bool | false | CLASSIFY stores the set-up | pre-pass |
/// | 14 | `NO_CAPS` | `no_caps` | bool | false | nothing reaches in front of the near plane | graphics |
/// | 15 | `COMPACT` | `compact` | bool | false | 32-byte instances | graphics, pre-pass |
/// | 16 | `REVERSED_Z` | `reversed_z` | bool | true | larger depth is nearer (the splat keeps the largest key; the visible-first steps read keys) | graphics, splat, pre-pass |
/// | 17 | `SPLAT_FLOOR` | `splat_floor` | int | 0 | the benchmark's roofline: 1 only reads every instance, 2 ray casts without atomics, 3 ray casts only the pixels each glyph shows (`research`) | splat |
/// | 18 | `SPLAT_MAX_BOX_PIXELS` | `splat_max_box_pixels` | int | 4096 | the most pixel centres a glyph's box may hold for the splat to walk it (the splat path's `max_box_pixels`) | splat |
/// | 19 | `COVERAGE_SAMPLES` | `coverage_samples` | int | 1 | on a multisampled target shaded once per pixel, its sample count: the fragment stage tests each standard sample position and writes `gl_SampleMask` (`FramePlan::coverage_samples`, `Target`'s documentation) | graphics |
/// | 20 | `SAMPLE_GRID` | `sample_grid` | int | 1 | where the culling proofs find a pixel's samples: 1 its centre, R the cell centres of a grid R times finer, 0 anywhere (`FramePlan::sample_grid`, design §5.3) | pre-pass |
/// | 21 | `FAR_PLANE` | `far_plane` | bool | false | the camera has a finite far plane: pixel-rate coverage runs the full hit at every sample (`FramePlan::far_plane`, `Target`'s documentation); set only with `COVERAGE_SAMPLES` above 1 | graphics |
/// | 22 | `COUNT_RAY_CASTS` | `count_ray_casts` | bool | false | the splat adds its ray casts to the counter's second word (`research` counting frames, design §5.7) | splat |
/// | 23 | `CULL_SELECT` | `cull_select` | int | 0 | what CLASSIFY lists: 0 all its culling keeps, 1 `SHOWN`, 2 `REST`, 3 `DRAWN` (`CullSelect`, design §5.7); in the splat over a list, which list it walks (`REST` skips the tiles the first pass hides) | pre-pass, splat |
/// | 24 | `SPLAT_LIST` | `splat_list` | bool | false | the splat takes its glyphs from the pre-pass's list and leaves large ones to the draw by their stamp (design §5.7) | splat |
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
    /// `SPLAT_SETUP_ONCE` (25): the compute splat stores each glyph's shading set-up, and its
    /// resolve reads it instead of setting the pixel's glyph up again.
    pub splat_setup_once: vk::Bool32,
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
            splat_setup_once: 0,
        }
    }
}

impl SpecConstants {
    /// `(constant_id, byte offset)` of every field.
    pub const IDS: [(u32, usize); 23] = [
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
        (25, offset_of!(SpecConstants, splat_setup_once)),
    ];

    /// The map entries of [`SpecConstants::IDS`], for a `VkSpecializationInfo` over
    /// `bytemuck::bytes_of(self)`.
    pub fn map_entries() -> [vk::SpecializationMapEntry; 23] {
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
    assert!(size_of::<SpecConstants>() == 92);
};
