//! The kept fragments of a CSG operation stitched back into faces
//! (Firebaugh 001, chapter 8): points welded within the tolerance,
//! T-junctions closed, spikes removed.

use super::*;

/// Joins points closer than `tol` (a grid of cells of that size, each
/// point looked up in its 27 neighbouring cells), returning an id per
/// point and the representative positions.
pub(super) fn weld(points: &[DVec3], tol: f64) -> (Vec<u32>, Vec<DVec3>) {
    let cell = |p: DVec3| (p / tol).floor().to_array().map(|c| c as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut reps: Vec<DVec3> = Vec::new();
    let mut ids = Vec::with_capacity(points.len());
    for p in points {
        let c = cell(*p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        for &id in list {
                            if reps[id as usize].distance(*p) <= tol {
                                found = Some(id);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let id = found.unwrap_or_else(|| {
            reps.push(*p);
            let id = (reps.len() - 1) as u32;
            grid.entry(c).or_default().push(id);
            id
        });
        ids.push(id);
    }
    (ids, reps)
}

/// A face as welded point ids with a normal per corner.
pub(super) struct Loop {
    pub(super) ids: Vec<u32>,
    pub(super) normals: Vec<DVec3>,
    pub(super) attr: u32,
}

/// Welds the fragments and removes T-junctions (see the module doc).
pub(super) fn stitch(polys: Vec<Poly>, tol: f64) -> Vec<Face> {
    let all: Vec<DVec3> = polys
        .iter()
        .flat_map(|p| p.points.iter().copied())
        .collect();
    let (ids, reps) = weld(&all, tol);
    let mut loops = Vec::with_capacity(polys.len());
    let mut k = 0;
    for p in &polys {
        let mut l = Loop {
            ids: Vec::new(),
            normals: Vec::new(),
            attr: p.attr,
        };
        for n in &p.normals {
            let id = ids[k];
            k += 1;
            if l.ids.last() != Some(&id) {
                l.ids.push(id);
                l.normals.push(*n);
            }
        }
        remove_spikes(&mut l);
        if l.ids.len() >= 3 {
            loops.push(l);
        }
    }
    // Edges without their reverse, and the points at their ends.
    let mut count: HashMap<(u32, u32), i32> = HashMap::new();
    for l in &loops {
        let m = l.ids.len();
        for i in 0..m {
            *count.entry((l.ids[i], l.ids[(i + 1) % m])).or_insert(0) += 1;
        }
    }
    let mut candidates: Vec<u32> = count
        .keys()
        .filter(|(a, b)| !count.contains_key(&(*b, *a)))
        .flat_map(|&(a, b)| [a, b])
        .collect();
    candidates.sort_unstable();
    candidates.dedup();
    // Sorted by x, so that an edge looks only at the points in its x range.
    candidates.sort_by(|a, b| reps[*a as usize].x.total_cmp(&reps[*b as usize].x));
    if !candidates.is_empty() {
        for l in &mut loops {
            insert_t_points(l, &count, &candidates, &reps, tol);
        }
    }
    loops
        .into_iter()
        .filter(|l| l.ids.len() >= 3)
        .map(|l| Face {
            points: l.ids.iter().map(|&i| reps[i as usize]).collect(),
            normals: l.normals,
            attr: l.attr,
        })
        .collect()
}

/// Inserts into the unmatched edges of `l` the candidate points (sorted by
/// x) lying on them, in order along the edge, with normals interpolated.
pub(super) fn insert_t_points(
    l: &mut Loop,
    count: &HashMap<(u32, u32), i32>,
    candidates: &[u32],
    reps: &[DVec3],
    tol: f64,
) {
    let m = l.ids.len();
    let mut ids = Vec::with_capacity(m);
    let mut normals = Vec::with_capacity(m);
    for i in 0..m {
        let (a, b) = (l.ids[i], l.ids[(i + 1) % m]);
        ids.push(a);
        normals.push(l.normals[i]);
        if count.contains_key(&(b, a)) {
            continue;
        }
        let (pa, pb) = (reps[a as usize], reps[b as usize]);
        let ab = pb - pa;
        let len2 = ab.length_squared();
        if len2 == 0.0 {
            continue;
        }
        let (lo, hi) = (pa.x.min(pb.x) - tol, pa.x.max(pb.x) + tol);
        let from = candidates.partition_point(|&c| reps[c as usize].x < lo);
        let to = candidates.partition_point(|&c| reps[c as usize].x <= hi);
        let mut on: Vec<(f64, u32)> = candidates[from..to.max(from)]
            .iter()
            .filter(|&&c| c != a && c != b)
            .filter_map(|&c| {
                let p = reps[c as usize];
                let t = (p - pa).dot(ab) / len2;
                (t > 0.0 && t < 1.0 && (pa + ab * t).distance(p) <= tol).then_some((t, c))
            })
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (na, nb) = (l.normals[i], l.normals[(i + 1) % m]);
        for (t, c) in on {
            ids.push(c);
            normals.push(na.lerp(nb, t).normalize_or(na));
        }
    }
    l.ids = ids;
    l.normals = normals;
    remove_spikes(l);
}

/// Removes from a loop the points repeated in a row and the spikes
/// `a, b, a` (a sliver welded flat, or a point inserted on both of its
/// sides): each would use one edge twice and leave the mesh open.
pub(super) fn remove_spikes(l: &mut Loop) {
    let mut ids: Vec<u32> = Vec::with_capacity(l.ids.len());
    let mut normals: Vec<DVec3> = Vec::with_capacity(l.ids.len());
    let push = |ids: &mut Vec<u32>, normals: &mut Vec<DVec3>, id: u32, n: DVec3| {
        if ids.last() == Some(&id) {
            return;
        }
        if ids.len() >= 2 && ids[ids.len() - 2] == id {
            ids.pop();
            normals.pop();
            return;
        }
        ids.push(id);
        normals.push(n);
    };
    for (&id, &n) in l.ids.iter().zip(&l.normals) {
        push(&mut ids, &mut normals, id, n);
    }
    // Across the loop's start: rotate the spike or repetition away.
    let mut guard = ids.len();
    while ids.len() >= 3 && guard > 0 {
        guard -= 1;
        let m = ids.len();
        if ids[0] == ids[m - 1] {
            ids.pop();
            normals.pop();
        } else if ids[1] == ids[m - 1] {
            // last, first, second = x, y, x.
            ids.remove(0);
            normals.remove(0);
            ids.pop();
            normals.pop();
        } else if ids[0] == ids[m - 2] {
            // second last, last, first = x, y, x.
            ids.pop();
            normals.pop();
            ids.pop();
            normals.pop();
        } else {
            break;
        }
    }
    if ids.len() < 3 {
        ids.clear();
        normals.clear();
    }
    l.ids = ids;
    l.normals = normals;
}
