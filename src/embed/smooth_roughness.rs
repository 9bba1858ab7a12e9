//! The seeded start roughness of a cloth: a smooth random height field over the cloth's flat
//! layout, the same field whatever the lattice that samples it.
//!
//! A flat cloth needs a small roughness to break its symmetry, so that it buckles into folds
//! and repeats differ as laboratory repeats do. Drawn independently at every node, the
//! roughness would be a different start at every spacing and every placement of the lattice
//! against the outline: its smooth part, the part that seeds the folds, shrinks as the nodes get
//! denser, and runs at two spacings would not be two approximations of one problem. This field
//! is a sum of plane waves fixed in the cloth's own frame (along warp and weft, from the
//! cloth's centre), so a seed stands for one physical start, which every lattice samples.

use std::f64::consts::TAU;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

/// How a cloth's start roughness is drawn (`cloth.roughness` in a scene).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Roughness {
    /// An independent uniform offset in ±amplitude at every node (the default): a different
    /// start at every spacing and placement, whose smooth part shrinks as the lattice is
    /// refined.
    #[default]
    PerNode,
    /// A smooth random height field over the flat cloth ([`SmoothRoughness`]), the same at
    /// every spacing and lattice placement for a given seed.
    Smooth,
}

impl Roughness {
    /// The vertical offset (m) of each node at flat positions `flat` (m, along warp and weft
    /// from the cloth's centre), of peak `amplitude` (m), drawn from `seed`.
    pub fn offsets(self, amplitude: f64, seed: u64, flat: &[[f64; 2]]) -> Vec<f64> {
        match self {
            Self::Smooth => {
                let field = SmoothRoughness::new(amplitude, seed);
                flat.iter().map(|&[u, v]| field.height(u, v)).collect()
            }
            Self::PerNode => {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                flat.iter()
                    .map(|_| amplitude * rng.random_range(-1.0..=1.0))
                    .collect()
            }
        }
    }
}

/// Number of plane waves in the field.
const WAVES: usize = 8;

/// Shortest and longest wavelength of the waves (m): from a few nodes' spacing on the coarsest
/// lattices to the size of a drape's folds (6–20 cm on the drapemeters' skirts).
const WAVELENGTHS_M: (f64, f64) = (0.02, 0.2);

/// Largest peak amplitude (m) of a smooth start: its steepest possible slope, 2π·A over the
/// shortest wavelength, stays at 1/2, the slope a per-node start reaches at its own bound (a
/// quarter of the spacing: neighbours up to half a spacing apart in height). The bound is the
/// cloth's, not the lattice's, so one start serves every spacing (about 1.6 mm).
pub const MAX_SMOOTH_AMPLITUDE_M: f64 = WAVELENGTHS_M.0 / (4.0 * std::f64::consts::PI);

/// One plane wave: wave vector (rad/m, along warp and weft) and phase (rad).
#[derive(Clone, Copy, Debug)]
struct Wave {
    k: [f64; 2],
    phase: f64,
}

/// A seeded smooth random height field h(u, v) (m) over the cloth's flat layout, u along the
/// warp and v along the weft (m, from the cloth's centre): the mean of [`WAVES`] plane waves of
/// amplitude `amplitude`, with wavelengths spread evenly on a log scale over 2–20 cm, random
/// directions and phases. |h| never exceeds the amplitude; its RMS is amplitude/4.
#[derive(Clone, Debug)]
pub struct SmoothRoughness {
    amplitude: f64,
    waves: Vec<Wave>,
}

impl SmoothRoughness {
    /// The field of `seed` with peak bound `amplitude` (m).
    pub fn new(amplitude: f64, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (shortest, longest) = WAVELENGTHS_M;
        let waves = (0..WAVES)
            .map(|_| {
                let wavelength = shortest * (longest / shortest).powf(rng.random_range(0.0..1.0));
                let direction = rng.random_range(0.0..TAU);
                let size = TAU / wavelength;
                Wave {
                    k: [size * direction.cos(), size * direction.sin()],
                    phase: rng.random_range(0.0..TAU),
                }
            })
            .collect();
        Self { amplitude, waves }
    }

    /// The height (m) at flat position (`u`, `v`) (m, along warp and weft from the centre).
    pub fn height(&self, u: f64, v: f64) -> f64 {
        let sum: f64 = self
            .waves
            .iter()
            .map(|w| (w.k[0] * u + w.k[1] * v + w.phase).cos())
            .sum();
        self.amplitude * sum / self.waves.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The field is bounded by its amplitude, and its RMS over a large area is amplitude/4
    /// (eight waves of mean square ½, averaged: 8·½/64 = 1/16). Tolerance: over a 1 m square
    /// sampled every 5 mm the waves' cross terms average to within a few per cent.
    #[test]
    fn the_roughness_is_bounded_by_its_amplitude_with_an_rms_of_a_quarter_of_it() {
        let field = SmoothRoughness::new(0.002, 3);
        let (mut sum_sq, mut count, mut peak) = (0.0, 0.0, 0.0f64);
        for i in -100..=100 {
            for j in -100..=100 {
                let h = field.height(i as f64 * 0.005, j as f64 * 0.005);
                sum_sq += h * h;
                count += 1.0;
                peak = peak.max(h.abs());
            }
        }
        let rms = (sum_sq / count).sqrt();
        assert!(peak <= 0.002, "peak {peak} m");
        assert!((rms / 0.0005 - 1.0).abs() < 0.1, "rms {rms} m against 0.5 mm");
    }

    /// Smooth: between two points 1 mm apart the height changes by at most the amplitude times
    /// 2π·1 mm / 2 cm (the steepest wave's slope), whatever the seed.
    #[test]
    fn the_roughness_is_smooth_at_the_scale_of_a_millimetre() {
        for seed in 0..5 {
            let field = SmoothRoughness::new(0.001, seed);
            for i in 0..200 {
                let u = i as f64 * 0.0013 - 0.1;
                let step = (field.height(u + 0.001, 0.03) - field.height(u, 0.03)).abs();
                assert!(
                    step <= 0.001 * TAU * 0.001 / 0.02 + 1e-15,
                    "seed {seed}: {step} m"
                );
            }
        }
    }
}
