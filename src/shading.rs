//! The illumination model of Garcia 1986 (004 section 4.8), Phong's:
//!
//! `I = ka Ia + sum_j k(j) (kd (N.L_j) + ks (N.H_j)^n)`,
//! `ka = max(0, 1 - (kd + kr + kt))`,
//! `k(j) = max(1 - |P_j - P_v| / Range_j, 0)^2`.
//!
//! Colour enters as in Phong's model: the ambient and diffuse terms are
//! multiplied by the surface colour and by the ambient or light colour, the
//! specular term by the light colour only. Lights behind the surface
//! (N.L <= 0) contribute nothing. Results are clamped to 0..1.
//! Shading is done in world space.

use glam::DVec3;

use crate::scene::model::{Color, Light, Object};
use crate::scene::object_file::ColorEntry;

/// The surface parameters at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Surface colour.
    pub color: Color,
    /// Diffuse coefficient kd.
    pub diffuse: f64,
    /// Specular coefficient ks.
    pub specular: f64,
    /// Shininess n.
    pub shininess: f64,
    /// Reflection coefficient kr.
    pub reflectance: f64,
    /// Transmission coefficient kt.
    pub transmittance: f64,
}

impl Material {
    /// The ambient coefficient `max(0, 1 - (kd + kr + kt))`.
    pub fn ambient_coefficient(&self) -> f64 {
        (1.0 - (self.diffuse + self.reflectance + self.transmittance)).max(0.0)
    }

    /// This material with colour and coefficients of a `.pcl`/`.vcl` entry.
    pub fn with_entry(mut self, e: &ColorEntry) -> Material {
        self.color = e.color;
        self.diffuse = e.diffuse;
        self.reflectance = e.reflectance;
        self.transmittance = e.transmittance;
        self
    }
}

/// The range attenuation k(j) of a light at distance `d`.
pub fn range_attenuation(d: f64, range: f64) -> f64 {
    let k = (1.0 - d / range).max(0.0);
    k * k
}

/// The intensity at world point `p` with unit normal `n` (facing the
/// viewer's side that is shaded), seen from direction `to_eye` (unit).
pub fn shade(
    m: &Material,
    p: DVec3,
    n: DVec3,
    to_eye: DVec3,
    lights: &[Light],
    ambient: Color,
) -> Color {
    let mut c = m.color * ambient * m.ambient_coefficient();
    for light in lights {
        let to_light = light.position - p;
        let d = to_light.length();
        if d == 0.0 {
            continue;
        }
        let l = to_light / d;
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        let k = range_attenuation(d, light.range);
        if k == 0.0 {
            continue;
        }
        let mut term = m.color * m.diffuse * n_dot_l;
        if m.specular > 0.0 {
            let h = (l + to_eye).normalize_or_zero();
            let n_dot_h = n.dot(h).max(0.0);
            term += DVec3::splat(m.specular * n_dot_h.powf(m.shininess));
        }
        c += light.color * term * k;
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

/// The material of polygon `pi` of `object`, with its `.pcl` entry or the
/// average of its vertices' `.vcl` entries.
pub fn polygon_material(object: &Object, pi: usize) -> Material {
    let s = &object.surface;
    let base = Material {
        color: s.color,
        diffuse: s.diffuse,
        specular: s.specular,
        shininess: s.shininess,
        reflectance: s.reflectance,
        transmittance: s.transmittance,
    };
    if let Some(pcl) = &object.polygon_colors {
        let source = object.source_polygon[pi] as usize;
        return base.with_entry(&pcl[source]);
    }
    if let Some(vcl) = &object.vertex_colors {
        let idx = &object.polygons[pi].indices;
        let n = idx.len() as f64;
        let mut avg = vcl[idx[0] as usize];
        let sum = |f: &dyn Fn(usize) -> f64| idx.iter().map(|&i| f(i as usize)).sum::<f64>() / n;
        avg.color = idx.iter().map(|&i| vcl[i as usize].color).sum::<DVec3>() / n;
        avg.diffuse = sum(&|i| vcl[i].diffuse);
        avg.reflectance = sum(&|i| vcl[i].reflectance);
        avg.transmittance = sum(&|i| vcl[i].transmittance);
        return base.with_entry(&avg);
    }
    base
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::model::LightKind;

    fn material() -> Material {
        Material {
            color: DVec3::new(0.0, 1.0, 0.0),
            diffuse: 0.6,
            specular: 0.0,
            shininess: 0.0,
            reflectance: 0.0,
            transmittance: 0.0,
        }
    }

    #[test]
    fn ambient_coefficient_hand_worked() {
        assert!((material().ambient_coefficient() - 0.4).abs() < 1e-15);
        let mut m = material();
        m.reflectance = 0.5;
        assert_eq!(m.ambient_coefficient(), 0.0);
    }

    #[test]
    fn one_light_hand_worked() {
        // Light 5 above the point, range 10: k = (1 - 0.5)^2 = 0.25, N.L = 1.
        let light = Light {
            position: DVec3::new(0.0, 0.0, 5.0),
            color: DVec3::splat(0.8),
            range: 10.0,
            kind: LightKind::Point,
        };
        let c = shade(
            &material(),
            DVec3::ZERO,
            DVec3::Z,
            DVec3::Z,
            &[light],
            DVec3::ONE,
        );
        // green = 0.4 * 1 + 0.25 * 0.8 * 0.6 = 0.52
        assert!((c.y - 0.52).abs() < 1e-12, "{c}");
        assert_eq!(c.x, 0.0);
        // From behind: ambient only.
        let c = shade(
            &material(),
            DVec3::ZERO,
            -DVec3::Z,
            DVec3::Z,
            &[light],
            DVec3::ONE,
        );
        assert!((c.y - 0.4).abs() < 1e-12);
    }

    #[test]
    fn specular_is_light_coloured() {
        let mut m = material();
        m.specular = 0.5;
        m.shininess = 10.0;
        let light = Light {
            position: DVec3::new(0.0, 0.0, 1.0),
            color: DVec3::ONE,
            range: 1e9,
            kind: LightKind::Diffuse,
        };
        let c = shade(&m, DVec3::ZERO, DVec3::Z, DVec3::Z, &[light], DVec3::ZERO);
        // N.H = 1: red gets the specular 0.5 only (k ~ 1).
        assert!((c.x - 0.5).abs() < 1e-6, "{c}");
    }

    #[test]
    fn range_attenuation_zero_beyond_range() {
        assert_eq!(range_attenuation(20.0, 10.0), 0.0);
        assert_eq!(range_attenuation(0.0, 10.0), 1.0);
    }
}
