//! Joint coordinates for tree-shaped linkages: when the ideal joints connect every body to the
//! ground without a closed loop (loops close only through clearance joints, as in the
//! slider-crank), the run integrates one coordinate per ideal-joint freedom instead of three
//! per body. The coordinate of a revolute joint is its child body's absolute angle (so that its
//! error scale stays that of the angle, not of the turns of the parent), that of a
//! translational joint the slide along its line; the driven body's angle is prescribed.
//!
//! Each body's pose is closed-form in the coordinates, walking the tree from the ground:
//! `r_C = r_P + A_P − A_C` with `A = R(φ) (l + d u)` the arm from a body's centre of mass to
//! the joint (`d u` the slide, on the body holding the line). With `J = ∂(r, φ)/∂z` and the
//! acceleration `a` of the motion at `z̈ = 0` (centripetal, Coriolis and driver terms), the
//! equations of motion are Lagrange's, `(Jᵀ M J) z̈ = Jᵀ (F − M a)`: a mass matrix of the size of
//! the freedoms (at most [`MAX_TREE_FREEDOMS`]), solved by Cholesky. No constraint is
//! integrated, so there is nothing to stabilise and no drift. Clearance joints are the same
//! force elements as in the absolute formulation (the same kinematics and laws).

use super::kinematics::{perp, rotate, Frame};
use super::{BodyIndex, Mechanism, RunState, ENERGY_STATES};
use crate::{Error, Result};
use nalgebra::Vector2;

/// Most ideal-joint freedoms integrated in joint coordinates; a tree with more keeps the
/// absolute coordinates. Every shipped tree scene has 2 (the slider-crank's rod angle and
/// slider position).
pub const MAX_TREE_FREEDOMS: usize = 3;

/// Each body of a tree adds a freedom except the driven one.
const MAX_BODIES: usize = MAX_TREE_FREEDOMS + 1;

/// How a body's angle follows from the coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Angle {
    /// Coordinate `k` is the body's absolute angle (a revolute joint).
    Free(usize),
    /// The driver prescribes it.
    Driven,
    /// The parent's plus a constant (a translational joint); `sc`, its `(sin, cos)`, when
    /// the parent is the ground and the angle therefore constant.
    Fixed {
        relative: f64,
        sc: Option<(f64, f64)>,
    },
}

/// A translational joint's slide: coordinate `k` along the unit direction `dir`, fixed in the
/// body holding the line (the parent if `on_parent`, else the child).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slide {
    k: usize,
    dir: Vector2<f64>,
    on_parent: bool,
}

/// A body and the ideal joint to its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Link {
    body: usize,
    parent: BodyIndex,
    angle: Angle,
    /// The joint point in the parent's and in the body's frame (m).
    on_parent: Vector2<f64>,
    on_child: Vector2<f64>,
    slide: Option<Slide>,
}

/// A linkage whose ideal joints form a tree rooted at the ground, in joint coordinates.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Tree {
    /// Parents before children.
    links: Vec<Link>,
    freedoms: usize,
    /// The bodies that move with the freedoms, in body order: the others (the driven body
    /// pinned to the ground, and bodies on it with no freedom of their own) have zero Jacobian
    /// columns along the freedoms and add nothing to Lagrange's sums.
    moving: Vec<usize>,
}

/// Pose and velocity of one body, with the arms of the joint to its parent.
#[derive(Clone, Copy, Debug)]
struct Pose {
    f: Frame,
    /// `A_P`, `A_C`: from the parent's and the body's centre of mass to the joint (m).
    arm_parent: Vector2<f64>,
    arm_child: Vector2<f64>,
    /// The slide's global direction (zero without one).
    dir: Vector2<f64>,
}

/// Jacobian columns `∂(φ, r)/∂z` (`C`: the freedoms, then the driver's angle if needed) and the
/// acceleration at `z̈ = 0` of one body.
#[derive(Clone, Copy, Debug)]
struct Jacobian<const C: usize> {
    phi: [f64; C],
    r: [Vector2<f64>; C],
    aphi: f64,
    ar: Vector2<f64>,
}

