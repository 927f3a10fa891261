//! Writes a wavy open sheet of about N triangles as a binary PLY, for the
//! big-mesh benchmark (`benches/big_mesh.sh`): a square grid of K x K
//! quads of two triangles (K = sqrt(N / 2)) over -1.5..1.5 in x and y,
//! its height a sum of two waves, so that seen from above nearly every
//! triangle faces the eye and the crests shadow the troughs:
//!
//!     cargo run --release --example sheet_ply -- 10000000 det/mesh.ply

use std::io::Write;

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(n), Some(path)) = (
        args.first().and_then(|a| a.parse::<f64>().ok()),
        args.get(1),
    ) else {
        eprintln!("usage: sheet_ply TRIANGLES OUT.ply");
        std::process::exit(2);
    };
    let k = ((n / 2.0).sqrt() as usize).max(1);
    let side = k + 1;
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(
        out,
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        side * side,
        2 * k * k
    )?;
    for i in 0..side {
        for j in 0..side {
            let x = -1.5 + 3.0 * i as f64 / k as f64;
            let y = -1.5 + 3.0 * j as f64 / k as f64;
            let z = 0.12 * (4.0 * x + 1.0).sin() * (3.0 * y).cos() + 0.05 * (9.0 * (x + y)).sin();
            for c in [x, y, z] {
                out.write_all(&(c as f32).to_le_bytes())?;
            }
        }
    }
    // Counter-clockwise seen from above (+z), as PLY lists faces.
    let at = |i: usize, j: usize| (i * side + j) as i32;
    for i in 0..k {
        for j in 0..k {
            for t in [
                [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
            ] {
                out.write_all(&[3])?;
                for v in t {
                    out.write_all(&v.to_le_bytes())?;
                }
            }
        }
    }
    out.flush()
}
