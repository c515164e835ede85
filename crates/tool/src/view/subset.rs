//! What a frame draws while the camera moves: the rule, and why the sample is drawn by a hash
//! of each glyph's index (fixed, so no flicker, and spread over the whole scene), is
//! `docs/viewer.md` ("Large scenes"); this is its code.

use ellipsoid_splat::{Ellipsoid, Scene};

/// The default most glyphs a moving frame draws (measured on lavapipe with 2 cores: a moving
/// frame of this many small glyphs at 1280x720 takes about as long as a still frame of the
/// default tensor field).
pub const DEFAULT_MOVING_GLYPHS: usize = 100_000;

/// A uniform sample of a scene: its glyphs and their indices in the full scene (ascending).
pub struct Sample {
    /// The sampled glyphs, in scene order.
    pub scene: Scene,
    /// `indices[k]` is the full scene's index of sampled glyph `k`.
    pub indices: Vec<u32>,
}

impl Sample {
    /// About `cap` of `scene`'s glyphs, each kept with probability `cap / len`; `None` when
    /// the scene has no more than `cap` (or `cap` is 0: sampling off).
    pub fn of(scene: &Scene, cap: usize) -> Option<Self> {
        let total = scene.len();
        if cap == 0 || total <= cap {
            return None;
        }
        let threshold = ((cap as f64 / total as f64) * u64::MAX as f64) as u64;
        let indices: Vec<u32> = (0..total as u32)
            .filter(|&i| mix(u64::from(i)) < threshold)
            .collect();
        let glyphs: Vec<Ellipsoid> = indices
            .iter()
            .map(|&i| scene.ellipsoids[i as usize])
            .collect();
        Some(Self {
            scene: Scene::new(glyphs),
            indices,
        })
    }

    /// The sample's index of full-scene glyph `index`, if it is in the sample.
    pub fn position(&self, index: u32) -> Option<u32> {
        self.indices.binary_search(&index).ok().map(|k| k as u32)
    }
}

/// SplitMix64's finaliser: a fixed, well-spread hash of a glyph index.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_is_uniform_and_maps_back() {
        let scene = ellipsoid_splat_loaders::random_cloud(20_000, 1, 10.0, 1.0);
        assert!(Sample::of(&scene, 20_000).is_none());
        assert!(Sample::of(&scene, 0).is_none());
        let sample = Sample::of(&scene, 2_000).unwrap();
        let n = sample.indices.len();
        // Binomial(20000, 0.1): standard deviation 42.
        assert!((1_800..2_200).contains(&n), "{n}");
        // Each quarter of the index range holds about a quarter of the sample.
        for q in 0..4u32 {
            let inside = sample.indices.iter().filter(|&&i| i / 5_000 == q).count();
            assert!((400..600).contains(&inside), "quarter {q}: {inside}");
        }
        for (k, &i) in sample.indices.iter().enumerate() {
            assert_eq!(sample.scene.ellipsoids[k], scene.ellipsoids[i as usize]);
            assert_eq!(sample.position(i), Some(k as u32));
        }
        let missing = (0..20_000).find(|i| sample.position(*i).is_none()).unwrap();
        assert!(!sample.indices.contains(&missing));
    }
}
