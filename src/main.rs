//! The `plytrace` program: the command interpreter and immediate mode of
//! Garcia 1986 (004 appendix, plytrace manual page), and the `mkdet`,
//! `mkpcl`, `mkvcl` converters. A thin layer over the library: argument
//! parsing, terminal input, messages and exit codes.
//!
//! The arguments are parsed by hand because the manual's flags are unusual
//! for an argument library: every `setmode` letter is a flag taking its
//! value as the next word (`-n on`, `-l 3`), and the debugging level is a
//! bare digit (`-3`).

use std::io::{BufRead, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use plytrace::error::{Error, Result};
use plytrace::output;
use plytrace::render::{self, RenderOptions};
use plytrace::scene::commands::COMMANDS;
use plytrace::scene::object_file::{self, ConvertKind};
use plytrace::scene::{Flow, Host, Interpreter, Scene};
use plytrace::visibility::Algorithm;

const VERSION: &str = env!("CARGO_PKG_VERSION");

#[derive(Debug, Default)]
struct Options {
    immediate: bool,
    scene: Option<PathBuf>,
    modes: Vec<(char, String)>,
    output: Option<PathBuf>,
    size: Option<(u32, u32)>,
    id_image: Option<PathBuf>,
    visibility: Option<Algorithm>,
    profile: bool,
    refraction: plytrace::image_tree::Refraction,
    aa: Option<plytrace::raster::scan::Method>,
    threads: usize,
    shading: plytrace::shading::ShadingModel,
    quiet: bool,
}

fn usage() -> String {
    let mut s = format!(
        "plytrace {VERSION} - image rendering processor for 3-D polygonal environments

USAGE:
    plytrace                      interactive command interpreter (prompt `Command:`)
    plytrace -i -f SCENE.des      immediate mode: read the scene, render it, exit
    plytrace mkdet|mkpcl|mkvcl IN OUT
                                  convert an ASCII object file to binary form
    plytrace tessellation FILE    check Brown's Angle and Edge Conditions of a
                                  triangulated surface about its origin

FLAGS (the setmode letters of the manual, each taking its value as the next word):
    -i                 immediate mode
    -f FILE            scene descriptor file
    -b on|off          pre-blend parent and child intensities
    -d SIZE            minimum screen detail (default 0.0002)
    -e EPS             clipping epsilon (default 1e-7)
    -h on|off          explicit shadow shades
    -l 1-14            maximum reflection/refraction level
    -n on|off          Newell-Newell-Sancha sorting
    -o on|off          write the virtual image tree
    -p on|off          bounding boxes only
    -s on|off          Phong highlight vectors
    -v on|off          vertex shades
    -x on|off          expand all objects into one list before sorting
    -0 .. -9           debugging level
Flags override the same setmode in the scene file.

MODERN CONVENIENCES:
    -o FILE.png|.ppm   output image (any value of -o other than on/off)
    --output FILE      output image (default FNAME.png in the working directory)
    --size WxH         image size overriding the scene's resolution/viewport
    --id-image FILE    also write the polygon seen at every pixel as a false-colour PNG
                       (one colour per object and polygon, the same for every algorithm)
    --visibility ALG   visible-surface algorithm: depth-sort (default), nns (also
                       `setmode n on` / -n on), z-buffer, scan-line, warnock, brown
                       (well-tesselated surfaces), ray-cast (the oracle)
    --quiet            print only errors and warnings
    --profile          print the run-time profile in the categories of 004 table 6.2
    --refraction M     refraction matrix: linearized (default; exact for the ray through
                       the polygon's centre), orthographic (M_to), paraxial (M_tp)
    --aa METHOD        scan conversion (004 chapter 5): none (point sampled preview),
                       area (1), mask (2), hybrid (3), multilevel (4); default: the
                       best for the scene (multilevel: every tree level blended)
    --supersample N    Donovan's N x N samples per pixel instead (N from 1 to 16)
    --shading MODEL    illumination: garcia (004 section 4.8, default) or donovan (000
                       section 6: I0 cos^a, I1 cos^b(theta - theta1), transparency rule 3)
    --threads N        worker threads (default: all cores); the image does not depend on it
    --help, --version

COMMANDS of the scene descriptor language (shortest unique prefix accepted):
"
    );
    for c in COMMANDS {
        s.push_str(&format!("    {:<13} {:<38} {}\n", c.name, c.usage, c.help));
    }
    s.push_str(
        "\nNot yet acted on (parsed, checked and kept): clear (every run starts from the\n\
         background).\n",
    );
    s
}

enum Parsed {
    Run(Options),
    Tessellation(PathBuf),
    Convert(ConvertKind, PathBuf, PathBuf),
    Help,
    Version,
}

fn parse_args(args: &[String]) -> std::result::Result<Parsed, String> {
    if let Some(first) = args.first() {
        let kind = match first.as_str() {
            "mkdet" => Some(ConvertKind::Det),
            "mkpcl" => Some(ConvertKind::Pcl),
            "mkvcl" => Some(ConvertKind::Vcl),
            _ => None,
        };
        if first == "tessellation" {
            return match args {
                [_, file] => Ok(Parsed::Tessellation(file.into())),
                _ => Err("usage: plytrace tessellation <object file>".into()),
            };
        }
        if let Some(kind) = kind {
            return match args {
                [_, input, out] => Ok(Parsed::Convert(kind, input.into(), out.into())),
                _ => Err(format!(
                    "usage: plytrace {first} <input_file> <output_file>"
                )),
            };
        }
    }
    let mut o = Options::default();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let mut value = |what: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("`{arg}` needs {what}"))
        };
        match arg.as_str() {
            "--help" | "-help" => return Ok(Parsed::Help),
            "--version" | "-V" => return Ok(Parsed::Version),
            "-i" => o.immediate = true,
            "-f" => o.scene = Some(value("a scene file")?.into()),
            "--output" => o.output = Some(value("a file name")?.into()),
            "--id-image" => o.id_image = Some(value("a file name")?.into()),
            "--quiet" | "-q" => o.quiet = true,
            "--profile" => o.profile = true,
            "--aa" => {
                let v = value("none, area, mask, hybrid or multilevel (or 1 to 4)")?;
                o.aa = Some(parse_aa(&v)?);
            }
            "--supersample" => {
                let v = value("N from 1 to 16")?;
                match v.parse::<u32>() {
                    Ok(n @ 1..=16) => o.aa = Some(plytrace::raster::scan::Method::Supersample(n)),
                    _ => {
                        return Err(format!(
                            "--supersample: expected N from 1 to 16, found `{v}`"
                        ));
                    }
                }
            }
            "--shading" => {
                o.shading = match value("garcia or donovan")?.to_ascii_lowercase().as_str() {
                    "garcia" => plytrace::shading::ShadingModel::Garcia,
                    "donovan" => plytrace::shading::ShadingModel::Donovan,
                    v => {
                        return Err(format!(
                            "--shading: expected garcia or donovan, found `{v}`"
                        ));
                    }
                };
            }
            "--threads" => {
                let v = value("a thread count")?;
                o.threads = match v.parse::<usize>() {
                    Ok(n @ 1..=1024) => n,
                    _ => return Err(format!("--threads: expected 1 to 1024, found `{v}`")),
                };
            }
            "--refraction" => {
                let v = value("linearized, orthographic or paraxial")?;
                o.refraction = v.parse().map_err(|e| format!("--refraction: {e}"))?;
            }
            "--visibility" => {
                let v = value("an algorithm name")?;
                o.visibility = Some(
                    v.parse::<Algorithm>()
                        .map_err(|e| format!("--visibility: {e}"))?,
                );
            }
            "--size" => {
                let v = value("a size WxH")?;
                o.size = Some(parse_size(&v).ok_or_else(|| {
                    format!("--size: expected WxH with 1 <= W, H <= 65536, found `{v}`")
                })?);
            }
            "-o" => {
                let v = value("`on`, `off` or an output file")?;
                if matches!(v.to_ascii_lowercase().as_str(), "on" | "off") {
                    o.modes.push(('o', v));
                } else {
                    o.output = Some(v.into());
                }
            }
            a if a.len() == 2 && a.starts_with('-') => {
                let letter = a.chars().nth(1).expect("two characters");
                if letter.is_ascii_digit() {
                    o.modes.push((letter, String::new()));
                } else if "bdehlnpsvx".contains(letter) {
                    o.modes.push((letter, value("a value")?));
                } else {
                    return Err(format!(
                        "unknown flag `{a}`; `plytrace --help` lists the flags"
                    ));
                }
            }
            a => {
                return Err(format!(
                    "unexpected argument `{a}`; `plytrace --help` lists the flags"
                ));
            }
        }
    }
    if o.immediate && o.scene.is_none() {
        return Err("immediate mode (-i) needs a scene file: plytrace -i -f scene.des".into());
    }
    Ok(Parsed::Run(o))
}

