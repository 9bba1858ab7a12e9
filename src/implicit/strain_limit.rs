//! A bound on link strain after a step too long for one linear solve (strain limiting, after
//! Provot 1995).
//!
//! The implicit solve linearises our forces at the start of the step and knows only the contacts
//! of the step before. A link at rest length under no tension has no stiffness across itself,
//! so where a surface stops one node within the step and its neighbour keeps falling, the
//! neighbour moves along the tangent and the link stretches by about ½·(δ/σ)² for a sideways
//! move δ. At a long step on a fine lattice δ is several spacings: thin wool at 2.5 mm and
//! 1/60 s lands on the drapemeter with links 93 % long, and the KES law, far outside its
//! measured range, then throws the cloth apart; where the nodes landing on a surface are
//! pushed together, links shorten by half within a step. It is a last resort, for a step too
//! long for the lattice. After Rapier's step, every link
//! longer than (1 + [`STRAIN_LIMIT`])·σ or shorter than (1 − [`STRAIN_LIMIT`])·σ is brought
//! back to that length, its two nodes moved along it by inverse mass (a node held by a pin
//! stays; one on a surface moves, and Rapier's contact answers in the next step), and the two
//! nodes' relative velocity along the link, where it would carry them further beyond the
//! limit, is taken out as in an inelastic collision: momentum is kept and kinetic energy only
//! lost (`docs/model.md` §12, "The longest step"). A step that leaves every link within the
//! limit is untouched.

use glam::DVec3;

use crate::forces::ClothTopology;

/// Largest link strain |length − σ|/σ (dimensionless) a step may leave, stretched or
/// compressed: 0.45, just inside the divergence guard's [`crate::measure::RUNAWAY_STRAIN`]
/// (0.5), so that the limit acts only where a run was about to be stopped as a runaway. Every
/// run whose links stay within it is untouched: the shipped scenes' largest transients, on
/// landing, are 3–14 %. A tighter limit (0.2) also rescued thin wool at 2.5 mm and 1/60 s but
/// changed runs that went well without it (a cloth landing on a pile of boxes at 1/60 s,
/// `tests/embedding_carriers.rs`, no longer came to rest within 6 s).
pub const STRAIN_LIMIT: f64 = 0.45;

/// Sweeps over the links at most (each brings every link over the limit back to it; a
/// neighbour's move can stretch it again).
const SWEEPS: usize = 16;

/// Whether any link of `topology` at `positions` (m) is strained beyond the limit, stretched
/// or compressed.
pub fn over_limit(topology: &ClothTopology, positions: &[DVec3]) -> bool {
    let (short, long) = bounds(topology.spacing);
    topology.links.iter().any(|[a, b]| {
        let l2 = (positions[*b as usize] - positions[*a as usize]).length_squared();
        l2 > long * long || l2 < short * short
    })
}

/// The shortest and longest a link may be (m) on a lattice of spacing `sigma` (m).
fn bounds(sigma: f64) -> (f64, f64) {
    ((1.0 - STRAIN_LIMIT) * sigma, (1.0 + STRAIN_LIMIT) * sigma)
}

