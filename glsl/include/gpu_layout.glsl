// Every layout shared by the CPU and the shaders: push constants, instance records, set-up
// records, the indirect draw and the specialization constants. `src/gpu_layout.rs` declares
// the same structs with the same field names (#[repr(C)], sizes and offsets checked there);
// change both together.

// Push constants (`PushConstants`, 128 bytes: the most every device allows). Positions are
// relative to the scene origin; the eye arrives already in view axes (rounded once from
// float64), so float32 never subtracts two large nearly equal positions.
layout(push_constant, std430) uniform PushConstants {
    vec3 eye_view;          // the eye relative to the scene origin, in view axes
    float near_plane;       // view depth of the near plane
    vec3 right;             // camera right, world axes
    float ndc_scale_x;      // the shaders' NDC x -> screen plane: W / (2 fx) (§3.2)
    vec3 up;                // camera up
    float ndc_scale_y;      // the shaders' NDC y -> screen plane: H / (2 fy)
    vec3 forward;           // view direction
    float depth_a;          // depth map a (depth = a + b d + c / d, src/depth.rs)
    vec2 ndc_per_pixel;     // 2/W, 2/H
    vec2 ndc_shift;         // the shaders' NDC minus Vulkan's (y up): principal point, jitter
    float depth_b;          // depth map b
    float ambient;          // material (Blinn-Phong)
    float diffuse;
    float specular;
    vec3 specular_color;
    float shininess;
    float depth_c;          // depth map c
    uint first_instance;    // the draw's first instance: scenes beyond one binding are drawn
                            // in chunks, and shader instance indices are chunk-relative
    float radius_unit;      // the compact format's unit of semi-axes
    uint viewport_origin;   // the camera's pixel (0, 0) in the attachments: x | y << 16
} cam;

// The full instance record (`Instance`, 48 bytes).
struct Instance {
    vec3 center;            // relative to the scene origin
    uint color;             // sRGB-encoded RGBA8, packUnorm4x8 order
    vec4 rotation;          // unit quaternion (x, y, z, w): local axes -> world
    vec3 radii;             // semi-axes
    float unused;
};

// The compact instance record (`CompactInstance`, 32 bytes). Both records are read as 16-byte
// texels (`load_instance` in ellipsoid_common.glsl unpacks them field by field).
struct CompactInstance {
    vec3 center;            // as in Instance
    uint color;
    uvec2 rotation;         // the quaternion as 4 x snorm16 (x, y | z, w)
    uvec2 radii;            // 3 x float16 in units of cam.radius_unit (x, y | z, unused)
};

// The pre-pass's set-up of one impostor for the vertex stage (`FootprintRecord`, 32 bytes).
struct FootprintRecord {
    vec2 centre;            // footprint: centre + dir.x axis1 + dir.y axis2
    vec2 axis1;
    vec2 axis2;
    float quad_z;           // constant depth-buffer value at the nearest point
    uint flags;             // FOOTPRINT_CULLED, FOOTPRINT_SCREEN
};

// The pre-pass's set-up of one impostor for the fragment stage (`ShadingRecord`, 128 bytes:
// a million instances fit the 128 MiB storage-buffer range every device supports).
struct ShadingRecord {
    vec3 ray_x;             // ray = ray_x (ndc.x - o.x) + ray_y (ndc.y - o.y) + ray_c
    float radius;           // r = sqrt(1 - u^2)
    vec3 ray_y;
    float inv_eye_dist;     // u = 1 / |e~|
    vec2 ray_origin;        // o: the projected centre's NDC (0 without offset mode)
    float centre_depth;     // cz
    uint flags;             // FLAG_* of instance_setup, FLAG_OFFSET_ORIGIN
    vec3 ray_c;             // read only without FLAG_OFFSET_ORIGIN
    float eye_dist;         // |e~|, likewise
    vec3 depth_gradient;    // g: depth = cz + g.p (orthographic depth reads it)
    float unused;
    vec3 to_normal_x;       // frame point -> world normal (unnormalised), by column
    float color_r;          // linear colour
    vec3 to_normal_y;
    float color_g;
    vec3 to_normal_z;
    float color_b;
};

