//! jointwear: wear prediction in planar mechanisms with clearance revolute joints.
//!
//! Reproduces and generalises the coupled method of *A comprehensive method for joint wear
//! prediction in planar mechanical systems with clearances considering complex contact
//! conditions*: rigid multibody dynamics (eq. 10-12) with clearance joints as force elements,
//! the hybrid contact force law (eq. 1-3), modified Coulomb friction (eq. 4) and Archard wear
//! on a sectored bearing profile fed back into the contact geometry (eq. 5-9).
//!
//! Layers, from the bottom (each uses only those above it in this list; ARCHITECTURE.md):
//! [`error`], [`io`], [`laws`], [`ode`], [`mechanism`], [`simulation`], [`scene`],
//! [`analysis`], [`sweep`], and the top layers: the paper's reproduction [`paper`] (feature
//! `paper`, on by default) and the Python bindings `python` (feature `python`, built by maturin
//! from `pyproject.toml`).
//!
//! All quantities inside the library are SI (m, kg, s, N, Pa, rad). Engineering units of
//! the scene files (mm, r/min, GPa, deg) are converted once, in [`scene`].

pub mod analysis;
pub mod error;
pub mod io;
pub mod laws;
pub mod mechanism;
pub mod ode;
#[cfg(feature = "paper")]
pub mod paper;
#[cfg(feature = "python")]
pub mod python;
pub mod scene;
pub mod simulation;
pub mod sweep;
#[cfg(test)]
mod test_support;

pub use error::{Error, Result};
