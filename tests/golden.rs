//! Golden-output regression test: a fixed list of scenes, each rendered under validation with
//! one combination of renderer settings. Every case but the benchmark's methods is compared
//! with the float64 reference (coverage, IDs, depth and normals within the accuracy bounds,
//! colours within a level of the shading model), on any driver. Bits are a property of one
//! driver build, not of conformant drivers: each read-back output (colour, view depth,
//! normal, instance ID) is also reduced to a 64-bit hash and compared with the set recorded
//! for this driver and device in `tests/golden/` (one `scene output hash` line each; any
//! differing, missing or unexpected line fails, every mismatch reported at once). A driver
//! without a recorded set is held to the reference alone, and the test says so.
//!
//! `GOLDEN_RECORD=1 cargo test --release --test golden` records this driver's set (`add` adds this host's hashes where its CPU rounds differently);
//! `GOLDEN_PRINT=1 ... -- --nocapture` prints the computed lines.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

#[cfg(feature = "research")]
use ellipsoid_splat::research::DrawConfig;
#[cfg(feature = "research")]
use ellipsoid_splat::research::Method;
use ellipsoid_splat::{PathKind, PlanMode};

/// Without `research` every case draws the shipped impostor.
#[cfg(not(feature = "research"))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct DrawConfig {}
use ellipsoid_splat::Culling;
use ellipsoid_splat::InstanceFormat;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat::{
    Camera, DepthConvention, Ellipsoid, Frame, Outputs, Projection, Scene, Settings, NO_INSTANCE,
};
use ellipsoid_splat_loaders::{random_cloud, tensor_field};
use ellipsoid_splat_reference::compare::compare;
use ellipsoid_splat_reference::reference::render_reference;
use ellipsoid_splat_reference::shading::compare_colors;
use ellipsoid_splat_reference::testing::{bounds_for, finish_validated, validated_renderer, Seen};
use glam::{DMat3, DQuat, DVec3};

// ---------------------------------------------------------------------------------------------
// Hashing

/// FNV-1a, 64 bits.
struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// A hash of one output: the frame's width and height, then the values, all little-endian.
fn hash_output(frame: &Frame, values: impl FnOnce(&mut Fnv1a)) -> u64 {
    let mut h = Fnv1a::new();
    h.u32(frame.width);
    h.u32(frame.height);
    values(&mut h);
    h.0
}

/// The four outputs of a frame and their hashes, in a fixed order.
fn hash_frame(frame: &Frame) -> [(&'static str, u64); 4] {
    let color = hash_output(frame, |h| frame.color.iter().for_each(|c| h.bytes(c)));
    let depth = hash_output(frame, |h| {
        frame.depth.iter().for_each(|d| h.u32(d.to_bits()))
    });
    let normal = hash_output(frame, |h| {
        frame
            .normal
            .iter()
            .flatten()
            .for_each(|n| h.u32(n.to_bits()))
    });
    let id = hash_output(frame, |h| frame.id.iter().for_each(|&i| h.u32(i)));
    [
        ("color", color),
        ("depth", depth),
        ("normal", normal),
        ("id", id),
    ]
}

// ---------------------------------------------------------------------------------------------
// Cameras

fn orthographic(eye: DVec3, target: DVec3, height: f64, near: f64, w: u32, h: u32) -> Camera {
    Camera::new(
        eye,
        target,
        DVec3::Y,
        Projection::Orthographic { height },
        near,
        w,
        h,
    )
    .expect("camera")
}

/// Standard Z (0 at the near plane), infinite far plane.
fn standard_infinite(camera: Camera) -> Camera {
    camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention")
}

/// Standard Z with a finite far plane at view depth 60 (beyond every scene).
fn standard_far(camera: Camera) -> Camera {
    camera
        .with_depth(DepthConvention {
            reversed: false,
            far: Some(60.0),
        })
        .expect("depth convention")
}

/// Reversed Z (1 at the near plane) with a finite far plane at view depth 60.
fn reversed_far(camera: Camera) -> Camera {
    camera
        .with_depth(DepthConvention {
            reversed: true,
            far: Some(60.0),
        })
        .expect("depth convention")
}

/// The camera looking from inside a cloud, shared by the near-plane scenes.
fn inside_camera() -> Camera {
    Camera::look_at(
        DVec3::new(0.5, 0.2, 1.0),
        DVec3::new(-4.0, -3.0, -6.0),
        70.0,
        0.3,
        320,
        240,
    )
    .unwrap()
}

// ---------------------------------------------------------------------------------------------
// Scenes (deterministic: fixed sizes and seeds)

/// The 6^3 tensor-field demo lattice, framed from the oblique default view at 320x200.
fn tensor_field_6() -> (Scene, Camera) {
    let camera = Camera::framing(DVec3::ZERO, 5.5, 320, 200).expect("camera");
    (tensor_field(6), camera)
}

/// 300 overlapping random ellipsoids (seed 7) in perspective at 320x240.
fn cloud_300() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(4.0, 3.0, 9.0), DVec3::ZERO, 50.0, 0.5, 320, 240).unwrap();
    (random_cloud(300, 7, 3.0, 0.8), camera)
}

