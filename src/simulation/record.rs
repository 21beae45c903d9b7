//! What a run records without changing it: the uniform time grid of the recorded rotations
//! ([`Sampler`]) and the journal orbit at fixed driver phases that tells a steady state
//! ([`Settler`]), both read from the dense output of each accepted step.

use super::*;
use crate::mechanism::{Mechanism, RunState, Workspace};
use crate::Result;
use serde::{Deserialize, Serialize};

/// Samples the uniform recording grid from each step's dense output.
#[derive(Clone, Serialize, Deserialize)]
pub(super) struct Sampler {
    next: usize,
    start: f64,
    interval: f64,
    count: usize,
    dy: Vec<f64>,
}

impl Sampler {
    pub(super) fn new(dim: usize, start: f64, interval: f64, end: f64) -> Sampler {
        // Grid points t_i = start + i·interval for t_i ≤ end (with a hair of slack for rounding).
        let count = if end > start {
            ((end - start) / interval * (1.0 + 1e-12)).floor() as usize + 1
        } else {
            0
        };
        Sampler {
            next: 0,
            start,
            interval,
            count,
            dy: vec![0.0; dim],
        }
    }

    /// The first field in which a saved sampler is not `fresh`, the window this run records
    /// (a checkpoint keeps its window and how far into it the run has sampled).
    pub(super) fn misfit(&self, fresh: &Sampler) -> Option<&'static str> {
        if self.start.to_bits() != fresh.start.to_bits() {
            Some("start")
        } else if self.interval.to_bits() != fresh.interval.to_bits() {
            Some("interval")
        } else if self.count != fresh.count {
            Some("count")
        } else if self.dy.len() != fresh.dy.len() {
            Some("dy")
        } else if self.next > self.count {
            Some("next")
        } else {
            None
        }
    }

    /// Grid point `i`'s time (s).
    fn time(&self, i: usize) -> f64 {
        self.start + i as f64 * self.interval
    }

    /// The grid points a run has sampled once it reached time `t` (s): every one up to `t`,
    /// as [`Sampler::sample`] takes them.
    pub(super) fn due(&self, t: f64) -> usize {
        (0..self.count).take_while(|&i| self.time(i) <= t).count()
    }

    /// The grid points sampled so far.
    pub(super) fn sampled(&self) -> usize {
        self.next
    }

    /// The times of the samples recorded so far: the grid points sampled (a window never
    /// reaches back before the step that opens it, `run.record_rotations` being at most
    /// `run.rotations`, so none was skipped).
    pub(super) fn recorded(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.next).map(|i| self.time(i))
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample(
        &mut self,
        mechanism: &Mechanism,
        state: &RunState,
        ws: &mut Workspace,
        mut dense: impl FnMut(f64, &mut [f64]),
        ta: f64,
        tb: f64,
        rec: &mut Recording,
        y: &mut [f64],
    ) -> Result<()> {
        let n = mechanism.coordinates();
        while self.next < self.count {
            let t = self.time(self.next);
            if t > tb {
                break;
            }
            self.next += 1;
            if t < ta {
                continue;
            }
            dense(t, y);
            mechanism.rhs(state, ws, t, y, &mut self.dy)?;
            if rec.accelerations.is_empty() {
                rec.positions = vec![Default::default(); mechanism.bodies().len()];
                rec.accelerations = vec![Default::default(); mechanism.bodies().len()];
                rec.joints = vec![JointTrace::default(); mechanism.clearance_joints.len()];
            }
            rec.time.push(t);
            rec.driver_angle.push(y[3 * mechanism.driver.body + 2]);
            for (b, (pos, acc)) in rec
                .positions
                .iter_mut()
                .zip(&mut rec.accelerations)
                .enumerate()
            {
                for c in 0..3 {
                    pos[c].push(y[3 * b + c]);
                    acc[c].push(self.dy[n + 3 * b + c]);
                }
            }
            for (k, tr) in rec.joints.iter_mut().enumerate() {
                let cs = mechanism.contact_state(state, k, &y[..n], &y[n..2 * n]);
                let pressure = match mechanism.clearance_joints[k].wear {
                    Some(law) if cs.f_n > 0.0 => (
                        law.pressure(cs.f_n, cs.delta, cs.local_clearance).peak,
                        law.k_over_h,
                    ),
                    _ => (0.0, 0.0),
                };
                tr.ex.push(cs.e.x);
                tr.ey.push(cs.e.y);
                tr.theta.push(cs.theta);
                tr.delta.push(cs.delta);
                tr.normal_force.push(cs.f_n);
                tr.friction_force.push(cs.f_t);
                tr.sliding_velocity.push(cs.v_t);
                tr.pressure.push(pressure.0);
                tr.wear_rate.push(pressure.1 * pressure.0 * cs.v_t.abs());
            }
        }
        Ok(())
    }
}

