//! Visibility queries, apart from shading: the nearest hit along a ray (planes, then the
//! grid front to back, then whatever moves) and a shadow ray's transmittance. Both have a
//! counting twin for statistics, and the nearest hit a brute-force reference for tests
//! ([`crate::testing::closest_hit_brute`]); the packet kernels ([`super::packet`]) are checked
//! against these lane by lane.

use smallvec::SmallVec;

use super::scene::TraceScene;
use crate::accel::walk;
use crate::math::{Ray, Vec3};
use crate::store::{Hit, NoTally, PrimitiveStore, Tally};

/// Nearest hit in `(t_min, t_max)`: planes first, then the grid's cells front to back.
///
/// The direction may have any non-zero length; `t` is in units of it. Counts nothing; see
/// [`closest_hit_tallied`] for the traversal statistics.
#[inline]
pub fn closest_hit<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    closest_hit_tallied(scene, ray, t_min, t_max, &mut NoTally)
}

/// [`closest_hit`], adding the cells visited and primitives tested to `tally` (a
/// [`crate::store::TraversalCost`] counts them).
#[inline]
pub fn closest_hit_tallied<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
) -> Option<Hit> {
    closest_hit_at(scene, ray, t_min, t_max, 0.0, tally)
}

/// [`closest_hit_tallied`] for a ray at time `s` of the shutter interval (0 at open, 1 at
/// close): moving objects are seen where they are then ([`super::motion`]); the static scene
/// is the same at every time.
#[inline]
pub fn closest_hit_at<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    s: f32,
    tally: &mut T,
) -> Option<Hit> {
    let mut nearest = Nearest::new(t_max);
    let store = &scene.store;
    for i in 0..store.unbounded_count() {
        tally.tests(1);
        nearest.offer(store.intersect_unbounded(i, ray, t_min, nearest.t));
    }
    nearest.offer(grid_hit(scene, ray, t_min, nearest.t, tally));
    if let Some(motion) = &scene.motion {
        nearest.offer(motion.nearest(store.meshes(), ray, t_min, nearest.t, s, tally));
    }
    nearest.hit
}

/// Nearest hit with a bounded object in `(t_min, t_max)`, walking the top-level grid with the
/// walk the mesh grids share ([`walk::nearest`]): the second half of [`closest_hit_tallied`],
/// after the planes.
#[inline]
pub(crate) fn grid_hit<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
) -> Option<Hit> {
    let store = &scene.store;
    walk::nearest(&scene.grid, ray, t_min, t_max, tally, |id, bound, tally| {
        store.intersect_bounded(id, ray, t_min, bound, tally).map(|h| (h.t, h))
    })
}

/// The nearest hit so far and the ray parameter that bounds further searches.
struct Nearest {
    hit: Option<Hit>,
    t: f32,
}

impl Nearest {
    #[inline]
    fn new(t_max: f32) -> Self {
        Self { hit: None, t: t_max }
    }

    /// Keeps `candidate`, which the caller found within `(t_min, self.t)`, so it is nearer.
    #[inline]
    fn offer(&mut self, candidate: Option<Hit>) {
        if let Some(h) = candidate {
            self.t = h.t;
            self.hit = Some(h);
        }
    }
}

/// Fraction of light that passes along `ray` over `(0, t_max)` (`t` in units of the direction's
/// length, which may be any), per colour channel: 0 behind an opaque object, the product of
/// `kt` over every surface
/// crossed otherwise (planes first, then each object's crossings nearest first, the objects in
/// ascending id: `ordered_product`). Counts nothing; see
/// [`transmittance_tallied`] for the traversal statistics.
///
/// Each object is handled whole the first time the walk meets it: all its crossings in
/// `(0, t_max)` are counted then, and a per-ray list of visited ids skips it in later cells.
/// Counting a crossing in "the cell whose t-range holds it" is not enough: a crossing exactly on
/// a wall, or rounded across one, can land in a span whose cell does not store the object.
pub fn transmittance<S: PrimitiveStore>(scene: &TraceScene<S>, ray: &Ray, t_max: f32) -> Vec3 {
    transmittance_tallied(scene, ray, t_max, &mut NoTally)
}

/// [`transmittance`], adding the cells visited and primitives tested to `tally` (a
/// [`TraversalCost`](crate::store::TraversalCost) counts them). Both branches walk the top-level grid with the any-hit walk
/// the mesh grids share ([`walk::any`]); with transmission, "hit" means the light is used up.
pub fn transmittance_tallied<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    transmittance_at(scene, ray, t_max, 0.0, tally)
}

