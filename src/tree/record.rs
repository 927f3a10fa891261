//! The one boundary type between image generation and everything after it
//! (Garcia 1986, 004 section 4.10, figure 4.14): the virtual image tree as a
//! stream of polygon records. The painter's preview, the tree files
//! (`setmode o`), the scan converters rftb1-4 (004 chapter 5) and every
//! other output consume a [`RecordStream`]; nothing downstream sees the
//! tree itself.
//!
//! A record holds exactly what figure 4.14 holds, so writing a stream to a
//! file and reading it back gives the same records, bit for bit: vertices
//! as `f32` in normalized screen coordinates (0 to 1 from the lower left
//! corner), shades as bytes. Transparency `t` (004 section 4.9) exists only
//! in the Phong record's `<r g b t>`; a transparent polygon without
//! highlights is written as a Phong record with no lights (`nlt = 0`).

/// A record's type and shades (figure 4.14).
#[derive(Debug, Clone, PartialEq)]
pub enum Shades {
    /// Type 0: the specially tagged copy of a polygon between its reflected
    /// and refracted branches (the restore polygon of 004 section 5.9,
    /// case 6). No shade.
    Special,
    /// Type 1: one shade.
    Faceted([u8; 3]),
    /// Type 2: one shade per vertex.
    Gouraud(Vec<[u8; 3]>),
    /// Type 3: Phong, with `r g b t` and highlight vectors per vertex
    /// (boxed: most records are faceted, and the stream is held whole).
    Phong(Box<PhongShades>),
}

/// The Phong parameters of figure 4.14: `<hilite> <nlt> <hltclr>` and, per
/// vertex, `<r g b t>` and `nlt` highlight normal vectors.
#[derive(Debug, Clone, PartialEq)]
pub struct PhongShades {
    /// Shininess of the surface (`hilite`, a double).
    pub shininess: f64,
    /// The highlight colour of each light (`hltclr`).
    pub light_colors: Vec<[u8; 3]>,
    /// Per vertex: shade without highlights, and transparency `t`
    /// (0 opaque, 255 fully transparent).
    pub rgbt: Vec<[u8; 4]>,
    /// Per vertex, per light: the highlight normal vector (`hltnmals`),
    /// rotated so that the halfway vector is +z: the highlight is
    /// `hltclr (n_z / |n|)^hilite`.
    pub normals: Vec<Vec<[f32; 3]>>,
}

/// One polygon of the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Tree level, from 1 (0 only for the background record of a file).
    pub level: u16,
    /// Vertices, normalized screen coordinates: 0 to 1 from the lower left.
    pub points: Vec<[f32; 2]>,
    /// Its type and shades.
    pub shades: Shades,
}

impl Record {
    /// Whether this is a restore (special) record.
    pub fn is_special(&self) -> bool {
        matches!(self.shades, Shades::Special)
    }
}

/// A whole virtual image tree in output order.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordStream {
    /// Records in output order.
    pub records: Vec<Record>,
    /// The background colour (the `-B` polygon of the rftb manual page).
    /// In a file it is a level-0 record; `None` for a file that has none.
    pub background: Option<[u8; 3]>,
    /// Front to back (else back to front).
    pub front_to_back: bool,
    /// Shades pre-blended (`setmode b on`): a child's shade includes its
    /// ancestors'. Else post-blended: a child carries its own shade times
    /// the product of the coefficients above it.
    pub blended: bool,
}
