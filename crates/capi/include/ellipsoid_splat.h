/*
 * ellipsoid-splat: exact ray-cast ellipsoids on the host's Vulkan device -- the C ABI.
 *
 * Every function but es_abi_version and es_last_error returns an EsStatus (ES_STATUS_SUCCESS =
 * 0); es_last_error() gives the message of the last failure on the calling thread. A panic
 * never unwinds into the caller. Option structs begin with struct_size: set it to sizeof the
 * struct. Nothing the host passes in is destroyed by the library. A renderer is used by one
 * thread at a time. The rules:
 * docs/c-and-cpp.md of the ellipsoid-splat repository.
 */

#ifndef ELLIPSOID_SPLAT_H
#define ELLIPSOID_SPLAT_H

/* Generated from crates/capi/src by cbindgen (crates/capi/tests/header.rs). Do not edit. */

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <vulkan/vulkan.h>

/**
 * The ABI's version: it changes whenever a function, struct or constant changes in a way a
 * host compiled against the old header would break on. The shared library's soname carries
 * it (`libellipsoid_splat.so.2`). Version 2: `EsSettings` and `EsFramePlan` grew (the plan's
 * mode; the path taken and why), and `es_settings_default`, `es_renderer_plan` write them
 * whole.
 */
#define ES_ABI_VERSION 2

/**
 * `maintenance4` (Vulkan 1.3): every target needs it.
 */
#define ES_FEATURE_MAINTENANCE4 1

/**
 * `dynamicRendering` (Vulkan 1.3): targets drawn with dynamic rendering need it.
 */
#define ES_FEATURE_DYNAMIC_RENDERING 2

/**
 * `sampleRateShading`: multisampled targets need it.
 */
#define ES_FEATURE_SAMPLE_RATE_SHADING 4

/**
 * `shaderInt64`: with the next, lets frames of many small glyphs take the compute splat.
 */
#define ES_FEATURE_SHADER_INT64 8

/**
 * `shaderBufferInt64Atomics` (Vulkan 1.2): with the previous, the compute splat.
 */
#define ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS 16

/**
 * The `id` of a pixel where no glyph is hit.
 */
#define ES_NO_GLYPH UINT32_MAX

/**
 * What a call did.
 */
typedef enum EsStatus {
  /**
   * It succeeded.
   */
  ES_STATUS_SUCCESS = 0,
  /**
   * An argument was null, out of range or inconsistent (the message names which).
   */
  ES_STATUS_ERROR_INVALID_ARGUMENT = 1,
  /**
   * The device lacks a feature or format the call needs, or the host did not enable it.
   */
  ES_STATUS_ERROR_UNSUPPORTED = 2,
  /**
   * A Vulkan call (or the host's allocator callback) failed.
   */
  ES_STATUS_ERROR_VULKAN = 3,
  /**
   * Device or host memory ran out while the renderer made what the message names. The
   * call changed nothing: the renderer stays usable (docs/c-and-cpp.md, "Errors").
   */
  ES_STATUS_ERROR_OUT_OF_MEMORY = 4,
  /**
   * The device was lost (the message names the call that reported it): wait for the
   * device to be idle, destroy the renderer and make a new device (docs/c-and-cpp.md,
   * "Errors").
   */
  ES_STATUS_ERROR_DEVICE_LOST = 5,
  /**
   * The library panicked (a bug): the renderer refuses every call but its destruction.
   */
  ES_STATUS_ERROR_PANIC = 6,
  /**
   * Any other failure (the message says what).
   */
  ES_STATUS_ERROR_OTHER = 7,
  /**
   * Another process of the communicator failed (its own call reports why; the message
   * names its rank): nothing was composited. Only `es_offscreen_render_composited`.
   */
  ES_STATUS_ERROR_OTHER_RANK = 8,
} EsStatus;

/**
 * What a buffer's memory is for.
 */
typedef enum EsMemoryUse {
  /**
   * Read and written by the GPU only: device-local where the device has it.
   */
  ES_MEMORY_USE_GPU_ONLY = 0,
  /**
   * Written by the CPU, read by the GPU: host-visible, host-coherent, mapped for as long
   * as the buffer lives.
   */
  ES_MEMORY_USE_UPLOAD = 1,
  /**
   * Written by the GPU, read by the CPU: host-visible, host-coherent, mapped.
   */
  ES_MEMORY_USE_READBACK = 2,
} EsMemoryUse;

/**
 * How the view volume is shaped.
 */
typedef enum EsProjection {
  /**
   * A pinhole with `fov_y_deg`, centred, square pixels.
   */
  ES_PROJECTION_PERSPECTIVE = 0,
  /**
   * Parallel rays through a centred window `ortho_height` high, square pixels.
   */
  ES_PROJECTION_ORTHOGRAPHIC = 1,
  /**
   * A pinhole with `intrinsics` (OpenCV's `fx, fy, cx, cy` in pixels).
   */
  ES_PROJECTION_PERSPECTIVE_INTRINSICS = 2,
  /**
   * Parallel rays with `intrinsics` (`fx`, `fy` in pixels per world unit).
   */
  ES_PROJECTION_ORTHOGRAPHIC_INTRINSICS = 3,
} EsProjection;

