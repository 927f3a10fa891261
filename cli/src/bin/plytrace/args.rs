//! The command line of `plytrace` (004 appendix B, the plytrace manual
//! page: `plytrace [-flags]`, the flags being the `setmode` letters).
//!
//! Parsed in two steps, as ripgrep does: clap reads the raw flags into
//! [`Cli`], one definition from which the help, the shell completions and
//! the man page are also made; [`Cli::settings`] then checks them together
//! and gives the [`Settings`] of a session.
//!
//! Two conventions of the manual are older than argument libraries and
//! are brought to clap's form by [`normalize`] first: the debugging level
//! is a bare digit (`-3`), and an on/off letter may stand alone
//! (`setmode <mode> [<on, off>]`: `-v` is `-v on`).

use std::ffi::OsString;
use std::path::PathBuf;

use clap::{ArgAction, CommandFactory, Parser, Subcommand};
use plytrace::api::Antialiasing as Method;
use plytrace::api::Budgets;
use plytrace::api::program::parts::PartSpec;
use plytrace::api::program::pipeline::{Algorithm, Refraction, ShadingModel};

use crate::settings::{
    Image, SceneSource, Settings, Shading, StatsTarget, StdoutFormat, check_id_image, check_part,
    image_path, output_flags, parse_aa, parse_frames, parse_part, parse_refraction, parse_size,
    parse_visibility, pixels_exceeded, positive,
};

const MANUAL: &str = "The manual's flags (the setmode letters; they override the scene)";
const OUTPUT: &str = "Output";
const RENDERING: &str = "Rendering";
const BUDGETS: &str = "Budgets (a run that would pass one stops, naming its flag)";

/// The on/off letters of `setmode` (004 appendix B, SETMODE COMMANDS).
const ON_OFF_LETTERS: &str = "bhnpsvx";

/// A word after an on/off letter that is the scene, not the letter's value
/// (`plytrace -v ccube.des`): a `.des` file.
fn is_scene_name(s: &str) -> bool {
    std::path::Path::new(s)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("des"))
}

/// plytrace: image rendering processor for 3-D polygonal environments.
#[derive(Debug, Parser)]
#[command(
    name = "plytrace",
    version,
    about = "Image rendering processor for 3-D polygonal environments",
    long_about = "Image rendering processor for 3-D polygonal environments: shadows, \
                  transparency, reflection and refraction by the virtual image tree \
                  (A. Garcia, MIT 1986).\n\n\
                  plytrace                  interactive: the prompt `Command:`\n\
                  plytrace scene.des        render scene.des to scene.png and exit\n\
                  plytrace -i -f scene.des  the same, in the manual's words\n\
                  plytrace - < scene.des    the scene from standard input",
    disable_help_flag = true,
    disable_version_flag = true,
    max_term_width = 80,
    args_conflicts_with_subcommands = true,
    subcommand_value_name = "TOOL",
    subcommand_help_heading = "Tools",
    disable_help_subcommand = true,
    args_override_self = true
)]
pub struct Cli {
    /// A tool instead of a render.
    #[command(subcommand)]
    pub tool: Option<Tool>,

    /// The scene descriptor file (`-` for standard input); immediate mode.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,

