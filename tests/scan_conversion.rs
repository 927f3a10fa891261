//! The anti-aliasing scan converters (Garcia 1986, 004 chapter 5;
//! Donovan 1973, 000 section 6) through `raster::scan::scan_convert`.

mod support;

use glam::DVec2;
use plytrace::internal::raster::frame_buffer::{FrameBuffer, PaintItem, PaintMode};
use plytrace::internal::raster::scan::{
    Method, PixelStruct, Row, RowSink, SavedFragment, ScanOptions, ScanStats, TransparencyRule,
    scan_convert,
};
use plytrace::internal::shading::PhongVertices;
use plytrace::internal::tree::{PhongShades, Record, RecordStream, Shades};
use proptest::prelude::*;
use support::within;

/// A row as owned data, colours as bits so that comparisons are exact.
#[derive(Debug, Clone, PartialEq)]
struct Owned {
    y: u32,
    rgb: Vec<[u32; 3]>,
    coverage: Option<Vec<u8>>,
    mask: Option<Vec<u16>>,
    pixels: Option<Vec<PixelStruct>>,
    ids: Option<Vec<u32>>,
}

impl Owned {
    fn rgb(&self, i: usize) -> [f32; 3] {
        self.rgb[i].map(f32::from_bits)
    }
}

#[derive(Default)]
struct Collect(Vec<Owned>);

impl RowSink for Collect {
    fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
        assert_eq!(row.y as usize, self.0.len(), "rows in order, top first");
        self.0.push(Owned {
            y: row.y,
            rgb: row.rgb.iter().map(|c| c.map(f32::to_bits)).collect(),
            coverage: row.coverage.map(<[u8]>::to_vec),
            mask: row.mask.map(<[u16]>::to_vec),
            pixels: row.pixels.map(<[PixelStruct]>::to_vec),
            ids: row.ids.map(<[u32]>::to_vec),
        });
        Ok(())
    }
}

fn opts(w: u32, h: u32, method: Method) -> ScanOptions {
    ScanOptions {
        width: w,
        height: h,
        method,
        act_lines: h,
        paint_background: false,
        transparency: TransparencyRule::Garcia,
        threads: 1,
        ids: true,
        max_overdraw: u64::MAX,
    }
}

fn run(s: &RecordStream, o: &ScanOptions) -> (Vec<Owned>, ScanStats) {
    let mut c = Collect::default();
    let stats = scan_convert(s, o, &mut c).unwrap();
    assert_eq!(c.0.len(), o.height as usize);
    (c.0, stats)
}

fn stream(records: Vec<Record>, blended: bool) -> RecordStream {
    RecordStream {
        records,
        background: Some([40, 80, 120]),
        front_to_back: true,
        blended,
    }
}

fn rec(level: u16, pts: &[(f32, f32)], shades: Shades) -> Record {
    Record {
        level,
        points: pts.iter().map(|&(x, y)| [x, y]).collect(),
        shades,
    }
}

fn flat(level: u16, pts: &[(f32, f32)], c: [u8; 3]) -> Record {
    rec(level, pts, Shades::Faceted(c))
}

/// A transparent flat record (Phong with no lights).
fn glass(level: u16, pts: &[(f32, f32)], c: [u8; 3], t: u8) -> Record {
    let n = pts.len();
    rec(
        level,
        pts,
        Shades::Phong(Box::new(PhongShades {
            shininess: 1.0,
            light_colors: vec![],
            rgbt: vec![[c[0], c[1], c[2], t]; n],
            normals: vec![vec![]; n],
        })),
    )
}

const WHITE: [u8; 3] = [255; 3];

/// A polygon star-shaped around `c`, so simple; equal radii: convex.
fn star(c: (f64, f64), jitter: &[f64], radii: &[f64]) -> Vec<(f32, f32)> {
    let n = jitter.len() as f64;
    jitter
        .iter()
        .zip(radii.iter().cycle())
        .enumerate()
        .map(|(k, (j, r))| {
            let t = (k as f64 + j) * std::f64::consts::TAU / n;
            ((c.0 + r * t.cos()) as f32, (c.1 + r * t.sin()) as f32)
        })
        .collect()
}

/// Brute force: is `(x, y)` (pixels, y up) inside, by the half-open rule?
fn inside(pts: &[DVec2], x: f64, y: f64) -> bool {
    let n = pts.len();
    let mut odd = false;
    for k in 0..n {
        let (a, b) = (pts[k], pts[(k + 1) % n]);
        let (p, q) = if (a.y, a.x) <= (b.y, b.x) {
            (a, b)
        } else {
            (b, a)
        };
        if p.y <= y && y < q.y && p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y) <= x {
            odd = !odd;
        }
    }
    odd
}

