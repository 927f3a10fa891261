//! Objects (Garcia 1986, 004 section 4.3 and appendix B, the plytrace
//! manual page; Brown's geodesics, 003): `defobj` ... `endobj` reads an
//! object's geometry from the detail directory (or copies it, `callobj`,
//! or generates it, `geodesic`) and places it by the CTM at `endobj`;
//! `getobj` is both at once, `delobj` deletes. The object becomes the
//! scene's, in world coordinates ([`crate::scene::build`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::active::ActiveObject;
use super::deleting::Doomed;
use super::generators::Ending;
use crate::budget::Budgets;
use crate::error::{
    Diagnostic, Error, Location, MAX_SHOWN_PATH, MAX_SHOWN_TOKEN, Result, printable,
};
use crate::model::{ColorEntry, Mesh, Object};
use crate::modeling::geodesic::{self, Division, Radial, TurnedRadial};
use crate::scene::arguments::{Context, ObjectRef, Spanned};
use crate::scene::build::{ObjectParts, build_object, warning_kind};
use crate::scene::command::RadialCommand;
use crate::scene::interpreter::Interpreter;
use crate::scene::lexer::Token;
use crate::scene::mesh_import;
use crate::scene::object_file::{self, ColorKind};

/// Polygon and vertex colours of an object.
type Colors = (Option<Arc<Vec<ColorEntry>>>, Option<Arc<Vec<ColorEntry>>>);

impl Interpreter {
    /// `defobj name [number]`.
    pub(in crate::scene) fn defobj(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        name: &str,
        number: Option<&Spanned<u32>>,
    ) -> Result<()> {
        if let Some(n) = number
            && self.numbers.uses(&self.scene.objects, n.value)
        {
            return Err(ctx.error(
                &n.token,
                format!("object number {} is already in use", n.value),
            ));
        }
        self.begin_object(ctx, cmd, name.to_string(), number.map(|n| n.value))
    }

    /// `getobj name`: `defobj name` and `endobj`.
    pub(in crate::scene) fn getobj(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        name: &str,
    ) -> Result<()> {
        self.begin_object(ctx, cmd, name.to_string(), None)?;
        self.end_object(ctx, cmd)
    }

    /// `callobj n`: inside a definition, the object's source; outside, a
    /// new object of its own.
    pub(in crate::scene) fn callobj(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        object: &Spanned<ObjectRef>,
    ) -> Result<()> {
        let n = self.find_object(ctx, object)?;
        let loc = ctx.location(&object.token);
        match &mut self.active {
            Some(active) => active.copy_of = Some((n, loc)),
            None => {
                self.begin_object(ctx, cmd, format!("#{n}"), None)?;
                if let Some(active) = &mut self.active {
                    active.copy_of = Some((n, loc));
                }
                self.end_object(ctx, cmd)?;
            }
        }
        Ok(())
    }

    /// `delobj n...`, in order; an object that is not there is an error
    /// (those named before it are deleted). The objects are marked, and
    /// leave the scene at [`Self::settle_deletions`] (see
    /// [`super::deleting`]).
    pub(in crate::scene) fn delobj(
        &mut self,
        ctx: &Context,
        objects: &[Spanned<ObjectRef>],
    ) -> Result<()> {
        let count = self.scene.objects.len();
        let mut doomed = self.doomed.take().unwrap_or_else(|| Doomed::new(count));
        let missing = objects
            .iter()
            .find(|r| !doomed.mark(&self.scene.objects, &r.value));
        self.doomed = Some(doomed);
        match missing {
            Some(r) => Err(no_object(ctx, &r.token)),
            None => Ok(()),
        }
    }

    /// Removes the objects `delobj` statements marked: before any other
    /// statement runs, and whenever the interpreter stops or hands out
    /// its scene.
    pub(in crate::scene) fn settle_deletions(&mut self) {
        if let Some(doomed) = self.doomed.take() {
            let mut k = 0;
            self.retain_objects(|_| {
                k += 1;
                !doomed.is_gone(k - 1)
            });
        }
    }

