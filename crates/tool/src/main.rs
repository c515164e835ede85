//! The `ellipsoid-splat` command-line tool.

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;

use ellipsoid_splat::research::Intersection;
use ellipsoid_splat::research::Method;
use ellipsoid_splat::Context;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat_loaders::Progress;
use ellipsoid_splat_tool::antialias_bench;
use ellipsoid_splat_tool::antialias_stress::{
    antialias_points, run_antialias_point, write_antialias_report, AntialiasMode,
};
use ellipsoid_splat_tool::bench;
use ellipsoid_splat_tool::camera_setup;
use ellipsoid_splat_tool::cli::{
    BenchArgs, Cli, Command, ConformanceArgs, DeviceArgs, RenderArgs, StressArgs,
};
use ellipsoid_splat_tool::error::{Error, Result};
use ellipsoid_splat_tool::output::{self, Image};
use ellipsoid_splat_tool::plan;
use ellipsoid_splat_tool::render_device;
use ellipsoid_splat_tool::scene_io;
use ellipsoid_splat_tool::sequence;
use ellipsoid_splat_tool::skip;
use ellipsoid_splat_tool::stress::{run_point, sweep_points, write_report, Extent, StressResult};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => render(&RenderArgs::default()),
        Some(Command::Render(args)) => render(&args),
        Some(Command::Stress(args)) => return stress(&args),
        Some(Command::Bench(args)) => return bench(&args),
        Some(Command::Info(args)) => info(&args),
        Some(Command::Conformance(args)) => return conformance(&args),
        Some(Command::View(args)) => ellipsoid_splat_tool::view::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn render(args: &RenderArgs) -> Result<()> {
    if let Some(range) = args.frames {
        let report = sequence::render_sequence(args, range)?;
        let movie = args
            .movie
            .as_ref()
            .map(|m| format!(" and {}", m.display()))
            .unwrap_or_default();
        println!(
            "wrote {} frame{} of {}{movie} in {:.2} s ({:.0} ms a frame end to end, {:.1} ms \
             the median frame on the device)",
            report.frames,
            if report.frames == 1 { "" } else { "s" },
            args.scene,
            report.total.as_secs_f64(),
            report.total.as_secs_f64() * 1e3 / report.frames.max(1) as f64,
            report.median_frame.as_secs_f64() * 1e3
        );
        return Ok(());
    }
    let start = Instant::now();
    // Every argument, the scene's size and the output files, before anything is allocated.
    let plan = args.check()?;
    let loaded = scene_io::load_colored(&plan.scene, &args.load)?;
    for note in &loaded.notes {
        eprintln!("{}: {note}", args.scene);
    }
    let scene = loaded.scene;
    let camera = camera_setup::camera_for(args, &scene)?;
    if let Some(warning) = camera_setup::nothing_in_view(args, &camera, &scene) {
        eprintln!("warning: {warning}");
    }
    scene_io::save_scene(args, &scene, &camera)?;
    let load_time = start.elapsed();

    // Only the targets of the outputs asked for are allocated, drawn and read back.
    let outputs = plan.outputs;
    let mut prepared = render_device::prepare(args, &scene, &camera, outputs)?;
    let setup = start.elapsed() - load_time;
    let (frame, timing) = prepared.draw(args.supersample, outputs)?;
    let warm = prepared.warm;
    let renderer = prepared.renderer;
    let plan_line = renderer.last_plan().map(|last| {
        let note = if warm.settled {
            ""
        } else {
            " (the plan had not settled: no more frames are drawn first)"
        };
        format!(
            "plan: {}; frame {} of its camera{note}",
            plan::describe(last),
            warm.frames + 1
        )
    });

    for image in Image::all_in(outputs) {
        if let Some(path) = args.file(image) {
            output::write_image(&frame, image, path)?;
        }
    }
    let device = renderer.context().info().name.clone();
    let memory = renderer.gpu_memory_bytes();
    drop(renderer);
    println!(
        "wrote {} ({}x{}, {} ellipsoids) in {:.0} ms: scene {:.0} ms, set-up (device, upload, \
         plan) {:.0} ms, \
         frame {:.1} ms (submit to fence) on {device}; GPU memory {:.1} MiB ({:.1} bytes per \
         ellipsoid)",
        args.output.display(),
        args.width,
        args.height,
        scene.len(),
        start.elapsed().as_secs_f64() * 1e3,
        load_time.as_secs_f64() * 1e3,
        setup.as_secs_f64() * 1e3,
        timing.gpu_wall.as_secs_f64() * 1e3,
        memory as f64 / (1 << 20) as f64,
        memory as f64 / scene.len().max(1) as f64,
    );
    if let Some(line) = plan_line {
        println!("{line}");
    }
    Ok(())
}

