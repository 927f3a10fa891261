//! The library from Rust: a cube and a light built from arrays, rendered
//! to `cube.png` and `cube.svg` in the working directory.
//!
//!     cargo run --release --example api_cube

use plytrace::api::{Camera, Light, Material, MeshData, Options, Scene, VectorFormat};

fn main() -> Result<(), plytrace::Error> {
    let cube = MeshData::new(
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
    );
    let mut scene = Scene::new(Camera::looking_at([4., -6., 3.], [0., 0., 0.]), 256, 256);
    scene.add_light(Light::point([5., -5., 8.], [1., 1., 1.]))?;
    scene.add_mesh("cube", &cube, &Material::color([0.2, 0.6, 1.0]))?;
    let image = plytrace::api::render(&scene, &Options::default())?;
    std::fs::write("cube.png", image.to_png()?)
        .map_err(|e| plytrace::Error::io("cube.png".as_ref(), e))?;
    let svg = plytrace::api::render_vector(&scene, &Options::default(), VectorFormat::Svg)?;
    std::fs::write("cube.svg", svg).map_err(|e| plytrace::Error::io("cube.svg".as_ref(), e))?;
    Ok(())
}
