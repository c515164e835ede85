//! `render`'s arguments checked before anything is loaded, allocated or drawn: numbers, the
//! scene's name and size, the output names and whether their files can be written. Errors
//! name the flag.

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::render::{RenderArgs, MAX_IMAGE_SIDE};
use super::scene::SceneSpec;
use super::values::xyz;
use crate::error::{Error, Result};
use crate::host_memory::{check_host_memory, machine_memory};
use crate::output::{self, Image};
use ellipsoid_splat::Outputs;

/// What `render` was asked for, checked before anything is loaded, allocated or drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderPlan {
    /// The scene to load or generate.
    pub scene: SceneSpec,
    /// The images to produce.
    pub outputs: Outputs,
}

impl RenderArgs {
    /// Checks every argument that can be checked without the scene -- numbers, the scene's
    /// size, output names and whether the output files can be written -- so that a mistake
    /// is reported before anything is loaded, allocated or drawn. Errors name the flag.
    pub fn check(&self) -> Result<RenderPlan> {
        let scene = self.check_scene()?;
        let outputs = self.outputs();
        let files: Vec<(Image, &Path)> = Image::all_in(outputs)
            .filter_map(|image| Some((image, self.file(image)?)))
            .collect();
        if self.frames.is_some() {
            self.check_sequence_names(&files)?;
        } else {
            for &(image, path) in &files {
                output::check_extension(image, path)?;
            }
            for &(image, path) in &files {
                output::check_writable(image.flag(), path)?;
            }
        }
        let mut inputs: Vec<(&str, &Path)> = Vec::new();
        if let SceneSpec::File(path) = &scene {
            inputs.push(("--scene", path));
        }
        if let Some(path) = &self.save_scene {
            output::check_writable("--save-scene", path)?;
            if let SceneSpec::File(input) = &scene {
                if input
                    .canonicalize()
                    .is_ok_and(|i| i == output::resolved(path))
                {
                    return Err(Error::invalid(
                        "--save-scene",
                        format!("'{}' is the scene being read", path.display()),
                    ));
                }
            }
        }
        if let Some(mask) = &self.load.mask {
            inputs.push(("--mask", mask));
        }
        // A sequence's files are compared as frame 1's names (`x.png` and `x_%04d.png` both
        // number to `x_0001.png`).
        let named: Vec<(Image, PathBuf)> = files
            .iter()
            .map(|&(image, path)| match self.frames {
                Some(_) => output::numbered(image.flag(), path, 1).map(|p| (image, p)),
                None => Ok((image, path.to_path_buf())),
            })
            .collect::<Result<_>>()?;
        for (k, (image, path)) in named.iter().enumerate() {
            let (image, path) = (*image, path.as_path());
            let target = output::resolved(path);
            if let Some((other, _)) = named[..k]
                .iter()
                .find(|(_, p)| output::resolved(p) == target)
            {
                return Err(Error::invalid(
                    image.flag(),
                    format!(
                        "'{}' is also the {} file; each image needs a file of its own",
                        path.display(),
                        other.flag()
                    ),
                ));
            }
            if let Some((flag, _)) = inputs
                .iter()
                .find(|(_, input)| input.canonicalize().is_ok_and(|i| i == target))
            {
                return Err(Error::invalid(
                    image.flag(),
                    format!(
                        "'{}' is the {flag} input file; writing it would overwrite it",
                        path.display()
                    ),
                ));
            }
        }
        Ok(RenderPlan { scene, outputs })
    }

    /// Checks the sequence's file names (as frame 1's) and the movie's name, before anything is
    /// loaded: every name's pattern, every first file writable, the movie's directory there.
    fn check_sequence_names(&self, images: &[(Image, &Path)]) -> Result<()> {
        // With a movie the colour goes there, not to files.
        let files = images
            .iter()
            .filter(|(image, _)| !(*image == Image::Color && self.movie.is_some()));
        for &(image, path) in files {
            let first = output::numbered(image.flag(), path, 1)?;
            output::check_extension(image, &first)?;
            output::check_writable(image.flag(), &first)?;
        }
        if let Some(movie) = &self.movie {
            if movie.extension().is_none() {
                return Err(Error::invalid(
                    "--movie",
                    format!(
                        "'{}' has no extension, which names the movie's container (.mp4, .mkv, \
                         .webm, ...)",
                        movie.display()
                    ),
                ));
            }
            output::check_writable("--movie", movie)?;
        }
        Ok(())
    }

