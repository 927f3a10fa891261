//! The tools of `plytrace` besides rendering: Brown's tessellation check
//! (003 section 3), the patches' continuity (Firebaugh section 8), and
//! the shell completions and man page made from the command line's
//! definition.

use std::path::Path;
use std::process::ExitCode;

use plytrace::api::Budgets;
use plytrace::api::program::{parts, tools};

use crate::args::Tool;
use crate::term::{err, out, print_data, print_document, report};

/// Runs a tool.
pub fn run(tool: Tool) -> ExitCode {
    use tools::ConvertKind;
    match tool {
        Tool::Mkdet { args } => tools::run_convert(ConvertKind::Det, &args),
        Tool::Mkpcl { args } => tools::run_convert(ConvertKind::Pcl, &args),
        Tool::Mkvcl { args } => tools::run_convert(ConvertKind::Vcl, &args),
        Tool::Tessellation { file } => check_tessellation(&file),
        Tool::Continuity { file, form } => match tools::continuity_report(&file, form.as_deref()) {
            Ok(text) => {
                out(&text);
                ExitCode::SUCCESS
            }
            Err(e) => {
                report(&e);
                ExitCode::FAILURE
            }
        },
        Tool::Completions { shell } => {
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut crate::args::command(), "plytrace", &mut script);
            print_document(&script)
        }
        Tool::Merge {
            parts,
            output,
            separations,
            missing,
            count,
            max_pixels,
        } => {
            let mut budgets = Budgets::default();
            if let Some(n) = max_pixels {
                budgets.pixels = n;
            }
            if missing {
                list_missing(&parts, count, &budgets)
            } else {
                merge(&parts, output.as_deref(), separations, &budgets)
            }
        }
        Tool::Man => {
            let mut page = Vec::new();
            match clap_mangen::Man::new(crate::args::command()).render(&mut page) {
                Ok(()) => print_document(&page),
                Err(e) => {
                    err(&format!("error: the man page: {e}"));
                    ExitCode::FAILURE
                }
            }
        }
    }
}

/// `plytrace tessellation FILE`: Brown's Angle and Edge Conditions for a
/// triangulated surface about its origin.
fn check_tessellation(path: &Path) -> ExitCode {
    let is_det = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("det"));
    let mesh = if is_det {
        tools::read_det(path)
    } else {
        tools::read_mesh(path)
    };
    let mesh = match mesh {
        Ok(m) => m,
        Err(e) => {
            report(&e);
            return ExitCode::FAILURE;
        }
    };
    match tools::check_tessellation(&mesh, glam::DVec3::ZERO) {
        Ok(r) => {
            let yes = |b: bool| if b { "met" } else { "NOT met" };
            out(&format!(
                "{}: {} vertices, {} faces",
                path.display(),
                mesh.vertices.len(),
                mesh.polygons.len()
            ));
            out(&format!(
                "Angle Condition {}: adjacent patch edges at most {:.2} deg (limit 90), nonadjacent at least {:.2} deg (limit 90), degree up to {}",
                yes(r.angle_condition),
                r.max_adjacent_angle.to_degrees(),
                r.min_nonadjacent_angle.to_degrees(),
                r.max_degree
            ));
            out(&format!(
                "Edge Condition {}: longest patch edge {:.4} rad (limit 1), edge ratio up to {:.4} (limit 1.27)",
                yes(r.edge_condition),
                r.max_edge,
                r.max_edge_ratio
            ));
            ExitCode::SUCCESS
        }
        Err(e) => {
            err(&format!("error: {}: {e}", path.display()));
            ExitCode::FAILURE
        }
    }
}

/// `plytrace merge PARTS -o OUT`: the parts checked, then joined.
fn merge(
    parts: &[std::path::PathBuf],
    output: Option<&Path>,
    separations: bool,
    budgets: &Budgets,
) -> ExitCode {
    use parts::MergeFormat;
    if separations && output.is_none() {
        err("error: merge --separations needs -o SEED (the separations are SEED.r, .g, .b)");
        return ExitCode::from(2);
    }
    let format = separations.then_some(MergeFormat::Separations);
    match parts::merge(parts, output, format, budgets) {
        Ok(m) => {
            let names: Vec<String> = m.written.iter().map(|p| p.display().to_string()).collect();
            out(&format!(
                "Merged {} parts into {} ({} x {})",
                m.parts,
                names.join(", "),
                m.size.0,
                m.size.1
            ));
            ExitCode::SUCCESS
        }
        Err(e) => {
            report(&e);
            ExitCode::FAILURE
        }
    }
}

/// `plytrace merge --missing PARTS`: the indices of the parts still to
/// render, comma-separated on standard output (nothing when all are
/// there). The list is what a job array is submitted again from, so a
/// failure to write it (a full disk, a closed pipe) is an error.
fn list_missing(parts: &[std::path::PathBuf], count: Option<u32>, budgets: &Budgets) -> ExitCode {
    match parts::missing(parts, count, budgets) {
        Ok((missing, warnings)) => {
            for w in warnings {
                err(&format!("warning: {w}"));
            }
            if missing.is_empty() {
                return ExitCode::SUCCESS;
            }
            let list: Vec<String> = missing.iter().map(u32::to_string).collect();
            print_data(
                format!("{}\n", list.join(",")).as_bytes(),
                "the list of missing parts",
            )
        }
        Err(e) => {
            report(&e);
            ExitCode::FAILURE
        }
    }
}