/**
 * How the frame plan chooses among the exact paths that can serve a frame (each draws the
 * same picture; they differ in cost).
 */
typedef enum EsPlanMode {
  /**
   * First a guess from the scene's size on screen, then the candidate paths timed on
   * frames the renderer draws anyway, a few frames each; the fastest is kept per scene
   * class (`es_renderer_plan_wisdom` saves what was learned). Where the queue family has
   * no timestamps it plans as `ES_PLAN_MODE_ESTIMATE`. The default.
   */
  ES_PLAN_MODE_MEASURE = 0,
  /**
   * The first guess alone: the same path for the same scene and camera every time.
   */
  ES_PLAN_MODE_ESTIMATE = 1,
  /**
   * The path `fixed_path` names wherever it can serve the frame; otherwise the draw.
   */
  ES_PLAN_MODE_FIXED = 2,
} EsPlanMode;

/**
 * A kind of exact path a frame can take.
 */
typedef enum EsPathKind {
  /**
   * No path: in `EsSettings.fixed_path` when no path is fixed, in
   * `EsFramePlan.runner_up` when no other candidate was timed.
   */
  ES_PATH_KIND_NONE = 0,
  /**
   * Every glyph rasterized as an impostor (after a pre-pass where it culls or sets up).
   */
  ES_PATH_KIND_DRAW = 1,
  /**
   * The compute splat: the glyphs ray cast into a visibility buffer and shaded by a
   * resolve in the host's pass; glyphs too large for it are drawn in the same frame.
   */
  ES_PATH_KIND_SPLAT = 2,
  /**
   * The compute splat, the glyphs the last frame showed first, the camera still or moving
   * (its first frame after an upload stamps what it shows).
   */
  ES_PATH_KIND_VISIBLE_FIRST = 3,
} EsPathKind;

/**
 * Which glyphs a splatted frame ray casts first, and what it leaves out.
 */
typedef enum EsHiddenLayers {
  /**
   * The frame draws every glyph: nothing is splatted.
   */
  ES_HIDDEN_LAYERS_NONE = 0,
  /**
   * Every glyph is splatted, hidden ones too.
   */
  ES_HIDDEN_LAYERS_SPLAT_ALL = 1,
  /**
   * Every glyph is splatted, and those the frame shows are stamped so that the next frame
   * can splat them first (the visible-first splat's first frame after an upload).
   */
  ES_HIDDEN_LAYERS_STAMP_SHOWN = 2,
  /**
   * The glyphs the last stamping frame showed are splatted first, then of the rest only those
   * their hits do not hide.
   */
  ES_HIDDEN_LAYERS_VISIBLE_FIRST = 3,
} EsHiddenLayers;

/**
 * Why a frame takes its path.
 */
typedef enum EsPlanReasonKind {
  /**
   * The draw is the only path that can serve the frame (`drawn_because` says why).
   */
  ES_PLAN_REASON_KIND_ONLY = 0,
  /**
   * The host fixed the path (`ES_PLAN_MODE_FIXED`).
   */
  ES_PLAN_REASON_KIND_FIXED = 1,
  /**
   * The first guess from the scene's size on screen (before measuring, or with
   * `ES_PLAN_MODE_ESTIMATE`).
   */
  ES_PLAN_REASON_KIND_ESTIMATED = 2,
  /**
   * A candidate timed while the plan learns this scene class.
   */
  ES_PLAN_REASON_KIND_EXPLORING = 3,
  /**
   * The fastest candidate measured for this scene class on this device (`measured_ms`,
   * `runner_up`, `runner_up_ms`).
   */
  ES_PLAN_REASON_KIND_MEASURED = 4,
} EsPlanReasonKind;

/**
 * An offscreen renderer: opaque to the host.
 */
typedef struct EsOffscreenRenderer EsOffscreenRenderer;

/**
 * A renderer: opaque to the host.
 */
typedef struct EsRenderer EsRenderer;

/**
 * A viewport as the host gives `vkCmdSetViewport` (whole pixels, depth range [0, 1]); a
 * negative `height` flips it (`y` is then its bottom edge and the projection's y points up).
 */
typedef struct EsViewport {
  /**
   * Left edge in attachment pixels.
   */
  uint32_t x;
  /**
   * Top edge, or the bottom edge when `height` is negative.
   */
  uint32_t y;
  /**
   * Width in pixels.
   */
  uint32_t width;
  /**
   * Height in pixels; negative for a flipped viewport.
   */
  int32_t height;
} EsViewport;

/**
 * A camera: the contract of `docs/design.md` §3 field by field. Fill it with
 * `es_camera_from_matrices` or `es_camera_look_at`, or directly (set `struct_size`).
 */
