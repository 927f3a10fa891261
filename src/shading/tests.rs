//! Unit tests of `shading`.

use super::*;
use crate::model::LightKind;

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

/// A light of colour 0.8 at 10 units, 60 degrees off the normal.
fn light_at_60_degrees(range: f64) -> Light {
    let r = 60f64.to_radians();
    Light {
        position: DVec3::new(r.sin(), 0.0, r.cos()) * 10.0,
        color: DVec3::splat(0.8),
        range,
        kind: LightKind::Point,
    }
}

#[test]
fn donovan_rule_1_scattering_hand_worked() {
    // I0 cos(theta) = 0.8 * 0.6 * 1 (green) * cos 60 = 0.24; no range
    // attenuation (a distant source): range 1 at distance 10 still lights.
    let light = light_at_60_degrees(1.0);
    let c = shade_donovan(
        &material(),
        DVec3::ZERO,
        DVec3::Z,
        DVec3::Z,
        &[light],
        DVec3::ZERO,
    );
    assert!((c.y - 0.24).abs() < 1e-12, "{c}");
    assert_eq!((c.x, c.z), (0.0, 0.0));
    // Plus Garcia's ambient term ka Ia = 0.4.
    let c = shade_donovan(
        &material(),
        DVec3::ZERO,
        DVec3::Z,
        DVec3::Z,
        &[light],
        DVec3::ONE,
    );
    assert!((c.y - 0.64).abs() < 1e-12, "{c}");
    // The same through the selector; Garcia's model is attenuated to 0.
    let m = ShadingModel::Donovan;
    let d = shade_with_model(
        m,
        &material(),
        DVec3::ZERO,
        DVec3::Z,
        DVec3::Z,
        &[light],
        DVec3::ONE,
    );
    assert_eq!(d, c);
    let g = shade_with_model(
        ShadingModel::default(),
        &material(),
        DVec3::ZERO,
        DVec3::Z,
        DVec3::Z,
        &[light],
        DVec3::ONE,
    );
    assert!((g.y - 0.4).abs() < 1e-12, "{g}");
    // Behind the face: nothing.
    let c = shade_donovan(
        &material(),
        DVec3::ZERO,
        -DVec3::Z,
        DVec3::Z,
        &[light],
        DVec3::ZERO,
    );
    assert_eq!(c, DVec3::ZERO);
}

#[test]
fn donovan_rule_2_specular_hand_worked() {
    // theta = 60, theta1 = 30 degrees, b = 2: I1 cos^2(30) = 0.8 * 0.5 *
    // 0.75 = 0.3, in every channel (light coloured); no scattering.
    let mut m = material();
    m.diffuse = 0.0;
    m.specular = 0.5;
    m.shininess = 2.0;
    let t1 = 30f64.to_radians();
    let to_eye = DVec3::new(-t1.sin(), 0.0, t1.cos());
    let light = light_at_60_degrees(100.0);
    let c = shade_donovan(&m, DVec3::ZERO, DVec3::Z, to_eye, &[light], DVec3::ZERO);
    assert!(
        (c.x - 0.3).abs() < 1e-12 && (c.y - 0.3).abs() < 1e-12,
        "{c}"
    );
    // theta1 = theta: cos^b(0) = 1, I = I1 = 0.4.
    let t1 = 60f64.to_radians();
    let to_eye = DVec3::new(t1.sin(), 0.0, t1.cos());
    let c = shade_donovan(&m, DVec3::ZERO, DVec3::Z, to_eye, &[light], DVec3::ZERO);
    assert!((c.z - 0.4).abs() < 1e-12, "{c}");
}

#[test]
fn range_attenuation_zero_beyond_range() {
    assert_eq!(range_attenuation(20.0, 10.0), 0.0);
    assert_eq!(range_attenuation(0.0, 10.0), 1.0);
}
