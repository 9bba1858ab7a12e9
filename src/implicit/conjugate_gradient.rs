//! Conjugate gradients on 3-vector fields, for a symmetric positive definite operator.

use glam::DVec3;

/// How a solve ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CgReport {
    /// Operator applications after the initial residual.
    pub iterations: usize,
    /// |b − A·x|_P / |b|_P at the end (0 when b = 0): the residual in the norm of the
    /// preconditioner P ≈ A⁻¹, |r|_P = √(rᵀ·P·r), which weighs each node's residual by the
    /// inverse of its own stiffness, so that the figure is a relative error in velocity terms.
    pub relative_residual: f64,
}

fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x.dot(*y)).sum()
}

/// Solves A·x = b, starting from the `x` passed in (a warm start), until |b − A·x|_P ≤
/// `tolerance`·|b|_P or `max_iterations` products. The norm is the preconditioner's
/// ([`CgReport::relative_residual`]): in the plain norm, a few nodes with very stiff diagonal
/// blocks (a support's friction) dominate |r|, and the solve would stop while the light free
/// nodes' velocities are still far off. `apply(p, out)` writes A·p into `out`;
/// `precondition(r, z)` writes z = P·r for a symmetric positive definite P ≈ A⁻¹.
/// `r`, `z`, `p`, `ap` are scratch buffers of the same length as `b`.
#[allow(clippy::too_many_arguments)]
pub fn conjugate_gradient(
    mut apply: impl FnMut(&[DVec3], &mut [DVec3]),
    precondition: impl Fn(&[DVec3], &mut [DVec3]),
    b: &[DVec3],
    x: &mut [DVec3],
    (r, z, p, ap): (&mut [DVec3], &mut [DVec3], &mut [DVec3], &mut [DVec3]),
    tolerance: f64,
    max_iterations: usize,
) -> CgReport {
    precondition(b, z);
    let b_norm = dot(b, z).max(0.0).sqrt();
    if b_norm == 0.0 {
        x.fill(DVec3::ZERO);
        return CgReport::default();
    }
    apply(x, ap);
    for i in 0..b.len() {
        r[i] = b[i] - ap[i];
    }
    precondition(r, z);
    p.copy_from_slice(z);
    let mut rz = dot(r, z);
    let target = tolerance * b_norm;
    let mut residual = rz.max(0.0).sqrt();
    let mut iterations = 0;
    while residual > target && iterations < max_iterations {
        apply(p, ap);
        iterations += 1;
        let curvature = dot(p, ap);
        if curvature <= 0.0 || !curvature.is_finite() {
            break; // not positive definite along p: keep the best iterate so far
        }
        let alpha = rz / curvature;
        for i in 0..b.len() {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        precondition(r, z);
        let rz_next = dot(r, z);
        residual = rz_next.max(0.0).sqrt();
        let beta = rz_next / rz;
        rz = rz_next;
        for i in 0..b.len() {
            p[i] = z[i] + beta * p[i];
        }
    }
    CgReport {
        iterations,
        relative_residual: residual / b_norm,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of nodes, every other one with a block 10⁴ times stiffer (a dragged rim node
    /// next to a free one), coupled to its neighbours: A·x along each axis.
    fn chain(x: &[DVec3], out: &mut [DVec3]) {
        let n = x.len();
        for i in 0..n {
            let own = if i % 2 == 0 { 1e4 } else { 1.0 } + 1.0;
            let mut y = own * x[i];
            for j in [i.wrapping_sub(1), i + 1] {
                if j < n {
                    y -= 0.5 * x[j];
                }
            }
            out[i] = y;
        }
    }

    #[test]
    fn stopping_leaves_the_light_nodes_accurate_too() {
        // The solution is 1 m/s at every node, so b is dominated 10⁴:1 by the stiff rows. The
        // stop is judged in the preconditioner's norm, so at a relative tolerance of 1e-3 every
        // node, light or stiff, is within 1e-2 of its value; in the plain norm |r| the light
        // nodes' residual could be 10 times their b and the stop still met.
        let n = 40;
        let exact = vec![DVec3::ONE; n];
        let mut b = vec![DVec3::ZERO; n];
        chain(&exact, &mut b);
        let mut x = vec![DVec3::ZERO; n];
        let mut scratch: [Vec<DVec3>; 4] = std::array::from_fn(|_| vec![DVec3::ZERO; n]);
        let [r, z, p, ap] = &mut scratch;
        let jacobi = |r: &[DVec3], z: &mut [DVec3]| {
            for (i, (z, r)) in z.iter_mut().zip(r).enumerate() {
                *z = *r / if i % 2 == 0 { 1e4 + 1.0 } else { 2.0 };
            }
        };
        let report = conjugate_gradient(chain, jacobi, &b, &mut x, (r, z, p, ap), 1e-3, 100);
        assert!(report.relative_residual <= 1e-3, "{report:?}");
        let worst = x
            .iter()
            .map(|x| (*x - DVec3::ONE).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst < 1e-2, "a node is {worst:e} m/s off after {report:?}");
    }
}
