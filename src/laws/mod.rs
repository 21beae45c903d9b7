//! The paper's constitutive laws, each a small pure function of the contact kinematics:
//! the hybrid normal contact force (eq. 1-3), modified Coulomb friction (eq. 4) and Archard
//! wear on a sectored bearing profile (eq. 5-9).
//!
//! Owns: force and wear laws and their parameters. Uses: nothing of the crate but
//! [`crate::Error`]. A new contact law goes into [`contact`] (see ARCHITECTURE.md).

pub mod contact;
pub mod friction;
pub mod wear;