impl<const C: usize> Jacobian<C> {
    const ZERO: Self = Jacobian {
        phi: [0.0; C],
        r: [Vector2::new(0.0, 0.0); C],
        aphi: 0.0,
        ar: Vector2::new(0.0, 0.0),
    };
}

/// Slot of a body in the per-body arrays: the ground is slot 0.
#[inline(always)]
fn slot(b: BodyIndex) -> usize {
    b.map_or(0, |i| i + 1)
}

impl Tree {
    /// The tree of `m`'s ideal joints, if they form one rooted at the ground with the driven
    /// body on a revolute joint and 1 to [`MAX_TREE_FREEDOMS`] freedoms.
    pub(super) fn of(m: &Mechanism) -> Option<Tree> {
        let bodies = m.bodies.len();
        let joints = m.revolutes.len() + m.translationals.len();
        if joints != bodies || bodies > MAX_BODIES {
            return None;
        }
        // Breadth first from the ground: with as many joints as bodies, reaching every body
        // means there is no loop.
        let mut reached: Vec<BodyIndex> = vec![None];
        let mut used = vec![false; joints];
        let mut links: Vec<Link> = Vec::new();
        let mut freedoms = 0;
        // Whether a body's position or angle depends on a freedom, by slot (ground first).
        let mut moving = vec![false; bodies + 1];
        let mut next = 0;
        while next < reached.len() {
            let parent = reached[next];
            next += 1;
            for (j, flag) in used.iter_mut().enumerate() {
                let (a, b) = match j.checked_sub(m.revolutes.len()) {
                    None => (m.revolutes[j].a, m.revolutes[j].b),
                    Some(i) => (m.translationals[i].a, m.translationals[i].b),
                };
                let (near, far, near_is_b) = match (a.body == parent, b.body == parent) {
                    (true, false) => (a, b, false),
                    (false, true) => (b, a, true),
                    _ => continue,
                };
                if *flag {
                    continue;
                }
                let child = far.body?;
                if reached.contains(&Some(child)) {
                    return None;
                }
                *flag = true;
                reached.push(Some(child));
                let driven = child == m.driver.body;
                let (angle, slide) = match j.checked_sub(m.revolutes.len()) {
                    None if driven => (Angle::Driven, None),
                    None => (Angle::Free(freedoms), None),
                    Some(_) if driven => return None,
                    Some(i) => {
                        let tj = &m.translationals[i];
                        let on_parent = near_is_b;
                        let relative = if on_parent {
                            tj.relative_angle
                        } else {
                            -tj.relative_angle
                        };
                        let sc = parent.is_none().then(|| relative.sin_cos());
                        let slide = Slide {
                            k: freedoms,
                            dir: perp(tj.normal),
                            on_parent,
                        };
                        (Angle::Fixed { relative, sc }, Some(slide))
                    }
                };
                if !driven {
                    freedoms += 1;
                }
                moving[child + 1] =
                    moving[slot(parent)] || matches!(angle, Angle::Free(_)) || slide.is_some();
                links.push(Link {
                    body: child,
                    parent,
                    angle,
                    on_parent: near.local,
                    on_child: far.local,
                    slide,
                });
            }
        }
        let all = links.len() == bodies;
        let moving = (0..bodies).filter(|&b| moving[b + 1]).collect();
        (all && (1..=MAX_TREE_FREEDOMS).contains(&freedoms)).then_some(Tree {
            links,
            freedoms,
            moving,
        })
    }

    /// Number of ideal-joint freedoms (coordinates).
    pub(super) fn freedoms(&self) -> usize {
        self.freedoms
    }

