//! Each node's 3×3 blocks of the filtered system, for the preconditioners: its filter P (I, a
//! support's plane, or 0), its diagonal block of S = P·(M + A + D)·P + (I − P)·M, and block
//! Jacobi's inverse of it on the plane the filter leaves free.

use glam::{DMat3, DVec3};

use crate::forces::outer;

/// Each node's filter as a matrix: zero for a fixed node, the plane of its support's normal
/// `normals[i]` (the identity where it has none) otherwise.
pub(super) fn projections(normals: &[DVec3], fixed: &[bool], out: &mut [DMat3]) {
    for ((p, n), fixed) in out.iter_mut().zip(normals).zip(fixed) {
        *p = if *fixed {
            DMat3::ZERO
        } else {
            DMat3::IDENTITY - outer(*n, *n)
        };
    }
}

/// What a node's filtered diagonal block is made of.
pub(super) struct Filtered<'a> {
    /// Each node's diagonal block of M + h·C + h²·H (kg).
    pub diagonal: &'a [DMat3],
    /// Each node's filter ([`projections`]).
    pub projection: &'a [DMat3],
    /// Each sliding node's kinetic friction drag (kg; zero elsewhere).
    pub drag: &'a [f64],
    /// Node masses (kg).
    pub masses: &'a [f64],
}

impl Filtered<'_> {
    /// Each node's diagonal block of S (kg): P·(block + drag·I)·P + m·(I − P).
    pub fn diagonal_blocks(&self, out: &mut [DMat3]) {
        for (i, s) in out.iter_mut().enumerate() {
            let p = self.projection[i];
            let drag = DMat3::from_diagonal(DVec3::splat(self.drag[i]));
            *s = p * (self.diagonal[i] + drag) * p + self.masses[i] * (DMat3::IDENTITY - p);
        }
    }

    /// Block Jacobi: each node's own block of P·A·P inverted on the plane the filter leaves
    /// free (the normal gets m, which the filter then removes again); zero for a fixed node.
    pub fn jacobi_inverses(&self, normals: &[DVec3], fixed: &[bool], out: &mut [DMat3]) {
        for (i, inverse) in out.iter_mut().enumerate() {
            let (n, block) = (normals[i], self.diagonal[i]);
            *inverse = if fixed[i] {
                DMat3::ZERO
            } else if n == DVec3::ZERO {
                block.inverse()
            } else {
                let plane = DMat3::IDENTITY - outer(n, n);
                let free = plane * (block + self.drag[i] * plane) * plane + self.masses[i] * outer(n, n);
                plane * free.inverse() * plane
            };
        }
    }
}