typedef struct EsCamera {
  /**
   * `sizeof(EsCamera)`.
   */
  uint32_t struct_size;
  /**
   * Which of the projection fields apply: an `EsProjection` value.
   */
  uint32_t projection;
  /**
   * Eye position (perspective centre, or a point of the orthographic view axis).
   */
  double eye[3];
  /**
   * A point on the view axis in front of the eye.
   */
  double target[3];
  /**
   * Approximate up direction.
   */
  double up[3];
  /**
   * `ES_PROJECTION_PERSPECTIVE`: the vertical field of view in degrees, in (0, 180).
   */
  double fov_y_deg;
  /**
   * `ES_PROJECTION_ORTHOGRAPHIC`: the window's height in world units.
   */
  double ortho_height;
  /**
   * The `*_INTRINSICS` projections: `fx, fy, cx, cy` in pixels.
   */
  double intrinsics[4];
  /**
   * View depth of the near plane (> 0).
   */
  double near;
  /**
   * Image width in pixels (1 ..= 16384).
   */
  uint32_t width;
  /**
   * Image height in pixels (1 ..= 16384).
   */
  uint32_t height;
  /**
   * Sub-pixel jitter in pixels (x right, y down): pixel `(i, j)` samples the unjittered
   * image at `(i + 0.5 + dx, j + 0.5 + dy)`.
   */
  double jitter[2];
  /**
   * The attachment pixel of the camera's pixel (0, 0).
   */
  uint32_t viewport_origin[2];
  /**
   * Non-zero: reversed Z (near at 1, compare GREATER); zero: standard (near at 0).
   */
  uint32_t depth_reversed;
  /**
   * View depth of the far plane; 0 (or infinity) for an infinite far plane.
   */
  double depth_far;
} EsCamera;

/**
 * One ellipsoid.
 */
typedef struct EsGlyph {
  /**
   * Centre in world coordinates.
   */
  double center[3];
  /**
   * Semi-axes along the local x, y, z axes (finite, > 0).
   */
  double radii[3];
  /**
   * The rotation of the local axes into world axes, a quaternion `(w, x, y, z)` (normalised
   * by the library; not zero).
   */
  double rotation[4];
  /**
   * Display (sRGB) colour, each channel in [0, 1].
   */
  float color[3];
} EsGlyph;

/**
 * Where a frame's outputs go: arrays the host allocated, each of `width * height` pixels
 * (the camera's), row by row from the top; a null pointer skips that output.
 */
typedef struct EsFrameBuffers {
  /**
   * `sizeof(EsFrameBuffers)`.
   */
  uint32_t struct_size;
  /**
   * RGBA8 colour, sRGB-encoded: 4 bytes a pixel.
   */
  uint8_t *color;
  /**
   * View depth (the distance along the view axis): 1 float a pixel, `+inf` where no glyph
   * is hit.
   */
  float *depth;
  /**
   * World-space unit normal: 3 floats a pixel, zero where no glyph is hit.
   */
  float *normal;
  /**
   * The index of the glyph shown: 1 `uint32_t` a pixel, `ES_NO_GLYPH` where none is.
   */
  uint32_t *id;
} EsFrameBuffers;

/**
 * The shading: Blinn-Phong weights and highlight colour.
 */
typedef struct EsMaterial {
  /**
   * Ambient weight.
   */
  float ambient;
  /**
   * Diffuse weight.
   */
  float diffuse;
  /**
   * Specular weight.
   */
  float specular;
  /**
   * Phong exponent.
   */
  float shininess;
  /**
   * Colour of highlights (linear RGB).
   */
  float specular_color[3];
} EsMaterial;

/**
 * What a host may tune. Start from `es_settings_default`; every field but the material only
 * changes the work done and leaves the picture the same.
 *
 * Versions: the first (`struct_size` 52) ends at `per_sample_shading`; the second adds
 * `plan_mode` and `fixed_path`. The library reads only the version `struct_size` names, and
 * a first-version struct keeps its meaning: `compute_splat` zero keeps every frame on the
 * draw; non-zero lets the plan choose as the renderer's settings had it (measuring unless a
 * second-version struct chose otherwise).
 */
typedef struct EsSettings {
  /**
   * `sizeof(EsSettings)`.
   */
  uint32_t struct_size;
  /**
   * The shading.
   */
  struct EsMaterial material;
  /**
   * Non-zero: cull glyphs wholly outside the view.
   */
  uint32_t culling_frustum;
  /**
   * Non-zero: cull glyphs that cover no pixel centre.
   */
  uint32_t culling_pixel_centres;
  /**
   * Non-zero: cull glyphs hidden behind nearer ones (needs a `D32_SFLOAT` depth
   * attachment).
   */
  uint32_t culling_occlusion;
  /**
   * Deprecated (leave it at the default 1 and use `plan_mode`): zero keeps every frame on
   * the draw whatever `plan_mode` says, as `ES_PLAN_MODE_FIXED` with `ES_PATH_KIND_DRAW`
   * does; zero with a `plan_mode` that fixes a splat path is refused.
   */
  uint32_t compute_splat;
  /**
   * Non-zero: multisampled targets shade every sample (exact depth per sample) instead of
   * once per pixel with exact per-sample coverage.
   */
  uint32_t per_sample_shading;
  /**
   * How the frame plan chooses its path: an `EsPlanMode` value (second version).
   */
  uint32_t plan_mode;
  /**
   * With `ES_PLAN_MODE_FIXED`, the path: an `EsPathKind` value other than
   * `ES_PATH_KIND_NONE`; otherwise ignored (`es_settings_default` writes
   * `ES_PATH_KIND_NONE`). Second version.
   */
  uint32_t fixed_path;
} EsSettings;