    /// Immediate mode: read the scene (-f), render it, exit.
    #[arg(short = 'i', help_heading = MANUAL)]
    pub immediate: bool,
    /// The scene descriptor file for immediate mode.
    #[arg(short = 'f', value_name = "FILE", help_heading = MANUAL)]
    pub file: Option<PathBuf>,
    /// Blend parent and child intensities in the tree (pre-blending).
    #[arg(short = 'b', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub b: Option<String>,
    /// Minimum screen detail size (default 0.0002).
    #[arg(short = 'd', value_name = "SIZE", allow_hyphen_values = true, help_heading = MANUAL)]
    pub d: Option<String>,
    /// Epsilon of the clipping operations (default 1e-7).
    #[arg(short = 'e', value_name = "EPS", allow_hyphen_values = true, help_heading = MANUAL)]
    pub e: Option<String>,
    /// Explicit shadow shades (off: an approximate reduction).
    #[arg(short = 'h', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub h: Option<String>,
    /// Deepest reflection/refraction level, 1 to 14 (default 1).
    #[arg(short = 'l', value_name = "1-14", allow_hyphen_values = true, help_heading = MANUAL)]
    pub l: Option<String>,
    /// Newell-Newell-Sancha sorting with face splitting (default on; off is
    /// the simple depth sort).
    #[arg(short = 'n', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub n: Option<String>,
    /// `on`/`off`: write the virtual image tree (FNAME.out, FNAME.txt).
    /// Any other value is the output image: .png, .ppm, .svg, .pdf, .tex,
    /// or `-` for standard output (with --format).
    #[arg(short = 'o', long = "output", value_name = "on|off|FILE",
          action = ArgAction::Append, help_heading = MANUAL)]
    pub o: Vec<String>,
    /// Bounding boxes only.
    #[arg(short = 'p', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub p: Option<String>,
    /// Phong highlight vectors at each vertex.
    #[arg(short = 's', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub s: Option<String>,
    /// Vertex shades (Gouraud) instead of one shade a polygon.
    #[arg(short = 'v', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub v: Option<String>,
    /// Expand all objects into one list before sorting.
    #[arg(short = 'x', value_name = "on|off", num_args = 0..=1,
          default_missing_value = "on", help_heading = MANUAL)]
    pub x: Option<String>,
    /// Debugging level 0 to 9 (the manual's -0 .. -9).
    #[arg(long = "debug", value_name = "0-9", value_parser = clap::value_parser!(u8).range(0..=9),
          help_heading = MANUAL)]
    pub debug: Option<u8>,

    /// Image size, overriding the scene's resolution (W x H at most 2^28).
    #[arg(long, value_name = "WxH", value_parser = parse_size, allow_hyphen_values = true, help_heading = OUTPUT)]
    pub size: Option<(u32, u32)>,
    /// The format of `-o -` (standard output).
    #[arg(long, value_enum, value_name = "FORMAT", help_heading = OUTPUT)]
    pub format: Option<StdoutFormat>,
    /// Also write the polygon seen at each pixel, in false colour (PNG).
    #[arg(long, value_name = "FILE.png", help_heading = OUTPUT)]
    pub id_image: Option<PathBuf>,
    /// Brown's hidden-line drawing: white faces, black visible edges
    /// (anti-aliased; only black and white with --aa none).
    #[arg(long, help_heading = OUTPUT, conflicts_with_all = ["raytrace", "supersample"])]
    pub hidden_line: bool,
    /// Let the scene's `fname` name files outside the working directory.
    #[arg(long, help_heading = OUTPUT)]
    pub allow_outside: bool,
    /// Statistics as one JSON object: `json` on standard error, or a file.
    #[arg(long, value_name = "json|FILE", help_heading = OUTPUT)]
    pub stats: Option<PathBuf>,
    /// Print only errors and warnings.
    #[arg(short = 'q', long, help_heading = OUTPUT)]
    pub quiet: bool,
    /// Print the run-time profile in the categories of table 6.2.
    #[arg(long, help_heading = OUTPUT)]
    pub profile: bool,
    /// Read and check the scene and its outputs; render nothing.
    #[arg(long, help_heading = OUTPUT)]
    pub check: bool,
    /// Render only part I of N horizontal bands (I from 0) into the part
    /// file that -o names; `plytrace merge` joins the parts. On a scene
    /// with several `run`s the parts are its frames (without -o).
    #[arg(long, value_name = "I/N", value_parser = parse_part, help_heading = OUTPUT)]
    pub part: Option<PartSpec>,
    /// Render only the frames (`run`s) A to B, counted from 0 over the
    /// whole scene: A..B, A.. or a single A.
    #[arg(long, value_name = "A..B", value_parser = parse_frames, help_heading = OUTPUT)]
    pub frames: Option<(u32, u32)>,

    /// Visible-surface algorithm (default nns).
    #[arg(long, value_name = "ALG", value_parser = parse_visibility, help_heading = RENDERING)]
    pub visibility: Option<Algorithm>,
    /// Scan conversion: none (point sampled), area, mask, hybrid,
    /// multilevel, or 1 to 4 (default: the best for the scene).
    #[arg(long, value_name = "METHOD", value_parser = parse_aa, help_heading = RENDERING)]
    pub aa: Option<Method>,
    /// Donovan's N x N samples a pixel (1 to 16); N x N rays with --raytrace.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16),
          conflicts_with = "aa", help_heading = RENDERING)]
    pub supersample: Option<u32>,
    /// Render with the Whitted ray tracer (same scene, exact optics).
    #[arg(long, conflicts_with_all = ["visibility", "aa"], help_heading = RENDERING)]
    pub raytrace: bool,
    /// Refraction model: linearized, orthographic, paraxial, exact, auto.
    #[arg(long, value_name = "MODEL", value_parser = parse_refraction, help_heading = RENDERING)]
    pub refraction: Option<Refraction>,
    /// Illumination model: garcia (section 4.8) or donovan (section 6).
    #[arg(long, value_enum, value_name = "MODEL", help_heading = RENDERING)]
    pub shading: Option<Shading>,
    /// Render without shadows (the manual's `run n`; immediate mode is `run y`).
    #[arg(long, help_heading = RENDERING)]
    pub no_shadows: bool,
    /// Worker threads (default: all cores); the image does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024),
          allow_hyphen_values = true, help_heading = RENDERING)]
    pub threads: Option<u32>,

    /// Polygons in the scene, read and generated.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_polygons: Option<u64>,
    /// Nesting of `call`.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_call_depth: Option<u64>,
    /// Fragments of the virtual image tree.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_tree_nodes: Option<u64>,
    /// Face splits of one NNS sort.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_splits: Option<u64>,
    /// Pixels of one image.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_pixels: Option<u64>,
    /// Times the records may cover the image over (default 4096).
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_overdraw: Option<u64>,
    /// Pair tests of one modeling operation: CSG, outline checks.
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_pair_tests: Option<u64>,
    /// MiB of one generated object's vertices and polygons (default 1024).
    #[arg(long, value_name = "MiB", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_model_memory: Option<u64>,
    /// MiB of a whole frame held in memory (default 1024).
    #[arg(long, value_name = "MiB", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_frame_memory: Option<u64>,
    /// Rays of one ray-traced render, shadow rays included (default
    /// 50000000).
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_rays: Option<u64>,
    /// Pixel samples of one z-buffer, scan-line or brown painting,
    /// estimated before it (default 10000000000).
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_samples: Option<u64>,
    /// Polygon-window tests of one warnock render (default 400000000).
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_window_tests: Option<u64>,
    /// Ray-polygon tests of one ray-cast render (default 300000000).
    #[arg(long, value_name = "N", value_parser = positive, allow_hyphen_values = true,
          help_heading = BUDGETS)]
    pub max_ray_tests: Option<u64>,

    /// Print the help (-h is the manual's shadow-shade flag).
    #[arg(long, action = ArgAction::SetTrue)]
    pub help: bool,
    /// Print the version.
    #[arg(short = 'V', long, action = ArgAction::SetTrue)]
    pub version: bool,
}

