//! glTF geometry that is not plain floats in plain buffer views, decoded at load (issue 11):
//! quantised attributes (KHR_mesh_quantization, `quantized.rs`), meshopt-compressed buffer
//! views (EXT_/KHR_meshopt_compression, `meshopt.rs`) and Draco-compressed primitives
//! (KHR_draco_mesh_compression, `draco.rs`, with the `draco` feature). From then on the
//! reader and the pass-through writer read plain data.

pub(crate) mod draco;
pub(crate) mod meshopt;
pub(crate) mod quantized;