/**
 * What an offscreen renderer is made with.
 */
typedef struct EsOffscreenCreateInfo {
  /**
   * `sizeof(EsOffscreenCreateInfo)`.
   */
  uint32_t struct_size;
  /**
   * Non-zero: the Khronos validation layer (with synchronization checks) is on, and any
   * message it reports makes the call that caused it fail with `ES_STATUS_ERROR_VULKAN`.
   */
  uint32_t validation;
  /**
   * The device: its index or a part of its name (a NUL-terminated string), or null for
   * the environment's `ELLIPSOID_SPLAT_DEVICE`, else a real GPU, else lavapipe.
   */
  const char *device;
  /**
   * The settings, or null for `es_settings_default`'s.
   */
  const struct EsSettings *settings;
} EsOffscreenCreateInfo;

/**
 * The plan of a frame: the path `es_renderer_record_prepass` and `es_renderer_record`
 * take with a camera, why, and what it does. Written whole by the library (this header's
 * version).
 */
typedef struct EsFramePlan {
  /**
   * `sizeof(EsFramePlan)`, set by the library.
   */
  uint32_t struct_size;
  /**
   * Non-zero: the pre-pass runs (to cull, to set glyphs up, or to splat), and the draw
   * is indirect.
   */
  uint32_t prepass;
  /**
   * Non-zero: the compute splat draws the glyphs without the rasterizer (`path` is
   * `ES_PATH_KIND_SPLAT` or `ES_PATH_KIND_VISIBLE_FIRST`).
   */
  uint32_t compute_splat;
  /**
   * Where the draw is the only path (`reason` is `ES_PLAN_REASON_KIND_ONLY`), why: a
   * NUL-terminated sentence in static storage; null otherwise.
   */
  const char *drawn_because;
  /**
   * The sampled glyphs' mean projected area in pixels; negative where none is on screen.
   */
  double mean_area_px;
  /**
   * Non-zero for each culling that runs.
   */
  uint32_t culling_frustum;
  /**
   * As above: pixel centres.
   */
  uint32_t culling_pixel_centres;
  /**
   * As above: occlusion.
   */
  uint32_t culling_occlusion;
  /**
   * Non-zero: small glyphs are set up once by the pre-pass.
   */
  uint32_t setup_once;
  /**
   * Non-zero: the glyphs the view's last stamping frame showed go first (`hidden_layers`
   * is `ES_HIDDEN_LAYERS_VISIBLE_FIRST`).
   */
  uint32_t visible_first;
  /**
   * Samples the fragment stage decides per pixel (0 where it shades every sample).
   */
  uint32_t coverage_samples;
  /**
   * Non-zero: an orthographic camera.
   */
  uint32_t orthographic;
  /**
   * Non-zero: reversed Z.
   */
  uint32_t reversed_z;
  /**
   * The path the frame takes: an `EsPathKind` value (`ES_PATH_KIND_VISIBLE_FIRST` also for
   * its first frame after an upload, which stamps what it shows).
   */
  uint32_t path;
  /**
   * What a splatted frame does about hidden glyphs: an `EsHiddenLayers` value
   * (`ES_HIDDEN_LAYERS_NONE` where the frame draws).
   */
  uint32_t hidden_layers;
  /**
   * Why the frame takes its path: an `EsPlanReasonKind` value.
   */
  uint32_t reason;
  /**
   * With `ES_PLAN_REASON_KIND_MEASURED`, the next fastest candidate: an `EsPathKind`
   * value, `ES_PATH_KIND_NONE` where no other was timed (or the plan did not measure).
   */
  uint32_t runner_up;
  /**
   * With `ES_PLAN_REASON_KIND_MEASURED`, the median GPU time of the path's frames in
   * milliseconds; negative otherwise.
   */
  double measured_ms;
  /**
   * The runner-up's median GPU time in milliseconds; negative where there is none.
   */
  double runner_up_ms;
} EsFramePlan;

/**
 * `vkGetInstanceProcAddr`: the loader's (or the host's) entry point every other Vulkan
 * function is looked up through.
 */
typedef PFN_vkVoidFunction (*EsGetInstanceProcAddr)(VkInstance,
                                                    const char*);

/**
 * The host's Vulkan objects (borrowed: never destroyed by the library; they must outlive
 * the renderer) and the features it enabled on the device.
 */
