//! The casters of a scene's shadows and their hierarchies, per Point
//! light (Garcia 1986, section 6.4.2: improved shadow generation, a
//! hierarchy of bounding volumes instead of testing every object), and
//! their reuse from frame to frame while the world does not change.

use super::*;

/// How many tolerances the boxes of [`LightFaces`] are widened by: the
/// clipper keeps what lies within a tolerance of each plane of a volume,
/// and within another of its target's plane.
pub(super) const FACE_MARGIN: f64 = 4.0;

/// How many tolerances the box of a shadow volume is widened by: the
/// clipper keeps what lies within the tolerance of each plane, which near
/// the apex of a thin volume reaches farther than the tolerance.
pub(super) const BOX_MARGIN: f64 = 1e4;

/// At most this many casters in the lights' own hierarchies together
/// (32 bytes an item). A light's faces hold one item per caster, and one
/// more for each further face a caster reaches: only the few large
/// polygons that pass near the light reach several.
pub(super) const MAX_LIGHT_ITEMS: usize = 1 << 20;

/// Every displayed polygon of a scene as a caster, in world coordinates
/// (levels below 1 map their shadow volumes back to them), and per Point
/// light the hierarchy of those facing it.
pub struct CasterIndex {
    pub(super) casters: Vec<Caster>,
    pub(super) lights: Vec<OnceLock<LightTree>>,
    /// Per light within the memory bound, its casters as it sees them.
    pub(super) faces: Vec<OnceLock<LightFaces>>,
    /// Whether shadow volumes are looked up in [`Self::faces`] when they
    /// can be (off only to test them against the world hierarchies).
    pub(super) light_space: bool,
    /// Every caster, for the lights past the memory bound.
    pub(super) shared: OnceLock<LightTree>,
    /// The bound: [`MAX_LIGHT_ITEMS`].
    pub(super) max_light_items: usize,
    /// The shadows on whole polygons, in world coordinates.
    pub(super) world: PieceCache<WholePieces>,
    /// The overlap regions of all lights on whole polygons seen directly,
    /// by the side they are seen from.
    pub(super) regions: PieceCache<Arc<WholeRegions>>,
    /// The outlines of objects as each light sees them, by (object,
    /// light), each made once, when first asked for.
    pub(super) outlines: Mutex<rustc_hash::FxHashMap<(u32, u32), OutlineCell>>,
    /// Whether an object between the light and a whole polygon is cast by
    /// its outline (off only to test the outlines against the polygons).
    pub(super) cast_outlines: bool,
    /// Whether shadows are kept the first time they are asked for, not
    /// the second: an index kept for the next frames of an animation
    /// (every polygon a moving camera uncovers would else be cast twice),
    /// or one whose tree has mirror or refraction levels.
    pub(super) keep_first: bool,
}

impl CasterIndex {
    /// The casters among a scene's `objects`, for its `lights` lights; the
    /// lights' hierarchies are built on first use.
    pub fn new(objects: &[Object], lights: usize) -> CasterIndex {
        let casters = distinct_casters(objects);
        CasterIndex {
            casters,
            lights: (0..lights).map(|_| OnceLock::new()).collect(),
            faces: (0..lights).map(|_| OnceLock::new()).collect(),
            light_space: true,
            shared: OnceLock::new(),
            max_light_items: MAX_LIGHT_ITEMS,
            world: PieceCache::default(),
            regions: PieceCache::default(),
            outlines: Mutex::default(),
            cast_outlines: true,
            keep_first: false,
        }
    }

    /// The hierarchy to query for light `j` (world position `light`), and
    /// whether its casters still need the facing test: the light's own
    /// while all lights' hierarchies together stay within
    /// [`MAX_LIGHT_ITEMS`] items, else one shared by every further light,
    /// so that many lights never cost lights times casters memory.
    pub(super) fn tree(&self, objects: &[Object], j: usize, light: DVec3) -> (&LightTree, bool) {
        if !self.own_hierarchy(j) {
            return (
                self.shared
                    .get_or_init(|| LightTree::of_casters(objects, &self.casters, |_| true)),
                true,
            );
        }
        let tree = self.lights[j].get_or_init(|| {
            LightTree::of_casters(objects, &self.casters, |c| {
                CasterRef::of(objects, c).faces(c.open, light)
            })
        });
        (tree, false)
    }

    /// Where the outline of object `m` as light `j` sees it is kept.
    pub(super) fn outline_cell(&self, m: u32, j: usize) -> OutlineCell {
        let mut kept = self.outlines.lock().unwrap_or_else(|e| e.into_inner());
        kept.entry((m, j as u32)).or_default().clone()
    }

    /// Whether light `j` has hierarchies of its own: all lights' together
    /// stay within [`MAX_LIGHT_ITEMS`] items.
    pub(super) fn own_hierarchy(&self, j: usize) -> bool {
        let n = self.casters.len().max(1);
        j == 0 || (j + 1).saturating_mul(n) <= self.max_light_items
    }

    /// Light `j`'s casters as it sees them ([`LightFaces`]), made by
    /// [`Self::warm_faces`]; `None` before, for a light without
    /// hierarchies of its own, or when `tol` is larger than theirs.
    pub(super) fn faces(&self, j: usize, tol: f64) -> Option<&LightFaces> {
        if !self.light_space || !self.own_hierarchy(j) {
            return None;
        }
        self.faces[j].get().filter(|faces| tol <= faces.tol)
    }

