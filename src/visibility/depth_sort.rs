//! The simple depth sort of Garcia 1986 (004 section 4.4): "the sorting
//! order is simply determined by either the minimum or maximum vertex
//! Z-coordinate of the polygon, depending on the sorting order", by
//! insertion sort for fewer than 64 polygons and bucket sort otherwise.
//!
//! There is one priority order: by the maximum z (farthest vertex),
//! descending, which paints back to front. Front to back (`sort ftb`) is
//! that order reversed, not a second sort by the minimum z as the
//! thesis's sentence reads: a sort by nearest vertex puts any large floor
//! before what stands on it (its near edge is nearer than the objects), so
//! the two orders gave two pictures. Reversing one order keeps the picture
//! of both the same; the image tree reverses each level with its children
//! before their parents (figure 4.15's front-to-back sequence). The sort
//! is stable, so equal keys keep their input order and the result is
//! deterministic.
//!
//! Preconditions: keys are finite. The order is wrong whenever polygons
//! overlap in depth and on the screen; that is the NNS sorter's job.

/// Below this many items, insertion sort (004 section 4.4).
pub const INSERTION_SORT_LIMIT: usize = 64;

/// The sort key of a polygon whose farthest vertex has depth `max_z`:
/// ascending keys paint back to front (reverse the sorted order for front
/// to back).
pub fn sort_key(max_z: f64) -> f64 {
    -max_z
}

/// The permutation that sorts `keys` ascending, stably.
pub fn sorted_order(keys: &[f64]) -> Vec<usize> {
    if keys.len() < INSERTION_SORT_LIMIT {
        insertion_sort(keys)
    } else {
        bucket_sort(keys)
    }
}

fn insertion_sort(keys: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..keys.len()).collect();
    insertion_sort_in(&mut order, keys);
    order
}

/// One bucket per item over the key range; items go to their buckets in
/// input order and each bucket is insertion sorted, so the sort is
/// stable. The buckets are ranges of one array, placed by counting
/// (office2's 12,000 polygons once took a small vector each).
fn bucket_sort(keys: &[f64]) -> Vec<usize> {
    let n = keys.len();
    let (lo, hi) = keys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &k| {
            (lo.min(k), hi.max(k))
        });
    if hi <= lo || hi.is_nan() || lo.is_nan() {
        return (0..n).collect();
    }
    let scale = n as f64 / (hi - lo);
    let bucket = |k: f64| (((k - lo) * scale) as usize).min(n - 1);
    // `start[b]..start[b + 1]`: where bucket `b` lies in the order.
    let mut start = vec![0; n + 1];
    for &k in keys {
        start[bucket(k) + 1] += 1;
    }
    for b in 0..n {
        start[b + 1] += start[b];
    }
    let mut order = vec![0; n];
    let mut next = start.clone();
    for (i, &k) in keys.iter().enumerate() {
        let b = bucket(k);
        order[next[b]] = i;
        next[b] += 1;
    }
    for b in 0..n {
        insertion_sort_in(&mut order[start[b]..start[b + 1]], keys);
    }
    order
}

/// `items` (indices of `keys`) sorted by their keys, stably.
fn insertion_sort_in(items: &mut [usize], keys: &[f64]) {
    for i in 1..items.len() {
        let item = items[i];
        let mut j = i;
        while j > 0 && keys[items[j - 1]] > keys[item] {
            items[j] = items[j - 1];
            j -= 1;
        }
        items[j] = item;
    }
}

/// Puts `items` in the order `order` (a permutation of their indices:
/// item `order[i]` goes to place `i`), in place, by following its cycles:
/// a level of millions of polygons is not copied into a list anew.
pub fn put_in_order<T>(items: &mut [T], mut order: Vec<usize>) {
    assert_eq!(order.len(), items.len(), "one place per item");
    const DONE: usize = usize::MAX;
    for start in 0..items.len() {
        let mut place = start;
        while order[place] != DONE {
            let from = order[place];
            order[place] = DONE;
            if from == start {
                break;
            }
            items.swap(place, from);
            place = from;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn reference(keys: &[f64]) -> Vec<usize> {
        let mut v: Vec<usize> = (0..keys.len()).collect();
        v.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
        v
    }

    #[test]
    fn the_farthest_vertex_sorts_first() {
        let keys = [sort_key(0.7), sort_key(0.9), sort_key(0.2)];
        assert_eq!(sorted_order(&keys), vec![1, 0, 2]);
    }

    #[test]
    fn equal_keys_keep_input_order() {
        let keys = vec![1.0; 100];
        assert_eq!(sorted_order(&keys), (0..100).collect::<Vec<_>>());
        let keys = [2.0, 1.0, 2.0, 1.0];
        assert_eq!(sorted_order(&keys), vec![1, 3, 0, 2]);
    }

    proptest! {
        /// Any permutation puts each item where the order says.
        #[test]
        fn items_go_where_the_order_puts_them(
            order in (0usize..200).prop_flat_map(|n| Just((0..n).collect::<Vec<_>>()).prop_shuffle())
        ) {
            let items: Vec<usize> = (0..order.len()).map(|k| k * 10).collect();
            let mut placed = items.clone();
            put_in_order(&mut placed, order.clone());
            let expected: Vec<usize> = order.iter().map(|&k| items[k]).collect();
            prop_assert_eq!(placed, expected);
        }

        #[test]
        fn agrees_with_a_stable_library_sort(keys in prop::collection::vec(-1000i32..1000, 0..300)) {
            let keys: Vec<f64> = keys.into_iter().map(|k| k as f64 / 7.0).collect();
            prop_assert_eq!(sorted_order(&keys), reference(&keys));
        }
    }
}