/// 200 random ellipsoids (seed 11) seen orthographically at 300x200.
fn ortho_200() -> (Scene, Camera) {
    let camera = orthographic(DVec3::new(-5.0, 4.0, 8.0), DVec3::ZERO, 9.0, 0.5, 300, 200);
    (random_cloud(200, 11, 3.0, 0.8), camera)
}

/// The eye inside a 1,500-ellipsoid cloud (seed 42), the near plane cutting glyphs, plus one
/// glyph holding the eye whose cap covers about the right half of the 320x240 image.
fn inside_cloud() -> (Scene, Camera) {
    let camera = inside_camera();
    let mut scene = random_cloud(1_500, 42, 6.0, 0.6);
    let b = camera.basis();
    let aligned = DQuat::from_mat3(&DMat3::from_cols(b.right, b.up, -b.forward));
    let tilt = DQuat::from_axis_angle(DVec3::new(0.3, 1.0, 0.2).normalize(), 0.15);
    let holder = Ellipsoid::new(
        camera.eye + b.right * 0.45,
        DVec3::new(0.5, 0.9, 1.2),
        aligned * tilt,
        Some([0.85, 0.55, 0.25]),
    )
    .expect("eye-holding glyph");
    scene.ellipsoids.push(holder);
    (scene, camera)
}

/// 20,000 glyphs (seed 21) of one or two pixels each, in perspective at 320x240: small enough
/// for the pre-pass to set them up.
fn tiny_glyphs() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(2.0, 3.0, 25.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    (random_cloud(20_000, 21, 10.0, 0.06), camera)
}

/// The 20,000 tiny glyphs seen orthographically at 320x240.
fn tiny_glyphs_ortho() -> (Scene, Camera) {
    let (scene, perspective) = tiny_glyphs();
    let camera = Camera {
        projection: Projection::Orthographic { height: 22.0 },
        ..perspective
    };
    (scene, camera)
}

/// 600 randomly rotated spheres (seed 41), all clear of the near plane, in perspective at
/// 320x240.
fn spheres() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(3.0, 4.0, 14.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    (sphere_cloud(600, 41, 4.0, 0.7), camera)
}

/// The 600 spheres seen orthographically at 320x240.
fn spheres_ortho() -> (Scene, Camera) {
    let camera = orthographic(DVec3::new(3.0, 4.0, 14.0), DVec3::ZERO, 11.0, 1.0, 320, 240);
    (sphere_cloud(600, 41, 4.0, 0.7), camera)
}

/// The eye inside 1,500 spheres (seed 43), the near plane cutting some, at 320x240.
fn spheres_inside() -> (Scene, Camera) {
    (sphere_cloud(1_500, 43, 6.0, 0.6), inside_camera())
}