/// What `plytrace TOOL ...` runs instead of a render.
#[derive(Debug, Subcommand)]
pub enum Tool {
    /// Convert an ASCII object file to binary (the manual's mkdet).
    #[command(disable_help_flag = true)]
    Mkdet {
        /// INPUT OUTPUT, as the manual's synopsis.
        #[arg(num_args = 0.., allow_hyphen_values = true, trailing_var_arg = true)]
        args: Vec<String>,
    },
    /// Convert an ASCII polygon colour file to binary (mkpcl).
    #[command(disable_help_flag = true)]
    Mkpcl {
        /// INPUT OUTPUT.
        #[arg(num_args = 0.., allow_hyphen_values = true, trailing_var_arg = true)]
        args: Vec<String>,
    },
    /// Convert an ASCII vertex colour file to binary (mkvcl).
    #[command(disable_help_flag = true)]
    Mkvcl {
        /// INPUT OUTPUT.
        #[arg(num_args = 0.., allow_hyphen_values = true, trailing_var_arg = true)]
        args: Vec<String>,
    },
    /// Check Brown's Angle and Edge Conditions of a triangulated surface.
    Tessellation {
        /// The object file (.det, .obj, .ply, .stl).
        file: PathBuf,
    },
    /// C0/C1 continuity between adjacent bicubic patches.
    Continuity {
        /// A .bpt (Bezier) or .hpt (Hermite) patch file.
        file: PathBuf,
        /// The patch form, when the extension does not say it.
        form: Option<String>,
    },
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff; `plytrace man | man -l -`).
    Man,
    /// Merge the part files of `--part I/N` into the image, or list the
    /// parts still missing.
    Merge {
        /// The part files (any order).
        #[arg(value_name = "PART")]
        parts: Vec<PathBuf>,
        /// The image: .png, .ppm, or the seed of the separations
        /// (default: the name the parts give).
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
        /// Write the colour separations OUTPUT.r, .g, .b instead.
        #[arg(long)]
        separations: bool,
        /// Print the indices of the parts not given (comma-separated, for
        /// a job array) instead of merging.
        #[arg(long, conflicts_with_all = ["output", "separations"])]
        missing: bool,
        /// With --missing: the part count, when no part is there yet.
        #[arg(long, value_name = "N", requires = "missing",
              value_parser = clap::value_parser!(u32).range(1..=65536))]
        count: Option<u32>,
        /// The most pixels the parts' image may have (default 2^30).
        #[arg(long, value_name = "N", value_parser = positive)]
        max_pixels: Option<u64>,
    },
}

