//! # seamlit-web
//!
//! seamlit in a web page: the WebAssembly side of `web/` (built by `web/build.sh`). It
//! draws with seamlit's own renderer (`seamlit-render`, the same WGSL) on the browser's
//! WebGPU, fixes with `seamlit-mesh`, and everything stays in the page: nothing is uploaded.
//!
//! The JavaScript API (wasm-bindgen) is one class, `Viewer`: `Viewer.create(canvas)` opens
//! WebGPU on the canvas (and fails with one line when the browser has none), `showDemo`
//! loads the embedded Newell teapot, `rotate`/`zoom` move the orbit camera, `setView`
//! chooses the lit view or a debug view (`objects`, `normals`), `setFixed` switches between
//! the model as loaded (with the shared positions whose normals differ marked, [`marks`]) and
//! as fixed, and `draw` draws a frame.
//!
//! `timeDemoFix` times the fix of the demo teapot in the page; [`timing`] is that code, which
//! `examples/teapot_fix_time.rs` runs natively. [`files`] reads the dropped files from memory
//! and writes the download into memory. On targets other than `wasm32` the crate is
//! [`files`], [`marks`] and [`timing`].

pub mod files;
pub mod marks;
pub mod timing;

#[cfg(target_arch = "wasm32")]
mod viewer;

#[cfg(target_arch = "wasm32")]
pub use viewer::Viewer;
