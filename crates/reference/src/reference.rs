//! The float64 CPU reference renderer: the oracle for every accuracy test and benchmark.
//!
//! Each pixel's ray (the camera contract, `Camera::ray`) is intersected exactly with every
//! ellipsoid that may cover it, in parameter space where the ellipsoid is the unit sphere, with a
//! quadratic solved without catastrophic cancellation. Visibility follows `docs/design.md` §3.3:
//! a surface point shows only at view depth >= near; a ray that enters before the near plane and
//! leaves after it shows a *cap* at depth `near` facing the camera. The nearest visible depth
//! wins, ties going to the lower instance index.
//!
//! Each pixel also says whether it is *ambiguous*: its centre lies within [`HAIR`] of a place
//! where the answer jumps (a silhouette, the rim of a cap, the curve where two ellipsoids meet) or
//! two ellipsoids tie in depth there. Comparisons skip those pixels for coverage and IDs.
//!
//! Speed comes from binning bounding spheres (clipped to the near plane) into screen tiles,
//! visiting each tile's ellipsoids front to back with an early exit, and rendering bands of
//! tiles on all cores.

use std::sync::{Mutex, PoisonError};
use std::thread;

use glam::{DMat3, DVec2, DVec3};

use ellipsoid_splat::internals::{Basis, Ray};
use ellipsoid_splat::Camera;
use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::Scene;
use ellipsoid_splat::NO_INSTANCE;
use ellipsoid_splat::{Error, Result};

/// Distance in pixels of the four extra samples around each pixel centre that detect
/// discontinuities (see [`ReferenceFrame::ambiguous`]).
pub const HAIR: f64 = 1e-3;

/// Two visible depths closer than this, relative to the nearer, are a tie: which instance shows
/// is then a matter of rounding, so the pixel is ambiguous.
pub const DEPTH_TIE: f64 = 1e-6;

/// Unit roundoff of float32 (2^-24): the relative precision of every stored or computed value
/// in a float32 pipeline.
pub const F32_ROUNDOFF: f64 = 1.0 / 16_777_216.0;

/// Side of the square screen tiles ellipsoids are binned into, in pixels.
const TILE: u32 = 16;

/// What one ray sees of one ellipsoid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// View depth `dot(p - eye, f)` of the visible point; `near` for a cap.
    pub depth: f64,
    /// World-space unit normal: the surface normal, or `-f` for a cap.
    pub normal: DVec3,
    /// True when the ray enters before the near plane and the pixel shows the cut-open cap.
    pub cap: bool,
}

/// The reference image: float64 depth and normal, instance ID and ambiguity per pixel,
/// row-major with row 0 at the top (the layout of [`ellipsoid_splat::Frame`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReferenceFrame {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// View depth `dot(p - eye, f)`; `f64::INFINITY` where nothing is visible.
    pub depth: Vec<f64>,
    /// World-space unit normal; zero where nothing is visible.
    pub normal: Vec<DVec3>,
    /// Index of the visible ellipsoid; [`NO_INSTANCE`] where nothing is visible.
    pub id: Vec<u32>,
    /// True when a sample [`HAIR`] pixels away from the centre (in x or y) sees a different
    /// instance, or a hit where the centre misses (or the reverse), or a cap where the centre
    /// sees the surface (or the reverse); or when the two nearest visible depths at the centre
    /// tie within [`DEPTH_TIE`]. Coverage and ID comparisons skip these pixels.
    pub ambiguous: Vec<bool>,
    /// The float32 floor of the relative depth error at this pixel: the change in depth caused
    /// by moving the sample point by what float32 screen coordinates resolve
    /// (`F32_ROUNDOFF (W + H)` pixels) and the surface by what float32 view-space positions
    /// resolve (across the view: `F32_ROUNDOFF (lateral offset of the centre + largest radius)`;
    /// along it: `F32_ROUNDOFF (centre depth + largest radius)`), to first order. It is
    /// large only where the problem is ill-conditioned: grazing rims, features thinner than a
    /// pixel, surfaces much nearer the eye than the size of their ellipsoid. 0 where nothing is
    /// visible or the pixel is ambiguous.
    pub depth_floor: Vec<f64>,
    /// The float32 floor of the normal angle error at this pixel, in degrees (same model).
    pub normal_floor_deg: Vec<f64>,
    /// How many ellipsoids the pixel centre's ray meets where they are visible by the
    /// near-plane rules, hidden or not: the depth complexity. Its sum over the image is the
    /// number of fragments an exact per-glyph footprint would shade.
    pub layers: Vec<u32>,
}

impl ReferenceFrame {
    /// Sum of [`ReferenceFrame::layers`]: pixel centres inside each ellipsoid's silhouette,
    /// added up over all ellipsoids.
    pub fn silhouette_pixels(&self) -> u64 {
        self.layers.iter().map(|&n| n as u64).sum()
    }
}

impl ReferenceFrame {
    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// True for a 0x0 frame.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Linear index of pixel `(i, j)`.
    pub fn index(&self, i: u32, j: u32) -> usize {
        j as usize * self.width as usize + i as usize
    }
}

