//! The `ellipsoid-splat` command-line tool.

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;

use ellipsoid_splat::cli::{self, Cli, Command, DeviceArgs, RenderArgs};
use ellipsoid_splat::gpu::{Context, ContextOptions};
use ellipsoid_splat::{output, OffscreenRenderer, Result};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => render(&RenderArgs::default()),
        Some(Command::Render(args)) => render(&args),
        Some(Command::Info(args)) => info(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn context_options(args: &DeviceArgs) -> ContextOptions {
    ContextOptions {
        validation: args.validation,
        synchronization_validation: args.validation,
        device: args.device.clone(),
        ..ContextOptions::default()
    }
}

fn render(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let scene = cli::load_scene(&args.scene)?;
    let camera = cli::camera_for(args, &scene)?;
    let loaded = start.elapsed();

    let mut renderer = OffscreenRenderer::new(&context_options(&args.device))?;
    let setup = start.elapsed() - loaded;
    renderer.upload(&scene)?;
    let (frame, timing) = renderer.render_uploaded(&camera)?;
    renderer.context().check_validation()?;

    output::write_color_png(&frame, &args.output)?;
    if let Some(path) = &args.depth {
        output::write_depth_exr(&frame, path)?;
    }
    if let Some(path) = &args.normal {
        output::write_normal_exr(&frame, path)?;
    }
    if let Some(path) = &args.id {
        output::write_id_image(&frame, path)?;
    }
    let device = renderer.context().info().name.clone();
    drop(renderer);
    println!(
        "wrote {} ({}x{}, {} ellipsoids) in {:.0} ms: scene {:.0} ms, device set-up {:.0} ms, \
         frame {:.1} ms (submit to fence) on {device}",
        args.output.display(),
        camera.width,
        camera.height,
        scene.len(),
        start.elapsed().as_secs_f64() * 1e3,
        loaded.as_secs_f64() * 1e3,
        setup.as_secs_f64() * 1e3,
        timing.gpu_wall.as_secs_f64() * 1e3,
    );
    Ok(())
}

fn info(args: &DeviceArgs) -> Result<()> {
    let context = Context::new(&context_options(args))?;
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
    println!("features used:     dynamicRendering, pipelineStatisticsQuery={}", info.pipeline_statistics);
    println!("validation:        {}", if args.validation { "on (core + synchronization)" } else { "off" });
    context.check_validation()
}
