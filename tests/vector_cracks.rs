//! Cracks between abutting faces of different colours in the vector
//! output, as viewers anti-alias it, in three rasterizers: resvg (in
//! process), cairo through `rsvg-convert` (librsvg2-bin) and poppler's
//! `pdftoppm` (poppler-utils); `.ci/run` installs both programs. The
//! TikZ output is read back into SVG path for path and rasterized by
//! resvg (LaTeX is not installed), which checks that it carries the same
//! seal.
//!
//! **What is measured.** A viewer anti-aliases each path on its own. Where
//! two faces abut and each covers part of a pixel (`c` and `1 - c`), the
//! second painted over the first leaves `c (1 - c)` of the background
//! showing: a crack along every shared edge. The reference is plytrace's
//! own PNG of the same scene (the scan converter's area anti-aliasing,
//! which has no such cracks: `tests/scan_conversion.rs`). A pixel is
//! *interior* when the 3 x 3 pixel centres around it all show, in the
//! PNG's id frame, polygons of the figure that are one continuous piece
//! with the centre's: every pixel of the figure except those along its
//! silhouettes (against the background, or over a farther part of the
//! figure at a fold), edge and corner pixels between faces included (the
//! cracks are there). A pixel is *off* when one of its channels differs
//! from the PNG's by more than 12 levels (of 255): at an edge pixel the
//! PNG holds the area-weighted blend of the faces there, which is what a
//! crack-free rasterization shows (within a few levels: neighbouring
//! faces' shades differ little, so filters of any shape give nearly the
//! same blend). At most 0.05 % of the interior pixels may be off, in each
//! rasterizer. The pixels along silhouettes over farther polygons are
//! counted too and printed (`--nocapture`), not checked.
//!
//! The figures (512 x 512):
//! - a colormapped height field of 100 x 100 cells (20,000 triangles,
//!   colours from a viridis-like map of the height, unlit), white
//!   background, with a fold where a hill hides the valley behind it;
//! - a geodesic sphere of 69,620 triangles lit by a diffuse light, each
//!   face in its own flat shade, black background;
//! - a one-colour star split by the plane of a narrower square piercing
//!   it (NNS cuts the star along the whole line), so that the star's
//!   pieces are separate paths with the square painted between them.
//!
//! Before the vertex caps of `plytrace::internal::vector::seal` (resvg, rsvg-convert,
//! pdftoppm): the surface had 60.6, 63.2 and 45.4 % of its interior
//! pixels off, the mesh 60.8, 62.7 and 46.1 %, the star 0.44, 0.43 and
//! 0.30 %.
//!
//! Silhouettes: the same pictures with every fill made white on black,
//! against the faces' exact outline: no pixel may gain more than half a
//! pixel of coverage.

mod support;

use plytrace::internal::render::Rendered;
use plytrace::internal::scene::Scene;
use plytrace::internal::vector::{self, Item, Picture, Style};

/// Share of interior pixels that may be off, per figure and rasterizer.
const LIMIT: f64 = 0.0005;

/// A viridis-like colour map: 0 dark purple, 1 yellow.
fn colormap(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let s = t.clamp(0.0, 1.0) * 4.0;
    let k = (s.floor() as usize).min(3);
    let f = s - k as f64;
    std::array::from_fn(|c| (STOPS[k][c] + (STOPS[k + 1][c] - STOPS[k][c]) * f).round() as u8)
}

