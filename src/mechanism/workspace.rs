//! The workspace of the constraint solve: which equations are solved for one coordinate,
//! the sparse rows of the others and their Schur complement `Φ_q M⁻¹ Φ_qᵀ`, factorised by
//! LDLᵀ ([`Workspace::project`]). Sized once per run; nothing here allocates per evaluation.

use super::{BodyIndex, ClearanceJoint, Mechanism, MIN_RELATIVE_PIVOT};
use crate::ode::EventValue;
use crate::{Error, Result};
use nalgebra::Vector2;

/// Rows of the constraint system found linearly dependent by the LDLᵀ solve: the row whose
/// pivot vanished, then the earlier rows it combines.
#[derive(Debug)]
pub(super) struct Dependent(pub(super) Vec<usize>);

/// A constraint equation solved for one coordinate: `coef · q̈_coord + Σ_other (Φ_q)_c q̈_c =
/// γ̂`, with every other column on a coordinate solved before.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Solved {
    pub(super) row: Row,
    pub(super) coord: usize,
    /// 1 / (∂Φ/∂q_coord), the same at every state: a multiplication, not a division, on the
    /// chain from one solved coordinate to the next.
    pub(super) inv_coef: f64,
    pub(super) gamma: f64,
    pub(super) phi: f64,
    /// ∂Φ/∂t.
    pub(super) phi_t: f64,
}

/// Where `constraints` stores an equation.
#[derive(Clone, Copy, Debug)]
pub(super) enum Slot {
    Row(usize),
    Solved(usize),
}

/// Stores the equations of one `constraints` call, in order, at their slots.
pub(super) struct Sink<'a> {
    pub(super) rows: &'a mut [Row],
    pub(super) gamma: &'a mut [f64],
    pub(super) solved: &'a mut [Solved],
    pub(super) slot: &'a [Slot],
    pub(super) phi: Option<&'a mut [f64]>,
    pub(super) e: usize,
}

impl Sink<'_> {
    /// The next equation: its two blocks of Φ_q, γ, Φ and ∂Φ/∂t.
    #[inline(always)]
    pub(super) fn set(
        &mut self,
        blocks: [(BodyIndex, [f64; 3]); 2],
        g: f64,
        value: f64,
        phi_t: f64,
    ) {
        match self.slot[self.e] {
            Slot::Row(i) => {
                self.rows[i].set(blocks);
                self.gamma[i] = g;
                if let Some(phi) = self.phi.as_deref_mut() {
                    phi[i] = value;
                }
            }
            Slot::Solved(j) => {
                let s = &mut self.solved[j];
                s.row.set(blocks);
                (s.gamma, s.phi, s.phi_t) = (g, value, phi_t);
            }
        }
        self.e += 1;
    }
}

/// The scratch space of the right-hand side: the layout of the constraint solve, derived once
/// from the mechanism's joints, and every buffer sized once, so that an evaluation allocates
/// nothing. One per run ([`Mechanism::workspace`]); it carries nothing from one evaluation to
/// the next that changes a result, and keeps the penetrations and their rates of the last
/// evaluation ([`Workspace::last_gaps`]).
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    /// `(sin φ, cos φ)` of every body: one `sin_cos` per body and evaluation, not per point.
    pub(super) rot: Vec<(f64, f64)>,
    /// Whether a body's rotation matters: it has a point off its centre of mass or carries a
    /// translational joint's axis. The others skip their `sin_cos` (a tenth of the
    /// right-hand side), as their rotation multiplies only zero vectors.
    pub(super) rotates: Vec<bool>,
    /// Diagonal of M per coordinate.
    pub(super) mass: Vec<f64>,
    /// Diagonal of M⁻¹ per coordinate, zero for the solved ones.
    pub(super) inv_mass: Vec<f64>,
    /// Applied forces F: x, y and torque of each body.
    pub(super) force: Vec<[f64; 3]>,
    /// Storage of each equation, in the order `constraints` visits them.
    pub(super) slot: Vec<Slot>,
    /// The equations solved for one coordinate, in the order they are solved (driver first).
    pub(super) solved: Vec<Solved>,
    /// Φ_q without the solved equations, sparse: every row touches at most two bodies.
    pub(super) rows: Vec<Row>,
    /// The non-zero entries of the lower triangle of Φ_q M⁻¹ Φ_qᵀ: the pairs of row blocks of
    /// the same body. Fixed by the joints, so found once, in `resize_workspace`.
    pub(super) pairs: Vec<Pair>,
    pub(super) gamma: Vec<f64>,
    /// J W Jᵀ, then its LDLᵀ factors (row-major m×m, lower triangle).
    pub(super) schur: Vec<f64>,
    /// The pivots D of the LDLᵀ factorisation.
    pub(super) pivots: Vec<f64>,
    pub(super) lambda: Vec<f64>,
    /// Φ_qᵀ λ, for the driver's torque.
    pub(super) reaction: Vec<f64>,
    /// Penetration δ (m) of each clearance joint and its rate (m/s) at the last evaluation.
    pub(super) gaps: Vec<EventValue>,
}