/// 3,000 random glyphs (seed 11), several chunks' worth at 256 instances per chunk, 320x240.
fn chunk_cloud() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(4.0, 5.0, 22.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    (random_cloud(3_000, 11, 8.0, 0.5), camera)
}

/// 3,000 small glyphs (seed 12) the pre-pass sets up, for chunking, at 320x240.
fn chunk_cloud_small() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(4.0, 5.0, 40.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    (random_cloud(3_000, 12, 8.0, 0.12), camera)
}

/// A random cloud with every glyph made a sphere of its first semi-axis; each keeps its random
/// rotation, which the sphere path must ignore.
fn sphere_cloud(count: usize, seed: u64, extent: f64, radius: f64) -> Scene {
    let mut scene = random_cloud(count, seed, extent, radius);
    for e in &mut scene.ellipsoids {
        e.radii = DVec3::splat(e.radii.x);
    }
    scene
}

// ---------------------------------------------------------------------------------------------
// Renderer settings

/// Every renderer setting a case may change, applied in full before each case so that no case
/// depends on the one before.
#[derive(Clone, Copy)]
struct CaseSettings {
    config: DrawConfig,
    format: InstanceFormat,
    culling: Culling,
    setup_once: bool,
    small_glyph_triangles: bool,
    cap_free_path: bool,
    max_chunk_instances: u32,
    plan: PlanMode,
    /// The benchmark's tiled splat in splatted frames (`research`).
    tiled_splat: bool,
}

impl CaseSettings {
    /// The renderer as shipped.
    fn shipped() -> CaseSettings {
        CaseSettings {
            config: DrawConfig::default(),
            format: InstanceFormat::Full,
            culling: Culling::ON,
            setup_once: true,
            small_glyph_triangles: false,
            cap_free_path: true,
            max_chunk_instances: u32::MAX,
            plan: PlanMode::Fixed(PathKind::Draw),
            tiled_splat: false,
        }
    }

    /// Sets everything on `renderer`; the scene must be uploaded afterwards (the instance
    /// format and the chunk size take effect at the upload).
    fn apply(&self, renderer: &mut OffscreenRenderer) {
        #[cfg(feature = "research")]
        {
            renderer.set_draw_config(self.config);
            renderer.set_tiled_splat(self.tiled_splat);
        }
        #[cfg(not(feature = "research"))]
        assert_eq!(
            self.config,
            DrawConfig::default(),
            "baselines need `research`"
        );
        #[cfg(not(feature = "research"))]
        assert!(!self.tiled_splat, "the tiled splat needs `research`");
        renderer.set_settings({
            let mut settings = Settings::default();
            settings.instance_format = self.format;
            settings.culling = self.culling;
            settings.setup_once = self.setup_once;
            settings.small_glyph_triangles = self.small_glyph_triangles;
            settings.cap_free_path = self.cap_free_path;
            settings.max_chunk_instances = self.max_chunk_instances;
            settings.plan = self.plan;
            settings
        });
    }
}

/// What a case asserts about the draw, so that it cannot silently stop covering its path.
#[derive(Clone, Copy, Default)]
struct Expect {
    /// `FramePlan::setup_once` after the upload.
    setup_once: Option<bool>,
    /// `FramePlan::no_caps`.
    cap_free: Option<bool>,
}

/// Builds a scene and the camera it is seen with.
type SceneFn = fn() -> (Scene, Camera);
/// Changes a scene's camera (here: its depth convention).
type CameraFn = fn(Camera) -> Camera;

/// One rendered case: a name (no spaces), a scene with its camera, and the settings.
struct Case {
    name: String,
    scene: SceneFn,
    camera: CameraFn,
    settings: CaseSettings,
    expect: Expect,
}

fn case(name: &str, scene: SceneFn, settings: CaseSettings, expect: Expect) -> Case {
    Case {
        name: name.to_string(),
        scene,
        camera: |c| c,
        settings,
        expect,
    }
}