fn to_pixels(pts: &[(f32, f32)], w: u32, h: u32) -> Vec<DVec2> {
    pts.iter()
        .map(|&(x, y)| DVec2::new(x as f64 * w as f64, y as f64 * h as f64))
        .collect()
}

/// The 4 x 4 mask of pixel `(i, top_row)` by brute force.
fn brute_mask(pts: &[DVec2], i: u32, top_row: u32, h: u32) -> u16 {
    let j = (h - 1 - top_row) as f64;
    let mut m = 0;
    for r in 0..4 {
        for c in 0..4 {
            let x = i as f64 + (c as f64 + 0.5) / 4.0;
            let y = j + 1.0 - (r as f64 + 0.5) / 4.0;
            if inside(pts, x, y) {
                m |= 1 << (4 * r + c);
            }
        }
    }
    m
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn masks_equal_brute_force_point_in_polygon(
        cx in 0.2f64..0.8, cy in 0.2f64..0.8,
        jitter in prop::collection::vec(0.0f64..0.9, 4..10),
        radii in prop::collection::vec(0.01f64..0.45, 1..10),
        convex in any::<bool>(),
    ) {
        let radii = if convex { vec![radii[0]] } else { radii };
        let pts = star((cx, cy), &jitter, &radii);
        let (w, h) = (23, 19);
        let s = stream(vec![flat(1, &pts, WHITE)], true);
        let (rows, _) = run(&s, &opts(w, h, Method::Mask));
        let px = to_pixels(&pts, w, h);
        for row in &rows {
            let mask = row.mask.as_ref().unwrap();
            for i in 0..w {
                let want = brute_mask(&px, i, row.y, h);
                prop_assert_eq!(mask[i as usize], want, "pixel {} row {}", i, row.y);
                let v = want.count_ones() as f32 / 16.0;
                prop_assert_eq!(row.rgb(i as usize), [v; 3]);
            }
        }
    }
}

/// Triangles tiling the unit square: `g x g` cells, interior vertices
/// jittered, two triangles per cell sharing the diagonal.
fn mesh(g: usize) -> Vec<Vec<(f32, f32)>> {
    let mut seed = 11u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let inner = |k: usize| k > 0 && k < g;
    let v: Vec<Vec<(f32, f32)>> = (0..=g)
        .map(|r| {
            (0..=g)
                .map(|c| {
                    let (dx, dy) = if inner(r) && inner(c) {
                        (rnd() - 0.5, rnd() - 0.5)
                    } else {
                        (0.0, 0.0)
                    };
                    (
                        ((c as f64 + 0.7 * dx) / g as f64) as f32,
                        ((r as f64 + 0.7 * dy) / g as f64) as f32,
                    )
                })
                .collect()
        })
        .collect();
    let mut tris = Vec::new();
    for r in 0..g {
        for c in 0..g {
            let (a, b, cc, d) = (v[r][c], v[r][c + 1], v[r + 1][c + 1], v[r + 1][c]);
            tris.push(vec![a, b, cc]);
            tris.push(vec![a, cc, d]);
        }
    }
    tris
}

