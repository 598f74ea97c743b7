//! Keyframe animation (thesis chapters 3–4): physically generated poses, the keyframe table with
//! its selection and smoothing, compression figures, the pose error against a direct solve, and
//! the GPU encodings.

pub mod compression;
pub mod encoding;
pub mod pose;
pub mod pose_error;
pub mod table;

pub use pose::BladeModel;
pub use table::{KeyframeLayout, KeyframeTable, Representation, Smoothing};
