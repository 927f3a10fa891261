//! Test support: an independent ray-cast oracle. For each pixel centre it
//! casts the ray between the near and far planes (found by inverting the
//! projection with Gauss-Jordan elimination, not through the renderer's
//! clipper or viewport code) and returns the nearest polygon hit. Brute
//! force over all polygons: small scenes and images only.
#![allow(dead_code)]

use glam::{DVec3, DVec4};
use plytrace::internal::math::Matrix4;
use plytrace::internal::scene::Scene;

/// Inverse of a 4x4 matrix by Gauss-Jordan elimination with partial pivoting.
pub fn invert(m: &Matrix4) -> Option<Matrix4> {
    let mut a = m.m;
    let mut inv = Matrix4::IDENTITY.m;
    for col in 0..4 {
        let pivot = (col..4).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for k in 0..4 {
            a[col][k] /= p;
            inv[col][k] /= p;
        }
        for r in 0..4 {
            if r != col {
                let f = a[r][col];
                for k in 0..4 {
                    a[r][k] -= f * a[col][k];
                    inv[r][k] -= f * inv[col][k];
                }
            }
        }
    }
    Some(Matrix4::from_rows(inv))
}

/// The world point of normalized device coordinates `(x, y, z)`.
pub fn unproject(inv: &Matrix4, x: f64, y: f64, z: f64) -> DVec3 {
    let p = inv.transform(DVec4::new(x, y, z, 1.0));
    p.truncate() / p.w
}

/// Whether `p` (on the polygon's plane) is inside the polygon, by the
/// even-odd rule in the projection that drops the normal's largest axis.
pub fn inside(points: &[DVec3], normal: DVec3, p: DVec3) -> bool {
    let a = normal.abs();
    let (u, v) = if a.x >= a.y && a.x >= a.z {
        (1, 2)
    } else if a.y >= a.z {
        (2, 0)
    } else {
        (0, 1)
    };
    let g = |q: DVec3| (q.to_array()[u], q.to_array()[v]);
    let (px, py) = g(p);
    let mut odd = false;
    for i in 0..points.len() {
        let (ax, ay) = g(points[i]);
        let (bx, by) = g(points[(i + 1) % points.len()]);
        if (ay > py) != (by > py) && px < ax + (py - ay) * (bx - ax) / (by - ay) {
            odd = !odd;
        }
    }
    odd
}

/// The nearest (object index, polygon index) at each pixel centre, rows from
/// the top. Polygons seen from behind are skipped unless the object is
/// `type open`, as in the renderer.
pub fn oracle_ids(scene: &Scene, width: u32, height: u32) -> Vec<Option<(u32, u32)>> {
    let inv = invert(&scene.projection).expect("invertible projection");
    let mut out = Vec::with_capacity((width * height) as usize);
    for row in 0..height {
        for col in 0..width {
            let x = (col as f64 + 0.5) / width as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / height as f64 * 2.0;
            let o = unproject(&inv, x, y, -1.0);
            let d = unproject(&inv, x, y, 1.0) - o;
            let mut best: Option<(f64, (u32, u32))> = None;
            for (oi, obj) in scene.objects.iter().enumerate() {
                if obj.surface_type.hidden {
                    continue;
                }
                for (pi, poly) in obj.polygons.iter().enumerate() {
                    let n = poly.normal();
                    let denom = n.dot(d);
                    if denom == 0.0 || (denom > 0.0 && !obj.surface_type.open) {
                        continue;
                    }
                    let t = -(n.dot(o) + poly.plane.w) / denom;
                    if !(0.0..=1.0).contains(&t) || best.is_some_and(|(bt, _)| bt <= t) {
                        continue;
                    }
                    let pts: Vec<DVec3> = poly
                        .indices
                        .iter()
                        .map(|&i| obj.vertices[i as usize])
                        .collect();
                    if inside(&pts, n, o + d * t) {
                        best = Some((t, (oi as u32, pi as u32)));
                    }
                }
            }
            out.push(best.map(|b| b.1));
        }
    }
    out
}

/// Pixels (x, y from the top) whose 3x3 neighbourhood in `oracle` holds one
/// single value, where `painted` differs from it.
pub fn mismatches(
    oracle: &[Option<(u32, u32)>],
    painted: &[Option<(u32, u32)>],
    width: u32,
    height: u32,
) -> (usize, Vec<(u32, u32)>) {
    let mut checked = 0;
    let mut bad = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let here = oracle[(y * width + x) as usize];
            let uniform = (-1i64..=1).all(|dy| {
                (-1i64..=1).all(|dx| {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                        return true;
                    }
                    oracle[(ny as u32 * width + nx as u32) as usize] == here
                })
            });
            if !uniform {
                continue;
            }
            checked += 1;
            if painted[(y * width + x) as usize] != here {
                bad.push((x, y));
            }
        }
    }
    (checked, bad)
}

/// The renderer's id image as (object index, polygon index) per pixel.
pub fn painted_ids(r: &plytrace::internal::render::Rendered) -> Vec<Option<(u32, u32)>> {
    let f = &r.frame;
    (0..f.height)
        .flat_map(|y| (0..f.width).map(move |x| (x, y)))
        .map(|(x, y)| r.polygon_at(x, y))
        .collect()
}

/// The repository's top folder (fixtures live in its `tests/data`), for
/// the library's tests (run from there) and the programs' in `cli/tests`
/// (one folder down), which include this file too.
pub fn repo_root() -> std::path::PathBuf {
    let manifest = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    match env!("CARGO_PKG_NAME") {
        "plytrace-cli" => manifest.parent().unwrap().to_path_buf(),
        _ => manifest.to_path_buf(),
    }
}

