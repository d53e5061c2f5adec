//! Rhai scripting: a sandboxed engine that drives the World's camera, objects, materials and
//! settings frame by frame.

pub mod api;