/// What the command line asks for.
pub enum Request {
    /// A session: immediate, interactive or a check.
    Run(Box<Settings>),
    /// A tool.
    Tool(Tool),
    /// `--help`.
    Help,
    /// `--version`.
    Version,
}

/// The clap command with its long help's closing sections.
pub fn command() -> clap::Command {
    Cli::command().after_long_help(crate::help::after_help())
}

/// Parses the arguments (without the program name). The long help's
/// closing sections are left out: only `--help`, the man page and the
/// completions show them, and wrapping the command table took longer
/// than the parse.
pub fn parse(args: Vec<OsString>) -> Result<Request, clap::Error> {
    let mut cmd = Cli::command();
    let normalized = normalize(&cmd, args);
    let matches = cmd
        .try_get_matches_from_mut(std::iter::once(OsString::from("plytrace")).chain(normalized))?;
    let cli = <Cli as clap::FromArgMatches>::from_arg_matches(&matches)
        .map_err(|e| e.format(&mut cmd))?;
    if cli.help {
        return Ok(Request::Help);
    }
    if cli.version {
        return Ok(Request::Version);
    }
    if let Some(tool) = cli.tool {
        return Ok(Request::Tool(tool));
    }
    cli.settings()
        .map(|s| Request::Run(Box::new(s)))
        .map_err(|message| cmd.error(clap::error::ErrorKind::ArgumentConflict, message))
}

/// The manual's bare forms brought to clap's: `-3` becomes `--debug=3`,
/// and an on/off letter followed by nothing, by a flag or by a scene file
/// becomes `-v=on` (any other word is its value, checked later).
/// Values of flags that take one are left alone, and so is everything
/// after `--` or after a tool's name.
pub fn normalize(cmd: &clap::Command, args: Vec<OsString>) -> Vec<OsString> {
    let takes_value = |token: &str| -> bool {
        cmd.get_arguments().any(|a| {
            let by_short =
                token.len() == 2 && token.starts_with('-') && a.get_short() == token.chars().nth(1);
            let by_long = token
                .strip_prefix("--")
                .is_some_and(|l| a.get_long() == Some(l));
            (by_short || by_long) && a.get_action().takes_values()
        })
    };
    let tools: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_string())
        .collect();
    let mut out = Vec::with_capacity(args.len());
    let mut it = args.into_iter().peekable();
    while let Some(arg) = it.next() {
        let Some(text) = arg.to_str().map(str::to_string) else {
            out.push(arg);
            continue;
        };
        let letter = (text.len() == 2 && text.starts_with('-'))
            .then(|| text.chars().nth(1))
            .flatten();
        match letter {
            _ if text == "--" || tools.contains(&text) => {
                out.push(arg);
                out.extend(it);
                return out;
            }
            Some(d) if d.is_ascii_digit() => out.push(format!("--debug={d}").into()),
            Some(l) if ON_OFF_LETTERS.contains(l) => {
                let valued = it
                    .peek()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| !n.starts_with('-') && !is_scene_name(n));
                if valued {
                    out.push(arg);
                    out.extend(it.next());
                } else {
                    out.push(format!("-{l}=on").into());
                }
            }
            _ if takes_value(&text) => {
                out.push(arg);
                out.extend(it.next());
            }
            _ => out.push(arg),
        }
    }
    out
}

