//! A host on VMA (`vk-mem`, feature `vk-mem`): the renderer allocates every buffer through the
//! host's VMA allocator, draws under validation exactly what it draws on gpu-allocator (the
//! same pixels, bit for bit, the glyphs where the float64 reference puts them), and gives all
//! of its memory back. Prints the GPU memory the scene takes with each allocator.

use ash::vk;
use ellipsoid_splat::{
    DeviceFeatures, EllipsoidRenderer, HostDevice, MemoryAllocator, RendererOptions, Scene,
    Settings, Target, NO_INSTANCE,
};
use ellipsoid_splat::{PathKind, PlanMode};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::reference::render_reference;
use ellipsoid_splat_test_host::{DepthKind, Host, HostTarget, TargetKind};
use glam::DVec3;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// Draws `scene` with a renderer whose buffers come from `allocator` into a new target of the
/// host; returns the target's RGBA8 pixels, the renderer's memory in bytes and what
/// `reserved` says of the allocator while the renderer lives.
fn draw<A: MemoryAllocator>(
    host: &mut Host,
    allocator: &mut A,
    reserved: impl Fn(&A) -> u64,
    scene: &Scene,
    camera: &ellipsoid_splat::Camera,
    settings: Settings,
) -> (Vec<u8>, u64, u64) {
    let samples = vk::SampleCountFlags::TYPE_1;
    let target = HostTarget::new(
        host,
        TargetKind::Dynamic,
        DepthKind::ReversedInfinite,
        samples,
        WIDTH,
        HEIGHT,
    )
    .unwrap();
    let mut features = DeviceFeatures::default();
    features.maintenance4 = true;
    features.dynamic_rendering = true;
    features.sample_rate_shading = true;
    if host.int64_atomics() {
        features = features.union(DeviceFeatures::COMPUTE_SPLAT);
    }
    let handles = host.handles();
    let host_device = HostDevice::new(
        handles.instance,
        handles.physical_device,
        handles.device,
        handles.queue_family,
        features,
    );
    let mut options = RendererOptions::new(Target::dynamic(
        HostTarget::COLOR_FORMAT,
        HostTarget::DEPTH_FORMAT,
    ));
    options.settings = settings;
    // SAFETY: the host's handles belong together and enable the features `features` names;
    // `allocator` allocates from the host's device.
    let mut renderer = unsafe { EllipsoidRenderer::new(&host_device, allocator, options) }.unwrap();
    let cmd = host.begin().unwrap();
    let device = host.device().clone();
    // SAFETY: `cmd` is recording; upload and pre-pass outside the pass, the draw inside; the
    // submission is waited for before the renderer is destroyed.
    unsafe {
        renderer.begin_frame(&device, allocator, 0).unwrap();
        renderer.upload(&device, allocator, cmd, scene).unwrap();
        renderer
            .record_prepass(&device, allocator, cmd, camera)
            .unwrap();
        target.begin_pass(&device, cmd);
        renderer.record(&device, allocator, cmd, camera).unwrap();
        target.end_pass(&device, cmd);
    }
    host.submit_and_wait().unwrap();
    let memory = renderer.gpu_memory_bytes();
    let blocks = reserved(allocator);
    let rgba = target.read_rgba().unwrap();
    // SAFETY: the submission completed.
    unsafe { renderer.destroy(&device, allocator) };
    target.destroy(host);
    (rgba, memory, blocks)
}

#[test]
fn a_host_on_vma_draws_what_a_host_on_gpu_allocator_draws() {
    let mut host = Host::new(true).unwrap();
    let mut scene = random_cloud(3000, 21, 5.0, 0.5);
    for e in &mut scene.ellipsoids {
        e.color = [0.9, 0.8, 0.7];
    }
    let camera = ellipsoid_splat::Camera::look_at(
        DVec3::new(3.0, 4.0, 15.0),
        DVec3::ZERO,
        45.0,
        2.0,
        WIDTH,
        HEIGHT,
    )
    .unwrap();
    let handles = host.handles();
    let mut info =
        vk_mem::AllocatorCreateInfo::new(handles.instance, handles.device, handles.physical_device);
    info.vulkan_api_version = vk::API_VERSION_1_3;
    // SAFETY: the host's instance, device and physical device outlive the allocator (it is
    // dropped before the host below).
    let mut vma = unsafe { vk_mem::Allocator::new(info) }.unwrap();
    let reference = render_reference(&scene, &camera).unwrap();
    // The draw, and the compute splat taking every glyph.
    for splat in [false, true] {
        let mut settings = Settings::default();
        settings.plan = PlanMode::Fixed(if splat {
            PathKind::Splat
        } else {
            PathKind::Draw
        });
        let vma_blocks = |vma: &vk_mem::Allocator| {
            vma.calculate_statistics()
                .unwrap()
                .total
                .statistics
                .blockBytes
        };
        let (on_vma, vma_bytes, vma_reserved) =
            draw(&mut host, &mut vma, vma_blocks, &scene, &camera, settings);
        let stats = vma.calculate_statistics().unwrap().total.statistics;
        assert_eq!(
            stats.allocationCount, 0,
            "every VMA allocation is given back"
        );
        let mut gpu_allocator = {
            let handles = host.handles();
            gpu_allocator::vulkan::Allocator::new(&gpu_allocator::vulkan::AllocatorCreateDesc {
                instance: handles.instance.clone(),
                device: handles.device.clone(),
                physical_device: handles.physical_device,
                debug_settings: Default::default(),
                buffer_device_address: false,
                allocation_sizes: Default::default(),
            })
            .unwrap()
        };
        let reserved =
            |a: &gpu_allocator::vulkan::Allocator| a.generate_report().total_capacity_bytes;
        let (on_gpu_allocator, gpu_allocator_bytes, gpu_allocator_reserved) = draw(
            &mut host,
            &mut gpu_allocator,
            reserved,
            &scene,
            &camera,
            settings,
        );
        let report = gpu_allocator.generate_report();
        assert_eq!(
            report.total_allocated_bytes, 0,
            "every gpu-allocator allocation is given back"
        );
        drop(gpu_allocator);
        println!(
            "splat {splat}: {} glyphs; the renderer's allocations: {vma_bytes} bytes on VMA \
             (in {vma_reserved} bytes of blocks), {gpu_allocator_bytes} bytes on gpu-allocator \
             (in {gpu_allocator_reserved} bytes of blocks)",
            scene.len()
        );
        assert!(vma_bytes > 3000 * 48 && gpu_allocator_bytes > 3000 * 48);
        assert!(on_vma == on_gpu_allocator, "splat {splat}: pixels differ");
        // Covered where the reference covers (background black, glyphs lit), off ambiguous
        // pixels.
        let mut covered = 0;
        for k in 0..reference.id.len() {
            if reference.ambiguous[k] {
                continue;
            }
            let lit = on_vma[4 * k..4 * k + 3].iter().any(|&c| c > 0);
            let shown = reference.id[k] != NO_INSTANCE;
            assert_eq!(lit, shown, "splat {splat}: pixel {k}");
            covered += shown as usize;
        }
        assert!(covered > 2_000, "{covered} covered pixels");
    }
    drop(vma);
    let messages = host.messages();
    assert!(messages.is_empty(), "validation: {messages:#?}");
}
