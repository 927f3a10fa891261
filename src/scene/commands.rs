//! The command table of the scene descriptor language (Garcia 1986, 004
//! appendix, plytrace manual page): names, arguments and one-line help.
//!
//! The manual: "all input characters are converted to lower case before
//! processing and ... commands are recognized by the first sequence of
//! unique characters". Commands are therefore case-insensitive and
//! recognized by a unique prefix; an exact name always wins (`ortho`
//! versus `ortho2`). The table also holds commands the manual does not
//! have (the modeling commands of Firebaugh's chapter and Brown's
//! geodesics: [`ADDED`]); they must not take an abbreviation away from
//! the manual's own commands. So a word is looked up first among the
//! manual's commands ([`MANUAL`]): a prefix unique there names that
//! command even if an added command shares it (`b` is `background`, not
//! `bezier`; `e` is `endobj`); a prefix of several manual commands is
//! ambiguous; a prefix of no manual command is looked up among the added
//! ones (`be` is `bezier`, `sph` is `sphere`).

/// A command of the language.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandSpec {
    /// The full name.
    pub name: &'static str,
    /// Its arguments, as the manual writes them.
    pub usage: &'static str,
    /// What it does.
    pub help: &'static str,
}

macro_rules! commands {
    ($( $name:literal, $usage:literal, $help:literal; )*) => {
        /// Every command, in the manual's (alphabetical) order.
        pub const COMMANDS: &[CommandSpec] = &[
            $( CommandSpec { name: $name, usage: $usage, help: $help }, )*
        ];
    };
}

commands! {
    "ambient", "r g b", "ambient illumination colour (default 1 1 1)";
    "background", "r g b", "background colour (default 0 0 0)";
    "bezier", "FILE NU NV", "in defobj: bicubic Bezier patches (Firebaugh eq. 8.6) from det_dir/FILE, e.g. bezier teapot.bpt 8 8";
    "call", "file", "read commands from a file without initializing";
    "callobj", "obj-number", "copy geometry and colours of an existing object";
    "clear", "", "clear the frame buffer to the background colour";
    "color", "r g b", "global or active object colour (default 1 1 1)";
    "cylinder", "NU [capped|open]", "in defobj: radius 1 about z, z -1..1, NU steps, e.g. cylinder 32 open";
    "defobj", "name [number]", "begin an object read from name.det in the detail directory";
    "delobj", "number...", "delete objects";
    "depth", "1-14", "maximum reflection/refraction recursion depth (default 1)";
    "det_dir", "path", "detail directory for .det/.pcl/.vcl files (default det/)";
    "difference", "A B", "in defobj: CSG A - B of two closed objects (consumed), e.g. difference plate hole";
    "diffuse", "k", "diffuse coefficient (default 0.6)";
    "disp", "[on|off]", "show the tree level by level in a window (build feature `display`); files are written either way";
    "endobj", "", "end the object: read its files and transform it by the CTM";
    "extrude", "DEPTH x1 y1 ... xk yk", "in defobj: a simple outline swept z 0..DEPTH, capped, e.g. extrude 0.5 0 0 1 0 1 1";
    "fname", "name", "output file name (name.png, name.out)";
    "geodesic", "n [equal|angle]", "in defobj: a geodesic icosahedron, n divisions per edge (Brown 1978)";
    "get", "file", "initialize, then read commands from a file";
    "getobj", "name", "defobj name followed by endobj";
    "hermite", "FILE NU NV", "in defobj: bicubic Hermite patches (Firebaugh eq. 8.16-8.18), e.g. hermite wave.hpt 8 8";
    "ident", "", "load the identity on the CTM";
    "index", "n", "index of refraction (default 1)";
    "init", "", "reset all parameters, objects and lights to their defaults";
    "intersection", "A B", "in defobj: CSG A and B of two closed objects (consumed), e.g. intersection ball box";
    "lathe", "N r1 z1 ... rk zk", "in defobj: a profile (r, z) spun N steps about z, e.g. lathe 24 0 0 1 0 1 2 0 2";
    "light", "x y z r g b range [Point|Diffuse]", "add a light (Point casts shadows)";
    "lookat", "vx vy vz px py pz twist", "view from v towards p (pre-multiplies the CTM)";
    "nolight", "", "delete all lights";
    "ortho", "left right bottom top near far", "load an orthographic projection";
    "ortho2", "left right bottom top", "load a 2D orthographic projection";
    "outmode", "c|r|g|b|y|a bits", "colour output mode (default c)";
    "pcolors", "file", "polygon colours of the active object (file.pcl)";
    "perspective", "fovy aspect near far", "load a perspective projection";
    "polarview", "dist azim inc twist", "view in polar coordinates (pre-multiplies the CTM)";
    "popmatrix", "", "pop the CTM from the matrix stack";
    "pushmatrix", "", "push a copy of the CTM on the matrix stack";
    "quit", "", "end the program";
    "radial", "sphere|ellipsoid a b c|bumps amp freq|lobes amp k|rotate angle x|y|z", "a geodesic's radial function (in defobj); `rotate` turns it inside the fixed vertex directions (outside defobj: every geodesic's)";
    "reflectance", "k", "reflection coefficient (default 0)";
    "resolution", "hres vres", "image size; loads perspective 45 hres/vres 0.01 10000";
    "rotate", "angle x|y|z", "rotation (pre-multiplies the CTM)";
    "run", "[y]", "render the scene (y: with shadows)";
    "scale", "sx sy sz", "scaling (pre-multiplies the CTM)";
    "setmode", "mode [value]", "set a run-time mode: b d e h l n o p s v x or a digit, as the flags of the same letters (a bare on/off mode is on)";
    "shininess", "n", "Phong exponent of highlights";
    "sort", "[btf|ftb]", "polygon order: back to front (default) or front to back";
    "specular", "k", "specular coefficient (default 0)";
    "sphere", "NU NV", "in defobj: the unit sphere, NU steps of longitude, NV of latitude, e.g. sphere 24 12";
    "superquadric", "E1 E2 NU NV [AX AY AZ]", "in defobj: a superquadric (Firebaugh eq. 8.22), e.g. superquadric 0.5 1 24 12 1 1 2";
    "threshold", "k", "smallest coefficient worth tracing (default 0)";
    "translate", "tx ty tz", "translation (pre-multiplies the CTM)";
    "transmittance", "k", "transmission coefficient (default 0)";
    "transparency", "t rolloff", "linear transparency and its roll-off (default 0 0)";
    "type", "polygon [open curved concave hidden ltsrc]", "surface type attributes";
    "union", "A B", "in defobj: CSG A or B of two closed objects (consumed), e.g. union head shaft";
    "vcolors", "file", "vertex colours of the active object (file.vcl)";
    "viewport", "left right bottom top", "image region in pixels";
    "wait", "", "wait for a key in the display window, else for return (terminal only)";
    "window", "left right bottom top near far", "load a perspective frustum";
}

