//! The camera of the public face: eye, target, twist and projection, as
//! the scene language's `view` and `perspective`/`orthographic` commands
//! (Garcia 1986, section 4.3 and appendix B), turned into the viewing
//! transform of section 4.4.

use super::*;

/// How the scene is seen: an eye, the point it looks at, a twist about
/// the line of sight, and a projection.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut camera = Camera::looking_at([0., -5., 0.], [0., 0., 0.]);
/// camera.twist = 90.0;
/// assert!(render(&Scene::new(camera, 16, 16), &Options::default()).is_ok());
/// // A camera looking at its own eye has no line of sight.
/// camera.target = camera.eye;
/// assert!(render(&Scene::new(camera, 16, 16), &Options::default()).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// The eye.
    pub eye: [f64; 3],
    /// The point looked at.
    pub target: [f64; 3],
    /// The world direction shown up on the screen.
    pub up: [f64; 3],
    /// Rotation about the line of sight, degrees (the manual's `lookat`).
    pub twist: f64,
    /// The projection.
    pub projection: Projection,
}

/// The projection of a [`Camera`].
///
/// ```
/// use plytrace::api::{render, Camera, Options, Projection, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut camera = Camera::looking_at([0., -5., 0.], [0., 0., 0.]);
/// camera.projection = Projection::Orthographic {
///     left: -2., right: 2., bottom: -1., top: 1., near: 0.1, far: 100.,
/// };
/// let image = render(&Scene::new(camera, 32, 16), &Options::default())?;
/// assert_eq!((image.width, image.height), (32, 16));
/// // A field of view of 180 degrees or more is refused.
/// camera.projection = Projection::Perspective { fovy: 200., near: 0.1, far: 100. };
/// assert!(render(&Scene::new(camera, 32, 16), &Options::default()).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// `perspective fovy aspect near far`; the aspect is the image's.
    Perspective {
        /// Vertical field of view, degrees.
        fovy: f64,
        /// Nearest distance drawn.
        near: f64,
        /// Farthest distance drawn.
        far: f64,
    },
    /// `ortho left right bottom top near far`, in eye coordinates.
    Orthographic {
        /// Left edge.
        left: f64,
        /// Right edge.
        right: f64,
        /// Bottom edge.
        bottom: f64,
        /// Top edge.
        top: f64,
        /// Nearest distance drawn.
        near: f64,
        /// Farthest distance drawn.
        far: f64,
    },
}

impl Camera {
    /// A camera at `eye` looking at `target` with a 45-degree perspective
    /// (near 0.01, far 10,000) and +z up, as in most plotting tools. (The
    /// scene language's `lookat` keeps +y up, as IRIS GL did: set `up` to
    /// `[0, 1, 0]` for the same view.)
    ///
    /// ```
    /// use plytrace::api::{Camera, Projection};
    ///
    /// let camera = Camera::looking_at([4., -6., 3.], [0., 0., 0.]);
    /// assert_eq!((camera.eye, camera.target), ([4., -6., 3.], [0., 0., 0.]));
    /// assert_eq!((camera.up, camera.twist), ([0., 0., 1.], 0.));
    /// assert_eq!(camera.projection, Projection::Perspective { fovy: 45., near: 0.01, far: 10_000. });
    /// ```
    pub fn looking_at(eye: [f64; 3], target: [f64; 3]) -> Camera {
        Camera {
            eye,
            target,
            up: [0.0, 0.0, 1.0],
            twist: 0.0,
            projection: Projection::Perspective {
                fovy: 45.0,
                near: 0.01,
                far: 10_000.0,
            },
        }
    }

    /// World to clip coordinates for an image of `aspect` = width / height:
    /// the projection, pre-multiplied by the view (IRIS GL order).
    pub(super) fn matrix(&self, aspect: f64) -> Result<Matrix4> {
        let projection = match self.projection {
            Projection::Perspective { fovy, near, far } => {
                check_range("fovy", fovy, 0.0, 180.0)?;
                check_depths(near, far)?;
                math::perspective(fovy, aspect, near, far)
            }
            Projection::Orthographic {
                left,
                right,
                bottom,
                top,
                near,
                far,
            } => {
                let all = [left, right, bottom, top, near, far];
                if all.iter().any(|v| !v.is_finite())
                    || left == right
                    || bottom == top
                    || near == far
                {
                    return Err(invalid(
                        "an orthographic camera needs finite, distinct bounds",
                    ));
                }
                math::ortho(left, right, bottom, top, near, far)
            }
        };
        let (eye, target) = (
            finite3("camera eye", self.eye)?,
            finite3("camera target", self.target)?,
        );
        let up = finite3("camera up", self.up)?;
        if !self.twist.is_finite() {
            return Err(invalid(&format!(
                "camera twist {}: expected a finite angle",
                self.twist
            )));
        }
        let view = math::lookat_up(eye, target, up, self.twist).ok_or_else(|| {
            invalid("the camera's eye and target are the same point, or it looks along `up`")
        })?;
        Ok(view.mul(&projection))
    }
}
