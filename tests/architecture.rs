//! Data flows one way: the library's files import only from their own
//! stage of the pipeline or from the stages before it (Garcia 1986, 004
//! figure 3.2: scene -> geometry -> visibility -> image tree -> records ->
//! scan conversion -> output), and no two files import each other, directly
//! or around a circle. `ARCHITECTURE.md` draws the same stages.
//!
//! Imports are read from the source: every `crate::a::b` path outside
//! comments and `#[cfg(test)]` modules names the longest module it starts
//! with. A module's own submodules belong to it (a parent re-exports its
//! children's types and a child uses its parent's), so only imports
//! between siblings and across folders count.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The stages, first to last: a module path prefix and its stage. The
/// longest prefix that matches a module decides.
const STAGES: &[(&str, u8)] = &[
    // Foundations: no stage of their own.
    ("math", 0),
    ("precision", 0),
    ("error", 0),
    ("cancel", 0),
    ("threads", 0),
    ("budget", 0),
    ("profile", 0),
    ("input_guard", 0),
    // The world the scene builds: objects, polygons, materials, lights.
    ("model", 1),
    // Geometry and the modeling primitives that make polygons.
    ("geometry", 2),
    ("modeling", 2),
    // The scene descriptor language and object files.
    ("scene", 3),
    // Shading, shadows and the list-priority sorts.
    ("shading", 4),
    ("shadow", 4),
    ("visibility", 4),
    // The virtual image tree.
    ("image_tree", 5),
    // One stream of tree records.
    ("emit", 6),
    ("tree", 6),
    // Scan conversion and vector drawing of the records.
    ("raster", 7),
    ("vector", 7),
    // Renderers that paint an image themselves.
    ("visibility/z_buffer", 8),
    ("visibility/scan_line", 8),
    ("visibility/warnock", 8),
    ("visibility/ray_cast", 8),
    ("raytrace", 8),
    // Files.
    ("output", 9),
    ("part", 9),
    // The pipeline run in order.
    ("render", 10),
    // The manual's programs, the display, signals.
    ("rftb", 11),
    ("convert", 11),
    ("display", 11),
    ("signals", 11),
    // A run of the scene language with its files.
    ("run", 11),
    // The front: the library API (with `api/program`, what the programs
    // use), the last stage: nothing in the library imports it.
    ("api", 12),
];

fn stage(module: &str) -> u8 {
    STAGES
        .iter()
        .filter(|(p, _)| module == *p || module.starts_with(&format!("{p}/")))
        .max_by_key(|(p, _)| p.len())
        .unwrap_or_else(|| panic!("module `{module}` has no stage in STAGES"))
        .1
}

/// `src/a/b.rs` and `src/a/b/mod.rs` are module `a/b`.
fn module_name(path: &Path, src: &Path) -> String {
    let rel = path.strip_prefix(src).unwrap().with_extension("");
    let name = rel.to_string_lossy().replace('\\', "/");
    name.strip_suffix("/mod").unwrap_or(&name).to_string()
}

