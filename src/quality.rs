//! Quality measures of interpolated frames: inverted triangles, distortion, area.