/// Intersects one ray with one ellipsoid under the near-plane rules of `docs/design.md` §3.3.
///
/// The ray must follow the camera contract (as `Camera::ray` and `Camera::ray_at_pixel` build
/// them): perspective rays leave the eye with forward component 1, orthographic rays leave the
/// eye plane along `forward`, so in both cases the ray parameter is the view depth.
/// `forward` is the camera's unit view direction; a cap's normal is `-forward`.
pub fn intersect(e: &Ellipsoid, ray: &Ray, near: f64, forward: DVec3) -> Option<Hit> {
    let m = e.to_parameter();
    hit_unit_sphere(
        m * (ray.origin - e.center),
        m * ray.direction,
        &m,
        near,
        forward,
    )
}

/// The hit of the ray `o + t d` on the unit sphere (parameter space of the ellipsoid whose
/// world-to-parameter map is `m`), as world-space depth and normal.
fn hit_unit_sphere(o: DVec3, d: DVec3, m: &DMat3, near: f64, forward: DVec3) -> Option<Hit> {
    // |o + t d|^2 = 1  <=>  a t^2 + 2 b t + c = 0.
    let a = d.length_squared();
    let b = o.dot(d);
    // The discriminant b^2 - a c equals a (1 - |o_perp|^2), with o_perp the part of o
    // perpendicular to d: no difference of two huge squares when the eye is far away.
    let o_perp = o - (b / a) * d;
    let k = o_perp.length();
    if k.is_nan() || k > 1.0 {
        return None;
    }
    // Half the chord, in parameter-space length; (1-k)(1+k) keeps precision near the rim.
    let half_chord = ((1.0 - k) * (1.0 + k)).sqrt();
    let len_d = a.sqrt();
    let sqrt_disc = half_chord * len_d;
    let c = o.length_squared() - 1.0;
    // q = -(b + sign(b) sqrt(disc)) adds like signs; the roots are q/a and c/q.
    let q = -(b + sqrt_disc.copysign(b));
    let (t_in, t_out) = if q == 0.0 {
        // b = 0 and disc = 0: the ray starts on the sphere and grazes it, a double root at 0.
        (0.0, 0.0)
    } else {
        let (t1, t2) = (q / a, c / q);
        (t1.min(t2), t1.max(t2))
    };
    if t_in >= near {
        // Entry point o + t_in d, written without cancellation: o_perp - half_chord d/|d|.
        let p = o_perp - (half_chord / len_d) * d;
        // The world gradient of |M (x - c)|^2 is 2 M^T M (x - c) = 2 M^T p.
        let normal = (m.transpose() * p).normalize();
        Some(Hit {
            depth: t_in,
            normal,
            cap: false,
        })
    } else if t_out >= near {
        Some(Hit {
            depth: near,
            normal: -forward,
            cap: true,
        })
    } else {
        None
    }
}

/// Renders the reference image of `scene` seen by `camera` (validated first).
pub fn render_reference(scene: &Scene, camera: &Camera) -> Result<ReferenceFrame> {
    camera.validate()?;
    if scene.len() >= NO_INSTANCE as usize {
        return Err(Error::invalid(
            "scene",
            format!("{} ellipsoids exceed the 32-bit instance IDs", scene.len()),
        ));
    }
    let (width, height) = (camera.width, camera.height);
    let pixels = width as usize * height as usize;
    let mut frame = ReferenceFrame {
        width,
        height,
        depth: vec![f64::INFINITY; pixels],
        normal: vec![DVec3::ZERO; pixels],
        id: vec![NO_INSTANCE; pixels],
        ambiguous: vec![false; pixels],
        depth_floor: vec![0.0; pixels],
        normal_floor_deg: vec![0.0; pixels],
        layers: vec![0; pixels],
    };

    let context = Context::new(scene, camera);

    // One work item per row of tiles; threads take the next band until none is left.
    let band_len = width as usize * TILE as usize;
    let bands: Vec<Band> = frame
        .depth
        .chunks_mut(band_len)
        .zip(frame.normal.chunks_mut(band_len))
        .zip(frame.id.chunks_mut(band_len))
        .zip(frame.ambiguous.chunks_mut(band_len))
        .zip(frame.depth_floor.chunks_mut(band_len))
        .zip(frame.normal_floor_deg.chunks_mut(band_len))
        .zip(frame.layers.chunks_mut(band_len))
        .enumerate()
        .map(
            |(
                tile_row,
                ((((((depth, normal), id), ambiguous), depth_floor), normal_floor), layers),
            )| {
                Band {
                    tile_row: tile_row as u32,
                    depth,
                    normal,
                    id,
                    ambiguous,
                    depth_floor,
                    normal_floor,
                    layers,
                }
            },
        )
        .collect();
    let threads = thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(bands.len());
    let queue = Mutex::new(bands);
    thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                // Popping cannot panic, so a poisoned lock still holds a consistent queue.
                let next = queue.lock().unwrap_or_else(PoisonError::into_inner).pop();
                match next {
                    Some(band) => context.render_band(band),
                    None => break,
                }
            });
        }
    });
    Ok(frame)
}

