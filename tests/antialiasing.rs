//! Multisampled frames of the offscreen renderer resolve each pixel to the exact fraction of
//! its samples the glyphs cover: unlit white glyphs over the background, so a pixel's linear
//! light is `bg + f (1 - bg)`, and `f` times the sample count must be the float64
//! reference's count at the standard sample positions. The four standard positions of 4x
//! MSAA lie on the 4 x 4 grid `((s + 0.5) / 4, (t + 0.5) / 4)`, so the reference drawn at four
//! times the size gives each sample's answer. Both shading rates: once per pixel with the
//! exact coverage in the sample mask (the default), and once per sample; and supersampling, each
//! pixel the exact fraction of its K x K grid.

use ash::vk;
use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::{Camera, Ellipsoid, Material, Outputs, Scene, Settings, NO_INSTANCE};
use ellipsoid_splat_reference::coverage::{compare_coverage, reference_coverage, SamplePattern};
use ellipsoid_splat_reference::reference::render_reference;
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use glam::{DQuat, DVec3};

/// Twelve white glyphs, some overlapping, and one cut by the near plane (its cap shows).
fn scene() -> Scene {
    let mut glyphs: Vec<Ellipsoid> = (0..12)
        .map(|n| {
            let t = n as f64;
            Ellipsoid::new(
                DVec3::new(
                    3.0 * (t % 6.0) - 7.5,
                    if n < 6 { 2.0 } else { -2.0 } + 0.3 * (t % 6.0),
                    -0.5 * t,
                ),
                DVec3::new(1.2, 0.35 + 0.1 * t, 0.6),
                DQuat::from_rotation_z(0.5 * t + 0.2) * DQuat::from_rotation_x(0.3 * t),
                Some([1.0, 1.0, 1.0]),
            )
            .unwrap()
        })
        .collect();
    // About 1.6 in front of the eye at (0.5, 1, 16), reaching 0.6 nearer: the near plane at
    // 1.5 cuts it.
    glyphs.push(
        Ellipsoid::new(
            DVec3::new(1.0, 0.8, 14.4),
            DVec3::new(0.6, 0.25, 0.6),
            DQuat::from_rotation_z(0.3),
            Some([1.0, 1.0, 1.0]),
        )
        .unwrap(),
    );
    Scene::new(glyphs)
}

/// Unlit white: a pixel's light is the covered fraction of its samples over the background.
fn unlit() -> Settings {
    let mut settings = Settings::default();
    settings.material = Material::unlit();
    settings
}

fn camera() -> Camera {
    Camera::look_at(DVec3::new(0.5, 1.0, 16.0), DVec3::ZERO, 45.0, 1.5, 96, 64).unwrap()
}

#[test]
fn four_samples_resolve_to_the_exact_covered_fraction_at_both_shading_rates() {
    let scene = scene();
    let camera = camera();
    let big = Camera {
        width: camera.width * 4,
        height: camera.height * 4,
        ..camera
    };
    let coverage = reference_coverage(&scene, &camera, SamplePattern::Standard4).unwrap();
    // Sample 0 of the standard pattern is the 4 x 4 grid's cell (1, 0).
    let reference = render_reference(&scene, &big).unwrap();
    let mut renderer = validated_renderer();
    renderer.set_samples(vk::SampleCountFlags::TYPE_4).unwrap();
    for per_sample_shading in [false, true] {
        renderer.set_settings({
            let mut settings = unlit();
            settings.per_sample_shading = per_sample_shading;
            settings
        });
        renderer.upload(&scene).unwrap();
        let frame = renderer.render_uploaded(&camera, Outputs::ALL).unwrap().0;
        // The plan of the frame just drawn (its target is the multisampled one now).
        let plan = renderer.plan(&camera).unwrap();
        assert_eq!(
            plan.coverage_samples,
            if per_sample_shading { 1 } else { 4 }
        );
        let stats = compare_coverage(&frame, &coverage).unwrap();
        println!("per sample {per_sample_shading}: {stats}");
        assert_eq!(stats.wrong, 0, "per sample {per_sample_shading}: {stats}");
        assert!(
            stats.max_error < 0.1,
            "per sample {per_sample_shading}: {stats}"
        );
        assert!(
            stats.partly_covered > 200 && stats.compared > 5_000,
            "{stats}"
        );
        // The ID output holds sample 0's glyph: exactly the reference's when every sample is
        // shaded; shaded once per pixel, one depth per pixel may let another glyph win
        // sample 0 where two overlap within the pixel.
        let mut other_glyph = 0;
        let mut sample_zero_wrong = Vec::new();
        for j in 0..camera.height {
            for i in 0..camera.width {
                let k = frame.index(i, j);
                if coverage.ambiguous[k] {
                    continue;
                }
                let expected = reference.id[reference.index(4 * i + 1, 4 * j)];
                if (frame.id[k] != NO_INSTANCE) != (expected != NO_INSTANCE) {
                    // Each standard sample's glyph in the reference, to tell a sample
                    // numbered otherwise from a sample decided otherwise.
                    let samples = SamplePattern::Standard4
                        .cells()
                        .iter()
                        .map(|&(s, t)| reference.id[reference.index(4 * i + s, 4 * j + t)])
                        .collect::<Vec<_>>();
                    sample_zero_wrong.push(format!(
                        "pixel ({i},{j}): the frame's ID {} and colour {:?}, the reference's \
                         samples 0-3 {samples:?}",
                        frame.id[k], frame.color[k]
                    ));
                }
                other_glyph += (frame.id[k] != expected) as usize;
            }
        }
        assert!(
            sample_zero_wrong.is_empty(),
            "per sample {per_sample_shading}: {} pixels' sample 0 covered otherwise than the \
             reference's; the first: {}",
            sample_zero_wrong.len(),
            sample_zero_wrong[..sample_zero_wrong.len().min(5)].join("; ")
        );
        println!(
            "per sample {per_sample_shading}: {other_glyph} pixels show another glyph at sample 0"
        );
        if per_sample_shading {
            assert_eq!(other_glyph, 0, "sample 0's glyph differs");
        } else {
            assert!(
                other_glyph <= 20,
                "{other_glyph} pixels show another glyph at sample 0"
            );
        }
    }
    finish_validated(renderer);
}

/// `--supersample 4` (`ellipsoid_splat::supersample`) resolves each pixel to the exact fraction
/// of its 16-sample grid that the float64 reference finds covered.
#[test]
fn four_by_four_supersampling_resolves_the_exact_coverage_fraction() {
    let k = 4;
    let (scene, camera) = (scene(), camera());
    let big = supersampled_camera(&camera, k).unwrap();
    let mut renderer = validated_renderer();
    renderer.set_settings(unlit());
    let drawn = renderer.render(&scene, &big, Outputs::ALL).unwrap();
    let out = box_filter(&drawn, k).unwrap();
    let coverage = reference_coverage(&scene, &camera, SamplePattern::Grid(k)).unwrap();
    let stats = compare_coverage(&out, &coverage).unwrap();
    assert_eq!(stats.wrong, 0, "{stats}");
    assert!(stats.max_error < 0.25, "{stats}");
    assert!(
        stats.partly_covered > 200 && stats.compared > 5_000,
        "{stats}"
    );
    finish_validated(renderer);
}