fn method_name(m: plytrace::raster::scan::Method) -> String {
    use plytrace::raster::scan::Method;
    match m {
        Method::Point => "point sampled (--aa none)".into(),
        Method::Area => "method 1, area coverage".into(),
        Method::Mask => "method 2, 4x4 pixel masks".into(),
        Method::Hybrid => "method 3, hybrid area/mask".into(),
        Method::Multilevel => "method 4, multi-level pixel masks".into(),
        Method::Supersample(n) => format!("Donovan's {n} x {n} supersampling"),
    }
}

fn parse_aa(v: &str) -> std::result::Result<plytrace::raster::scan::Method, String> {
    use plytrace::raster::scan::Method;
    Ok(match v.to_ascii_lowercase().as_str() {
        "none" | "point" | "0" => Method::Point,
        "area" | "1" => Method::Area,
        "mask" | "2" => Method::Mask,
        "hybrid" | "3" => Method::Hybrid,
        "multilevel" | "4" => Method::Multilevel,
        _ => {
            return Err(format!(
                "--aa: expected none, area, mask, hybrid, multilevel or 1 to 4, found `{v}`"
            ));
        }
    })
}

fn parse_size(s: &str) -> Option<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X'])?;
    let (w, h): (u32, u32) = (w.trim().parse().ok()?, h.trim().parse().ok()?);
    let ok = |v: u32| (1..=65536).contains(&v);
    (ok(w) && ok(h) && (w as u64 * h as u64) <= 1 << 28).then_some((w, h))
}

