//! Runaway renders: the ray budget of `--raytrace`, the work budgets of
//! the image-space algorithms (`--visibility z-buffer`, `scan-line`,
//! `brown`, `warnock`, `ray-cast`) and Ctrl-C within a second in each.

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// 12 tilted glass slabs over a floor, `depth 14`: every glass surface
/// spawns a reflected and a refracted ray.
fn glass_scene(dir: &Path, size: u32) {
    let cube = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("tests/data/scenes/det/cube.det");
    std::fs::create_dir_all(dir.join("det")).unwrap();
    std::fs::copy(cube, dir.join("det/cube.det")).unwrap();
    let mut s = format!(
        "resolution {size} {size}\ndepth 14\nident\nperspective 45 1.0 0.01 1000.0\npushmatrix\n\
         ident\ntranslate 0 0 -8\nlight 3 4 10 1 1 1 100 Point\n\
         defobj cube\n color 0.8 0.3 0.2\n diffuse 0.8\n translate 0 0 -6\n scale 4 4 0.5\nendobj\n"
    );
    for k in 0..12 {
        writeln!(
            s,
            "defobj cube\n color 0.7 0.8 0.9\n diffuse 0.1\n reflectance 0.5\n transmittance 0.5\n \
             index 1.5\n translate 0 0 {}\n rotate {} x\n rotate {} y\n scale 6 6 0.1\nendobj",
            2.5 - k as f64 * 0.6,
            (7 * k + 5) % 9 + 2,
            (11 * k + 3) % 7 + 1
        )
        .unwrap();
    }
    s.push_str("popmatrix\n");
    std::fs::write(dir.join("scene.des"), s).unwrap();
}

/// 20,000 random interpenetrating triangles: NNS splits for many seconds.
fn tangle_scene(dir: &Path) {
    let n = 20_000;
    let mut seed: u64 = 5;
    let mut rnd = move |lo: f64, hi: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut det = format!("title tangle\ndata\n{} {n}\n", 3 * n);
    for _ in 0..n {
        let c = [rnd(-1.0, 1.0), rnd(-1.0, 1.0), rnd(-1.0, 1.0)];
        for _ in 0..3 {
            let p: Vec<f64> = c.iter().map(|v| v + rnd(-0.3, 0.3)).collect();
            writeln!(det, "{} {} {}", p[0], p[1], p[2]).unwrap();
        }
    }
    for i in 0..n {
        writeln!(det, "3 {} {} {}", 3 * i + 1, 3 * i + 2, 3 * i + 3).unwrap();
    }
    std::fs::create_dir_all(dir.join("det")).unwrap();
    std::fs::write(dir.join("det/tangle.det"), det).unwrap();
    std::fs::write(
        dir.join("scene.des"),
        "resolution 256 256\nperspective 45 1 0.01 100\npushmatrix\nident\ntranslate 0 0 -4\n\
         light 0 0 10 1 1 1 100 Point\ngetobj tangle\npopmatrix\n",
    )
    .unwrap();
}

/// `n` random large triangles through one another, no light (the
/// image-space algorithms paint level 1 only), at `size` x `size`.
fn soup_scene(dir: &Path, n: usize, size: u32) {
    let mut seed: u64 = 11;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut det = format!("title soup\ndata\n{} {n}\n", 3 * n);
    for _ in 0..3 * n {
        writeln!(det, "{} {} {}", rnd(), rnd(), rnd()).unwrap();
    }
    for i in 0..n {
        writeln!(det, "3 {} {} {}", 3 * i + 1, 3 * i + 2, 3 * i + 3).unwrap();
    }
    std::fs::create_dir_all(dir.join("det")).unwrap();
    std::fs::write(dir.join("det/soup.det"), det).unwrap();
    std::fs::write(
        dir.join("scene.des"),
        format!(
            "resolution {size} {size}\nperspective 45 1 0.01 100\npushmatrix\nident\n\
             translate 0 0 -4\ngetobj soup\npopmatrix\n"
        ),
    )
    .unwrap();
}

/// Each image-space algorithm with the flag of its work budget.
const WORK_BUDGETS: [(&str, &str); 5] = [
    ("z-buffer", "--max-samples"),
    ("scan-line", "--max-samples"),
    ("brown", "--max-samples"),
    ("warnock", "--max-window-tests"),
    ("ray-cast", "--max-ray-tests"),
];

