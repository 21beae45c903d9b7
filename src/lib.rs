//! jointwear: wear prediction in planar mechanisms with clearance revolute joints.
//!
//! Reproduces and generalises the coupled method of the paper in `../shared/paper`:
//! rigid multibody dynamics (eq. 10-12) with clearance joints as force elements, the hybrid
//! contact force law (eq. 1-3), modified Coulomb friction (eq. 4) and Archard wear on a
//! sectored bearing profile fed back into the contact geometry (eq. 5-9).
//!
//! All quantities inside the library are SI (m, kg, s, N, Pa, rad). Engineering units of
//! the scene files (mm, r/min, GPa, deg) are converted once, in [`scene`].

pub mod analysis;
pub mod calibration;
pub mod checkpoint;
pub mod concordance;
pub mod contact;
pub mod convergence;
pub mod ensemble;
pub mod error;
pub mod figures;
pub mod friction;
pub mod golden;
pub mod integrator;
pub mod interrupt;
pub mod longlife;
pub mod mechanism;
pub mod output;
pub mod performance;
pub mod plot;
pub mod report;
pub mod runs;
pub mod scene;
pub mod simulation;
pub mod statistics;
pub mod studies;
pub mod sweep;
pub mod sweep_file;
pub mod wear;

pub use error::{Error, Result};
