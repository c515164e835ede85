//! What a host does, one call (or one short run of calls) at a time: the operations a
//! sequence is made of, and proptest's strategies for them. Each operation is read against
//! the state it meets (sizes relative to the chunk limit, update ranges relative to the
//! uploaded count), so a shrunk sequence stays meaningful.

use proptest::prelude::*;

use super::cameras::{CameraChoice, CameraDefect, CameraKind, MatrixDefect};
use super::glyphs::GlyphDefect;

/// How many glyphs an upload has.
#[derive(Clone, Copy, Debug)]
pub enum SceneSize {
    Empty,
    One,
    Few(u8),
    /// `chunks` times the chunk limit in force, plus `offset` (-1, 0 or 1).
    AroundChunks {
        chunks: u8,
        offset: i8,
    },
}

/// Where an update starts.
#[derive(Clone, Copy, Debug)]
pub enum UpdateStart {
    /// At this share of the uploaded count.
    Share(f64),
    /// This many past the uploaded count (refused unless empty at the end exactly).
    PastEnd(u8),
    /// So far that `first + len` overflows `u32`.
    Overflow,
}

/// The host's target: how it is drawn into, its depth, samples and size.
#[derive(Clone, Copy, Debug)]
pub struct TargetChoice {
    pub render_pass: bool,
    pub standard_depth: bool,
    pub multisampled: bool,
    /// An index into `TARGET_SIZES`.
    pub size: usize,
}

/// The target sizes: a pixel, and small squares and strips.
pub const TARGET_SIZES: [(u32, u32); 6] =
    [(1, 1), (32, 32), (48, 24), (24, 40), (64, 48), (80, 80)];

/// A target description `set_target` must refuse.
#[derive(Clone, Copy, Debug)]
pub enum TargetDefect {
    TwoSampleCounts,
    UnsupportedSamples,
    ColourAsDepth,
    AuxWithoutAttachments,
    NullRenderPass,
    UndefinedColour,
}

/// The material a setting change takes, or one with a field no shading can use.
#[derive(Clone, Copy, Debug)]
pub enum MaterialChoice {
    Default,
    Unlit,
    Shiny,
    NanAmbient,
    NegativeDiffuse,
    InfiniteSpecular,
    ZeroShininess,
    NanHighlight,
}

/// Every setting's variants.
#[derive(Clone, Copy, Debug)]
pub struct SettingsChoice {
    /// Bits: frustum, pixel centres, occlusion.
    pub culling: u8,
    pub setup_once: bool,
    pub cap_free_path: bool,
    pub small_glyph_triangles: bool,
    pub compact: bool,
    /// Measure, estimate, or fixed on the draw, the splat or the visible-first splat.
    pub plan: u8,
    /// An index into `CHUNK_LIMITS`.
    pub chunk: usize,
    pub per_sample_shading: bool,
    pub material: MaterialChoice,
}

/// `Settings::max_chunk_instances` values: the default (the device's limit), the smallest
/// chunk, two chunks' worth, one rounded down to 256, and 0 (rounded up to 256).
pub const CHUNK_LIMITS: [u32; 5] = [u32::MAX, 256, 512, 300, 0];

/// One view of a `Draw`.
#[derive(Clone, Copy, Debug)]
pub enum ViewChoice {
    /// A valid camera; without its pre-pass when `skip_prepass`.
    Camera {
        camera: CameraChoice,
        skip_prepass: bool,
    },
    /// A valid camera with a defect written in: `plan`, `record_prepass` and `record`
    /// refuse it, as the constructors do.
    Defective {
        camera: CameraChoice,
        defect: CameraDefect,
    },
    /// Host matrices no camera comes from.
    Matrices(MatrixDefect),
}

/// A `Draw`: its views, and what the host changes between their pre-passes and its pass.
#[derive(Clone, Debug)]
pub struct Draw {
    pub views: Vec<ViewChoice>,
    /// New settings: the draws keep their pre-passes' plans and push the new material.
    pub settings_between: Option<SettingsChoice>,
    /// A new host target made current: the views still draw into the target of their
    /// pre-passes (each records one: a view without plans for the target current at its
    /// draw, which is no longer the pass's).
    pub target_between: Option<TargetChoice>,
}

impl Draw {
    /// The views, changing nothing between.
    pub fn views(views: Vec<ViewChoice>) -> Op {
        Op::Draw(Draw {
            views,
            settings_between: None,
            target_between: None,
        })
    }
}

