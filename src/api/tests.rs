//! Unit tests of `api`.

use super::*;

fn square() -> MeshData {
    MeshData::new(
        vec![[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]],
        vec![vec![0, 1, 2, 3]],
    )
}

#[test]
fn bad_arrays_are_refused_with_the_reason() {
    let mut m = square();
    m.vertices[2][1] = f64::NAN;
    assert!(
        m.validate()
            .unwrap_err()
            .to_string()
            .contains("vertex 2 is not finite")
    );
    let mut m = square();
    m.faces[0][3] = 9;
    assert!(
        m.validate()
            .unwrap_err()
            .to_string()
            .contains("names vertex 9, but there are 4")
    );
    let mut m = square();
    m.faces.push(vec![0, 1]);
    assert!(
        m.validate()
            .unwrap_err()
            .to_string()
            .contains("face 1 has 2 vertices")
    );
    let mut m = square();
    m.face_colors = Some(vec![]);
    assert!(
        m.validate()
            .unwrap_err()
            .to_string()
            .contains("0 colours for 1 faces")
    );
}

#[test]
fn a_square_seen_from_above_fills_the_middle_in_its_colour() {
    let mut camera = Camera::looking_at([0., 0., 5.], [0., 0., 0.]);
    camera.up = [0., 1., 0.];
    let mut scene = Scene::new(camera, 32, 32);
    scene.set_ambient([1., 1., 1.]).unwrap();
    let mut red = Material::color([1., 0., 0.]);
    red.surface.diffuse = 0.0;
    scene.add_mesh("square", &square(), &red).unwrap();
    let image = render(&scene, &Options::default()).unwrap();
    let centre = ((16 * 32 + 16) * 3) as usize;
    // Ambient only: k_a = 1 - k_d = 1, the colour itself.
    assert_eq!(&image.rgb[centre..centre + 3], &[255, 0, 0]);
    assert_eq!(&image.rgb[0..3], &[0, 0, 0], "the corner is background");
    // Seen from behind, a one-sided square is culled; two-sided it shows.
    camera.eye = [0., 0., -5.];
    let mut back = Scene::new(camera, 32, 32);
    back.add_mesh("square", &square(), &red).unwrap();
    let culled = render(&back, &Options::default()).unwrap();
    assert_eq!(&culled.rgb[centre..centre + 3], &[0, 0, 0]);
    red.two_sided = true;
    let mut back = Scene::new(camera, 32, 32);
    back.add_mesh("square", &square(), &red).unwrap();
    let shown = render(&back, &Options::default()).unwrap();
    assert_ne!(&shown.rgb[centre..centre + 3], &[0, 0, 0]);
}

/// The unit cube, counter-clockwise faces; the top (z = +1) is face 1.
fn cube() -> MeshData {
    MeshData::new(
        vec![
            [-1., -1., -1.],
            [1., -1., -1.],
            [1., 1., -1.],
            [-1., 1., -1.],
            [-1., -1., 1.],
            [1., -1., 1.],
            [1., 1., 1.],
            [-1., 1., 1.],
        ],
        vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![2, 3, 7, 6],
            vec![1, 2, 6, 5],
            vec![0, 4, 7, 3],
        ],
    )
}

#[test]
fn counter_clockwise_faces_face_out_and_z_is_up() {
    let mut mesh = cube();
    let mut colors = vec![[0., 0., 1.]; 6];
    colors[1] = [1., 0., 0.];
    mesh.face_colors = Some(colors);
    let mut material = Material::default();
    material.surface.diffuse = 0.0;
    let pixel = |up: [f64; 3], x: usize, y: usize| {
        let mut camera = Camera::looking_at([3., -5., 6.], [0., 0., 0.]);
        camera.up = up;
        let mut scene = Scene::new(camera, 40, 40);
        scene.add_mesh("cube", &mesh, &material).unwrap();
        let image = render(&scene, &Options::default()).unwrap();
        let i = (y * 40 + x) * 3;
        [image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]]
    };
    let red = |p: [u8; 3]| p[0] > 200 && p[1] == 0 && p[2] < 30;
    let blue = |p: [u8; 3]| p[2] > 200 && p[0] < 30 && p[1] == 0;
    // Above the centre the red top is seen; below it a blue side.
    assert!(
        red(pixel([0., 0., 1.], 20, 12)),
        "{:?}",
        pixel([0., 0., 1.], 20, 12)
    );
    assert!(
        blue(pixel([0., 0., 1.], 20, 28)),
        "{:?}",
        pixel([0., 0., 1.], 20, 28)
    );
    // Upside down, the top is below the centre.
    assert!(
        red(pixel([0., 0., -1.], 20, 28)),
        "{:?}",
        pixel([0., 0., -1.], 20, 28)
    );
}