#[test]
fn a_triangle_mesh_has_no_seams_and_no_double_cover() {
    let (w, h) = (21, 17);
    let tris = mesh(6);
    // Area: every pixel exactly covered, the colour exactly white.
    let recs = tris.iter().map(|t| flat(1, t, WHITE)).collect();
    let (rows, stats) = run(&stream(recs, true), &opts(w, h, Method::Area));
    assert_eq!(stats.polygons_tiled, tris.len());
    for row in &rows {
        assert!(row.coverage.as_ref().unwrap().iter().all(|&c| c == 255));
        for i in 0..w as usize {
            assert!(
                row.rgb(i).iter().all(|v| (v - 1.0).abs() < 1e-5),
                "{:?}",
                row.rgb(i)
            );
        }
    }
    // Hybrid: masks never overlap in a mesh, so every share is an exact
    // area and the masks fill every pixel.
    let recs: Vec<Record> = tris.iter().map(|t| flat(1, t, WHITE)).collect();
    let (rows, _) = run(&stream(recs.clone(), true), &opts(w, h, Method::Hybrid));
    for row in &rows {
        assert!(row.coverage.as_ref().unwrap().iter().all(|&c| c == 255));
        assert!(row.mask.as_ref().unwrap().iter().all(|&m| m == 0xFFFF));
        for i in 0..w as usize {
            assert!(row.rgb(i).iter().all(|v| (v - 1.0).abs() < 1e-5));
        }
    }
    // Method 4: every pixel ends covered at level 1, all fragments freed.
    let (rows, stats) = run(&stream(recs, false), &opts(w, h, Method::Multilevel));
    assert!(stats.peak_fragments > 0 && stats.total_fragments > stats.peak_fragments as u64);
    for row in &rows {
        for p in row.pixels.as_ref().unwrap() {
            assert_eq!(
                (p.pixstat, p.fragments.len(), p.rgb),
                (1 | COVERED, 0, [255; 3])
            );
        }
    }
    // Mask: every subpixel owned by exactly one triangle.
    let mut owners = vec![[0u8; 16]; (w * h) as usize];
    for t in &tris {
        let (rows, _) = run(
            &stream(vec![flat(1, t, WHITE)], true),
            &opts(w, h, Method::Mask),
        );
        for row in &rows {
            for (i, m) in row.mask.as_ref().unwrap().iter().enumerate() {
                let o = &mut owners[row.y as usize * w as usize + i];
                for (b, n) in o.iter_mut().enumerate() {
                    *n += (m >> b & 1) as u8;
                }
            }
        }
    }
    assert!(
        owners.iter().all(|o| o.iter().all(|&n| n == 1)),
        "{owners:?}"
    );
}

// --- Method 4: the six cases of 004 section 5.9 on a 1 x 1 image ---------

const FULL: [(f32, f32); 4] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
const LEFT: [(f32, f32); 4] = [(0.0, 0.0), (0.5, 0.0), (0.5, 1.0), (0.0, 1.0)];
const LEFT_MASK: u16 = 0x3333;
const COVERED: u8 = 1 << 5;
const COMPLEX: u8 = 1 << 6;

fn one_pixel(records: Vec<Record>, background: bool) -> (Owned, ScanStats) {
    let mut o = opts(1, 1, Method::Multilevel);
    o.paint_background = background;
    let (mut rows, stats) = run(&stream(records, false), &o);
    (rows.remove(0), stats)
}

fn b(v: f32) -> f32 {
    v / 255.0
}

fn assert_rgb(row: &Owned, want: [f32; 3]) {
    let got = row.rgb(0);
    for c in 0..3 {
        assert!((got[c] - want[c]).abs() < 1e-6, "{got:?} != {want:?}");
    }
}

fn pixel(row: &Owned) -> &PixelStruct {
    &row.pixels.as_ref().unwrap()[0]
}

#[test]
fn case_1_empty_pixel() {
    let (row, _) = one_pixel(vec![flat(1, &FULL, [200, 100, 0])], false);
    assert_rgb(&row, [b(200.0), b(100.0), 0.0]);
    assert_eq!(pixel(&row).pixstat, 1 | COVERED);
    assert!(pixel(&row).fragments.is_empty());
    let (row, stats) = one_pixel(vec![flat(1, &LEFT, [200, 100, 0])], false);
    assert_rgb(&row, [b(100.0), b(50.0), 0.0]);
    let p = pixel(&row);
    assert_eq!((p.rgb, p.pixstat), ([100, 50, 0], 1 | COMPLEX));
    let f = SavedFragment {
        pmask: LEFT_MASK,
        pstat: 1 | COMPLEX,
        pcover: 128,
    };
    assert_eq!(p.fragments, vec![f]);
    assert_eq!((stats.peak_fragments, stats.total_fragments), (1, 1));
}

#[test]
fn case_2_full_pixel_hides_same_and_deeper_levels() {
    let recs = vec![
        flat(1, &FULL, [10, 20, 30]),
        flat(1, &FULL, [200, 0, 0]),
        flat(2, &LEFT, [0, 200, 0]),
    ];
    let (row, stats) = one_pixel(recs, false);
    assert_rgb(&row, [b(10.0), b(20.0), b(30.0)]);
    assert_eq!(stats.pixels_written, 1);
    assert_eq!(row.ids.as_ref().unwrap()[0], 1);
}

#[test]
fn case_3_complex_pixel_same_depth() {
    let recs = vec![flat(1, &LEFT, [100, 0, 0]), flat(1, &FULL, [0, 200, 0])];
    let (row, _) = one_pixel(recs, false);
    assert_rgb(&row, [b(50.0), b(100.0), 0.0]);
    assert_eq!(pixel(&row).pixstat, 1 | COVERED);
    assert!(pixel(&row).fragments.is_empty());
}