    /// The pose and velocity of link `l`'s body at time `t`, coordinates `z` and rates `zd`,
    /// from its parent's frame `p`.
    #[inline(always)]
    fn pose(m: &Mechanism, l: &Link, p: &Frame, t: f64, z: &[f64], zd: &[f64]) -> Pose {
        let (phi, w, sc) = match l.angle {
            Angle::Free(k) => (z[k], zd[k], z[k].sin_cos()),
            Angle::Driven => {
                let d = &m.driver;
                let phi = d.angle0 + d.omega * t;
                (phi, d.omega, phi.sin_cos())
            }
            Angle::Fixed { relative, sc } => {
                let phi = p.phi + relative;
                (phi, p.w, sc.unwrap_or_else(|| phi.sin_cos()))
            }
        };
        let mut c = Pose {
            f: Frame {
                r: Vector2::zeros(),
                phi,
                rd: Vector2::zeros(),
                w,
                sc,
            },
            arm_parent: rotate(p.sc, l.on_parent),
            arm_child: rotate(sc, l.on_child),
            dir: Vector2::zeros(),
        };
        let (mut vp, mut vc) = (perp(c.arm_parent) * p.w, perp(c.arm_child) * w);
        if let Some(s) = l.slide {
            let (d, dd) = (z[s.k], zd[s.k]);
            c.dir = rotate(if s.on_parent { p.sc } else { sc }, s.dir);
            let (arm, rate, w) = if s.on_parent {
                (&mut c.arm_parent, &mut vp, p.w)
            } else {
                (&mut c.arm_child, &mut vc, w)
            };
            *arm += c.dir * d;
            *rate += c.dir * dd + perp(c.dir) * (w * d);
        }
        c.f.r = p.r + c.arm_parent - c.arm_child;
        c.f.rd = p.rd + vp - vc;
        c
    }

    /// The Jacobian columns and `z̈ = 0` acceleration of link `l`'s body at pose `c` and rates
    /// `zd`, from its parent's frame `p` and Jacobian `pj` (`C`: the `F` freedoms, and the
    /// driver's angle if `C > F`).
    #[inline(always)]
    fn jacobian<const F: usize, const C: usize>(
        l: &Link,
        p: &Frame,
        pj: &Jacobian<C>,
        c: &Pose,
        zd: &[f64],
    ) -> Jacobian<C> {
        let mut cj = Jacobian::<C>::ZERO;
        match l.angle {
            Angle::Free(k) => cj.phi[k] = 1.0,
            Angle::Driven if C > F => cj.phi[C - 1] = 1.0,
            Angle::Driven => {}
            Angle::Fixed { .. } => (cj.phi, cj.aphi) = (pj.phi, pj.aphi),
        }
        let (pp, pc) = (perp(c.arm_parent), perp(c.arm_child));
        for j in 0..C {
            cj.r[j] = pj.r[j] + pp * pj.phi[j] - pc * cj.phi[j];
        }
        cj.ar = pj.ar + pp * pj.aphi - c.arm_parent * (p.w * p.w) - pc * cj.aphi
            + c.arm_child * (c.f.w * c.f.w);
        if let Some(s) = l.slide {
            // The slide moves the joint along the line of its body: +U on the parent's
            // side, −U on the body's, with the Coriolis term of the line's rotation.
            let (sign, w) = if s.on_parent {
                (1.0, p.w)
            } else {
                (-1.0, c.f.w)
            };
            cj.r[s.k] += c.dir * sign;
            cj.ar += perp(c.dir) * (sign * 2.0 * w * zd[s.k]);
        }
        cj
    }

    /// Writes the absolute coordinates and velocities `(q, q̇)` of the bodies at (t, z) into
    /// `y`, and the energy integrals that follow them in `z`, if any.
    pub(super) fn absolute(&self, m: &Mechanism, t: f64, z: &[f64], y: &mut [f64]) {
        let f = self.freedoms;
        let n = m.coordinates();
        let mut frame = [Frame::GROUND; MAX_BODIES + 1];
        for l in &self.links {
            frame[l.body + 1] = Self::pose(m, l, &frame[slot(l.parent)], t, z, &z[f..2 * f]).f;
        }
        for (b, p) in frame[1..=m.bodies.len()].iter().enumerate() {
            y[3 * b..3 * b + 3].copy_from_slice(&[p.r.x, p.r.y, p.phi]);
            y[n + 3 * b..n + 3 * b + 3].copy_from_slice(&[p.rd.x, p.rd.y, p.w]);
        }
        y[2 * n..].copy_from_slice(&z[2 * f..]);
    }