/// [`transmittance_tallied`] for a shadow ray at time `s` of the shutter interval: the static
/// scene's part, times the moving objects' part ([`super::motion::SceneMotion::transmittance`],
/// objects in ascending index) where something moves.
pub fn transmittance_at<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    s: f32,
    tally: &mut T,
) -> Vec3 {
    let pass = static_transmittance(scene, ray, t_max, tally);
    match &scene.motion {
        Some(motion) if pass != Vec3::ZERO => {
            let kt = |m| scene.material(m).kt;
            let opaque = !scene.effects.transmission;
            pass * motion.transmittance(scene.store.meshes(), ray, t_max, s, opaque, kt, tally)
        }
        _ => pass,
    }
}

/// The static scene's part of [`transmittance_at`].
fn static_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let pass = planes_transmittance(scene, ray, t_max, tally);
    if pass == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let grid = &scene.grid;
    if !scene.effects.transmission {
        // Any crossing anywhere in (0, t_max) blocks the light: no bookkeeping needed.
        let blocked = walk::any(grid, ray, 0.0, t_max, tally, |id, tally| {
            store.occludes_bounded(id, ray, 0.0, t_max, tally)
        });
        return if blocked { Vec3::ZERO } else { pass };
    }
    let mut shares = Shares::new();
    let blocked = walk::any(grid, ray, 0.0, t_max, tally, |id, tally| {
        let Some(slot) = shares.slot(id) else { return false };
        let share = object_transmittance(scene, id, ray, t_max, tally);
        shares.insert(slot, id, share);
        share == Vec3::ZERO
    });
    if blocked {
        Vec3::ZERO
    } else {
        ordered_product(pass, shares.in_id_order().iter().copied())
    }
}

/// Objects met inline before a shadow ray's [`Shares`] spill to the heap: shadow rays through
/// glass usually cross a handful.
const INLINE_SHARES: usize = 8;

/// The objects a shadow ray has met and each one's share of its transmittance, kept in
/// ascending id: membership is a binary search, the product needs no sort, and up to
/// [`INLINE_SHARES`] objects need no allocation.
pub(crate) struct Shares(SmallVec<[(u32, Vec3); INLINE_SHARES]>);

impl Shares {
    #[inline]
    pub(crate) fn new() -> Self {
        Self(SmallVec::new())
    }

    /// Where object `id`'s share goes, or `None` when it already has one.
    #[inline]
    pub(crate) fn slot(&self, id: u32) -> Option<usize> {
        self.0.binary_search_by_key(&id, |&(seen, _)| seen).err()
    }

    /// Records `share` for `id` at `slot` (from [`Shares::slot`]).
    #[inline]
    pub(crate) fn insert(&mut self, slot: usize, id: u32, share: Vec3) {
        self.0.insert(slot, (id, share));
    }

    /// The shares, in ascending object id.
    #[inline]
    pub(crate) fn in_id_order(&self) -> &[(u32, Vec3)] {
        &self.0
    }
}

/// The planes' part of a shadow ray's transmittance: `kt` of every plane crossed in
/// `(0, t_max)`, multiplied in plane order (0 as soon as one blocks; in a scene without
/// transmission, any crossing blocks).
#[inline]
pub(crate) fn planes_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let mut pass = Vec3::ONE;
    for i in 0..store.unbounded_count() {
        tally.tests(1);
        if let Some(h) = store.intersect_unbounded(i, ray, 0.0, t_max) {
            pass *= scene.material(store.material(&h)).kt;
            if !scene.effects.transmission || pass == Vec3::ZERO {
                return Vec3::ZERO;
            }
        }
    }
    pass
}

/// Bounded object `id`'s share of a shadow ray's transmittance: its `kt` once per crossing in
/// `(0, t_max)`, multiplied nearest first; 0 once it blocks.
#[inline]
pub(crate) fn object_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    id: u32,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let mut share = Vec3::ONE;
    let mut t_lo = 0.0;
    while let Some(h) = store.intersect_bounded(id, ray, t_lo, t_max, tally) {
        share *= scene.material(store.material(&h)).kt;
        if share == Vec3::ZERO {
            return Vec3::ZERO;
        }
        t_lo = h.t;
    }
    share
}

/// A shadow ray's transmittance from its planes' part and its objects' shares: the shares are
/// multiplied in ascending object id, an order that does not depend on how the objects were
/// found, so a single ray's walk and a packet's (which meets objects in another order) give the
/// same bits. `shares` must be in ascending, distinct ids.
#[inline]
pub(crate) fn ordered_product(pass: Vec3, shares: impl IntoIterator<Item = (u32, Vec3)>) -> Vec3 {
    let mut last = None;
    shares.into_iter().fold(pass, |pass, (id, share)| {
        debug_assert!(last.is_none_or(|last| last < id), "shares must be in ascending id");
        last = Some(id);
        pass * share
    })
}
