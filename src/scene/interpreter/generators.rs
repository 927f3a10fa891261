//! The generator commands of Firebaugh's chapter 8 (001) inside `defobj`
//! ... `endobj`: `sphere`, `cylinder`, `superquadric`, `bezier`,
//! `hermite`, `lathe`, `extrude`, and the CSG commands `union`,
//! `intersection`, `difference` (see [`crate::modeling`]).
//!
//! The commands are parsed by [`crate::scene::parse`]; here they are
//! recorded in the active object and, at `endobj`, built.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::active::{ActiveObject, Pending};
use crate::budget::Budgets;
use crate::error::{
    Diagnostic, Error, Location, MAX_SHOWN_PATH, MAX_SHOWN_TOKEN, Result, printable,
};
use crate::math::Matrix4;
use crate::model::{ColorEntry, Mesh};
use crate::model::{Object, Surface, SurfaceType};
use crate::modeling::patch::{self, Form};
use crate::modeling::sweep::{self, Profile};
use crate::modeling::{Generated, Primitive, csg, solid};
use crate::scene::arguments::Context;
use crate::scene::build::{ObjectParts, build_object, warning_kind};
use crate::scene::commands::Verb;
use crate::scene::interpreter::Interpreter;
use crate::scene::lexer::Token;

/// The normals of an object transformed by `m` (row vectors: the inverse
/// transpose of its linear part); `None` if `m` is singular.
fn transform_normals(normals: &[DVec3], m: &Matrix4) -> Option<Vec<DVec3>> {
    let it = m.inverse()?.transpose();
    Some(
        normals
            .iter()
            .map(|n| it.transform_vector(*n).normalize_or_zero())
            .collect(),
    )
}

/// What `endobj` of a generated object needs besides the block.
pub(in crate::scene) struct Ending<'a> {
    pub ctx: &'a Context<'a>,
    pub cmd: &'a Token,
    /// The CTM at `endobj`.
    pub transform: Matrix4,
    /// The CTM at `defobj` (the one `endobj` restores).
    pub saved: Matrix4,
}

impl Interpreter {
    /// `lathe N r1 z1 ...`: the profile checked simple within the pair
    /// budget, then recorded.
    pub(in crate::scene) fn lathe(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        n: usize,
        points: &[DVec2],
    ) -> Result<()> {
        let profile = Profile::new_within(points.to_vec(), Some(self.budgets.pair_tests))
            .map_err(|e| ctx.error(cmd, e))?;
        let pending = Pending::Primitive(Primitive::Lathe { profile, n });
        self.add_generator(ctx, cmd, Verb::Lathe, pending)
    }

    /// `extrude DEPTH x1 y1 ...`: the outline checked simple within the
    /// pair budget, then recorded.
    pub(in crate::scene) fn extrude(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        depth: f64,
        points: &[DVec2],
    ) -> Result<()> {
        let outline = sweep::extrude_outline_within(points.to_vec(), Some(self.budgets.pair_tests))
            .map_err(|e| ctx.error(cmd, e))?;
        let pending = Pending::Primitive(Primitive::Extrude { outline, depth });
        self.add_generator(ctx, cmd, Verb::Extrude, pending)
    }

    /// Records the generator command `verb` in the active object.
    pub(in crate::scene) fn add_generator(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        verb: Verb,
        pending: Pending,
    ) -> Result<()> {
        let loc = ctx.location(cmd);
        let Some(active) = &mut self.active else {
            return Err(ctx.error(
                cmd,
                format!("`{}` outside an object definition", verb.name()),
            ));
        };
        if let Some((_, first)) = &active.generator {
            return Err(ctx.error(
                cmd,
                format!("an object has one generator; this one already has one at {first}"),
            ));
        }
        if active.geodesic.is_some() {
            return Err(ctx.error(
                cmd,
                "an object has one generator; this one has a `geodesic`",
            ));
        }
        if matches!(pending, Pending::Csg { .. })
            && let Some(at) = &active.surface_cmd
        {
            return Err(surface_in_csg(at));
        }
        active.generator = Some((pending, loc));
        Ok(())
    }

