//! Random call sequences against the embedding API, under validation with synchronization
//! validation (issue 33, docs/testing.md): uploads of 0, 1, a few and around the chunk
//! limit's glyphs, updates in and out of range, every setting's variants, cameras of every
//! kind and degenerate ones, new targets (resizes down to one pixel, render pass or dynamic
//! rendering, either depth convention, 1 or 4 samples), views added and dropped, frames
//! submitted or skipped. Every answer must be the model's (`Ok`, or a refusal naming what
//! was wrong; a panic fails), every submitted pass must cover the pixels the offscreen
//! renderer covers for the model's scene (single-sample passes in the same colours), and
//! after each sequence the host's allocator holds what it held before and validation said
//! nothing.
//!
//! The suite runs `SUITE_SEQUENCES` sequences from a fixed seed; `ES_SEQUENCES=N` runs `N`
//! (`ES_SEQUENCES_SEED=S` from another seed, `ES_SEQUENCES_MINUTES=M` none begun after M
//! minutes), printing the figures with `--nocapture`: the long run of
//! `docs/results/sequences/`. A failing sequence is shrunk and printed; each one found is
//! kept below as a plain test.

mod sequences;

use std::cell::RefCell;
use std::time::{Duration, Instant};

use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

use sequences::cameras::{CameraChoice, CameraKind};
use sequences::glyphs::GlyphDefect;
use sequences::ops::{
    sequence, Draw, MaterialChoice, Op, SceneSize, Sequence, SettingsChoice, TargetChoice,
    ViewChoice,
};
use sequences::runner::Fixture;

/// Sequences the suite runs (under a minute on either lavapipe with validation).
const SUITE_SEQUENCES: u32 = 32;
/// The most operations in one sequence.
const MAX_OPS: usize = 24;
/// The suite's seed: the same sequences every run.
const SUITE_SEED: u64 = 33;

fn env_number(name: &str) -> Option<u64> {
    let value = std::env::var(name).ok()?;
    Some(
        value
            .parse()
            .unwrap_or_else(|_| panic!("{name}={value} is not a number")),
    )
}

#[test]
fn random_call_sequences_answer_as_the_model_says() {
    let cases = env_number("ES_SEQUENCES").map_or(SUITE_SEQUENCES, |n| n as u32);
    let seed = env_number("ES_SEQUENCES_SEED").unwrap_or(SUITE_SEED);
    let fixture = RefCell::new(Fixture::new());
    let mut config = Config::with_cases(cases);
    config.rng_seed = RngSeed::Fixed(seed);
    // A failure is shrunk and printed; each one found is kept below as a plain test (the
    // suite's seed is fixed, so a seed file would replay nothing new).
    config.failure_persistence = None;
    config.max_shrink_iters = 4096;
    let mut runner = TestRunner::new(config);
    let start = Instant::now();
    let deadline =
        env_number("ES_SEQUENCES_MINUTES").map(|minutes| start + Duration::from_secs(minutes * 60));
    let result = runner.run(&sequence(MAX_OPS), |sequence| {
        if deadline.is_some_and(|deadline| Instant::now() > deadline) {
            return Ok(()); // past the long run's time: generated, not run (not counted)
        }
        fixture
            .borrow_mut()
            .run(&sequence)
            .map_err(TestCaseError::fail)
    });
    let fixture = fixture.into_inner();
    println!(
        "{} of {cases} sequences run, from seed {seed}, in {:.1} s\n{}",
        fixture.stats.sequences,
        start.elapsed().as_secs_f64(),
        fixture.stats.report()
    );
    if let Err(failure) = result {
        panic!("{failure}");
    }
    fixture.finish();
}

/// Runs `ops` on a fixture of its own: one frame in flight, a 32x32 dynamic-rendering
/// target with reversed Z, the default settings.
fn run(ops: Vec<Op>) {
    let sequence = Sequence {
        frames_in_flight: 1,
        target: TargetChoice {
            render_pass: false,
            standard_depth: false,
            multisampled: false,
            size: 1,
        },
        settings: SettingsChoice {
            culling: 7,
            setup_once: true,
            cap_free_path: true,
            small_glyph_triangles: false,
            compact: false,
            plan: 0,
            chunk: 0,
            per_sample_shading: false,
            material: MaterialChoice::Default,
        },
        ops,
    };
    let mut fixture = Fixture::new();
    if let Err(why) = fixture.run(&sequence) {
        panic!("{why}");
    }
    fixture.finish();
}

/// A view of the glyphs' cube from above and aside.
fn view() -> ViewChoice {
    ViewChoice::Camera {
        camera: CameraChoice {
            kind: CameraKind::LookAt { fov_y_deg: 50.0 },
            azimuth: 30.0,
            elevation: 20.0,
            distance: 6.0,
            near_share: 0.05,
            look: [0.0; 3],
            jitter: None,
        },
        skip_prepass: false,
    }
}

fn upload(size: SceneSize) -> Op {
    Op::Upload { size, seed: 7 }
}

/// Found first: two passes in one command buffer copied into the test host's readback
/// buffer with no barrier between the copies (a write-after-write hazard; the host's
/// barrier after its copy now orders the next copy too).
#[test]
fn two_passes_in_one_command_buffer() {
    run(vec![
        upload(SceneSize::Few(12)),
        Draw::views(vec![view()]),
        Draw::views(vec![view(), view()]),
        Op::Submit,
    ]);
}

/// A rotation written as the zero quaternion (or NaN) was uploaded as it was: the glyph
/// vanished or smeared. It is refused now, naming the glyph, like a bad colour.
#[test]
fn a_zero_rotation_is_refused_by_name() {
    for defect in [
        GlyphDefect::ZeroRotation,
        GlyphDefect::NanRotation,
        GlyphDefect::NanColour,
    ] {
        run(vec![
            Op::UploadDefective {
                size: SceneSize::Few(5),
                seed: 3,
                at: 0.5,
                defect,
            },
            Draw::views(vec![view()]),
            Op::Submit,
        ]);
    }
}

/// One glyph far beyond float32's reach from the others spoiled the placement, and the
/// refusal named glyph 0; it now names the scene and the glyphs at both ends.
#[test]
fn an_outlier_is_refused_naming_the_scene() {
    run(vec![
        upload(SceneSize::Few(3)),
        Op::UploadDefective {
            size: SceneSize::Few(6),
            seed: 5,
            at: 0.7,
            defect: GlyphDefect::HugeCentre,
        },
        Draw::views(vec![view()]),
        Op::Submit,
    ]);
}

/// A material with a NaN weight drew every pixel with NaN shading; frames are refused by
/// name until the settings replace it (and a new renderer is refused at once).
#[test]
fn a_nan_material_is_refused_by_name() {
    let settings = |material| SettingsChoice {
        culling: 7,
        setup_once: true,
        cap_free_path: true,
        small_glyph_triangles: false,
        compact: false,
        plan: 0,
        chunk: 0,
        per_sample_shading: false,
        material,
    };
    run(vec![
        upload(SceneSize::Few(4)),
        Op::Settings(settings(MaterialChoice::NanAmbient)),
        Draw::views(vec![view()]),
        Op::Submit,
        Op::Settings(settings(MaterialChoice::Shiny)),
        Draw::views(vec![view()]),
        Op::Submit,
    ]);
}
