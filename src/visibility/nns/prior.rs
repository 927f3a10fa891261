//! Where a frame's sort of the faces given starts: the order the last
//! frame's sort gave them. A camera that moves a little changes the
//! faces' order by depth a little, so the faces found again are put in
//! their last order, an insertion pass puts that right, and the faces new
//! to the frame are sorted apart and merged in. The key (the far end of
//! the depth range, then the index) orders any two faces one way only, so
//! the order is the one a sort from scratch gives, whatever was kept; a
//! frame whose faces moved too far gives up the pass and sorts from
//! scratch.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::HeapKey;

/// The most faces whose order is kept for the next frame (12 bytes a
/// face): a bigger level is sorted from scratch each frame.
const MAX_KEPT: usize = 1 << 20;

/// The moves the insertion pass may make per face before it gives up
/// (a cut to another view rather than a step).
const MOVES_PER_FACE: usize = 16;

/// The order of the faces given to the last sort, kept for the next (see
/// the module comment). A frame is the same with it or without it.
#[derive(Default)]
pub struct PriorOrder {
    kept: Mutex<Option<Kept>>,
    /// Whether frames are known to follow the next sort's.
    follow: AtomicBool,
    /// Sorts asked to order their faces, and how many of them started
    /// from the kept order.
    sorts: AtomicUsize,
    warm: AtomicUsize,
}

/// A sort's faces given and their order.
struct Kept {
    /// Each face's source (object, polygon), in the order given.
    sources: Vec<(u32, u32)>,
    /// The order: indices into `sources`, farthest first.
    order: Vec<u32>,
}

impl PriorOrder {
    /// Says whether frames follow the next (the order is then kept from
    /// the first frame on; otherwise from the second).
    pub fn frames_follow(&self, more: bool) {
        self.follow.store(more, Ordering::Relaxed);
    }

    /// How many sorts started from the order a sort before kept.
    pub fn warm_starts(&self) -> usize {
        self.warm.load(Ordering::Relaxed)
    }

    /// The faces given farthest first ([`HeapKey`] order), `zmax[i]` the
    /// far end of face `i`'s depth range and `sources[i]` its source;
    /// kept for the next call.
    pub(super) fn order(&self, sources: Vec<(u32, u32)>, zmax: &[f64]) -> Vec<usize> {
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let warm = kept.take().and_then(|k| warm_order(&k, &sources, zmax));
        if warm.is_some() {
            self.warm.fetch_add(1, Ordering::Relaxed);
        }
        let order = warm.unwrap_or_else(|| cold_order(zmax));
        let again = self.sorts.fetch_add(1, Ordering::Relaxed) > 0;
        if (again || self.follow.load(Ordering::Relaxed)) && order.len() <= MAX_KEPT {
            *kept = Some(Kept {
                sources,
                order: order.iter().map(|&i| i as u32).collect(),
            });
        }
        order
    }
}

/// Whether face `a` comes before face `b`: farther, or as far and given
/// first.
fn before(zmax: &[f64], a: usize, b: usize) -> bool {
    HeapKey(zmax[a], a) > HeapKey(zmax[b], b)
}

