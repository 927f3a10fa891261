//! The command table of the scene descriptor language (Garcia 1986, 004
//! appendix, plytrace manual page): names, arguments and one-line help.
//!
//! The manual: "all input characters are converted to lower case before
//! processing and ... commands are recognized by the first sequence of
//! unique characters". Commands are therefore case-insensitive and
//! recognized by a unique prefix; an exact name always wins (`ortho`
//! versus `ortho2`). The table also holds commands the manual does not
//! have (the modeling commands of Firebaugh's chapter and Brown's
//! geodesics, marked `added` in the table: [`ADDED`]); they must not take
//! an abbreviation away from the manual's own commands. So a word is
//! looked up first among the manual's commands ([`MANUAL`]): a prefix
//! unique there names that command even if an added command shares it
//! (`b` is `background`, not `bezier`; `e` is `endobj`); a prefix of
//! several manual commands is ambiguous; a prefix of no manual command is
//! looked up among the added ones (`be` is `bezier`, `sph` is `sphere`).
//!
//! Each line of the table makes a [`CommandSpec`] and a [`Verb`]: the
//! parser, the prompt's `help`, its completion and `--help` all read this
//! one table.

/// A command of the language.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandSpec {
    /// The command's word as a type: the parser turns a statement of this
    /// command into the `Command` variant of the same name.
    pub verb: Verb,
    /// The full name.
    pub name: &'static str,
    /// Whether the manual page (004 appendix B) has the command; the
    /// others are added (modeling), and never take an abbreviation from a
    /// manual command (see the module comment).
    pub manual: bool,
    /// Its arguments, as the manual writes them.
    pub usage: &'static str,
    /// What it does.
    pub help: &'static str,
}

/// `manual` or `added` in the table, as a `bool`.
macro_rules! is_manual {
    (manual) => {
        true
    };
    (added) => {
        false
    };
}

/// The one table: each line makes a [`CommandSpec`] of [`COMMANDS`] and
/// the [`Verb`] variant that names it, so that a command cannot be in the
/// table without a type or have a type without a table entry.
macro_rules! commands {
    ($( $verb:ident $name:literal $origin:ident, $usage:literal, $help:literal; )*) => {
        /// Every command, in the manual's (alphabetical) order.
        pub const COMMANDS: &[CommandSpec] = &[
            $( CommandSpec {
                verb: Verb::$verb,
                name: $name,
                manual: is_manual!($origin),
                usage: $usage,
                help: $help,
            }, )*
        ];

        /// The word of a statement: one variant per entry of [`COMMANDS`],
        /// in its order.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Verb {
            $( #[doc = concat!("`", $name, " ", $usage, "`: ", $help)] $verb, )*
        }

        impl Verb {
            /// Every verb, in the order of [`COMMANDS`].
            pub const ALL: &[Verb] = &[ $( Verb::$verb, )* ];
        }
    };
}

impl Verb {
    /// The verb's entry in [`COMMANDS`].
    pub fn spec(self) -> &'static CommandSpec {
        &COMMANDS[self as usize]
    }

    /// The command's full name.
    pub fn name(self) -> &'static str {
        self.spec().name
    }
}

