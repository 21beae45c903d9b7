//! Files a run writes and reads: atomic CSV/PNG/JSON writing, output-folder checks and
//! manifests, plotting, and clean interruption (SIGINT/SIGTERM remove temporary files).
//!
//! Owns: the byte formats and the file system. Uses: nothing of the crate but
//! [`crate::Error`]; it knows no physics.

pub mod interrupt;
pub mod output;
pub mod plot;