#[test]
fn every_image_space_algorithm_stops_at_its_work_budget_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    soup_scene(dir.path(), 400, 96);
    for (algorithm, flag) in WORK_BUDGETS {
        let args = ["--visibility", algorithm, "-o", "s.png"];
        let child = start(dir.path(), &[&args[..], &[flag, "1000"]].concat());
        let (code, err, _) = finish(child, Duration::from_secs(60));
        assert_eq!(code, Some(1), "{algorithm}: {err}");
        assert!(
            err.contains(&format!("`{flag} N` raises it")),
            "{algorithm}: {err}"
        );
        assert!(!dir.path().join("s.png").exists(), "{algorithm}");
        // Within the default budget the same render is made.
        let (code, err, _) = finish(start(dir.path(), &args), Duration::from_secs(60));
        assert_eq!(code, Some(0), "{algorithm}: {err}");
        assert!(dir.path().join("s.png").exists(), "{algorithm}");
        std::fs::remove_file(dir.path().join("s.png")).unwrap();
    }
}

#[test]
fn ctrl_c_stops_every_image_space_algorithm_within_a_second() {
    let dir = tempfile::tempdir().unwrap();
    // About 10 s of the z-buffer's painting on 2 cores. Warnock's
    // subdivision, which drops the polygons hidden in a window, finishes
    // this in a second; its stop is looked at where its budget is.
    soup_scene(dir.path(), 40_000, 2048);
    for (algorithm, flag) in WORK_BUDGETS.iter().filter(|w| w.0 != "warnock") {
        let args = [
            "--visibility",
            algorithm,
            "-o",
            "s.png",
            flag,
            "100000000000000",
        ];
        interrupted_within_a_second(dir.path(), &args, "s.png", Duration::from_millis(1200));
    }
}

fn start(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .current_dir(dir)
        .arg("scene.des")
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits at most `limit` for `child`; its exit code and stderr.
fn finish(mut child: Child, limit: Duration) -> (Option<i32>, String, Duration) {
    let t = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if t.elapsed() > limit {
            child.kill().unwrap();
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        t.elapsed(),
    )
}

/// Starts a render, interrupts it after `after`; it must stop within a
/// second, with status 130, writing nothing.
fn interrupted_within_a_second(dir: &Path, args: &[&str], output: &str, after: Duration) {
    let child = start(dir, args);
    std::thread::sleep(after);
    let ok = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill -INT");
    let (code, err, took) = finish(child, Duration::from_secs(30));
    assert_eq!(code, Some(130), "{err}");
    assert!(
        took < Duration::from_secs(5),
        "stopped {took:?} after Ctrl-C; {err}"
    );
    assert!(!dir.join(output).exists());
}

#[test]
fn glass_slabs_stop_at_the_ray_budget_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    glass_scene(dir.path(), 64);
    let child = start(
        dir.path(),
        &["--raytrace", "-o", "g.png", "--max-rays", "2000000"],
    );
    let (code, err, took) = finish(child, Duration::from_secs(60));
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("--max-rays"), "{err}");
    assert!(took < Duration::from_secs(50), "{took:?}");
    assert!(!dir.path().join("g.png").exists());
    // Within the budget the same render is made.
    let small = tempfile::tempdir().unwrap();
    glass_scene(small.path(), 4);
    let child = start(
        small.path(),
        &["--raytrace", "-o", "g.png", "--max-rays", "2000000"],
    );
    let (code, err, _) = finish(child, Duration::from_secs(60));
    assert_eq!(code, Some(0), "{err}");
    assert!(small.path().join("g.png").exists());
}

#[test]
fn ctrl_c_stops_a_ray_trace_within_a_second() {
    let dir = tempfile::tempdir().unwrap();
    glass_scene(dir.path(), 256);
    interrupted_within_a_second(
        dir.path(),
        &["--raytrace", "-o", "g.png"],
        "g.png",
        Duration::from_millis(1500),
    );
}

#[test]
fn ctrl_c_stops_a_hidden_line_drawing_within_a_second() {
    let dir = tempfile::tempdir().unwrap();
    tangle_scene(dir.path());
    interrupted_within_a_second(
        dir.path(),
        &["--hidden-line", "-o", "t.svg"],
        "t.svg",
        Duration::from_millis(1500),
    );
}
