//! Files a run writes and reads: atomic CSV/PNG/JSON writing, output-folder checks, claims
//! and manifests, plotting, clean interruption (SIGINT/SIGTERM remove temporary files), the
//! progress observers of long computations, and numbers printed for people
//! ([`mod@format`]).
//!
//! Owns: the byte formats and the file system. Uses: nothing of the crate but
//! [`crate::Error`]; it knows no physics.

pub mod format;
pub mod interrupt;
pub mod lock;
pub mod output;
pub mod paper_claim;
pub mod plot;
pub mod progress;
