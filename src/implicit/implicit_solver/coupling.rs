//! The carriers' rows of the coupled solve (`super::super::carriers`): each body's velocity
//! and spin change are two more unknowns after the nodes', and each coupled node's filtered
//! part of Δv is the body's motion at the node.

use glam::{DMat3, DVec3};

use crate::implicit::Carriers;
use crate::implicit::Twist;

/// The skew matrix C of `a`: C·x = a × x.
fn cross_matrix(a: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, a.z, -a.y),
        DVec3::new(-a.z, 0.0, a.x),
        DVec3::new(a.y, -a.x, 0.0),
    )
}

/// One solve's coupling: which node goes with which body, and the bodies' preconditioner.
pub(super) struct Coupling<'a> {
    carriers: &'a Carriers,
    /// (node, body) for every coupled node.
    pairs: Vec<(usize, usize)>,
    /// Inverse of each body slot's diagonal block (ΔV, then Δω, per body; zero for the spin of
    /// a body that cannot turn).
    inverse: Vec<DMat3>,
    /// The scheme's step over Rapier's (1 for backward Euler, BDF2's β: 2/3 at a constant step): the body's rows,
    /// backward Euler's over Rapier's step, are scaled by it to match the nodes'.
    scale: f64,
}

impl<'a> Coupling<'a> {
    /// The coupling of `carriers` with the scheme's step over Rapier's, `scale` (nodes whose
    /// body index is out of range, or for which `keep` is false, are left out).
    pub fn new(carriers: &'a Carriers, scale: f64, keep: impl Fn(usize) -> bool) -> Self {
        let bodies = carriers.bodies.len();
        let pairs = carriers
            .of_node
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.map(|b| (i, b as usize)))
            .filter(|&(i, b)| b < bodies && keep(i))
            .collect();
        Self {
            carriers,
            pairs,
            inverse: vec![DMat3::ZERO; 2 * bodies],
            scale,
        }
    }

    /// Number of body slots (two per body).
    pub fn slots(&self) -> usize {
        2 * self.carriers.bodies.len()
    }

    /// The body's motion at coupled node `i` for the body slots `x`: ΔV + Δω × r.
    fn motion(&self, i: usize, b: usize, x: &[DVec3]) -> DVec3 {
        x[2 * b] + x[2 * b + 1].cross(self.carriers.arm[i])
    }

    /// Adds to each coupled node's `full` velocity the filtered-out part (v − filter(v)) of its
    /// body's motion for the body slots `x`.
    pub fn spread(&self, x: &[DVec3], filter: impl Fn(usize, DVec3) -> DVec3, full: &mut [DVec3]) {
        for &(i, b) in &self.pairs {
            let g = self.motion(i, b, x);
            full[i] += g - filter(i, g);
        }
    }

    /// The body rows: M_b·x plus, from each coupled node, the filtered-out part s of its row
    /// `y` (force s, torque r × s), into `out`.
    pub fn gather(
        &self,
        y: &[DVec3],
        x: &[DVec3],
        filter: impl Fn(usize, DVec3) -> DVec3,
        out: &mut [DVec3],
    ) {
        for (k, body) in self.carriers.bodies.iter().enumerate() {
            let [v, w] = body.momentum([x[2 * k], x[2 * k + 1]]);
            [out[2 * k], out[2 * k + 1]] = [self.scale * v, self.scale * w];
        }
        self.add_rows(y, filter, out);
    }

    /// The body rows of the right-hand side: h times each body's weight plus the filtered-out
    /// part of each coupled node's `b`, into `out`.
    pub fn right_hand_side(
        &self,
        b: &[DVec3],
        h: f64,
        filter: impl Fn(usize, DVec3) -> DVec3,
        out: &mut [DVec3],
    ) {
        for (k, body) in self.carriers.bodies.iter().enumerate() {
            out[2 * k] = h * body.weight;
            out[2 * k + 1] = DVec3::ZERO;
        }
        self.add_rows(b, filter, out);
    }

    fn add_rows(&self, y: &[DVec3], filter: impl Fn(usize, DVec3) -> DVec3, out: &mut [DVec3]) {
        for &(i, b) in &self.pairs {
            let s = y[i] - filter(i, y[i]);
            out[2 * b] += s;
            out[2 * b + 1] += self.carriers.arm[i].cross(s);
        }
        // A body does not move along its constraints in the solve, nor turn if it cannot.
        self.filter_bodies(out);
    }

    /// Each body's slots without their parts along its constraints.
    fn filter_bodies(&self, out: &mut [DVec3]) {
        for (k, body) in self.carriers.bodies.iter().enumerate() {
            [out[2 * k], out[2 * k + 1]] = body.constrained([out[2 * k], out[2 * k + 1]]);
        }
    }

    /// Forms the body slots' block-Jacobi preconditioner from each node's diagonal block of
    /// the system (`diagonal`) and filter (`projection`, P).
    pub fn factor(&mut self, diagonal: &[DMat3], projection: &[DMat3]) {
        let mut blocks: Vec<DMat3> = self
            .carriers
            .bodies
            .iter()
            .flat_map(|body| {
                [
                    DMat3::from_diagonal(DVec3::splat(self.scale * body.mass)),
                    self.scale * body.inertia,
                ]
            })
            .collect();
        for &(i, b) in &self.pairs {
            let q = DMat3::IDENTITY - projection[i];
            let d = q * diagonal[i] * q;
            let c = cross_matrix(self.carriers.arm[i]);
            blocks[2 * b] += d;
            blocks[2 * b + 1] += c.transpose() * d * c;
        }
        for (k, (inverse, block)) in self.inverse.iter_mut().zip(blocks).enumerate() {
            let body = &self.carriers.bodies[k / 2];
            let moves = k % 2 == 0 || body.inertia != DMat3::ZERO;
            *inverse = if moves && block.determinant().abs() > 0.0 {
                block.inverse()
            } else {
                DMat3::ZERO
            };
        }
    }

    /// z = D⁻¹·r on the body slots, filtered.
    pub fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
        for ((z, r), inverse) in z.iter_mut().zip(r).zip(&self.inverse) {
            *z = *inverse * *r;
        }
        self.filter_bodies(z);
    }

    /// Adds the body's motion (filtered-out part) to each coupled node's `dv` from the solved
    /// body slots `x`, and returns each body's (ΔV, Δω).
    pub fn finish(
        &self,
        x: &[DVec3],
        filter: impl Fn(usize, DVec3) -> DVec3,
        dv: &mut [DVec3],
    ) -> Vec<[DVec3; 2]> {
        self.spread(x, filter, dv);
        x.chunks(2).map(|c| [c[0], c[1]]).collect()
    }

    /// The impulse each held body's constraints took over the step, reversed: what to hand
    /// the body for Rapier's contacts and joints to take (zero for a body nothing else holds).
    /// From the body's solved change `changes`, the step `h` (s) and the impulse its surface
    /// gave each coupled node (`impulse(i)`, N·s): the support's impulse is
    /// M_b·ΔU − h·weight − (the cloth's push), along the constraints.
    pub fn held_impulses(&self, changes: &[Twist], h: f64, impulse: impl Fn(usize) -> DVec3) -> Vec<Twist> {
        let bodies = &self.carriers.bodies;
        let mut push = vec![[DVec3::ZERO; 2]; bodies.len()];
        for &(i, b) in &self.pairs {
            if bodies[b].is_held() {
                let j = impulse(i);
                push[b][0] -= j;
                push[b][1] -= self.carriers.arm[i].cross(j);
            }
        }
        bodies
            .iter()
            .zip(changes)
            .zip(push)
            .map(|((body, change), push)| {
                if !body.is_held() {
                    return [DVec3::ZERO; 2];
                }
                let m = body.momentum(*change);
                let s = self.scale;
                let support = [s * m[0] - h * body.weight - push[0], s * m[1] - push[1]];
                let free = body.constrained(support);
                // Over Rapier's step: the solve's impulses are over the scheme's.
                [(free[0] - support[0]) / s, (free[1] - support[1]) / s]
            })
            .collect()
    }

    /// Whether any body is held by something else.
    pub fn any_held(&self) -> bool {
        self.carriers.bodies.iter().any(|b| b.is_held())
    }
}