/// Path of a benchmark scene copied into `tests/data/scenes`; a missing
/// fixture fails loudly (never skips).
pub fn scene_fixture(name: &str) -> std::path::PathBuf {
    let p = repo_root().join("tests/data/scenes").join(name);
    assert!(
        p.is_file(),
        "missing fixture {}: the benchmark scenes are copied into tests/data/scenes",
        p.display()
    );
    p
}

/// A temporary folder with `det/cube.det` (the example's cube) and a unit
/// `det/square.det` facing +z, for scenes written by tests.
pub fn cube_and_square_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    let cube = std::fs::read_to_string(repo_root().join("examples/det/cube.det")).unwrap();
    std::fs::write(dir.path().join("det/cube.det"), cube).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title square facing +z\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    dir
}

/// Volume of a mesh by the divergence theorem over its world polygons
/// (clockwise from outside: each fan triangle reversed is
/// counter-clockwise).
pub fn volume(o: &plytrace::internal::model::Object) -> f64 {
    let mut six = 0.0;
    for p in &o.polygons {
        let v = |k: usize| o.vertices[p.indices[k] as usize];
        for k in 1..p.indices.len() - 1 {
            six += v(0).dot(v(k + 1).cross(v(k)));
        }
    }
    six / 6.0
}

/// Whether every edge (by vertex position) is used exactly once in each
/// direction: a closed, consistently oriented mesh.
pub fn closed(o: &plytrace::internal::model::Object) -> bool {
    let key = |v: DVec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let mut edges: std::collections::HashMap<([u64; 3], [u64; 3]), i32> =
        std::collections::HashMap::new();
    for p in &o.polygons {
        let m = p.indices.len();
        for k in 0..m {
            let a = key(o.vertices[p.indices[k] as usize]);
            let b = key(o.vertices[p.indices[(k + 1) % m] as usize]);
            *edges.entry((a, b)).or_default() += 1;
        }
    }
    edges
        .iter()
        .all(|((a, b), n)| *n == 1 && edges.get(&(*b, *a)) == Some(&1))
}

/// Copies the folder `from` into `to`, recursively (fixtures into a
/// temporary working directory).
pub fn copy_tree(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap_or_else(|e| panic!("{}: {e}", from.display())) {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// The options the vector tests render with: shadows on.
pub fn vector_options() -> plytrace::internal::render::RenderOptions {
    plytrace::internal::render::RenderOptions {
        shadows: true,
        ..plytrace::internal::render::RenderOptions::default()
    }
}

/// The PNG's picture of `scene` as the vector output sees it: NNS
/// visibility, shadows on, ids included.
pub fn vector_png(scene: &Scene) -> plytrace::internal::render::Rendered {
    plytrace::internal::render::render(
        scene,
        &plytrace::internal::render::RenderOptions {
            visibility: Some(plytrace::internal::visibility::Algorithm::Nns),
            ..vector_options()
        },
    )
    .unwrap()
}

/// A binary PPM (P6, maxval 255): its RGB pixels, width and height.
pub fn parse_ppm(b: &[u8]) -> (Vec<[u8; 3]>, u32, u32) {
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while b[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while !b[at].is_ascii_whitespace() {
            at += 1;
        }
        fields.push(String::from_utf8_lossy(&b[start..at]).into_owned());
    }
    assert_eq!(fields[0], "P6");
    let (w, h): (u32, u32) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let data = &b[at + 1..];
    (data.chunks(3).map(|p| [p[0], p[1], p[2]]).collect(), w, h)
}

/// An SVG rasterized by resvg at `w x h`: RGB per pixel, rows top first
/// (un-premultiplied; the background rectangle makes every pixel opaque).
pub fn resvg_rgb(svg: &[u8], w: u32, h: u32) -> Vec<[u8; 3]> {
    let tree = resvg::usvg::Tree::from_data(svg, &resvg::usvg::Options::default()).unwrap();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap
        .data()
        .chunks(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// Interior pixels of a rendered picture: their 3 x 3 neighbourhood of
/// pixel centres shows, in the id frame, records `together` with the
/// centre's (`together(centre, neighbour)`; the border pixels are never
/// interior).
pub fn interior_pixels(
    r: &plytrace::internal::render::Rendered,
    together: &dyn Fn(u32, u32) -> bool,
) -> Vec<bool> {
    let (w, h) = (r.frame.width as i64, r.frame.height as i64);
    let id = |x: i64, y: i64| r.frame.ids[(y * w + x) as usize];
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            x > 0
                && y > 0
                && x < w - 1
                && y < h - 1
                && (-1..=1).all(|dy| (-1..=1).all(|dx| together(id(x, y), id(x + dx, y + dy))))
        })
        .collect()
}

/// Of the `inside` pixels, (how many, how many of `raster` differ from
/// the PNG `r` by more than 12 levels (of 255) in some channel).
pub fn pixels_off(
    raster: &[[u8; 3]],
    r: &plytrace::internal::render::Rendered,
    inside: &[bool],
) -> (usize, usize) {
    let (mut checked, mut bad) = (0, 0);
    for (k, c) in raster.iter().enumerate() {
        if !inside[k] {
            continue;
        }
        checked += 1;
        let p = r.frame.color[k].map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as i32);
        if (0..3).any(|i| (p[i] - c[i] as i32).abs() > 12) {
            bad += 1;
        }
    }
    (checked, bad)
}

/// Runs `f` on another thread; fails the test if it takes longer than
/// `secs` seconds (a hang) or panics.
pub fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(std::time::Duration::from_secs(secs)) {
        Ok(v) => v,
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
            panic!("still running after {secs} s: a hang")
        }
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => panic!("the run panicked"),
    }
}
