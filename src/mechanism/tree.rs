//! Joint coordinates for tree-shaped linkages: when the ideal joints connect every body to the
//! ground without a closed loop (loops close only through clearance joints, as in the
//! slider-crank), the run integrates one coordinate per ideal-joint freedom instead of three
//! per body. The coordinate of a revolute joint is its child body's absolute angle (so that its
//! error scale stays that of the angle, not of the turns of the parent), that of a
//! translational joint the slide along its line; the driven body's angle is prescribed. A body
//! that no ideal joint connects to the ground (held by clearance joints only, as the rod of
//! `two_clearance`) floats: its centre of mass and angle are three coordinates, the absolute
//! ones, and the bodies on its ideal joints hang from it.
//!
//! Each body's pose is closed-form in the coordinates, walking the tree from the ground:
//! `r_C = r_P + A_P − A_C` with `A = R(φ) (l + d u)` the arm from a body's centre of mass to
//! the joint (`d u` the slide, on the body holding the line). With `J = ∂(r, φ)/∂z` and the
//! acceleration `a` of the motion at `z̈ = 0` (centripetal, Coriolis and driver terms), the
//! equations of motion are Lagrange's, `(Jᵀ M J) z̈ = Jᵀ (F − M a)`: a mass matrix of the size of
//! the freedoms (at most [`MAX_TREE_FREEDOMS`]), solved as `L D Lᵀ`. No constraint is
//! integrated, so there is nothing to stabilise and no drift. Clearance joints are the same
//! force elements as in the absolute formulation (the same kinematics and laws).

use super::kinematics::{perp, rotate, sincos, Frame};
use super::{BodyIndex, Mechanism, RunState, ENERGY_STATES};
use crate::ode::EventValue;
use crate::{Error, Result};
use nalgebra::Vector2;

/// Most ideal-joint freedoms integrated in joint coordinates; a tree with more keeps the
/// absolute coordinates. The shipped tree scenes have 2 (the slider-crank's rod angle and
/// slider position; the four-bar's coupler and rocker angles) and 4 (`two_clearance`: its
/// floating rod's three and the slider's position).
pub const MAX_TREE_FREEDOMS: usize = 4;

/// Most bodies of a tree in joint coordinates (a [`shape_code`] holds one link per body).
const MAX_BODIES: usize = 4;

/// How a body's angle follows from the coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Angle {
    /// Coordinate `k` is the body's absolute angle (a revolute joint).
    Free(usize),
    /// The driver prescribes it.
    Driven,
    /// The parent's plus the link's constant `relative` (a translational joint).
    Fixed,
    /// A floating body on the ground: coordinates `k` and `k + 1` are its centre of mass's
    /// absolute position, `k + 2` its absolute angle.
    Floating(usize),
}

/// A translational joint's slide: coordinate `k` along the link's unit direction `dir`, fixed
/// in the body holding the line (the parent if `on_parent`, else the child).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slide {
    k: usize,
    on_parent: bool,
}

/// Which coordinates move a link's body, and how: what a [`shape_code`] fixes of a link
/// besides its slots, so that the walk of a known shape has no branch on them.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Joint {
    angle: Angle,
    slide: Option<Slide>,
}

impl Joint {
    /// Eight bits: the angle's kind (0 driven, 1 free, 2 fixed, 3 floating) in bits 0-1 and
    /// its (first) coordinate in bits 2-3; whether there is a slide in bit 4, whether on the parent in
    /// bit 5, its coordinate in bits 6-7 (coordinates are below [`MAX_TREE_FREEDOMS`] ≤ 4).
    const fn code(self) -> u128 {
        let angle = match self.angle {
            Angle::Driven => 0,
            Angle::Free(k) => 1 | (k << 2),
            Angle::Fixed => 2,
            Angle::Floating(k) => 3 | (k << 2),
        };
        let slide = match self.slide {
            None => 0,
            Some(s) => 16 | ((s.on_parent as usize) << 5) | (s.k << 6),
        };
        (angle | slide) as u128
    }

    /// The joint of [`Joint::code`]'s bits `c`.
    #[inline(always)]
    fn decode(c: u128) -> Joint {
        let k = |shift: u32| ((c >> shift) & 3) as usize;
        Joint {
            angle: match c & 3 {
                0 => Angle::Driven,
                1 => Angle::Free(k(2)),
                2 => Angle::Fixed,
                _ => Angle::Floating(k(2)),
            },
            slide: if c & 16 != 0 {
                Some(Slide {
                    k: k(6),
                    on_parent: c & 32 != 0,
                })
            } else {
                None
            },
        }
    }
}

/// A body and the ideal joint to its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Link {
    body: usize,
    parent: BodyIndex,
    joint: Joint,
    /// A [`Angle::Fixed`] body's angle relative to its parent's (rad), and the `(sin, cos)`
    /// of that angle: the body's own when the parent is the ground.
    relative: f64,
    relative_sc: (f64, f64),
    /// `A_C` of a [`Angle::Fixed`] body on the ground, constant: `on_child` turned by
    /// `relative_sc`.
    ground_arm: Vector2<f64>,
    /// The joint point in the parent's and in the body's frame (m).
    on_parent: Vector2<f64>,
    on_child: Vector2<f64>,
    /// A slide's unit direction in the frame of the body holding the line (zero without one).
    dir: Vector2<f64>,
}

