use ellipsoid_splat::bench::frustum_cloud;
use ellipsoid_splat::gpu::ContextOptions;
use ellipsoid_splat::offscreen::OffscreenRenderer;
use ellipsoid_splat::renderer::Culling;
fn main() {
    let n: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    let s = frustum_cloud(n, 2.0, 7);
    let mut r = OffscreenRenderer::new(&ContextOptions::default()).unwrap();
    r.set_culling(Culling::OFF);
    r.upload(&s.scene).unwrap();
    for _ in 0..2 { r.render_timed(&s.camera).unwrap(); }
    let mut t: Vec<f64> = (0..5).map(|_| r.render_timed(&s.camera).unwrap().gpu_wall.as_secs_f64()*1e3).collect();
    t.sort_by(f64::total_cmp);
    println!("n={n} median {:.1} ms", t[2]);
    r.finish().unwrap();
}
