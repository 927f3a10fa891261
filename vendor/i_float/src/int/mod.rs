pub mod angle;
pub mod number;
pub mod point;
pub mod rect;
pub mod unit_vector;
pub mod vector;