/// One row of Φ_q: the three columns of each of (at most) two bodies, and the same columns
/// times M⁻¹. A `None` body (ground) has zero columns and comes second.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Row {
    pub(super) body: [BodyIndex; 2],
    /// Index of each block's first coordinate (0 for a `None` body).
    pub(super) at: [usize; 2],
    pub(super) col: [[f64; 3]; 2],
    pub(super) wcol: [[f64; 3]; 2],
}

/// Rows `i ≥ j` whose blocks `a` and `b` belong to the same body.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pair {
    pub(super) i: usize,
    pub(super) a: usize,
    pub(super) j: usize,
    pub(super) b: usize,
}

#[inline]
pub(super) fn dot3(a: &[f64; 3], b: &[f64]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Row {
    /// Sets the blocks in place (a `Row` returned by value would be copied by `memcpy`).
    #[inline]
    pub(super) fn set(&mut self, mut blocks: [(BodyIndex, [f64; 3]); 2]) {
        // A ground block goes second, where `dot` skips it.
        if blocks[0].0.is_none() {
            blocks.swap(0, 1);
        }
        for (s, (body, col)) in blocks.into_iter().enumerate() {
            self.body[s] = body;
            (self.at[s], self.col[s]) = match body {
                Some(i) => (3 * i, col),
                None => (0, [0.0; 3]),
            };
        }
    }

    /// Σ columns · x over the row's bodies (x: 3 entries per body).
    #[inline]
    pub(super) fn dot(&self, x: &[f64]) -> f64 {
        let [a, b] = self.at;
        let first = dot3(&self.col[0], &x[a..a + 3]);
        // Most rows of one body are pins and locks to the ground: skip its zero block.
        match self.body[1] {
            Some(_) => first + dot3(&self.col[1], &x[b..b + 3]),
            None => first,
        }
    }

    /// The coordinates and values of the non-zero columns.
    pub(super) fn entries(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..2)
            .filter(|&s| self.body[s].is_some())
            .flat_map(move |s| (0..3).map(move |k| (self.at[s] + k, self.col[s][k])))
            .filter(|&(_, c)| c != 0.0)
    }
}

impl Workspace {
    /// Penetration δ (m) of each clearance joint and its rate δ̇ (m/s) at the state of the last
    /// evaluation of the right-hand side: after an accepted step, at its end (every method
    /// evaluates the right-hand side there last), which is where a run tests for contact
    /// onsets.
    pub fn last_gaps(&self) -> &[EventValue] {
        &self.gaps
    }

    /// Lays out the constraint solve of `m` (which equations are solved for one coordinate,
    /// the sparse rows of the others, the pairs of blocks that meet) and sizes every buffer.
    /// Errors when a joint constrains coordinates the others already fix (redundant joints).
    pub fn new(m: &Mechanism) -> Result<Workspace> {
        Workspace::holding(m, &[])
    }

