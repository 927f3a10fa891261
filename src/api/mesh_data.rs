//! Meshes given as arrays (vertices and faces of 0-based indices),
//! checked and turned into the polygons of an object (Garcia 1986,
//! section 4.3: input processing).

use super::*;

/// An object's geometry as arrays: vertices, and faces as lists of
/// 0-based vertex indices, counter-clockwise seen from outside (the
/// convention of OBJ, PLY and numpy-based tools; the scene language's
/// object files are clockwise). Optional colours per face or per vertex.
///
/// ```
/// use plytrace::api::MeshData;
///
/// let mut triangle = MeshData::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![vec![0, 1, 2]]);
/// triangle.vertex_colors = Some(vec![[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]]);
/// assert!(triangle.validate().is_ok());
/// // Face colours must be one per face.
/// triangle.face_colors = Some(vec![[1., 1., 1.]; 2]);
/// assert!(triangle.validate().is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshData {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Faces: at least three vertex indices each.
    pub faces: Vec<Vec<u32>>,
    /// One colour per face, 0 to 1.
    pub face_colors: Option<Vec<[f64; 3]>>,
    /// One colour per vertex, 0 to 1 (Gouraud shaded).
    pub vertex_colors: Option<Vec<[f64; 3]>>,
}

impl MeshData {
    /// A mesh of `vertices` and counter-clockwise `faces`.
    ///
    /// ```
    /// use plytrace::api::MeshData;
    ///
    /// let square = MeshData::new(
    ///     vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
    ///     vec![vec![0, 1, 2, 3]],
    /// );
    /// assert_eq!((square.vertices.len(), square.faces.len()), (4, 1));
    /// assert!(square.face_colors.is_none() && square.vertex_colors.is_none());
    /// ```
    pub fn new(vertices: Vec<[f64; 3]>, faces: Vec<Vec<u32>>) -> MeshData {
        MeshData {
            vertices,
            faces,
            ..MeshData::default()
        }
    }

    /// Checks the arrays: finite coordinates and colours, faces of three
    /// or more indices within the vertices, colour arrays of the right
    /// length.
    ///
    /// ```
    /// use plytrace::api::MeshData;
    ///
    /// let mut mesh = MeshData::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![vec![0, 1, 2]]);
    /// assert!(mesh.validate().is_ok());
    /// mesh.faces[0][2] = 3;
    /// let error = mesh.validate().unwrap_err().to_string();
    /// assert!(error.contains("face 0 names vertex 3, but there are 3 vertices"), "{error}");
    /// mesh.faces[0] = vec![0, 1];
    /// assert!(mesh.validate().is_err(), "a face needs three vertices");
    /// ```
    pub fn validate(&self) -> Result<()> {
        if let Some(i) = self
            .vertices
            .iter()
            .position(|v| v.iter().any(|c| !c.is_finite()))
        {
            return Err(invalid(&format!(
                "vertex {i} is not finite: {:?}",
                self.vertices[i]
            )));
        }
        let n = self.vertices.len();
        for (f, face) in self.faces.iter().enumerate() {
            if face.len() < 3 {
                return Err(invalid(&format!(
                    "face {f} has {} vertices; a face needs 3",
                    face.len()
                )));
            }
            if let Some(&i) = face.iter().find(|&&i| i as usize >= n) {
                return Err(invalid(&format!(
                    "face {f} names vertex {i}, but there are {n} vertices"
                )));
            }
        }
        for (what, colors, want) in [
            ("face_colors", &self.face_colors, self.faces.len()),
            ("vertex_colors", &self.vertex_colors, n),
        ] {
            let Some(colors) = colors else { continue };
            if colors.len() != want {
                return Err(invalid(&format!(
                    "{what} has {} colours for {want} {}",
                    colors.len(),
                    if what == "face_colors" {
                        "faces"
                    } else {
                        "vertices"
                    }
                )));
            }
            if let Some(i) = colors.iter().position(|c| c.iter().any(|v| !v.is_finite())) {
                return Err(invalid(&format!("{what}[{i}] is not finite")));
            }
        }
        Ok(())
    }

    /// The scene language's mesh: faces clockwise from outside.
    pub(super) fn to_mesh(&self) -> Mesh {
        Mesh {
            vertices: self
                .vertices
                .iter()
                .map(|v| DVec3::from_array(*v))
                .collect(),
            polygons: self
                .faces
                .iter()
                .map(|f| f.iter().rev().copied().collect())
                .collect(),
        }
    }
}