impl Cli {
    /// Checks the flags together: what one flag alone cannot say.
    fn settings(self) -> Result<Settings, String> {
        let mut modes = self.modes();
        let (tree, image) = output_flags(&self.o)?;
        if let Some(t) = tree {
            modes.push(('o', t));
        }
        let image = self.image(image)?;
        let scene = self.scene_source()?;
        let immediate = self.immediate || scene != SceneSource::None && self.file.is_none();
        let immediate = immediate || self.check || matches!(scene, SceneSource::Stdin);
        let budgets = self.budgets();
        self.check_together(immediate, &scene, &image, &budgets)?;
        let aa = match (self.aa, self.supersample) {
            (_, Some(n)) => Some(Method::Supersample(n)),
            (aa, None) => aa,
        };
        Ok(Settings {
            immediate,
            scene,
            modes,
            image,
            size: self.size,
            id_image: self.id_image,
            visibility: self.visibility,
            profile: self.profile,
            refraction: self.refraction.unwrap_or_default(),
            aa,
            threads: self.threads.map_or(0, |n| n as usize),
            shading: match self.shading {
                Some(Shading::Donovan) => ShadingModel::Donovan,
                _ => ShadingModel::Garcia,
            },
            quiet: self.quiet,
            allow_outside: self.allow_outside,
            budgets,
            hidden_line: self.hidden_line,
            raytrace: self.raytrace,
            shadows: !self.no_shadows,
            check: self.check,
            part: self.part,
            frames: self.frames,
            stats: self.stats.map(|p| {
                if p.as_os_str().eq_ignore_ascii_case("json") {
                    StatsTarget::Stderr
                } else {
                    StatsTarget::File(p)
                }
            }),
        })
    }

    /// The `setmode` letters given, and the debugging level as `(digit, "")`.
    fn modes(&self) -> Vec<(char, String)> {
        let letters = [
            ('b', &self.b),
            ('d', &self.d),
            ('e', &self.e),
            ('h', &self.h),
            ('l', &self.l),
            ('n', &self.n),
            ('p', &self.p),
            ('s', &self.s),
            ('v', &self.v),
            ('x', &self.x),
        ];
        let mut modes: Vec<(char, String)> = letters
            .into_iter()
            .filter_map(|(letter, value)| value.clone().map(|v| (letter, v)))
            .collect();
        if let Some(d) = self.debug {
            modes.push((char::from(b'0' + d), String::new()));
        }
        modes
    }

    /// Where the image goes: `-o` with `--format` for standard output.
    fn image(&self, image: Option<PathBuf>) -> Result<Image, String> {
        Ok(match (image, self.format) {
            (Some(p), Some(f)) if p.as_os_str() == "-" => Image::Stdout(f),
            (Some(p), None) if p.as_os_str() == "-" => Image::Stdout(StdoutFormat::Png),
            (_, Some(_)) => {
                return Err("--format is for `-o -` (standard output); \
                     a file's format is chosen by its extension"
                    .into());
            }
            (Some(p), None) => Image::File(image_path(p)?),
            (None, None) => Image::Default,
        })
    }