/// The faces ordered from scratch.
pub(super) fn cold_order(zmax: &[f64]) -> Vec<usize> {
    // The order of `HeapKey`s, greatest first, sorted as integer pairs:
    // (`total_cmp`'s order of the depth as an unsigned integer, reversed;
    // the index), held with the keys rather than looked up per comparison.
    let mut keyed: Vec<(u64, usize)> = zmax
        .iter()
        .enumerate()
        .map(|(i, &z)| (!total_order_bits(z), i))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// `z` as an unsigned integer in the order of `f64::total_cmp`.
fn total_order_bits(z: f64) -> u64 {
    let bits = z.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// The faces ordered from `kept`, or `None` when the faces' sources are
/// not in order (the two lists cannot be matched in one pass) or they
/// moved too far for the insertion pass.
fn warm_order(kept: &Kept, sources: &[(u32, u32)], zmax: &[f64]) -> Option<Vec<usize>> {
    let (map, found) = matched(&kept.sources, sources)?;
    let mut order: Vec<usize> = kept
        .order
        .iter()
        .filter_map(|&i| map.get(i as usize).copied().flatten())
        .collect();
    if order.len() != found.iter().filter(|&&f| f).count() {
        return None;
    }
    insertion_pass(&mut order, zmax)?;
    let mut new: Vec<usize> = (0..sources.len()).filter(|&j| !found[j]).collect();
    new.sort_unstable_by(|&a, &b| HeapKey(zmax[b], b).cmp(&HeapKey(zmax[a], a)));
    Some(merged(&order, &new, zmax))
}

/// For each face of `old`, the face of `new` with the same source (the
/// k-th of a source's faces matched to the k-th), and which faces of
/// `new` were matched; `None` unless both lists are in order of source.
#[allow(clippy::type_complexity)]
fn matched(old: &[(u32, u32)], new: &[(u32, u32)]) -> Option<(Vec<Option<usize>>, Vec<bool>)> {
    let sorted = |v: &[(u32, u32)]| v.windows(2).all(|w| w[0] <= w[1]);
    if !sorted(old) || !sorted(new) {
        return None;
    }
    let mut map = vec![None; old.len()];
    let mut found = vec![false; new.len()];
    let (mut i, mut j) = (0, 0);
    while i < old.len() && j < new.len() {
        match old[i].cmp(&new[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                map[i] = Some(j);
                found[j] = true;
                i += 1;
                j += 1;
            }
        }
    }
    Some((map, found))
}

/// Sorts `order` by insertion; `None` past [`MOVES_PER_FACE`] moves a
/// face.
fn insertion_pass(order: &mut [usize], zmax: &[f64]) -> Option<()> {
    let budget = MOVES_PER_FACE * order.len() + 1024;
    let mut moves = 0;
    for k in 1..order.len() {
        let x = order[k];
        let mut m = k;
        while m > 0 && before(zmax, x, order[m - 1]) {
            order[m] = order[m - 1];
            m -= 1;
        }
        order[m] = x;
        moves += k - m;
        if moves > budget {
            return None;
        }
    }
    Some(())
}

/// Two ordered lists as one.
fn merged(a: &[usize], b: &[usize], zmax: &[f64]) -> Vec<usize> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if before(zmax, b[j], a[i]) {
            out.push(b[j]);
            j += 1;
        } else {
            out.push(a[i]);
            i += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cold order is the [`HeapKey`] order, greatest first, whatever
    /// the depths: ties, signed zeros, infinities and NaNs of both signs.
    #[test]
    fn the_cold_order_is_the_heap_key_order() {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        let mut rng = Lcg(7);
        let zmax: Vec<f64> = (0..3000)
            .map(|k| match rng.next() % 4 {
                0 => special[k % special.len()],
                1 => (rng.next() % 5) as f64 - 2.0,
                _ => f64::from_bits(rng.next()),
            })
            .collect();
        let mut want: Vec<usize> = (0..zmax.len()).collect();
        want.sort_by(|&a, &b| HeapKey(zmax[b], b).cmp(&HeapKey(zmax[a], a)));
        assert_eq!(cold_order(&zmax), want);
    }

    /// A small deterministic generator (no seed to vary between runs).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            self.0 >> 33
        }
    }

    /// Faces of `polygons` sources, some split in two, with depths on a
    /// few levels (ties) moved by `step`.
    fn frame(rng: &mut Lcg, polygons: u32, step: f64) -> (Vec<(u32, u32)>, Vec<f64>) {
        let mut sources = Vec::new();
        let mut zmax = Vec::new();
        for p in 0..polygons {
            if rng.next().is_multiple_of(7) {
                continue; // out of view in this frame
            }
            let pieces = 1 + usize::from(rng.next().is_multiple_of(5));
            for _ in 0..pieces {
                sources.push((p / 10, p % 10));
                let z = f64::from(p % 13) / 13.0 + step * (rng.next() % 100) as f64 / 100.0;
                zmax.push(if rng.next().is_multiple_of(11) {
                    0.5
                } else {
                    z
                });
            }
        }
        (sources, zmax)
    }

    /// Every frame's order equals the order from scratch, whatever the
    /// last frame left: small steps (the insertion pass), large ones
    /// (given up), faces gone and new, ties, and sources out of order.
    #[test]
    fn the_order_from_the_last_frame_equals_the_order_from_scratch() {
        let mut rng = Lcg(7);
        let prior = PriorOrder::default();
        prior.frames_follow(true);
        for k in 0..40 {
            let step = if k % 10 == 9 { 5.0 } else { 0.01 };
            let (mut sources, zmax) = frame(&mut rng, 400, step);
            if k == 20 {
                sources.swap(3, 200);
            }
            let expected = cold_order(&zmax);
            assert_eq!(prior.order(sources, &zmax), expected, "frame {k}");
        }
        // The small steps started from the last order (all but the
        // first frame, the large steps and the sources out of order).
        let warm = prior.warm_starts();
        assert!((20..=31).contains(&warm), "{warm} warm starts");
    }

    /// A still keeps no order; a second sort of the same `PriorOrder`
    /// (frames not announced) keeps it for a third.
    #[test]
    fn the_order_is_kept_when_frames_follow_or_from_the_second_sort() {
        let zmax = [0.3, 0.1, 0.2];
        let sources = vec![(0, 0), (0, 1), (0, 2)];
        let prior = PriorOrder::default();
        for _ in 0..3 {
            assert_eq!(prior.order(sources.clone(), &zmax), vec![0, 2, 1]);
        }
        assert_eq!(prior.warm_starts(), 1);
        let announced = PriorOrder::default();
        announced.frames_follow(true);
        for _ in 0..3 {
            announced.order(sources.clone(), &zmax);
        }
        assert_eq!(announced.warm_starts(), 2);
    }
}