    /// Checks the numbers and the scene's name and size (what [`RenderArgs::check`] checks
    /// but the output files), naming the flag; the scene to load or generate.
    pub fn check_scene(&self) -> Result<SceneSpec> {
        self.check_numbers()?;
        let scene = SceneSpec::parse(&self.scene)?;
        if let Some(count) = scene.generated_count() {
            check_host_memory(&self.scene, count, self.instance_format(), machine_memory())?;
        }
        Ok(scene)
    }

    /// Every numeric and vector flag on its own.
    fn check_numbers(&self) -> Result<()> {
        for (flag, value) in [("--width", self.width), ("--height", self.height)] {
            if !(1..=MAX_IMAGE_SIDE).contains(&value) {
                return Err(Error::invalid(
                    flag,
                    format!(
                        "{value} pixels is outside 1..={MAX_IMAGE_SIDE} (the largest image side \
                         the renderer accepts)"
                    ),
                ));
            }
        }
        if let Some([x, y, w, h]) = self.viewport {
            if x as u64 + w as u64 > self.width as u64 || y as u64 + h as u64 > self.height as u64 {
                return Err(Error::invalid(
                    "--viewport",
                    format!(
                        "the {w}x{h} rectangle at ({x}, {y}) reaches beyond the {}x{} output \
                         (--width, --height)",
                        self.width, self.height
                    ),
                ));
            }
        }
        if !self.samples.is_power_of_two() || self.samples > 64 {
            return Err(Error::invalid(
                "--samples",
                format!("{} is not a sample count (1, 2, 4, ... 64)", self.samples),
            ));
        }
        if self.per_sample_shading && self.samples == 1 {
            return Err(Error::invalid(
                "--per-sample-shading",
                "applies to multisampling: give --samples 2 or more",
            ));
        }
        let k = self.supersample;
        if !(1..=ellipsoid_splat::supersample::MAX_SUPERSAMPLE).contains(&k) {
            return Err(Error::invalid(
                "--supersample",
                format!(
                    "{k} is outside 1..={}",
                    ellipsoid_splat::supersample::MAX_SUPERSAMPLE
                ),
            ));
        }
        for (flag, value) in [("--width", self.width), ("--height", self.height)] {
            if value as u64 * k as u64 > MAX_IMAGE_SIDE as u64 {
                return Err(Error::invalid(
                    "--supersample",
                    format!(
                        "{k} x {flag} {value} = {} pixels is more than {MAX_IMAGE_SIDE}, the \
                         largest image side the renderer accepts",
                        value as u64 * k as u64
                    ),
                ));
            }
        }
        let positive = |flag: &str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    flag,
                    format!("must be positive (and finite), got {value}"),
                ))
            }
        };
        let number = |flag: &str, value: f64| {
            if value.is_nan() {
                Err(Error::invalid(flag, "must be a number, got NaN"))
            } else {
                Ok(())
            }
        };
        if let Some(near) = self.near {
            positive("--near", near)?;
        }
        match self.camera.ortho {
            Some(height) => positive("--ortho", height)?,
            None => {
                let fov = self.camera.fov_y;
                if !(fov.is_finite() && fov > 0.0 && fov < 180.0) {
                    return Err(Error::invalid(
                        "--fov-y",
                        format!("must be between 0 and 180 degrees (exclusive), got {fov}"),
                    ));
                }
            }
        }
        if self.camera.up == DVec3::ZERO {
            return Err(Error::invalid("--up", "must not be 0,0,0"));
        }
        if let (Some(eye), Some(target)) = (self.camera.eye, self.camera.target) {
            if eye == target {
                return Err(Error::invalid(
                    "--target",
                    format!(
                        "{} is the same point as --eye; the camera needs a direction",
                        xyz(target)
                    ),
                ));
            }
        }
        positive("--sigma", self.load.sigma)?;
        number("--min-opacity", self.load.min_opacity)?;
        number("--min-fa", self.load.min_fa)?;
        positive("--glyph-scale", self.load.glyph_scale)?;
        Ok(())
    }
}
