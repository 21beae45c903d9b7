//! The constitutive laws, each a small pure function of the contact kinematics: the normal
//! contact force (the paper's hybrid law, eq. 1-3, and a catalogue of the field's elastic and
//! hysteresis-damping laws, any with any), modified Coulomb friction (eq. 4) and Archard wear
//! on a sectored bearing profile (eq. 5-9).
//!
//! Owns: force and wear laws and their parameters. Uses: nothing of the crate but
//! [`crate::Error`]. A new elastic law goes into [`stiffness`], a new damping law into [`dissipation`]
//! (see ARCHITECTURE.md).

pub mod contact;
pub mod dissipation;
pub mod friction;
pub mod stiffness;
pub mod wear;
