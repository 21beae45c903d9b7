//! The reproduction of the paper: its cases, figures 3-15 and Table 3, golden values,
//! calibration of Table 2, numerical studies, the ensemble-size study, benchmarks, the records
//! of what produced the studies' results, and the generated report `paper.md`.
//!
//! Owns: everything that is about the one published paper. Uses: the library layers below
//! it. Nothing of the library uses it, so a program that embeds the solver need not carry it
//! (it is compiled only with the default feature `paper`).

pub mod calibration;
pub mod cases;
pub mod convergence;
pub mod figures;
pub mod format;
pub mod golden;
pub mod performance;
pub mod perturbation;
pub mod program;
pub mod provenance;
pub mod report;
pub mod separation;
pub mod studies;