fn hms(d: Duration) -> String {
    let s = d.as_secs();
    format!(
        "Time (HR:MIN:SEC) = {:02}:{:02}:{:02} ({:.3} s)",
        s / 3600,
        s / 60 % 60,
        s % 60,
        d.as_secs_f64()
    )
}

/// Renders on `run` and writes the image.
struct CliHost {
    output: Option<PathBuf>,
    size: Option<(u32, u32)>,
    id_image: Option<PathBuf>,
    visibility: Option<Algorithm>,
    profile: bool,
    refraction: plytrace::image_tree::Refraction,
    aa: Option<plytrace::raster::scan::Method>,
    threads: usize,
    shading: plytrace::shading::ShadingModel,
    scene_stem: Option<String>,
    quiet: bool,
    interactive: bool,
}

impl CliHost {
    fn say(&self, s: &str) {
        if !self.quiet {
            println!("{s}");
        }
    }

    fn output_path(&self, scene: &Scene) -> PathBuf {
        if let Some(p) = &self.output {
            return p.clone();
        }
        let stem = scene
            .fname
            .clone()
            .or_else(|| self.scene_stem.clone())
            .unwrap_or_else(|| "plytrace".into());
        PathBuf::from(format!("{stem}.png"))
    }
}

impl Host for CliHost {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        let start = Instant::now();
        self.say("Building image.");
        if scene.objects.is_empty() {
            eprintln!("warning: the scene has no objects; the image is the background only");
        }
        let options = RenderOptions {
            size: self.size,
            shadows,
            visibility: self.visibility,
            profile: self.profile,
            refraction: self.refraction,
            aa: self.aa,
            threads: self.threads,
            shading: self.shading,
        };
        let path = self.output_path(scene);
        let streamed = scene.display
            && self.id_image.is_none()
            && path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let rendered = match render::plan(scene, &options)? {
            render::Plan::Tree(mut prepared) if streamed => {
                // The virtual frame buffer: bands of rows go to the PNG as
                // they are finished; the whole image is never in memory.
                prepared.scan.ids = false;
                let (w, h) = (prepared.scan.width, prepared.scan.height);
                let mut sink = output::PngSink::create(&path, w, h, scene.outmode.into())?;
                let rendered = render::scan_into(*prepared, &mut sink)?;
                sink.finish()?.0.commit()?;
                self.say(&format!("Wrote {} ({w} x {h})", path.display()));
                rendered
            }
            plan => {
                let rendered = match plan {
                    render::Plan::Tree(prepared) => render::scan_into_frame(*prepared)?,
                    render::Plan::Painted(r) => *r,
                };
                if scene.display {
                    output::write_image(&path, &rendered.frame, scene.outmode)?;
                    self.say(&format!(
                        "Wrote {} ({} x {})",
                        path.display(),
                        rendered.frame.width,
                        rendered.frame.height
                    ));
                }
                rendered
            }
        };
        if let Some(tree) = &rendered.tree {
            let stem = scene
                .fname
                .clone()
                .or_else(|| self.scene_stem.clone())
                .unwrap_or_else(|| "plytrace".into());
            let (bin, txt) = (
                PathBuf::from(format!("{stem}.out")),
                PathBuf::from(format!("{stem}.txt")),
            );
            let bytes = tree.to_bytes();
            output::write_atomically(&bin, |w| w.write_all(&bytes))?;
            let text = tree.to_text();
            output::write_atomically(&txt, |w| w.write_all(text.as_bytes()))?;
            self.say(&format!(
                "Wrote the virtual image tree ({} polygons) to {} and {}",
                tree.records.len(),
                bin.display(),
                txt.display()
            ));
        }
        if let Some(p) = &self.id_image {
            output::write_id_png(p, &rendered.frame, &rendered.polygons)?;
        }
        let s = &rendered.stats;
        self.say(&format!(
            "{} Polygons tiled, Max depth = {}",
            s.polygons_tiled, s.max_depth
        ));
        if let Some(m) = s.method {
            let fragments = if s.scan.total_fragments > 0 {
                format!(
                    ", {} pixel-fragments at most at once, {} in all",
                    s.scan.peak_fragments, s.scan.total_fragments
                )
            } else {
                String::new()
            };
            self.say(&format!("Scan conversion: {}{fragments}", method_name(m)));
        }
        if let Some(p) = &rendered.profile {
            print!("{p}");
        } else if self.profile {
            println!(
                "(no profile: the virtual image tree was not built; it is for the depth-sort and nns algorithms)"
            );
        }
        if let Some(n) = &s.nns {
            self.say(&format!(
                "NNS: {} faces in, {} out, {} splits ({} cycles of two, {} longer){}",
                n.faces_in,
                n.faces_out,
                n.splits,
                n.cycles_of_two,
                n.longer_cycles,
                if n.unresolved > 0 {
                    format!(", {} unresolved", n.unresolved)
                } else {
                    String::new()
                }
            ));
        }
        if scene.modes.debug > 0 {
            self.say(&format!(
                "  geometry {:?}, sort {:?}, shading {:?}, paint {:?}; {:?}",
                s.geometry_time, s.sort_time, s.shading_time, s.paint_time, s.geometry
            ));
        }
        self.say(&hms(start.elapsed()));
        Ok(())
    }

    fn clear(&mut self, _scene: &Scene) {}

    fn scanning(&mut self, file: &Path) {
        self.say(&format!("Scanning descriptor file {}", file.display()));
        self.scene_stem = file.file_stem().map(|s| s.to_string_lossy().into_owned());
    }

    fn scanned(&mut self, _file: &Path, scene: &Scene, elapsed: Duration) {
        self.say(&format!(
            "{} objects, {} points, {} polygons",
            scene.objects.len(),
            scene.point_count(),
            scene.polygon_count()
        ));
        self.say(&hms(elapsed));
    }

    fn wait(&mut self) {
        if self.interactive && std::io::stdin().is_terminal() {
            print!("Press return to continue.");
            let _ = std::io::stdout().flush();
            let mut line = String::new();
            let _ = std::io::stdin().lock().read_line(&mut line);
        }
    }
}

