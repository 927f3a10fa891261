//! The checked settings of a session (the command line's flags taken
//! together, [`crate::args`]'s result) and the checks of single values:
//! sizes, parts, frames, methods, the outputs' names.

use std::path::PathBuf;

use clap::ValueEnum;
use plytrace::api::Antialiasing as Method;
use plytrace::api::program::files::check_image_extension;
use plytrace::api::program::parts::PartSpec;
use plytrace::api::program::pipeline::{Algorithm, Refraction, ShadingModel};
use plytrace::api::{Budgets, VectorFormat};

/// `--format` of `-o -`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StdoutFormat {
    /// PNG (the default).
    Png,
    /// Binary PPM.
    Ppm,
    /// SVG.
    Svg,
    /// One-page PDF.
    Pdf,
    /// TikZ.
    Tex,
}

impl StdoutFormat {
    /// The extension the renderer chooses the format by.
    pub fn extension(self) -> &'static str {
        match self {
            StdoutFormat::Png => "png",
            StdoutFormat::Ppm => "ppm",
            StdoutFormat::Svg => "svg",
            StdoutFormat::Pdf => "pdf",
            StdoutFormat::Tex => "tex",
        }
    }
}

/// `--shading`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Shading {
    /// Garcia's model (004 section 4.8).
    Garcia,
    /// Donovan's model (000 section 6).
    Donovan,
}

/// Where the image goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Image {
    /// FNAME.png (from the scene's `fname`, else the scene file's name).
    Default,
    /// A file named on the command line.
    File(PathBuf),
    /// Standard output, in this format.
    Stdout(StdoutFormat),
}

/// Where the scene comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SceneSource {
    /// None: the interactive session reads commands.
    None,
    /// A file.
    File(PathBuf),
    /// Standard input (`plytrace -`).
    Stdin,
}

/// Where the statistics go as JSON.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StatsTarget {
    /// Standard error.
    Stderr,
    /// A file.
    File(PathBuf),
}

/// The checked settings of a session.
#[derive(Debug)]
pub struct Settings {
    pub immediate: bool,
    pub scene: SceneSource,
    /// `setmode` letters and values to force (`(digit, "")` for a level).
    pub modes: Vec<(char, String)>,
    pub image: Image,
    pub size: Option<(u32, u32)>,
    pub id_image: Option<PathBuf>,
    pub visibility: Option<Algorithm>,
    pub profile: bool,
    pub refraction: Refraction,
    pub aa: Option<Method>,
    pub threads: usize,
    pub shading: ShadingModel,
    pub quiet: bool,
    pub allow_outside: bool,
    pub budgets: Budgets,
    pub hidden_line: bool,
    pub raytrace: bool,
    pub shadows: bool,
    pub check: bool,
    pub stats: Option<StatsTarget>,
    pub part: Option<PartSpec>,
    pub frames: Option<(u32, u32)>,
}

/// The values of `-o`: at most one `on`/`off` (the tree) and at most one
/// image name.
pub fn output_flags(values: &[String]) -> Result<(Option<String>, Option<PathBuf>), String> {
    let mut tree: Option<&String> = None;
    let mut image: Option<&String> = None;
    for v in values {
        let slot = if matches!(v.to_ascii_lowercase().as_str(), "on" | "off") {
            &mut tree
        } else {
            &mut image
        };
        if let Some(first) = slot.replace(v) {
            return Err(format!(
                "-o `{first}` and -o `{v}`: give one {}",
                if first.eq_ignore_ascii_case("on") || first.eq_ignore_ascii_case("off") {
                    "tree setting"
                } else {
                    "output image"
                }
            ));
        }
    }
    Ok((tree.cloned(), image.map(PathBuf::from)))
}

/// An output image named on the command line: its format must be one
/// that is written.
pub fn image_path(p: PathBuf) -> Result<PathBuf, String> {
    if VectorFormat::from_path(&p).is_some() {
        return Ok(p);
    }
    check_image_extension(&p)
        .map_err(|e| format!("{e}, and the vector formats .svg, .pdf and .tex"))?;
    Ok(p)
}

pub fn check_id_image(
    id: &std::path::Path,
    image: &Image,
    hidden_line: bool,
) -> Result<(), String> {
    if !id
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(format!(
            "--id-image: {}: the id image is written as PNG only; name it .png",
            id.display()
        ));
    }
    let vector = match image {
        Image::File(p) => VectorFormat::from_path(p).is_some(),
        Image::Stdout(f) => matches!(f, StdoutFormat::Svg | StdoutFormat::Pdf | StdoutFormat::Tex),
        Image::Default => false,
    };
    if vector || hidden_line {
        return Err(
            "--id-image is made from the shaded PNG; it cannot go with vector output or \
             --hidden-line"
                .into(),
        );
    }
    if *image == Image::File(id.to_path_buf()) {
        return Err("the image and --id-image name the same file".into());
    }
    Ok(())
}