/// What the plan wisdom given to `load_plan_wisdom` is.
#[derive(Clone, Copy, Debug)]
pub enum WisdomChoice {
    RoundTrip,
    Truncated,
    Garbage(u64),
}

/// One step of the host.
#[derive(Clone, Debug)]
pub enum Op {
    /// `begin_frame` of the next slot (opening a command buffer if none is open).
    BeginFrame,
    /// `begin_frame` with a slot past `frames_in_flight`.
    BeginFrameBadSlot(u8),
    Upload {
        size: SceneSize,
        seed: u64,
    },
    /// An upload whose glyph at `at` (a share of the size) has a defect.
    UploadDefective {
        size: SceneSize,
        seed: u64,
        at: f64,
        defect: GlyphDefect,
    },
    Update {
        start: UpdateStart,
        len: u8,
        seed: u64,
        defect: Option<GlyphDefect>,
    },
    Settings(SettingsChoice),
    /// A new host target (a resize, another kind, depth or sample count) made current.
    Target(TargetChoice),
    TargetDefective(TargetDefect),
    /// A second renderer with options it must refuse (no frames in flight, or too many).
    RendererDefective {
        frames_in_flight: u32,
    },
    /// The views' pre-passes, then one pass over the target drawing each into its strip.
    Draw(Draw),
    /// Ends, submits and waits for the open command buffer; its last pass is checked.
    Submit,
    /// A skipped frame: what the renderer recorded is submitted, then the next frame begins
    /// and the host drops its command buffer unsubmitted (its swapchain went out of date).
    SkipFrame,
    Wisdom(WisdomChoice),
}

/// A whole sequence: how the renderer is made, then the operations.
#[derive(Clone, Debug)]
pub struct Sequence {
    pub frames_in_flight: u32,
    pub target: TargetChoice,
    pub settings: SettingsChoice,
    pub ops: Vec<Op>,
}

fn scene_size() -> impl Strategy<Value = SceneSize> {
    prop_oneof![
        1 => Just(SceneSize::Empty),
        1 => Just(SceneSize::One),
        5 => (2u8..60).prop_map(SceneSize::Few),
        2 => (1u8..=2, -1i8..=1).prop_map(|(chunks, offset)| SceneSize::AroundChunks { chunks, offset }),
    ]
}

pub fn target_choice() -> impl Strategy<Value = TargetChoice> {
    (
        any::<bool>(),
        any::<bool>(),
        prop::bool::weighted(0.3),
        0..TARGET_SIZES.len(),
    )
        .prop_map(
            |(render_pass, standard_depth, multisampled, size)| TargetChoice {
                render_pass,
                standard_depth,
                multisampled,
                size,
            },
        )
}

fn material() -> impl Strategy<Value = MaterialChoice> {
    prop_oneof![
        10 => Just(MaterialChoice::Default),
        5 => Just(MaterialChoice::Unlit),
        5 => Just(MaterialChoice::Shiny),
        1 => Just(MaterialChoice::NanAmbient),
        1 => Just(MaterialChoice::NegativeDiffuse),
        1 => Just(MaterialChoice::InfiniteSpecular),
        1 => Just(MaterialChoice::ZeroShininess),
        1 => Just(MaterialChoice::NanHighlight),
    ]
}

pub fn settings_choice() -> impl Strategy<Value = SettingsChoice> {
    (
        0u8..8,
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop::bool::weighted(0.3),
        0u8..5,
        0..CHUNK_LIMITS.len(),
        prop::bool::weighted(0.3),
        material(),
    )
        .prop_map(
            |(
                culling,
                setup_once,
                cap_free_path,
                small,
                compact,
                plan,
                chunk,
                per_sample,
                material,
            )| {
                SettingsChoice {
                    culling,
                    setup_once,
                    cap_free_path,
                    small_glyph_triangles: small,
                    compact,
                    plan,
                    chunk,
                    per_sample_shading: per_sample,
                    material,
                }
            },
        )
}

fn camera_kind() -> impl Strategy<Value = CameraKind> {
    let tangent = || 0.15f64..1.2;
    let window = || 0.3f64..3.0;
    prop_oneof![
        (15.0f64..90.0).prop_map(|fov_y_deg| CameraKind::LookAt { fov_y_deg }),
        (1.0f64..6.0).prop_map(|height| CameraKind::Orthographic { height }),
        (tangent(), tangent(), tangent(), tangent()).prop_map(|(left, right, bottom, top)| {
            CameraKind::Tangents {
                left,
                right,
                bottom,
                top,
            }
        }),
        (window(), window(), window(), window()).prop_map(|(left, right, bottom, top)| {
            CameraKind::Window {
                left,
                right,
                bottom,
                top,
            }
        }),
        (15.0f64..90.0, any::<bool>()).prop_map(|(fov_y_deg, orthographic)| {
            CameraKind::Matrices {
                fov_y_deg,
                orthographic,
            }
        }),
    ]
}

