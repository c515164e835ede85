//! The C ABI of `ellipsoid-splat`: the library `ellipsoid_splat` (`libellipsoid_splat.so.2`,
//! `libellipsoid_splat.a`, as `scripts/install-capi.sh` installs this crate's
//! `libellipsoid_splat_capi`) and its header `include/ellipsoid_splat.h`, generated from these
//! sources by cbindgen and committed.
//!
//! It is a thin layer over the Rust API, following the same embedding steps: a renderer made
//! from the host's raw Vulkan handles and `vkGetInstanceProcAddr`, a target (a render pass and
//! subpass, or dynamic rendering formats), frame slots, glyphs uploaded from arrays of plain
//! structs, per view a pre-pass outside the pass and a draw inside it, cameras from
//! column-major matrices and a viewport or from a look-at, settings (the frame plan's mode
//! among them), the frame plan before and after a frame, the plan's learned wisdom as bytes,
//! and memory from the host's callbacks (or the library's own allocator).
//!
//! Codes without an engine draw with an offscreen renderer of the library's own device into
//! arrays they allocate (`es_offscreen_create`, `es_offscreen_render`); with the feature `mpi`
//! each process of an MPI application draws its share and the root gets the whole frame
//! (`es_offscreen_render_composited`, the only call that links MPI).
//!
//! The rules (`docs/c-and-cpp.md`): every function returns an [`EsStatus`]; after a failure
//! [`es_last_error`] gives the message on the calling thread. No panic unwinds into the
//! host: it becomes `ES_STATUS_ERROR_PANIC`, and the renderer it happened in refuses every
//! call but `es_renderer_destroy`. Option structs begin with `struct_size` (set it to
//! `sizeof` the struct), so later versions can add fields at the end and the library reads
//! only the version the host was compiled with. Structs the library writes (settings,
//! cameras, plans) are written whole, so growing one of them changes [`ES_ABI_VERSION`].
//! Handles are opaque; nothing the host passes in is ever destroyed by the library.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | the C ABI (`docs/c-and-cpp.md`), one file per part: status and errors, device, target, allocator callbacks, glyphs, cameras, settings, plan, wisdom, renderer, the offscreen renderer (`offscreen.rs`) and its frame in the host's arrays (`frame.rs`), in situ over MPI (`composited.rs`, feature `mpi`) | `src/`; the header `include/ellipsoid_splat.h` (cbindgen, committed); `tests/` (the header's freshness, bad input, the C11 and C++ hosts in `tests/c/` and `tests/cpp_host/`, the offscreen renderer, in situ under `mpirun`); the in-situ example `examples/insitu_mpi.c`; `benches/c_overhead.rs` |

mod allocator;
mod camera;
#[cfg(feature = "mpi")]
mod composited;
mod device;
mod frame;
mod glyphs;
mod offscreen;
mod plan;
mod renderer;
mod settings;
mod status;
mod target;
mod wisdom;

pub use allocator::{
    EsAllocatorCallbacks, EsBuffer, EsCreateBufferFn, EsDestroyBufferFn, EsMemoryUse,
};
pub use camera::{es_camera_from_matrices, es_camera_look_at, EsCamera, EsProjection, EsViewport};
#[cfg(feature = "mpi")]
pub use composited::es_offscreen_render_composited;
pub use device::{
    EsDeviceInfo, EsGetInstanceProcAddr, ES_FEATURE_DYNAMIC_RENDERING, ES_FEATURE_MAINTENANCE4,
    ES_FEATURE_SAMPLE_RATE_SHADING, ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS,
    ES_FEATURE_SHADER_INT64,
};
pub use frame::{EsFrameBuffers, ES_NO_GLYPH};
pub use glyphs::EsGlyph;
pub use offscreen::{
    es_offscreen_create, es_offscreen_destroy, es_offscreen_render, EsOffscreenCreateInfo,
    EsOffscreenRenderer,
};
pub use plan::{
    es_renderer_last_plan, es_renderer_plan, EsFramePlan, EsHiddenLayers, EsPlanReasonKind,
};
pub use renderer::{
    es_renderer_begin_frame, es_renderer_create, es_renderer_destroy, es_renderer_gpu_memory_bytes,
    es_renderer_record, es_renderer_record_prepass, es_renderer_set_settings,
    es_renderer_set_target, es_renderer_update, es_renderer_upload, EsRenderer,
    EsRendererCreateInfo,
};
pub use settings::{es_settings_default, EsMaterial, EsPathKind, EsPlanMode, EsSettings};
pub use status::{es_last_error, EsStatus};
pub use target::{es_target_required_features, EsTargetInfo};
pub use wisdom::{es_renderer_can_measure, es_renderer_load_plan_wisdom, es_renderer_plan_wisdom};

/// The ABI's version: it changes whenever a function, struct or constant changes in a way a
/// host compiled against the old header would break on. The shared library's soname carries
/// it (`libellipsoid_splat.so.2`). Version 2: `EsSettings` and `EsFramePlan` grew (the plan's
/// mode; the path taken and why), and `es_settings_default`, `es_renderer_plan` write them
/// whole.
pub const ES_ABI_VERSION: u32 = 2;

/// The ABI version of the library loaded, to compare with `ES_ABI_VERSION` of the header the
/// host was compiled with. Any thread.
#[no_mangle]
pub extern "C" fn es_abi_version() -> u32 {
    ES_ABI_VERSION
}
