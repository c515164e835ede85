//! The model: what the renderer should hold after each call (the scene as uploaded and
//! updated, its placement, format and chunk limit, the settings, the frame slots and the
//! open command buffer) and what each call should answer: `Ok`, or a refusal naming
//! what was wrong (`Error::Invalid::what`).

use std::collections::BTreeMap;

use ellipsoid_splat::{Culling, Ellipsoid, Error, InstanceFormat, Material, Placement, Settings};
use ellipsoid_splat::{PathKind, PlanMode};

use super::ops::{MaterialChoice, SettingsChoice, CHUNK_LIMITS};

/// What a call should answer.
#[derive(Clone, Debug, PartialEq)]
pub enum Expect {
    Ok,
    /// `Error::Invalid` whose `what` is this.
    Refused(String),
    /// Either, where the answer rests on a plan the model does not make (the path the frame
    /// plan picks); a refusal must still carry this name.
    OkOrRefused(String),
}

impl Expect {
    pub fn refused(what: impl Into<String>) -> Self {
        Expect::Refused(what.into())
    }
}

/// Counts of what the sequences did.
#[derive(Default, Debug)]
pub struct Stats {
    pub sequences: u64,
    /// Per operation kind: how many, and the seconds they took.
    pub ops: BTreeMap<&'static str, (u64, f64)>,
    pub calls: u64,
    pub refusals: BTreeMap<String, u64>,
    /// Pre-passes recorded, by the path their plan took.
    pub paths: BTreeMap<&'static str, u64>,
    pub frames_submitted: u64,
    pub frames_dropped: u64,
    pub passes_compared: u64,
    pub pixels_compared: u64,
    pub pixels_covered: u64,
}

impl Stats {
    /// Checks `got` against `expected` for the call `call`; counts it.
    pub fn check<T>(
        &mut self,
        call: &str,
        got: &Result<T, Error>,
        expected: &Expect,
    ) -> Result<(), String> {
        self.calls += 1;
        let named = |name: &str| match got {
            Err(Error::Invalid { what, .. }) => what == name,
            _ => false,
        };
        let fine = match (expected, got) {
            (Expect::Ok, Ok(_)) => true,
            (Expect::OkOrRefused(_), Ok(_)) => true,
            (Expect::Refused(name) | Expect::OkOrRefused(name), Err(_)) => named(name),
            _ => false,
        };
        if !fine {
            let got = match got {
                Ok(_) => "Ok".to_string(),
                Err(e) => format!("Err({e:?})"),
            };
            return Err(format!("{call}: expected {expected:?}, got {got}"));
        }
        if let Err(Error::Invalid { what, .. }) = got {
            *self.refusals.entry(what.clone()).or_default() += 1;
        }
        Ok(())
    }

    pub fn op(&mut self, name: &'static str, seconds: f64) {
        let entry = self.ops.entry(name).or_default();
        entry.0 += 1;
        entry.1 += seconds;
    }

    /// The figures, one per line.
    pub fn report(&self) -> String {
        // Refusals naming a glyph by index are counted together.
        let mut refusals: BTreeMap<&str, u64> = BTreeMap::new();
        for (what, n) in &self.refusals {
            let what = if what.starts_with("ellipsoid ") {
                "ellipsoid <index>"
            } else {
                what
            };
            *refusals.entry(what).or_default() += n;
        }
        let mut lines = vec![
            format!("sequences: {}", self.sequences),
            format!(
                "operations: {}",
                self.ops.values().map(|(n, _)| n).sum::<u64>()
            ),
        ];
        for (op, (n, seconds)) in &self.ops {
            lines.push(format!("  {op}: {n} ({seconds:.1} s)"));
        }
        lines.push(format!("renderer calls checked: {}", self.calls));
        lines.push(format!("refusals: {}", self.refusals.values().sum::<u64>()));
        for (what, n) in refusals {
            lines.push(format!("  {what}: {n}"));
        }
        lines.push(format!(
            "pre-passes recorded: {}",
            self.paths.values().sum::<u64>()
        ));
        for (path, n) in &self.paths {
            lines.push(format!("  {path}: {n}"));
        }
        lines.push(format!(
            "command buffers submitted: {}, dropped unsubmitted: {}",
            self.frames_submitted, self.frames_dropped
        ));
        lines.push(format!(
            "passes compared with the offscreen renderer: {} ({} pixels, {} covered)",
            self.passes_compared, self.pixels_compared, self.pixels_covered
        ));
        lines.join("\n")
    }
}

/// The command buffer being recorded.
#[derive(Default)]
pub struct Open {
    /// Frame slots begun in it.
    pub slots: Vec<u32>,
    /// The renderer recorded into it (an upload, an update, a pre-pass or a draw): it must
    /// be submitted (the contracts of `upload` and `record_prepass`).
    pub recorded: bool,
    /// `record_prepass` calls since the last `begin_frame`.
    pub views: usize,
}