fn setup_once(on: bool) -> Expect {
    Expect {
        setup_once: Some(on),
        ..Expect::default()
    }
}

fn cap_free(on: bool) -> Expect {
    Expect {
        cap_free: Some(on),
        ..Expect::default()
    }
}

/// The whole list, in a fixed order.
fn cases() -> Vec<Case> {
    let shipped = CaseSettings::shipped();
    let none = Expect::default();
    let mut list = vec![
        // Scenes with the shipped renderer.
        case("tensor-field-6", tensor_field_6, shipped, cap_free(true)),
        case("cloud-300", cloud_300, shipped, cap_free(true)),
        case("ortho-200", ortho_200, shipped, cap_free(true)),
        case("inside-cloud", inside_cloud, shipped, cap_free(false)),
        case("tiny-glyphs", tiny_glyphs, shipped, setup_once(true)),
        case(
            "tiny-glyphs-ortho",
            tiny_glyphs_ortho,
            shipped,
            setup_once(true),
        ),
        // The compute splat must give the draw's very bits (the expected lines are the draw's,
        // recorded before the splat existed).
        case(
            "tiny-glyphs-compute",
            tiny_glyphs,
            CaseSettings {
                plan: PlanMode::Fixed(PathKind::Splat),
                ..shipped
            },
            setup_once(false),
        ),
        case(
            "tiny-glyphs-ortho-compute",
            tiny_glyphs_ortho,
            CaseSettings {
                plan: PlanMode::Fixed(PathKind::Splat),
                ..shipped
            },
            setup_once(false),
        ),
        case("spheres", spheres, shipped, cap_free(true)),
        case("spheres-ortho", spheres_ortho, shipped, cap_free(true)),
        case("spheres-inside", spheres_inside, shipped, cap_free(false)),
        // The cap-free variant switched off: the general shaders on spheres.
        case(
            "spheres-general",
            spheres,
            CaseSettings {
                cap_free_path: false,
                ..shipped
            },
            cap_free(false),
        ),
        // Compact instances.
        case(
            "cloud-300-compact",
            cloud_300,
            CaseSettings {
                format: InstanceFormat::Compact,
                ..shipped
            },
            none,
        ),
        case(
            "tiny-glyphs-compact",
            tiny_glyphs,
            CaseSettings {
                format: InstanceFormat::Compact,
                ..shipped
            },
            setup_once(true),
        ),
        // Chunks of 256 instances.
        case(
            "chunks",
            chunk_cloud,
            CaseSettings {
                max_chunk_instances: 256,
                ..shipped
            },
            setup_once(false),
        ),
        case(
            "chunks-small",
            chunk_cloud_small,
            CaseSettings {
                max_chunk_instances: 256,
                ..shipped
            },
            setup_once(true),
        ),
        // Culling switched off, wholly or in part.
        case(
            "cloud-300-cull-off",
            cloud_300,
            CaseSettings {
                culling: Culling::OFF,
                ..shipped
            },
            none,
        ),
        case(
            "cloud-300-cull-frustum",
            cloud_300,
            CaseSettings {
                culling: {
                    let mut culling = Culling::OFF;
                    culling.frustum = true;
                    culling.pixel_centres = false;
                    culling.occlusion = false;
                    culling
                },
                ..shipped
            },
            none,
        ),
        case(
            "cloud-300-cull-no-occlusion",
            cloud_300,
            CaseSettings {
                culling: {
                    let mut culling = Culling::OFF;
                    culling.frustum = true;
                    culling.pixel_centres = true;
                    culling.occlusion = false;
                    culling
                },
                ..shipped
            },
            none,
        ),
        case(
            "tiny-glyphs-cull-off",
            tiny_glyphs,
            CaseSettings {
                culling: Culling::OFF,
                ..shipped
            },
            setup_once(true),
        ),
        // The set-up in the pre-pass switched off.
        case(
            "tiny-glyphs-no-setup",
            tiny_glyphs,
            CaseSettings {
                setup_once: false,
                ..shipped
            },
            setup_once(false),
        ),
        // Small glyphs drawn as one triangle.
        case(
            "tiny-glyphs-triangles",
            tiny_glyphs,
            CaseSettings {
                small_glyph_triangles: true,
                ..shipped
            },
            none,
        ),
    ];
    // Depth conventions other than the default (reversed, infinite far plane).
    let conventions: [(&str, CameraFn); 3] = [
        ("standard-infinite", standard_infinite),
        ("standard-far", standard_far),
        ("reversed-far", reversed_far),
    ];
    for (suffix, camera) in conventions {
        for (base, scene) in [
            ("cloud-300", cloud_300 as SceneFn),
            ("ortho-200", ortho_200),
            ("inside-cloud", inside_cloud),
        ] {
            let mut c = case(&format!("{base}-{suffix}"), scene, shipped, none);
            c.camera = camera;
            list.push(c);
        }
    }
    // Every bench method on the 300-glyph cloud, with its own instance format (the baselines
    // exist only with the `research` feature).
    #[cfg(feature = "research")]
    for method in Method::ALL {
        list.push(case(
            &format!("{METHOD_CASE_PREFIX}{}", method.name()),
            cloud_300,
            CaseSettings {
                config: method.config(),
                format: method.settings().instance_format,
                plan: method.settings().plan,
                tiled_splat: method.tiled_splat(),
                ..shipped
            },
            none,
        ));
    }
    list
}