/// A linkage whose ideal joints form a tree rooted at the ground, in joint coordinates.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Tree {
    /// Parents before children.
    links: Vec<Link>,
    freedoms: usize,
    /// Which links' parents and bodies are in which slots, their joints, and which bodies
    /// move with the freedoms ([`shape_code`]).
    shape: u128,
    /// Which sized walk [`Tree::rhs`] runs, chosen here from `freedoms` and `shape` so that
    /// each evaluation branches on one small value instead of comparing 128-bit codes.
    walk: Walk,
}

/// The sized walks of [`Tree::rhs`]: the known shapes', else one per number of freedoms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Walk {
    SliderCrank,
    FourBar,
    TwoClearance,
    Listed1,
    Listed2,
    Listed3,
    Listed4,
}

impl Walk {
    fn of(freedoms: usize, shape: u128) -> Walk {
        match freedoms {
            1 => Walk::Listed1,
            2 if shape == SLIDER_CRANK => Walk::SliderCrank,
            2 if shape == FOUR_BAR => Walk::FourBar,
            2 => Walk::Listed2,
            3 => Walk::Listed3,
            4 if shape == TWO_CLEARANCE => Walk::TwoClearance,
            _ => Walk::Listed4,
        }
    }
}

/// The code of a tree's shape: for link `i` (parents first), its parent's slot (0 for the
/// ground) in bits `16i..16i + 4`, its body's slot in bits `16i + 4..16i + 8` and its
/// [`Joint::code`] in bits `16i + 8..16i + 16`; bit `64 + s` set if the body in slot `s` moves
/// with the freedoms. The others (the driven body pinned to the ground, bodies on it with no
/// freedom of their own) have zero Jacobian columns along the freedoms and add nothing to
/// Lagrange's sums. Then the clearance joints (`ends`: the slots of each one's journal and
/// bearing bodies): their number in bits `72..76` and joint `k`'s journal's slot in bits
/// `76 + 8k..80 + 8k`, its bearing's in the next four, for at most [`CODED_CLEARANCES`]
/// joints (more are coded as 15 joints and no slots: a shape no known one equals).
const fn shape_code(
    links: &[(usize, usize, Joint)],
    moving: u128,
    ends: &[(usize, usize)],
) -> u128 {
    let mut code = moving << 64;
    let mut i = 0;
    while i < links.len() {
        let (parent, body, joint) = links[i];
        code |= ((parent | (body << 4)) as u128 | (joint.code() << 8)) << (16 * i);
        i += 1;
    }
    if ends.len() > CODED_CLEARANCES {
        return code | (15 << 72);
    }
    code |= (ends.len() as u128) << 72;
    let mut k = 0;
    while k < ends.len() {
        let (journal, bearing) = ends[k];
        code |= ((journal | (bearing << 4)) as u128) << (76 + 8 * k);
        k += 1;
    }
    code
}

/// Most clearance joints a [`shape_code`] holds.
const CODED_CLEARANCES: usize = 6;

// The layout of a [`shape_code`]: the links' 16 bits each below the moving bits, a slot
// (0..=MAX_BODIES) in 4 bits and a moving bit per slot in bits 64..72, a count below the 15 that
// marks too many clearance joints, and each coded joint's 8 bits within the 128.
const _: () = assert!(16 * MAX_BODIES <= 64 && MAX_BODIES < 8);
const _: () = assert!(CODED_CLEARANCES < 15 && 76 + 8 * CODED_CLEARANCES <= 128);

/// The driven crank's joint (to the ground).
const DRIVEN: Joint = Joint {
    angle: Angle::Driven,
    slide: None,
};

/// A slider on a line fixed in the ground, its slide coordinate 0.
const GROUND_SLIDE: Joint = Joint {
    angle: Angle::Fixed,
    slide: Some(Slide {
        k: 0,
        on_parent: true,
    }),
};

/// A driven crank (body 0) on the ground and a second body (body 1) on the crank, with a
/// third (body 2) on the ground: the last two move. One clearance joint, its journal on the
/// second body and its bearing on the third.
const fn crank_and_two(third: Joint, second: Joint) -> u128 {
    shape_code(
        &[(0, 1, DRIVEN), (0, 3, third), (1, 2, second)],
        0b1100,
        &[(2, 3)],
    )
}

/// The standard slider-crank's shape (crank, rod, slider): the slider's line on the ground
/// gives coordinate 0, the rod's angle coordinate 1.
const SLIDER_CRANK: u128 = crank_and_two(
    GROUND_SLIDE,
    Joint {
        angle: Angle::Free(1),
        slide: None,
    },
);

/// The shape of the four-bar whose coupler-rocker pin has the clearance (crank, coupler,
/// rocker): the rocker's angle is coordinate 0, the coupler's coordinate 1.
const FOUR_BAR: u128 = crank_and_two(
    Joint {
        angle: Angle::Free(0),
        slide: None,
    },
    Joint {
        angle: Angle::Free(1),
        slide: None,
    },
);

