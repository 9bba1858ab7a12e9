//! The largest step at which each KES force stays stable when applied explicitly
//! (`docs/model.md` §10).
//!
//! Our forces, applied as one velocity kick before Rapier's step, give symplectic Euler, stable
//! while ω·dt < 2 for the fastest mode. Per node of mass m = ρ_A·σ², with tangent stiffnesses
//! taken at their largest over the range a drape reaches (the curves' maximum slope up to full
//! fold or full shear, the tensile laws at EMT):
//!
//! * bending: the out-of-plane checkerboard mode bends every warp and weft spring by 4u/σ, so
//!   k = 16·(B_warp + B_weft)/σ²;
//! * trellising: the in-plane checkerboard shear mode, k = 4·G (G in N/m per radian);
//! * with hysteresis, a sticking friction element adds its stick stiffness k_f to B (bending) and
//!   to G (trellising), [`crate::material::HysteresisLaw`];
//! * stretch by the KES law, k = 4·T'(EMT) = 4·n·T_m/EMT; by the seed's law, k = 4·(4·T_m/EMT);
//! * link compression (stretch as a constraint) of modulus E (N/m, one link's stiffness), k = 4·E
//!   (the alternating mode along a thread);
//!
//! and ω = √(k/m). Symplectic Euler's own limit is ω·dt = 2, but near it the highest modes are
//! barely damped and contact and joints add stiffness: thick cotton at 1 cm (trellising,
//! 2/ω = 0.46 ms) settles at 0.35 ms (ω·dt = 1.54), still moves at 0.8 m/s after 3 s at 0.41 ms
//! (ω·dt = 1.8) and diverges at 1.37 ms (measured with a compression spring sized from the step,
//! softer than [`LinkCompression::default_modulus`]; `tests/stability_guard.rs` probes
//! trellising with a 100 N/m spring). The
//! limit used is therefore ω·dt ≤ [`MAX_OMEGA_DT`].
//! Link damping is checked on its own (rate·dt < 1/4, `scene::scene_validation`).

use super::{EffectChoice, LinkCompression, NodeMass, StretchModel};
use crate::material::{Fabric, HysteresisLaw, Thread};

/// Largest ω·dt allowed for an explicit force (dimensionless; symplectic Euler's bound is 2).
pub const MAX_OMEGA_DT: f64 = 1.6;

/// One effect's explicit step limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepLimit {
    /// The effect, as scenes and metrics name it.
    pub effect: &'static str,
    /// [`MAX_OMEGA_DT`]/ω: the largest explicit step allowed (s).
    pub max_step: f64,
}

/// The explicit step limit of every listed effect for `fabric` at node spacing `spacing` (m),
/// tightest first. `compression_modulus` (N/m) is the link compression spring's when stretch is a
/// constraint, `None` for [`LinkCompression::default_modulus`].
pub fn explicit_step_limits(
    fabric: &Fabric,
    spacing: f64,
    bending: bool,
    trellising: bool,
    hysteresis: bool,
    stretch: StretchModel,
    compression_modulus: Option<f64>,
) -> Vec<StepLimit> {
    let mass = fabric.areal_density * spacing * spacing;
    let limit = |effect, stiffness: f64| StepLimit {
        effect,
        max_step: MAX_OMEGA_DT / (stiffness / mass).sqrt(),
    };
    let threads = [Thread::Warp, Thread::Weft];
    let mut limits = Vec::new();
    if bending {
        // Up to K = 2/σ, a thread folded flat over one spacing.
        let b: f64 = threads
            .iter()
            .map(|t| {
                let friction = HysteresisLaw::bending(fabric.bending(*t));
                fabric.bending(*t).moment.max_slope(2.0 / spacing)
                    + if hysteresis { friction.stick_stiffness } else { 0.0 }
            })
            .sum();
        limits.push(limit("bending", 16.0 * b / (spacing * spacing)));
    }
    if trellising {
        let friction = if hysteresis {
            HysteresisLaw::shear(&fabric.shear).stick_stiffness
        } else {
            0.0
        };
        limits.push(limit(
            "trellising",
            4.0 * (fabric.shear.force.max_slope(1.0) + friction),
        ));
    }
    let tensile = |per_law: &dyn Fn(&crate::material::TensileLaw) -> f64| {
        threads
            .iter()
            .map(|t| per_law(&fabric.tensile(*t).law))
            .fold(0.0, f64::max)
    };
    match stretch {
        StretchModel::Constraint => {
            let modulus =
                compression_modulus.unwrap_or_else(|| LinkCompression::default_modulus(fabric, spacing));
            limits.push(limit("compression", 4.0 * modulus));
        }
        StretchModel::Kes => limits.push(limit(
            "stretch_kes",
            4.0 * tensile(&|law| law.stiffness(law.strain_at_max_load)),
        )),
        StretchModel::Seed => limits.push(limit(
            "stretch_seed",
            4.0 * tensile(&|law| 4.0 * law.max_load / law.strain_at_max_load),
        )),
    }
    limits.sort_by(|a, b| a.max_step.total_cmp(&b.max_step));
    limits
}

/// The explicit step limit of every effect in `choice` for `fabric` at node spacing `spacing`
/// (m), tightest first, for nodes massed by `node_mass`. With [`NodeMass::CellArea`] an edge
/// node carries half a cell against an interior node's stiffness along the edge, so every limit
/// is √2 shorter than [`explicit_step_limits`] gives; with [`NodeMass::TrueArea`] a circle's hem
/// node carries at least 0.45 of a cell, and every limit is √(1/0.45) shorter.
pub fn step_limits(
    fabric: &Fabric,
    spacing: f64,
    choice: &EffectChoice,
    node_mass: NodeMass,
) -> Vec<StepLimit> {
    let mut limits = explicit_step_limits(
        fabric,
        spacing,
        choice.bending,
        choice.trellising,
        choice.hysteresis,
        choice.stretch,
        choice.compression_modulus,
    );
    // 1/√(the lightest outline node's share of a cell): ½ on an edge, at least 0.45 on a
    // circle's clipped hem (`TrueArea`; `tests/node_masses.rs`), against an interior node's
    // stiffness along the outline.
    let shorter = match node_mass {
        NodeMass::Uniform => None,
        NodeMass::CellArea => Some(std::f64::consts::SQRT_2),
        NodeMass::TrueArea => Some((1.0f64 / 0.45).sqrt()),
    };
    if let Some(factor) = shorter {
        for limit in &mut limits {
            limit.max_step /= factor;
        }
    }
    limits
}