    /// The joint coordinates and rates of an absolute state `y` that satisfies the ideal
    /// joints (an assembled one), with the energy integrals that follow it.
    pub(super) fn coordinates(&self, m: &Mechanism, y: &[f64]) -> Vec<f64> {
        let (f, n) = (self.freedoms, m.coordinates());
        let mut z = vec![0.0; 2 * f];
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let frame = |b: BodyIndex| {
            b.map_or((Vector2::zeros(), Vector2::zeros(), 0.0, 0.0), |i| {
                let k = 3 * i;
                (
                    Vector2::new(q[k], q[k + 1]),
                    Vector2::new(v[k], v[k + 1]),
                    q[k + 2],
                    v[k + 2],
                )
            })
        };
        for l in &self.links {
            match (l.angle, l.slide) {
                (Angle::Free(k), _) => {
                    (z[k], z[f + k]) = (q[3 * l.body + 2], v[3 * l.body + 2]);
                }
                (_, Some(s)) => {
                    // The line's body and point, and the sliding point.
                    let (line, line_at, at) = if s.on_parent {
                        (l.parent, l.on_parent, (Some(l.body), l.on_child))
                    } else {
                        (Some(l.body), l.on_child, (l.parent, l.on_parent))
                    };
                    let point = |b: BodyIndex, local: Vector2<f64>| {
                        let (r, rd, phi, w) = frame(b);
                        let s = rotate(phi.sin_cos(), local);
                        (r + s, rd + perp(s) * w)
                    };
                    let (pl, vl) = point(line, line_at);
                    let (pa, va) = point(at.0, at.1);
                    let (_, _, phi, w) = frame(line);
                    let u = rotate(phi.sin_cos(), s.dir);
                    z[s.k] = u.dot(&(pa - pl));
                    z[f + s.k] = u.dot(&(va - vl)) + w * perp(u).dot(&(pa - pl));
                }
                _ => {}
            }
        }
        z.extend_from_slice(&y[2 * n..]);
        z
    }

    /// `dz = f(t, z)`: the joint accelerations of Lagrange's equations, and the energy powers
    /// when accounting is on.
    pub(super) fn rhs(
        &self,
        m: &Mechanism,
        state: &RunState,
        t: f64,
        z: &[f64],
        dz: &mut [f64],
        gaps: &mut [f64],
    ) -> Result<()> {
        // Sized at compile time for each number of freedoms (and so of bodies, one more);
        // the driver's column only for its torque.
        match (self.freedoms, m.energy_accounting) {
            (1, false) => self.rhs_sized::<1, 1, 3>(m, state, t, z, dz, gaps),
            (1, true) => self.rhs_sized::<1, 2, 3>(m, state, t, z, dz, gaps),
            (2, false) => self.rhs_sized::<2, 2, 4>(m, state, t, z, dz, gaps),
            (2, true) => self.rhs_sized::<2, 3, 4>(m, state, t, z, dz, gaps),
            (_, false) => self.rhs_sized::<3, 3, 5>(m, state, t, z, dz, gaps),
            (_, true) => self.rhs_sized::<3, 4, 5>(m, state, t, z, dz, gaps),
        }
    }