fn sources(dir: &Path, src: &Path, out: &mut BTreeMap<String, String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if path.file_name().unwrap() != "bin" {
                sources(&path, src, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs")
            && path.file_name().unwrap() != "lib.rs"
        {
            let text = std::fs::read_to_string(&path).unwrap();
            out.insert(module_name(&path, src), text);
        }
    }
}

/// The code of a file without its tests and comments.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|l| l.split(" // ").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The modules that the code `text` of module `module` names by
/// `crate::` and `super::` paths.
fn imports(module: &str, text: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let parent = module.rsplit_once('/').map_or("", |(p, _)| p);
    let mut out = BTreeSet::new();
    for (root, base) in [("crate::", ""), ("super::", parent)] {
        for (at, _) in text.match_indices(root) {
            let path: String = text[at + root.len()..]
                .chars()
                .take_while(|c| {
                    c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_' || *c == ':'
                })
                .collect();
            let mut parts: Vec<&str> = base.split('/').filter(|p| !p.is_empty()).collect();
            parts.extend(path.split("::").filter(|p| !p.is_empty()));
            if let Some(m) = (1..=parts.len())
                .rev()
                .map(|k| parts[..k].join("/"))
                .find(|m| modules.contains(m))
            {
                out.insert(m);
            }
        }
    }
    out
}

/// Whether one of `a`, `b` contains the other (a module and its submodule).
fn related(a: &str, b: &str) -> bool {
    a == b || a.starts_with(&format!("{b}/")) || b.starts_with(&format!("{a}/"))
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    sources(&src, &src, &mut files);
    assert!(files.len() > 50, "{} library files found", files.len());
    let modules: BTreeSet<String> = files.keys().cloned().collect();
    files
        .iter()
        .map(|(m, text)| {
            let deps = imports(m, &code(text), &modules)
                .into_iter()
                .filter(|d| !related(m, d))
                .collect();
            (m.clone(), deps)
        })
        .collect()
}

#[test]
fn every_import_goes_to_the_same_stage_or_an_earlier_one() {
    let upward: Vec<String> = graph()
        .iter()
        .flat_map(|(m, deps)| deps.iter().map(move |d| (m, d)))
        .filter(|(m, d)| stage(d) > stage(m))
        .map(|(m, d)| format!("{m} (stage {}) imports {d} (stage {})", stage(m), stage(d)))
        .collect();
    assert!(
        upward.is_empty(),
        "imports against the flow:\n{}",
        upward.join("\n")
    );
}

/// A circle of imports in `graph`, if there is one.
fn circle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    // Depth-first search; a grey node met again closes a circle.
    fn visit<'a>(
        m: &'a str,
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<&'a str, u8>,
        path: &mut Vec<&'a str>,
    ) -> Option<Vec<String>> {
        match state.get(m) {
            Some(1) => {
                let start = path.iter().position(|p| *p == m).unwrap();
                let mut circle: Vec<String> = path[start..].iter().map(|s| s.to_string()).collect();
                circle.push(m.to_string());
                return Some(circle);
            }
            Some(_) => return None,
            None => {}
        }
        state.insert(m, 1);
        path.push(m);
        for d in graph.get(m).into_iter().flatten() {
            if let Some(c) = visit(d, graph, state, path) {
                return Some(c);
            }
        }
        path.pop();
        state.insert(m, 2);
        None
    }
    let mut state = BTreeMap::new();
    graph
        .keys()
        .find_map(|m| visit(m, graph, &mut state, &mut Vec::new()))
}

#[test]
fn no_two_files_import_each_other_around_a_circle() {
    let found = circle(&graph());
    assert!(
        found.is_none(),
        "a circle of imports: {}",
        found.unwrap().join(" -> ")
    );
}

/// The imports between the files of the `plytrace` program
/// (`cli/src/bin/plytrace`), by `crate::` paths.
fn program_graph() -> BTreeMap<String, BTreeSet<String>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cli/src/bin/plytrace");
    let mut files = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            files.insert(module_name(&path, &dir), text);
        }
    }
    assert!(files.len() > 5, "{} program files found", files.len());
    let modules: BTreeSet<String> = files.keys().cloned().collect();
    files
        .iter()
        .map(|(m, text)| {
            let deps = imports(m, &code(text), &modules);
            (m.clone(), deps.into_iter().filter(|d| d != m).collect())
        })
        .collect()
}

#[test]
fn settings_flow_into_a_run_and_a_run_into_its_report() {
    // The program's files: the settings (`args`) import no run, the run
    // (`host`) no session, the report (`stats`) neither.
    let graph = program_graph();
    let found = circle(&graph);
    assert!(
        found.is_none(),
        "a circle of imports in cli/src/bin/plytrace: {}",
        found.unwrap().join(" -> ")
    );
    for (file, not) in [("args", "host"), ("host", "session"), ("stats", "host")] {
        assert!(!graph[file].contains(not), "{file} imports {not}");
    }
}

#[test]
fn the_import_reader_sees_imports_and_skips_comments_and_tests() {
    let modules: BTreeSet<String> = [
        "model",
        "render",
        "raster/scan",
        "raster/scan/edge",
        "raster/scan/tiler",
    ]
    .map(String::from)
    .into();
    let text = "use crate::model::Scene;\n/// [`crate::render::plan`]\nuse super::edge::Edge;\n\
                let x = crate::raster::scan::Row;\n#[cfg(test)]\nuse crate::render;";
    let found = imports("raster/scan/tiler", &code(text), &modules);
    assert_eq!(
        found,
        ["model", "raster/scan", "raster/scan/edge"]
            .map(String::from)
            .into()
    );
    assert_eq!(stage("visibility/z_buffer"), 8);
    assert_eq!(stage("visibility/nns"), 4);
    assert!(
        related("raster/scan", "raster/scan/band") && !related("raster/scan", "raster/scanner")
    );
}
