use ellipsoid_splat::bench::frustum_cloud;
use ellipsoid_splat::gpu::ContextOptions;
use ellipsoid_splat::offscreen::OffscreenRenderer;
use ellipsoid_splat::renderer::Culling;
fn main() {
    let n: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    let s = frustum_cloud(n, 2.0, 7);
    let mut r = OffscreenRenderer::new(&ContextOptions::default()).unwrap();
    r.set_culling(Culling::OFF);
    let a = r.render(&s.scene, &s.camera).unwrap();
    r.set_culling(Culling::ON);
    let b = r.render(&s.scene, &s.camera).unwrap();
    let ca = a.id.iter().filter(|&&i| i != ellipsoid_splat::NO_INSTANCE).count();
    let cb = b.id.iter().filter(|&&i| i != ellipsoid_splat::NO_INSTANCE).count();
    let diff = a.id.iter().zip(&b.id).filter(|(x, y)| x != y).count();
    let maxid_b = b.id.iter().filter(|&&i| i != ellipsoid_splat::NO_INSTANCE).max();
    println!("n={n} covered off={ca} on={cb} diff={diff} max id on={maxid_b:?}");
    r.finish().unwrap();
}