#[test]
fn case_4_deeper_fragment_saves_the_level_and_case_5_restores_it() {
    // A closer object A on the left at level 1; then the child C (level 2)
    // of the mirror P behind it; then P itself.
    let a = flat(1, &LEFT, [100, 0, 0]);
    let c = flat(2, &FULL, [0, 100, 0]);
    let p = flat(1, &FULL, [0, 0, 200]);
    let (row, _) = one_pixel(vec![a.clone(), c.clone()], false);
    assert_rgb(&row, [b(50.0), b(50.0), 0.0]);
    let ps = pixel(&row);
    assert_eq!(ps.pixstat, 2 | COVERED);
    let saved = SavedFragment {
        pmask: LEFT_MASK,
        pstat: 1 | COMPLEX,
        pcover: 128,
    };
    assert_eq!(ps.fragments, vec![saved]);
    let (row, stats) = one_pixel(vec![a, c, p], false);
    assert_rgb(&row, [b(50.0), b(50.0), b(100.0)]);
    assert_eq!(pixel(&row).pixstat, 1 | COVERED);
    assert!(pixel(&row).fragments.is_empty());
    assert_eq!((stats.peak_fragments, stats.total_fragments), (1, 1));
}

#[test]
fn case_4_partial_child_pushes_a_level() {
    // Child on the left under a complex level-1 pixel on the left: hidden;
    // the child on the whole pixel shows on the right only, as a new level.
    let a = flat(1, &LEFT, [100, 0, 0]);
    let hidden = flat(2, &LEFT, [0, 250, 0]);
    let right = [(0.5, 0.0), (1.0, 0.0), (1.0, 0.5), (0.5, 0.5)];
    let c = flat(2, &right, [0, 0, 200]);
    let (row, stats) = one_pixel(vec![a, hidden, c], false);
    assert_rgb(&row, [b(50.0), 0.0, b(50.0)]);
    let ps = pixel(&row);
    assert_eq!(ps.pixstat, 2 | COMPLEX);
    let fr: Vec<(u16, u8)> = ps.fragments.iter().map(|f| (f.pmask, f.pstat)).collect();
    assert_eq!(fr, vec![(0xFF33, 2 | COMPLEX), (LEFT_MASK, 1 | COMPLEX)]);
    assert_eq!((stats.peak_fragments, stats.total_fragments), (2, 2));
}

#[test]
fn case_5_partly_diffuse_mirror() {
    // Figure 5.14: the reflection (level 2), then the shadow on the mirror
    // (level 1), then the mirror (level 1). The reflection and the shadow's
    // shade both survive; the mirror shows where not shadowed.
    let reflection = flat(2, &FULL, [0, 0, 100]);
    let shadow = flat(1, &LEFT, [50, 0, 0]);
    let mirror = flat(1, &FULL, [100, 100, 0]);
    let (row, _) = one_pixel(vec![reflection, shadow, mirror], false);
    assert_rgb(&row, [b(25.0 + 50.0), b(50.0), b(100.0)]);
    assert_eq!(pixel(&row).pixstat, 1 | COVERED);
    assert_eq!(row.ids.as_ref().unwrap()[0], 1);
}

#[test]
fn case_6_special_record_restores_between_reflection_and_refraction() {
    let reflected = flat(2, &FULL, [100, 0, 0]);
    let special = rec(1, &FULL, Shades::Special);
    let refracted = flat(2, &FULL, [0, 100, 0]);
    let parent = flat(1, &FULL, [0, 0, 100]);
    let with = vec![
        reflected.clone(),
        special,
        refracted.clone(),
        parent.clone(),
    ];
    let (row, stats) = one_pixel(with, false);
    assert_rgb(&row, [b(100.0), b(100.0), b(100.0)]);
    assert_eq!(stats.pixels_written, 3);
    // Without the restore, the refraction is hidden by the reflection.
    let (row, _) = one_pixel(vec![reflected, refracted, parent], false);
    assert_rgb(&row, [b(100.0), 0.0, b(100.0)]);
}

#[test]
fn background_pass_and_transparency_in_method_4() {
    let (row, _) = one_pixel(vec![flat(1, &LEFT, [100, 0, 0])], true);
    assert_rgb(&row, [b(50.0 + 20.0), b(40.0), b(60.0)]);
    assert_eq!(pixel(&row).pixstat, 1 | COVERED);
    // Glass with t = 0.5 in front of an opaque wall: I = I_glass + t I_wall.
    let recs = vec![
        glass(1, &FULL, [0, 100, 0], 51),
        flat(1, &FULL, [200, 0, 0]),
    ];
    let (row, _) = one_pixel(recs, false);
    assert_rgb(&row, [0.2 * b(200.0), b(100.0), 0.0]);
}