/// The shape of the slider-crank with clearance at both ends of its rod (`two_clearance`:
/// crank, rod, slider): the driven crank and the slider on the ground (the slider's line on the
/// ground gives coordinate 0), the rod floating (coordinates 1-3); clearance joints from the
/// crank's journal to the rod's bearing and from the rod's journal to the slider's bearing.
const TWO_CLEARANCE: u128 = shape_code(
    &[
        (0, 1, DRIVEN),
        (0, 3, GROUND_SLIDE),
        (
            0,
            2,
            Joint {
                angle: Angle::Floating(1),
                slide: None,
            },
        ),
    ],
    0b1100,
    &[(1, 2), (2, 3)],
);

/// Where the walk finds each link's parent and body, its joint, and which bodies move: read
/// from the links, or constants of a [`shape_code`] that the compiler unrolls (the parents'
/// frames then stay in registers, the ground's zeros drop out, and no joint kind is tested).
trait Shape: Copy {
    /// Slots of link `i`'s parent and body.
    fn slots(self, i: usize, l: &Link) -> (usize, usize);
    /// Link `i`'s joint.
    fn joint(self, i: usize, l: &Link) -> Joint;
    /// Whether the body in slot `s` moves with the freedoms, given the tree's code.
    fn moves(self, code: u128, s: usize) -> bool;
    /// How many clearance joints `m` has.
    fn clearances(self, m: &Mechanism) -> usize;
    /// The bodies of clearance joint `k`'s journal and bearing.
    fn ends(self, k: usize, m: &Mechanism) -> (BodyIndex, BodyIndex);
    /// How many bodies `m` has, with `S` body slots (the ground's too): `S − 1` for a known
    /// shape; a listed one may leave slots empty (a floating body adds three freedoms).
    fn bodies<const S: usize>(self, m: &Mechanism) -> usize;
}

/// The shape read at run time.
#[derive(Clone, Copy)]
struct Listed;

impl Shape for Listed {
    #[inline(always)]
    fn slots(self, _: usize, l: &Link) -> (usize, usize) {
        (slot(l.parent), l.body + 1)
    }
    #[inline(always)]
    fn joint(self, _: usize, l: &Link) -> Joint {
        l.joint
    }
    #[inline(always)]
    fn moves(self, code: u128, s: usize) -> bool {
        (code >> (64 + s)) & 1 != 0
    }
    #[inline(always)]
    fn clearances(self, m: &Mechanism) -> usize {
        m.clearance_joints.len()
    }
    #[inline(always)]
    fn ends(self, k: usize, m: &Mechanism) -> (BodyIndex, BodyIndex) {
        m.clearance_ends(k)
    }
    #[inline(always)]
    fn bodies<const S: usize>(self, m: &Mechanism) -> usize {
        m.bodies.len()
    }
}

/// A shape fixed at compile time.
#[derive(Clone, Copy)]
struct Known<const CODE: u128>;