// Specialization constants (`SpecConstants`): chosen when a pipeline is built. Every stage
// declares all of them; each reads those it needs.
layout(constant_id = 0) const bool ORTHOGRAPHIC = false;
layout(constant_id = 2) const bool TEXTBOOK = false;       // benchmark baseline intersection
// Footprint of an instance on screen.
const int BOUNDS_TIGHT = 0;      // n-gon around the projected ellipse (4 corners: its oriented box)
const int BOUNDS_AXIS_RECT = 1;  // the projected ellipse's axis-aligned bounding rectangle
const int BOUNDS_WORLD_QUAD = 2; // Gumhold's square in the silhouette plane
layout(constant_id = 3) const int BOUNDS = BOUNDS_TIGHT;
layout(constant_id = 4) const int CORNERS = 4;
layout(constant_id = 5) const bool FAST_NORMAL = false;    // modulus-normalised gradient
layout(constant_id = 6) const bool CULL_FRUSTUM = true;
layout(constant_id = 7) const bool CULL_PIXEL_CENTRES = true;
// The draw reads instance indices compacted by the culling pre-pass (cull.comp).
layout(constant_id = 8) const bool CULLED = false;
layout(constant_id = 9) const int CULL_STEP = 1;
layout(constant_id = 10) const bool CULL_OCCLUSION = false;
layout(constant_id = 11) const bool CULL_SETUP = false;    // the pre-pass writes set-up records
layout(constant_id = 14) const bool NO_CAPS = false;       // nothing reaches the near plane
layout(constant_id = 15) const bool COMPACT = false;       // instances are CompactInstance
layout(constant_id = 16) const bool REVERSED_Z = true;     // larger depth is nearer
// The benchmark's floors of the compute splat: 1 reads every instance and nothing else, 2 ray
// casts every pixel centre but keeps no hit, 3 ray casts only the pixels each glyph shows
// (given by the host), each once, and keeps no hit.
const int SPLAT_FLOOR_NONE = 0;
const int SPLAT_FLOOR_MEMORY = 1;
const int SPLAT_FLOOR_ARITHMETIC = 2;
const int SPLAT_FLOOR_VISIBLE = 3;
layout(constant_id = 17) const int SPLAT_FLOOR = SPLAT_FLOOR_NONE;
// The most pixel centres a glyph's box may hold for the compute splat to walk it (one
// invocation walks each glyph, so a larger one would hold up its workgroup); larger glyphs
// are drawn. From `FramePlan::splat_max_box_pixels`.
layout(constant_id = 18) const int SPLAT_MAX_BOX_PIXELS = 4096;
// On a multisampled target shaded once per pixel, its sample count: the fragment stage tests
// each standard sample position against the glyph and writes gl_SampleMask. 1 otherwise
// (single-sample targets, and sample-rate shading, where each sample runs the stage).
layout(constant_id = 19) const int COVERAGE_SAMPLES = 1;
// Where the culling pre-pass finds a pixel's samples: 1 the pixel centre (one sample); R > 1
// the cell centres of a grid R times finer than the pixels (the standard locations of 2, 4
// and 8 samples); 0 anywhere in the pixel.
layout(constant_id = 20) const int SAMPLE_GRID = 1;
// The camera has a finite far plane, which may cut a glyph inside a pixel: pixel-rate
// coverage tests every sample in full.
layout(constant_id = 21) const bool FAR_PLANE = false;
// The benchmark's counting frames: the compute splat adds its ray casts to the second word of
// the fragment counter (binding 1).
layout(constant_id = 22) const bool COUNT_RAY_CASTS = false;
// Which glyphs the pre-pass's CLASSIFY step lists (`CullSelect`): 0 every glyph its culling
// keeps; 1 those the last stamping frame showed (the visible-first splat's first pass, for a
// still camera); 2 the others
// its culling keeps, occlusion by the first pass's hits included (the second pass); 3 those a
// splat pass of this frame left to the draw. In the compute splat over a list, which list it
// walks (the second pass skips the tiles the first pass hides).
const int CULL_SELECT_ALL = 0;
const int CULL_SELECT_SHOWN = 1;
const int CULL_SELECT_REST = 2;
const int CULL_SELECT_DRAWN = 3;
layout(constant_id = 23) const int CULL_SELECT = CULL_SELECT_ALL;
// The compute splat takes its glyphs from the pre-pass's list (the visible-first splat's
// passes) instead of the whole chunk, and leaves glyphs to the draw by their stamp.
layout(constant_id = 24) const bool SPLAT_LIST = false;
// The compute splat stores the shading set-up of each glyph with a hit (binding 6), and its
// resolve reads it (binding 14) instead of setting the pixel's glyph up again.
layout(constant_id = 25) const bool SPLAT_SETUP_ONCE = false;

#if defined(CULL_PASS) || defined(SPLAT_PASS)
#define INDIRECT_DRAW_ACCESS
#else
#define INDIRECT_DRAW_ACCESS readonly
#endif
// The culled draw's `VkDrawIndirectCommand`, the number of instances in the chunk, the frame's
// stamps and the visible-first splat's `VkDispatchIndirectCommand` (`IndirectDraw`, 40 bytes).
layout(std430, set = 0, binding = 3) INDIRECT_DRAW_ACCESS buffer IndirectDraw {
    uint vertex_count;
    uint instance_count;
    uint first_vertex;
    uint first_instance;
    uint total;
    uint frame;             // the frame's stamp (never 0), for the glyph stamps
    uint shown;             // the stamp of the frame whose shown glyphs go first (0: none)
    uint dispatch_x;        // the splat pass over the list: (x, y, 1) workgroups (three
    uint dispatch_y;        // words: a uvec3 would sit at the next multiple of 16 bytes)
    uint dispatch_z;
};
