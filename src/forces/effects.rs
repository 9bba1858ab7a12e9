//! The one list of effects: every force generator a cloth can carry, the condition under which
//! it is built, its name, its checkpoint state. Adding an effect means adding a variant to
//! [`EffectKind`] (its name, and how [`EffectKind::build`] makes it) and nothing else: scenes,
//! the bevy_ecs schedule, the plain-Rapier [`crate::embed::KesCloth`], the implicit solve, the
//! divergence diagnostics, `metrics.json` and checkpoints all go through [`Effects`].

use std::sync::Arc;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{
    AirDrag, Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Hysteresis, KesTensile,
    LinkCompression, LinkDamping, SeedSeparation, Trellising,
};
use crate::material::Fabric;

/// How the threads resist stretch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StretchModel {
    /// Rapier rope joints at the rest spacing: nearly inextensible, solved implicitly.
    Constraint,
    /// The seed's separation law (eq. 1), C₀ from the KES tensile test.
    Seed,
    /// The KES tensile power law from EMT, LT and WT.
    Kes,
}

/// What a cloth asks for: the input of every effect's build condition.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectChoice {
    /// How the threads resist stretch.
    pub stretch: StretchModel,
    /// With [`StretchModel::Constraint`], the compression spring's modulus (N/m); `None` for
    /// [`LinkCompression::default_modulus`].
    pub compression_modulus: Option<f64>,
    /// KES bending M(K).
    pub bending: bool,
    /// KES trellising F(φ).
    pub trellising: bool,
    /// Link damping rate (1/s), if any.
    pub damping: Option<f64>,
    /// Air drag coefficient (N·s/m³), if any.
    pub air_drag: Option<f64>,
    /// Bending and shear hysteresis (built only with bending or trellising on).
    pub hysteresis: bool,
}

/// Every effect kes-cloth can run, in the order its forces are added each step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EffectKind {
    /// KES bending M(K) along warp and weft (seed eq. 2), [`Bending`].
    Bending,
    /// KES trellising F(φ) (seed eq. 3), [`Trellising`].
    Trellising,
    /// The seed's separation stretch (eq. 1), [`SeedSeparation`].
    StretchSeed,
    /// The KES tensile stretch, [`KesTensile`].
    StretchKes,
    /// Compression resistance of rope-jointed links, [`LinkCompression`].
    Compression,
    /// Damping of relative motion along links, [`LinkDamping`].
    Damping,
    /// Linear air drag, [`AirDrag`].
    AirDrag,
    /// Bending and shear hysteresis (KES 2HB, 2HG, 2HG5), [`Hysteresis`].
    Hysteresis,
}

impl EffectKind {
    /// Every effect, in the order its forces are added.
    pub const ALL: [EffectKind; 8] = [
        EffectKind::Bending,
        EffectKind::Trellising,
        EffectKind::StretchSeed,
        EffectKind::StretchKes,
        EffectKind::Compression,
        EffectKind::Damping,
        EffectKind::AirDrag,
        EffectKind::Hysteresis,
    ];

    /// The effect's name, as `metrics.json` and divergence errors spell it; equal to its
    /// generator's [`ForceGenerator::effect`].
    pub const fn name(self) -> &'static str {
        match self {
            EffectKind::Bending => "bending",
            EffectKind::Trellising => "trellising",
            EffectKind::StretchSeed => "stretch_seed",
            EffectKind::StretchKes => "stretch_kes",
            EffectKind::Compression => "compression",
            EffectKind::Damping => "damping",
            EffectKind::AirDrag => "air_drag",
            EffectKind::Hysteresis => "hysteresis",
        }
    }

    /// The effect's generator for a cloth of `topology` and `fabric` whose nodes weigh
    /// `masses` (kg, in particle order), if `choice` asks for it: this is the effect's run condition, since an
    /// effect that is not built never runs.
    pub fn build(
        self,
        choice: &EffectChoice,
        topology: &Arc<ClothTopology>,
        fabric: &Fabric,
        masses: &[f64],
    ) -> Option<Box<dyn ForceGenerator>> {
        let t = topology.clone();
        let sigma = topology.spacing;
        let generator: Box<dyn ForceGenerator> = match self {
            EffectKind::Bending if choice.bending => Box::new(Bending::new(t, fabric)),
            EffectKind::Trellising if choice.trellising => Box::new(Trellising::new(t, fabric)),
            EffectKind::StretchSeed if choice.stretch == StretchModel::Seed => {
                Box::new(SeedSeparation::new(t, fabric))
            }
            EffectKind::StretchKes if choice.stretch == StretchModel::Kes => {
                Box::new(KesTensile::new(t, fabric))
            }
            EffectKind::Compression if choice.stretch == StretchModel::Constraint => {
                let modulus = choice
                    .compression_modulus
                    .unwrap_or_else(|| LinkCompression::default_modulus(fabric, sigma));
                Box::new(LinkCompression::new(t, modulus))
            }
            EffectKind::Damping => Box::new(LinkDamping::with_masses(t, choice.damping?, masses)),
            EffectKind::AirDrag => Box::new(AirDrag::new(choice.air_drag?, sigma)),
            EffectKind::Hysteresis if choice.hysteresis && (choice.bending || choice.trellising) => {
                Box::new(Hysteresis::new(t, fabric, choice.bending, choice.trellising))
            }
            _ => return None,
        };
        Some(generator)
    }
}