commands! {
    Ambient "ambient" manual, "r g b", "ambient illumination colour (default 1 1 1)";
    Background "background" manual, "r g b", "background colour (default 0 0 0)";
    Bezier "bezier" added, "FILE NU NV", "in defobj: bicubic Bezier patches (Firebaugh eq. 8.6) from det_dir/FILE, e.g. bezier teapot.bpt 8 8";
    Call "call" manual, "file", "read commands from a file without initializing";
    Callobj "callobj" manual, "obj-number", "copy geometry and colours of an existing object";
    Clear "clear" manual, "", "clear the frame buffer to the background colour";
    Color "color" manual, "r g b", "global or active object colour (default 1 1 1)";
    Cylinder "cylinder" added, "NU [capped|open]", "in defobj: radius 1 about z, z -1..1, NU steps, e.g. cylinder 32 open";
    Defobj "defobj" manual, "name [number]", "begin an object read from name.det in the detail directory";
    Delobj "delobj" manual, "number...", "delete objects";
    Depth "depth" manual, "1-14", "maximum reflection/refraction recursion depth (default 1)";
    DetDir "det_dir" manual, "path", "detail directory for .det/.pcl/.vcl files (default det/)";
    Difference "difference" added, "A B", "in defobj: CSG A - B of two closed objects (consumed), e.g. difference plate hole";
    Diffuse "diffuse" manual, "k", "diffuse coefficient (default 0.6)";
    Disp "disp" manual, "[on|off]", "show the tree level by level in a window (build feature `display`); files are written either way";
    Endobj "endobj" manual, "", "end the object: read its files and transform it by the CTM";
    Extrude "extrude" added, "DEPTH x1 y1 ... xk yk", "in defobj: a simple outline swept z 0..DEPTH, capped, e.g. extrude 0.5 0 0 1 0 1 1";
    Fname "fname" manual, "name", "output file name (name.png, name.out)";
    Geodesic "geodesic" added, "n [equal|angle]", "in defobj: a geodesic icosahedron, n divisions per edge (Brown 1978)";
    Get "get" manual, "file", "initialize, then read commands from a file";
    Getobj "getobj" manual, "name", "defobj name followed by endobj";
    Hermite "hermite" added, "FILE NU NV", "in defobj: bicubic Hermite patches (Firebaugh eq. 8.16-8.18), e.g. hermite wave.hpt 8 8";
    Ident "ident" manual, "", "load the identity on the CTM";
    Index "index" manual, "n", "index of refraction (default 1)";
    Init "init" manual, "", "reset all parameters, objects and lights to their defaults";
    Intersection "intersection" added, "A B", "in defobj: CSG A and B of two closed objects (consumed), e.g. intersection ball box";
    Lathe "lathe" added, "N r1 z1 ... rk zk", "in defobj: a profile (r, z) spun N steps about z, e.g. lathe 24 0 0 1 0 1 2 0 2";
    Light "light" manual, "x y z r g b range [Point|Diffuse]", "add a light (Point casts shadows)";
    Lookat "lookat" manual, "vx vy vz px py pz twist", "view from v towards p (pre-multiplies the CTM)";
    Nolight "nolight" manual, "", "delete all lights";
    Ortho "ortho" manual, "left right bottom top near far", "load an orthographic projection";
    Ortho2 "ortho2" manual, "left right bottom top", "load a 2D orthographic projection";
    Outmode "outmode" manual, "c|r|g|b|y|a bits", "colour output mode (default c)";
    Pcolors "pcolors" manual, "file", "polygon colours of the active object (file.pcl)";
    Perspective "perspective" manual, "fovy aspect near far", "load a perspective projection";
    Polarview "polarview" manual, "dist azim inc twist", "view in polar coordinates (pre-multiplies the CTM)";
    Popmatrix "popmatrix" manual, "", "pop the CTM from the matrix stack";
    Pushmatrix "pushmatrix" manual, "", "push a copy of the CTM on the matrix stack";
    Quit "quit" manual, "", "end the program";
    Radial "radial" added, "sphere|ellipsoid a b c|bumps amp freq|lobes amp k|rotate angle x|y|z", "a geodesic's radial function (in defobj); `rotate` turns it inside the fixed vertex directions (outside defobj: every geodesic's)";
    Reflectance "reflectance" manual, "k", "reflection coefficient (default 0)";
    Resolution "resolution" manual, "hres vres", "image size; loads perspective 45 hres/vres 0.01 10000";
    Rotate "rotate" manual, "angle x|y|z", "rotation (pre-multiplies the CTM)";
    Run "run" manual, "[y]", "render the scene (y: with shadows)";
    Scale "scale" manual, "sx sy sz", "scaling (pre-multiplies the CTM)";
    Setmode "setmode" manual, "mode [value]", "set a run-time mode: b d e h l n o p s v x or a digit, as the flags of the same letters (a bare on/off mode is on)";
    Shininess "shininess" manual, "n", "Phong exponent of highlights";
    Sort "sort" manual, "[btf|ftb]", "polygon order: back to front (default) or front to back";
    Specular "specular" manual, "k", "specular coefficient (default 0)";
    Sphere "sphere" added, "NU NV", "in defobj: the unit sphere, NU steps of longitude, NV of latitude, e.g. sphere 24 12";
    Superquadric "superquadric" added, "E1 E2 NU NV [AX AY AZ]", "in defobj: a superquadric (Firebaugh eq. 8.22), e.g. superquadric 0.5 1 24 12 1 1 2";
    Threshold "threshold" manual, "k", "smallest coefficient worth tracing (default 0)";
    Translate "translate" manual, "tx ty tz", "translation (pre-multiplies the CTM)";
    Transmittance "transmittance" manual, "k", "transmission coefficient (default 0)";
    Transparency "transparency" manual, "t rolloff", "linear transparency and its roll-off (default 0 0)";
    Type "type" manual, "polygon [open curved concave hidden ltsrc]", "surface type attributes";
    Union "union" added, "A B", "in defobj: CSG A or B of two closed objects (consumed), e.g. union head shaft";
    Vcolors "vcolors" manual, "file", "vertex colours of the active object (file.vcl)";
    Viewport "viewport" manual, "left right bottom top", "image region in pixels";
    Wait "wait" manual, "", "wait for a key in the display window, else for return (terminal only)";
    Window "window" manual, "left right bottom top near far", "load a perspective frustum";
}

