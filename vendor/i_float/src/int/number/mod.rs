pub mod fixed_scale;
pub mod int;
pub mod product_uint;
pub mod signed_product;
pub mod uint;
pub mod unit_ratio;
pub mod wide_int;