typedef struct EsDeviceInfo {
  /**
   * `sizeof(EsDeviceInfo)`.
   */
  uint32_t struct_size;
  /**
   * The loader's (or the host's) `vkGetInstanceProcAddr`; every other entry point is
   * loaded through it.
   */
  EsGetInstanceProcAddr get_instance_proc_addr;
  /**
   * The instance the device was created from.
   */
  VkInstance instance;
  /**
   * The physical device behind `device`.
   */
  VkPhysicalDevice physical_device;
  /**
   * The host's device.
   */
  VkDevice device;
  /**
   * The family of the queue that will run the command buffers the renderer records into:
   * graphics and compute.
   */
  uint32_t queue_family_index;
  /**
   * The `ES_FEATURE_*` bits the host enabled on `device` (at least
   * `es_target_required_features` of every target).
   */
  uint32_t enabled_features;
} EsDeviceInfo;

/**
 * The pass the renderer draws into.
 */
typedef struct EsTargetInfo {
  /**
   * `sizeof(EsTargetInfo)`.
   */
  uint32_t struct_size;
  /**
   * The host's render pass (borrowed), or `VK_NULL_HANDLE` for dynamic rendering.
   */
  VkRenderPass render_pass;
  /**
   * The subpass the renderer draws in (render pass only).
   */
  uint32_t subpass;
  /**
   * The subpass's colour attachments (render pass), or the number of `color_formats`
   * (dynamic rendering); at least 1. The renderer writes attachment 0 (and 1 and 2 with
   * `aux_outputs`), and masks the others.
   */
  uint32_t color_attachment_count;
  /**
   * Dynamic rendering: the colour attachments' formats, `color_attachment_count` of them
   * (ignored for a render pass).
   */
  const VkFormat *color_formats;
  /**
   * The depth attachment's format (the renderer writes exact depth).
   */
  VkFormat depth_format;
  /**
   * Samples per pixel: 1, 2, 4 or 8.
   */
  uint32_t samples;
  /**
   * Non-zero: attachment 1 takes world normals (`R32G32B32A32_SFLOAT`) and attachment 2
   * instance indices (`R32_UINT`).
   */
  uint32_t aux_outputs;
} EsTargetInfo;

/**
 * A buffer the host's allocator made: the buffer, the allocator's handle of its memory (a
 * `VmaAllocation`, or anything the host needs to free it), the mapping of host-visible
 * memory, and the memory's size in bytes.
 */
typedef struct EsBuffer {
  /**
   * The buffer, with memory bound.
   */
  VkBuffer buffer;
  /**
   * The host's handle of the buffer's memory, handed back to `destroy_buffer`.
   */
  void *allocation;
  /**
   * The first mapped byte, for `ES_MEMORY_USE_UPLOAD` and `ES_MEMORY_USE_READBACK`
   * (required there); may be null for `ES_MEMORY_USE_GPU_ONLY`.
   */
  void *mapped;
  /**
   * The memory's size in bytes (at least the buffer's size).
   */
  uint64_t size;
} EsBuffer;

/**
 * Creates a buffer from `info` with memory for `usage` bound to it (`vmaCreateBuffer` with
 * the usage's memory properties; `name` is for the host's debugging and memory budget), and
 * fills `out`. Returns `VK_SUCCESS` or the failure's `VkResult`.
 */
typedef VkResult (*EsCreateBufferFn)(void *user_data,
                                     const VkBufferCreateInfo *info,
                                     enum EsMemoryUse usage,
                                     const char *name,
                                     struct EsBuffer *out);

/**
 * Destroys a buffer `create_buffer` made, and frees its memory (`vmaDestroyBuffer`). The GPU
 * no longer uses it.
 */
typedef void (*EsDestroyBufferFn)(void *user_data,
                                  const struct EsBuffer *buffer);

/**
 * The host's allocator: both callbacks, or neither (the library then allocates with its own
 * allocator). They are called on the thread calling into the renderer (two renderers on two
 * threads may call them at once with the same `user_data`). They must return, not unwind or
 * `longjmp`, and must not call into the renderer that called them. After a failure the
 * library ignores `out`: the callback cleans up what it made. A callback that reports
 * success with a null buffer, no mapping where one is needed, or less memory than asked
 * for fails the call (`ES_STATUS_ERROR_VULKAN`) and what it made is handed back.
 */
typedef struct EsAllocatorCallbacks {
  /**
   * `sizeof(EsAllocatorCallbacks)`.
   */
  uint32_t struct_size;
  /**
   * Passed to both callbacks as their first argument.
   */
  void *user_data;
  /**
   * Creates a buffer with its memory.
   */
  EsCreateBufferFn create_buffer;
  /**
   * Destroys a buffer and frees its memory.
   */
  EsDestroyBufferFn destroy_buffer;
} EsAllocatorCallbacks;

/**
 * What a renderer is made from.
 */
