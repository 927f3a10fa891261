//! Hostile input for the modeling primitives (Firebaugh 001 chapter 8):
//! sizes that were quadratic, budgets that refuse before allocating, and
//! CSG results that must stay closed solids.

use glam::{DVec2, DVec3};
use plytrace::modeling::Generated;
use plytrace::modeling::csg::{self, Face, Op};
use plytrace::modeling::{parametric, solid};

/// A generated solid as CSG faces, scaled by `scale` and moved by `offset`.
fn faces(g: &Generated, scale: f64, offset: DVec3) -> Vec<Face> {
    g.mesh
        .polygons
        .iter()
        .map(|p| Face {
            points: p
                .iter()
                .map(|&i| g.mesh.vertices[i as usize] * scale + offset)
                .collect(),
            normals: match &g.normals {
                Some(n) => p.iter().map(|&i| n[i as usize]).collect(),
                None => vec![DVec3::Z; p.len()],
            },
            attr: 0,
        })
        .collect()
}

/// The result as a mesh: closed (or why not) and its volume.
fn closed_volume(r: &[Face]) -> (Result<(), String>, f64) {
    let (mesh, _, _) = csg::to_mesh(r, false);
    let closed = solid::check_closed(&solid::weld_exact(&mesh.vertices), &mesh.polygons)
        .map_err(|e| e.to_string());
    (closed, solid::mesh_volume(&mesh))
}

#[test]
fn union_of_two_fine_spheres_is_closed() {
    for (nu, nv) in [(32, 16), (64, 32), (128, 64), (256, 128)] {
        let s = parametric::sphere(nu, nv);
        let a = faces(&s, 1.0, DVec3::ZERO);
        let b = faces(&s, 1.0, DVec3::new(0.5, 0.3, 0.2));
        for op in [Op::Union, Op::Intersection, Op::Difference] {
            let r = csg::combine(a.clone(), b.clone(), op);
            let (closed, v) = closed_volume(&r.faces);
            assert!(closed.is_ok(), "{nu}x{nv} {op:?}: {closed:?} (volume {v})");
        }
    }
}