/// One ellipsoid, ready for many rays.
struct Prepared {
    /// World-to-parameter map, exactly as `Ellipsoid::to_parameter` gives it, so the tiled
    /// renderer and [`intersect`] agree to the bit.
    to_parameter: DMat3,
    center: DVec3,
    /// Largest semi-axis.
    extent: f64,
    /// No point of the ellipsoid is nearer than this view depth: the front-to-back sort key.
    min_depth: f64,
}

/// The output rows of one row of tiles.
struct Band<'a> {
    tile_row: u32,
    depth: &'a mut [f64],
    normal: &'a mut [DVec3],
    id: &'a mut [u32],
    ambiguous: &'a mut [bool],
    depth_floor: &'a mut [f64],
    normal_floor: &'a mut [f64],
    layers: &'a mut [u32],
}

/// Everything the band workers share, read-only.
struct Context<'a> {
    camera: &'a Camera,
    forward: DVec3,
    prepared: Vec<Prepared>,
    bins: TileBins,
}

/// The result of sampling one pixel.
struct PixelSample {
    centre: Trace,
    ambiguous: bool,
    depth_floor: f64,
    normal_floor_deg: f64,
}

/// What a ray sees across a list of ellipsoids.
#[derive(Clone, Copy)]
struct Trace {
    /// The winning instance and its hit.
    best: Option<(u32, Hit)>,
    /// The second nearest visible depth (`INFINITY` if none); exact only when asked for.
    second_depth: f64,
}

impl Trace {
    /// What must agree between the centre and its neighbours: instance (or none) and cap-ness.
    fn key(&self) -> Option<(u32, bool)> {
        self.best.map(|(id, hit)| (id, hit.cap))
    }

    /// The two nearest visible depths tie.
    fn tied(&self) -> bool {
        match self.best {
            Some((_, hit)) => self.second_depth - hit.depth <= DEPTH_TIE * hit.depth,
            None => false,
        }
    }
}

impl<'a> Context<'a> {
    fn new(scene: &Scene, camera: &'a Camera) -> Self {
        let basis = camera.basis();
        let prepared: Vec<Prepared> = scene
            .ellipsoids
            .iter()
            .map(|e| Prepared {
                to_parameter: e.to_parameter(),
                center: e.center,
                extent: e.bounding_radius(),
                min_depth: {
                    let (z, r) = (
                        (e.center - camera.eye).dot(basis.forward),
                        e.bounding_radius(),
                    );
                    // Slightly low, so rounding never sorts an ellipsoid behind its own hit.
                    (z - r) - 1e-9 * (z.abs() + r)
                },
            })
            .collect();
        let bins = TileBins::build(scene, camera, &basis);
        Self {
            camera,
            forward: basis.forward,
            prepared,
            bins,
        }
    }

    fn render_band(&self, band: Band<'_>) {
        let width = self.camera.width;
        let rows = (band.depth.len() / width as usize) as u32;
        let mut candidates = Vec::new();
        for tile_col in 0..self.bins.tiles_x {
            candidates.clear();
            candidates.extend_from_slice(self.bins.tile(tile_col, band.tile_row));
            if candidates.is_empty() {
                continue;
            }
            // Front to back, so a trace can stop once nothing left can be nearer.
            candidates.sort_unstable_by(|&a, &b| {
                let (pa, pb) = (&self.prepared[a as usize], &self.prepared[b as usize]);
                pa.min_depth.total_cmp(&pb.min_depth).then(a.cmp(&b))
            });
            let i0 = tile_col * TILE;
            let i1 = (i0 + TILE).min(width);
            for row in 0..rows {
                let j = band.tile_row * TILE + row;
                for i in i0..i1 {
                    let index = row as usize * width as usize + i as usize;
                    let sample = self.pixel(i, j, &candidates);
                    if let Some((id, hit)) = sample.centre.best {
                        band.depth[index] = hit.depth;
                        band.normal[index] = hit.normal;
                        band.id[index] = id;
                    }
                    band.ambiguous[index] = sample.ambiguous;
                    band.depth_floor[index] = sample.depth_floor;
                    band.normal_floor[index] = sample.normal_floor_deg;
                    band.layers[index] = self.layers(&self.camera.ray(i, j), &candidates);
                }
            }
        }
    }