typedef struct EsRendererCreateInfo {
  /**
   * `sizeof(EsRendererCreateInfo)`.
   */
  uint32_t struct_size;
  /**
   * The host's device (borrowed).
   */
  const struct EsDeviceInfo *device;
  /**
   * The pass the ellipsoids are drawn into first (`es_renderer_set_target` adds more).
   */
  const struct EsTargetInfo *target;
  /**
   * The host's allocator callbacks, or null for the library's own allocator.
   */
  const struct EsAllocatorCallbacks *allocator;
  /**
   * The settings, or null for `es_settings_default`'s.
   */
  const struct EsSettings *settings;
  /**
   * How many frames the host records before waiting for the oldest (1 ..= 16).
   */
  uint32_t frames_in_flight;
  /**
   * The host's pipeline cache for every pipeline the renderer builds (borrowed), or
   * `VK_NULL_HANDLE`.
   */
  VkPipelineCache pipeline_cache;
} EsRendererCreateInfo;

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

/**
 * The ABI version of the library loaded, to compare with `ES_ABI_VERSION` of the header the
 * host was compiled with. Any thread.
 */
uint32_t es_abi_version(void);

/**
 * The camera the host's `view` and `projection` matrices (column-major `float[16]`, world to
 * Vulkan clip space) describe when drawn with `viewport`: any perspective or orthographic
 * frustum -- jittered, off-centre, asymmetric, non-square pixels -- in reversed or standard
 * Z with a finite or infinite far plane, and y-up projections with a flipped viewport.
 * Skewed, oblique and mirroring matrices are refused (the message says why). Any thread.
 *
 * # Safety
 * `view` and `projection` point at 16 floats each; `out_camera` at a writable `EsCamera`.
 */
enum EsStatus es_camera_from_matrices(const float *view,
                                      const float *projection,
                                      struct EsViewport viewport,
                                      struct EsCamera *out_camera);

/**
 * A perspective camera at `eye` looking at `target` with `up` roughly up, `fov_y_deg`
 * degrees of vertical field of view, the near plane at `near` and a `width x height` image
 * (reversed Z, infinite far plane). Any thread.
 *
 * # Safety
 * `eye`, `target` and `up` point at 3 doubles each; `out_camera` at a writable `EsCamera`.
 */
enum EsStatus es_camera_look_at(const double *eye,
                                const double *target,
                                const double *up,
                                double fov_y_deg,
                                double near,
                                uint32_t width,
                                uint32_t height,
                                struct EsCamera *out_camera);

#if defined(ELLIPSOID_SPLAT_MPI)
/**
 * Draws this process's `count` glyphs (`glyphs`; glyph `i` is glyph `global_ids[i]` of the
 * whole scene, the indices strictly increasing) with `camera`, and composites the frames of
 * every process of the communicator at rank `root`: there the outputs `buffers` asks for are
 * written (each array `camera->width * camera->height` pixels), exactly what one process
 * drawing every glyph with `es_offscreen_render` writes (`id` holds global indices).
 *
 * The rules of this layer:
 * - `communicator` is the communicator's Fortran handle, `MPI_Comm_c2f(comm)`, so this
 *   header needs no `mpi.h`. It is borrowed: never freed; MPI is never initialised or
 *   finalised here (the application does both, around every call). The exchange runs on a
 *   duplicate, so the application's own messages are never taken.
 * - Collective: every process of the communicator calls it, with the same root, camera and
 *   image size, and renderers of the same settings.
 * - `buffers` is read at the root only (elsewhere it may be null).
 * - A process whose arguments or drawing fail makes every process return an error: that
 *   one its own, the others `ES_STATUS_ERROR_OTHER_RANK` naming the lowest failing rank.
 *   None waits for an image that will not come.
 *
 * Only in a library built with the `mpi` feature; declared when `ELLIPSOID_SPLAT_MPI` is
 * defined before the header is included. Thread: the renderer's, one the application's MPI
 * threading level allows to call MPI.
 *
 * # Safety
 * `communicator` is the Fortran handle of a live communicator of this process (or
 * `MPI_COMM_NULL`'s, refused); `renderer` is live; `glyphs` and `global_ids` point at
 * `count` values each; `camera` at a valid `EsCamera`; at the root, `buffers` at a valid
 * `EsFrameBuffers` whose arrays are writable, large enough and apart.
 */
enum EsStatus es_offscreen_render_composited(struct EsOffscreenRenderer *renderer,
                                             int communicator,
                                             int root,
                                             const struct EsGlyph *glyphs,
                                             const uint32_t *global_ids,
                                             size_t count,
                                             const struct EsCamera *camera,
                                             const struct EsFrameBuffers *buffers);
#endif

/**
 * Makes an offscreen renderer (its own Vulkan instance and device) and writes its handle to
 * `out_renderer` (null on failure). Any thread.
 *
 * # Safety
 * `info` points at a valid `EsOffscreenCreateInfo` (its `device` null or a NUL-terminated
 * string, its `settings` null or a valid `EsSettings`); `out_renderer` at a writable
 * pointer.
 */
