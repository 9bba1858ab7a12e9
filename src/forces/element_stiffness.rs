//! Second derivatives of the KES energies for the implicit solve: angle elements (bending,
//! trellising) and link springs. For an angle element, E = f(c) with c = Û·Ŵ the cosine between two
//! link vectors U and W that meet at a particle: the core of the bending and trellising
//! stiffness.
//!
//! With p = Ŵ − c·Û and q = Û − c·Ŵ, ∇_U c = p/|U| and ∇_W c = q/|W|, and
//!
//! ∂²c/∂U² = −(p·Ûᵀ + Û·pᵀ + c·P_U)/|U|²,   ∂²c/∂U∂W = P_U·P_W/(|U|·|W|),
//!
//! (P_U = I − Û·Ûᵀ), symmetrically for W. The energy Hessian is H = f''·∇c·∇cᵀ + f'·∇²c.
//! It is indefinite in general (tilting both links out of a bent plane lowers c), so the implicit
//! integrator uses [`AngleClamp::Majorant`]: a positive semi-definite matrix that bounds H from
//! above (more stiffness means more numerical damping, never instability) and equals it at both
//! rest states, a straight thread (c = −1) and a right-angled crossing (f' = 0). In the scaled
//! perturbations a = δU/|U|, b = δW/|W|, with y = P_U·a and z = P_W·b, the quadratic form of
//! f'·∇²c is f'·[−c(|y|² + |z|²) + 2y·z] − 2f'·[(p·a)(Û·a) + (q·b)(Ŵ·b)], bounded by
//!
//! * f'·|y + z|² for f' ≥ 0 and |f'|·|y − z|² for f' < 0 (exact at c = −1 or c = +1), and
//! * |f'|·(|p|·((Û·a)² + (p̂·a)²) + |q|·((Ŵ·b)² + (q̂·b)²)) for the coupling of length and angle,
//!
//! and f''·∇c·∇cᵀ by f''₊·∇c·∇cᵀ (`docs/model.md` §12).

use glam::{DMat3, DVec3};

use super::{ClothGeometry, ForceBuffer, LinkMatrix, Perturbation};

/// Which positive semi-definite clamp of the element Hessian to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AngleClamp {
    /// The exact Hessian (indefinite in general), for tests and diagnostics.
    Exact,
    /// A positive semi-definite upper bound, exact at rest (module docs).
    Majorant,
}

/// H·(δU, δW) for E = f(c), given unit vectors `u`, `w`, inverse lengths (m⁻¹), f' = dE/dc and
/// f'' = d²E/dc² (J), and the perturbations `du`, `dw` of U and W (m). Returns the U and W parts.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn angle_hessian_product(
    (u, w): (DVec3, DVec3),
    (inv_u, inv_w): (f64, f64),
    (f1, f2): (f64, f64),
    (du, dw): (DVec3, DVec3),
    clamp: AngleClamp,
) -> (DVec3, DVec3) {
    let c = u.dot(w);
    let (p, q) = (w - c * u, u - c * w);
    // Perturbations scaled by the inverse lengths.
    let (a, b) = (du * inv_u, dw * inv_w);
    let gauss = |f2: f64| {
        let gc = p.dot(a) + q.dot(b);
        (f2 * gc * inv_u * p, f2 * gc * inv_w * q)
    };
    match clamp {
        AngleClamp::Exact => {
            let (gu, gw) = gauss(f2);
            let (ua, wb) = (u.dot(a), w.dot(b));
            let pa = a - ua * u; // P_U·a
            let pb = b - wb * w; // P_W·b
            let pupwb = pb - u.dot(pb) * u; // P_U·P_W·b
            let pwpua = pa - w.dot(pa) * w; // P_W·P_U·a
            let hu = (-(ua * p) - p.dot(a) * u - c * pa + pupwb) * inv_u;
            let hw = (-(wb * q) - q.dot(b) * w - c * pb + pwpua) * inv_w;
            (gu + f1 * hu, gw + f1 * hw)
        }
        AngleClamp::Majorant => {
            let (gu, gw) = gauss(f2.max(0.0));
            let (ua, wb) = (u.dot(a), w.dot(b));
            let (y, z) = (a - ua * u, b - wb * w);
            let side = if f1 >= 0.0 { 1.0 } else { -1.0 };
            let strength = f1.abs();
            let s = y + side * z;
            let mut hu = s - u.dot(s) * u;
            let mut hw = side * (s - w.dot(s) * w);
            // Coupling bound: |p|·(Û·a)·Û + (p·a)·p/|p|, likewise for W.
            let (np, nq) = (p.length(), q.length());
            if np > 0.0 {
                hu += np * ua * u + (p.dot(a) / np) * p;
            }
            if nq > 0.0 {
                hw += nq * wb * w + (q.dot(b) / nq) * q;
            }
            (gu + strength * inv_u * hu, gw + strength * inv_w * hw)
        }
    }
}

