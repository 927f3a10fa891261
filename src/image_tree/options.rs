//! The tree builder's options (Garcia 1986, 004 sections 4.6-4.8): how
//! deep and how light a branch is traced, the sort, shadows, the
//! refraction matrix ([`Refraction`], 004 sections 4.6 and 6.4.3), the
//! illumination model and the budgets.

use crate::budget::Budgets;
use crate::shading::ShadingModel;

/// The refraction matrix used for refractive polygons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Refraction {
    /// The renderer's choice (`render::prepare`): exact when the
    /// linearized matrix is off by more than a pixel through a
    /// transmitting polygon (at its corners or at the refracted objects'
    /// vertices, `raytrace::exact::linear_error`), else linearized. The tree builder itself treats
    /// it as linearized.
    #[default]
    Auto,
    /// `M_t` linearized exactly about the ray through the polygon's centre
    /// (the improvement of 004 section 6.4.3).
    Linearized,
    /// No refracted branches in the tree: they are ray traced per pixel
    /// and composited after scan conversion (`raytrace::exact`, the hybrid
    /// of 004 section 6.4).
    Exact,
    /// `M_to`, exact for rays parallel to the line of sight (004 section
    /// 4.6; exact under an orthographic projection).
    Orthographic,
    /// The paraxial approximation `M_tp = I + (eta - 1) L N`.
    Paraxial,
}

impl std::str::FromStr for Refraction {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "linearized" | "linearised" => Ok(Refraction::Linearized),
            "orthographic" => Ok(Refraction::Orthographic),
            "paraxial" => Ok(Refraction::Paraxial),
            "exact" => Ok(Refraction::Exact),
            "auto" => Ok(Refraction::Auto),
            _ => Err(format!(
                "unknown refraction model `{s}`; expected linearized, orthographic, paraxial, \
                 exact or auto"
            )),
        }
    }
}

/// Options of the tree builder.
#[derive(Debug, Clone, Copy)]
pub struct TreeOptions {
    /// Deepest level (`depth`, 1-14).
    pub max_level: u32,
    /// Smallest coefficient worth tracing (`threshold`).
    pub threshold: f64,
    /// Use the NNS sorter at every level.
    pub nns: bool,
    /// Cast shadows from Point lights (`run y`).
    pub shadows: bool,
    /// Which refraction matrix (004 sections 4.6 and 6.4.3).
    pub refraction: Refraction,
    /// `setmode h on`: shade every shadow polygon at its own centroid;
    /// off: all shadows of one light on one target share the target's
    /// shade without that light (004 section 4.7).
    pub explicit_shadow_shades: bool,
    /// The illumination model of the fragments' shades (Garcia's, 004
    /// section 4.8, by default; or Donovan's, 000 section 6).
    pub shading: ShadingModel,
    /// The limits: tree fragments ([`Budgets::tree_nodes`]) and NNS splits
    /// per level ([`Budgets::splits`]).
    pub budgets: Budgets,
    /// With `Some(n)`, leave out the polygons of each level whose every
    /// sample of the image's `n x n` grid per pixel is covered by opaque
    /// polygons of that level later in its order
    /// ([`crate::visibility::occlusion`]): right for a
    /// picture made from those samples only, not for exact areas, tree
    /// files or vector output, where what lies behind shows through the
    /// seams of a mesh.
    pub cull_samples: Option<u32>,
}

impl Default for TreeOptions {
    /// One level, no threshold, the simple sort, no shadows, the
    /// linearized refraction matrix, shared shadow shades, Garcia's model,
    /// the default budgets.
    fn default() -> TreeOptions {
        TreeOptions {
            max_level: 1,
            threshold: 0.0,
            nns: false,
            shadows: false,
            refraction: Refraction::default(),
            explicit_shadow_shades: false,
            shading: ShadingModel::default(),
            budgets: Budgets::default(),
            cull_samples: None,
        }
    }
}