    /// `geodesic n [equal|angle]` in a definition.
    pub(in crate::scene) fn geodesic(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        n: usize,
        division: Division,
    ) -> Result<()> {
        let loc = ctx.location(cmd);
        let Some(active) = &mut self.active else {
            return Err(ctx.error(cmd, "`geodesic` outside an object definition"));
        };
        active.geodesic = Some((n, division, loc));
        Ok(())
    }

    /// `radial ...`: a geodesic's radial function, or its turn; outside a
    /// definition, `radial rotate` turns every geodesic object.
    pub(in crate::scene) fn radial(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        radial: RadialCommand,
    ) -> Result<()> {
        let loc = ctx.location(cmd);
        match (radial, &mut self.active) {
            (RadialCommand::Function(f), Some(active)) => active.radial = Some((f, loc)),
            (RadialCommand::Function(_), None) => {
                return Err(ctx.error(cmd, "`radial` outside an object definition"));
            }
            (RadialCommand::Rotate(angle, axis), Some(active)) => {
                let before = active.turn.as_ref().map_or(glam::DMat3::IDENTITY, |t| t.0);
                let turned = TurnedRadial {
                    radial: Radial::Sphere,
                    rotation: before,
                }
                .turned(angle, axis);
                active.turn = Some((turned.rotation, loc));
            }
            (RadialCommand::Rotate(angle, axis), None) => {
                self.turn_geodesics(ctx, cmd, angle, axis)?;
            }
        }
        Ok(())
    }

    /// Opens a definition (`defobj`, `getobj`, `callobj` outside one).
    pub(in crate::scene) fn begin_object(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        name: String,
        number: Option<u32>,
    ) -> Result<()> {
        if let Some(active) = &self.active {
            return Err(ctx.error(
                cmd,
                format!(
                    "`{}` inside the definition of `{}` begun at {} (missing `endobj`)",
                    printable(&cmd.text, MAX_SHOWN_TOKEN),
                    printable(&active.name, MAX_SHOWN_TOKEN),
                    active.location
                ),
            ));
        }
        self.push(ctx, cmd)?;
        self.active = Some(ActiveObject {
            name: name.to_lowercase(),
            written: name,
            number,
            surface: self.globals,
            surface_type: self.global_type,
            copy_of: None,
            geodesic: None,
            radial: None,
            turn: None,
            generator: None,
            surface_cmd: None,
            pcolors: None,
            vcolors: None,
            stack_depth: self.stack.len(),
            location: ctx.location(cmd),
            det_base: ctx.dir.clone(),
        });
        Ok(())
    }

    /// `endobj`: the CTM restored, the object's polygons made (generated,
    /// copied or read), coloured, placed and added to the scene.
    pub(in crate::scene) fn end_object(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        let Some(active) = self.active.take() else {
            return Err(ctx.error(cmd, "`endobj` without `defobj`"));
        };
        // Restore the CTM whatever happens next.
        self.stack.truncate(active.stack_depth);
        let transform = self.ctm;
        let Some(saved) = self.stack.pop() else {
            return Err(ctx.error(
                cmd,
                "matrix stack underflow: the matrix `defobj` saved is gone",
            ));
        };
        self.ctm = saved;
        if let Some((pending, loc)) = active.generator.clone() {
            let end = Ending {
                ctx,
                cmd,
                transform,
                saved,
            };
            return self.end_generated(active, pending, loc, end);
        }
        let geodesic = self.make_geodesic(&active)?;
        let (mesh, colors) = match &geodesic {
            Some((mesh, _)) => (Arc::clone(mesh), (None, None)),
            None => self.copied_or_read(&active)?,
        };
        let (pcl, vcl) = self.color_files(&active, &mesh, colors)?;
        if active.copy_of.is_none() && active.geodesic.is_none() {
            let count = mesh.polygons.len();
            self.check_polygons(
                count,
                &active.location,
                &format!(
                    "object `{}` ({count} polygons)",
                    printable(&active.written, MAX_SHOWN_TOKEN)
                ),
            )?;
        }
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        let parts = ObjectParts {
            number,
            name: active.name.clone(),
            mesh,
            polygon_colors: pcl,
            vertex_colors: vcl,
            transform,
            surface: active.surface,
            surface_type: active.surface_type,
        };
        let object = build_object(parts, &mut |msg| {
            let kind = warning_kind(&msg);
            self.warn(kind, Diagnostic::new(ctx.location(cmd), msg));
        })
        .map_err(|msg| ctx.error(cmd, msg))?;
        // Splitting non-planar polygons may have added some.
        self.check_polygons(
            object
                .polygons
                .len()
                .saturating_sub(object.mesh.polygons.len()),
            &active.location,
            "the triangles of split non-planar polygons",
        )?;
        self.polygons += object.polygons.len();
        match geodesic {
            Some(g) => self.geodesics.insert(object.number, g),
            None => self.geodesics.remove(&object.number),
        };
        self.scene.objects.push(object);
        Ok(())
    }

