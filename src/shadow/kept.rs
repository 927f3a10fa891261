//! The shadows kept per polygon (004 section 4.7's shadow polygons, kept
//! as surface detail after Atherton, Weiler and Greenberg 1978): the
//! united pieces of each light on a whole polygon, and the overlap regions
//! of all lights on it, in world coordinates, cast once and shared by
//! every fragment, mirror and frame that shows the polygon, within a
//! memory bound.

use rustc_hash::FxHashMap as HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use glam::DVec3;

use super::bounds;
use super::overlap::ShadowRegion;

/// The shadows on whole polygons in world coordinates, by (object,
/// polygon, light). A polygon's shadows are kept the second time they
/// are asked for, or the first when the asker knows more will follow (a
/// piece of a polygon the sort split, a still whose tree has mirror or
/// refraction levels, the frames of an animation after its first): the
/// polygons of a still without such levels, seen once, keep nothing.
/// Kept up to [`MAX_KEPT_BYTES`]; past it they are cast again when
/// asked, the same.
pub(super) struct PieceCache<V> {
    shards: [Mutex<HashMap<PieceKey, Kept<V>>>; SHARDS],
    bytes: AtomicUsize,
}

impl<V> Default for PieceCache<V> {
    fn default() -> Self {
        PieceCache {
            shards: std::array::from_fn(|_| Mutex::default()),
            bytes: AtomicUsize::new(0),
        }
    }
}

/// Object, polygon, light.
type PieceKey = (u32, u32, u32);

/// A polygon's shadows as the cache holds them.
enum Kept<V> {
    /// Asked for once, not kept.
    Seen,
    /// Kept.
    Shadows(V),
}

/// The shadows on a whole polygon (world coordinates); `None`: none.
pub type WholePieces = Option<Arc<WholeShadows>>;

/// A polygon's shadows as [`super::Casting::on_polygon`] gives them.
pub enum OnPolygon {
    /// Kept in the index.
    Kept(Arc<WholeShadows>),
    /// Just cast, not kept.
    Cast(Vec<Vec<DVec3>>),
}

/// The shadow pieces on a whole polygon, their points in one list.
pub struct WholeShadows {
    points: Box<[DVec3]>,
    /// Where each piece ends in `points`.
    ends: Box<[u32]>,
}

impl WholeShadows {
    pub(super) fn new(pieces: &[Vec<DVec3>]) -> WholeShadows {
        let mut ends = Vec::with_capacity(pieces.len());
        let mut points = Vec::with_capacity(pieces.iter().map(Vec::len).sum());
        for p in pieces {
            points.extend_from_slice(p);
            ends.push(points.len() as u32);
        }
        WholeShadows {
            points: points.into_boxed_slice(),
            ends: ends.into_boxed_slice(),
        }
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> impl Iterator<Item = &[DVec3]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts
            .zip(self.ends.iter().copied())
            .map(|(a, b)| &self.points[a as usize..b as usize])
    }

    /// The memory it takes, roughly.
    pub(super) fn bytes(&self) -> usize {
        64 + self.points.len() * std::mem::size_of::<DVec3>() + self.ends.len() * 4
    }
}

/// The overlap regions on a whole polygon (world coordinates), with the
/// box of each.
pub struct WholeRegions {
    pub(super) regions: Vec<ShadowRegion>,
    boxes: Vec<(DVec3, DVec3)>,
}

impl WholeRegions {
    pub(super) fn new(regions: Vec<ShadowRegion>) -> WholeRegions {
        let boxes = regions.iter().map(|(ring, _)| bounds(ring)).collect();
        WholeRegions { regions, boxes }
    }

    /// Copies of the regions whose boxes meet the box `near`.
    pub(super) fn near(&self, (lo, hi): (DVec3, DVec3)) -> Vec<ShadowRegion> {
        self.regions
            .iter()
            .zip(&self.boxes)
            .filter(|(_, (rlo, rhi))| !(rlo.cmpgt(hi).any() || rhi.cmplt(lo).any()))
            .map(|(r, _)| r.clone())
            .collect()
    }

    /// The memory it takes, roughly.
    pub(super) fn bytes(&self) -> usize {
        let regions: usize = self
            .regions
            .iter()
            .map(|(p, l)| 48 + 48 + p.len() * 24 + l.len() * 4)
            .sum();
        64 + regions
    }
}

/// Locks the pieces are spread over (threads cast on different polygons).
const SHARDS: usize = 16;

/// The memory the kept shadows may take: ample for the pieces of a
/// furnished room (office2's take 6 MB), and no second copy of the
/// shadows of ten million polygons seen once each.
const MAX_KEPT_BYTES: usize = 64 << 20;

/// What the cache says of a polygon asked for.
pub(super) enum Found<V> {
    /// Its kept shadows.
    Kept(V),
    /// Asked for before: keep them this time.
    Again,
    /// Never asked for.
    First,
}

impl<V: Clone> PieceCache<V> {
    fn shard(&self, key: PieceKey) -> std::sync::MutexGuard<'_, HashMap<PieceKey, Kept<V>>> {
        let (o, p, j) = key;
        let h = (o as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (p as u64) ^ ((j as u64) << 40);
        let shard = &self.shards[(h.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 60) as usize % SHARDS];
        shard.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// What is known of `key`; a first request is noted.
    pub(super) fn get(&self, key: PieceKey) -> Found<V> {
        let mut shard = self.shard(key);
        match shard.get(&key) {
            Some(Kept::Shadows(s)) => Found::Kept(s.clone()),
            Some(Kept::Seen) => Found::Again,
            None => {
                if self.bytes.fetch_add(24, Ordering::Relaxed) + 24 > MAX_KEPT_BYTES {
                    self.bytes.fetch_sub(24, Ordering::Relaxed);
                } else {
                    shard.insert(key, Kept::Seen);
                }
                Found::First
            }
        }
    }

    /// Keeps the shadows of `key` (`size` bytes), within the memory
    /// bound.
    pub(super) fn put(&self, key: PieceKey, pieces: &V, size: usize) {
        if self.bytes.fetch_add(size, Ordering::Relaxed) + size > MAX_KEPT_BYTES {
            self.bytes.fetch_sub(size, Ordering::Relaxed);
            return;
        }
        self.shard(key).insert(key, Kept::Shadows(pieces.clone()));
    }
}