/// The renderer as the model sees it.
pub struct Model {
    pub frames_in_flight: u32,
    pub scene: Vec<Ellipsoid>,
    pub placement: Placement,
    /// The format and chunk limit of the last upload.
    pub format: InstanceFormat,
    pub chunk_limit: u32,
    pub settings: Settings,
    pub next_slot: u32,
    pub open: Option<Open>,
}

/// The most views one frame may have (`MAX_VIEWS` in the renderer).
pub const MAX_VIEWS: usize = 64;

impl Model {
    pub fn new(frames_in_flight: u32, settings: Settings) -> Self {
        Self {
            frames_in_flight,
            scene: Vec::new(),
            placement: Placement::of(&ellipsoid_splat::Scene::default()),
            format: settings.instance_format,
            chunk_limit: settings.max_chunk_instances,
            settings,
            next_slot: 0,
            open: None,
        }
    }

    /// Instances per chunk under the settings in force, as `Chunking` cuts them; 256 where
    /// only the device limits them (millions of glyphs are beyond a test's time).
    pub fn chunk_capacity(&self) -> u32 {
        match self.settings.max_chunk_instances {
            limit if limit >= 1 << 20 => 256,
            limit => (limit / 256 * 256).max(256),
        }
    }

    /// The refusal a frame's plan gives for the material in force, if any.
    pub fn material_refusal(&self) -> Option<&'static str> {
        material_defect(&self.settings.material)
    }

    /// What `record` without this frame's pre-pass of its camera answers (the camera valid,
    /// the material too).
    pub fn record_without_prepass(&self) -> Expect {
        let culling = self.settings.culling;
        if self.scene.is_empty() {
            Expect::Ok
        } else if culling.any() {
            // Every path culls or splats in a pre-pass.
            Expect::refused("record")
        } else if !self.settings.setup_once && self.settings.plan == PlanMode::Fixed(PathKind::Draw)
        {
            Expect::Ok
        } else {
            Expect::OkOrRefused("record".into())
        }
    }
}

/// The name a frame's refusal of `material` carries, if it has a field no shading can use.
pub fn material_defect(material: &Material) -> Option<&'static str> {
    let weight = |v: f32| v.is_finite() && v >= 0.0;
    if !weight(material.ambient) {
        Some("material ambient")
    } else if !weight(material.diffuse) {
        Some("material diffuse")
    } else if !weight(material.specular) {
        Some("material specular")
    } else if !(material.shininess.is_finite() && material.shininess > 0.0) {
        Some("material shininess")
    } else if !material.specular_color.iter().all(|&c| weight(c)) {
        Some("material specular colour")
    } else {
        None
    }
}

/// The settings a choice describes.
pub fn settings(choice: &SettingsChoice) -> Settings {
    let mut s = Settings::default();
    s.culling = Culling::OFF;
    s.culling.frustum = choice.culling & 1 != 0;
    s.culling.pixel_centres = choice.culling & 2 != 0;
    s.culling.occlusion = choice.culling & 4 != 0;
    s.setup_once = choice.setup_once;
    s.cap_free_path = choice.cap_free_path;
    s.small_glyph_triangles = choice.small_glyph_triangles;
    s.instance_format = if choice.compact {
        InstanceFormat::Compact
    } else {
        InstanceFormat::Full
    };
    s.plan = match choice.plan {
        0 => PlanMode::Measure,
        1 => PlanMode::Estimate,
        2 => PlanMode::Fixed(PathKind::Draw),
        3 => PlanMode::Fixed(PathKind::Splat),
        _ => PlanMode::Fixed(PathKind::VisibleFirst),
    };
    s.max_chunk_instances = CHUNK_LIMITS[choice.chunk];
    s.per_sample_shading = choice.per_sample_shading;
    s.material = material(choice.material);
    s
}

fn material(choice: MaterialChoice) -> Material {
    let mut m = Material::default();
    match choice {
        MaterialChoice::Default => {}
        MaterialChoice::Unlit => m = Material::unlit(),
        MaterialChoice::Shiny => {
            m.ambient = 0.3;
            m.diffuse = 0.5;
            m.specular = 1.0;
            m.shininess = 5.0;
            m.specular_color = [0.2, 0.9, 0.4];
        }
        MaterialChoice::NanAmbient => m.ambient = f32::NAN,
        MaterialChoice::NegativeDiffuse => m.diffuse = -0.5,
        MaterialChoice::InfiniteSpecular => m.specular = f32::INFINITY,
        MaterialChoice::ZeroShininess => m.shininess = 0.0,
        MaterialChoice::NanHighlight => m.specular_color[1] = f32::NAN,
    }
    m
}