    /// The mesh of the block's `geodesic`, with its radial function; a
    /// `radial` without one is an error.
    fn make_geodesic(&self, active: &ActiveObject) -> Result<Option<(Arc<Mesh>, TurnedRadial)>> {
        let Some((n, division, loc)) = &active.geodesic else {
            let stray = active.radial.as_ref().map(|r| &r.1);
            if let Some(loc) = stray.or(active.turn.as_ref().map(|t| &t.1)) {
                return Err(Error::at(
                    loc.clone(),
                    "`radial` deforms a `geodesic`; this object has none",
                ));
            }
            return Ok(None);
        };
        // Refused before anything is allocated.
        let faces = geodesic::face_count(*n).unwrap_or(usize::MAX);
        self.check_polygons(faces, loc, &format!("`geodesic {n}` ({faces} faces)"))?;
        let radial = TurnedRadial {
            radial: active.radial.as_ref().map_or(Radial::Sphere, |r| r.0),
            rotation: active.turn.as_ref().map_or(glam::DMat3::IDENTITY, |t| t.0),
        };
        let mesh = geodesic::geodesic_turned(*n, *division, &radial)
            .map_err(|e| Error::at(loc.clone(), e))?;
        Ok(Some((Arc::new(mesh), radial)))
    }

    /// The mesh of the object `callobj` copies (with its colours), or of
    /// the block's geometry file.
    fn copied_or_read(&mut self, active: &ActiveObject) -> Result<(Arc<Mesh>, Colors)> {
        let Some((n, loc)) = &active.copy_of else {
            return Ok((self.read_object_file(active)?, (None, None)));
        };
        // `callobj` checked the number, but a `delobj` may have deleted the
        // object since.
        let Some(src) = self.scene.objects.iter().find(|o| o.number == *n) else {
            return Err(Error::at(
                loc.clone(),
                format!("object number {n}, copied here by `callobj`, was deleted before `endobj`"),
            ));
        };
        let count = src.polygons.len().max(src.mesh.polygons.len());
        self.check_polygons(count, loc, &format!("`callobj {n}` ({count} polygons)"))?;
        Ok((
            src.mesh.clone(),
            (src.polygon_colors.clone(), src.vertex_colors.clone()),
        ))
    }

    /// The object's geometry file (`.det`, or a mesh format) read.
    fn read_object_file(&mut self, active: &ActiveObject) -> Result<Arc<Mesh>> {
        let path = self.find_object_file(active)?;
        // A `.det` file may use what is left of the budget, a mesh file
        // the whole (the object's count is checked after).
        let limit = if is_det(&path) {
            self.budgets.polygons.saturating_sub(self.polygons)
        } else {
            self.budgets.polygons
        };
        let ahead = self.read_ahead.take(&path);
        let mesh = match ahead.filter(|(mesh, _)| mesh.polygons.len() <= limit) {
            Some((mesh, notes)) => {
                notes.enter();
                Ok(mesh)
            }
            None => read_geometry(&path, limit).map(Arc::new),
        };
        // A problem in the file names the statement that read it.
        let mesh = mesh.map_err(|e| match e {
            Error::Input(mut d) => {
                d.included_from.push(active.location.clone());
                Error::Input(d)
            }
            other => other,
        })?;
        Ok(mesh)
    }