    /// The centre sample of pixel `(i, j)`, whether the pixel is ambiguous, and its float32
    /// error floors (from the same four neighbour samples).
    fn pixel(&self, i: u32, j: u32, candidates: &[u32]) -> PixelSample {
        let centre = self.trace(&self.camera.ray(i, j), candidates, true);
        let mut sample = PixelSample {
            centre,
            ambiguous: true,
            depth_floor: 0.0,
            normal_floor_deg: 0.0,
        };
        if centre.tied() {
            return sample;
        }
        let centre_px = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
        let key = centre.key();
        let mut neighbours = [None; 4];
        // Left, right, down, up (pixel y grows downwards).
        let steps = [(-HAIR, 0.0), (HAIR, 0.0), (0.0, HAIR), (0.0, -HAIR)];
        for (slot, (dx, dy)) in neighbours.iter_mut().zip(steps) {
            let at = centre_px + DVec2::new(dx, dy);
            let trace = self.trace(&self.camera.ray_at_pixel(at), candidates, false);
            if trace.key() != key {
                return sample;
            }
            *slot = trace.best.map(|(_, hit)| hit);
        }
        sample.ambiguous = false;
        if let (Some((id, hit)), [Some(x0), Some(x1), Some(y0), Some(y1)]) =
            (centre.best, neighbours)
        {
            if !hit.cap {
                let e = &self.prepared[id as usize];
                // Gradients per pixel from central differences over 2 HAIR.
                let depth_grad = ((x1.depth - x0.depth).powi(2) + (y1.depth - y0.depth).powi(2))
                    .sqrt()
                    / (2.0 * HAIR);
                let turn = |a: DVec3, b: DVec3| a.cross(b).length().atan2(a.dot(b));
                let normal_grad = (turn(x0.normal, x1.normal).powi(2)
                    + turn(y0.normal, y1.normal).powi(2))
                .sqrt()
                    / (2.0 * HAIR);
                // What float32 resolves: screen position, and the surface's position relative to
                // the eye in view axes -- across the view by the centre's lateral offset, along
                // it by its depth (each plus the ellipsoid's size).
                let rel = e.center - self.camera.eye;
                let along = rel.dot(self.forward);
                let across = (rel - along * self.forward).length();
                let lateral = F32_ROUNDOFF * (across + e.extent);
                let axial = F32_ROUNDOFF * (along.abs() + e.extent);
                // The shaders' NDC reach 1 plus the principal point's shift (§3.2).
                let (nx, ny) = self.camera.ndc_shift();
                let reach = self.camera.width as f64 * (1.0 + nx.abs())
                    + self.camera.height as f64 * (1.0 + ny.abs());
                let shift_px = F32_ROUNDOFF * reach + lateral / self.pixel_size_at(hit.depth);
                sample.depth_floor = (depth_grad * shift_px + axial) / hit.depth;
                sample.normal_floor_deg = (normal_grad * shift_px).to_degrees();
            }
        }
        sample
    }

    /// World size of one pixel (its shorter side) at view depth `depth`.
    fn pixel_size_at(&self, depth: f64) -> f64 {
        let k = self.camera.intrinsics();
        let per_unit = 1.0 / k.fx.max(k.fy);
        if self.camera.is_orthographic() {
            per_unit
        } else {
            depth * per_unit
        }
    }

    /// How many of `candidates` the ray meets where they are visible (surface or cap).
    fn layers(&self, ray: &Ray, candidates: &[u32]) -> u32 {
        let near = self.camera.near;
        candidates
            .iter()
            .filter(|&&id| {
                let e = &self.prepared[id as usize];
                let m = &e.to_parameter;
                hit_unit_sphere(
                    *m * (ray.origin - e.center),
                    *m * ray.direction,
                    m,
                    near,
                    self.forward,
                )
                .is_some()
            })
            .count() as u32
    }

    /// Nearest visible hit along `ray` among `candidates` (sorted front to back); with
    /// `want_second`, also the exact second nearest depth wherever it could make a tie.
    fn trace(&self, ray: &Ray, candidates: &[u32], want_second: bool) -> Trace {
        let near = self.camera.near;
        let mut trace = Trace {
            best: None,
            second_depth: f64::INFINITY,
        };
        let mut cutoff = f64::INFINITY;
        for &id in candidates {
            let e = &self.prepared[id as usize];
            // Everything from here on lies beyond the cutoff: it can neither win nor tie.
            if e.min_depth > cutoff {
                break;
            }
            let m = &e.to_parameter;
            let Some(hit) = hit_unit_sphere(
                *m * (ray.origin - e.center),
                *m * ray.direction,
                m,
                near,
                self.forward,
            ) else {
                continue;
            };
            let better = match trace.best {
                None => true,
                Some((best_id, best)) => {
                    hit.depth < best.depth || (hit.depth == best.depth && id < best_id)
                }
            };
            if !better {
                trace.second_depth = trace.second_depth.min(hit.depth);
                continue;
            }
            if let Some((_, previous)) = trace.best {
                trace.second_depth = previous.depth;
            }
            trace.best = Some((id, hit));
            cutoff = if want_second {
                hit.depth + DEPTH_TIE * hit.depth
            } else {
                hit.depth
            };
        }
        trace
    }
}

/// Ellipsoid indices per screen tile, in index order (compressed rows).
struct TileBins {
    tiles_x: u32,
    /// `starts[t]..starts[t + 1]` indexes `entries` for tile `t = row * tiles_x + col`.
    starts: Vec<usize>,
    entries: Vec<u32>,
}