/// Samples the journal orbit at fixed driver phases to detect a steady state.
#[derive(Clone, Serialize, Deserialize)]
pub(super) struct Settler {
    criterion: SteadyState,
    period: f64,
    clearances: Vec<f64>,
    /// `[rotation parity][joint][phase]` journal eccentricity.
    orbits: [Vec<Vec<[f64; 2]>>; 2],
    rotation: usize,
    next_phase: usize,
}

impl Settler {
    pub(super) fn new(mechanism: &Mechanism, criterion: SteadyState, period: f64) -> Settler {
        let joints = mechanism.clearance_joints.len();
        let orbit = vec![vec![[0.0; 2]; ORBIT_PHASES]; joints];
        Settler {
            criterion,
            period,
            clearances: mechanism
                .clearance_joints
                .iter()
                .map(|c| c.clearance().max(1e-9))
                .collect(),
            orbits: [orbit.clone(), orbit],
            rotation: 0,
            next_phase: 0,
        }
    }

    /// The first field in which a settler saved after `rotation` completed rotations is not
    /// `fresh` (the one this run starts) in all but its orbits, or holds a non-finite orbit.
    pub(super) fn misfit(&self, fresh: &Settler, rotation: u32) -> Option<&'static str> {
        let shape = |o: &Vec<Vec<[f64; 2]>>| o.iter().map(Vec::len).collect::<Vec<_>>();
        if self.criterion != fresh.criterion {
            Some("criterion")
        } else if self.period.to_bits() != fresh.period.to_bits() {
            Some("period")
        } else if self.clearances != fresh.clearances {
            Some("clearances")
        } else if (0..2).any(|i| shape(&self.orbits[i]) != shape(&fresh.orbits[i]))
            || self
                .orbits
                .iter()
                .flatten()
                .flatten()
                .flatten()
                .any(|x| !x.is_finite())
        {
            Some("orbits")
        } else if self.rotation != rotation as usize {
            Some("rotation")
        } else if self.next_phase != 0 {
            Some("next_phase")
        } else {
            None
        }
    }

    pub(super) fn sample(
        &mut self,
        mechanism: &Mechanism,
        state: &RunState,
        mut dense: impl FnMut(f64, &mut [f64]),
        ta: f64,
        tb: f64,
        y: &mut [f64],
    ) {
        let n = mechanism.coordinates();
        while self.next_phase < ORBIT_PHASES {
            let t =
                (self.rotation as f64 + self.next_phase as f64 / ORBIT_PHASES as f64) * self.period;
            if t > tb {
                break;
            }
            if t >= ta {
                dense(t, y);
                for (k, orbit) in self.orbits[self.rotation % 2].iter_mut().enumerate() {
                    let e = mechanism
                        .contact_kinematics(state, k, &y[..n], &y[n..2 * n])
                        .e;
                    orbit[self.next_phase] = [e.x, e.y];
                }
            }
            self.next_phase += 1;
        }
    }

    /// Called at the end of rotation `done` (1-based): `Some` when settling is over.
    pub(super) fn end_rotation(&mut self, done: u32) -> Option<Settling> {
        self.rotation += 1;
        self.next_phase = 0;
        if done < 2 {
            return None;
        }
        let [a, b] = &self.orbits;
        let change = a
            .iter()
            .zip(b)
            .zip(&self.clearances)
            .map(|((oa, ob), c)| {
                let ms: f64 = oa
                    .iter()
                    .zip(ob)
                    .map(|(p, q)| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2))
                    .sum();
                (ms / ORBIT_PHASES as f64).sqrt() / c
            })
            .fold(0.0, f64::max);
        let steady = change <= self.criterion.tolerance;
        (steady || done >= self.criterion.max_rotations).then_some(Settling {
            rotations: done,
            orbit_change: change,
            steady,
        })
    }
}