    /// [`Workspace::new`] for `m` with its last `held.len()` revolutes the clearance joints
    /// `held`, held ideal (assembly): an error names them as the scene does.
    pub(super) fn holding(m: &Mechanism, held: &[ClearanceJoint]) -> Result<Workspace> {
        let n = m.coordinates();
        let equations = m.constraint_count();
        let mass: Vec<f64> = (m.bodies.iter())
            .flat_map(|b| [b.mass, b.mass, b.inertia])
            .collect();
        let mut rotates = vec![false; m.bodies.len()];
        let points = (m.revolutes.iter().flat_map(|j| [j.a, j.b]))
            .chain(m.translationals.iter().flat_map(|j| [j.a, j.b]))
            .chain(
                m.clearance_joints
                    .iter()
                    .flat_map(|j| [j.journal, j.bearing]),
            );
        for p in points {
            if let Some(i) = p.body.filter(|_| p.local != Vector2::zeros()) {
                rotates[i] = true;
            }
        }
        for i in m.translationals.iter().filter_map(|j| j.b.body) {
            rotates[i] = true;
        }
        let mut ws = Workspace {
            rot: vec![(0.0, 1.0); m.bodies.len()],
            rotates,
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            mass,
            force: vec![[0.0; 3]; n / 3],
            slot: (0..equations).map(Slot::Row).collect(),
            rows: vec![Row::default(); equations],
            gamma: vec![0.0; equations],
            reaction: vec![0.0; n],
            gaps: vec![EventValue::default(); m.clearance_joints.len()],
            ..Default::default()
        };
        // The pattern at two unremarkable states: a column non-zero at either is non-zero,
        // and a coefficient that differs between them is not constant.
        let pattern = |ws: &mut Workspace, phase: f64| {
            let q: Vec<f64> = (0..n).map(|i| (phase + i as f64).sin()).collect();
            m.constraints(ws, 0.0, &q, &q, None);
            ws.rows.clone()
        };
        let (p1, p2) = (pattern(&mut ws, 0.3), pattern(&mut ws, 1.1));
        // The equation that fixed each coordinate, if one has.
        let mut fixed: Vec<Option<usize>> = vec![None; n];
        let mut order = Vec::new();
        // The driver (the last equation) first, then sweeps until no equation qualifies.
        let candidates: Vec<usize> = std::iter::once(equations - 1)
            .chain(0..equations - 1)
            .collect();
        let mut progress = true;
        while progress {
            progress = false;
            for &e in &candidates {
                if order.iter().any(|&(o, _, _)| o == e) {
                    continue;
                }
                let free: Vec<(usize, f64)> = (p1[e].entries().chain(p2[e].entries()))
                    .filter(|&(k, _)| fixed[k].is_none())
                    .collect();
                let coord = free.first().map(|f| f.0);
                if let Some(k) = coord.filter(|&k| free.iter().all(|f| f.0 == k)) {
                    let coefs = |p: &[Row]| p[e].entries().find(|f| f.0 == k).map(|f| f.1);
                    if let (Some(c), Some(c2)) = (coefs(&p1), coefs(&p2)) {
                        if c == c2 {
                            fixed[k] = Some(e);
                            order.push((e, k, c));
                            progress = true;
                        }
                    }
                } else if free.is_empty() {
                    // Name the joints that fixed its coordinates: a driver on a body whose
                    // angle a translational joint holds was reported as that joint's fault.
                    let mut by: Vec<usize> = (p1[e].entries().chain(p2[e].entries()))
                        .filter_map(|(k, _)| fixed[k])
                        .collect();
                    by.sort_unstable();
                    by.dedup();
                    let by: Vec<String> = by.iter().map(|&o| m.equation_joint(o, held)).collect();
                    let joint = m.equation_joint(e, held);
                    return Err(Error::invalid(
                        "joints",
                        if by.is_empty() {
                            format!(
                                "{joint} constrains no coordinate (both its ends on one body or \
                                 on the ground)"
                            )
                        } else {
                            format!(
                                "{joint} constrains coordinates already fixed by {}",
                                by.join(" and ")
                            )
                        },
                        "independent joints (no locked or redundant joint)",
                    ));
                }
            }
        }
        let rows = equations - order.len();
        let mut next_row = 0;
        for (e, slot) in ws.slot.iter_mut().enumerate() {
            *slot = match order.iter().position(|&(o, _, _)| o == e) {
                Some(j) => Slot::Solved(j),
                None => {
                    next_row += 1;
                    Slot::Row(next_row - 1)
                }
            };
        }
        ws.solved = (order.iter())
            .map(|&(_, coord, coef)| Solved {
                coord,
                inv_coef: 1.0 / coef,
                ..Default::default()
            })
            .collect();
        for s in &ws.solved {
            ws.inv_mass[s.coord] = 0.0;
        }
        ws.rows.truncate(rows);
        ws.gamma.truncate(rows);
        ws.schur = vec![0.0; rows * rows];
        ws.pivots = vec![0.0; rows];
        ws.lambda = vec![0.0; rows];
        // The rows' bodies do not depend on the state: any state reveals the pattern.
        let zeros = vec![0.0; n];
        m.constraints(&mut ws, 0.0, &zeros, &zeros, None);
        let blocks = |i: usize| (0..2).map(move |a| (i, a));
        let rows = &ws.rows;
        ws.pairs = (0..rows.len())
            .flat_map(blocks)
            .flat_map(|(i, a)| {
                (0..=i)
                    .flat_map(blocks)
                    .map(move |(j, b)| Pair { i, a, j, b })
            })
            .filter(|p| rows[p.i].body[p.a].is_some() && rows[p.i].body[p.a] == rows[p.j].body[p.b])
            .collect();
        Ok(ws)
    }