// --- Single-level methods -------------------------------------------------

#[test]
fn area_mask_and_hybrid_measure_a_sliver() {
    // The left 0.3 of a pixel: 4 of 16 subpixel centres (x = 0.125).
    let left = [(0.0, 0.0), (0.3, 0.0), (0.3, 1.0), (0.0, 1.0)];
    let s = stream(vec![flat(1, &left, WHITE)], true);
    let v = |m| run(&s, &opts(1, 1, m)).0[0].rgb(0)[0];
    assert!((v(Method::Area) - 0.3).abs() < 1e-6);
    assert_eq!(v(Method::Mask), 0.25);
    assert!((v(Method::Hybrid) - 0.3).abs() < 1e-6);
    let (rows, _) = run(&s, &opts(1, 1, Method::Hybrid));
    assert_eq!(rows[0].mask.as_ref().unwrap()[0], 0x1111);
    assert_eq!(rows[0].coverage.as_ref().unwrap()[0], 77);
}

#[test]
fn transparency_in_the_single_level_methods() {
    for m in [Method::Area, Method::Mask, Method::Hybrid, Method::Point] {
        let recs = vec![
            glass(1, &FULL, [0, 100, 0], 51),
            flat(1, &FULL, [200, 0, 0]),
        ];
        let (rows, _) = run(&stream(recs, true), &opts(1, 1, m));
        assert_rgb(&rows[0], [0.2 * b(200.0), b(100.0), 0.0]);
        if let Some(mask) = &rows[0].mask {
            assert_eq!(mask[0], 0xFFFF, "{m:?}");
        }
    }
}

#[test]
fn back_to_front_painter_and_donovan_rule() {
    let recs = vec![
        flat(1, &FULL, [200, 200, 200]),
        glass(1, &FULL, [0, 100, 0], 51),
    ];
    let mut s = stream(recs, true);
    s.front_to_back = false;
    let (rows, _) = run(&s, &opts(1, 1, Method::Point));
    assert_rgb(
        &rows[0],
        [0.2 * b(200.0), b(100.0) + 0.2 * b(200.0), 0.2 * b(200.0)],
    );
    assert_eq!(rows[0].ids.as_ref().unwrap()[0], 2);
    let mut o = opts(1, 1, Method::Point);
    o.transparency = TransparencyRule::Donovan;
    let (rows, _) = run(&s, &o);
    // The glass is darker than the wall: (1 - w) I_a + w I_b, w = 0.2.
    assert_rgb(
        &rows[0],
        [
            0.2 * b(200.0),
            0.8 * b(100.0) + 0.2 * b(200.0),
            0.2 * b(200.0),
        ],
    );
    // A brighter glass hides the wall.
    s.records[1] = glass(1, &FULL, [255, 255, 255], 51);
    let (rows, _) = run(&s, &o);
    assert_rgb(&rows[0], [1.0; 3]);
}

// --- Point against the point sampler of raster::tiler ----------------------

fn scene(n: usize, seed: u64, levels: bool) -> Vec<Record> {
    let mut seed = seed;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let byte = |r: f64| (r * 255.0) as u8;
    (0..n)
        .map(|k| {
            let m = 4 + (rnd() * 5.0) as usize;
            let jitter: Vec<f64> = (0..m).map(|_| rnd() * 0.9).collect();
            let radii: Vec<f64> = (0..m).map(|_| 0.05 + rnd() * 0.3).collect();
            let pts = star((rnd(), rnd()), &jitter, &radii);
            let level = if levels { 1 + (k % 3) as u16 } else { 1 };
            let shades = match k % 4 {
                0 => Shades::Faceted([byte(rnd()), byte(rnd()), byte(rnd())]),
                1 => Shades::Gouraud(pts.iter().map(|_| [byte(rnd()), byte(rnd()), 9]).collect()),
                2 if k % 8 == 2 => Shades::Special,
                _ => {
                    let t = if k % 3 == 0 { byte(rnd() * 0.8) } else { 0 };
                    Shades::Phong(Box::new(PhongShades {
                        shininess: 5.0 + 20.0 * rnd(),
                        light_colors: vec![[90, 90, 60], [30, 30, 70]],
                        rgbt: pts.iter().map(|_| [byte(rnd()), 40, 50, t]).collect(),
                        normals: pts
                            .iter()
                            .map(|_| {
                                (0..2)
                                    .map(|_| [rnd() as f32 - 0.5, rnd() as f32 - 0.5, 1.0])
                                    .collect()
                            })
                            .collect(),
                    }))
                }
            };
            rec(level, &pts, shades)
        })
        .collect()
}