// ---------------------------------------------------------------------------------------------
// Running and comparing

/// Renders one case and checks what it expects; returns the frame.
fn render_case(renderer: &mut OffscreenRenderer, case: &Case) -> Frame {
    let (scene, camera) = (case.scene)();
    let camera = (case.camera)(camera);
    case.settings.apply(renderer);
    renderer.upload(&scene).expect("upload");
    if let Some(want) = case.expect.setup_once {
        assert_eq!(
            renderer.plan(&camera).expect("plan").setup_once(),
            want,
            "{}: set-up in the pre-pass",
            case.name
        );
    }
    if let Some(want) = case.expect.cap_free {
        assert_eq!(
            renderer.plan(&camera).expect("plan").no_caps,
            want,
            "{}: the cap-free shader variant",
            case.name
        );
    }
    let (frame, _) = renderer
        .render_uploaded(&camera, Outputs::ALL)
        .expect("render");
    assert_eq!((frame.width, frame.height), (camera.width, camera.height));
    let shown = frame.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    assert!(
        shown >= frame.len() / 50,
        "{}: only {shown} of {} pixels show a glyph",
        case.name,
        frame.len()
    );
    frame
}

/// Names of the cases drawn with the benchmark's methods.
const METHOD_CASE_PREFIX: &str = "cloud-300-method-";

/// The cases drawn with the benchmark's methods are held to their own driver's bits only:
/// `tests/methods.rs` holds each method to what it promises against the reference (the
/// exact ones to the strict bounds, the baselines -- textbook intersection, box proxy,
/// meshes, flat fill -- to their own), and the baselines' unstable arithmetic rounds
/// differently from one driver build to the next.
fn is_method_case(case: &Case) -> bool {
    case.name.starts_with(METHOD_CASE_PREFIX)
}

/// A case's frame against the float64 reference: geometry within the accuracy bounds (the
/// compact format's and standard Z's own where they apply), colours within a level of the
/// shading model.
fn check_against_reference(case: &Case, frame: &Frame) -> Result<String, String> {
    let (scene, camera) = (case.scene)();
    let camera = (case.camera)(camera);
    let reference = render_reference(&scene, &camera).expect("reference render");
    let stats = compare(frame, &reference).expect("same size");
    let bounds = bounds_for(Seen {
        scene: &scene,
        camera: &camera,
        format: case.settings.format,
    });
    let colors = compare_colors(frame, &scene, &camera, &Settings::default().material)
        .expect("colour comparison");
    let mut problems: Vec<String> = [stats.check(&bounds), colors.check()]
        .into_iter()
        .filter_map(Result::err)
        .collect();
    if stats.covered_pixels < frame.len() / 50 {
        problems.push(format!(
            "the reference covers only {} pixels",
            stats.covered_pixels
        ));
    }
    if problems.is_empty() {
        Ok(format!("{stats}; {colors}"))
    } else {
        Err(format!(
            "{}\n    {stats}\n    {colors}",
            problems.join("; ")
        ))
    }
}

