//! CPU-side benchmarks: scene generation, CSV parsing, instance packing, the float64 reference
//! renderer and icosphere construction. `cargo bench --bench cpu` (add `-- --quick` for a fast
//! pass). Sample counts and measurement times are kept small so the whole run takes a few
//! minutes on a 2-core machine.
// criterion's macros define undocumented functions.
#![allow(missing_docs)]

use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use ellipsoid_splat::internals::pack_instances;
use ellipsoid_splat::research::icosphere;
use ellipsoid_splat::{Camera, Projection};
use ellipsoid_splat_loaders::{parse_csv, random_cloud, tensor_field};
use ellipsoid_splat_reference::reference::render_reference;
use glam::DVec3;

/// Rows of the generated CSV.
const CSV_ROWS: usize = 10_000;

fn packing(c: &mut Criterion) {
    let mut group = c.benchmark_group("pack_instances");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(4));
    let field = tensor_field(40);
    group.throughput(Throughput::Elements(field.len() as u64));
    group.bench_function("tensor_field_40", |b| {
        b.iter(|| pack_instances(black_box(&field)).unwrap())
    });
    let cloud = random_cloud(1_000_000, 1, 50.0, 0.5);
    group.throughput(Throughput::Elements(cloud.len() as u64));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    group.bench_function("random_cloud_1e6", |b| {
        b.iter(|| pack_instances(black_box(&cloud)).unwrap())
    });
    group.finish();
}

fn scenes(c: &mut Criterion) {
    let mut group = c.benchmark_group("scene");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(4));
    group.throughput(Throughput::Elements(40 * 40 * 40));
    group.bench_function("tensor_field_40", |b| {
        b.iter(|| tensor_field(black_box(40)))
    });

    let text = csv_text(CSV_ROWS);
    group.throughput(Throughput::Elements(CSV_ROWS as u64));
    group.bench_function("parse_csv_10k", |b| {
        b.iter(|| parse_csv(black_box(&text), Path::new("bench.csv")).unwrap())
    });
    group.finish();
}

/// `rows` ellipsoids of a random cloud as CSV in the semi-axes + quaternion form, with colour.
fn csv_text(rows: usize) -> String {
    let scene = random_cloud(rows, 2, 20.0, 0.6);
    let mut text = String::from("# benchmark scene\nx,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n");
    for e in &scene.ellipsoids {
        let (c, r, q, k) = (e.center, e.radii, e.rotation, e.color);
        writeln!(
            text,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            c.x, c.y, c.z, r.x, r.y, r.z, q.w, q.x, q.y, q.z, k[0], k[1], k[2]
        )
        .unwrap();
    }
    // Sanity: the text parses back to the same number of ellipsoids.
    assert_eq!(
        parse_csv(&text, Path::new("bench.csv")).unwrap().len(),
        rows
    );
    text
}

fn reference(c: &mut Criterion) {
    let mut group = c.benchmark_group("reference");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(8));
    // The accuracy test's overlapping cloud and camera.
    let scene = random_cloud(300, 7, 3.0, 0.8);
    let camera = Camera::new(
        DVec3::new(4.0, 3.0, 9.0),
        DVec3::ZERO,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 50.0 },
        0.5,
        320,
        240,
    )
    .unwrap();
    group.throughput(Throughput::Elements(320 * 240));
    group.bench_function("random_cloud_300_320x240", |b| {
        b.iter(|| render_reference(black_box(&scene), black_box(&camera)).unwrap())
    });
    group.finish();
}

fn meshes(c: &mut Criterion) {
    let mut group = c.benchmark_group("icosphere");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(5120));
    group.bench_function("level_4", |b| {
        b.iter_batched(|| black_box(4), icosphere, BatchSize::SmallInput)
    });
    group.finish();
}

criterion_group!(benches, packing, scenes, reference, meshes);
criterion_main!(benches);
