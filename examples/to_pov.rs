//! Writes a scene's geometry as a POV-Ray 3.7 scene, for the side-by-side
//! timing in benches/side_by_side.sh (not part of the tests):
//!
//!     cargo run --release --example to_pov -- office2.des 512 office2.pov
//!     povray +Ioffice2.pov +W512 +H512 +A0.0 +AM1 +R3 -D
//!
//! The same world polygons (triangle fans, one mesh per object), the
//! same camera rays (the projection's rays through the image's centre and
//! edges), the same Point lights with shadows (Diffuse ones shadowless),
//! colours and the coefficients of 004 section 4.8 (ambient, diffuse,
//! specular, mirror reflection, transmission with the index) and
//! `max_trace_level` = the scene's `depth`. POV-Ray has no range
//! attenuation `(1 - d/range)^2`; it is left out.

use std::fmt::Write as _;

use glam::DVec3;
use plytrace::internal::geometry::view::View;

fn v(p: DVec3) -> String {
    format!("<{:.9}, {:.9}, {:.9}>", p.x, p.y, p.z)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        eprintln!("usage: to_pov SCENE.des SIZE OUT.pov");
        std::process::exit(2);
    }
    let scene = plytrace::internal::scene::load(std::path::Path::new(&args[1]))
        .expect("a scene")
        .0;
    let size: u32 = args[2].parse().expect("a size");
    let view = View::new(&scene, size, size).expect("a view");
    let (w, h) = (view.width, view.height);
    let ray = |x: f64, y: f64| view.ray(x, y).expect("a ray");
    let (eye, dc) = ray(w / 2.0, h / 2.0);
    // Directions scaled to the plane at distance 1 along the centre ray,
    // where they are affine in the pixel coordinates.
    let flat = |d: DVec3| d / d.dot(dc);
    let right = (flat(ray(w, h / 2.0).1) - flat(dc)) * 2.0;
    let up = (flat(ray(w / 2.0, h).1) - flat(dc)) * 2.0;
    let mut s = String::new();
    let bg = scene.background;
    let amb = scene.ambient;
    writeln!(
        s,
        "global_settings {{ max_trace_level {} assumed_gamma 1.0 ambient_light rgb <{}, {}, {}> }}",
        scene.modes.max_level.max(1),
        amb.x,
        amb.y,
        amb.z
    )
    .unwrap();
    writeln!(s, "background {{ rgb <{}, {}, {}> }}", bg.x, bg.y, bg.z).unwrap();
    writeln!(
        s,
        "camera {{ perspective location {} direction {} right {} up {} }}",
        v(eye),
        v(flat(dc)),
        v(right),
        v(up)
    )
    .unwrap();
    for light in &scene.lights {
        let c = light.color;
        let shadowless = if light.kind == plytrace::internal::model::LightKind::Point {
            ""
        } else {
            " shadowless"
        };
        writeln!(
            s,
            "light_source {{ {} rgb <{}, {}, {}>{shadowless} }}",
            v(light.position),
            c.x,
            c.y,
            c.z
        )
        .unwrap();
    }
    let mut triangles = 0usize;
    // Mesh triangles take declared textures only.
    let mut textures: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let mut meshes = String::new();
    for object in &scene.objects {
        if object.surface_type.hidden || object.polygons.is_empty() {
            continue;
        }
        writeln!(meshes, "mesh {{").unwrap();
        for (pi, poly) in object.polygons.iter().enumerate() {
            let m = object.material(pi);
            let tex = format!(
                "texture {{ pigment {{ rgbt <{}, {}, {}, {}> }} finish {{ ambient {} diffuse {} specular {} roughness {} reflection {} }} }}",
                m.color.x,
                m.color.y,
                m.color.z,
                m.transmittance,
                m.ambient_coefficient(),
                m.diffuse,
                m.specular,
                1.0 / m.shininess.max(1.0),
                m.reflectance
            );
            let p: Vec<DVec3> = poly
                .indices
                .iter()
                .map(|&i| object.vertices[i as usize])
                .collect();
            let next = textures.len();
            let id = *textures.entry(tex.clone()).or_insert(next);
            if id == next {
                writeln!(s, "#declare T{id} = {tex}").unwrap();
            }
            for k in 1..p.len().saturating_sub(1) {
                writeln!(
                    meshes,
                    "  triangle {{ {}, {}, {} texture {{ T{id} }} }}",
                    v(p[0]),
                    v(p[k]),
                    v(p[k + 1])
                )
                .unwrap();
                triangles += 1;
            }
        }
        if object.surface.index != 1.0 {
            writeln!(meshes, "  interior {{ ior {} }}", object.surface.index).unwrap();
        }
        writeln!(meshes, "}}").unwrap();
    }
    s.push_str(&meshes);
    std::fs::write(&args[3], s).expect("writable");
    eprintln!(
        "{}: {triangles} triangles, {} lights",
        args[3],
        scene.lights.len()
    );
}