/// The effects one cloth carries, in [`EffectKind::ALL`]'s order.
pub struct Effects(Vec<Box<dyn ForceGenerator>>);

/// An effect's state carried from step to step (hysteresis slips), by effect name, as a
/// checkpoint keeps it.
pub type EffectStates = Vec<(String, Vec<f64>)>;

impl Effects {
    /// The effects `choice` asks for (see [`EffectKind::build`]).
    pub fn build(
        choice: &EffectChoice,
        topology: &Arc<ClothTopology>,
        fabric: &Fabric,
        masses: &[f64],
    ) -> Self {
        Self(
            EffectKind::ALL
                .iter()
                .filter_map(|k| k.build(choice, topology, fabric, masses))
                .collect(),
        )
    }

    /// The generators, in the order their forces are added.
    pub fn iter(&self) -> impl Iterator<Item = &dyn ForceGenerator> {
        self.0.iter().map(|g| g.as_ref())
    }

    /// The generators, mutable (to advance their state).
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut Box<dyn ForceGenerator>> {
        self.0.iter_mut()
    }

    /// The generators as the implicit solve takes them.
    pub fn as_slice(&self) -> &[Box<dyn ForceGenerator>] {
        &self.0
    }

    /// The effect named `name`, if the cloth carries it.
    pub fn get(&self, name: &str) -> Option<&dyn ForceGenerator> {
        self.iter().find(|g| g.effect() == name)
    }

    /// Moves every effect's state to `geometry` (once a step, before forces are taken).
    pub fn advance_state(&mut self, geometry: &ClothGeometry) {
        for g in &mut self.0 {
            g.advance_state(geometry);
        }
    }

    /// Adds every effect's forces (N) into `forces`.
    pub fn add_forces(&self, geometry: &ClothGeometry, velocities: &[DVec3], forces: &mut ForceBuffer) {
        for g in &self.0 {
            g.add_forces(geometry, velocities, forces);
        }
    }

    /// Node forces (N) of one effect alone at `positions` (m) and `velocities` (m/s).
    fn forces_of(
        g: &dyn ForceGenerator,
        topology: &Arc<ClothTopology>,
        positions: &[DVec3],
        velocities: &[DVec3],
    ) -> Vec<DVec3> {
        let mut geometry = ClothGeometry::new(topology.clone());
        geometry.update(positions);
        let mut buffer = ForceBuffer::new(topology);
        g.add_forces(&geometry, velocities, &mut buffer);
        buffer.resolve(topology).to_vec()
    }

    /// The first effect whose forces alone, at this state, are not finite: the one at fault
    /// when a step's summed forces are.
    pub fn first_non_finite(
        &self,
        topology: &Arc<ClothTopology>,
        positions: &[DVec3],
        velocities: &[DVec3],
    ) -> Option<&'static str> {
        self.iter()
            .find(|g| {
                Self::forces_of(*g, topology, positions, velocities)
                    .iter()
                    .any(|f| !f.is_finite())
            })
            .map(|g| g.effect())
    }

    /// The effect whose forces alone push hardest on `node` at this state: in a runaway, the
    /// likeliest culprit.
    pub fn strongest_at(
        &self,
        node: usize,
        topology: &Arc<ClothTopology>,
        positions: &[DVec3],
        velocities: &[DVec3],
    ) -> Option<&'static str> {
        self.iter()
            .filter_map(|g| {
                let f = Self::forces_of(g, topology, positions, velocities)
                    .get(node)?
                    .length();
                f.is_finite().then_some((f, g.effect()))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, name)| name)
    }

    /// Every stateful effect's state, by name.
    pub fn states(&self) -> EffectStates {
        self.iter()
            .filter_map(|g| Some((g.effect().to_string(), g.state()?)))
            .collect()
    }

    /// Restores states saved by [`Self::states`]; `false` unless every stateful effect finds its
    /// own state and every state its effect.
    pub fn restore_states(&mut self, states: &EffectStates) -> bool {
        let stateful = self.0.iter().filter(|g| g.state().is_some()).count();
        stateful == states.len()
            && states.iter().all(|(name, state)| {
                self.0
                    .iter_mut()
                    .find(|g| g.effect() == name)
                    .is_some_and(|g| g.restore_state(state))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The registry's names are the generators' own (metrics and checkpoints use the latter).
    #[test]
    fn every_effect_is_named_as_its_generator() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/fabrics/thick_cotton.ron");
        let fabric = Fabric::load(path).expect("shipped fabric loads");
        let topology = Arc::new(ClothTopology::rectangle(4, 4, 0.01));
        for stretch in [StretchModel::Constraint, StretchModel::Seed, StretchModel::Kes] {
            let choice = EffectChoice {
                stretch,
                compression_modulus: None,
                bending: true,
                trellising: true,
                damping: Some(1.0),
                air_drag: Some(1.0),
                hysteresis: true,
            };
            for kind in EffectKind::ALL {
                if let Some(g) = kind.build(&choice, &topology, &fabric, &[1e-3; 16]) {
                    assert_eq!(g.effect(), kind.name());
                }
            }
        }
    }
}
