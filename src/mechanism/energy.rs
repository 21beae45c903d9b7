//! Energies of the mechanism, for the energy balance of a run: kinetic `½ vᵀ M v`,
//! gravitational `−Σ m g·r`, and the elastic energy stored in the contacts (the integral of
//! eq. 1-2's elastic part over the penetration).

use super::{Mechanism, RunState};

impl Mechanism {
    /// Kinetic energy (J).
    pub fn kinetic_energy(&self, v: &[f64]) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                0.5 * b.mass * (v[3 * i].powi(2) + v[3 * i + 1].powi(2))
                    + 0.5 * b.inertia * v[3 * i + 2].powi(2)
            })
            .sum()
    }

    /// Gravitational potential energy (J), zero at the origin.
    pub fn potential_energy(&self, q: &[f64]) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| -b.mass * (self.gravity.x * q[3 * i] + self.gravity.y * q[3 * i + 1]))
            .sum()
    }

    /// Elastic energy stored in all clearance contacts (J).
    pub fn contact_energy(&self, state: &RunState, q: &[f64], v: &[f64]) -> f64 {
        (0..self.clearance_joints.len())
            .map(|k| {
                let cs = self.contact_kinematics(state, k, q, v);
                self.clearance_joints[k]
                    .contact
                    .elastic_energy(cs.delta, cs.local_clearance)
            })
            .sum()
    }
}