/// The largest image, in pixels, whatever the budget: 2^28.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

/// `--size WxH`: each side 1 to 65536, and W x H at most 2^28.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let form = || format!("expected WxH, two whole numbers such as 1024x768, found `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(form)?;
    let side = |v: &str| -> Result<u32, String> {
        match v.trim().parse::<u32>() {
            Ok(n @ 1..=65536) => Ok(n),
            Ok(n) => Err(format!("each side must be 1 to 65536, found {n}")),
            Err(_) => Err(form()),
        }
    };
    let (w, h) = (side(w)?, side(h)?);
    let pixels = u64::from(w) * u64::from(h);
    if pixels > MAX_IMAGE_PIXELS {
        return Err(format!(
            "{w} x {h} = {pixels} pixels is more than an image may have \
             (W x H at most 2^28 = {MAX_IMAGE_PIXELS})"
        ));
    }
    Ok((w, h))
}

/// `--part`: what a part needs, checked with the other flags.
/// `refused` are the flags given that a part does not go with (`--id-image`,
/// `--hidden-line`, `--raytrace`).
pub fn check_part(spec: PartSpec, image: &Image, refused: &[(bool, &str)]) -> Result<(), String> {
    // Without -o: an animation's parts are frames, named by their runs;
    // a one-run scene is told to name its part file once it is read.
    let named = match image {
        Image::File(p) => p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")),
        Image::Default => true,
        Image::Stdout(_) => false,
    };
    if !named {
        return Err(format!(
            "--part {spec} writes a part file (PNG): name it with -o, such as \
             -o parts/{}.png",
            spec.index
        ));
    }
    if let Some((_, flag)) = refused.iter().find(|(on, _)| *on) {
        return Err(format!(
            "--part splits the scan conversion of the virtual image tree; it does not go \
             with {flag}"
        ));
    }
    Ok(())
}

/// `--part I/N`.
pub fn parse_part(v: &str) -> Result<PartSpec, String> {
    v.parse()
}

/// `--frames A..B`, `A..` or `A`: the first and last frame, from 0.
pub fn parse_frames(v: &str) -> Result<(u32, u32), String> {
    let form = || format!("expected A..B, A.. or A (frames from 0), such as 10..19, found `{v}`");
    let number = |s: &str| s.trim().parse::<u32>().map_err(|_| form());
    let (a, b) = match v.split_once("..") {
        Some((a, "")) => (number(a)?, u32::MAX),
        Some((a, b)) => (number(a)?, number(b.trim_start_matches('='))?),
        None => (number(v)?, number(v)?),
    };
    if b < a {
        return Err(format!(
            "--frames {v}: the last frame comes before the first"
        ));
    }
    Ok((a, b))
}

pub fn parse_aa(v: &str) -> Result<Method, String> {
    Ok(match v.to_ascii_lowercase().as_str() {
        "none" | "point" | "0" => Method::Point,
        "area" | "1" => Method::Area,
        "mask" | "2" => Method::Mask,
        "hybrid" | "3" => Method::Hybrid,
        "multilevel" | "4" => Method::Multilevel,
        _ => return Err("expected none, area, mask, hybrid, multilevel or 1 to 4".into()),
    })
}

pub fn parse_visibility(v: &str) -> Result<Algorithm, String> {
    v.parse()
}

pub fn parse_refraction(v: &str) -> Result<Refraction, String> {
    v.parse()
}

pub fn positive(v: &str) -> Result<u64, String> {
    v.parse::<u64>()
        .ok()
        .filter(|n| *n >= 1)
        .ok_or_else(|| "expected a whole number of at least 1".into())
}

/// The name standard input goes by in messages and statistics.
pub const STDIN: &str = "<stdin>";

/// The message of an image over the pixel budget.
pub fn pixels_exceeded(w: u32, h: u32, limit: u64) -> String {
    Budgets::exceeded(
        &format!(
            "the image of {w} x {h} = {} pixels",
            u64::from(w) * u64::from(h)
        ),
        limit,
        "--max-pixels",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("1024x768"), Ok((1024, 768)));
        assert!(parse_size("20000x20000").unwrap_err().contains("2^28"));
        assert!(parse_size("0x10").unwrap_err().contains("1 to 65536"));
        assert!(parse_size("axb").unwrap_err().contains("expected WxH"));
        assert_eq!(parse_size("65536x4096"), Ok((65536, 4096)));
    }
}
