//! The potential energy of a cloth's shape: what ranks two rest shapes of one lattice.
//!
//! A drape can come to rest in more than one shape with the same fold count (thick cotton's
//! four nodes on the bias or on the threads, `docs/model.md` §1, "Link support"); a rest shape
//! is a local minimum of the potential energy, and the lower of two is the more stable.

use glam::DVec3;

use crate::forces::{ClothGeometry, Effects};

/// The potential energy of a shape (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PotentialEnergy {
    /// Gravitational energy −Σ mᵢ g·xᵢ (J), zero for a cloth whose nodes all lie in the plane
    /// through the origin normal to g (in the shipped scenes, y = 0: the disk's or table's top).
    pub gravitational: f64,
    /// Energy stored in the cloth's elastic effects (J): bending, trellising, stretch and
    /// compression, and hysteresis's element springs; damping and drag store none.
    pub elastic: f64,
}

/// The potential energy of nodes of `masses` (kg) at `positions` (m) under `gravity` (m/s²),
/// with the elastic energy of every effect in `effects`; `geometry` is updated to `positions`.
pub fn potential_energy(
    effects: &Effects,
    geometry: &mut ClothGeometry,
    masses: &[f64],
    positions: &[DVec3],
    gravity: DVec3,
) -> PotentialEnergy {
    geometry.update(positions);
    PotentialEnergy {
        gravitational: -positions
            .iter()
            .zip(masses)
            .map(|(x, m)| m * gravity.dot(*x))
            .sum::<f64>(),
        elastic: effects.iter().map(|e| e.energy(geometry)).sum(),
    }
}