fn paint_item(r: &Record, id: u32, w: u32, h: u32) -> PaintItem {
    let c = |v: u8| v as f32 / 255.0;
    let mut item = PaintItem {
        points: to_pixels(
            &r.points.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>(),
            w,
            h,
        ),
        color: [0.0; 3],
        id,
        transparency: 0.0,
        vertex_colors: None,
        vertex_transparency: None,
        phong: None,
    };
    match &r.shades {
        Shades::Faceted(rgb) => item.color = rgb.map(c),
        Shades::Gouraud(v) => item.vertex_colors = Some(v.iter().map(|x| x.map(c)).collect()),
        Shades::Phong(p) => {
            item.transparency = c(p.rgbt[0][3]);
            let mut attrs = Vec::new();
            for (k, rgbt) in p.rgbt.iter().enumerate() {
                attrs.extend([c(rgbt[0]), c(rgbt[1]), c(rgbt[2])]);
                for (n, lc) in p.normals[k].iter().zip(&p.light_colors) {
                    attrs.extend(n);
                    attrs.extend(lc.map(c));
                }
            }
            item.phong = Some(PhongVertices {
                lights: p.light_colors.len(),
                shininess: p.shininess as f32,
                attrs,
            });
        }
        Shades::Special => unreachable!(),
    }
    item
}

#[test]
fn point_matches_the_point_sampler() {
    let (w, h) = (37, 29);
    let recs: Vec<Record> = scene(40, 3, false)
        .into_iter()
        .filter(|r| !r.is_special())
        .collect();
    let items: Vec<PaintItem> = recs
        .iter()
        .enumerate()
        .map(|(k, r)| paint_item(r, k as u32 + 1, w, h))
        .collect();
    let s = stream(recs, true);
    let bg = s.background.unwrap().map(|v| v as f32 / 255.0);
    let mut fb = FrameBuffer::new(w, h, bg);
    fb.paint(&items, PaintMode::FirstWins);
    let mut o = opts(w, h, Method::Point);
    o.paint_background = true;
    let (rows, _) = run(&s, &o);
    for row in &rows {
        for i in 0..w {
            let (got, want) = (row.rgb(i as usize), fb.pixel(i, row.y));
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 1e-5,
                    "{i} {}: {got:?} {want:?}",
                    row.y
                );
            }
            assert_eq!(row.ids.as_ref().unwrap()[i as usize], fb.id(i, row.y));
        }
    }
}

// --- Bands and threads ------------------------------------------------------

#[test]
fn bands_and_threads_do_not_change_a_bit() {
    let (w, h) = (41, 31);
    let pre = stream(scene(60, 5, false), true);
    let post = stream(scene(60, 9, true), false);
    let cases = [
        (Method::Point, &pre),
        (Method::Area, &pre),
        (Method::Mask, &pre),
        (Method::Hybrid, &pre),
        (Method::Supersample(3), &pre),
        (Method::Point, &post),
        (Method::Multilevel, &post),
        (Method::Supersample(5), &post),
    ];
    for (m, s) in cases {
        let mut o = opts(w, h, m);
        o.paint_background = true;
        let reference = run(s, &o);
        for (threads, act_lines) in [(2, 1), (3, 7), (2, 0), (1, 1000), (3, h)] {
            let mut o2 = o;
            (o2.threads, o2.act_lines) = (threads, act_lines);
            let mut got = run(s, &o2);
            if act_lines < h {
                // The peak is per band: smaller bands, fewer fragments alive.
                assert!(got.1.peak_fragments <= reference.1.peak_fragments);
                got.1.peak_fragments = reference.1.peak_fragments;
            }
            assert_eq!(got.1, reference.1, "{m:?} {threads} {act_lines}");
            for (a, b) in got.0.iter().zip(&reference.0) {
                assert!(a == b, "{m:?} {threads} {act_lines}: {a:?} {b:?}");
            }
        }
        o.paint_background = false;
        o.act_lines = 4;
        o.threads = 2;
        let banded = run(s, &o);
        o.act_lines = h;
        o.threads = 1;
        assert!(run(s, &o).0 == banded.0, "{m:?} without background");
    }
}

/// A sink that takes `left` rows, then fails.
struct FailAfter {
    left: usize,
    taken: Vec<u32>,
}

impl RowSink for FailAfter {
    fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
        if self.left == 0 {
            return Err(plytrace::Error::Invalid("the disk is full".into()));
        }
        self.left -= 1;
        self.taken.push(row.y);
        Ok(())
    }
}

