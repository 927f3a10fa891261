//! The program's side of a `run` (the interpreter's [`Host`]): it checks
//! and creates the outputs, renders through the library, commits the
//! files together and prints the manual's statistics (004 appendix B:
//! "the total number of polygons tiled, maximum recursion level, and the
//! elapsed time").

use std::io::{BufRead, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use plytrace::api::program::files::{self, AtomicFile};
use plytrace::api::program::pipeline::{self, Algorithm, RenderOptions};
use plytrace::api::program::rows::FrameBuffer;
use plytrace::api::program::run::{self, PartRun, RunObserver, RunReport, RunSpec};
use plytrace::api::program::session::printable;
use plytrace::api::program::session::{Host, Scene};
use plytrace::api::program::{control, display, parts};
use plytrace::api::{Antialiasing, Budgets};
use plytrace::{Error, Result};

use crate::stats::RunStats;
use crate::term::{err, out, out_text};

/// Renders on `run` and writes the image.
pub struct CliHost {
    /// The image file named on the command line (for `-o -`, a file in a
    /// private temporary folder, copied to stdout when the run is done).
    pub output: Option<PathBuf>,
    /// `-o -`: the image goes to standard output, the messages to stderr.
    pub to_stdout: bool,
    /// `--check`: runs check their outputs and render nothing.
    pub check: bool,
    /// The statistics of every run, for `--stats`.
    pub stats: Vec<RunStats>,
    pub size: Option<(u32, u32)>,
    pub id_image: Option<PathBuf>,
    pub visibility: Option<Algorithm>,
    pub profile: bool,
    pub refraction: pipeline::Refraction,
    pub aa: Option<Antialiasing>,
    pub threads: usize,
    pub shading: pipeline::ShadingModel,
    pub scene_stem: Option<String>,
    /// The scene file last read, for the log.
    pub scene_file: Option<PathBuf>,
    pub quiet: bool,
    pub interactive: bool,
    /// `--allow-outside`: the scene's `fname` may leave the working
    /// directory.
    pub allow_outside: bool,
    /// The limits of the session: the interpreter has its own copy
    /// (polygons, call depth); `run` checks pixels and hands the rest to
    /// the renderer.
    pub budgets: Budgets,
    /// A progress bar on stderr during the scan conversion.
    pub progress: bool,
    /// The aspect-ratio warning was given (once per session).
    pub aspect_warned: bool,
    /// Every file written by the runs so far, in order.
    pub written: Vec<PathBuf>,
    /// `run`s rendered so far.
    pub runs: usize,
    /// `--hidden-line`.
    pub hidden_line: bool,
    /// What the previous frame leaves to the next: Brown's priority orders
    /// (003 sections 2-3), the shadows of an unchanged world.
    pub reuse: pipeline::Reuse,
    /// `--raytrace`.
    pub raytrace: bool,
    /// The live display (`disp on`).
    pub live: display::LiveDisplay,
    /// `--part I/N`: the run writes this part of its image.
    pub part: Option<parts::PartSpec>,
    /// `--frames A..B`: the runs (from 0) rendered; the others are skipped.
    pub frames: Option<(u32, u32)>,
    /// Frames (`run`s) met so far, rendered or skipped.
    pub frame: u32,
    /// The command line's flags that decide the pixels, for the
    /// fingerprint of a part.
    pub pixel_flags: String,
    /// `--stats FILE`: checked before each run not to be an input read
    /// so far (the scene, its object files), so that a run is refused
    /// before it renders rather than its statistics lost after.
    pub stats_file: Option<PathBuf>,
    /// The `--stats` file was refused as an input.
    pub stats_refused: bool,
}

/// The name and place of a scene-chosen output, `fname`, checked: no `..`
/// and no absolute path, unless `--allow-outside`.
fn confine(name: &str) -> Result<()> {
    if name.is_empty() {
        return Err(Error::Invalid("fname: an empty output name".into()));
    }
    match files::check_inside(Path::new(name)) {
        Ok(()) => Ok(()),
        Err(files::Outside::ByName) => Err(Error::Invalid(format!(
            "fname `{}`: names from a scene file must stay inside the working directory \
             (no `..`, no absolute path); `--allow-outside` permits it",
            printable(name, 200)
        ))),
        // A directory on the way that is a link out of the working
        // directory escapes as surely as `..`.
        Err(files::Outside::ByLink) => Err(Error::Invalid(format!(
            "fname `{}`: its directory leads outside the working directory (through a link); \
             names from a scene file must stay inside it; `--allow-outside` permits it",
            printable(name, 200)
        ))),
    }
}

/// A progress bar on stderr, one step a row (a band of rows at a time,
/// as the scan converter finishes them), and the run's warnings.
struct Progress {
    show: bool,
    bar: Option<indicatif::ProgressBar>,
    /// Lines said when the outputs are made and the render begins, each
    /// on stderr (`true`) or stdout.
    opening: Vec<(bool, String)>,
}

impl RunObserver for Progress {
    fn started(&mut self) {
        for (to_stderr, line) in self.opening.drain(..) {
            if to_stderr {
                err(&line);
            } else {
                out(&line);
            }
        }
    }

    fn rows_start(&mut self, rows: u32) {
        self.bar = self.show.then(|| {
            let bar = indicatif::ProgressBar::new(u64::from(rows));
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "Scan conversion [{bar:30}] {pos}/{len} rows (eta {eta})",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.tick();
            bar
        });
    }

    fn row_done(&mut self) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }

    fn rows_end(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    fn warning(&mut self, message: &str) {
        err(&format!("warning: {message}"));
    }
}

/// The date and time now, UTC, as the logs of every program write it.
fn utc_now() -> String {
    files::utc_timestamp(std::time::SystemTime::now())
}

/// Appends `line` to `plytrace.log` in the working directory (the manual's
/// FILES). A log that is a link or special file is left alone; a failure
/// is a warning, never an error of the run.
fn append_log(line: &str) {
    let path = Path::new("plytrace.log");
    if let Ok(m) = std::fs::symlink_metadata(path)
        && !m.file_type().is_file()
    {
        err("warning: plytrace.log is not a regular file; the run is not logged");
        return;
    }
    let written = std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .and_then(|mut f| f.write_all(format!("{line}\n").as_bytes()));
    if let Err(e) = written {
        err(&format!(
            "warning: plytrace.log: {e}; the run is not logged"
        ));
    }
}

impl CliHost {
    /// Prints a line of the session's report: on stdout, or on stderr
    /// when the image goes to stdout; nothing with `--quiet`.
    pub fn say(&self, s: &str) {
        if self.quiet {
        } else if self.to_stdout {
            err(s);
        } else {
            out(s);
        }
    }

    /// The stem of the outputs: the scene's `fname` (checked by
    /// [`confine`]), else the scene file's name, else `plytrace`.
    fn stem(&self, scene: &Scene) -> Result<String> {
        if let Some(f) = &scene.fname {
            if !self.allow_outside {
                confine(f)?;
            }
            return Ok(f.clone());
        }
        Ok(self.scene_stem.clone().unwrap_or_else(|| "plytrace".into()))
    }

    /// The image a run writes: `-o`, else the stem with `.png`.
    fn image_path(&self, scene: &Scene) -> Result<PathBuf> {
        match &self.output {
            Some(p) => Ok(p.clone()),
            None => Ok(PathBuf::from(format!("{}.png", self.stem(scene)?))),
        }
    }

    /// Warns once when `--size` stretches the scene's image.
    fn warn_aspect(&mut self, scene: &Scene) {
        if let Some(w) = self.aspect_warning(scene) {
            err(&w);
        }
    }

    /// The warning, once, that `--size` stretches the scene's image.
    fn aspect_warning(&mut self, scene: &Scene) -> Option<String> {
        let (w, h) = self.size?;
        let (sw, sh) = (scene.viewport.width(), scene.viewport.height());
        let (a, b) = (f64::from(w) / f64::from(h), f64::from(sw) / f64::from(sh));
        if self.aspect_warned || ((a - b) / b).abs() <= 0.01 {
            return None;
        }
        self.aspect_warned = true;
        Some(format!(
            "warning: --size {w}x{h} changes the aspect ratio of the scene's {sw} x {sh} image \
                 (width/height {} to {}); the picture is stretched",
            significant(b),
            significant(a)
        ))
    }
}

impl CliHost {
    fn render_options(&self, shadows: bool) -> RenderOptions {
        RenderOptions {
            size: self.size,
            shadows,
            visibility: self.visibility,
            profile: self.profile,
            refraction: self.refraction,
            aa: self.aa,
            threads: self.threads,
            shading: self.shading,
            budgets: self.budgets,
        }
    }

    /// The size of the image a run of `scene` makes, checked against the
    /// pixel budget.
    fn run_size(&self, scene: &Scene) -> Result<(u32, u32)> {
        let (w, h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if u64::from(w) * u64::from(h) > self.budgets.pixels {
            return Err(Error::Invalid(crate::settings::pixels_exceeded(
                w,
                h,
                self.budgets.pixels,
            )));
        }
        Ok((w, h))
    }

    /// What a run of `scene` writes and how it renders.
    fn run_spec(&self, scene: &Scene, shadows: bool) -> Result<RunSpec> {
        let named = self.output.is_none() || scene.modes.output_tree || self.part.is_some();
        let stem = if named {
            self.stem(scene)?
        } else {
            String::new()
        };
        let part = self.part.map(|spec| PartRun {
            spec,
            whole: PathBuf::from(format!("{stem}.png")),
            flags: format!("{} shadows {shadows}", self.pixel_flags),
        });
        Ok(RunSpec {
            image: match &self.output {
                Some(p) => p.clone(),
                None => PathBuf::from(format!("{stem}.png")),
            },
            id_image: self.id_image.clone(),
            tree_stem: scene.modes.output_tree.then_some(stem),
            options: self.render_options(shadows),
            hidden_line: self.hidden_line,
            raytrace: self.raytrace,
            part,
        })
    }

    /// One `run`: the library checks and creates the outputs, renders and
    /// commits them all together (or none); this reports.
    fn render(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        self.runs += 1;
        // From the second run of the session on (skipped frames count),
        // frames reuse each other's freed pages; setting it again is free.
        if self.runs >= 2 {
            crate::allocator::keep_freed_pages();
        }
        let start = Instant::now();
        if let Some(spec) = self.part
            && self.runs > 1
        {
            return Err(Error::Invalid(format!(
                "--part {spec}: this scene has more than one `run`, and every run would write \
                 {}; render one frame at a time with --frames",
                self.output.as_deref().unwrap_or(Path::new("")).display()
            )));
        }
        self.run_size(scene)?;
        let spec = self.run_spec(scene, shadows)?;
        // Said once the outputs are made, in this order, as before a render.
        let mut opening: Vec<(bool, String)> = self
            .aspect_warning(scene)
            .map(|w| (true, w))
            .into_iter()
            .collect();
        if !self.quiet {
            opening.push((self.to_stdout, "Building image.".into()));
        }
        if scene.objects.is_empty() && self.part.is_none() {
            opening.push((
                true,
                "warning: the scene has no objects; the image is the background only".into(),
            ));
        }
        let mut progress = Progress {
            show: self.progress,
            bar: None,
            opening,
        };
        let report = run::run(scene, &spec, &self.reuse, &mut self.live, &mut progress)?;
        let shown = self.tell_written(&spec, &report)?;
        self.report_stats(scene, &report.rendered);
        let elapsed = start.elapsed();
        self.say(&hms(elapsed));
        self.log_run(&shown, report.size, &report.rendered.stats, elapsed);
        Ok(())
    }

    /// Says what a run wrote (and sends `-o -`'s image to stdout); the
    /// image's name for the log.
    fn tell_written(&mut self, spec: &RunSpec, report: &RunReport) -> Result<PathBuf> {
        let (w, h) = report.size;
        if let (Some(part), Some(rows)) = (&spec.part, &report.rows) {
            self.written.extend(report.written.iter().cloned());
            self.say(&format!(
                "Wrote part {} of {} ({w} x {h}): rows {} to {} in {}",
                part.spec,
                part.whole.display(),
                rows.start,
                rows.end.saturating_sub(1).max(rows.start),
                spec.image.display()
            ));
            return Ok(spec.image.clone());
        }
        let shown = if self.to_stdout {
            crate::stdout_image::send(&spec.image)?;
            PathBuf::from("<stdout>")
        } else {
            self.written.extend(report.written.iter().cloned());
            spec.image.clone()
        };
        self.say(&format!("Wrote {} ({w} x {h})", shown.display()));
        if let Some((records, bin, txt)) = &report.tree {
            self.say(&format!(
                "Wrote the virtual image tree ({records} polygons) to {} and {}",
                bin.display(),
                txt.display()
            ));
        }
        if let Some(p) = &self.id_image {
            self.say(&format!("Wrote the id image {}", p.display()));
        }
        Ok(shown)
    }

    /// Appends the run to `plytrace.log` and keeps its statistics.
    fn log_run(
        &mut self,
        image: &Path,
        (w, h): (u32, u32),
        s: &pipeline::RenderStats,
        elapsed: Duration,
    ) {
        let field = |p: &Path| printable(&p.display().to_string(), 300).replace(' ', "\\x20");
        append_log(&format!(
            "{} scene={} image={} size={w}x{h} polygons_tiled={} max_depth={} seconds={:.3}",
            utc_now(),
            self.scene_file
                .as_deref()
                .map_or_else(|| crate::settings::STDIN.into(), field),
            field(image),
            s.polygons_tiled,
            s.max_depth,
            elapsed.as_secs_f64()
        ));
        self.stats.push(RunStats::new(image, (w, h), s, elapsed));
    }

    /// `--check`: what a run would do is checked (the image's size
    /// against the budgets, the outputs' names and places) and said;
    /// nothing is rendered or written.
    fn check_run(&mut self, scene: &Scene) -> Result<()> {
        self.runs += 1;
        let (w, h) = self.run_size(scene)?;
        let image = self.image_path(scene)?;
        let mut outputs = vec![image.clone()];
        if scene.modes.output_tree {
            let stem = self.stem(scene)?;
            outputs.push(PathBuf::from(format!("{stem}.out")));
            outputs.push(PathBuf::from(format!("{stem}.txt")));
        }
        outputs.extend(self.id_image.iter().cloned());
        for p in &outputs {
            if !self.to_stdout || p != &image {
                files::check_target(p)?;
            }
        }
        self.warn_aspect(scene);
        let shown = if self.to_stdout {
            "<stdout>".to_string()
        } else {
            image.display().to_string()
        };
        self.say(&format!("Checked: a run would write {shown} ({w} x {h})"));
        Ok(())
    }

    /// The manual's statistics of a run, and this program's own figures.
    fn report_stats(&self, scene: &Scene, rendered: &pipeline::Rendered) {
        let s = &rendered.stats;
        if s.raytrace.is_some() {
            // Rays, not polygons: the ray tracer's line below says what it did.
            self.say(&format!("Max depth = {}", s.max_depth));
        } else {
            self.say(&format!(
                "{} Polygons tiled, Max depth = {}",
                s.polygons_tiled, s.max_depth
            ));
        }
        for w in &s.warnings {
            err(&format!("warning: {w}"));
        }
        if let Some(r) = &s.raytrace {
            self.say(&format!(
                "Ray tracing: {} primary rays, {} rays in all, {} shadow rays, {:.0} rays per second \
                 (hierarchy {:.3} s, tracing {:.3} s)",
                r.primary,
                r.rays,
                r.shadow_rays,
                r.rays_per_second(),
                r.build_time.as_secs_f64(),
                r.trace_time.as_secs_f64()
            ));
        }
        if let Some(m) = &s.refraction {
            self.say(&format!("Refraction: {m}"));
        }
        if let Some(m) = s.method {
            let fragments = if s.scan.total_fragments > 0 {
                format!(
                    ", {} pixel-fragments at most at once, {} in all",
                    s.scan.peak_fragments, s.scan.total_fragments
                )
            } else {
                String::new()
            };
            self.say(&format!(
                "Scan conversion: {}{fragments}",
                crate::stats::method_name(m)
            ));
        }
        if let Some(p) = &rendered.profile {
            self.say(&p.to_string());
        } else if self.profile {
            self.say(
                "(no profile: the virtual image tree was not built; it is for the depth-sort and nns algorithms)",
            );
        }
        if let Some(n) = &s.nns {
            self.say(&nns_line(n));
        }
        if let Some(b) = &s.brown {
            self.say(&format!("Brown: {b}"));
        }
        if scene.modes.debug > 0 {
            self.say(&debug_timings(s));
        }
    }
}

/// The `setmode d` timing line: the stages the run measured, by name.
/// The tree path builds geometry, order and shadows in one pass (the
/// virtual image tree), then its records and the scan conversion; the
/// vector painter builds its tree, then paints; the image-space
/// algorithms have their own stages. Stages a path does not have are left
/// out rather than shown as zero.
fn debug_timings(s: &pipeline::RenderStats) -> String {
    let names = if s.method.is_some() {
        [
            "geometry",
            "virtual image tree (geometry, sort, shadows)",
            "records (shading)",
            "scan conversion",
        ]
    } else {
        ["geometry", "sort", "shading", "paint"]
    };
    let times = [s.geometry_time, s.sort_time, s.shading_time, s.paint_time];
    let stages: Vec<String> = names
        .iter()
        .zip(times)
        .filter(|(_, t)| !t.is_zero())
        .map(|(n, t)| format!("{n} {t:?}"))
        .collect();
    format!("  {}; {:?}", stages.join(", "), s.geometry)
}

/// The NNS statistics line.
fn nns_line(n: &pipeline::NnsStats) -> String {
    format!(
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
    )
}

impl Host for CliHost {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        if let Some((a, b)) = self.frames {
            let frame = self.frame;
            self.frame += 1;
            if !(a..=b).contains(&frame) {
                // A run all the same: immediate mode renders no more.
                self.runs += 1;
                self.say(&format!("Frame {frame} skipped (--frames)"));
                return Ok(());
            }
        }
        if let Some(p) = &self.stats_file
            && let Err(e) = files::check_not_input(p)
        {
            // Said once: the statistics are then not written at all.
            self.stats_file = None;
            self.stats_refused = true;
            return Err(Error::Invalid(format!("--stats {e}")));
        }
        if self.check {
            return self.check_run(scene);
        }
        control::reset_cancel();
        control::rendering(true);
        let result = self.render(scene, shadows);
        control::rendering(false);
        control::reset_cancel();
        result
    }
    /// The manual's `clear` empties the display to the background; here
    /// the display is the image file, so it is written (atomically) in the
    /// background colour, at the size the next `run` would write.
    fn clear(&mut self, scene: &Scene) -> Result<()> {
        let path = self.image_path(scene)?;
        let (w, h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if u64::from(w) * u64::from(h) > self.budgets.pixels {
            return Err(Error::Invalid(crate::settings::pixels_exceeded(
                w,
                h,
                self.budgets.pixels,
            )));
        }
        self.budgets
            .check_frame(w, h, pipeline::FRAME_BYTES_PER_PIXEL)
            .map_err(Error::Invalid)?;
        let file = AtomicFile::create(&path)?;
        let bg = scene.background;
        let frame = FrameBuffer::new(w, h, [bg.x as f32, bg.y as f32, bg.z as f32]);
        files::commit_all(vec![files::stage_image(file, &frame, scene.outmode)?])?;
        if let Ok(Some(window)) = self.live.observer(w, h) {
            let cleared = pipeline::Rendered {
                frame,
                ..pipeline::Rendered::empty(pipeline::RenderStats::default())
            };
            display::show_painted(&cleared, window);
        }
        self.say(&format!(
            "Cleared {} to the background ({w} x {h})",
            path.display()
        ));
        Ok(())
    }

    fn scanning(&mut self, file: &Path) {
        self.say(&format!("Scanning descriptor file {}", file.display()));
        if file == Path::new(crate::settings::STDIN) {
            // A scene without `fname` from standard input writes plytrace.png.
            self.scene_stem = None;
            self.scene_file = None;
            return;
        }
        self.scene_stem = file.file_stem().map(|s| s.to_string_lossy().into_owned());
        self.scene_file = Some(file.to_path_buf());
    }

    fn runs_follow(&mut self, more: bool) {
        // The last frame --frames asks for is followed by none.
        let last = self.frames.is_some_and(|(_, b)| self.frame >= b);
        self.reuse.frames_follow(more && !last);
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

    fn display(&mut self, on: bool) {
        if let Some(message) = self.live.request(on) {
            err(&format!("warning: {message}"));
        }
    }

    fn wait(&mut self) {
        if self.live.wait() {
            return;
        }
        if self.interactive && std::io::stdin().is_terminal() {
            out_text("Press return to continue.", false);
            let mut line = String::new();
            let _ = std::io::stdin().lock().read_line(&mut line);
        }
    }
}

/// The manual's timing line, `Time (HR:MIN:SEC) = 00:00:02`, rounded to
/// the second (`--stats` and `setmode d` give the exact times).
pub fn hms(d: Duration) -> String {
    let s = (d.as_secs_f64() + 0.5) as u64;
    format!(
        "Time (HR:MIN:SEC) = {:02}:{:02}:{:02}",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

/// A ratio with four significant digits: 1.067, 0.0002500.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
}

/// The settings that decide the pixels, as text: the manual's letters
/// (not `-o`, nor the debugging level), the size and the rendering
/// flags. Threads, budgets, messages and output names do not count.
fn pixel_flags(s: &crate::settings::Settings) -> String {
    let modes: Vec<&(char, String)> = s
        .modes
        .iter()
        .filter(|(l, _)| *l != 'o' && !l.is_ascii_digit())
        .collect();
    format!(
        "modes {modes:?} size {:?} visibility {:?} refraction {:?} aa {:?} shading {:?} \
         hidden-line {} raytrace {}",
        s.size, s.visibility, s.refraction, s.aa, s.shading, s.hidden_line, s.raytrace
    )
}

impl CliHost {
    /// The host of a session with these settings; `output` is where the
    /// image goes (a temporary file for `-o -`).
    pub fn new(s: &crate::settings::Settings, output: Option<PathBuf>) -> CliHost {
        let scene_file = match &s.scene {
            crate::settings::SceneSource::File(p) => Some(p.clone()),
            _ => None,
        };
        CliHost {
            output,
            to_stdout: matches!(s.image, crate::settings::Image::Stdout(_)),
            check: s.check,
            stats: Vec::new(),
            size: s.size,
            id_image: s.id_image.clone(),
            visibility: s.visibility,
            profile: s.profile,
            refraction: s.refraction,
            aa: s.aa,
            threads: s.threads,
            shading: s.shading,
            scene_stem: scene_file
                .as_ref()
                .and_then(|p| p.file_stem())
                .map(|s| s.to_string_lossy().into_owned()),
            scene_file,
            quiet: s.quiet,
            interactive: !s.immediate,
            allow_outside: s.allow_outside,
            budgets: s.budgets,
            progress: !s.quiet && std::io::stderr().is_terminal(),
            aspect_warned: false,
            written: Vec::new(),
            runs: 0,
            hidden_line: s.hidden_line,
            reuse: Default::default(),
            raytrace: s.raytrace,
            live: Default::default(),
            part: s.part,
            frames: s.frames,
            frame: 0,
            pixel_flags: pixel_flags(s),
            stats_file: match &s.stats {
                Some(crate::settings::StatsTarget::File(p)) => Some(p.clone()),
                _ => None,
            },
            stats_refused: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_manuals_timing_line() {
        // 004 appendix B, the sample session: "Time (HR:MIN:SEC) = 00:00:02".
        assert_eq!(
            hms(Duration::from_millis(2_200)),
            "Time (HR:MIN:SEC) = 00:00:02"
        );
        assert_eq!(
            hms(Duration::from_secs(3_723)),
            "Time (HR:MIN:SEC) = 01:02:03"
        );
    }

    #[test]
    fn ratios_keep_four_digits() {
        assert_eq!(significant(512.0 / 480.0), "1.067");
        assert_eq!(significant(1.0 / 4000.0), "0.0002500");
    }
}