    /// The colours of `pcolors` and `vcolors` read (replacing those copied
    /// by `callobj`), one per polygon and per vertex of `mesh`.
    fn color_files(&self, active: &ActiveObject, mesh: &Mesh, colors: Colors) -> Result<Colors> {
        let (mut pcl, mut vcl) = colors;
        if let Some((name, loc)) = &active.pcolors {
            let p = self.read_colors(active, name, loc, ColorKind::Polygon)?;
            pcl = Some(Arc::new(p));
        }
        if let Some((name, loc)) = &active.vcolors {
            let v = self.read_colors(active, name, loc, ColorKind::Vertex)?;
            vcl = Some(Arc::new(v));
        }
        if let (Some(p), Some((_, loc))) = (&pcl, &active.pcolors)
            && p.len() != mesh.polygons.len()
        {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "{} polygon colours for {} polygons",
                    p.len(),
                    mesh.polygons.len()
                ),
            ));
        }
        if let (Some(v), Some((_, loc))) = (&vcl, &active.vcolors)
            && v.len() != mesh.vertices.len()
        {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "{} vertex colours for {} vertices",
                    v.len(),
                    mesh.vertices.len()
                ),
            ));
        }
        Ok((pcl, vcl))
    }

    /// `radial rotate ANGLE AXIS` outside a definition: turns the radial
    /// function of every geodesic object inside its fixed vertex
    /// directions (Brown's approximate rotation, 003 section 2) and moves
    /// its vertices along them; the faces and their priority order stay.
    fn turn_geodesics(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        angle: f64,
        axis: usize,
    ) -> Result<()> {
        let mut turned = 0;
        for i in 0..self.scene.objects.len() {
            let number = self.scene.objects[i].number;
            let Some((mesh, f)) = self.geodesics.get(&number) else {
                continue;
            };
            // Still the object `geodesic` made (not deleted and replaced).
            if !Arc::ptr_eq(mesh, &self.scene.objects[i].mesh) {
                continue;
            }
            let f = f.turned(angle, axis);
            let mesh = Arc::new(geodesic::reshape(mesh, &f).map_err(|e| ctx.error(cmd, e))?);
            let o = &self.scene.objects[i];
            let object = build_object(
                ObjectParts {
                    number,
                    name: o.name.clone(),
                    mesh: Arc::clone(&mesh),
                    polygon_colors: o.polygon_colors.clone(),
                    vertex_colors: o.vertex_colors.clone(),
                    transform: o.transform,
                    surface: o.surface,
                    surface_type: o.surface_type,
                },
                &mut |_| {},
            )
            .map_err(|msg| ctx.error(cmd, msg))?;
            // The scene's count follows the faces the turn kept.
            let before = self.scene.objects[i].polygons.len();
            self.polygons = (self.polygons + object.polygons.len()).saturating_sub(before);
            self.scene.objects[i] = object;
            self.geodesics.insert(number, (mesh, f));
            turned += 1;
        }
        if turned == 0 {
            return Err(ctx.error(
                cmd,
                "`radial rotate` outside a definition turns the geodesic objects; there are none",
            ));
        }
        Ok(())
    }

    /// Refuses `adding` more polygons when the scene would then have more
    /// than [`Budgets::polygons`].
    pub(in crate::scene) fn check_polygons(
        &self,
        adding: usize,
        location: &Location,
        what: &str,
    ) -> Result<()> {
        let limit = self.budgets.polygons;
        let total = self.polygons.saturating_add(adding);
        if total > limit {
            let total = if total == usize::MAX {
                "too many to count".to_string()
            } else {
                total.to_string()
            };
            return Err(Error::at(
                location.clone(),
                Budgets::exceeded(
                    &format!(
                        "{what}: the scene's polygons, {} with these, {total}",
                        self.polygons
                    ),
                    limit,
                    "--max-polygons",
                ),
            ));
        }
        Ok(())
    }

    /// The number of the object `callobj` names: by number, or by
    /// (case-folded) name, the last defined of that name.
    fn find_object(&self, ctx: &Context, object: &Spanned<ObjectRef>) -> Result<u32> {
        let r = &object.value;
        let objects = &self.scene.objects;
        let found = match r {
            ObjectRef::Number(_) => objects.iter().find(|o| r.names(o)),
            ObjectRef::Name(_) => objects.iter().rev().find(|o| r.names(o)),
        };
        found
            .map(|o| o.number)
            .ok_or_else(|| no_object(ctx, &object.token))
    }

    /// Keeps the objects `keep` says to (called once for each, in order):
    /// the one way objects leave the scene, so that [`FreeNumbers`]
    /// forgets their numbers and the scene's polygon count goes down
    /// whenever one does.
    pub(in crate::scene) fn retain_objects(&mut self, mut keep: impl FnMut(&Object) -> bool) {
        let (mut removed, mut polygons) = (0, 0);
        let mut numbers = Vec::new();
        self.numbers.update(&self.scene.objects);
        self.scene.objects.retain(|o| {
            let kept = keep(o);
            if !kept {
                removed += 1;
                polygons += o.polygons.len();
                numbers.push(o.number);
            }
            kept
        });
        if removed > 0 {
            self.numbers.forget(&numbers, self.scene.objects.len());
            debug_assert!(
                polygons <= self.polygons,
                "the polygon count is the objects'"
            );
            self.polygons = self.polygons.saturating_sub(polygons);
        }
    }

    /// The smallest object number not in use.
    pub(in crate::scene) fn next_free_number(&mut self) -> u32 {
        self.numbers.next_free(&self.scene.objects)
    }

    /// The folders an object's files are looked up in: the detail
    /// directory relative to the file that set it, to the file of the
    /// definition and to the working directory, then the same folded to
    /// lower case (004 appendix B: input is converted to lower case).
    pub(in crate::scene) fn det_dirs(&self, det_base: &Path) -> Vec<PathBuf> {
        let mut dirs = Vec::new();
        let mut add = |d: PathBuf| {
            if !dirs.contains(&d) {
                dirs.push(d);
            }
        };
        if self.det_dir.is_absolute() {
            add(self.det_dir.clone());
        } else {
            for base in [&self.det_base, det_base, Path::new(".")] {
                add(base.join(&self.det_dir));
            }
        }
        let folded = PathBuf::from(self.det_dir.to_string_lossy().to_lowercase());
        if folded != self.det_dir {
            let bases: Vec<PathBuf> = if folded.is_absolute() {
                vec![PathBuf::new()]
            } else {
                vec![self.det_base.clone(), det_base.to_path_buf(), ".".into()]
            };
            for base in bases {
                add(base.join(&folded));
            }
        }
        dirs
    }

    /// The geometry file of an object named `written` in a definition in
    /// a file of folder `det_base` ([`Self::look_up_object_file`]), or
    /// `None`: looked up once for the same name and folders until the end
    /// of the run, found or not (see [`super::FoundFiles`]).
    pub(super) fn object_file(&mut self, written: &str, det_base: &Path) -> Option<PathBuf> {
        let key = (
            written.to_string(),
            self.det_dir.clone(),
            self.det_base.clone(),
            det_base.to_path_buf(),
        );
        if let Some(found) = self.found_files.get(&key) {
            return found.clone();
        }
        let found = self.look_up_object_file(written, det_base).ok();
        self.found_files.insert(key, found.clone());
        found
    }

    /// The geometry file of an object named `written` in a definition in
    /// a file of folder `det_base`: the name as written, then folded, with
    /// `.det` or a mesh extension, in [`Self::det_dirs`]; else the paths
    /// tried.
    fn look_up_object_file(
        &self,
        written: &str,
        det_base: &Path,
    ) -> std::result::Result<PathBuf, Vec<PathBuf>> {
        let folded = written.to_lowercase();
        let mut tried = Vec::new();
        for dir in self.det_dirs(det_base) {
            for ext in std::iter::once("det").chain(mesh_import::MESH_EXTENSIONS.iter().copied()) {
                for name in [written, &folded] {
                    let p = dir.join(format!("{name}.{ext}"));
                    if tried.contains(&p) {
                        continue;
                    }
                    if p.is_file() {
                        return Ok(p);
                    }
                    tried.push(p);
                }
            }
        }
        Err(tried)
    }

    /// The geometry file of the active object ([`Self::object_file`]);
    /// one not found is looked up again, as the files are now, for the
    /// paths tried.
    fn find_object_file(&mut self, active: &ActiveObject) -> Result<PathBuf> {
        if let Some(path) = self.object_file(&active.written, &active.det_base) {
            return Ok(path);
        }
        let tried = match self.look_up_object_file(&active.written, &active.det_base) {
            Ok(path) => return Ok(path),
            Err(tried) => tried,
        };
        let shown = tried.len().min(6);
        let mut list: Vec<String> = tried[..shown]
            .iter()
            .map(|p| printable(&p.display().to_string(), MAX_SHOWN_PATH))
            .collect();
        if tried.len() > shown {
            list.push(format!("and {} more", tried.len() - shown));
        }
        Err(Error::at(
            active.location.clone(),
            format!(
                "no geometry file for object `{}` (tried {}); set `det_dir`",
                printable(&active.written, MAX_SHOWN_TOKEN),
                list.join(", ")
            ),
        ))
    }

    /// A colour file (`name.pcl` or `name.vcl`) of the detail directory.
    fn read_colors(
        &self,
        active: &ActiveObject,
        name: &str,
        loc: &Location,
        kind: ColorKind,
    ) -> Result<Vec<ColorEntry>> {
        let ext = match kind {
            ColorKind::Polygon => "pcl",
            ColorKind::Vertex => "vcl",
        };
        let folded = name.to_lowercase();
        for dir in self.det_dirs(&active.det_base) {
            for name in [name, folded.as_str()] {
                let p = dir.join(format!("{name}.{ext}"));
                if p.is_file() {
                    return object_file::read_colors(&p, kind);
                }
            }
        }
        Err(Error::at(
            loc.clone(),
            format!(
                "colour file `{}.{ext}` not found in the detail directory",
                printable(name, MAX_SHOWN_TOKEN)
            ),
        ))
    }
}

