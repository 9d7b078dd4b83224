//! seamlit-render: per-pixel lighting with normal mapping on wgpu (being written).
#![deny(missing_docs)]

mod light;

pub use light::{CameraView, DebugView, Light, LightingModel};