/// The file of hashes recorded on this driver and device: `tests/golden/<driver>__<device>.txt`,
/// each lowercased, every run of other characters than letters, digits and dots one `-`.
fn hashes_path(driver: &str, device: &str) -> PathBuf {
    let slug = |text: &str| {
        let mut slug = String::new();
        for c in text.chars().flat_map(char::to_lowercase) {
            if c.is_ascii_alphanumeric() || c == '.' {
                slug.push(c);
            } else if !slug.is_empty() && !slug.ends_with('-') {
                slug.push('-');
            }
        }
        slug.trim_end_matches('-').to_string()
    };
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!(
        "tests/golden/{}__{}.txt",
        slug(driver),
        slug(device)
    ))
}

/// `scene output` -> the hashes recorded for it, from the file's lines (blank lines and `#`
/// comments skipped). An output may be listed more than once: lavapipe compiles its shaders
/// for the host CPU, so hosts with other vector extensions (AVX-512 or not) round some
/// outputs differently on the same driver build, and each host's hash is recorded.
fn parse_expected(text: &str) -> BTreeMap<(String, String), Vec<String>> {
    let mut expected: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        match fields[..] {
            [scene, output, hash]
                if hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit()) =>
            {
                let key = (scene.to_string(), output.to_string());
                let hashes = expected.entry(key).or_default();
                let hash = hash.to_ascii_lowercase();
                assert!(
                    !hashes.contains(&hash),
                    "line {}: `{scene} {output} {hash}` listed twice",
                    k + 1
                );
                hashes.push(hash);
            }
            _ => panic!(
                "line {}: expected `scene output hash` (16 hex digits), got `{line}`",
                k + 1
            ),
        }
    }
    expected
}

/// Every computed hash against the recorded set: what differs, is missing or is extra.
fn hash_problems(
    computed: &[(String, &'static str, String)],
    mut expected: BTreeMap<(String, String), Vec<String>>,
) -> Vec<String> {
    if cfg!(not(feature = "research")) {
        expected.retain(|(scene, _), _| !scene.starts_with(METHOD_CASE_PREFIX));
    }
    let mut problems = Vec::new();
    for (scene, output, hash) in computed {
        match expected.remove(&(scene.clone(), output.to_string())) {
            Some(want) if want.contains(hash) => {}
            Some(want) => problems.push(format!(
                "{scene} {output}: expected {}, got {hash}",
                want.join(" or ")
            )),
            None => problems.push(format!("{scene} {output}: not recorded (computed {hash})")),
        }
    }
    for ((scene, output), want) in expected {
        problems.push(format!(
            "{scene} {output}: recorded ({}) but not rendered",
            want.join(", ")
        ));
    }
    problems
}

/// The host CPU's vector extensions that change how lavapipe's compiled shaders round.
fn host_vectors() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            return "AVX-512";
        }
        if std::arch::is_x86_feature_detected!("fma") {
            return "AVX2 and FMA";
        }
    }
    "no AVX-512 or FMA"
}

