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
    /// Whether the solve met its stopping rule ([`Stop`]) rather than running out of products
    /// or of positive curvature.
    #[serde(default)]
    pub converged: bool,
}

/// When [`conjugate_gradient`] stops: at |b − A·x|_P ≤ max(`relative`·|b|_P, `absolute`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// Residual relative to the right-hand side's, both in the preconditioner's norm
    /// (dimensionless).
    pub relative: f64,
    /// Residual below which the solve stops whatever b (the units of |b|_P, √(bᵀ·P·b)). A
    /// relative rule alone chases round-off when b nearly vanishes (a cloth at rest), so a
    /// caller passes the accuracy it needs in absolute terms; 0 for none.
    pub absolute: f64,
    /// Most operator products.
    pub max_iterations: usize,
}

fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x.dot(*y)).sum()
}

/// Solves A·x = b, starting from the `x` passed in (a warm start), until [`Stop`] is met or
/// its products are used up. The norm is the preconditioner's
/// ([`CgReport::relative_residual`]): in the plain norm, a few nodes with very stiff diagonal
/// blocks (a support's friction) dominate |r|, and the solve would stop while the light free
/// nodes' velocities are still far off. `apply(p, out)` writes A·p into `out`;
/// `precondition(r, z)` writes z = P·r for a symmetric positive definite P ≈ A⁻¹.
/// `r`, `z`, `p`, `ap` are scratch buffers of the same length as `b`.
pub fn conjugate_gradient(
    mut apply: impl FnMut(&[DVec3], &mut [DVec3]),
    mut precondition: impl FnMut(&[DVec3], &mut [DVec3]),
    b: &[DVec3],
    x: &mut [DVec3],
    (r, z, p, ap): (&mut [DVec3], &mut [DVec3], &mut [DVec3], &mut [DVec3]),
    stop: Stop,
) -> CgReport {
    precondition(b, z);
    let b_norm = dot(b, z).max(0.0).sqrt();
    if b_norm == 0.0 {
        x.fill(DVec3::ZERO);
        return CgReport {
            converged: true,
            ..CgReport::default()
        };
    }
    apply(x, ap);
    for i in 0..b.len() {
        r[i] = b[i] - ap[i];
    }
    precondition(r, z);
    p.copy_from_slice(z);
    let mut rz = dot(r, z);
    let target = (stop.relative * b_norm).max(stop.absolute);
    let mut residual = rz.max(0.0).sqrt();
    let mut iterations = 0;
    while residual > target && iterations < stop.max_iterations {
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
        converged: residual <= target,
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
        let stop = Stop {
            relative: 1e-3,
            absolute: 0.0,
            max_iterations: 100,
        };
        let report = conjugate_gradient(chain, jacobi, &b, &mut x, (r, z, p, ap), stop);
        assert!(report.converged && report.relative_residual <= 1e-3, "{report:?}");
        let worst = x
            .iter()
            .map(|x| (*x - DVec3::ONE).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst < 1e-2, "a node is {worst:e} m/s off after {report:?}");
    }

    #[test]
    fn a_warm_start_within_the_absolute_floor_is_kept() {
        // A cloth at rest: b is 1e-9 of its moving size and the warm start already solves it
        // to within the floor, so the solve stops at once and leaves x as it was; with no
        // floor the relative rule makes it iterate on that tiny b.
        let n = 40;
        let mut b = vec![DVec3::ZERO; n];
        chain(&vec![DVec3::splat(1e-9); n], &mut b);
        let start = vec![DVec3::ZERO; n];
        let mut scratch: [Vec<DVec3>; 4] = std::array::from_fn(|_| vec![DVec3::ZERO; n]);
        let jacobi = |r: &[DVec3], z: &mut [DVec3]| {
            for (i, (z, r)) in z.iter_mut().zip(r).enumerate() {
                *z = *r / if i % 2 == 0 { 1e4 + 1.0 } else { 2.0 };
            }
        };
        let solve = |absolute: f64, scratch: &mut [Vec<DVec3>; 4]| {
            let [r, z, p, ap] = scratch;
            let mut x = start.clone();
            let stop = Stop {
                relative: 1e-3,
                absolute,
                max_iterations: 100,
            };
            let report = conjugate_gradient(chain, jacobi, &b, &mut x, (r, z, p, ap), stop);
            (report, x)
        };
        let (kept, x) = solve(1e-3, &mut scratch);
        assert!(kept.converged && kept.iterations == 0, "{kept:?}");
        assert_eq!(x, start);
        let (chased, _) = solve(0.0, &mut scratch);
        assert!(chased.converged && chased.iterations > 0, "{chased:?}");
    }
}
