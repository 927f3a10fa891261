//! The checks of what a caller gives the public face: finite numbers,
//! colours and ranges, image sizes within the scene language's limits
//! (Garcia 1986, appendix B), near and far planes.

use super::*;

pub(super) fn invalid(message: &str) -> Error {
    Error::Invalid(message.to_string())
}

pub(super) fn finite3(what: &str, v: [f64; 3]) -> Result<DVec3> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(DVec3::from_array(v))
    } else {
        Err(invalid(&format!("{what} is not finite: {v:?}")))
    }
}

/// Refuses an image size the program's `--size` refuses.
pub(super) fn check_size(w: u32, h: u32) -> Result<()> {
    let side = |v: u32| (1..=MAX_IMAGE_SIDE).contains(&i64::from(v));
    if side(w) && side(h) && u64::from(w) * u64::from(h) <= MAX_IMAGE_PIXELS {
        return Ok(());
    }
    Err(invalid(&format!(
        "an image of {w} x {h} pixels: each side must be 1 to {MAX_IMAGE_SIDE} and the total \
         at most {MAX_IMAGE_PIXELS} pixels"
    )))
}

/// A colour's components, each from 0 to 1.
pub(super) fn check_color(what: &str, rgb: [f64; 3]) -> Result<()> {
    if rgb.iter().all(|c| (0.0..=1.0).contains(c)) {
        Ok(())
    } else {
        Err(invalid(&format!(
            "{what} {rgb:?}: expected components from 0 to 1"
        )))
    }
}

pub(super) fn check_range(what: &str, v: f64, lo: f64, hi: f64) -> Result<()> {
    if v.is_finite() && v > lo && v < hi {
        Ok(())
    } else {
        Err(invalid(&format!(
            "{what} {v}: expected more than {lo} and less than {hi}"
        )))
    }
}

pub(super) fn check_depths(near: f64, far: f64) -> Result<()> {
    if near.is_finite() && far.is_finite() && near > 0.0 && far > near {
        Ok(())
    } else {
        Err(invalid(&format!(
            "near {near} and far {far}: expected 0 < near < far"
        )))
    }
}