    /// `endobj` of an object with a generator.
    pub(in crate::scene) fn end_generated(
        &mut self,
        active: ActiveObject,
        pending: Pending,
        loc: Location,
        end: Ending,
    ) -> Result<()> {
        if active.geodesic.is_some() || active.copy_of.is_some() {
            return Err(Error::at(
                loc,
                "an object has one source of polygons: a generator, a `geodesic` or `callobj`",
            ));
        }
        let generated = match pending {
            Pending::Primitive(p) => {
                let faces = p.face_count().unwrap_or(usize::MAX);
                self.check_polygons(faces, &loc, &format!("this generator ({faces} polygons)"))?;
                let (vertices, corners) = p
                    .vertex_and_corner_counts()
                    .unwrap_or((usize::MAX, usize::MAX));
                self.check_model_memory(vertices, faces, corners, &loc)?;
                p.build()
            }
            Pending::Patches { form, file, nu, nv } => {
                self.read_patches(&active, form, &file, nu, nv, &loc)?
            }
            Pending::Csg { op, a, b } => return self.end_csg(active, op, a, b, loc, end),
        };
        let mut surface_type = active.surface_type;
        surface_type.open |= generated.open;
        surface_type.curved = generated.curved();
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        let Generated { mesh, normals, .. } = generated;
        self.push_object(
            &active,
            end,
            number,
            mesh,
            normals,
            active.surface,
            surface_type,
            None,
        )
    }