    /// Moves x onto `J x = b` along `W Jᵀ` (W = M⁻¹ without the prescribed coordinates,
    /// which stay as they are): with b in `ws.lambda` on entry, solves `(J W Jᵀ) λ = J x − b`
    /// by LDLᵀ, leaving λ there, and sets `x −= W Jᵀ λ`.
    /// Only the blocks of bodies two rows share contribute ([`Workspace::pairs`]).
    pub(super) fn project(&mut self, x: &mut [f64]) -> std::result::Result<(), Dependent> {
        let ws = self;
        for (b, row) in ws.lambda.iter_mut().zip(&ws.rows) {
            *b = row.dot(x) - *b;
        }
        let m = ws.rows.len();
        ws.schur.fill(0.0);
        for p in &ws.pairs {
            let (ri, rj) = (&ws.rows[p.i], &ws.rows[p.j]);
            ws.schur[p.i * m + p.j] += dot3(&ri.col[p.a], &rj.wcol[p.b]);
        }
        let (a, d, b) = (&mut ws.schur, &mut ws.pivots, &mut ws.lambda);
        // Loop control, not arithmetic, dominates this small solve: with a constant size
        // (ldl_solve is inlined into each arm) the compiler unrolls it and drops the bounds
        // checks, a quarter fewer instructions for the standard scene.
        macro_rules! unrolled {
            ($($size:literal)*) => {
                match m {
                    $($size => ldl_solve(a, d, b, $size),)*
                    _ => ldl_solve(a, d, b, m),
                }
            };
        }
        if let Err(j) = unrolled!(1 2 3 4 5 6 7 8 9 10) {
            // Row j of L (complete when column j fails) holds the rows it combines.
            let coupled = (0..j).filter(|&k| ws.schur[j * m + k].abs() > 1e-6);
            return Err(Dependent(std::iter::once(j).chain(coupled).collect()));
        }
        for (r, l) in ws.rows.iter().zip(&ws.lambda) {
            for s in 0..2 {
                // A ground block would chain the stores to x[0..3] for nothing.
                if r.body[s].is_some() {
                    let at = r.at[s];
                    for (x, wc) in x[at..at + 3].iter_mut().zip(&r.wcol[s]) {
                        *x -= l * wc;
                    }
                }
            }
        }
        Ok(())
    }