/// The band workers stop when the sink fails: its error comes back (no
/// hang waiting for bands nobody takes), after exactly the rows it took,
/// in order.
#[test]
fn a_failing_sink_stops_every_band_worker() {
    let (w, h) = (41, 31);
    let s = stream(scene(60, 9, true), false);
    for (threads, act_lines, left) in [(3, 1, 0), (3, 1, 17), (2, 4, 5), (1, 7, 30)] {
        let mut o = opts(w, h, Method::Multilevel);
        (o.threads, o.act_lines) = (threads, act_lines);
        let mut sink = FailAfter {
            left,
            taken: Vec::new(),
        };
        let e = scan_convert(&s, &o, &mut sink).unwrap_err();
        assert!(e.to_string().contains("the disk is full"), "{e}");
        assert_eq!(sink.taken, (0..left as u32).collect::<Vec<_>>());
    }
}

/// A sink that runs work on rayon's pool for every row, as a caller's
/// sink may: the band workers, tasks of that pool, must not hold its
/// threads while they wait for this thread to deliver.
#[derive(Default)]
struct UsesThePool(Collect);

impl RowSink for UsesThePool {
    fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
        use rayon::prelude::*;
        let sum: u64 = (0..256u64).into_par_iter().map(|k| k * k).sum();
        assert_eq!(sum, 5_559_680);
        self.0.row(row)
    }
}

/// The bands' workers are tasks of rayon's pool when the caller is not
/// in it, and threads of their own when it is (a caller's parallel
/// work): either way the image is the same and nothing waits forever,
/// with a sink that uses the pool too, or from a pool of one thread.
#[test]
fn band_workers_never_wait_for_the_pool_they_run_in() {
    let (w, h) = (41, 31);
    let s = stream(scene(60, 9, true), false);
    let mut o = opts(w, h, Method::Multilevel);
    o.paint_background = true;
    let reference = run(&s, &o).0;
    (o.threads, o.act_lines) = (rayon::current_num_threads().max(2), 1);
    let (s2, o2) = (s.clone(), o);
    let from_outside = within(60, move || {
        let mut sink = UsesThePool::default();
        scan_convert(&s2, &o2, &mut sink).unwrap();
        sink.0.0
    });
    assert!(from_outside == reference, "a sink that uses the pool");
    let (s3, o3) = (s.clone(), o);
    let from_inside = within(60, move || {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| run(&s3, &o3).0)
    });
    assert!(from_inside == reference, "from a pool of one thread");
}

/// A sink that panics at its fourth row.
struct PanicsAtRow3;

impl RowSink for PanicsAtRow3 {
    fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
        assert!(row.y < 3, "the sink gives up at row {}", row.y);
        Ok(())
    }
}

/// A sink's panic reaches the caller, from outside rayon's pool and from
/// inside it (where the workers are threads that wait for deliveries):
/// no worker is left waiting for a delivery that will never come.
#[test]
fn a_panicking_sink_stops_every_band_worker() {
    let s = stream(scene(60, 9, true), false);
    let mut o = opts(41, 37, Method::Multilevel);
    (o.threads, o.act_lines) = (2, 1);
    for inside_the_pool in [false, true] {
        let (s, o) = (s.clone(), o);
        let outcome = within(60, move || {
            let convert = move || {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    scan_convert(&s, &o, &mut PanicsAtRow3)
                }))
                .is_err()
            };
            if inside_the_pool {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .unwrap();
                pool.install(convert)
            } else {
                convert()
            }
        });
        assert!(
            outcome,
            "the panic comes back (inside the pool: {inside_the_pool})"
        );
    }
}

// --- Supersampling ----------------------------------------------------------

#[test]
fn supersample_1_is_point() {
    let (w, h) = (33, 27);
    for (s, blended) in [(scene(50, 21, false), true), (scene(50, 22, true), false)] {
        let s = stream(s, blended);
        let mut o = opts(w, h, Method::Point);
        o.paint_background = true;
        let point = run(&s, &o);
        o.method = Method::Supersample(1);
        assert!(run(&s, &o) == point, "blended {blended}");
    }
}

