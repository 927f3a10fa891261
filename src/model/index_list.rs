//! A polygon's vertex indices, held in place when there are few.
//!
//! An object of ten million triangles had a `Vec<u32>` per polygon: a
//! 24-byte header and a 16-byte allocation for 12 bytes of indices. An
//! [`IndexList`] is 16 bytes with up to [`IndexList::INLINE`] indices in
//! place (a triangle, most polygons of a big mesh, allocates nothing),
//! longer lists on the heap behind a thin pointer; it reads as a `[u32]`.

use std::ops::{Deref, DerefMut};

/// A polygon's vertex indices (see the module's documentation).
#[derive(Clone)]
pub struct IndexList(Repr);

/// The two ways an [`IndexList`] holds its indices.
#[derive(Clone)]
enum Repr {
    /// The first `len` of `ids`.
    Inline {
        len: u8,
        ids: [u32; IndexList::INLINE],
    },
    /// More than [`IndexList::INLINE`], boxed twice: a thin pointer
    /// leaves the tag and the inline variant room in 16 bytes.
    Heap(Box<Box<[u32]>>),
}

impl IndexList {
    /// How many indices are held in place.
    pub const INLINE: usize = 3;

    /// The indices as a slice.
    pub fn as_slice(&self) -> &[u32] {
        match &self.0 {
            Repr::Inline { len, ids } => &ids[..usize::from(*len)],
            Repr::Heap(ids) => ids,
        }
    }

    /// The indices as a slice to change in place.
    pub fn as_mut_slice(&mut self) -> &mut [u32] {
        match &mut self.0 {
            Repr::Inline { len, ids } => &mut ids[..usize::from(*len)],
            Repr::Heap(ids) => ids,
        }
    }
}

impl Default for IndexList {
    /// No index.
    fn default() -> IndexList {
        IndexList(Repr::Inline {
            len: 0,
            ids: [0; IndexList::INLINE],
        })
    }
}

impl From<&[u32]> for IndexList {
    fn from(slice: &[u32]) -> IndexList {
        if slice.len() > IndexList::INLINE {
            return IndexList(Repr::Heap(Box::new(slice.into())));
        }
        let mut ids = [0; IndexList::INLINE];
        ids[..slice.len()].copy_from_slice(slice);
        IndexList(Repr::Inline {
            len: slice.len() as u8,
            ids,
        })
    }
}

impl From<Vec<u32>> for IndexList {
    /// Keeps a long list's allocation (shrunk to fit).
    fn from(v: Vec<u32>) -> IndexList {
        if v.len() > IndexList::INLINE {
            IndexList(Repr::Heap(Box::new(v.into_boxed_slice())))
        } else {
            IndexList::from(v.as_slice())
        }
    }
}

impl<const N: usize> From<[u32; N]> for IndexList {
    fn from(a: [u32; N]) -> IndexList {
        IndexList::from(a.as_slice())
    }
}

impl FromIterator<u32> for IndexList {
    fn from_iter<I: IntoIterator<Item = u32>>(iter: I) -> IndexList {
        let v: Vec<u32> = iter.into_iter().collect();
        IndexList::from(v)
    }
}

impl Deref for IndexList {
    type Target = [u32];

    fn deref(&self) -> &[u32] {
        self.as_slice()
    }
}

impl DerefMut for IndexList {
    fn deref_mut(&mut self) -> &mut [u32] {
        self.as_mut_slice()
    }
}

impl AsRef<[u32]> for IndexList {
    fn as_ref(&self) -> &[u32] {
        self.as_slice()
    }
}

impl<'a> IntoIterator for &'a IndexList {
    type Item = &'a u32;
    type IntoIter = std::slice::Iter<'a, u32>;

    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

impl PartialEq for IndexList {
    /// Equal indices, however held.
    fn eq(&self, other: &IndexList) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl Eq for IndexList {}

impl PartialEq<Vec<u32>> for IndexList {
    fn eq(&self, other: &Vec<u32>) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl<const N: usize> PartialEq<[u32; N]> for IndexList {
    fn eq(&self, other: &[u32; N]) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl std::fmt::Debug for IndexList {
    /// As the slice.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.as_slice().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 16 bytes, whatever it holds.
    #[test]
    fn an_index_list_is_16_bytes() {
        assert!(std::mem::size_of::<IndexList>() <= 16);
    }

    /// Every length, empty, in place and on the heap, reads back as
    /// given, from a slice, a `Vec`, an array or an iterator.
    #[test]
    fn every_length_reads_back() {
        for n in 0..=9u32 {
            let v: Vec<u32> = (0..n).map(|k| 10 * k + 1).collect();
            let lists = [
                IndexList::from(v.as_slice()),
                IndexList::from(v.clone()),
                v.iter().copied().collect(),
            ];
            for list in &lists {
                assert_eq!(list.as_slice(), v.as_slice(), "length {n}");
                assert_eq!(list.len(), v.len());
                assert_eq!(*list, v);
                assert_eq!(list.iter().copied().collect::<Vec<_>>(), v);
                assert_eq!(format!("{list:?}"), format!("{v:?}"));
            }
            assert_eq!(lists[0], lists[1]);
            let inline = matches!(lists[0].0, Repr::Inline { .. });
            assert_eq!(inline, v.len() <= IndexList::INLINE, "length {n}");
        }
        assert!(IndexList::default().is_empty());
        assert_eq!(IndexList::from([4, 5, 6]), [4, 5, 6]);
    }

    /// Changed in place (reversed, one index set), in place or on the
    /// heap, it holds the change; lists of different lengths differ.
    #[test]
    fn changes_in_place_hold() {
        for v in [vec![1, 2, 3], vec![1, 2, 3, 4, 5, 6]] {
            let mut list = IndexList::from(v.clone());
            list.reverse();
            list[0] = 99;
            let mut want = v.clone();
            want.reverse();
            want[0] = 99;
            assert_eq!(list, want);
            assert_ne!(list, IndexList::from(&want[..want.len() - 1]));
        }
    }
}