/// The commands of the manual page (004 appendix B), in its order.
pub const MANUAL: &[&str] = &[
    "ambient",
    "background",
    "call",
    "callobj",
    "clear",
    "color",
    "defobj",
    "delobj",
    "depth",
    "det_dir",
    "diffuse",
    "disp",
    "endobj",
    "fname",
    "get",
    "getobj",
    "ident",
    "index",
    "init",
    "light",
    "lookat",
    "nolight",
    "ortho",
    "ortho2",
    "outmode",
    "pcolors",
    "perspective",
    "polarview",
    "popmatrix",
    "pushmatrix",
    "quit",
    "reflectance",
    "resolution",
    "rotate",
    "run",
    "scale",
    "setmode",
    "shininess",
    "sort",
    "specular",
    "threshold",
    "translate",
    "transmittance",
    "transparency",
    "type",
    "vcolors",
    "viewport",
    "wait",
    "window",
];

/// The commands added to the manual's (modeling): every other name of
/// [`COMMANDS`].
pub const ADDED: &[&str] = &[
    "bezier",
    "cylinder",
    "difference",
    "extrude",
    "geodesic",
    "hermite",
    "intersection",
    "lathe",
    "radial",
    "sphere",
    "superquadric",
    "union",
];

/// Whether `name` is one of the manual's commands.
pub fn is_manual(name: &str) -> bool {
    MANUAL.contains(&name)
}

