//! Compatible triangulation of a source and a target drawing: stages 1–4 of the pipeline.
