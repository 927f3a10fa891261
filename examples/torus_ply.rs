//! Writes a bumpy torus of about N triangles as a binary PLY, for the
//! big-mesh benchmark (`benches/big_mesh.sh`):
//!
//!     cargo run --release --example torus_ply -- 10000000 det/mesh.ply

use std::io::Write;

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(n), Some(path)) = (
        args.first().and_then(|a| a.parse::<f64>().ok()),
        args.get(1),
    ) else {
        eprintln!("usage: torus_ply TRIANGLES OUT.ply");
        std::process::exit(2);
    };
    // U x V quads of two triangles, U about 2.5 V.
    let v = ((n / 2.0 / 2.5).sqrt() as usize).max(3);
    let u = ((n / 2.0) as usize / v).max(3);
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(
        out,
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        u * v,
        2 * u * v
    )?;
    let tau = std::f64::consts::TAU;
    for i in 0..u {
        for j in 0..v {
            let (a, b) = (tau * i as f64 / u as f64, tau * j as f64 / v as f64);
            let r = 0.35 * (1.0 + 0.08 * (7.0 * a).sin() * (5.0 * b).sin());
            let p = [
                (1.0 + r * b.cos()) * a.cos(),
                (1.0 + r * b.cos()) * a.sin(),
                r * b.sin(),
            ];
            for c in p {
                out.write_all(&(c as f32).to_le_bytes())?;
            }
        }
    }
    let at = |i: usize, j: usize| ((i % u) * v + j % v) as i32;
    for half in 0..2 {
        for i in 0..u {
            for j in 0..v {
                let t = if half == 0 {
                    [at(i, j), at(i + 1, j), at(i + 1, j + 1)]
                } else {
                    [at(i, j), at(i + 1, j + 1), at(i, j + 1)]
                };
                out.write_all(&[3])?;
                for k in t {
                    out.write_all(&k.to_le_bytes())?;
                }
            }
        }
    }
    out.flush()
}