#[test]
fn a_scene_from_text_renders_like_the_program() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join("ccube.des")).unwrap();
    let scene = Scene::from_text(&text, &dir).unwrap();
    let options = Options {
        size: Some((48, 48)),
        ..Options::default()
    };
    let image = render(&scene, &options).unwrap();
    let from_file = render(&Scene::from_file(&dir.join("ccube.des")).unwrap(), &options).unwrap();
    assert_eq!(image.rgb, from_file.rgb);
    assert!(image.stats.polygons_tiled > 0);
}

#[test]
fn a_scene_text_refuses_what_the_same_file_refuses() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let dir = tempfile::tempdir().unwrap();
    for (text, refused) in [
        ("defobj cube\n", true),
        ("lookat 0 0 6 0 0 0 0\ndefobj cube\ncolor 1 0 0\n", true),
        ("defobj cube\nendobj\n", false),
        // `quit` ends the input early, as in a file.
        ("defobj cube\nquit\n", false),
    ] {
        let file = dir.path().join("scene.des");
        std::fs::write(&file, text).unwrap();
        std::fs::create_dir_all(dir.path().join("det")).unwrap();
        std::fs::copy(
            examples.join("det/cube.det"),
            dir.path().join("det/cube.det"),
        )
        .unwrap();
        let from_text = Scene::from_text(text, dir.path());
        let from_file = Scene::from_file(&file);
        assert_eq!(from_text.is_err(), refused, "{text:?}");
        assert_eq!(from_file.is_err(), refused, "{text:?}");
        if let (Err(a), Err(b)) = (from_text, from_file) {
            let (a, b) = (a.diagnostic().unwrap(), b.diagnostic().unwrap());
            assert_eq!(a.message, b.message);
            assert_eq!(
                (a.location.line, a.location.column),
                (b.location.line, b.location.column)
            );
        }
    }
    let long = "# \n".repeat(crate::scene::interpreter::MAX_SCENE_BYTES as usize / 3 + 1);
    let e = Scene::from_text(&long, dir.path()).unwrap_err().to_string();
    assert!(e.contains("more than the 16777216 bytes"), "{e}");
}

#[test]
fn lights_materials_and_colours_that_are_not_finite_are_refused() {
    let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 8, 8);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut light = Light::point([0., -5., 0.], [1., 1., 1.]);
        light.range = bad;
        assert!(scene.add_light(light).is_err());
        light.range = 10.0;
        light.position[1] = bad;
        assert!(scene.add_light(light).is_err());
        light.position[1] = 0.0;
        light.color[2] = bad;
        assert!(scene.add_light(light).is_err());
        for field in 0..8 {
            let mut m = Material::default();
            let s = &mut m.surface;
            *[
                &mut s.diffuse,
                &mut s.specular,
                &mut s.shininess,
                &mut s.reflectance,
                &mut s.transmittance,
                &mut s.index,
                &mut s.transparency.0,
                &mut s.transparency.1,
            ][field] = bad;
            assert!(scene.add_mesh("m", &square(), &m).is_err(), "{field} {bad}");
        }
        assert!(scene.set_background([0., bad, 0.]).is_err());
        assert!(scene.set_ambient([bad, 0., 0.]).is_err());
    }
    assert!(scene.inner.lights.is_empty() && scene.inner.objects.is_empty());
    assert!(scene.add_mesh("m", &square(), &Material::default()).is_ok());
}

#[test]
fn sizes_beyond_the_program_s_are_refused_and_frames_over_the_budget_before_rendering() {
    let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 8, 8);
    for size in [(0, 1), (1, 0), (65537, 1), (20000, 20000)] {
        let options = Options {
            size: Some(size),
            ..Options::default()
        };
        assert!(render(&scene, &options).is_err(), "{size:?}");
        assert!(
            render_vector(&scene, &options, VectorFormat::Svg).is_err(),
            "{size:?}"
        );
    }
    let mut options = Options {
        size: Some((1024, 1024)),
        ..Options::default()
    };
    options.budgets.frame_memory = 1 << 20;
    let e = render(&scene, &options).unwrap_err().to_string();
    assert!(
        e.contains("3 MiB") && e.contains("--max-frame-memory"),
        "{e}"
    );
}
