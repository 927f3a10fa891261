#[cfg(feature = "glam")]
pub mod glam;
