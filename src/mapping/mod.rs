//! Composite harmonic mapping of the source triangulation onto the target (§5).