    /// Reads a patch file from the detail directory and tessellates it.
    fn read_patches(
        &self,
        active: &ActiveObject,
        form: Form,
        file: &str,
        nu: usize,
        nv: usize,
        loc: &Location,
    ) -> Result<Generated> {
        let Some(path) = self
            .det_dirs(&active.det_base)
            .into_iter()
            .map(|d| d.join(file))
            .find(|p| p.is_file())
        else {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "patch file `{}` not found in the detail directory",
                    printable(file, MAX_SHOWN_PATH)
                ),
            ));
        };
        let budget = |count: usize| {
            let faces = patch::face_count(count, nu, nv).unwrap_or(usize::MAX);
            self.check_polygons(
                faces,
                loc,
                &format!("{count} patches at {nu} x {nv} ({faces} triangles)"),
            )?;
            let vertices = count
                .checked_mul(nu.saturating_add(1))
                .and_then(|v| v.checked_mul(nv.saturating_add(1)))
                .unwrap_or(usize::MAX);
            self.check_model_memory(vertices, faces, faces.saturating_mul(3), loc)
        };
        let set = patch::read(&path, form, budget).map_err(|e| match e {
            Error::Input(mut d) => {
                d.included_from.push(loc.clone());
                Error::Input(d)
            }
            other => other,
        })?;
        Ok(patch::tessellate(&set, nu, nv))
    }

    /// Refuses a generated object whose `vertices`, `polygons` and
    /// `corners` would hold more than [`Budgets::model_memory`], before
    /// it is built.
    fn check_model_memory(
        &self,
        vertices: usize,
        polygons: usize,
        corners: usize,
        loc: &Location,
    ) -> Result<()> {
        let need = crate::modeling::model_bytes(vertices, polygons, corners);
        let limit = self.budgets.model_memory;
        if need <= limit {
            return Ok(());
        }
        Err(Error::at(
            loc.clone(),
            Budgets::exceeded(
                &format!(
                    "this generator's {vertices} vertices and {polygons} polygons ({} MiB)",
                    need.div_ceil(1 << 20)
                ),
                format!("{} MiB", limit >> 20),
                "--max-model-memory",
            ),
        ))
    }

    /// Builds and adds the object (transform, exact normals, budget).
    #[allow(clippy::too_many_arguments)]
    fn push_object(
        &mut self,
        active: &ActiveObject,
        end: Ending,
        number: u32,
        mesh: Mesh,
        normals: Option<Vec<DVec3>>,
        surface: Surface,
        surface_type: SurfaceType,
        polygon_colors: Option<Arc<Vec<ColorEntry>>>,
    ) -> Result<()> {
        let Ending {
            ctx,
            cmd,
            transform,
            ..
        } = end;
        let mut object = build_object(
            ObjectParts {
                number,
                name: active.name.clone(),
                mesh: Arc::new(mesh),
                polygon_colors,
                vertex_colors: None,
                transform,
                surface,
                surface_type,
            },
            &mut |msg| {
                let kind = warning_kind(&msg);
                self.warn(kind, Diagnostic::new(ctx.location(cmd), msg));
            },
        )
        .map_err(|msg| ctx.error(cmd, msg))?;
        if let Some(exact) = normals
            .as_deref()
            .and_then(|n| transform_normals(n, &transform))
        {
            object.vertex_normals = Some(exact);
        }
        self.check_polygons(
            object.polygons.len(),
            &active.location,
            &format!(
                "object `{}` ({} polygons)",
                printable(&active.written, MAX_SHOWN_TOKEN),
                object.polygons.len()
            ),
        )?;
        self.polygons += object.polygons.len();
        self.scene.objects.push(object);
        Ok(())
    }

    /// The operand of a CSG command: the last object of that name, closed.
    fn csg_operand(&self, name: &str, loc: &Location) -> Result<usize> {
        let Some(i) = self.scene.objects.iter().rposition(|o| o.name == name) else {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "no object `{}` is defined (a CSG operand is an object defined earlier)",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        };
        let o = &self.scene.objects[i];
        let polys: Vec<Vec<u32>> = o.polygons.iter().map(|p| p.indices.to_vec()).collect();
        if o.surface_type.open || polys.is_empty() {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "CSG operand `{}` is not a closed solid (it is open, or has no polygons)",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        }
        if let Err(why) = solid::check_closed(&solid::weld_exact(&o.vertices), &polys) {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "CSG operand `{}` is not a closed solid: {why}",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        }
        Ok(i)
    }

    /// `endobj` of a CSG block: the operands combined where they stand.
    fn end_csg(
        &mut self,
        active: ActiveObject,
        op: csg::Op,
        (a, aloc): (String, Location),
        (b, bloc): (String, Location),
        loc: Location,
        end: Ending,
    ) -> Result<()> {
        if let Some(at) = &active.surface_cmd {
            return Err(surface_in_csg(at));
        }
        let ia = self.csg_operand(&a, &aloc)?;
        let ib = self.csg_operand(&b, &bloc)?;
        if ia == ib {
            return Err(Error::at(bloc, "the two CSG operands are the same object"));
        }
        let names = (a.as_str(), b.as_str());
        let combined = self.combine(op, (ia, ib), names, &loc)?;
        // The operands are consumed.
        let (na, nb) = combined.numbers;
        self.retain_objects(|o| o.number != na && o.number != nb);
        let faces = combined.mesh.polygons.len();
        self.check_polygons(faces, &loc, &format!("the CSG result ({faces} faces)"))?;
        let end = Ending {
            transform: block_transform(&end, loc)?,
            ..end
        };
        let surface_type = SurfaceType {
            open: false,
            curved: combined.with_normals,
            concave: true,
            ..active.surface_type
        };
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        self.push_object(
            &active,
            end,
            number,
            combined.mesh,
            combined.normals,
            combined.surface,
            surface_type,
            Some(Arc::new(combined.colors)),
        )
    }

    /// The operands `ia` and `ib` (objects of the scene, named `names`)
    /// combined by `op` within the pair budget; the figures are a note,
    /// or a warning when the result is not closed.
    fn combine(
        &mut self,
        op: csg::Op,
        (ia, ib): (usize, usize),
        (a, b): (&str, &str),
        loc: &Location,
    ) -> Result<Combined> {
        let mut entries = Vec::new();
        let fa = operand_faces(&self.scene.objects[ia], &mut entries);
        let fb = operand_faces(&self.scene.objects[ib], &mut entries);
        let (oa, ob) = (&self.scene.objects[ia], &self.scene.objects[ib]);
        let with_normals = oa.vertex_normals.is_some() || ob.vertex_normals.is_some();
        let surface = oa.surface;
        let numbers = (oa.number, ob.number);
        if surfaces_differ(&oa.surface, &ob.surface) {
            self.warn(
                "csg",
                Diagnostic::new(
                    loc.clone(),
                    format!("warning: the CSG operands differ in specular, shininess, index or transparency; the result takes `{a}`'s (colour, diffuse, reflectance and transmittance are kept per face)"),
                ),
            );
        }
        let result =
            csg::combine_within(fa, fb, op, self.budgets.pair_tests).map_err(
                |stop| match stop {
                    csg::Stop::Cancelled => Error::Cancelled,
                    csg::Stop::Pairs(n) => Error::at(
                        loc.clone(),
                        Budgets::exceeded(
                            &format!("combining `{a}` and `{b}` ({n} face pair tests and more)"),
                            self.budgets.pair_tests,
                            "--max-pair-tests",
                        ),
                    ),
                },
            )?;
        let (mesh, normals, attrs) = csg::to_mesh(&result.faces, with_normals);
        self.report_csg(op, (a, b), &result.stats, &mesh, loc);
        Ok(Combined {
            colors: attrs.iter().map(|&i| entries[i as usize]).collect(),
            mesh,
            normals,
            surface,
            with_normals,
            numbers,
        })
    }

    /// A CSG result's figures: a note when it is closed (a result as
    /// asked is no warning), else a warning.
    fn report_csg(
        &mut self,
        op: csg::Op,
        (a, b): (&str, &str),
        s: &csg::Stats,
        mesh: &Mesh,
        loc: &Location,
    ) {
        let closed = solid::check_closed(&solid::weld_exact(&mesh.vertices), &mesh.polygons);
        let what = format!(
            "{} of `{a}` and `{b}`: {} input faces kept, {} split, {} removed; {} faces",
            match op {
                csg::Op::Union => "union",
                csg::Op::Intersection => "intersection",
                csg::Op::Difference => "difference",
            },
            s.kept,
            s.split,
            s.removed,
            mesh.polygons.len(),
        );
        match closed {
            Ok(()) => self.note(Diagnostic::new(loc.clone(), what)),
            Err(why) => self.warn(
                "csg",
                Diagnostic::new(
                    loc.clone(),
                    format!("warning: {what} (the result is not closed: {why})"),
                ),
            ),
        }
    }
}