pub fn camera_choice() -> impl Strategy<Value = CameraChoice> {
    (
        camera_kind(),
        0.0f64..360.0,
        -60.0f64..60.0,
        2.5f64..9.0,
        prop_oneof![4 => 0.01f64..0.25, 1 => 0.25f64..0.6],
        prop::array::uniform3(-0.5f64..0.5),
        prop::option::weighted(0.3, prop::array::uniform2(-0.5f64..0.5)),
    )
        .prop_map(
            |(kind, azimuth, elevation, distance, near_share, look, jitter)| CameraChoice {
                kind,
                azimuth,
                elevation,
                distance,
                near_share,
                look,
                jitter,
            },
        )
}

fn view_choice() -> impl Strategy<Value = ViewChoice> {
    prop_oneof![
        8 => (camera_choice(), prop::bool::weighted(0.15))
            .prop_map(|(camera, skip_prepass)| ViewChoice::Camera { camera, skip_prepass }),
        2 => (camera_choice(), prop::sample::select(CameraDefect::ALL.to_vec()))
            .prop_map(|(camera, defect)| ViewChoice::Defective { camera, defect }),
        1 => prop::sample::select(MatrixDefect::ALL.to_vec()).prop_map(ViewChoice::Matrices),
    ]
}

fn target_defect() -> impl Strategy<Value = TargetDefect> {
    prop::sample::select(vec![
        TargetDefect::TwoSampleCounts,
        TargetDefect::UnsupportedSamples,
        TargetDefect::ColourAsDepth,
        TargetDefect::AuxWithoutAttachments,
        TargetDefect::NullRenderPass,
        TargetDefect::UndefinedColour,
    ])
}

fn op() -> impl Strategy<Value = Op> {
    let defect = || prop::sample::select(GlyphDefect::ALL.to_vec());
    prop_oneof![
        4 => Just(Op::BeginFrame),
        1 => (0u8..4).prop_map(Op::BeginFrameBadSlot),
        7 => (scene_size(), any::<u64>()).prop_map(|(size, seed)| Op::Upload { size, seed }),
        1 => (scene_size(), any::<u64>(), 0.0f64..1.0, defect())
            .prop_map(|(size, seed, at, defect)| Op::UploadDefective { size, seed, at, defect }),
        3 => (
            prop_oneof![
                6 => (0.0f64..1.0).prop_map(UpdateStart::Share),
                2 => (0u8..3).prop_map(UpdateStart::PastEnd),
                1 => Just(UpdateStart::Overflow),
            ],
            0u8..6,
            any::<u64>(),
            prop::option::weighted(0.15, defect()),
        )
            .prop_map(|(start, len, seed, defect)| Op::Update { start, len, seed, defect }),
        3 => settings_choice().prop_map(Op::Settings),
        2 => target_choice().prop_map(Op::Target),
        1 => target_defect().prop_map(Op::TargetDefective),
        1 => prop::sample::select(vec![0u32, 17, 1000]).prop_map(|frames_in_flight| {
            Op::RendererDefective { frames_in_flight }
        }),
        8 => (
            prop::collection::vec(view_choice(), 1..=3),
            prop::option::weighted(0.1, settings_choice()),
            prop::option::weighted(0.1, target_choice()),
        )
            .prop_map(|(views, settings_between, target_between)| Op::Draw(Draw {
                views,
                settings_between,
                target_between,
            })),
        5 => Just(Op::Submit),
        2 => Just(Op::SkipFrame),
        1 => prop_oneof![
            Just(WisdomChoice::RoundTrip),
            Just(WisdomChoice::Truncated),
            any::<u64>().prop_map(WisdomChoice::Garbage),
        ]
        .prop_map(Op::Wisdom),
    ]
}

/// Sequences of up to `max_ops` operations.
pub fn sequence(max_ops: usize) -> impl Strategy<Value = Sequence> {
    (
        1u32..=3,
        target_choice(),
        settings_choice(),
        prop::collection::vec(op(), 1..=max_ops),
    )
        .prop_map(|(frames_in_flight, target, settings, ops)| Sequence {
            frames_in_flight,
            target,
            settings,
            ops,
        })
}