/// "no object `X` is defined", at the word that named it.
fn no_object(ctx: &Context, token: &Token) -> Error {
    ctx.error(
        token,
        format!(
            "no object `{}` is defined",
            printable(&token.text, MAX_SHOWN_TOKEN)
        ),
    )
}

/// Whether `path` names a `.det` object file (any case).
fn is_det(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("det"))
}

/// An object file read: a `.det` file, or a mesh format by its extension,
/// with at most `max_polygons` polygons.
pub(super) fn read_geometry(path: &Path, max_polygons: usize) -> Result<Mesh> {
    if is_det(path) {
        object_file::read_det_within(path, max_polygons)
    } else {
        mesh_import::read_mesh_within(path, max_polygons)
    }
}

/// The numbers the scene's objects use, for [`Interpreter::next_free_number`]
/// and `defobj n`'s check that `n` is free: brought up to date from the
/// objects added since the last call, told of those that leave (by
/// [`Interpreter::retain_objects`]), with the number below which all are
/// used. A call is then constant time on average; sorting every number at
/// every `endobj` made 40,000 objects take 2.4 s to read, growing as n^2,
/// and starting again after each deletion made a scene that deletes and
/// defines by turns pay for every number each time.
#[derive(Debug, Default, Clone)]
pub(in crate::scene) struct FreeNumbers {
    used: std::collections::HashSet<u32>,
    /// How many objects, from the first, have their numbers in `used`.
    seen: usize,
    /// Every number below it is used.
    below: u32,
}

impl FreeNumbers {
    /// Brings the numbers up to date with `objects`, which must be the
    /// last call's with objects added at the end (numbers of objects
    /// replaced in place unchanged); anything else starts afresh.
    fn update(&mut self, objects: &[Object]) {
        if objects.len() < self.seen {
            *self = FreeNumbers::default();
        }
        self.used
            .extend(objects[self.seen..].iter().map(|o| o.number));
        self.seen = objects.len();
    }

    /// Forgets `numbers`, of objects that left; `left` objects remain,
    /// those the numbers were up to date with less these (numbers are
    /// unique: `defobj n` refuses one in use).
    fn forget(&mut self, numbers: &[u32], left: usize) {
        for n in numbers {
            self.used.remove(n);
            self.below = self.below.min(*n);
        }
        self.seen = left;
    }

    /// Whether an object of `objects` has number `n`.
    fn uses(&mut self, objects: &[Object], n: u32) -> bool {
        self.update(objects);
        self.used.contains(&n)
    }

    /// The lowest number no object of `objects` uses.
    fn next_free(&mut self, objects: &[Object]) -> u32 {
        self.update(objects);
        while self.used.contains(&self.below) {
            self.below += 1;
        }
        self.below
    }
}
