//! The virtual image tree as a stream of records (004 section 4.10,
//! figure 4.14): the record type ([`record`]) and its binary and text files
//! ([`mod@file`]).

pub mod file;
pub mod record;

pub use record::{PhongShades, Record, RecordStream, Shades};