/// A CSG result, before it is placed.
struct Combined {
    mesh: Mesh,
    normals: Option<Vec<DVec3>>,
    /// The material of each face.
    colors: Vec<ColorEntry>,
    /// The first operand's surface.
    surface: Surface,
    with_normals: bool,
    /// The operands' object numbers.
    numbers: (u32, u32),
}

/// Whether the attributes a CSG result cannot keep per face differ.
fn surfaces_differ(x: &Surface, y: &Surface) -> bool {
    x.specular != y.specular
        || x.shininess != y.shininess
        || x.index != y.index
        || x.transparency != y.transparency
}

/// Only the transforms written inside a CSG block: the CTM of `defobj`,
/// which placed the operands already, undone.
fn block_transform(end: &Ending, loc: Location) -> Result<Matrix4> {
    if end.transform == end.saved {
        return Ok(Matrix4::IDENTITY);
    }
    let Some(inv) = end.saved.inverse() else {
        return Err(Error::at(
            loc,
            "the transforms inside this CSG block cannot be applied: the CTM at `defobj` is singular",
        ));
    };
    Ok(inv.mul(&end.transform))
}

fn surface_in_csg(at: &Location) -> Error {
    Error::at(
        at.clone(),
        "a surface command inside a CSG block: the result keeps the surfaces of its operands, face by face",
    )
}

/// An object's world polygons as CSG faces; each face's material is
/// appended to `entries` and its index is the face's attribute.
fn operand_faces(o: &Object, entries: &mut Vec<ColorEntry>) -> Vec<csg::Face> {
    o.polygons
        .iter()
        .enumerate()
        .map(|(pi, p)| {
            let m = o.material(pi);
            entries.push(ColorEntry {
                color: m.color,
                diffuse: m.diffuse,
                reflectance: m.reflectance,
                transmittance: m.transmittance,
            });
            let points = p.indices.iter().map(|&i| o.vertices[i as usize]).collect();
            let normals = match &o.vertex_normals {
                Some(n) => p.indices.iter().map(|&i| n[i as usize]).collect(),
                None => vec![p.normal(); p.indices.len()],
            };
            csg::Face {
                points,
                normals,
                attr: (entries.len() - 1) as u32,
            }
        })
        .collect()
}