    /// The driver's torque −λ_d, from the equations of motion of the solved coordinates,
    /// `m_k q̈_k = F_k − (Φ_qᵀ λ)_k`, taken in reverse order: each gives the multiplier of
    /// the equation solved for it, as only equations solved later (and the rows) touch it.
    pub(super) fn driver_torque(&mut self, acc: &[f64]) -> f64 {
        let ws = self;
        ws.reaction.fill(0.0);
        let add = |reaction: &mut [f64], r: &Row, l: f64| {
            for (k, c) in r.entries() {
                reaction[k] += c * l;
            }
        };
        for (r, &l) in ws.rows.iter().zip(&ws.lambda) {
            add(&mut ws.reaction, r, l);
        }
        let mut lambda = 0.0;
        for s in ws.solved.iter().rev() {
            let k = s.coord;
            lambda =
                (ws.force.as_flattened()[k] - ws.mass[k] * acc[k] - ws.reaction[k]) * s.inv_coef;
            add(&mut ws.reaction, &s.row, lambda);
        }
        // The driver's equation is solved first, so its multiplier comes last.
        -lambda
    }

    /// Sets each solved coordinate of x from its equation, `coef · x_k = b − Σ_other Φ_q x`
    /// (b from `target`), in order; x must be zero there on entry.
    #[inline]
    pub(super) fn solve_fixed(&self, x: &mut [f64], target: impl Fn(&Solved) -> f64) {
        for s in &self.solved {
            x[s.coord] = (target(s) - s.row.dot(x)) * s.inv_coef;
        }
    }

    /// The constraint equation at index `i` of [`Mechanism::constraint_vector`] (the rows of
    /// the constraint system, then the equations solved for one coordinate).
    pub(super) fn vector_equation(&self, i: usize) -> usize {
        let rows = self.rows.len();
        let wanted = |slot: &Slot| match *slot {
            Slot::Row(r) => i < rows && r == i,
            Slot::Solved(j) => i >= rows && j == i - rows,
        };
        self.slot.iter().position(wanted).unwrap_or(0)
    }
}

/// In-place LDLᵀ factorisation and solve of the SPD `m×m` matrix `a` (row-major, lower
/// triangle used), overwriting `b` with the solution. Errors with the column whose pivot is
/// not above [`MIN_RELATIVE_PIVOT`] times its diagonal entry (`a` singular or nearly so).
/// On exit the strict lower triangle holds L, the diagonal 1/D and `pivots` D. No square
/// roots and one division per column: the solve is bound by latency, not by its flops.
#[inline(always)]
pub(super) fn ldl_solve(
    a: &mut [f64],
    pivots: &mut [f64],
    b: &mut [f64],
    m: usize,
) -> std::result::Result<(), usize> {
    let (a, pivots, b) = (&mut a[..m * m], &mut pivots[..m], &mut b[..m]);
    for j in 0..m {
        let diagonal = a[j * m + j];
        let mut d = diagonal;
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k] * pivots[k];
        }
        // Also refuses NaN (no comparison holds) and a non-finite pivot.
        let regular = d > MIN_RELATIVE_PIVOT * diagonal && d.is_finite();
        if !regular {
            return Err(j);
        }
        let inv = 1.0 / d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k] * pivots[k];
            }
            a[i * m + j] = s * inv;
        }
        // Forward substitution L y = b, row by row as L is completed. Sums accumulate in
        // locals: through `b[j]` every term would wait for the previous store.
        let mut y = b[j];
        for k in 0..j {
            y -= a[j * m + k] * b[k];
        }
        b[j] = y;
        a[j * m + j] = inv;
        pivots[j] = d;
    }
    // D z = y, then back substitution Lᵀ x = z.
    for i in (0..m).rev() {
        let mut x = b[i] * a[i * m + i];
        for k in i + 1..m {
            x -= a[k * m + i] * b[k];
        }
        b[i] = x;
    }
    Ok(())
}