/// The colormapped height field: `z = f(x, y)` on a 101 x 101 grid over
/// [-1, 1]^2, two triangles per cell, each coloured by its mean height.
fn surface(dir: &std::path::Path) -> Scene {
    const N: usize = 100;
    let f = |x: f64, y: f64| {
        0.45 * (2.2 * x).sin() * (1.7 * y + 0.4).cos() + 0.25 * (-(x * x + y * y) * 2.0).exp()
    };
    let mut vertices = Vec::new();
    for j in 0..=N {
        for i in 0..=N {
            let (x, y) = (
                i as f64 / N as f64 * 2.0 - 1.0,
                j as f64 / N as f64 * 2.0 - 1.0,
            );
            vertices.push([x, y, f(x, y)]);
        }
    }
    let at = |i: usize, j: usize| j * (N + 1) + i;
    let mut faces: Vec<[usize; 3]> = Vec::new();
    for j in 0..N {
        for i in 0..N {
            // Clockwise seen from +z (the object files' convention).
            faces.push([at(i, j), at(i, j + 1), at(i + 1, j)]);
            faces.push([at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
        }
    }
    let heights: Vec<f64> = faces
        .iter()
        .map(|t| t.iter().map(|&k| vertices[k][2]).sum::<f64>() / 3.0)
        .collect();
    let (lo, hi) = heights
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    let det_dir = dir.join("det");
    std::fs::create_dir_all(&det_dir).unwrap();
    let mut det = format!("title surface\ndata\n{} {}\n", vertices.len(), faces.len());
    for v in &vertices {
        det += &format!("{:.6} {:.6} {:.6}\n", v[0], v[1], v[2]);
    }
    for t in &faces {
        det += &format!("3 {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(det_dir.join("surf.det"), det).unwrap();
    let mut pcl = format!("title surface colours\ndata {}\n", faces.len());
    for h in &heights {
        let c = colormap((h - lo) / (hi - lo));
        pcl += &format!(
            "{:.6} {:.6} {:.6} 0 0 0\n",
            c[0] as f64 / 255.0,
            c[1] as f64 / 255.0,
            c[2] as f64 / 255.0
        );
    }
    std::fs::write(det_dir.join("surf.pcl"), pcl).unwrap();
    let des = dir.join("surf.des");
    std::fs::write(
        &des,
        "resolution 512 512\nbackground 1 1 1\nperspective 40 1 0.1 100\npushmatrix\nident\n\
         polarview 3.6 20 58 0\ntype polygon open ltsrc\ndefobj surf\n  pcolors surf\nendobj\n\
         popmatrix\n",
    )
    .unwrap();
    plytrace::internal::scene::load(&des).unwrap().0
}

fn scene_text(dir: &std::path::Path, name: &str, des: &str) -> Scene {
    let path = dir.join(name);
    std::fs::write(&path, des).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// A geodesic sphere of 69,620 triangles (59 divisions), lit by a
/// diffuse light: each face has its own flat shade.
fn mesh(dir: &std::path::Path) -> Scene {
    scene_text(
        dir,
        "geo.des",
        "resolution 512 512\nperspective 40 1 0.1 100\nlight 2 -3 5 1 1 1 100 Diffuse\n\
         pushmatrix\nident\npolarview 4 25 65 0\ncolor 1 0.6 0.2\ndefobj geo\n  geodesic 59 equal\n  \
         radial sphere\nendobj\npopmatrix\n",
    )
}

/// A ten-pointed one-colour star in the plane z = 0, pierced along the
/// line y = 0.1 by a square half as wide, tilted 60 degrees: NNS cuts the
/// star along the square's plane, and the square's pieces are painted
/// between the star's.
fn star(dir: &std::path::Path) -> Scene {
    let det_dir = dir.join("det");
    std::fs::create_dir_all(&det_dir).unwrap();
    let n = 10;
    let mut det = format!("title star\ndata\n{} 1\n", 2 * n);
    for k in 0..2 * n {
        let a = std::f64::consts::PI * k as f64 / n as f64;
        let r = if k % 2 == 0 { 1.0 } else { 0.55 };
        det += &format!("{:.6} {:.6} 0\n", r * a.cos(), r * a.sin());
    }
    det += &format!("{}", 2 * n);
    // Clockwise seen from +z.
    for k in (0..2 * n).rev() {
        det += &format!(" {}", k + 1);
    }
    det += "\n";
    std::fs::write(det_dir.join("star.det"), det).unwrap();
    let (s, c) = (60f64.to_radians().sin(), 60f64.to_radians().cos());
    let sq = |u: f64, v: f64| format!("{:.6} {:.6} {:.6}\n", u, 0.1 + v * c, v * s);
    let square = format!(
        "title square\ndata\n4 1\n{}{}{}{}4 1 2 3 4\n",
        sq(-0.3, -0.7),
        sq(-0.3, 0.7),
        sq(0.3, 0.7),
        sq(0.3, -0.7)
    );
    std::fs::write(det_dir.join("blade.det"), square).unwrap();
    scene_text(
        dir,
        "star.des",
        "resolution 512 512\nbackground 0 0 0\nperspective 40 1 0.1 100\npushmatrix\nident\n\
         polarview 3.4 10 35 0\ntype polygon open concave ltsrc\ncolor 1 0.6 0.2\n\
         defobj star\nendobj\ncolor 0.2 0.5 1\ndefobj blade\nendobj\npopmatrix\n",
    )
}

fn run(program: &str, args: &[&std::ffi::OsStr], needs: &str) {
    let out = std::process::Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{program} ({needs}) is needed: .ci/run installs it: {e}"));
    assert!(out.status.success(), "{program}: {out:?}");
}

/// A TikZ picture as plytrace writes it, read back path for path into
/// SVG (TikZ's y up becomes SVG's y down; `\fill` fills with the nonzero
/// rule, as TikZ does; `\filldraw` also strokes 1 unit wide with round
/// joins): the geometry, colours and fill rule of the `.tex` file,
/// rasterized like the others, since LaTeX is not installed.
fn tikz_as_svg(tex: &str, w: u32, h: u32) -> Vec<u8> {
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\">\n"
    );
    let mut statements = tex.split(";\n").map(str::trim_start);
    for statement in &mut statements {
        let statement = statement.trim_start_matches("\\begin{scope}\n");
        let statement = statement.trim_start_matches("\\end{scope}\n");
        let (draw, rest) = if let Some(r) = statement.strip_prefix("\\filldraw[") {
            (true, r)
        } else if let Some(r) = statement.strip_prefix("\\fill[") {
            (false, r)
        } else {
            continue;
        };
        let (options, path) = rest.split_once("] ").expect("options then a path");
        let rgb = |key: &str| -> String {
            let at = options.find(key).expect("a colour") + key.len();
            let c = &options[at + "{rgb,255:".len()..];
            let c = &c[..c.find('}').unwrap()];
            let v: Vec<&str> = c.split(';').map(|p| p.split(',').nth(1).unwrap()).collect();
            format!("rgb({},{},{})", v[0], v[1], v[2])
        };
        let opacity = options
            .split_once("fill opacity=")
            .map_or("1", |(_, o)| o.split([',', ']']).next().unwrap());
        let y = |v: &str| h as f64 - v.parse::<f64>().unwrap();
        let mut d = String::new();
        if let Some((a, b)) = path.split_once(" rectangle ") {
            let p = |s: &str| -> (f64, f64) {
                let (x, v) = s.trim().trim_matches(['(', ')']).split_once(',').unwrap();
                (x.parse().unwrap(), y(v))
            };
            let ((x0, y0), (x1, y1)) = (p(a), p(b));
            d += &format!("M{x0},{y0}H{x1}V{y1}H{x0}Z");
        } else {
            for sub in path.split("--cycle").filter(|s| !s.trim().is_empty()) {
                for (i, point) in sub.trim().split("--").enumerate() {
                    let (x, v) = point.trim_matches(['(', ')']).split_once(',').unwrap();
                    d += &format!("{}{x},{}", if i == 0 { 'M' } else { 'L' }, y(v));
                }
                d += "Z";
            }
        }
        let fill = rgb("fill=");
        let stroke = if draw {
            format!(
                " stroke=\"{}\" stroke-width=\"1\" stroke-linejoin=\"round\"",
                rgb("draw=")
            )
        } else {
            String::new()
        };
        svg += &format!(
            "<path d=\"{d}\" fill=\"{fill}\" fill-rule=\"nonzero\" fill-opacity=\"{opacity}\"{stroke}/>\n"
        );
    }
    svg += "</svg>\n";
    svg.into_bytes()
}

/// An SVG rasterized by cairo through librsvg's `rsvg-convert`.
fn rsvg(svg: &[u8], w: u32, h: u32) -> Vec<[u8; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let (input, output) = (dir.path().join("in.svg"), dir.path().join("out.png"));
    std::fs::write(&input, svg).unwrap();
    run(
        "rsvg-convert",
        &[
            "-w".as_ref(),
            w.to_string().as_ref(),
            "-h".as_ref(),
            h.to_string().as_ref(),
            "-o".as_ref(),
            output.as_os_str(),
            input.as_os_str(),
        ],
        "librsvg2-bin",
    );
    let bytes = std::fs::read(&output).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (w, h));
    let n = info.color_type.samples();
    buf[..info.buffer_size()]
        .chunks(n)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// A PDF rasterized by poppler's `pdftoppm` at 72 dpi (one point, one
/// pixel).
fn pdftoppm(pdf: &[u8], w: u32, h: u32) -> Vec<[u8; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.pdf");
    std::fs::write(&input, pdf).unwrap();
    let stem = dir.path().join("out");
    run(
        "pdftoppm",
        &[
            "-r".as_ref(),
            "72".as_ref(),
            "-singlefile".as_ref(),
            input.as_os_str(),
            stem.as_os_str(),
        ],
        "poppler-utils",
    );
    let b = std::fs::read(dir.path().join("out.ppm")).unwrap();
    let (rgb, pw, ph) = support::parse_ppm(&b);
    assert_eq!((pw, ph), (w, h), "one point per pixel");
    rgb
}

/// Writes an RGB raster as PNG when `VECTOR_DUMP` names a directory.
fn dump(name: &str, rgb: &[[u8; 3]], w: u32, h: u32) {
    let Ok(dir) = std::env::var("VECTOR_DUMP") else {
        return;
    };
    let f = std::fs::File::create(format!("{dir}/{name}.png")).unwrap();
    let mut e = png::Encoder::new(std::io::BufWriter::new(f), w, h);
    e.set_color(png::ColorType::Rgb);
    let mut wr = e.write_header().unwrap();
    wr.write_image_data(&rgb.concat()).unwrap();
}

/// The figure in the three rasterizers: (rasterizer, interior pixels,
/// off pixels).
fn cracks(
    name: &str,
    scene: &Scene,
    together: &dyn Fn(&Rendered, u32, u32) -> bool,
) -> Vec<(&'static str, usize, usize)> {
    let r = support::vector_png(scene);
    let (w, h) = (r.frame.width, r.frame.height);
    let input =
        plytrace::internal::render::vector::prepare(scene, &support::vector_options()).unwrap();
    let pic = vector::picture(&input, Style::Shaded);
    let svg = vector::svg::to_svg(&pic);
    let pdf = vector::pdf::to_pdf(&pic);
    let tex = String::from_utf8(vector::tikz::to_tikz(&pic)).unwrap();
    let inside = support::interior_pixels(&r, &|a, b| together(&r, a, b));
    // Pixels on the scene's polygons along a silhouette over a farther
    // polygon (a fold of the surface, or another object): not interior,
    // counted for the record.
    let on = support::interior_pixels(&r, &|a, b| a != 0 && b != 0);
    let folds: Vec<bool> = on.iter().zip(&inside).map(|(o, i)| *o && !i).collect();
    let mut out = Vec::new();
    for (rasterizer, raster) in [
        ("resvg", support::resvg_rgb(&svg, w, h)),
        ("rsvg-convert", rsvg(&svg, w, h)),
        ("pdftoppm", pdftoppm(&pdf, w, h)),
        (
            "TikZ in resvg",
            support::resvg_rgb(&tikz_as_svg(&tex, w, h), w, h),
        ),
    ] {
        let (checked, bad) = support::pixels_off(&raster, &r, &inside);
        let (fold, fold_bad) = support::pixels_off(&raster, &r, &folds);
        eprintln!(
            "{name} in {rasterizer}: {bad} of {checked} interior pixels ({:.3} %) off by > 12 levels \
             ({fold_bad} of {fold} next to silhouettes over farther polygons; SVG {} bytes, PDF {} bytes)",
            100.0 * bad as f64 / checked as f64,
            svg.len(),
            pdf.len()
        );
        dump(&format!("{name}-{rasterizer}"), &raster, w, h);
        let marked: Vec<[u8; 3]> = raster
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let p = r.frame.color[k].map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as i32);
                if inside[k] && (0..3).any(|i| (p[i] - c[i] as i32).abs() > 12) {
                    [255, 0, 0]
                } else {
                    c.map(|v| v / 2 + 64)
                }
            })
            .collect();
        dump(&format!("{name}-{rasterizer}-off"), &marked, w, h);
        out.push((rasterizer, checked, bad));
    }
    let reference: Vec<[u8; 3]> = r
        .frame
        .color
        .iter()
        .map(|c| c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
        .collect();
    dump(&format!("{name}-png"), &reference, w, h);
    out
}

fn check(name: &str, figures: &[(&str, usize, usize)], min_checked: usize) {
    for &(rasterizer, checked, bad) in figures {
        assert!(checked >= min_checked, "{name}: {checked} interior pixels");
        assert!(
            bad as f64 <= LIMIT * checked as f64,
            "{name} in {rasterizer}: {bad} of {checked} interior pixels are off by more than \
             12 levels"
        );
    }
}

#[test]
fn a_colormapped_surface_has_no_cracks() {
    let dir = tempfile::tempdir().unwrap();
    let scene = surface(dir.path());
    // Faces within two cells of each other on the grid are one piece of
    // the surface; farther ones meet only along a fold.
    let cell = |r: &Rendered, id: u32| {
        let (o, p) = r.polygons[id as usize - 1];
        let f = scene.objects[o as usize].source_polygon[p as usize] as i64 / 2;
        (f % 100, f / 100)
    };
    let figures = cracks("surface", &scene, &|r, a, b| {
        if a == 0 || b == 0 {
            return false;
        }
        let (p, q) = (cell(r, a), cell(r, b));
        (p.0 - q.0).abs() <= 2 && (p.1 - q.1).abs() <= 2
    });
    check("surface", &figures, 60_000);
    // The same faces painted one path each, without caps, do crack: the
    // test can see cracks.
    let input =
        plytrace::internal::render::vector::prepare(&scene, &support::vector_options()).unwrap();
    let mut unsealed = vector::picture(&input, Style::Shaded);
    unsealed.items = input
        .stream
        .records
        .iter()
        .filter_map(|rec| match rec.shades {
            plytrace::internal::tree::Shades::Faceted(color) => Some(Item::Fill {
                paths: vec![vector::user_points(rec, 512.0, 512.0)],
                color,
                opacity: 1.0,
            }),
            _ => None,
        })
        .collect();
    let r = support::vector_png(&scene);
    let raster = support::resvg_rgb(&vector::svg::to_svg(&unsealed), 512, 512);
    let (checked, bad) = support::pixels_off(
        &raster,
        &r,
        &support::interior_pixels(&r, &|a, b| a != 0 && b != 0),
    );
    assert!(bad as f64 > 0.1 * checked as f64, "{bad} of {checked}");
}

#[test]
fn a_per_face_shaded_mesh_of_70k_triangles_has_no_cracks() {
    let dir = tempfile::tempdir().unwrap();
    let scene = mesh(dir.path());
    let figures = cracks("mesh", &scene, &|_, a, b| a != 0 && b != 0);
    check("mesh", &figures, 60_000);
}

#[test]
fn a_split_one_colour_star_has_no_seams() {
    let dir = tempfile::tempdir().unwrap();
    let scene = star(dir.path());
    let r = support::vector_png(&scene);
    // The star's pixels: the polygons of object 0.
    let star_ids: Vec<bool> = std::iter::once(false)
        .chain(r.polygons.iter().map(|&(o, _)| o == 0))
        .collect();
    let figures = cracks("star", &scene, &|_, a, b| {
        star_ids[a as usize] && star_ids[b as usize]
    });
    check("star", &figures, 20_000);
}

/// `pic` with every fill white, on black, each path kept as it is.
fn white(pic: &Picture) -> Picture {
    let mut p = pic.clone();
    p.background = [0, 0, 0];
    for item in &mut p.items {
        if let Item::Fill { color, .. } = item {
            *color = [255, 255, 255];
        }
    }
    p
}

/// Silhouettes: coverage gained by any pixel over what the faces give
/// without sealing, in resvg and pdftoppm. The reference at a pixel is the
/// larger of two coverages: the records' union painted as one white path
/// (the exact outline) and the records painted one white path each (where
/// faces overlap at a fold their edges add up, and pdftoppm draws a path
/// thinner than a pixel at least a pixel wide).
#[test]
fn silhouettes_grow_by_at_most_half_a_pixel() {
    let dir = tempfile::tempdir().unwrap();
    for (name, scene) in [
        ("surface", surface(dir.path())),
        ("mesh", mesh(dir.path())),
        ("star", star(dir.path())),
    ] {
        let input = plytrace::internal::render::vector::prepare(&scene, &support::vector_options())
            .unwrap();
        let pic = vector::picture(&input, Style::Shaded);
        let (w, h) = (input.width, input.height);
        let test = white(&pic);
        let records: Vec<Vec<[f64; 2]>> = input
            .stream
            .records
            .iter()
            .filter(|r| !r.is_special())
            .map(|r| vector::user_points(r, w as f64, h as f64))
            .collect();
        let fill = |paths: Vec<Vec<[f64; 2]>>| Item::Fill {
            paths,
            color: [255, 255, 255],
            opacity: 1.0,
        };
        let mut union = test.clone();
        union.items = vec![fill(records.clone())];
        let mut each = test.clone();
        each.items = records.into_iter().map(|p| fill(vec![p])).collect();
        type Raster = fn(&Picture, u32, u32) -> Vec<[u8; 3]>;
        let rasterizers: [(&str, Raster); 2] = [
            ("resvg", |p, w, h| {
                support::resvg_rgb(&vector::svg::to_svg(p), w, h)
            }),
            ("pdftoppm", |p, w, h| {
                pdftoppm(&vector::pdf::to_pdf(p), w, h)
            }),
        ];
        for (rasterizer, raster) in rasterizers {
            let (a, b, c) = (
                raster(&test, w, h),
                raster(&union, w, h),
                raster(&each, w, h),
            );
            let (mut edge, mut gained, mut worst) = (0, 0.0, 0.0f64);
            for ((p, q), r) in a.iter().zip(&b).zip(&c) {
                let exact = q[0] as f64 / 255.0;
                if exact > 0.0 && exact < 1.0 {
                    edge += 1;
                }
                let g = (p[0] as f64 - q[0].max(r[0]) as f64).max(0.0) / 255.0;
                gained += g;
                worst = worst.max(g);
            }
            eprintln!(
                "{name} in {rasterizer}: {edge} outline pixels gain {:.4} pixel on average, \
                 {worst:.3} at most",
                gained / edge.max(1) as f64
            );
            assert!(edge > 500, "{name}: {edge}");
            assert!(
                worst <= 0.5,
                "{name} in {rasterizer}: a pixel gains {worst:.3}"
            );
        }
    }
}
