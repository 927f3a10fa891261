//! The store of the virtual image tree's fragments (004 section 3.2: the
//! tree's nodes), in fixed-size chunks.
//!
//! A tree of ten million fragments is gigabytes. Grown as one `Vec`, it
//! would be reallocated by doubling: up to half its capacity unused, and
//! for the moment of each copy the old block and the new (1.5 times the
//! final size at the last one). Chunks of [`CHUNK`] fragments are allocated
//! whole and never moved, so the store holds at most one chunk more than
//! its fragments, and indices stay what they were in a `Vec`.

use super::Fragment;

/// Fragments per chunk: just over 8 MiB of them, pages touched as they
/// fill. Chunks this large are returned to the system as soon as the tree
/// is dropped (jemalloc serves blocks of 8 MiB or more from an arena that
/// purges at once); with chunks of 640 KiB the freed tree of office2
/// stayed resident through the scan conversion, 12 MB more peak.
const CHUNK: usize = (8usize << 20).div_ceil(std::mem::size_of::<Fragment>());

/// The fragments of a tree, indexed from 0 in the order they were added.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Fragments {
    chunks: Vec<Vec<Fragment>>,
    len: usize,
}

impl Fragments {
    /// How many fragments there are.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Adds `f` as fragment [`Self::len`].
    pub fn push(&mut self, f: Fragment) {
        match self.chunks.last_mut() {
            Some(chunk) if chunk.len() < CHUNK => chunk.push(f),
            _ => {
                let mut chunk = Vec::with_capacity(CHUNK);
                chunk.push(f);
                self.chunks.push(chunk);
            }
        }
        self.len += 1;
    }

    /// The fragments in index order.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &Fragment> {
        self.chunks.iter().flatten()
    }

    /// The fragments in index order, to change.
    pub fn iter_mut(&mut self) -> impl DoubleEndedIterator<Item = &mut Fragment> {
        self.chunks.iter_mut().flatten()
    }
}

impl std::ops::Index<usize> for Fragments {
    type Output = Fragment;

    fn index(&self, i: usize) -> &Fragment {
        &self.chunks[i / CHUNK][i % CHUNK]
    }
}

impl std::ops::IndexMut<usize> for Fragments {
    fn index_mut(&mut self, i: usize) -> &mut Fragment {
        &mut self.chunks[i / CHUNK][i % CHUNK]
    }
}

impl<'a> IntoIterator for &'a Fragments {
    type Item = &'a Fragment;
    type IntoIter = std::iter::Flatten<std::slice::Iter<'a, Vec<Fragment>>>;

    fn into_iter(self) -> Self::IntoIter {
        self.chunks.iter().flatten()
    }
}

impl FromIterator<Fragment> for Fragments {
    fn from_iter<I: IntoIterator<Item = Fragment>>(iter: I) -> Fragments {
        let mut out = Fragments::default();
        for f in iter {
            out.push(f);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image_tree::{Branch, FragmentKind};

    fn fragment(n: usize) -> Fragment {
        Fragment {
            level: 1,
            kind: FragmentKind::Polygon,
            branch: Branch::Direct,
            object: n as u32,
            polygon: 0,
            virtual_points: crate::model::Points::Scene,
            back_facing: false,
            shade: Default::default(),
            blended: Default::default(),
            weight: 1.0,
            parent: super::super::NO_PARENT,
            space: 0,
            links: Box::default(),
        }
    }

    /// Across chunk boundaries every index finds the fragment pushed as
    /// it, and iteration visits them in that order.
    #[test]
    fn indices_are_push_order_across_chunks() {
        let n = 2 * CHUNK + 3;
        let mut store: Fragments = (0..n).map(fragment).collect();
        assert_eq!(store.len(), n);
        assert_eq!(store.chunks.len(), 3);
        for i in [0, 1, CHUNK - 1, CHUNK, CHUNK + 1, 2 * CHUNK, n - 1] {
            assert_eq!(store[i].object, i as u32);
        }
        store[CHUNK].polygon = 7;
        assert_eq!(store.iter().nth(CHUNK).map(|f| f.polygon), Some(7));
        let objects: Vec<u32> = store.iter().map(|f| f.object).collect();
        assert_eq!(objects, (0..n as u32).collect::<Vec<_>>());
        for f in store.iter_mut() {
            f.level = 2;
        }
        assert!((&store).into_iter().all(|f| f.level == 2));
    }

    /// A fragment is 120 bytes: the parent a `u32`, the children and a
    /// shadow's lights one list.
    #[test]
    fn a_fragment_is_120_bytes() {
        assert!(std::mem::size_of::<Fragment>() <= 120);
        assert!(CHUNK * std::mem::size_of::<Fragment>() >= 8 << 20);
    }

    /// `parent` reads the sentinel as none; children keep the order they
    /// were added in, over several additions, and a non-shadow fragment
    /// is shadowed from no light.
    #[test]
    fn parent_and_children_round_trip() {
        let mut f = fragment(0);
        assert_eq!(f.parent(), None);
        assert_eq!(f.children().len(), 0);
        f.parent = super::super::link(7);
        assert_eq!(f.parent(), Some(7));
        f.add_children([3, 1]);
        f.add_children([]);
        f.add_children([9]);
        assert_eq!(f.children().collect::<Vec<_>>(), [3, 1, 9]);
        assert_eq!(f.children().next_back(), Some(9));
        assert!(f.shadowed_from().is_empty());
    }

    /// A shadow polygon's list is its lights, and it has no children.
    #[test]
    fn a_shadow_lists_its_lights_not_children() {
        let mut f = fragment(0);
        f.kind = FragmentKind::Shadow { light: 2 };
        f.branch = Branch::Shadow;
        f.links = vec![2, 5].into_boxed_slice();
        assert_eq!(f.shadowed_from(), [2, 5]);
        assert_eq!(f.children().len(), 0);
    }

    /// No index reaches the sentinel.
    #[test]
    #[should_panic(expected = "fragments")]
    fn the_sentinel_is_no_index() {
        super::super::link(u32::MAX as usize);
    }
}