/// The result of looking a word up in the table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Lookup {
    /// Exactly one command.
    Found(&'static CommandSpec),
    /// No command starts with the word; the closest name, if any is close.
    Unknown(Option<&'static str>),
    /// Several commands start with the word.
    Ambiguous(Vec<&'static str>),
}

/// The command named exactly `name`.
pub fn spec(name: &str) -> &'static CommandSpec {
    COMMANDS
        .iter()
        .find(|c| c.name == name)
        .expect("a command of the table")
}

/// Finds the command `word` names (case-insensitive, unique prefix; the
/// manual's commands first, see the module comment).
pub fn lookup(word: &str) -> Lookup {
    let w = word.to_ascii_lowercase();
    if let Some(c) = COMMANDS.iter().find(|c| c.name == w) {
        return Lookup::Found(c);
    }
    let starting = |manual: bool| -> Vec<&'static CommandSpec> {
        COMMANDS
            .iter()
            .filter(|c| is_manual(c.name) == manual && c.name.starts_with(&w))
            .collect()
    };
    let mut matches = starting(true);
    if matches.is_empty() {
        matches = starting(false);
    }
    match matches.len() {
        0 => Lookup::Unknown(closest(&w)),
        1 => Lookup::Found(matches[0]),
        _ => Lookup::Ambiguous(matches.iter().map(|c| c.name).collect()),
    }
}

/// The command name nearest `word` by edit distance, if near enough.
/// The distance is at least the difference in length, so names that
/// differ more than that are not measured: a 16 MB unknown word costs no
/// more than a short one.
fn closest(word: &str) -> Option<&'static str> {
    let len = word.chars().count();
    COMMANDS
        .iter()
        .map(|c| (c.name, 2.max(c.name.len() / 4)))
        .filter(|&(name, limit)| len.abs_diff(name.len()) <= limit)
        .map(|(name, limit)| (edit_distance(word, name), name, limit))
        .filter(|&(d, _, limit)| d <= limit)
        .map(|(d, name, _)| (d, name))
        .min()
        .map(|(_, n)| n)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = if ca == *cb {
                prev
            } else {
                1 + prev.min(cur).min(row[j])
            };
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_and_exact_names() {
        match lookup("TRANSL") {
            Lookup::Found(c) => assert_eq!(c.name, "translate"),
            other => panic!("{other:?}"),
        }
        assert_eq!(lookup("ortho").clone(), lookup("ORTHO"));
        match lookup("ortho") {
            Lookup::Found(c) => assert_eq!(c.name, "ortho"),
            other => panic!("{other:?}"),
        }
        match lookup("ortho2") {
            Lookup::Found(c) => assert_eq!(c.name, "ortho2"),
            other => panic!("{other:?}"),
        }
        match lookup("po") {
            Lookup::Ambiguous(v) => assert_eq!(v, ["polarview", "popmatrix"]),
            other => panic!("{other:?}"),
        }
        match lookup("pol") {
            Lookup::Found(c) => assert_eq!(c.name, "polarview"),
            other => panic!("{other:?}"),
        }
        assert_eq!(lookup("tranlate"), Lookup::Unknown(Some("translate")));
        assert_eq!(lookup("zzzz"), Lookup::Unknown(None));
    }

    /// `closest` skips names by length; it must suggest what measuring
    /// every name would, on words one, two and three edits from each name.
    #[test]
    fn the_length_filter_keeps_every_suggestion() {
        let every = |w: &str| {
            COMMANDS
                .iter()
                .map(|c| (edit_distance(w, c.name), c.name))
                .filter(|(d, name)| *d <= 2.max(name.len() / 4))
                .min()
                .map(|(_, n)| n)
        };
        let mut words = vec![String::new(), "x".repeat(100_000)];
        for c in COMMANDS {
            for k in 0..=c.name.len() {
                let (head, tail) = c.name.split_at(k);
                words.push(format!("{head}q{tail}"));
                words.push(format!("{head}qq{tail}"));
                words.push(format!("{head}qqq{tail}"));
                words.push(format!("{head}{}", tail.get(1..).unwrap_or("")));
                words.push(format!("{head}{}", tail.get(3..).unwrap_or("")));
            }
        }
        for w in &words {
            assert_eq!(closest(w), every(w), "{:.40}", w);
        }
    }

    /// The manual's and the added commands together are the table.
    #[test]
    fn manual_and_added_commands_partition_the_table() {
        let mut both: Vec<&str> = MANUAL.iter().chain(ADDED).copied().collect();
        both.sort_unstable();
        let table: Vec<&str> = COMMANDS.iter().map(|c| c.name).collect();
        assert_eq!(both, table);
    }

    #[test]
    fn table_is_sorted_and_unique() {
        for w in COMMANDS.windows(2) {
            assert!(w[0].name < w[1].name, "{} {}", w[0].name, w[1].name);
        }
    }
}