/// Brings every link of `topology` back within the limit (at most (1 ± [`STRAIN_LIMIT`])·σ
/// long), moving `positions` (m) and stopping the links' stretching in `velocities` (m/s);
/// nodes with `immovable` set stay. Returns the nodes it moved, in order.
pub fn limit_strain(
    topology: &ClothTopology,
    masses: &[f64],
    immovable: &[bool],
    positions: &mut [DVec3],
    velocities: &mut [DVec3],
) -> Vec<usize> {
    let (short, long) = bounds(topology.spacing);
    let inverse = |i: usize| if immovable[i] { 0.0 } else { 1.0 / masses[i] };
    let mut moved = vec![false; positions.len()];
    for _ in 0..SWEEPS {
        let mut any = false;
        for link in &topology.links {
            let [a, b] = link.map(|i| i as usize);
            let d = positions[b] - positions[a];
            let length = d.length();
            let (wa, wb) = (inverse(a), inverse(b));
            // A link of zero length has no direction to push along.
            let target = length.clamp(short, long);
            if target == length || length == 0.0 || wa + wb == 0.0 {
                continue;
            }
            let shift = d * ((length - target) / (length * (wa + wb)));
            positions[a] += wa * shift;
            positions[b] -= wb * shift;
            // The link stops stretching (or squeezing) further: the nodes' relative velocity
            // along it, if it still pulls them beyond the limit, is taken out as in an
            // inelastic collision, shared by inverse mass. Momentum is kept and kinetic energy
            // only lost: a move over the step put into the velocity would carry the nodes on
            // past the limit the other way.
            let along = d / length;
            let apart = (velocities[b] - velocities[a]).dot(along);
            if apart * (length - target) > 0.0 {
                let impulse = along * (apart / (wa + wb));
                velocities[a] += wa * impulse;
                velocities[b] -= wb * impulse;
            }
            moved[a] |= wa > 0.0;
            moved[b] |= wb > 0.0;
            any = true;
        }
        if !any {
            break;
        }
    }
    (0..moved.len()).filter(|i| moved[*i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two nodes of 1 g and 3 g, 1 cm apart on a 5 mm lattice (100 % strain), moving apart: the
    /// limit leaves them (1 + limit) spacings apart, moving the lighter three times as far,
    /// stops them moving apart, and keeps their momentum and centre of mass (to rounding).
    #[test]
    fn an_overstretched_link_shortens_to_the_limit_and_keeps_its_momentum() {
        let topology = ClothTopology::rectangle(2, 1, 0.005);
        let long = (1.0 + STRAIN_LIMIT) * 0.005;
        let masses = [0.001, 0.003];
        let mut x = [DVec3::ZERO, DVec3::new(0.01, 0.0, 0.0)];
        let mut v = [DVec3::new(-0.1, 0.0, 0.0), DVec3::new(0.2, 0.0, 0.0)];
        let momentum = |v: &[DVec3]| v[0] * masses[0] + v[1] * masses[1];
        let centre = |x: &[DVec3]| (x[0] * masses[0] + x[1] * masses[1]) / 0.004;
        let (p0, c0) = (momentum(&v), centre(&x));
        let moved = limit_strain(&topology, &masses, &[false, false], &mut x, &mut v);
        assert_eq!(moved, [0, 1]);
        assert!(((x[1] - x[0]).length() - long).abs() < 1e-15, "{x:?}");
        assert!((momentum(&v) - p0).length() < 1e-15, "{v:?}");
        assert!((centre(&x) - c0).length() < 1e-15);
        // The excess: three quarters taken by the 1 g node, a quarter by the 3 g one; moving
        // apart, both end at the pair's velocity, (−0.1·1 + 0.2·3)/4 = 0.125 m/s.
        assert!((x[0].x - 0.75 * (0.01 - long)).abs() < 1e-15, "{x:?}");
        assert!(v.iter().all(|v| (v.x - 0.125).abs() < 1e-15), "{v:?}");
        assert!(!over_limit(&topology, &x));
    }

    /// A held node stays, and the free nodes hanging below it are pulled up to it: links 2.5
    /// and 1.2 spacings long both end at the limit. Nodes at rest stay at rest. A link within
    /// the limit is left as it is.
    #[test]
    fn a_held_node_stays_and_a_link_within_the_limit_is_untouched() {
        let sigma = 0.005;
        let long = (1.0 + STRAIN_LIMIT) * sigma;
        let topology = ClothTopology::rectangle(3, 1, sigma);
        let mut x = [
            DVec3::ZERO,
            DVec3::new(0.0, -2.5 * sigma, 0.0),
            DVec3::new(0.0, -3.7 * sigma, 0.0),
        ];
        let mut v = [DVec3::ZERO; 3];
        assert!(over_limit(&topology, &x));
        let moved = limit_strain(&topology, &[0.001; 3], &[true, false, false], &mut x, &mut v);
        assert_eq!(x[0], DVec3::ZERO);
        assert!(moved.contains(&1), "{moved:?}");
        // Shortening the first link stretches the second past the limit, whose correction
        // stretches the first again by a fraction, and so on: after the sweeps both lie within
        // 0.1 µm of the limit.
        for k in 0..2 {
            assert!(((x[k + 1] - x[k]).length() - long).abs() < 1e-7, "{x:?}");
        }
        assert_eq!(v, [DVec3::ZERO; 3], "at rest, they stay at rest");
        let within = (1.0 + 0.9 * STRAIN_LIMIT) * sigma;
        let (mut y, mut w) = ([DVec3::ZERO, DVec3::new(within, 0.0, 0.0)], [DVec3::ZERO; 2]);
        let two = ClothTopology::rectangle(2, 1, sigma);
        assert!(limit_strain(&two, &[0.001; 2], &[false; 2], &mut y, &mut w).is_empty());
        assert_eq!(y[1].x, within);
    }

    /// A link squeezed to a tenth of its spacing is pushed back out to (1 − limit) of it, both
    /// nodes alike (equal masses).
    #[test]
    fn a_squeezed_link_is_pushed_out_to_the_limit() {
        let sigma = 0.004;
        let topology = ClothTopology::rectangle(2, 1, sigma);
        let mut x = [DVec3::ZERO, DVec3::new(0.1 * sigma, 0.0, 0.0)];
        let mut v = [DVec3::ZERO; 2];
        assert!(over_limit(&topology, &x));
        limit_strain(&topology, &[0.002; 2], &[false; 2], &mut x, &mut v);
        let short = (1.0 - STRAIN_LIMIT) * sigma;
        let push = 0.5 * (short - 0.1 * sigma);
        assert!(
            (x[0].x + push).abs() < 1e-15 && (x[1].x - 0.1 * sigma - push).abs() < 1e-15,
            "{x:?}"
        );
        assert!(!over_limit(&topology, &x));
    }
}
