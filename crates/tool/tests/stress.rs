//! The reduced stability sweep (every swept parameter's extremes and a middle value, small
//! images) under validation: every point must meet the strict bounds with the stable
//! intersection.

use ellipsoid_splat_reference::testing as common;

use ellipsoid_splat::research::Intersection;
use ellipsoid_splat_reference::compare::Bounds;
use ellipsoid_splat_tool::stress::{run_point, sweep_points, Extent};

fn run_sweep(sweep: &str) {
    let mut renderer = common::validated_renderer();
    let mut failures = Vec::new();
    let points: Vec<_> = sweep_points(Extent::Reduced)
        .into_iter()
        .filter(|p| p.sweep == sweep)
        .collect();
    assert!(!points.is_empty(), "sweep {sweep} has no points");
    for point in &points {
        let result = run_point(&mut renderer, point, Intersection::Stable).expect("render");
        println!(
            "{:<10} {:<16} {:>10.3e} worst/bound {:.2e} | {}",
            point.sweep,
            point.case,
            point.parameter,
            result.worst_ratio(&Bounds::STRICT),
            result.stats
        );
        if let Some(broken) = result.broken {
            failures.push(format!(
                "{} {} {}: {broken}",
                point.sweep, point.case, point.parameter
            ));
        }
    }
    common::finish_validated(renderer);
    assert!(
        failures.is_empty(),
        "bounds broken:\n{}",
        failures.join("\n")
    );
}

#[test]
fn distance_sweep() {
    run_sweep("distance");
}

#[test]
fn aspect_sweep() {
    run_sweep("aspect");
}

#[test]
fn offset_sweep() {
    run_sweep("offset");
}

#[test]
fn fov_sweep() {
    run_sweep("fov");
}

#[test]
fn near_plane_sweep() {
    run_sweep("near");
}

#[test]
fn subpixel_size_sweep() {
    run_sweep("size");
}

#[test]
fn scale_sweep() {
    run_sweep("scale");
}

#[test]
fn coincident_surfaces_sweep() {
    run_sweep("coincident");
}

/// The antialiased points (thin needles, sub-pixel glyphs, a near-plane cut, overlaps) in
/// every mode -- 4x MSAA shaded per pixel and per sample, 2 x 2 and 4 x 4 supersampling --
/// resolve every pixel to the float64 reference's count of covered samples, after a sweep
/// point drawn with the textbook baseline (as `stress` runs them).
#[test]
fn antialiased_points_resolve_to_the_exact_covered_samples() {
    use ellipsoid_splat_tool::antialias_stress::{
        antialias_points, run_antialias_point, AntialiasMode,
    };
    let mut renderer = common::validated_renderer();
    let first = &sweep_points(Extent::Reduced)[0];
    run_point(&mut renderer, first, Intersection::Textbook).expect("textbook sweep point");
    let mut failures = Vec::new();
    for point in &antialias_points() {
        for mode in AntialiasMode::ALL {
            let result = run_antialias_point(&mut renderer, point, mode).expect("render");
            println!("{:<20} {:<18} {}", point.case, mode.name(), result.stats);
            assert!(
                result.stats.partly_covered > 20,
                "{} {}: {}",
                point.case,
                mode.name(),
                result.stats
            );
            if !result.exact() {
                failures.push(format!("{} {}: {}", point.case, mode.name(), result.stats));
            }
        }
    }
    common::finish_validated(renderer);
    assert!(
        failures.is_empty(),
        "coverage wrong:\n{}",
        failures.join("\n")
    );
}