fn report(e: &Error) {
    eprintln!("error: {e}");
}

fn print_warnings(interp: &mut Interpreter) {
    for w in interp.take_warnings() {
        eprintln!("{w}");
    }
}

fn load_scene(interp: &mut Interpreter, host: &mut CliHost, path: &Path) -> Result<Flow> {
    let start = Instant::now();
    host.scanning(path);
    let flow = interp.execute_file(path, true, host);
    print_warnings(interp);
    let flow = flow?;
    host.scanned(path, &interp.scene(), start.elapsed());
    Ok(flow)
}

fn interactive(interp: &mut Interpreter, host: &mut CliHost) -> ExitCode {
    let on_terminal = std::io::stdin().is_terminal();
    let stdin_label = Path::new("<stdin>");
    let mut line_no = 0usize;
    let mut failed = false;
    // Runs one line; errors are reported and remembered, the session goes on.
    let mut execute =
        |interp: &mut Interpreter, host: &mut CliHost, line: &str, line_no: usize| -> Flow {
            let result = interp.execute_source(line, stdin_label, Path::new("."), host);
            print_warnings(interp);
            match result {
                Ok(f) => f,
                Err(Error::Input(mut d)) => {
                    for loc in std::iter::once(&mut d.location).chain(d.included_from.iter_mut()) {
                        if loc.file == stdin_label {
                            loc.line = line_no;
                        }
                    }
                    report(&Error::Input(d));
                    failed = true;
                    Flow::Continue
                }
                Err(e) => {
                    report(&e);
                    failed = true;
                    Flow::Continue
                }
            }
        };
    if on_terminal {
        host.say(&format!("plytrace - version {VERSION}"));
        let Ok(mut editor) = rustyline::DefaultEditor::new() else {
            eprintln!("error: cannot open the terminal for line editing");
            return ExitCode::FAILURE;
        };
        loop {
            match editor.readline("Command: ") {
                Ok(line) => {
                    line_no += 1;
                    let _ = editor.add_history_entry(line.as_str());
                    if execute(interp, host, &line, line_no) == Flow::Quit {
                        break;
                    }
                }
                Err(rustyline::error::ReadlineError::Interrupted) => continue,
                Err(_) => break,
            }
        }
    } else {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else {
                eprintln!("error: standard input is not text");
                return ExitCode::FAILURE;
            };
            line_no += 1;
            if execute(interp, host, &line, line_no) == Flow::Quit {
                break;
            }
        }
    }
    if failed && !on_terminal {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// `plytrace tessellation FILE`: Brown's Angle and Edge Conditions for a
/// triangulated surface about its origin.
fn check_tessellation(path: &Path) -> ExitCode {
    let is_det = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("det"));
    let mesh = if is_det {
        object_file::read_det(path)
    } else {
        plytrace::scene::mesh_import::read_mesh(path)
    };
    let mesh = match mesh {
        Ok(m) => m,
        Err(e) => {
            report(&e);
            return ExitCode::FAILURE;
        }
    };
    match plytrace::modeling::geodesic::check_tessellation(&mesh, glam::DVec3::ZERO) {
        Ok(r) => {
            let yes = |b: bool| if b { "met" } else { "NOT met" };
            println!(
                "{}: {} vertices, {} faces",
                path.display(),
                mesh.vertices.len(),
                mesh.polygons.len()
            );
            println!(
                "Angle Condition {}: adjacent patch edges at most {:.2} deg (limit 90), nonadjacent at least {:.2} deg (limit 90), degree up to {}",
                yes(r.angle_condition),
                r.max_adjacent_angle.to_degrees(),
                r.min_nonadjacent_angle.to_degrees(),
                r.max_degree
            );
            println!(
                "Edge Condition {}: longest patch edge {:.4} rad (limit 1), edge ratio up to {:.4} (limit 1.27)",
                yes(r.edge_condition),
                r.max_edge,
                r.max_edge_ratio
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let options = match parse_args(&args) {
        Ok(Parsed::Help) => {
            print!("{}", usage());
            return ExitCode::SUCCESS;
        }
        Ok(Parsed::Version) => {
            println!("plytrace {VERSION}");
            return ExitCode::SUCCESS;
        }
        Ok(Parsed::Convert(kind, input, out)) => {
            return match object_file::convert(kind, &input, &out) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    report(&e);
                    ExitCode::FAILURE
                }
            };
        }
        Ok(Parsed::Tessellation(path)) => return check_tessellation(&path),
        Ok(Parsed::Run(o)) => o,
        Err(msg) => {
            eprintln!("error: {msg}");
            return ExitCode::from(2);
        }
    };

    let mut interp = Interpreter::new();
    for (letter, value) in &options.modes {
        if let Err(e) = interp.force_mode(*letter, value) {
            let msg = match e.diagnostic() {
                Some(d) => d.message.clone(),
                None => e.to_string(),
            };
            eprintln!("error: flag -{letter}: {msg}");
            return ExitCode::from(2);
        }
    }
    let mut host = CliHost {
        output: options.output.clone(),
        size: options.size,
        id_image: options.id_image.clone(),
        visibility: options.visibility,
        profile: options.profile,
        refraction: options.refraction,
        aa: options.aa,
        threads: options.threads,
        shading: options.shading,
        scene_stem: options
            .scene
            .as_ref()
            .and_then(|p| p.file_stem())
            .map(|s| s.to_string_lossy().into_owned()),
        quiet: options.quiet,
        interactive: !options.immediate,
    };

    if let Some(scene) = &options.scene {
        match load_scene(&mut interp, &mut host, scene) {
            Ok(Flow::Quit) => return ExitCode::SUCCESS,
            Ok(Flow::Continue) => {}
            Err(e) => {
                report(&e);
                return ExitCode::FAILURE;
            }
        }
        if options.immediate {
            let scene = interp.scene();
            return match host.run(&scene, true) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    report(&e);
                    ExitCode::FAILURE
                }
            };
        }
    }
    interactive(&mut interp, &mut host)
}