    /// The flags that go together only in some ways: the modes, the
    /// image's place and size, the id image, parts and `--hidden-line`.
    fn check_together(
        &self,
        immediate: bool,
        scene: &SceneSource,
        image: &Image,
        budgets: &Budgets,
    ) -> Result<(), String> {
        if immediate && *scene == SceneSource::None {
            return Err("immediate mode (-i) needs a scene file: plytrace -i -f scene.des".into());
        }
        if !immediate && matches!(image, Image::Stdout(_)) {
            return Err(
                "`-o -` (the image to standard output) is for immediate mode: \
                 plytrace scene.des -o -"
                    .into(),
            );
        }
        if self.check && *scene == SceneSource::None {
            return Err("--check needs a scene file: plytrace --check scene.des".into());
        }
        if let Some((w, h)) = self.size
            && u64::from(w) * u64::from(h) > budgets.pixels
        {
            return Err(pixels_exceeded(w, h, budgets.pixels));
        }
        if let Some(id) = &self.id_image {
            check_id_image(id, image, self.hidden_line)?;
        }
        if let Some(spec) = self.part {
            let refused = [
                (self.id_image.is_some(), "--id-image"),
                (self.hidden_line, "--hidden-line"),
                (self.raytrace, "--raytrace"),
            ];
            check_part(spec, image, &refused)?;
        }
        if self.hidden_line
            && let Some(aa) = self.aa.filter(|&m| m != Method::Point)
        {
            return Err(format!(
                "--hidden-line draws its lines anti-aliased, or only black and white with \
                 --aa none; it does not go with --aa {}",
                format!("{aa:?}").to_lowercase()
            ));
        }
        Ok(())
    }

    /// The scene: `-f FILE`, a lone `SCENE` (`-` for standard input), or
    /// none (the interactive session).
    fn scene_source(&self) -> Result<SceneSource, String> {
        match (&self.scene, &self.file) {
            (Some(p), Some(f)) => Err(format!(
                "two scene files: `{}` and -f `{}`; give one",
                p.display(),
                f.display()
            )),
            (Some(p), None) | (None, Some(p)) if p.as_os_str() == "-" => Ok(SceneSource::Stdin),
            (Some(p), None) | (None, Some(p)) => Ok(SceneSource::File(p.clone())),
            (None, None) => Ok(SceneSource::None),
        }
    }

    fn budgets(&self) -> Budgets {
        let mut b = Budgets::default();
        let size = |n: u64| usize::try_from(n).unwrap_or(usize::MAX);
        if let Some(n) = self.max_polygons {
            b.polygons = size(n);
        }
        if let Some(n) = self.max_call_depth {
            b.call_depth = size(n);
        }
        if let Some(n) = self.max_tree_nodes {
            b.tree_nodes = size(n);
        }
        if let Some(n) = self.max_splits {
            b.splits = size(n);
        }
        if let Some(n) = self.max_pixels {
            b.pixels = n;
        }
        if let Some(n) = self.max_overdraw {
            b.overdraw = n;
        }
        if let Some(n) = self.max_frame_memory {
            b.frame_memory = n.saturating_mul(1 << 20);
        }
        if let Some(n) = self.max_pair_tests {
            b.pair_tests = n;
        }
        if let Some(n) = self.max_model_memory {
            b.model_memory = n.saturating_mul(1 << 20);
        }
        if let Some(n) = self.max_rays {
            b.rays = n;
        }
        if let Some(n) = self.max_samples {
            b.samples = n;
        }
        if let Some(n) = self.max_window_tests {
            b.window_tests = n;
        }
        if let Some(n) = self.max_ray_tests {
            b.ray_tests = n;
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<OsString> {
        s.split_whitespace().map(OsString::from).collect()
    }

    fn normalized(s: &str) -> Vec<String> {
        normalize(&command(), words(s))
            .into_iter()
            .map(|o| o.into_string().unwrap())
            .collect()
    }

    #[test]
    fn the_manuals_bare_forms_become_clap_forms() {
        assert_eq!(
            normalized("-i -v -f ccube.des -3"),
            ["-i", "-v=on", "-f", "ccube.des", "--debug=3"]
        );
        assert_eq!(
            normalized("-n off -v ccube.des"),
            ["-n", "off", "-v=on", "ccube.des"]
        );
        // A value is never rewritten, nor what follows a tool's name.
        assert_eq!(normalized("-f -v -e -3"), ["-f", "-v", "-e", "-3"]);
        assert_eq!(normalized("mkdet -v -3"), ["mkdet", "-v", "-3"]);
        assert_eq!(normalized("--size 8x8 -h"), ["--size", "8x8", "-h=on"]);
        assert_eq!(normalized("-n maybe"), ["-n", "maybe"]);
    }

    #[test]
    fn the_definition_is_consistent() {
        command().debug_assert();
    }
}