    /// [`Tree::rhs`] for `F` freedoms, `C` Jacobian columns (`F`, or `F + 1` with the
    /// driver's angle when energy accounting needs the driver torque) and `S = F + 2` body
    /// slots (the ground, then one per body).
    #[inline]
    fn rhs_sized<const F: usize, const C: usize, const S: usize>(
        &self,
        m: &Mechanism,
        state: &RunState,
        t: f64,
        z: &[f64],
        dz: &mut [f64],
        gaps: &mut [f64],
    ) -> Result<()> {
        debug_assert_eq!(
            (F, C, S),
            (
                self.freedoms,
                self.freedoms + usize::from(m.energy_accounting),
                m.bodies.len() + 1
            )
        );
        let (u, ud) = (chunk::<F>(z), chunk::<F>(&z[F..]));
        // Frames and Jacobians walking the tree, parents first; slot 0 stays the ground's.
        let mut frame = [Frame::GROUND; S];
        let mut jac = [Jacobian::<C>::ZERO; S];
        for l in &self.links {
            let (p, pj) = (frame[slot(l.parent)], jac[slot(l.parent)]);
            let c = Self::pose(m, l, &p, t, u, ud);
            jac[l.body + 1] = Self::jacobian::<F, C>(l, &p, &pj, &c, ud);
            frame[l.body + 1] = c.f;
        }
        let mut force = [[0.0; 3]; S];
        let (p_normal, p_friction) = m
            .applied_forces(
                state,
                |b| frame[slot(b)],
                &mut force.as_flattened_mut()[3..],
                gaps,
            )
            .map_err(|(k, delta)| m.overload(t, k, delta))?;
        // Lagrange: mass matrix Jᵀ M J (lower triangle) and forces Jᵀ (F − M a), over the
        // bodies that move with the freedoms (the others add exact zeros).
        let mut mass = [[0.0; F]; F];
        let mut rhs = [0.0; F];
        for &b in &self.moving {
            let (j, body) = (&jac[b + 1], &m.bodies[b]);
            let f = &force[b + 1];
            let fr = Vector2::new(f[0], f[1]) - j.ar * body.mass;
            let tau = f[2] - body.inertia * j.aphi;
            for i in 0..F {
                rhs[i] += j.r[i].dot(&fr) + j.phi[i] * tau;
                for k in 0..=i {
                    mass[i][k] +=
                        body.mass * j.r[i].dot(&j.r[k]) + body.inertia * j.phi[i] * j.phi[k];
                }
            }
        }
        let acc = cholesky_solve(&mut mass, rhs).ok_or_else(|| Error::Integration {
            time: t,
            cause: "non-finite state: the step is too large for the contact stiffness".into(),
        })?;
        let (rates, rest) = dz.split_at_mut(F);
        rates.copy_from_slice(ud);
        rest[..F].copy_from_slice(&acc);
        if m.energy_accounting {
            // The driver torque is the generalised force along the driver's angle that the
            // motion needs beyond the applied forces: Σ (M q̈ − F) · ∂q/∂φ_driver.
            let (d, mut torque) = (C - 1, 0.0);
            for ((j, f), body) in jac[1..].iter().zip(&force[1..]).zip(&m.bodies) {
                let (mut ar, mut aphi) = (j.ar, j.aphi);
                for (i, a) in acc.iter().enumerate() {
                    ar += j.r[i] * *a;
                    aphi += j.phi[i] * a;
                }
                let fr = ar * body.mass - Vector2::new(f[0], f[1]);
                torque += j.r[d].dot(&fr) + j.phi[d] * (body.inertia * aphi - f[2]);
            }
            dz[2 * F..2 * F + ENERGY_STATES].copy_from_slice(&[
                torque * m.driver.omega,
                p_normal,
                p_friction,
            ]);
        }
        Ok(())
    }
}

/// The first `N` components of `s`, as an array (one length check instead of one per index).
#[inline(always)]
fn chunk<const N: usize>(s: &[f64]) -> &[f64; N] {
    s.first_chunk()
        .expect("a state of the formulation's length")
}

/// Solves `A x = b` for the symmetric positive definite `A` given by its lower triangle
/// (overwritten by its Cholesky factor); `None` if a pivot is not positive.
#[inline]
fn cholesky_solve<const F: usize>(a: &mut [[f64; F]; F], mut b: [f64; F]) -> Option<[f64; F]> {
    for j in 0..F {
        let d = a[j][j] - a[j][..j].iter().map(|x| x * x).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..F {
            let dot: f64 = a[i][..j].iter().zip(&a[j][..j]).map(|(x, y)| x * y).sum();
            a[i][j] = (a[i][j] - dot) / d;
        }
    }
    for i in 0..F {
        for k in 0..i {
            b[i] -= a[i][k] * b[k];
        }
        b[i] /= a[i][i];
    }
    for i in (0..F).rev() {
        for k in i + 1..F {
            b[i] -= a[k][i] * b[k];
        }
        b[i] /= a[i][i];
    }
    Some(b)
}
