//! The directions of a Whitted ray tracer at a surface (Whitted 1980, as
//! used for the comparison of Garcia 1986, 004 chapter 6): the mirror
//! direction and exact Snell refraction, with total internal reflection.
//!
//! Directions need not be unit; results keep the incident direction's
//! length, so a ray's parameter range (its far-plane bound, 004 section
//! 4.4) carries over a bend.

use glam::DVec3;

/// `d` mirrored in the plane of unit normal `n`: `d - 2 (d.n) n`.
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

/// What happens to a ray at an interface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bend {
    /// Refracted into this direction (the incident direction's length).
    Refracted(DVec3),
    /// Totally reflected (the angle of incidence is past the critical
    /// angle), into this direction.
    TotalInternalReflection(DVec3),
}

impl Bend {
    /// The direction the ray goes on in, either way.
    pub fn direction(self) -> DVec3 {
        match self {
            Bend::Refracted(d) | Bend::TotalInternalReflection(d) => d,
        }
    }
}

/// Snell's law `n1 sin(theta1) = n2 sin(theta2)` for direction `d` meeting
/// a surface of unit normal `n` (either side), with `eta = n1 / n2`, the
/// index of the side the ray comes from over that of the side it enters:
/// `t = eta d^ + (eta cos1 - cos2) m`, `m` the normal against `d`,
/// `cos2 = sqrt(1 - eta^2 (1 - cos1^2))`; total internal reflection when
/// the root is imaginary.
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Bend {
    let len = d.length();
    if len == 0.0 {
        return Bend::Refracted(d);
    }
    let u = d / len;
    // The normal on the side the ray comes from.
    let m = if u.dot(n) > 0.0 { -n } else { n };
    let cos1 = -u.dot(m);
    let k = 1.0 - eta * eta * (1.0 - cos1 * cos1);
    if k < 0.0 {
        return Bend::TotalInternalReflection(reflect(d, m));
    }
    let t = u * eta + m * (eta * cos1 - k.sqrt());
    Bend::Refracted(t.normalize() * len)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 1e-12;

    #[test]
    fn normal_incidence_goes_straight() {
        let d = DVec3::new(0.0, 0.0, -2.0);
        let t = refract(d, DVec3::Z, 1.0 / 1.5).direction();
        assert!((t - d).length() < EPS);
    }

    #[test]
    fn snell_by_hand_at_45_degrees_into_glass() {
        // sin(theta2) = sin(45) / 1.5 = 0.471405; theta2 = 28.1255 degrees.
        let d = DVec3::new(1.0, 0.0, -1.0);
        let t = refract(d, DVec3::Z, 1.0 / 1.5).direction().normalize();
        assert!((t.x - 0.471_404_520_791).abs() < 1e-9, "{t}");
        assert!((t.z + 0.881_917_103_688).abs() < 1e-9, "{t}");
    }

    #[test]
    fn leaving_water_past_the_critical_angle_reflects() {
        // Critical angle of water: asin(1 / 1.33) = 48.75 degrees; at 60
        // degrees from the normal the ray stays in.
        let (s, c) = 60f64.to_radians().sin_cos();
        let d = DVec3::new(s, 0.0, c); // going up, out of the water
        match refract(d, DVec3::Z, 1.33) {
            Bend::TotalInternalReflection(r) => {
                assert!((r - DVec3::new(s, 0.0, -c)).length() < EPS)
            }
            other => panic!("expected total internal reflection, got {other:?}"),
        }
        // At 40 degrees it leaves: sin(theta2) = 1.33 sin(40) = 0.854908.
        let (s, c) = 40f64.to_radians().sin_cos();
        let t = refract(DVec3::new(s, 0.0, c), DVec3::Z, 1.33).direction();
        assert!((t.x - 0.854_907_520_883).abs() < 1e-9, "{t}");
    }

    #[test]
    fn reflection_is_the_mirror_image() {
        let r = reflect(DVec3::new(1.0, 2.0, -3.0), DVec3::Z);
        assert_eq!(r, DVec3::new(1.0, 2.0, 3.0));
    }
}
