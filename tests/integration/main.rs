//! Integration tests over the fixtures: one binary, one module per area.

mod architecture;
mod auto;
mod common;
mod compatible;
mod errors;
mod export;
mod far;
mod folds;
mod hostile;
mod motion;
mod rounding;
mod similarity;
mod skeleton;
mod texture;
