//! Disc-based rigidity-preserving interpolation with globally consistent rotation (§4.1).
