//! The scene a command names, read -- loaded or generated, then coloured as `--color` asks --
//! and written back where `--save-scene` asks.

use ellipsoid_splat::{Camera, Scene};
use ellipsoid_splat_loaders as scene;

use crate::camera_setup::camera_flags;
use crate::cli::{LoadArgs, RenderArgs, SceneSpec};
use crate::error::Result;

/// The seed of `--scene lattice[:N]` (the benchmark's `lattice` scene).
pub const LATTICE_SEED: u64 = 1;

/// The seed of `--scene md-liquid[:N]` (the benchmark's `md-liquid` scene).
pub const MD_LIQUID_SEED: u64 = 1;

/// Loads or generates `spec`, with what the loader reports.
pub fn load(spec: &SceneSpec, options: &scene::LoadOptions) -> Result<scene::Loaded> {
    let generated = |scene: Scene| scene::Loaded {
        scene,
        ..Default::default()
    };
    match spec {
        SceneSpec::TensorField(n) => Ok(generated(scene::tensor_field(*n))),
        SceneSpec::Lattice(n) => Ok(generated(scene::lattice(*n, LATTICE_SEED))),
        SceneSpec::MdLiquid(n) => Ok(generated(scene::md_liquid(*n, MD_LIQUID_SEED))),
        SceneSpec::Random(n) => {
            let extent = (*n as f64).cbrt() * 2.0;
            Ok(generated(scene::random_cloud(*n, 1, extent, 1.0)))
        }
        SceneSpec::File(path) => Ok(scene::load(path, options)?),
    }
}

/// Loads or generates `spec` with `load`'s options, then colours it in `--color`'s mode.
pub fn load_colored(spec: &SceneSpec, load_args: &LoadArgs) -> Result<scene::Loaded> {
    let mut loaded = load(spec, &load_args.options())?;
    load_args.color_mode().apply(&mut loaded.scene.ellipsoids);
    Ok(loaded)
}

/// Writes `scene` as Ellipsoid CSV where `--save-scene` asks, its first line the camera as
/// `render` flags.
pub fn save_scene(args: &RenderArgs, scene: &Scene, camera: &Camera) -> Result<()> {
    if let Some(path) = &args.save_scene {
        let comment = format!("camera: {}", camera_flags(camera));
        scene::save_csv(scene, &[comment], path)?;
        eprintln!("wrote {} ({} ellipsoids)", path.display(), scene.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn md_liquid_generates_its_particle_count() {
        let spec = SceneSpec::parse("md-liquid:300").unwrap();
        let scene = load(&spec, &scene::LoadOptions::default()).unwrap().scene;
        assert_eq!(scene.len(), 300);
    }
}