/// An inclusive range of tiles.
#[derive(Clone, Copy)]
struct TileRange {
    x0: u32,
    x1: u32,
    y0: u32,
    y1: u32,
}

impl TileBins {
    fn build(scene: &Scene, camera: &Camera, basis: &Basis) -> Self {
        let tiles_x = camera.width.div_ceil(TILE);
        let tiles_y = camera.height.div_ceil(TILE);
        let ranges: Vec<Option<TileRange>> = scene
            .ellipsoids
            .iter()
            .map(|e| tile_range(e, camera, basis, tiles_x, tiles_y))
            .collect();
        let tile_count = (tiles_x * tiles_y) as usize;
        let mut counts = vec![0usize; tile_count + 1];
        for r in ranges.iter().flatten() {
            for ty in r.y0..=r.y1 {
                for tx in r.x0..=r.x1 {
                    counts[(ty * tiles_x + tx) as usize + 1] += 1;
                }
            }
        }
        for t in 0..tile_count {
            counts[t + 1] += counts[t];
        }
        let starts = counts;
        let mut fill = starts.clone();
        let mut entries = vec![0u32; starts[tile_count]];
        for (id, r) in ranges.iter().enumerate() {
            let Some(r) = r else { continue };
            for ty in r.y0..=r.y1 {
                for tx in r.x0..=r.x1 {
                    let t = (ty * tiles_x + tx) as usize;
                    entries[fill[t]] = id as u32;
                    fill[t] += 1;
                }
            }
        }
        Self {
            tiles_x,
            starts,
            entries,
        }
    }

    fn tile(&self, col: u32, row: u32) -> &[u32] {
        let t = (row * self.tiles_x + col) as usize;
        &self.entries[self.starts[t]..self.starts[t + 1]]
    }
}

/// The tiles that may see any of `e`: the screen rectangle of its bounding sphere's part in front
/// of the near plane, widened by a pixel; `None` when nothing of it is in front of the near plane
/// or on screen.
fn tile_range(
    e: &Ellipsoid,
    camera: &Camera,
    basis: &Basis,
    tiles_x: u32,
    tiles_y: u32,
) -> Option<TileRange> {
    let rel = e.center - camera.eye;
    let (x, y, z) = (
        rel.dot(basis.right),
        rel.dot(basis.up),
        rel.dot(basis.forward),
    );
    // A hair larger than the bounding radius so rounding cannot make the rectangle too small.
    let radius = e.bounding_radius() * (1.0 + 1e-9);
    if z + radius < camera.near {
        return None;
    }
    // The rectangle on the screen plane: (x_min, x_max, y_min, y_max).
    let screen = if camera.is_orthographic() {
        (x - radius, x + radius, y - radius, y + radius)
    } else {
        let (x0, x1) = clipped_slopes(x, z, radius, camera.near)?;
        let (y0, y1) = clipped_slopes(y, z, radius, camera.near)?;
        (x0, x1, y0, y1)
    };
    // To continuous pixel coordinates (pixel i spans [i, i + 1]; rows grow downwards).
    let (w, h) = (camera.width as f64, camera.height as f64);
    let low = camera.screen_to_pixel(DVec2::new(screen.0, screen.3));
    let high = camera.screen_to_pixel(DVec2::new(screen.1, screen.2));
    let (px0, py0) = (low.x - 1.0, low.y - 1.0);
    let (px1, py1) = (high.x + 1.0, high.y + 1.0);
    if !(px1 >= 0.0 && px0 <= w && py1 >= 0.0 && py0 <= h) {
        return None;
    }
    // Float-to-int casts saturate, so huge rectangles clamp to the screen.
    let tile = |p: f64, n: u32| ((p.max(0.0) / TILE as f64) as u32).min(n - 1);
    Some(TileRange {
        x0: tile(px0, tiles_x),
        x1: tile(px1, tiles_x),
        y0: tile(py0, tiles_y),
        y1: tile(py1, tiles_y),
    })
}