enum EsStatus es_offscreen_create(const struct EsOffscreenCreateInfo *info,
                                  struct EsOffscreenRenderer **out_renderer);

/**
 * Destroys `renderer` with its device and instance (a null `renderer` is fine). The handle
 * is gone after the call whatever the status: a failure reports what a clean shutdown must
 * not have (validation messages, memory still allocated). Thread: the renderer's.
 *
 * # Safety
 * A non-null `renderer` came from `es_offscreen_create` and is not used again.
 */
enum EsStatus es_offscreen_destroy(struct EsOffscreenRenderer *renderer);

/**
 * Uploads the `count` glyphs of `glyphs` (read during the call only), draws them with
 * `camera` and writes the outputs `buffers` asks for (each array `camera->width *
 * camera->height` pixels). The camera draws its own image: its `viewport_origin` is
 * (0, 0). Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `glyphs` points at `count` glyphs; `camera` at a valid `EsCamera`;
 * `buffers` at a valid `EsFrameBuffers` whose arrays are writable and large enough, and do
 * not overlap.
 */
enum EsStatus es_offscreen_render(struct EsOffscreenRenderer *renderer,
                                  const struct EsGlyph *glyphs,
                                  size_t count,
                                  const struct EsCamera *camera,
                                  const struct EsFrameBuffers *buffers);

/**
 * The plan the next `es_renderer_record_prepass` with `camera` would make (the views'
 * history is the renderer's: call it before recording). Thread: the renderer's.
 *
 * # Safety
 * `renderer` is a live renderer; `camera` points at a valid `EsCamera`; `out_plan` at a
 * writable `EsFramePlan`.
 */
enum EsStatus es_renderer_plan(struct EsRenderer *renderer,
                               const struct EsCamera *camera,
                               struct EsFramePlan *out_plan);

/**
 * The plan of the last frame recorded (the last `es_renderer_record_prepass`): the path it
 * took and why. Fails with `ES_STATUS_ERROR_INVALID_ARGUMENT` before the first pre-pass.
 * Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `out_plan` points at a writable `EsFramePlan`.
 */
enum EsStatus es_renderer_last_plan(struct EsRenderer *renderer,
                                    struct EsFramePlan *out_plan);

/**
 * Makes a renderer on the host's device and writes its handle to `out_renderer` (null on
 * failure). It checks the queue family, the enabled features, the target's formats and
 * sample count, and names what is missing. Any thread.
 *
 * # Safety
 * `info` and what it points at are valid; the handles belong together, the device has the
 * features `enabled_features` names enabled, and they, the render pass and the pipeline
 * cache outlive the renderer; the allocator callbacks (if any) allocate from that device.
 * `out_renderer` points at a writable pointer.
 */
enum EsStatus es_renderer_create(const struct EsRendererCreateInfo *info,
                                 struct EsRenderer **out_renderer);

/**
 * Destroys `renderer` and everything it made (a null `renderer` is fine). The GPU must be
 * done with every command buffer the renderer recorded into. Nothing of the host's is
 * destroyed. The handle is gone after the call whatever the status (a failure only reports
 * what could not be freed). Thread: the renderer's.
 *
 * # Safety
 * A non-null `renderer` came from `es_renderer_create` and is not used again.
 */
enum EsStatus es_renderer_destroy(struct EsRenderer *renderer);

/**
 * Makes `target` the pass the next frames are drawn into (its pipelines are built on first
 * use and kept). Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `target` points at a valid `EsTargetInfo` whose render pass (if any)
 * outlives the renderer.
 */
enum EsStatus es_renderer_set_target(struct EsRenderer *renderer,
                                     const struct EsTargetInfo *target);

/**
 * Replaces the settings (the material costs nothing; other changes build their pipelines
 * on first use). Fields of versions later than the struct's `struct_size` keep their
 * values. A bad value (an unknown `plan_mode`, say) is refused and changes nothing.
 * Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `settings` points at a valid `EsSettings` of its `struct_size`.
 */
enum EsStatus es_renderer_set_settings(struct EsRenderer *renderer,
                                       const struct EsSettings *settings);

/**
 * Starts frame slot `slot` (in `0..frames_in_flight`), once the host has waited for that
 * slot's fence: frees what was replaced while earlier frames could still read it. Call it
 * first in every frame. Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; every command buffer recorded with it since `slot` last began has
 * finished executing.
 */
enum EsStatus es_renderer_begin_frame(struct EsRenderer *renderer,
                                      uint32_t slot);

/**
 * Records the upload of a whole scene of `count` glyphs into `command_buffer` (outside any
 * pass): a staged copy between barriers. Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `glyphs` points at `count` glyphs (read during the call only);
 * `command_buffer` is recording outside any pass, for the renderer's queue family, and is
 * submitted before (or is) the command buffer that draws this scene.
 */
enum EsStatus es_renderer_upload(struct EsRenderer *renderer,
                                 VkCommandBuffer command_buffer,
                                 const struct EsGlyph *glyphs,
                                 size_t count);

