//! Output writers: G-code, laser SVG, DXF, previews.
pub mod outline;