/// Range of slopes `lateral / forward` over the part of a sphere in front of the near plane,
/// along one screen axis: the exact extent of its perspective projection, also when it crosses
/// the near plane or the eye plane or holds the eye (after Mara & McGuire 2013).
///
/// Slopes depend only on the lateral and forward coordinates, so the problem is the disc of
/// centre `(x, z)` and radius `r` clipped to `Z >= near`. Over that convex set the extremes of
/// `X / Z` lie where lines through the eye touch the arc (tangent points that survive the clip)
/// or at the corners where the circle meets the near line. `None` when the clipped disc is empty.
fn clipped_slopes(x: f64, z: f64, r: f64, near: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut take = |px: f64, pz: f64| {
        let slope = px / pz;
        lo = lo.min(slope);
        hi = hi.max(slope);
    };
    let height = (z - near).abs();
    if height < r {
        let half_chord = ((r - height) * (r + height)).sqrt();
        take(x - half_chord, near);
        take(x + half_chord, near);
    }
    let d2 = x * x + z * z;
    let d = d2.sqrt();
    if d > r {
        // Tangent points from the eye: C (1 - r^2/d^2) +- perp(C) r sqrt(d^2 - r^2) / d^2.
        let along = 1.0 - (r / d) * (r / d);
        let across = r * ((d - r) * (d + r)).sqrt() / d2;
        for sign in [-1.0, 1.0] {
            let tx = x * along - sign * across * z;
            let tz = z * along + sign * across * x;
            if tz >= near {
                take(tx, tz);
            }
        }
    }
    (lo <= hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use ellipsoid_splat::Projection;
    use glam::{DQuat, EulerRot};

    use super::*;

    fn sphere(center: DVec3, radius: f64) -> Ellipsoid {
        Ellipsoid::new(center, DVec3::splat(radius), DQuat::IDENTITY, None).unwrap()
    }

    fn perspective(eye: DVec3, target: DVec3, fov: f64, near: f64, w: u32, h: u32) -> Camera {
        let p = Projection::Perspective { fov_y_deg: fov };
        Camera::new(eye, target, DVec3::Y, p, near, w, h).unwrap()
    }

    /// A small deterministic generator (SplitMix64) so tests need no extra crate.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }

        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }

        fn ellipsoid(&mut self, extent: f64, rmin: f64, rmax: f64) -> Ellipsoid {
            let c = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let r = DVec3::new(
                self.range(rmin, rmax),
                self.range(rmin, rmax),
                self.range(rmin, rmax),
            );
            let q = DQuat::from_xyzw(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            Ellipsoid::new(c * extent, r, q, None).unwrap()
        }
    }

    #[test]
    fn sphere_dead_ahead_is_exact() {
        let cam = perspective(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 45.0, 0.1, 65, 33);
        let ray = cam.ray(32, 16);
        let hit = intersect(
            &sphere(DVec3::ZERO, 1.0),
            &ray,
            cam.near,
            cam.basis().forward,
        )
        .unwrap();
        assert_eq!(hit.depth, 4.0);
        assert_eq!(hit.normal, -cam.basis().forward);
        assert!(!hit.cap);
    }

    #[test]
    fn rotated_ellipsoid_hit_is_on_surface_with_analytic_normal() {
        let e = Ellipsoid::new(
            DVec3::new(0.3, -0.2, 0.1),
            DVec3::new(3.0, 1.0, 0.5),
            DQuat::from_euler(EulerRot::XYZ, 0.4, -0.9, 1.7),
            None,
        )
        .unwrap();
        let cam = perspective(DVec3::new(4.0, 5.0, 9.0), DVec3::ZERO, 25.0, 0.1, 48, 40);
        let f = cam.basis().forward;
        let m = e.to_parameter();
        let mut hits = 0;
        for j in 0..cam.height {
            for i in 0..cam.width {
                let ray = cam.ray(i, j);
                let Some(hit) = intersect(&e, &ray, cam.near, f) else {
                    continue;
                };
                hits += 1;
                let x = ray.origin + hit.depth * ray.direction;
                let p = m * (x - e.center);
                assert!((p.length_squared() - 1.0).abs() < 1e-12, "{}", p.length());
                assert!((cam.view_depth(x) - hit.depth).abs() < 1e-12 * hit.depth);
                let gradient = (m.transpose() * m * (x - e.center)).normalize();
                assert!((gradient - hit.normal).length() < 1e-12);
                assert!(hit.normal.dot(ray.direction) < 0.0, "normal faces the eye");
            }
        }
        assert!(hits > 100, "only {hits} hits");
    }

    #[test]
    fn orthographic_rays_hit_where_expected() {
        let p = Projection::Orthographic { height: 3.0 };
        let cam = Camera::new(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            p,
            0.1,
            32,
            32,
        )
        .unwrap();
        let e = sphere(DVec3::ZERO, 1.0);
        let mut hits = 0;
        for j in 0..cam.height {
            for i in 0..cam.width {
                let ray = cam.ray(i, j);
                let (x, y) = (ray.origin.x, ray.origin.y);
                let inside = 1.0 - x * x - y * y;
                match intersect(&e, &ray, cam.near, cam.basis().forward) {
                    Some(hit) => {
                        hits += 1;
                        let z = inside.sqrt();
                        assert!((hit.depth - (5.0 - z)).abs() < 1e-12);
                        assert!((hit.normal - DVec3::new(x, y, z)).length() < 1e-12);
                    }
                    None => assert!(inside < 1e-12),
                }
            }
        }
        assert!(hits > 300, "only {hits} hits");
    }

    #[test]
    fn camera_inside_sees_the_cap_everywhere() {
        let cam = perspective(DVec3::new(0.0, 0.0, 0.5), DVec3::NEG_Z, 90.0, 0.1, 17, 9);
        let scene = Scene::new(vec![sphere(DVec3::new(0.1, 0.0, 0.0), 2.0)]);
        let frame = render_reference(&scene, &cam).unwrap();
        let f = cam.basis().forward;
        for j in 0..cam.height {
            for i in 0..cam.width {
                let hit = intersect(&scene.ellipsoids[0], &cam.ray(i, j), cam.near, f).unwrap();
                assert!(hit.cap);
                assert_eq!(hit.depth, cam.near);
                assert_eq!(hit.normal, -f);
                let k = frame.index(i, j);
                assert_eq!(
                    (frame.depth[k], frame.normal[k], frame.id[k]),
                    (cam.near, -f, 0)
                );
                assert!(!frame.ambiguous[k]);
            }
        }
    }

    #[test]
    fn near_plane_cut_shows_cap_inside_and_surface_outside() {
        // The near plane at depth 4.5 cuts a unit sphere whose front is at depth 4.
        let cam = perspective(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 30.0, 4.5, 64, 64);
        let e = sphere(DVec3::ZERO, 1.0);
        let f = cam.basis().forward;
        let cut_radius = (1.0f64 - 0.25).sqrt();
        let (mut caps, mut surfaces) = (0, 0);
        for j in 0..cam.height {
            for i in 0..cam.width {
                let ray = cam.ray(i, j);
                // Distance from the axis where the ray crosses the near plane.
                let rho = (ray.direction - f).length() * cam.near;
                let hit = intersect(&e, &ray, cam.near, f);
                if rho < cut_radius - 1e-9 {
                    let hit = hit.unwrap();
                    assert!(hit.cap && hit.depth == cam.near && hit.normal == -f);
                    caps += 1;
                } else if rho > cut_radius + 1e-9 {
                    if let Some(hit) = hit {
                        assert!(!hit.cap && hit.depth > cam.near);
                        surfaces += 1;
                    }
                }
            }
        }
        assert!(
            caps > 100 && surfaces > 100,
            "caps {caps}, surfaces {surfaces}"
        );
    }

    #[test]
    fn far_away_spheres_keep_relative_depth_accuracy() {
        for (distance, radius) in [(1e7, 1.0), (1e5, 1e-2)] {
            let center = DVec3::new(1.0, 2.0, 3.0);
            let eye = center + DVec3::new(1.0, 2.0, 2.0) / 3.0 * distance;
            let cam = perspective(eye, center, 10.0, 0.1, 64, 64);
            let ray = cam.ray_at_pixel(DVec2::new(32.0, 32.0));
            let e = sphere(center, radius);
            let hit = intersect(&e, &ray, cam.near, cam.basis().forward).unwrap();
            let want = cam.view_depth(center) - radius;
            let rel = (hit.depth - want).abs() / want;
            assert!(rel < 1e-12, "distance {distance}: relative error {rel}");
            assert!((hit.normal + cam.basis().forward).length() < 1e-6);
        }
    }

    #[test]
    fn ambiguity_lies_only_on_the_silhouette() {
        // Odd height, even width: pixel centres at (+-10.5, 0) px from the image centre, where
        // the silhouette circle is placed.
        let (w, h, fov, dist) = (64u32, 47u32, 30.0f64, 10.0f64);
        let half = (fov.to_radians() * 0.5).tan();
        let circle_px = 10.5;
        let tan_r = circle_px / (h as f64 * 0.5) * half;
        let radius = dist * tan_r.atan().sin();
        let cam = perspective(DVec3::new(0.0, 0.0, dist), DVec3::ZERO, fov, 0.1, w, h);
        let frame = render_reference(&Scene::new(vec![sphere(DVec3::ZERO, radius)]), &cam).unwrap();
        let mut flagged = 0;
        for j in 0..h {
            for i in 0..w {
                let dx = i as f64 + 0.5 - w as f64 * 0.5;
                let dy = j as f64 + 0.5 - h as f64 * 0.5;
                let off = (dx.hypot(dy) - circle_px).abs();
                let k = frame.index(i, j);
                if frame.ambiguous[k] {
                    flagged += 1;
                    assert!(
                        off < 1.01 * HAIR,
                        "pixel ({i},{j}) is {off} px off the circle"
                    );
                }
                if off > 2.0 * HAIR {
                    assert_eq!(frame.id[k] == 0, dx.hypot(dy) < circle_px, "({i},{j})");
                }
            }
        }
        assert!(frame.ambiguous[frame.index(w / 2 - 11, h / 2)]);
        assert!(frame.ambiguous[frame.index(w / 2 + 10, h / 2)]);
        assert!(flagged <= 8, "{flagged} ambiguous pixels");
    }

    #[test]
    fn depth_ties_are_ambiguous_and_go_to_the_lower_index() {
        let cam = perspective(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 30.0, 0.1, 24, 24);
        let e = sphere(DVec3::ZERO, 1.0);
        let frame =
            render_reference(&Scene::new(vec![sphere(DVec3::X * 9.0, 0.1), e, e]), &cam).unwrap();
        let covered: Vec<usize> = (0..frame.len())
            .filter(|&k| frame.id[k] != NO_INSTANCE)
            .collect();
        assert!(covered.len() > 50);
        for k in covered {
            assert_eq!(frame.id[k], 1);
            assert!(frame.ambiguous[k]);
        }
    }

    /// The tiled, front-to-back, multi-threaded renderer against every ellipsoid for every
    /// pixel: bins must never lose an ellipsoid, including ones crossing the eye plane.
    fn matches_brute_force(cam: &Camera, scene: &Scene) {
        let frame = render_reference(scene, cam).unwrap();
        let f = cam.basis().forward;
        let mut covered = 0;
        for j in 0..cam.height {
            for i in 0..cam.width {
                let ray = cam.ray(i, j);
                let mut best: Option<(u32, Hit)> = None;
                for (id, e) in scene.ellipsoids.iter().enumerate() {
                    if let Some(hit) = intersect(e, &ray, cam.near, f) {
                        if best.is_none_or(|(_, b)| hit.depth < b.depth) {
                            best = Some((id as u32, hit));
                        }
                    }
                }
                let k = frame.index(i, j);
                match best {
                    Some((id, hit)) => {
                        covered += 1;
                        assert_eq!(frame.id[k], id, "pixel ({i},{j})");
                        assert_eq!(frame.depth[k], hit.depth);
                        assert_eq!(frame.normal[k], hit.normal);
                    }
                    None => {
                        assert_eq!(frame.id[k], NO_INSTANCE, "pixel ({i},{j})");
                        assert_eq!(frame.depth[k], f64::INFINITY);
                        assert_eq!(frame.normal[k], DVec3::ZERO);
                    }
                }
            }
        }
        assert!(covered > frame.len() / 10, "only {covered} covered pixels");
    }

    #[test]
    fn tiled_render_matches_brute_force_perspective() {
        let mut rng = Rng(7);
        let mut scene = Scene::new((0..300).map(|_| rng.ellipsoid(4.0, 0.05, 0.6)).collect());
        // The eye sits inside the cloud, so some ellipsoids cross the eye plane or the near
        // plane, and some are behind.
        let cam = perspective(DVec3::new(0.2, 0.1, 1.5), DVec3::ZERO, 70.0, 0.05, 83, 61);
        // One more crosses the eye plane beside the eye and is cut open by the near plane.
        let b = cam.basis();
        scene
            .ellipsoids
            .push(sphere(cam.eye + 0.2 * b.forward + 0.3 * b.right, 0.32));
        matches_brute_force(&cam, &scene);
        let frame = render_reference(&scene, &cam).unwrap();
        let caps = frame.depth.iter().filter(|&&d| d == cam.near).count();
        assert!(caps > 100, "only {caps} cap pixels");
    }

    #[test]
    fn tiled_render_matches_brute_force_orthographic() {
        let mut rng = Rng(11);
        let scene = Scene::new((0..300).map(|_| rng.ellipsoid(4.0, 0.05, 0.6)).collect());
        let p = Projection::Orthographic { height: 6.0 };
        let cam = Camera::new(
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::ZERO,
            DVec3::Y,
            p,
            0.3,
            70,
            52,
        )
        .unwrap();
        matches_brute_force(&cam, &scene);
    }

    #[test]
    fn clipped_slopes_bound_the_clipped_disc_tightly() {
        let mut rng = Rng(3);
        for _ in 0..2000 {
            let (x, z, r) = (
                rng.range(-3.0, 3.0),
                rng.range(-2.0, 3.0),
                rng.range(0.01, 2.0),
            );
            let near = rng.range(0.01, 1.0);
            let Some((lo, hi)) = clipped_slopes(x, z, r, near) else {
                assert!(z + r <= near + 1e-12, "({x}, {z}, {r}, {near})");
                continue;
            };
            // Sample the clipped disc's boundary: the arc and the chord on the near line.
            let (mut seen_lo, mut seen_hi) = (f64::INFINITY, f64::NEG_INFINITY);
            let steps = 20_000;
            for k in 0..steps {
                let a = k as f64 / steps as f64 * std::f64::consts::TAU;
                let (px, pz) = (x + r * a.cos(), z + r * a.sin());
                let (px, pz) = if pz >= near {
                    (px, pz)
                } else {
                    // Project onto the chord, which lies inside the clipped disc.
                    let w = (r * r - (near - z).powi(2)).max(0.0).sqrt();
                    (px.clamp(x - w, x + w), near)
                };
                let s = px / pz;
                assert!(s >= lo - 1e-9 * (1.0 + s.abs()) && s <= hi + 1e-9 * (1.0 + s.abs()));
                seen_lo = seen_lo.min(s);
                seen_hi = seen_hi.max(s);
            }
            // Tight: the sampled extremes come close to the bounds.
            let tol = 1e-3 * (1.0 + lo.abs().max(hi.abs()));
            assert!(
                seen_lo - lo < tol && hi - seen_hi < tol,
                "({x}, {z}, {r}, {near})"
            );
        }
    }

    #[test]
    fn invalid_camera_is_rejected() {
        let mut cam = perspective(DVec3::Z * 5.0, DVec3::ZERO, 45.0, 0.1, 8, 8);
        cam.near = -1.0;
        let err = render_reference(&Scene::default(), &cam).unwrap_err();
        assert!(err.to_string().contains("near"), "{err}");
    }
}
