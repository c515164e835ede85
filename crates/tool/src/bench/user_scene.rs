//! `bench --scene`: a user's scenes, read with `render`'s loader flags and framed with its
//! camera flags by the same code `render` runs (`scene_io`, `camera_setup`), so a scene
//! benchmarks as it renders.

use super::{BenchScene, HEIGHT, WIDTH};
use crate::camera_setup;
use crate::cli::{BenchArgs, RenderArgs, SceneSpec};
use crate::error::{Error, Result};
use crate::scene_io;

/// The scenes of `args.scene`, each loaded (or generated) and framed; `taken` are the names
/// of the run's other scenes, which a user's scene of the same name does not reuse (it gets
/// ` #2`, ` #3`, ...). Also what the loaders and the camera check have to say, to print.
/// Errors name the flag, or the file with its line and field.
pub fn user_scenes(args: &BenchArgs, taken: &[String]) -> Result<(Vec<BenchScene>, Vec<String>)> {
    let mut names: Vec<String> = taken.to_vec();
    let mut scenes = Vec::new();
    let mut messages = Vec::new();
    for spec in &args.scene {
        let render = RenderArgs {
            scene: spec.clone(),
            load: args.load.clone(),
            camera: args.camera.clone(),
            width: args.width.unwrap_or(WIDTH),
            height: args.height.unwrap_or(HEIGHT),
            ..RenderArgs::default()
        };
        let parsed = render.check_scene()?;
        if let SceneSpec::File(path) = &parsed {
            // Said before the loader's own error, in the flag's words.
            std::fs::File::open(path).map_err(|e| {
                Error::invalid("--scene", format!("cannot read '{}': {e}", path.display()))
            })?;
        }
        let loaded = scene_io::load_colored(&parsed, &render.load)?;
        messages.extend(loaded.notes.iter().map(|note| format!("{spec}: {note}")));
        let camera = camera_setup::camera_for(&render, &loaded.scene)?;
        if let Some(warning) = camera_setup::nothing_in_view(&render, &camera, &loaded.scene) {
            messages.push(format!("warning: {spec}: {warning}"));
        }
        let name = (1..)
            .map(|k| match k {
                1 => spec.clone(),
                k => format!("{spec} #{k}"),
            })
            .find(|name| !names.contains(name))
            .expect("some suffix is free");
        names.push(name.clone());
        scenes.push(BenchScene {
            name,
            scene: loaded.scene,
            camera,
            size_px: 0.0,
        });
    }
    Ok((scenes, messages))
}