/// The commands of the manual page (004 appendix B), in its order: those
/// marked `manual` in the table.
pub const MANUAL: &[&str] = &names::<{ count(true) }>(true);

/// The commands added to the manual's (modeling): every other name of
/// [`COMMANDS`].
pub const ADDED: &[&str] = &names::<{ count(false) }>(false);

/// How many commands of the table are (or are not) the manual's.
const fn count(manual: bool) -> usize {
    let (mut n, mut i) = (0, 0);
    while i < COMMANDS.len() {
        if COMMANDS[i].manual == manual {
            n += 1;
        }
        i += 1;
    }
    n
}

/// The names of the `N` commands that are (or are not) the manual's.
const fn names<const N: usize>(manual: bool) -> [&'static str; N] {
    let mut out = [""; N];
    let (mut i, mut k) = (0, 0);
    while i < COMMANDS.len() {
        if COMMANDS[i].manual == manual {
            out[k] = COMMANDS[i].name;
            k += 1;
        }
        i += 1;
    }
    out
}

/// Whether `name` is one of the manual's commands.
pub fn is_manual(name: &str) -> bool {
    COMMANDS.iter().any(|c| c.manual && c.name == name)
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
            .filter(|c| c.manual == manual && c.name.starts_with(&w))
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

    /// The commands marked `manual` are those of the manual page (004
    /// appendix B), every one of them; the others are [`ADDED`].
    #[test]
    fn the_manual_commands_are_the_manual_pages() {
        const MANUAL_PAGE: &[&str] = &[
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
        assert_eq!(MANUAL, MANUAL_PAGE);
        let mut both: Vec<&str> = MANUAL.iter().chain(ADDED).copied().collect();
        both.sort_unstable();
        let table: Vec<&str> = COMMANDS.iter().map(|c| c.name).collect();
        assert_eq!(both, table);
    }

    /// Each verb is the one of its table entry.
    #[test]
    fn verbs_follow_the_table() {
        assert_eq!(Verb::ALL.len(), COMMANDS.len());
        for (verb, spec) in Verb::ALL.iter().zip(COMMANDS) {
            assert_eq!(*verb, spec.verb);
            assert_eq!(verb.spec(), spec);
        }
    }

    #[test]
    fn table_is_sorted_and_unique() {
        for w in COMMANDS.windows(2) {
            assert!(w[0].name < w[1].name, "{} {}", w[0].name, w[1].name);
        }
    }
}