/**
 * Records the replacement of glyphs `first .. first + count` of the uploaded scene (outside
 * any pass). Thread: the renderer's.
 *
 * # Safety
 * As for `es_renderer_upload`.
 */
enum EsStatus es_renderer_update(struct EsRenderer *renderer,
                                 VkCommandBuffer command_buffer,
                                 uint32_t first,
                                 const struct EsGlyph *glyphs,
                                 size_t count);

/**
 * Records the pre-pass of one view with `camera` into `command_buffer`, outside any pass.
 * The first call of a frame is view 0, the next view 1 (up to 64); each view's draw
 * (`es_renderer_record` with the same camera) follows in the host's pass. Thread: the
 * renderer's.
 *
 * # Safety
 * `renderer` is live; `camera` points at a valid `EsCamera`; `command_buffer` is recording
 * outside any pass, for the renderer's queue family, and is submitted before the frame slot
 * that is current begins again.
 */
enum EsStatus es_renderer_record_prepass(struct EsRenderer *renderer,
                                         VkCommandBuffer command_buffer,
                                         const struct EsCamera *camera);

/**
 * Records the draw of the view whose pre-pass had `camera` into `command_buffer`, inside
 * the host's pass (render pass subpass or dynamic rendering matching the target of that
 * pre-pass). It binds its own pipeline, descriptor set and push constants and sets viewport
 * and scissor to the camera's rectangle: the host rebinds its own state afterwards.
 * Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `camera` points at a valid `EsCamera`; `command_buffer` is recording
 * inside a pass compatible with the view's target whose attachments hold the camera's
 * rectangle.
 */
enum EsStatus es_renderer_record(struct EsRenderer *renderer,
                                 VkCommandBuffer command_buffer,
                                 const struct EsCamera *camera);

/**
 * Writes the bytes of GPU memory the renderer's buffers take (as its allocator gave them)
 * to `out_bytes`. Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `out_bytes` points at a writable `uint64_t`.
 */
enum EsStatus es_renderer_gpu_memory_bytes(struct EsRenderer *renderer,
                                           uint64_t *out_bytes);

/**
 * Fills `out_settings` with the shipped renderer's settings (the whole struct, this
 * header's version). Any thread.
 *
 * # Safety
 * `out_settings` points at a writable `EsSettings`.
 */
enum EsStatus es_settings_default(struct EsSettings *out_settings);

/**
 * The message of the last call on this thread that did not return `ES_STATUS_SUCCESS` (an
 * empty string if none has failed). The pointer stays valid until the next failing call on
 * this thread; copy the text to keep it. Any thread.
 */
const char *es_last_error(void);

/**
 * The `ES_FEATURE_*` bits a device must have enabled for `target`. Any thread.
 *
 * # Safety
 * `target` points at a valid `EsTargetInfo`; `out_features` at a writable `uint32_t`.
 */
enum EsStatus es_target_required_features(const struct EsTargetInfo *target,
                                          uint32_t *out_features);

/**
 * The plan's wisdom: for each scene class the renderer settled on, the path it chose and the
 * candidates' median frame times, keyed by the device's vendor and device IDs, driver
 * version and pipeline-cache UUID. Two calls: with `bytes` null it writes the size needed to
 * `size`; then with a buffer of `*size` bytes it writes the bytes and their count. A buffer
 * smaller than needed fails (`ES_STATUS_ERROR_INVALID_ARGUMENT`, the message names the size)
 * and `*size` is set to the size needed. A renderer that settled nothing still gives valid
 * bytes (a header without entries). Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `size` points at a writable `size_t`; a non-null `bytes` points at
 * `*size` writable bytes.
 */
enum EsStatus es_renderer_plan_wisdom(struct EsRenderer *renderer,
                                      uint8_t *bytes,
                                      size_t *size);

/**
 * Takes in the wisdom of `es_renderer_plan_wisdom` from a renderer on the same device and
 * driver build: the scene classes it settled are then planned as learned, without exploring
 * them again. Bytes from another device, driver build or format, truncated or damaged ones
 * are refused (`ES_STATUS_ERROR_INVALID_ARGUMENT`, the message says which) and change
 * nothing. The bytes are read during the call only. Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; a non-null `bytes` points at `size` readable bytes.
 */
enum EsStatus es_renderer_load_plan_wisdom(struct EsRenderer *renderer,
                                           const uint8_t *bytes,
                                           size_t size);

/**
 * Writes to `out_can_measure` whether the plan can time its frames on this device (its
 * queue family has timestamps): 1 if so; 0 where `ES_PLAN_MODE_MEASURE` plans as
 * `ES_PLAN_MODE_ESTIMATE` does and no wisdom is learned. Thread: the renderer's.
 *
 * # Safety
 * `renderer` is live; `out_can_measure` points at a writable `uint32_t`.
 */
enum EsStatus es_renderer_can_measure(struct EsRenderer *renderer,
                                      uint32_t *out_can_measure);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* ELLIPSOID_SPLAT_H */