#[test]
fn supersampling_a_half_plane_converges_to_the_area() {
    let (w, h) = (16, 16);
    let edge = [(0.0, 0.0), (0.83, 0.0), (0.21, 1.0), (0.0, 1.0)];
    let s = stream(vec![flat(1, &edge, WHITE)], true);
    let (exact, _) = run(&s, &opts(w, h, Method::Area));
    let error = |n| {
        let (rows, _) = run(&s, &opts(w, h, Method::Supersample(n)));
        let mut worst = 0.0f32;
        for (r, e) in rows.iter().zip(&exact) {
            for i in 0..w as usize {
                worst = worst.max((r.rgb(i)[0] - e.rgb(i)[0]).abs());
            }
        }
        worst
    };
    let errors: Vec<f32> = [1, 2, 4, 8, 16].map(error).to_vec();
    assert!(errors[0] > 0.4, "{errors:?}");
    assert!(errors[4] < 0.04, "{errors:?}");
    assert!(errors[4] < errors[2] && errors[2] < errors[0], "{errors:?}");
}

// --- Errors -------------------------------------------------------------------

fn error(s: &RecordStream, o: &ScanOptions) -> String {
    scan_convert(s, o, &mut Collect::default())
        .unwrap_err()
        .to_string()
}

#[test]
fn wrong_stream_kinds_are_clear_errors() {
    let pre = stream(vec![flat(1, &FULL, WHITE)], true);
    let post = stream(vec![flat(1, &FULL, WHITE)], false);
    let mut btf = pre.clone();
    btf.front_to_back = false;
    let e = error(&pre, &opts(1, 1, Method::Multilevel));
    assert_eq!(
        e,
        "rftb4 (multilevel) wants a front-to-back tree with post-blended shades \
         (setmode b off); this one is pre-blended"
    );
    let e = error(&post, &opts(1, 1, Method::Area));
    assert_eq!(
        e,
        "rftb1 (area coverage) wants a front-to-back tree with pre-blended shades \
         (setmode b on); this one is post-blended"
    );
    assert!(error(&btf, &opts(1, 1, Method::Mask)).contains("this one is back to front"));
    assert!(error(&btf, &opts(1, 1, Method::Supersample(2))).contains("back to front"));
    assert!(error(&pre, &opts(1, 1, Method::Supersample(17))).contains("1 to 16"));
    assert!(error(&pre, &opts(1, 1, Method::Supersample(0))).contains("1 to 16"));
    assert!(error(&pre, &opts(0, 1, Method::Point)).contains("0 x 1"));
    let mut o = opts(1, 1, Method::Point);
    o.transparency = TransparencyRule::Donovan;
    assert!(error(&pre, &o).contains("Donovan"));
    let deep = stream(vec![flat(32, &FULL, WHITE)], false);
    assert!(error(&deep, &opts(1, 1, Method::Multilevel)).contains("level 32"));
    let bad = stream(vec![rec(1, &FULL, Shades::Gouraud(vec![WHITE]))], true);
    assert!(error(&bad, &opts(1, 1, Method::Area)).contains("record 1"));
}

/// Horizontal and vertical edges inside pixels: a rectangle with
/// fractional sides, wider than a pixel, so the pixels between its sides
/// on its top and bottom rows are crossed by no sloping edge. Each pixel's
/// coverage is the product of the overlaps; masks are the brute-force
/// ones. (A tiler that only looks at columns where sloping edges pass
/// called those pixels empty: ccube's horizon vanished at some sizes.)
#[test]
fn axis_aligned_rectangle_areas_and_masks_are_exact() {
    let (w, h) = (16u32, 8u32);
    let (x0, x1, y0, y1) = (2.3f64, 13.6f64, 1.25f64, 5.7f64);
    let pts = [(x0, y0), (x0, y1), (x1, y1), (x1, y0)]
        .map(|(x, y)| ((x / w as f64) as f32, (y / h as f64) as f32));
    let s = stream(vec![flat(1, &pts, WHITE)], true);
    let (area_rows, _) = run(&s, &opts(w, h, Method::Area));
    let (mask_rows, _) = run(&s, &opts(w, h, Method::Mask));
    let poly = to_pixels(&pts, w, h);
    let overlap = |a: f64, b: f64, lo: f64, hi: f64| (hi.min(b) - lo.max(a)).max(0.0);
    for top in 0..h {
        let j = (h - 1 - top) as f64;
        for i in 0..w {
            let want = overlap(x0, x1, i as f64, i as f64 + 1.0) * overlap(y0, y1, j, j + 1.0);
            let got = area_rows[top as usize].rgb(i as usize)[0] as f64;
            assert!(
                (got - want).abs() < 1e-5,
                "area at ({i}, {top}): {got} != {want}"
            );
            let mask = mask_rows[top as usize].mask.as_ref().unwrap()[i as usize];
            assert_eq!(mask, brute_mask(&poly, i, top, h), "mask at ({i}, {top})");
        }
    }
}
