//! A polygon's points, held only where they are not the scene's own.
//!
//! A mesh of ten million triangles gave each of its polygons, as a
//! candidate of level 1, a face of the sort and a fragment of the tree, a
//! list of its three world points: a 24-byte header and an 80-byte
//! allocation for what its object already holds. [`Points::Scene`] holds
//! nothing: the points are the object's vertices at the polygon's indices,
//! read back where needed ([`Points::get`]). Only a polygon that clipping,
//! a split, a mirror or the triangulation of a concave outline changed
//! holds its own ([`Points::Own`]).

use std::ops::Deref;

use glam::DVec3;

use super::Object;

/// A polygon's points (see the module's documentation): those of polygon
/// `polygon` of object `object` of the scene, or its own. The holder
/// knows which polygon it is; [`Points::get`] is told.
#[derive(Debug, Clone, PartialEq)]
pub enum Points {
    /// The scene polygon's own points, exactly: its object's world
    /// vertices at its indices (at most [`Points::SCENE_MAX`] of them).
    Scene,
    /// Points of its own.
    Own(Box<[DVec3]>),
}

impl Default for Points {
    /// No points of its own: what `mem::take` leaves behind is empty, never
    /// a claim to be a scene polygon.
    fn default() -> Points {
        Points::Own(Box::new([]))
    }
}

impl Points {
    /// The most vertices a polygon held as [`Points::Scene`] has: its
    /// points are gathered on the stack when read.
    pub const SCENE_MAX: usize = 4;

    /// The points of polygon `polygon` of object `object` of `objects`
    /// with these points.
    pub fn get<'a>(&'a self, objects: &'a [Object], object: u32, polygon: u32) -> PointsRef<'a> {
        match self {
            Points::Own(points) => PointsRef::Slice(points),
            Points::Scene => PointsRef::of_polygon(&objects[object as usize], polygon),
        }
    }

    /// `points` as a polygon's own, or as the scene polygon's when they
    /// are its points exactly (`whole`) and few enough.
    pub fn new(points: impl ExactSizeIterator<Item = DVec3>, whole: bool) -> Points {
        if whole && points.len() <= Points::SCENE_MAX {
            Points::Scene
        } else {
            Points::Own(points.collect())
        }
    }

    /// [`Points::get`] as a list of its own (a list held is moved, not
    /// copied).
    pub fn into_vec(self, objects: &[Object], object: u32, polygon: u32) -> Vec<DVec3> {
        match self {
            Points::Own(points) => points.into_vec(),
            Points::Scene => Points::Scene.get(objects, object, polygon).to_vec(),
        }
    }

    /// Whether the points are the scene polygon's, held as nothing.
    pub fn is_scene(&self) -> bool {
        matches!(self, Points::Scene)
    }
}

impl From<Vec<DVec3>> for Points {
    fn from(points: Vec<DVec3>) -> Points {
        Points::Own(points.into_boxed_slice())
    }
}

/// A polygon's points as read: borrowed where they are its own, gathered
/// from its object's vertices otherwise. It reads as a `[DVec3]`.
#[derive(Debug, Clone)]
pub enum PointsRef<'a> {
    /// Points held as a list.
    Slice(&'a [DVec3]),
    /// Up to [`Points::SCENE_MAX`] points gathered in place.
    Inline {
        /// The first `len` are the points.
        points: [DVec3; Points::SCENE_MAX],
        /// How many there are.
        len: u8,
    },
    /// More, gathered on the heap (a polygon made [`Points::Scene`] has
    /// no more than [`Points::SCENE_MAX`]; this is only the safe answer).
    Heap(Vec<DVec3>),
}

impl<'a> PointsRef<'a> {
    /// Polygon `polygon` of `object`: its world vertices at its indices.
    pub fn of_polygon(object: &'a Object, polygon: u32) -> PointsRef<'a> {
        let indices = &object.polygons[polygon as usize].indices;
        let vertex = |i: &u32| object.vertices[*i as usize];
        if indices.len() > Points::SCENE_MAX {
            return PointsRef::Heap(indices.iter().map(vertex).collect());
        }
        let mut points = [DVec3::ZERO; Points::SCENE_MAX];
        for (p, i) in points.iter_mut().zip(indices.iter()) {
            *p = vertex(i);
        }
        PointsRef::Inline {
            points,
            len: indices.len() as u8,
        }
    }
}

impl Deref for PointsRef<'_> {
    type Target = [DVec3];

    fn deref(&self) -> &[DVec3] {
        match self {
            PointsRef::Slice(points) => points,
            PointsRef::Inline { points, len } => &points[..usize::from(*len)],
            PointsRef::Heap(points) => points,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{IndexList, Polygon};
    use glam::DVec4;

    fn object(polygons: &[&[u32]]) -> Object {
        let vertices: Vec<DVec3> = (0..6)
            .map(|k| DVec3::new(k as f64, (k * k) as f64, 1.0 - k as f64))
            .collect();
        Object {
            number: 1,
            name: "o".into(),
            mesh: Default::default(),
            polygon_colors: None,
            vertex_colors: None,
            transform: crate::math::Matrix4::IDENTITY,
            vertices,
            polygons: polygons
                .iter()
                .map(|ids| Polygon {
                    indices: IndexList::from(*ids),
                    plane: DVec4::Z,
                })
                .collect(),
            source_polygon: Vec::new(),
            vertex_normals: None,
            bbox_corners: [DVec3::ZERO; 8],
            surface: Default::default(),
            surface_type: Default::default(),
        }
    }

    /// A scene polygon's points read back as its vertices at its
    /// indices, in order, for a triangle, a quad and a longer outline;
    /// own points as given.
    #[test]
    fn scene_points_are_the_object_vertices_at_the_indices() {
        let objects = [object(&[&[4, 0, 2], &[1, 5, 3, 0], &[0, 1, 2, 3, 4, 5]])];
        for (pi, ids) in [vec![4u32, 0, 2], vec![1, 5, 3, 0], vec![0, 1, 2, 3, 4, 5]]
            .into_iter()
            .enumerate()
        {
            let want: Vec<DVec3> = ids
                .iter()
                .map(|&i| objects[0].vertices[i as usize])
                .collect();
            let got = Points::Scene.get(&objects, 0, pi as u32);
            assert_eq!(&*got, want.as_slice(), "polygon {pi}");
        }
        let own = Points::from(vec![DVec3::X, DVec3::Y, DVec3::Z]);
        assert_eq!(&*own.get(&objects, 0, 0), &[DVec3::X, DVec3::Y, DVec3::Z]);
    }

    /// Points are held as the scene's only when whole and few; a scene
    /// polygon holds nothing.
    #[test]
    fn only_whole_small_polygons_hold_nothing() {
        let three = [DVec3::X, DVec3::Y, DVec3::Z];
        assert!(Points::new(three.into_iter(), true).is_scene());
        assert!(!Points::new(three.into_iter(), false).is_scene());
        let five = [DVec3::X; 5];
        assert_eq!(
            Points::new(five.into_iter(), true),
            Points::Own(five.into())
        );
        assert!(std::mem::size_of::<Points>() <= 16);
    }
}
