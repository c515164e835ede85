//! Faults walked over a typical run of the offscreen renderer (create, upload, frames, an
//! update, a resize, two views, a larger upload, teardown): out of device
//! memory at each call, and the device lost from each call on.

mod support;

use ellipsoid_splat::PlanMode;
use ellipsoid_splat::{ContextOptions, Error, OffscreenRenderer, Outputs};
use glam::DVec3;
use support::fault::Fault;
use support::scenes::{self, bits, camera};
use support::walk::{walk, Bits, Run, Step, Strides, TYPICAL_RUN};

struct Offscreen(Option<OffscreenRenderer>);

impl Offscreen {
    fn renderer(&mut self) -> &mut OffscreenRenderer {
        self.0.as_mut().expect("created by step 0")
    }

    fn frame(&mut self, eye: DVec3, width: u32, height: u32) -> Result<Option<Bits>, Error> {
        let (frame, _) = self
            .renderer()
            .render_uploaded(&camera(eye, width, height), Outputs::ALL)?;
        Ok(Some(bits(&frame)))
    }
}

impl Run for Offscreen {
    type Error = Error;

    fn steps() -> &'static [Step] {
        TYPICAL_RUN
    }

    fn start() -> Self {
        Offscreen(None)
    }

    fn step(&mut self, k: usize) -> Result<Option<Bits>, Error> {
        let eye = DVec3::new(1.0, 2.0, 11.0);
        match k {
            0 => {
                let mut renderer = OffscreenRenderer::new(&ContextOptions::validated())?;
                let mut settings = *renderer.settings();
                settings.plan = PlanMode::Estimate; // the same calls every run
                renderer.set_settings(settings);
                self.0 = Some(renderer);
                Ok(None)
            }
            1 => self.renderer().upload(&scenes::first_scene()).map(|_| None),
            2 => self.frame(eye, 96, 64),
            3 => self.frame(DVec3::new(-4.0, 3.0, 9.0), 96, 64),
            4 => self
                .renderer()
                .update(scenes::UPDATE_FIRST, &scenes::updated_glyphs())
                .map(|_| None),
            5 => self.frame(eye, 96, 64),
            6 => self.frame(eye, 128, 96),
            7 => {
                let left = camera(eye, 64, 64);
                let right =
                    camera(DVec3::new(-4.0, 3.0, 9.0), 64, 64).with_viewport_origin(64, 0)?;
                let (frame, _) =
                    self.renderer()
                        .render_views(128, 64, &[left, right], Outputs::ALL)?;
                Ok(Some(bits(&frame)))
            }
            8 => self
                .renderer()
                .upload(&scenes::second_scene())
                .map(|_| None),
            9 => self.frame(eye, 96, 64),
            _ => unreachable!("{k} is not a step"),
        }
    }

    fn named(error: &Error) -> Option<Fault> {
        match error {
            Error::OutOfMemory { .. } => Some(Fault::OutOfMemory),
            Error::DeviceLost { .. } => Some(Fault::DeviceLost),
            _ => None,
        }
    }

    fn finish(self) -> Result<(), String> {
        match self.0 {
            Some(renderer) => renderer.finish().map_err(|e| e.to_string()),
            None => Ok(()),
        }
    }
}

/// One test: the layer's state and the environment are the process's.
#[test]
fn offscreen_faults_are_named_errors_and_leave_a_usable_renderer() {
    support::layer::layer();
    support::log::install();
    walk::<Offscreen>(
        Fault::OutOfMemory,
        Strides {
            dense: 3,
            sparse: 12,
        },
    );
    walk::<Offscreen>(
        Fault::DeviceLost,
        Strides {
            dense: 1,
            sparse: 3,
        },
    );
}