impl<const CODE: u128> Shape for Known<CODE> {
    #[inline(always)]
    fn slots(self, i: usize, _: &Link) -> (usize, usize) {
        let c = CODE >> (16 * i);
        ((c & 15) as usize, ((c >> 4) & 15) as usize)
    }
    #[inline(always)]
    fn joint(self, i: usize, _: &Link) -> Joint {
        Joint::decode((CODE >> (16 * i + 8)) & 255)
    }
    #[inline(always)]
    fn moves(self, _: u128, s: usize) -> bool {
        (CODE >> (64 + s)) & 1 != 0
    }
    #[inline(always)]
    fn clearances(self, _: &Mechanism) -> usize {
        ((CODE >> 72) & 15) as usize
    }
    #[inline(always)]
    fn ends(self, k: usize, m: &Mechanism) -> (BodyIndex, BodyIndex) {
        debug_assert!(k < self.clearances(m), "clearance joint {k} is not coded");
        let c = CODE >> (76 + 8 * k);
        // Slot s holds body s − 1; slot 0 is the ground.
        let body = |s: u128| (s as usize).checked_sub(1);
        (body(c & 15), body((c >> 4) & 15))
    }
    #[inline(always)]
    fn bodies<const S: usize>(self, _: &Mechanism) -> usize {
        S - 1
    }
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
/// acceleration at `z̈ = 0` of one body's centre of mass. Its angular acceleration at `z̈ = 0` is
/// zero in every tree: a free angle is a coordinate, the driver turns at constant speed and a
/// fixed angle follows its parent's.
#[derive(Clone, Copy, Debug)]
struct Jacobian<const C: usize> {
    phi: [f64; C],
    r: [Vector2<f64>; C],
    ar: Vector2<f64>,
}

impl<const C: usize> Jacobian<C> {
    const ZERO: Self = Jacobian {
        phi: [0.0; C],
        r: [Vector2::new(0.0, 0.0); C],
        ar: Vector2::new(0.0, 0.0),
    };
}

/// Slot of a body in the per-body arrays: the ground is slot 0.
#[inline(always)]
pub(super) fn slot(b: BodyIndex) -> usize {
    b.map_or(0, |i| i + 1)
}

/// Runs `$body` with the sizes of `$tree`'s walk bound to the constants `$f` (freedoms),
/// `$c` (Jacobian columns: the driver's angle too when `$energy`, for its torque) and `$s`
/// (body slots, the ground's first, as many as the freedoms' bodies can fill), and its
/// [`Shape`] to `$shape`: sized at compile time for each number of freedoms, with the
/// slider-crank's, the four-bar's and two_clearance's shapes fixed (their own unrolled copies,
/// without energy accounting).
macro_rules! sized_walk {
    ($tree:expr, $energy:expr, $f:ident, $c:ident, $s:ident, $shape:ident => $body:expr) => {{
        macro_rules! sized {
            ($fv:literal, $cv:literal, $sv:literal, $sh:expr) => {{
                const $f: usize = $fv;
                const $c: usize = $cv;
                const $s: usize = $sv;
                let $shape = $sh;
                $body
            }};
        }
        match ($tree.walk, $energy) {
            (Walk::SliderCrank, false) => sized!(2, 2, 4, Known::<SLIDER_CRANK>),
            (Walk::FourBar, false) => sized!(2, 2, 4, Known::<FOUR_BAR>),
            (Walk::TwoClearance, false) => sized!(4, 4, 4, Known::<TWO_CLEARANCE>),
            (Walk::Listed1, false) => sized!(1, 1, 3, Listed),
            (Walk::Listed1, true) => sized!(1, 2, 3, Listed),
            (Walk::Listed2, false) => sized!(2, 2, 4, Listed),
            (Walk::Listed2 | Walk::SliderCrank | Walk::FourBar, true) => sized!(2, 3, 4, Listed),
            (Walk::Listed3, false) => sized!(3, 3, 5, Listed),
            (Walk::Listed3, true) => sized!(3, 4, 5, Listed),
            (Walk::Listed4, false) => sized!(4, 4, 5, Listed),
            (Walk::Listed4 | Walk::TwoClearance, true) => sized!(4, 5, 5, Listed),
        }
    }};
}

impl Tree {
    /// The tree of `m`'s ideal joints, if they form one rooted at the ground with the driven
    /// body on a revolute joint and 1 to [`MAX_TREE_FREEDOMS`] freedoms; a body no ideal joint
    /// connects to the ground floats on it, with the bodies hanging from it.
    pub(super) fn of(m: &Mechanism) -> Option<Tree> {
        let bodies = m.bodies.len();
        let joints = m.revolutes.len() + m.translationals.len();
        if joints > bodies || bodies > MAX_BODIES {
            return None;
        }
        // Breadth first from the ground, then from each body left over as a floating one: a
        // joint that reaches a body reached before closes a loop.
        let mut reached: Vec<BodyIndex> = vec![None];
        let mut used = vec![false; joints];
        let mut links: Vec<Link> = Vec::new();
        let mut freedoms = 0;
        // Whether a body's position or angle depends on a freedom, by slot (ground first).
        let mut moving = 0u128;
        let mut next = 0;
        loop {
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
                    let (mut relative, mut dir) = (0.0, Vector2::zeros());
                    let (angle, slide) = match j.checked_sub(m.revolutes.len()) {
                        None if driven => (Angle::Driven, None),
                        None => (Angle::Free(freedoms), None),
                        Some(_) if driven => return None,
                        Some(i) => {
                            let tj = &m.translationals[i];
                            let on_parent = near_is_b;
                            relative = if on_parent {
                                tj.relative_angle
                            } else {
                                -tj.relative_angle
                            };
                            dir = perp(tj.normal);
                            let slide = Slide {
                                k: freedoms,
                                on_parent,
                            };
                            (Angle::Fixed, Some(slide))
                        }
                    };
                    if !driven {
                        freedoms += 1;
                    }
                    if (moving >> slot(parent)) & 1 != 0
                        || matches!(angle, Angle::Free(_))
                        || slide.is_some()
                    {
                        moving |= 1 << (child + 1);
                    }
                    // The hot path's sincos of the angle the absolute state stores (the ground's
                    // 0 plus the offset: +0, not −0, for a line in the block), as its readers take it.
                    let relative_sc = sincos(0.0 + relative);
                    links.push(Link {
                        body: child,
                        parent,
                        joint: Joint { angle, slide },
                        relative,
                        relative_sc,
                        ground_arm: rotate(relative_sc, far.local),
                        on_parent: near.local,
                        on_child: far.local,
                        dir,
                    });
                }
            }
            // (Not the driven body: it may hang from a floating one, and the driver turns it
            // about a pin, which a floating body does not have.)
            let unreached = |b: &usize| !reached.contains(&Some(*b));
            let Some(body) = (0..bodies).filter(unreached).find(|&b| b != m.driver.body) else {
                if unreached(&m.driver.body) {
                    return None;
                }
                break;
            };
            reached.push(Some(body));
            moving |= 1 << (body + 1);
            links.push(Link {
                body,
                parent: None,
                joint: Joint {
                    angle: Angle::Floating(freedoms),
                    slide: None,
                },
                relative: 0.0,
                relative_sc: sincos(0.0),
                ground_arm: Vector2::zeros(),
                on_parent: Vector2::zeros(),
                on_child: Vector2::zeros(),
                dir: Vector2::zeros(),
            });
            freedoms += 3;
        }
        // (A joint of a body to itself is never walked.)
        let all = links.len() == bodies && used.iter().all(|&u| u);
        let slots: Vec<_> = links
            .iter()
            .map(|l| (slot(l.parent), l.body + 1, l.joint))
            .collect();
        let ends: Vec<_> = (m.clearance_joints.iter())
            .map(|cj| (slot(cj.journal.body), slot(cj.bearing.body)))
            .collect();
        let shape = shape_code(&slots, moving, &ends);
        (all && (1..=MAX_TREE_FREEDOMS).contains(&freedoms)).then_some(Tree {
            links,
            freedoms,
            shape,
            walk: Walk::of(freedoms, shape),
        })
    }

    /// Number of ideal-joint freedoms (coordinates).
    pub(super) fn freedoms(&self) -> usize {
        self.freedoms
    }

    /// Number of floating bodies (three coordinates each).
    pub(super) fn floating(&self) -> usize {
        (self.links.iter())
            .filter(|l| matches!(l.joint.angle, Angle::Floating(_)))
            .count()
    }

    /// The pose and velocity of link `l`'s body, whose joint is `joint`, at time `t`,
    /// coordinates `z` and rates `zd`, from its parent's frame `p` (the ground's if `ground`:
    /// its zeros are left out).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn pose(
        m: &Mechanism,
        l: &Link,
        joint: Joint,
        p: &Frame,
        ground: bool,
        t: f64,
        z: &[f64],
        zd: &[f64],
    ) -> Pose {
        let (phi, w, sc) = match joint.angle {
            Angle::Free(k) => (z[k], zd[k], sincos(z[k])),
            Angle::Driven => {
                let d = &m.driver;
                let phi = d.angle0 + d.omega * t;
                (phi, d.omega, sincos(phi))
            }
            Angle::Fixed => {
                let phi = p.phi + l.relative;
                // On the ground the angle is the constant relative one.
                (phi, p.w, if ground { l.relative_sc } else { sincos(phi) })
            }
            Angle::Floating(k) => (z[k + 2], zd[k + 2], sincos(z[k + 2])),
        };
        let mut c = Pose {
            f: Frame {
                r: Vector2::zeros(),
                phi,
                rd: Vector2::zeros(),
                w,
                sc,
            },
            arm_parent: if ground {
                l.on_parent
            } else {
                rotate(p.sc, l.on_parent)
            },
            arm_child: match joint.angle {
                Angle::Fixed if ground => l.ground_arm,
                // On its centre of mass (`Tree::of`).
                Angle::Floating(_) => Vector2::zeros(),
                _ => rotate(sc, l.on_child),
            },
            dir: Vector2::zeros(),
        };
        let mut vp = if ground {
            Vector2::zeros()
        } else {
            perp(c.arm_parent) * p.w
        };
        let mut vc = perp(c.arm_child) * w;
        if let Some(s) = joint.slide {
            let (d, dd) = (z[s.k], zd[s.k]);
            if s.on_parent {
                c.dir = if ground { l.dir } else { rotate(p.sc, l.dir) };
                c.arm_parent += c.dir * d;
                vp += c.dir * dd;
                if !ground {
                    vp += perp(c.dir) * (p.w * d);
                }
            } else {
                c.dir = rotate(sc, l.dir);
                c.arm_child += c.dir * d;
                vc += c.dir * dd + perp(c.dir) * (w * d);
            }
        }
        (c.f.r, c.f.rd) = if let Angle::Floating(k) = joint.angle {
            // On the ground at its centre of mass (`Tree::of`): no arms.
            (Vector2::new(z[k], z[k + 1]), Vector2::new(zd[k], zd[k + 1]))
        } else if ground {
            (c.arm_parent - c.arm_child, vp - vc)
        } else {
            (p.r + c.arm_parent - c.arm_child, p.rd + vp - vc)
        };
        c
    }

    /// The Jacobian columns and `z̈ = 0` acceleration of the body of a link with `joint` at
    /// pose `c` and rates `zd`, from its parent's frame `p` and Jacobian `pj` (`C`: the `F`
    /// freedoms, and the driver's angle if `C > F`).
    /// A ground parent (`ground`) has no columns and no acceleration: its terms are left
    /// out, as are the products with the zeros and ones of a revolute's own column.
    #[inline(always)]
    fn jacobian<const F: usize, const C: usize>(
        joint: Joint,
        p: &Frame,
        pj: &Jacobian<C>,
        ground: bool,
        c: &Pose,
        zd: &[f64],
    ) -> Jacobian<C> {
        let (pp, pc) = (perp(c.arm_parent), perp(c.arm_child));
        let spin = c.arm_child * (c.f.w * c.f.w);
        let mut cj = if ground {
            Jacobian {
                ar: spin,
                ..Jacobian::ZERO
            }
        } else {
            Jacobian {
                phi: [0.0; C],
                r: std::array::from_fn(|j| pj.r[j] + pp * pj.phi[j]),
                ar: pj.ar - c.arm_parent * (p.w * p.w) + spin,
            }
        };
        // The body's own angle: `r_C = … − A_C`, so its column gains `−perp(A_C)` per unit.
        match joint.angle {
            Angle::Free(k) => {
                cj.phi[k] = 1.0;
                cj.r[k] -= pc;
            }
            Angle::Driven if C > F => {
                cj.phi[C - 1] = 1.0;
                cj.r[C - 1] -= pc;
            }
            Angle::Driven => {}
            Angle::Fixed if ground => {}
            Angle::Fixed => {
                cj.phi = pj.phi;
                for j in 0..C {
                    cj.r[j] -= pc * cj.phi[j];
                }
            }
            // On the ground at its centre of mass: a unit column per coordinate.
            Angle::Floating(k) => {
                cj.r[k].x = 1.0;
                cj.r[k + 1].y = 1.0;
                cj.phi[k + 2] = 1.0;
            }
        }
        if let Some(s) = joint.slide {
            // The slide moves the joint along the line of its body: +U on the parent's
            // side, −U on the body's, with the Coriolis term of the line's rotation.
            if s.on_parent {
                cj.r[s.k] += c.dir;
                if !ground {
                    cj.ar += perp(c.dir) * (2.0 * p.w * zd[s.k]);
                }
            } else {
                cj.r[s.k] -= c.dir;
                cj.ar -= perp(c.dir) * (2.0 * c.f.w * zd[s.k]);
            }
        }
        cj
    }

    /// Calls `visit(l, joint, parent's slot, body's slot)` for each link `l` of `links`,
    /// parents first, with its joint and slots as `shape` gives them. Unrolled, so that the
    /// slots of a known shape are constants: its frames then stay in registers (a loop with
    /// that body is not unrolled by the compiler); `visit` must be inlined for that.
    #[inline(always)]
    fn walk(shape: impl Shape, links: &[Link], mut visit: impl FnMut(&Link, Joint, usize, usize)) {
        macro_rules! link {
            ($i:literal) => {
                if let Some(l) = links.get($i) {
                    let (ps, bs) = shape.slots($i, l);
                    visit(l, shape.joint($i, l), ps, bs);
                }
            };
        }
        link!(0);
        link!(1);
        link!(2);
        link!(3);
        const _: () = assert!(MAX_BODIES == 4, "one link! per body");
    }

    /// The frames of the bodies at (t, z), by [`slot`], as the absolute state of (t, z) gives
    /// them: each `sc` is [`sincos`] of the body's angle, what the contact kinematics takes
    /// from that state. The walk of [`Tree::rhs_sized`], without the Jacobians.
    #[inline(always)]
    pub(super) fn frames(&self, m: &Mechanism, t: f64, z: &[f64]) -> [Frame; MAX_BODIES + 1] {
        let mut frame = [Frame::GROUND; MAX_BODIES + 1];
        sized_walk!(self, false, F, _C, S, shape => {
            let (u, ud) = (chunk::<F>(z), chunk::<F>(&z[F..]));
            Self::walk(shape, &self.links[..shape.bodies::<S>(m)], #[inline(always)] |l, joint, ps, bs| {
                frame[bs] = Self::pose(m, l, joint, &frame[ps], ps == 0, t, u, ud).f;
            });
        });
        frame
    }

    /// Writes the absolute coordinates and velocities `(q, q̇)` of the bodies at (t, z) into
    /// `y`, and the energy integrals that follow them in `z`, if any.
    pub(super) fn absolute(&self, m: &Mechanism, t: f64, z: &[f64], y: &mut [f64]) {
        let (f, n) = (self.freedoms, m.coordinates());
        let frame = self.frames(m, t, z);
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
            match (l.joint.angle, l.joint.slide) {
                (Angle::Free(k), _) => {
                    (z[k], z[f + k]) = (q[3 * l.body + 2], v[3 * l.body + 2]);
                }
                (Angle::Floating(k), _) => {
                    let b = 3 * l.body;
                    z[k..k + 3].copy_from_slice(&q[b..b + 3]);
                    z[f + k..f + k + 3].copy_from_slice(&v[b..b + 3]);
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
                        let s = rotate(sincos(phi), local);
                        (r + s, rd + perp(s) * w)
                    };
                    let (pl, vl) = point(line, line_at);
                    let (pa, va) = point(at.0, at.1);
                    let (_, _, phi, w) = frame(line);
                    let u = rotate(sincos(phi), l.dir);
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
        gaps: &mut [EventValue],
    ) -> Result<()> {
        // (Energy accounting is read here, not in `Tree::of`'s `Walk`: a clone of the mechanism may
        // turn it off.)
        sized_walk!(self, m.energy_accounting, F, C, S, shape => {
            self.rhs_sized::<F, C, S>(shape, m, state, t, z, dz, gaps)
        })
    }

    /// [`Tree::rhs`] for `F` freedoms, `C` Jacobian columns (`F`, or `F + 1` with the
    /// driver's angle when energy accounting needs the driver torque) and `S` body slots (the
    /// ground, then one per body: `F + 2` but with a floating body, whose slots beyond the
    /// bodies stay empty), and the tree's `shape`.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn rhs_sized<const F: usize, const C: usize, const S: usize>(
        &self,
        shape: impl Shape,
        m: &Mechanism,
        state: &RunState,
        t: f64,
        z: &[f64],
        dz: &mut [f64],
        gaps: &mut [EventValue],
    ) -> Result<()> {
        debug_assert_eq!(
            (F, C),
            (
                self.freedoms,
                self.freedoms + usize::from(m.energy_accounting),
            )
        );
        let n = shape.bodies::<S>(m);
        debug_assert!(n < S && n == m.bodies.len());
        let (u, ud) = (chunk::<F>(z), chunk::<F>(&z[F..]));
        // Frames and Jacobians walking the tree, parents first; slot 0 stays the ground's.
        let mut frame = [Frame::GROUND; S];
        let mut jac = [Jacobian::<C>::ZERO; S];
        Self::walk(
            shape,
            &self.links[..n],
            #[inline(always)]
            |l, joint, ps, bs| {
                let (p, pj, ground) = (frame[ps], jac[ps], ps == 0);
                let c = Self::pose(m, l, joint, &p, ground, t, u, ud);
                jac[bs] = Self::jacobian::<F, C>(joint, &p, &pj, ground, &c, ud);
                frame[bs] = c.f;
            },
        );
        let mut force = [[0.0; 3]; S];
        // The known shapes' clearance joints, and so the frames read and forces added, are
        // fixed at compile time: the frames can stay in registers.
        let ends = |k| shape.ends(k, m);
        let gaps = &mut gaps[..shape.clearances(m)];
        let (p_normal, p_friction) = m
            .applied_forces(state, ends, |b| frame[slot(b)], &mut force[1..n + 1], gaps)
            .map_err(|(k, delta)| m.overload(t, k, delta))?;
        // Lagrange: mass matrix Jᵀ M J (lower triangle) and forces Jᵀ (F − M a), over the
        // bodies that move with the freedoms (the others add exact zeros).
        let mut mass = [[0.0; F]; F];
        let mut rhs = [0.0; F];
        let bodies = &m.bodies[..n];
        for s in 1..S {
            if !shape.moves(self.shape, s) {
                continue;
            }
            let (j, body, f) = (&jac[s], &bodies[s - 1], &force[s]);
            let fr = Vector2::new(f[0], f[1]) - j.ar * body.mass;
            for i in 0..F {
                rhs[i] += j.r[i].dot(&fr) + j.phi[i] * f[2];
                for (k, m_ik) in mass[i].iter_mut().enumerate().take(i + 1) {
                    *m_ik += body.mass * j.r[i].dot(&j.r[k]) + body.inertia * j.phi[i] * j.phi[k];
                }
            }
        }
        let acc = ldlt_solve(&mass, rhs).ok_or_else(|| Error::Integration {
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
                let (mut ar, mut aphi) = (j.ar, 0.0);
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

/// Solves `A x = b` for the symmetric positive definite `A` given by its lower triangle, as
/// `A = L D Lᵀ` with the pivots' reciprocals; `None` if a pivot is not positive. Neither a
/// square root nor a division waits for `b`: the factors depend only on the poses, while `b`
/// carries the contact forces, the end of the evaluation's longest chain of dependent
/// operations, and meets only multiplications and additions.
#[inline]
fn ldlt_solve<const F: usize>(a: &[[f64; F]; F], mut b: [f64; F]) -> Option<[f64; F]> {
    // `l[i][k]` (k < i) of the unit lower triangle, and each pivot's reciprocal.
    let mut l = [[0.0; F]; F];
    let (mut d, mut r) = ([0.0; F], [0.0; F]);
    for j in 0..F {
        let pivot = a[j][j] - (0..j).map(|k| l[j][k] * l[j][k] * d[k]).sum::<f64>();
        // (An infinite pivot too: its reciprocal would zero a row of a non-finite system.)
        if pivot.is_nan() || pivot <= 0.0 || pivot.is_infinite() {
            return None;
        }
        (d[j], r[j]) = (pivot, 1.0 / pivot);
        for i in j + 1..F {
            let dot: f64 = (0..j).map(|k| l[i][k] * l[j][k] * d[k]).sum();
            l[i][j] = (a[i][j] - dot) * r[j];
        }
    }
    for i in 0..F {
        for k in 0..i {
            b[i] -= l[i][k] * b[k];
        }
    }
    for i in (0..F).rev() {
        b[i] *= r[i];
        for k in i + 1..F {
            b[i] -= l[k][i] * b[k];
        }
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{scene_path, SceneFile};

    // The standard and four-bar scenes must take their unrolled paths (their speed depends
    // on it; the oracle in tests/formulations.rs checks the answers either way). Fails when a
    // scene's code differs from its constant: seen with the slider's coordinate set to 1.
    #[test]
    fn the_standard_and_fourbar_scenes_have_known_shapes() {
        // (The walk's check fails with Walk::of's two known shapes swapped: tried.)
        for (name, code, walk) in [
            ("standard", SLIDER_CRANK, Walk::SliderCrank),
            ("fourbar", FOUR_BAR, Walk::FourBar),
            ("two_clearance", TWO_CLEARANCE, Walk::TwoClearance),
        ] {
            let scene = SceneFile::read(scene_path(name)).unwrap().build().unwrap();
            let tree = Tree::of(&scene.mechanism).unwrap();
            assert_eq!((tree.shape, tree.walk), (code, walk), "{name}");
            assert_eq!(
                tree.floating(),
                usize::from(code == TWO_CLEARANCE),
                "{name}"
            );
        }
    }

    // The clearance joints a known shape fixes at compile time are the scene's (their count
    // and their journal and bearing bodies, as the shape read at run time gives them). Fails
    // with Known::ends's journal and bearing swapped: tried.
    #[test]
    fn known_shapes_decode_the_scenes_clearance_joints() {
        fn ends(shape: impl Shape, m: &Mechanism) -> Vec<(BodyIndex, BodyIndex)> {
            (0..shape.clearances(m)).map(|k| shape.ends(k, m)).collect()
        }
        let scene = |name| SceneFile::read(scene_path(name)).unwrap().build().unwrap();
        let standard = scene("standard").mechanism;
        assert_eq!(
            ends(Known::<SLIDER_CRANK>, &standard),
            ends(Listed, &standard)
        );
        let fourbar = scene("fourbar").mechanism;
        assert_eq!(ends(Known::<FOUR_BAR>, &fourbar), ends(Listed, &fourbar));
        let two = scene("two_clearance").mechanism;
        assert_eq!(ends(Known::<TWO_CLEARANCE>, &two), ends(Listed, &two));
    }

    // The clearance joints are part of the shape: the standard slider-crank with its clearance
    // joint's journal and bearing exchanged has the same links and moving bodies but must not
    // take the walk that fixes the standard's ends. Fails with the clearance bits dropped from
    // shape_code (the swapped scene then gets Walk::SliderCrank): tried.
    #[test]
    fn a_slider_crank_with_other_clearance_ends_is_not_the_standard_shape() {
        let mut f = SceneFile::read(scene_path("standard")).unwrap();
        let cj = &mut f.clearance[0];
        std::mem::swap(&mut cj.journal, &mut cj.bearing);
        let scene = f.build().unwrap();
        let tree = Tree::of(&scene.mechanism).unwrap();
        assert_eq!(tree.walk, Walk::Listed2);
        // only the clearance bits (72 and above) differ from the standard's
        assert_eq!(tree.shape & ((1 << 72) - 1), SLIDER_CRANK & ((1 << 72) - 1));
        assert_ne!(tree.shape, SLIDER_CRANK);
    }

    // An ideal joint of a body to itself is walked from neither side; with it the joints do
    // not form a tree (the assembly refuses the scene). Fails without the check that every
    // joint was walked: tried.
    #[test]
    fn a_joint_of_a_body_to_itself_is_not_a_tree() {
        let mut f = SceneFile::read(scene_path("two_clearance")).unwrap();
        let mut pin = f.revolute[0].clone();
        (pin.a, pin.b) = ("rod.A".into(), "rod.B".into());
        f.revolute.push(pin);
        let scene = f.build().unwrap();
        assert_eq!(Tree::of(&scene.mechanism), None);
    }

    // L D Lᵀ against a known solution for each size a tree has, and its refusals. Fails with
    // the back substitution's reciprocal applied after the update (tried).
    #[test]
    fn ldlt_solves_symmetric_positive_definite_systems() {
        use approx::assert_relative_eq;
        // A = Bᵀ B + I for a fixed B, lower triangle only (the upper is never read: NaN).
        fn system<const F: usize>() -> ([[f64; F]; F], [f64; F]) {
            let b = |i: usize, j: usize| ((3 * i + 5 * j) % 7) as f64 - 2.5;
            let mut a = [[f64::NAN; F]; F];
            for (i, row) in a.iter_mut().enumerate() {
                for (j, a_ij) in row.iter_mut().enumerate().take(i + 1) {
                    *a_ij = (0..F).map(|k| b(k, i) * b(k, j)).sum::<f64>() + f64::from(i == j);
                }
            }
            let x: [f64; F] = std::array::from_fn(|i| 1.0 - 0.75 * i as f64);
            let rhs = std::array::from_fn(|i| {
                (0..F)
                    .map(|j| if j <= i { a[i][j] } else { a[j][i] } * x[j])
                    .sum()
            });
            (a, rhs)
        }
        fn check<const F: usize>() {
            let (a, rhs) = system::<F>();
            let x = ldlt_solve(&a, rhs).unwrap();
            for (i, xi) in x.iter().enumerate() {
                assert_relative_eq!(*xi, 1.0 - 0.75 * i as f64, max_relative = 1e-12);
            }
        }
        check::<1>();
        check::<2>();
        check::<3>();
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(ldlt_solve(&[[bad]], [1.0]), None, "{bad}");
        }
        // Not positive definite: the second pivot is 1 − 4 < 0.
        assert_eq!(ldlt_solve(&[[1.0, f64::NAN], [2.0, 1.0]], [1.0, 1.0]), None);
    }

    // Every joint a tree can hold survives its code. Fails with the slide's coordinate read
    // from bits 4-5: tried.
    #[test]
    fn joint_codes_round_trip() {
        for k in 0..MAX_TREE_FREEDOMS {
            for angle in [
                Angle::Driven,
                Angle::Free(k),
                Angle::Fixed,
                Angle::Floating(k),
            ] {
                for slide in [None, Some((k, false)), Some((k, true))] {
                    let slide = slide.map(|(k, on_parent)| Slide { k, on_parent });
                    let joint = Joint { angle, slide };
                    assert_eq!(Joint::decode(joint.code()), joint);
                }
            }
        }
    }
}