/// Every case against the float64 reference on any driver, and bit for bit against the
/// hashes recorded on this driver and device where there are some (`GOLDEN_RECORD=1`
/// records them; `GOLDEN_PRINT=1` prints the computed lines).
#[test]
fn outputs_match_the_reference_and_this_drivers_golden_hashes() {
    let mut renderer = validated_renderer();
    let info = renderer.context().info().clone();
    let mut computed: Vec<(String, &'static str, String)> = Vec::new();
    let mut off_reference = Vec::new();
    let mut checked = 0;
    for case in cases() {
        let frame = render_case(&mut renderer, &case);
        for (output, hash) in hash_frame(&frame) {
            computed.push((case.name.clone(), output, format!("{hash:016x}")));
        }
        if !is_method_case(&case) {
            checked += 1;
            match check_against_reference(&case, &frame) {
                Ok(figures) => println!("{}: {figures}", case.name),
                Err(why) => off_reference.push(format!("{}: {why}", case.name)),
            }
        }
    }
    finish_validated(renderer);
    assert!(
        off_reference.is_empty(),
        "{} of {checked} cases differ from the float64 reference:\n{}",
        off_reference.len(),
        off_reference.join("\n")
    );

    let mut lines = format!(
        "# Golden hashes: tests/golden.rs on {} with driver {}.\n",
        info.name, info.driver
    );
    for (scene, output, hash) in &computed {
        writeln!(lines, "{scene} {output} {hash}").unwrap();
    }
    let path = hashes_path(&info.driver, &info.name);
    let flag = |name: &str| std::env::var(name).is_ok_and(|v| v == "1");
    if flag("GOLDEN_PRINT") {
        println!(
            "---- computed hashes ({} lines) ----\n{lines}----",
            computed.len()
        );
    }
    if flag("GOLDEN_RECORD") {
        std::fs::write(&path, &lines).expect("write the golden hashes");
        println!("recorded {} hashes in {}", computed.len(), path.display());
        return;
    }
    // `GOLDEN_RECORD=add`: this host's hashes beside those recorded (another CPU's rounding).
    if std::env::var("GOLDEN_RECORD").is_ok_and(|v| v == "add") {
        let recorded = std::fs::read_to_string(&path).unwrap_or_default();
        let known = parse_expected(&recorded);
        let mut added = format!(
            "# Added on a host with {} (lavapipe rounds some outputs by the host CPU).\n",
            host_vectors()
        );
        let mut count = 0;
        for (scene, output, hash) in &computed {
            let key = (scene.clone(), output.to_string());
            if !known.get(&key).is_some_and(|h| h.contains(hash)) {
                writeln!(added, "{scene} {output} {hash}").unwrap();
                count += 1;
            }
        }
        if count > 0 {
            let text = if recorded.is_empty() {
                lines
            } else {
                recorded + &added
            };
            std::fs::write(&path, text).expect("write the golden hashes");
        }
        println!("added {count} hashes to {}", path.display());
        return;
    }
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // Straight to stderr, past the harness's capture: a passing run says it too.
            let note = format!(
                "golden: no hashes are recorded for driver {} on {} ({}): {checked} cases \
                 compared with the float64 reference only; GOLDEN_RECORD=1 records them\n",
                info.driver,
                info.name,
                path.display()
            );
            let _ = std::io::Write::write_all(&mut std::io::stderr(), note.as_bytes());
            return;
        }
        Err(e) => panic!("{}: {e}", path.display()),
    };
    let problems = hash_problems(&computed, parse_expected(&text));
    assert!(
        problems.is_empty(),
        "{} of {} outputs differ from {} (every non-baseline case is within the reference's \
         bounds{}):\n{}",
        problems.len(),
        computed.len(),
        path.display(),
        if info.name.contains("llvmpipe") {
            format!(
                "; this host has {}: where only its rounding differs, GOLDEN_RECORD=add \
                 records its hashes beside the others",
                host_vectors()
            )
        } else {
            String::new()
        },
        problems.join("\n")
    );
}

#[test]
fn hash_files_are_named_by_driver_and_device() {
    let path = hashes_path(
        "llvmpipe (Mesa 22.3.6 (LLVM 15.0.6))",
        "llvmpipe (LLVM 15.0.6, 256 bits)",
    );
    assert!(path.ends_with(
        "tests/golden/llvmpipe-mesa-22.3.6-llvm-15.0.6__llvmpipe-llvm-15.0.6-256-bits.txt"
    ));
}