/// a·bᵀ.
#[inline(always)]
pub(crate) fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The blocks (H_UU, H_UW, H_WW) of [`AngleClamp::Majorant`]'s matrix for the link vectors U, W
/// (the matrix [`angle_hessian_product`] multiplies by, written out; same arguments).
#[inline(always)]
pub(crate) fn angle_hessian_blocks(
    (u, w): (DVec3, DVec3),
    (inv_u, inv_w): (f64, f64),
    (f1, f2): (f64, f64),
) -> (DMat3, DMat3, DMat3) {
    let c = u.dot(w);
    let (p, q) = (w - c * u, u - c * w);
    let f2 = f2.max(0.0);
    let side = if f1 >= 0.0 { 1.0 } else { -1.0 };
    let strength = f1.abs();
    let (uu, ww) = (outer(u, u), outer(w, w));
    // Projections P_U, P_W and P_U·P_W = I − ÛÛᵀ − ŴŴᵀ + c·ÛŴᵀ.
    let (pu, pw) = (DMat3::IDENTITY - uu, DMat3::IDENTITY - ww);
    let pupw = DMat3::IDENTITY - uu - ww + c * outer(u, w);
    let (np, nq) = (p.length(), q.length());
    let mut huu = pu;
    let mut hww = pw;
    if np > 0.0 {
        huu += np * uu + outer(p, p) / np;
    }
    if nq > 0.0 {
        hww += nq * ww + outer(q, q) / nq;
    }
    (
        (inv_u * inv_u) * (strength * huu + f2 * outer(p, p)),
        (inv_u * inv_w) * (strength * side * pupw + f2 * outer(p, q)),
        (inv_w * inv_w) * (strength * hww + f2 * outer(q, q)),
    )
}

/// Adds `scale`·H of one angle element (f' and f'' in `tangent`, J) on the matrix slot whose
/// links meet at the element's middle particle (`LinkMatrix::slot_links` gives them).
#[inline(always)]
pub(crate) fn add_angle_blocks(
    geometry: &ClothGeometry,
    matrix: &mut LinkMatrix,
    slot: usize,
    tangent: (f64, f64),
    scale: f64,
) {
    let [(lu, su), (lw, sw)] = matrix.slot_links(slot);
    let (unit, inv) = (&geometry.unit, &geometry.inv_length);
    let (uu, uw, ww) = angle_hessian_blocks((su * unit[lu], sw * unit[lw]), (inv[lu], inv[lw]), tangent);
    matrix.add_element(slot, (scale * uu, scale * uw, scale * ww));
}

impl AngleClamp {
    /// [`Self::Majorant`] for the implicit solve's `definite` matrix, else [`Self::Exact`].
    pub(crate) fn for_definite(definite: bool) -> Self {
        if definite { Self::Majorant } else { Self::Exact }
    }
}

/// Adds `scale`·H·δ of one trellis corner into `out`: the corner's links `lu`, `lw` with the
/// signs `su`, `sw` that point them away from the crossing, f' = dE/dγ and f'' (J).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn add_corner_product(
    geometry: &ClothGeometry,
    dx: &Perturbation,
    ((lu, su), (lw, sw)): ((usize, f64), (usize, f64)),
    tangent: (f64, f64),
    scale: f64,
    clamp: AngleClamp,
    out: &mut ForceBuffer,
) {
    let (unit, inv, d) = (&geometry.unit, &geometry.inv_length, &dx.link);
    let (u, w) = (su * unit[lu], sw * unit[lw]);
    let (hu, hw) = angle_hessian_product(
        (u, w),
        (inv[lu], inv[lw]),
        tangent,
        (su * d[lu], sw * d[lw]),
        clamp,
    );
    out.link[lu] += (scale * su) * hu;
    out.link[lw] += (scale * sw) * hw;
}

/// Adds `scale`·H·δ for a spring on every link, E_l(r): `tangent(l)` gives E' = dE/dr (N) and
/// E'' (N/m) of link `l`. Per link, H·δ = E''·(d̂·δ)·d̂ + (E'/r)·P·δ; `definite` clamps both
/// coefficients at zero (a compressed spring's negative transverse stiffness is dropped).
pub(crate) fn add_link_spring_products(
    geometry: &ClothGeometry,
    dx: &Perturbation,
    scale: f64,
    definite: bool,
    out: &mut ForceBuffer,
    tangent: impl Fn(usize) -> (f64, f64),
) {
    for l in 0..geometry.length.len() {
        let (e1, e2) = tangent(l);
        let (mut axial, mut transverse) = (e2, e1 * geometry.inv_length[l]);
        if definite {
            axial = axial.max(0.0);
            transverse = transverse.max(0.0);
        }
        let (unit, d) = (geometry.unit[l], dx.link[l]);
        let along = unit.dot(d);
        out.link[l] += scale * (axial * along * unit + transverse * (d - along * unit));
    }
}

/// Adds `scale`·H of a spring on every link into the link diagonal of `matrix`, the definite
/// clamp of [`add_link_spring_products`] (same `tangent`).
pub(crate) fn add_link_spring_blocks(
    geometry: &ClothGeometry,
    scale: f64,
    matrix: &mut LinkMatrix,
    tangent: impl Fn(usize) -> (f64, f64),
) {
    for (l, block) in matrix.link.iter_mut().enumerate() {
        let (e1, e2) = tangent(l);
        let axial = e2.max(0.0);
        let transverse = (e1 * geometry.inv_length[l]).max(0.0);
        let along = outer(geometry.unit[l], geometry.unit[l]);
        *block += scale * (transverse * DMat3::IDENTITY + (axial - transverse) * along);
    }
}
