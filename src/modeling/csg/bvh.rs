//! The bounding volume hierarchy of a CSG operand's faces (Firebaugh 001,
//! chapter 8: CSG trees), through which each face finds the few faces of
//! the other solid near it.

use super::*;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy)]
pub(super) struct Aabb {
    pub(super) lo: DVec3,
    pub(super) hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    pub(super) fn of(points: &[DVec3], pad: f64) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.lo = b.lo.min(*p);
            b.hi = b.hi.max(*p);
        }
        b.lo -= DVec3::splat(pad);
        b.hi += DVec3::splat(pad);
        b
    }

    pub(super) fn union(self, o: Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    pub(super) fn overlaps(&self, o: &Aabb) -> bool {
        self.lo.cmple(o.hi).all() && o.lo.cmple(self.hi).all()
    }

    /// Whether the ray `o + t d`, `t >= 0`, meets the box (`inv` = 1/d).
    pub(super) fn hit_by(&self, o: DVec3, inv: DVec3) -> bool {
        let t1 = (self.lo - o) * inv;
        let t2 = (self.hi - o) * inv;
        let near = t1.min(t2).max_element();
        let far = t1.max(t2).min_element();
        far >= near.max(0.0)
    }
}

/// A bounding volume hierarchy over the faces of one operand: the spatial
/// index that finds the faces near a face, or along a ray, in logarithmic
/// time (a BSP tree of a convex solid is a chain as deep as its faces).
pub(super) struct Bvh {
    pub(super) boxes: Vec<Aabb>,
    pub(super) nodes: Vec<BNode>,
    pub(super) items: Vec<u32>,
}

pub(super) struct BNode {
    pub(super) bounds: Aabb,
    /// Children, or `None` for a leaf holding `items[start..start + count]`.
    pub(super) children: Option<(u32, u32)>,
    pub(super) start: u32,
    pub(super) count: u32,
}

impl Bvh {
    pub(super) fn new(polys: &[Poly], pad: f64) -> Bvh {
        let boxes: Vec<Aabb> = polys.iter().map(|p| Aabb::of(&p.points, pad)).collect();
        let mut items: Vec<u32> = (0..polys.len() as u32).collect();
        let mut nodes = vec![BNode {
            bounds: Aabb::EMPTY,
            children: None,
            start: 0,
            count: items.len() as u32,
        }];
        let centre = |i: u32| {
            let b = &boxes[i as usize];
            (b.lo + b.hi) * 0.5
        };
        let mut stack = vec![0usize];
        while let Some(id) = stack.pop() {
            let (start, count) = (nodes[id].start as usize, nodes[id].count as usize);
            let slice = &mut items[start..start + count];
            let bounds = slice
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
            nodes[id].bounds = bounds;
            if count <= 4 {
                continue;
            }
            let ext = bounds.hi - bounds.lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let half = count / 2;
            slice
                .select_nth_unstable_by(half, |a, b| centre(*a)[axis].total_cmp(&centre(*b)[axis]));
            let l = nodes.len();
            for (s, c) in [(start, half), (start + half, count - half)] {
                nodes.push(BNode {
                    bounds: Aabb::EMPTY,
                    children: None,
                    start: s as u32,
                    count: c as u32,
                });
            }
            nodes[id].children = Some((l as u32, l as u32 + 1));
            stack.push(l);
            stack.push(l + 1);
        }
        Bvh {
            boxes,
            nodes,
            items,
        }
    }

    /// The faces whose boxes meet `b`.
    pub(super) fn query(&self, b: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        if self.items.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(id) = stack.pop() {
            let n = &self.nodes[id as usize];
            if !n.bounds.overlaps(b) {
                continue;
            }
            match n.children {
                Some((l, r)) => {
                    stack.push(l);
                    stack.push(r);
                }
                None => {
                    let items = &self.items[n.start as usize..(n.start + n.count) as usize];
                    out.extend(
                        items
                            .iter()
                            .filter(|&&i| self.boxes[i as usize].overlaps(b)),
                    );
                }
            }
        }
    }

    /// The faces whose boxes the ray from `o` along `d` meets.
    pub(super) fn along_ray(&self, o: DVec3, d: DVec3, out: &mut Vec<u32>) {
        out.clear();
        if self.items.is_empty() {
            return;
        }
        let inv = d.recip();
        let mut stack = vec![0u32];
        while let Some(id) = stack.pop() {
            let n = &self.nodes[id as usize];
            if !n.bounds.hit_by(o, inv) {
                continue;
            }
            match n.children {
                Some((l, r)) => {
                    stack.push(l);
                    stack.push(r);
                }
                None => {
                    let items = &self.items[n.start as usize..(n.start + n.count) as usize];
                    out.extend(
                        items
                            .iter()
                            .filter(|&&i| self.boxes[i as usize].hit_by(o, inv)),
                    );
                }
            }
        }
    }
}
