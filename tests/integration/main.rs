//! Integration tests over the fixtures: one binary, one module per area.

mod auto;
mod common;
mod compatible;
mod errors;
mod export;
mod motion;
mod similarity;
mod skeleton;