/// Runs the stability sweep; exit status 1 when a stable-method point breaks a bound, 2 on
/// an error.
fn stress(args: &StressArgs) -> ExitCode {
    match run_stress(args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run_stress(args: &StressArgs) -> Result<bool> {
    output::check_output_dir("--out", &args.out, "stress.csv")?;
    let extent = if args.quick {
        Extent::Reduced
    } else {
        Extent::Full
    };
    let points = sweep_points(extent);
    let mut methods = vec![Intersection::Stable];
    if !args.no_baseline {
        methods.push(Intersection::Textbook);
    }
    let mut renderer = OffscreenRenderer::new(&render_device::context_options(&args.device))?;
    let progress = Progress::new((points.len() * methods.len()) as u64, "stress");
    let mut results = Vec::new();
    for point in &points {
        for &method in &methods {
            progress.inc(&format!(
                "{} {} {}",
                point.sweep, point.case, point.parameter
            ));
            results.push(run_point(&mut renderer, point, method)?);
        }
    }
    progress.finish();
    // The antialiased points: each in every mode.
    let mut antialiased = Vec::new();
    for point in &antialias_points() {
        for mode in AntialiasMode::ALL {
            antialiased.push(run_antialias_point(&mut renderer, point, mode)?);
        }
    }
    renderer.context().check_validation()?;
    renderer.finish()?;
    let table = write_report(&results, extent.size(), &args.out)?;
    println!("{table}");
    println!("{}", write_antialias_report(&antialiased, &args.out)?);
    let antialias_broken = antialiased.iter().filter(|r| !r.exact()).count();
    println!(
        "antialiased: {} of {} points resolve every pixel to the reference's covered samples",
        antialiased.len() - antialias_broken,
        antialiased.len()
    );
    let broken: Vec<&StressResult> = results
        .iter()
        .filter(|r| r.method == Intersection::Stable && r.broken.is_some())
        .collect();
    let baseline_broken = results
        .iter()
        .filter(|r| r.method == Intersection::Textbook && r.broken.is_some())
        .count();
    println!(
        "stable: {} of {} points within every bound; textbook baseline: {} of {} points break a bound",
        results.iter().filter(|r| r.method == Intersection::Stable).count() - broken.len(),
        points.len(),
        baseline_broken,
        if args.no_baseline { 0 } else { points.len() },
    );
    for r in &broken {
        println!(
            "BROKEN {} {} {}: {}",
            r.sweep,
            r.case,
            r.parameter,
            r.broken.as_deref().unwrap_or_default()
        );
    }
    println!(
        "wrote {}/stress.csv, stress_aa.csv and stress_*.png",
        args.out.display()
    );
    Ok(broken.is_empty() && antialias_broken == 0)
}

/// Runs the time-versus-error benchmark; exit status 1 when a target is missed, 2 on error.
fn bench(args: &BenchArgs) -> ExitCode {
    match run_bench(args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run_bench(args: &BenchArgs) -> Result<bool> {
    if args.frames == 0 {
        return Err(Error::invalid("--frames", "must be at least 1"));
    }
    if args.skip || args.antialias {
        let given = [
            ("--methods", !args.methods.is_empty()),
            ("--scenes", !args.scenes.is_empty()),
            ("--scene", !args.scene.is_empty()),
            ("--orbit", args.orbit.is_some()),
        ];
        if let Some((flag, _)) = given.into_iter().find(|(_, given)| *given) {
            return Err(Error::invalid(
                flag,
                "does not apply to --skip or --antialias, which measure their own methods and \
                 scenes",
            ));
        }
        if args.antialias {
            output::check_output_dir("--out", &args.out, "antialias.csv")?;
            let results = antialias_bench::run(
                &render_device::context_options(&args.device),
                args.frames,
                &antialias_bench::scenes(),
            )?;
            println!("{}", antialias_bench::write_report(&results, &args.out)?);
            return Ok(true);
        }
        output::check_output_dir("--out", &args.out, "skip.csv")?;
        return run_skip(args);
    }
    let methods: Vec<Method> = if args.methods.is_empty() {
        // The tiled splat is a research method that did not pay (docs/deep-scenes.md) and its
        // lists outgrow device memory on the scaling clouds (`bench --quick` stopped with out
        // of memory): it runs where --methods names it, like the traced path.
        Method::ALL
            .into_iter()
            .filter(|&m| m != Method::ImpostorTiled)
            .collect()
    } else {
        args.methods
            .iter()
            .map(|name| {
                Method::ALL
                    .iter()
                    .chain(&Method::TRACED)
                    .copied()
                    .find(|m| m.name() == *name)
                    .ok_or_else(|| {
                        Error::invalid(
                            "--methods",
                            format!(
                                "unknown method '{name}'; known: {}",
                                Method::ALL
                                    .iter()
                                    .chain(&Method::TRACED)
                                    .map(|m| m.name())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        )
                    })
            })
            .collect::<Result<_>>()?
    };
    // The camera and loader flags are for the user's scenes: the built-in ones have theirs.
    if args.scene.is_empty() {
        let flag = args
            .camera
            .given()
            .or(args.width.map(|_| "--width"))
            .or(args.height.map(|_| "--height"))
            .or(args.load.given());
        if let Some(flag) = flag {
            return Err(Error::invalid(
                flag,
                "applies to the scenes of --scene; the built-in scenes have their own cameras \
                 and loading",
            ));
        }
    }
    // With --scene alone, only the user's scenes run; --scenes picks built-in ones besides.
    let builtin = |name: &str| {
        if args.scenes.is_empty() {
            args.scene.is_empty()
        } else {
            args.scenes.iter().any(|s| name.contains(s.as_str()))
        }
    };
    let specs: Vec<(usize, f64)> = bench::cloud_specs(args.quick)
        .into_iter()
        .filter(|&(_, size)| builtin(&format!("cloud-{size}px")))
        .collect();
    let with_field = builtin("tensor-field");
    let with_lattice = builtin("lattice");
    let with_liquid = builtin("md-liquid");
    let builtin_count =
        specs.len() + with_field as usize + with_lattice as usize + with_liquid as usize;
    if builtin_count == 0 && !args.scenes.is_empty() {
        let mut names = vec![
            "tensor-field".to_string(),
            "lattice".to_string(),
            "md-liquid".to_string(),
        ];
        for (_, size) in bench::cloud_specs(args.quick) {
            let name = format!("cloud-{size}px");
            if !names.contains(&name) {
                names.push(name);
            }
        }
        return Err(Error::invalid(
            "--scenes",
            format!(
                "'{}' matches no scene; the scenes are {}",
                args.scenes.join(","),
                names.join(", ")
            ),
        ));
    }
    output::check_output_dir("--out", &args.out, "results.csv")?;
    // The user's scenes are read (and a bad file or flag reported) before the device opens.
    let taken: Vec<String> = ["tensor-field", "lattice", "md-liquid"]
        .into_iter()
        .map(String::from)
        .chain(specs.iter().map(|(_, size)| format!("cloud-{size}px")))
        .collect();
    let (user_scenes, messages) = bench::user_scenes(args, &taken)?;
    for message in &messages {
        eprintln!("{message}");
    }
    let scene_count = builtin_count + user_scenes.len();
    let mut scenes = with_field
        .then(bench::tensor_field_scene)
        .into_iter()
        .chain(with_lattice.then(bench::lattice_scene))
        .chain(with_liquid.then(bench::md_liquid_scene))
        .chain(
            specs
                .into_iter()
                .map(|(count, size)| bench::frustum_cloud(count, size, 1)),
        )
        .chain(user_scenes);
    let mut renderer = OffscreenRenderer::new(&render_device::context_options(&args.device))?;
    let mut skipped = Vec::new();
    let started = std::time::Instant::now();
    let motion = args
        .orbit
        .map_or(bench::Motion::Still, |degrees| bench::Motion::Orbit {
            degrees,
        });
    let results = bench::run(
        &mut renderer,
        &mut scenes,
        scene_count,
        &methods,
        (args.frames, motion),
        &mut skipped,
    )?;
    let device = renderer.context().info().name.clone();
    let driver = renderer.context().info().driver.clone();
    let four_samples = renderer
        .context()
        .info()
        .sample_counts
        .contains(ash::vk::SampleCountFlags::TYPE_4);
    renderer.context().check_validation()?;
    renderer.finish()?;
    // The antialiasing variants join the headline scene's chart (their own interleaved
    // run); a device without 4x multisampling skips them.
    let antialiased = if with_field && four_samples {
        antialias_bench::run(
            &render_device::context_options(&args.device),
            args.frames,
            &[bench::tensor_field_scene()],
        )?
    } else {
        if with_field {
            skipped.push("the antialiasing variants on tensor-field (no 4x MSAA)".into());
        }
        Vec::new()
    };
    let summary = bench::write_report(&results, &antialiased, (&device, &driver), &args.out)?;
    println!("{}", summary.table);
    if !antialiased.is_empty() {
        println!("antialiased (tensor field; antialias.csv):");
        println!(
            "{}",
            antialias_bench::write_report(&antialiased, &args.out)?
        );
    }
    println!("headline scene (Markdown):\n{}", summary.markdown);
    println!(
        "plan regret (time / fastest fixed path's; first guess: impostor-estimate, learned: \
         impostor):\n{}",
        summary.regret
    );
    if !skipped.is_empty() {
        // Over-budget entries give the glyph count, the others their reason.
        println!(
            "skipped (vertex work over budget: glyph count; else why): {}",
            skipped.join(", ")
        );
    }
    let checks = bench::check_targets(&results);
    let mut all = true;
    for c in &checks {
        println!(
            "[{}] {}: {}",
            if c.holds { "met" } else { "MISSED" },
            c.target,
            c.measured
        );
        all &= c.holds;
    }
    println!(
        "{} results ({}) in {:.0} s on {device}, driver {driver}; wrote {}/results.csv, time_vs_error.png, fill_efficiency.png, scaling.png{}",
        results.len(),
        motion.label(),
        started.elapsed().as_secs_f64(),
        args.out.display(),
        if antialiased.is_empty() {
            ""
        } else {
            ", antialias.csv, antialias_vs_error.png"
        }
    );
    Ok(all)
}

/// `bench --skip`: every skippable piece of work on and off.
fn run_skip(args: &BenchArgs) -> Result<bool> {
    let mut renderer = OffscreenRenderer::new(&render_device::context_options(&args.device))?;
    let started = std::time::Instant::now();
    let features = skip::Feature::parse_list(&args.features)?;
    let results = skip::run(&mut renderer, args.quick, args.frames, &features)?;
    renderer.context().check_validation()?;
    renderer.finish()?;
    let table = skip::write_report(&results, &args.out)?;
    println!("{table}");
    let features_meeting_both = features
        .iter()
        .filter(|&&f| {
            let mut measured = results.iter().filter(|r| r.feature == f).peekable();
            measured.peek().is_some() && measured.all(|r| r.meets_target())
        })
        .count();
    println!(
        "{features_meeting_both} of {} features meet both targets (need 4); {:.0} s; wrote {}/skip.csv and skip.png",
        features.len(),
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(features_meeting_both >= 4)
}

/// `conformance`: exit status 0 when every case passes, 1 when one fails or the run cannot.
fn conformance(args: &ConformanceArgs) -> ExitCode {
    let run = || -> Result<bool> {
        let method = match &args.method {
            None => None,
            Some(name) => Some(
                Method::ALL
                    .into_iter()
                    .find(|m| m.name() == *name)
                    .ok_or_else(|| {
                        Error::invalid("--method", format!("no method named {name:?}"))
                    })?,
            ),
        };
        if let Some(path) = &args.junit {
            output::check_writable("--junit", path)?;
        }
        let (summary, left_out, outcomes) =
            ellipsoid_splat_tool::conformance::run(args.device.clone(), args.quick, method)?;
        print!(
            "{}",
            ellipsoid_splat_tool::conformance::report(&summary, &left_out, &outcomes)
        );
        if let Some(path) = &args.junit {
            ellipsoid_splat_tool::conformance::write_junit(path, &summary, &outcomes)?;
        }
        Ok(outcomes.iter().all(|o| o.failure.is_none()))
    };
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn info(args: &DeviceArgs) -> Result<()> {
    let context = Context::new(&render_device::context_options(args))?;
    let info = context.info();
    let version = info.api_version;
    println!("device:            {}", info.name);
    println!("type:              {:?}", info.device_type);
    println!("driver:            {}", info.driver);
    println!(
        "Vulkan:            {}.{}.{}",
        ash::vk::api_version_major(version),
        ash::vk::api_version_minor(version),
        ash::vk::api_version_patch(version)
    );
    println!("timestamp period:  {} ns", info.timestamp_period);
    println!("max storage range: {} bytes", info.max_storage_buffer_range);
    // SAFETY: the physical device belongs to the context's instance, alive for this call.
    let limits = unsafe {
        context
            .instance()
            .get_physical_device_properties(context.physical_device())
    }
    .limits;
    // Multisampled pictures shaded once per pixel assume the standard positions, in order.
    println!(
        "sample locations:  {}",
        if limits.standard_sample_locations == ash::vk::TRUE {
            "standard"
        } else {
            "the device's own"
        }
    );
    println!(
        "features used:     dynamicRendering, pipelineStatisticsQuery={}",
        info.pipeline_statistics
    );
    println!(
        "validation:        {}",
        if args.validation {
            "on (core + synchronization)"
        } else {
            "off"
        }
    );
    Ok(context.check_validation()?)
}