    /// Makes light `j`'s [`LightFaces`] (world position `light`) for the
    /// tolerance `tol`, unless made. Their build runs on the pool's
    /// threads, so it is made before the casts, never inside one: a
    /// worker waiting for its part of a parallel build takes other work
    /// meanwhile, and a cast taken so would wait on the very cell being
    /// filled (a deadlock). The closures of this index's other cells run
    /// on their own thread only.
    pub(super) fn warm_faces(&self, objects: &[Object], j: usize, light: DVec3, tol: f64) {
        if self.light_space && self.own_hierarchy(j) {
            self.faces[j].get_or_init(|| LightFaces::new(objects, &self.casters, light, tol));
        }
    }
}

pub(super) fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    crate::math::bounds(points.iter().copied())
}

/// The largest world whose caster index is kept for the next frame. A
/// bigger one (ten million triangles: 0.7 GB of casters and hierarchy) is
/// freed with its tree, before the records are made, and is built again
/// for each frame.
pub(super) const MAX_KEPT_POLYGONS: usize = 1 << 20;

/// The caster index of the last frame, kept for the next while the world
/// it was built from does not change: an animation that only moves the
/// camera casts each polygon's shadows once. The world is recognised by
/// a keyed hash of everything the shadows depend on: every point, polygon
/// and plane, which objects are hidden, open or concave, the Point
/// lights' positions and the tolerance.
///
/// A world's first frame keeps only its hash, unless frames are known to
/// follow ([`Self::frames_follow`]): a still frees its index with its
/// tree, before the records are made (office2: about 5 MB less at the
/// peak). The second frame of the same world then builds the index again
/// and keeps it for the frames after.
#[derive(Default)]
pub struct CasterReuse {
    pub(super) keys: std::hash::RandomState,
    pub(super) kept: Mutex<Option<(u64, Option<Arc<CasterIndex>>)>>,
    pub(super) built: AtomicUsize,
    /// Whether the next frame is known to be followed by others.
    pub(super) follow: std::sync::atomic::AtomicBool,
}

impl CasterReuse {
    /// The index for `objects` and `lights` at tolerance `eps`: the kept
    /// one if they are the last call's, else a new one, kept if they are
    /// the last call's world seen a second time (or frames follow, see
    /// [`Self::frames_follow`]) and have at most 2^20
    /// polygons (a bigger index is built again for each frame). A new
    /// index keeps a polygon's shadows the first time they are cast when
    /// they will be asked for again: in the next frame of the same world,
    /// or `asked_again` (the frame's tree has mirror or refraction
    /// levels, which show polygons seen directly again).
    pub fn index(
        &self,
        objects: &[Object],
        lights: &[crate::model::Light],
        eps: f64,
        asked_again: bool,
    ) -> Arc<CasterIndex> {
        let polygons: usize = objects.iter().map(|o| o.polygons.len()).sum();
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let key = (polygons <= MAX_KEPT_POLYGONS).then(|| self.fingerprint(objects, lights, eps));
        let seen = matches!((key, kept.as_ref()), (Some(key), Some((k, _))) if *k == key);
        if seen && let Some((_, Some(index))) = kept.as_ref() {
            return index.clone();
        }
        // A world seen again, or one whose next frames are announced, is
        // kept from its first frame on.
        let keep = seen || self.follow.load(Ordering::Relaxed);
        let index = Arc::new(CasterIndex {
            keep_first: keep || asked_again,
            ..CasterIndex::new(objects, lights.len())
        });
        *kept = key.map(|key| (key, keep.then(|| index.clone())));
        self.built.fetch_add(1, Ordering::Relaxed);
        index
    }

    /// Says whether the frames to come follow others of an animation (a
    /// scene file's `run` with more `run`s after it): a first frame of a
    /// world then keeps its index for them rather than leave it to the
    /// second frame to build again.
    pub fn frames_follow(&self, more: bool) {
        self.follow.store(more, Ordering::Relaxed);
    }

    /// How many indexes were built: two per world an animation shows
    /// in more than one frame (its first frame keeps none), one per world
    /// shown once; one per world when [`Self::frames_follow`] said more
    /// frames follow its first.
    pub fn built(&self) -> usize {
        self.built.load(Ordering::Relaxed)
    }

    pub(super) fn fingerprint(
        &self,
        objects: &[Object],
        lights: &[crate::model::Light],
        eps: f64,
    ) -> u64 {
        let mut h = self.keys.build_hasher();
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        eps.to_bits().hash(&mut h);
        objects.len().hash(&mut h);
        for o in objects {
            let st = &o.surface_type;
            (st.hidden, st.open, st.concave).hash(&mut h);
            o.vertices.len().hash(&mut h);
            for v in &o.vertices {
                bits(*v).hash(&mut h);
            }
            o.polygons.len().hash(&mut h);
            for p in &o.polygons {
                p.indices.hash(&mut h);
                p.plane.to_array().map(f64::to_bits).hash(&mut h);
            }
        }
        lights.len().hash(&mut h);
        for l in lights {
            (l.kind == LightKind::Point).hash(&mut h);
            bits(l.position).hash(&mut h);
        }
        h.finish()
    }
}
