//! Building a KES cloth inside a Rapier world.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;
use rapier3d::prelude::*;

use crate::bodies::{ClothBodies, NodeOptions};
use crate::forces::{ClothTopology, EffectChoice, Effects, NodeMass, StretchModel};
use crate::implicit::{ImplicitSolver, Integrator};
use crate::material::Fabric;
use crate::schedule::ClothState;

/// Outline of the flat cloth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClothOutline {
    /// A circle of this diameter (m).
    Circle(f64),
    /// A rectangle, `warp` (m) along the warp and `weft` (m) along the weft.
    Rectangle {
        /// Length along the warp (m).
        warp: f64,
        /// Length along the weft (m).
        weft: f64,
    },
}

/// A node held to a rigid body (fixed, kinematic or dynamic) by a ball joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pin {
    /// Grid coordinates (i along the warp, j along the weft) of the node, from the cloth's
    /// (−warp, −weft) corner of its bounding square.
    pub node: (u32, u32),
    /// The body it hangs from.
    pub body: RigidBodyHandle,
    /// Where on that body, in the body's frame (m).
    pub anchor: Vec3,
}

/// Everything a built cloth consists of: its state, its Rapier bodies, and the generators of
/// the effects it asked for.
pub struct ClothParts {
    /// Node state and force buffers.
    pub state: ClothState,
    /// The Rapier bodies and joints.
    pub bodies: ClothBodies,
    /// One force generator per effect asked for, in the order their forces are added.
    pub effects: Effects,
    /// The backward-Euler solve, for [`Integrator::Implicit`].
    pub implicit: Option<ImplicitSolver>,
}

/// Builds a KES cloth into a Rapier world. Defaults: a 0.3 m square, 1 cm spacing, centred at
/// the origin, warp along +x, stretch as a constraint, bending and trellising on, link damping
/// 150/s, no hysteresis, contact with the world on, no self-collision, gravity on, no pins.
#[derive(Clone, Debug)]
pub struct ClothBuilder {
    fabric: Fabric,
    outline: ClothOutline,
    spacing: f64,
    centre: DVec3,
    warp_angle_deg: f64,
    initial_shear_deg: f64,
    lattice_offset: [f64; 2],
    fold_gap: Option<f64>,
    node_radius: Option<f64>,
    perturbation: (f64, u64),
    node_mass: NodeMass,
    effects: EffectChoice,
    contact: bool,
    self_collision: bool,
    gravity: bool,
    pins: Vec<Pin>,
    integrator: Integrator,
}

impl ClothBuilder {
    /// A cloth of `fabric` with the defaults above.
    pub fn new(fabric: Fabric) -> Self {
        Self {
            fabric,
            outline: ClothOutline::Rectangle { warp: 0.3, weft: 0.3 },
            spacing: 0.01,
            centre: DVec3::ZERO,
            warp_angle_deg: 0.0,
            initial_shear_deg: 0.0,
            lattice_offset: [0.0; 2],
            fold_gap: None,
            node_radius: None,
            perturbation: (0.0, 0),
            node_mass: NodeMass::Uniform,
            effects: EffectChoice {
                stretch: StretchModel::Constraint,
                compression_modulus: None,
                bending: true,
                trellising: true,
                damping: Some(150.0),
                air_drag: None,
                hysteresis: false,
            },
            contact: true,
            self_collision: false,
            gravity: true,
            pins: Vec::new(),
            integrator: Integrator::Explicit,
        }
    }

    /// The flat outline.
    pub fn outline(mut self, outline: ClothOutline) -> Self {
        self.outline = outline;
        self
    }

    /// σ, node spacing (m).
    pub fn spacing(mut self, spacing: f64) -> Self {
        self.spacing = spacing;
        self
    }

    /// Centre of the flat cloth (m) and angle of its warp from +x about +y (degrees); the cloth
    /// lies horizontal.
    pub fn pose(mut self, centre: DVec3, warp_angle_deg: f64) -> Self {
        self.centre = centre;
        self.warp_angle_deg = warp_angle_deg;
        self
    }

    /// Starts the cloth sheared in its plane: the weft leans towards the warp by `degrees`, every
    /// link at its rest length (default 0).
    pub fn initial_shear(mut self, degrees: f64) -> Self {
        self.initial_shear_deg = degrees;
        self
    }

    /// Shifts a circular cloth's node lattice by `offset` (m, along warp and weft, each within
    /// ± half the spacing: nodes beyond would fall outside the grid) against its outline, which
    /// stays centred at the pose (default (0, 0): a node at the centre). The grid coordinates
    /// that [`Self::pin`] takes then count from a lattice one node wider on each side. Ignored
    /// for rectangles, whose lattice fills the outline.
    pub fn lattice_offset(mut self, offset: [f64; 2]) -> Self {
        self.lattice_offset = offset;
        self
    }

    /// Starts the cloth folded flat onto itself across the middle of the warp, the far half
    /// `gap` (m) above the near half along the cloth's normal (default: flat).
    pub fn fold(mut self, gap: Option<f64>) -> Self {
        self.fold_gap = gap;
        self
    }

    /// Contact radius of the nodes (m; default half the spacing).
    pub fn node_radius(mut self, radius: f64) -> Self {
        self.node_radius = Some(radius);
        self
    }

    /// A seeded random vertical offset of up to `amplitude` (m) on every node.
    pub fn perturbation(mut self, amplitude: f64, seed: u64) -> Self {
        self.perturbation = (amplitude, seed);
        self
    }

    /// How the cloth's mass is shared among its nodes (default [`NodeMass::Uniform`]).
    pub fn node_mass(mut self, rule: NodeMass) -> Self {
        self.node_mass = rule;
        self
    }

    /// How the threads resist stretch.
    pub fn stretch(mut self, model: StretchModel) -> Self {
        self.effects.stretch = model;
        self
    }

    /// With stretch as a constraint, the link compression spring's in-plane modulus (N/m; each
    /// link's stiffness), or `None` (default) for the default modulus. The
    /// builder runs no stability guard: an explicit world step must stay below the limit
    /// [`crate::forces::explicit_step_limits`] gives (0.139 ms for thick cotton at 1 cm); the
    /// default is [`crate::forces::LinkCompression::default_modulus`].
    pub fn compression_modulus(mut self, modulus: Option<f64>) -> Self {
        self.effects.compression_modulus = modulus;
        self
    }

    /// Switches KES bending and trellising on or off.
    pub fn bending_and_trellising(mut self, bending: bool, trellising: bool) -> Self {
        self.effects.bending = bending;
        self.effects.trellising = trellising;
        self
    }

    /// Link damping rate (1/s), or `None` for none.
    pub fn damping(mut self, rate: Option<f64>) -> Self {
        self.effects.damping = rate;
        self
    }

    /// Air drag coefficient (N·s/m³), or `None` for none.
    pub fn air_drag(mut self, coefficient: Option<f64>) -> Self {
        self.effects.air_drag = coefficient;
        self
    }

    /// Hysteresis of bending and shear from the fabric's 2HB, 2HG and 2HG5 (default off: the
    /// elastic mean curves alone). Acts on whichever of bending and trellising is on.
    pub fn hysteresis(mut self, on: bool) -> Self {
        self.effects.hysteresis = on;
        self
    }

    /// Contact with the world's colliders, self-collision, gravity.
    pub fn collisions_and_gravity(mut self, contact: bool, self_collision: bool, gravity: bool) -> Self {
        self.contact = contact;
        self.self_collision = self_collision;
        self.gravity = gravity;
        self
    }

    /// Holds node (i, j) to `body` at `anchor` (body frame, m).
    pub fn pin(mut self, node: (u32, u32), body: RigidBodyHandle, anchor: Vec3) -> Self {
        self.pins.push(Pin { node, body, anchor });
        self
    }

    /// How our forces are integrated (default [`Integrator::Explicit`]).
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }

    /// The fabric.
    pub fn fabric(&self) -> &Fabric {
        &self.fabric
    }

    /// Nodes per side of the bounding grid.
    fn grid_size(&self) -> (usize, usize) {
        match self.outline {
            ClothOutline::Circle(d) => {
                // A shifted lattice can reach one node further on one side.
                let extra = usize::from(self.lattice_offset != [0.0; 2]);
                let n = 2 * ((d / 2.0 / self.spacing + 1e-9).floor() as usize + extra) + 1;
                (n, n)
            }
            ClothOutline::Rectangle { warp, weft } => (
                (warp / self.spacing).round() as usize + 1,
                (weft / self.spacing).round() as usize + 1,
            ),
        }
    }

    /// The woven grid and its flat node positions (m), before any perturbation.
    pub fn grid(&self) -> (ClothTopology, Vec<DVec3>) {
        let sigma = self.spacing;
        let (nu, nv) = self.grid_size();
        let (hu, hv) = ((nu - 1) as f64 / 2.0, (nv - 1) as f64 / 2.0);
        let (radius, [ou, ov]) = match self.outline {
            ClothOutline::Circle(d) => (Some(d / 2.0), self.lattice_offset),
            ClothOutline::Rectangle { .. } => (None, [0.0; 2]),
        };
        let topology = ClothTopology::from_mask(nu, nv, sigma, |i, j| {
            let (x, z) = ((i as f64 - hu) * sigma + ou, (j as f64 - hv) * sigma + ov);
            radius.is_none_or(|r| x * x + z * z <= r * r * (1.0 + 1e-9))
        });
        let angle = self.warp_angle_deg.to_radians();
        let warp = DVec3::new(angle.cos(), 0.0, -angle.sin());
        let weft = DVec3::new(angle.sin(), 0.0, angle.cos());
        let shear = self.initial_shear_deg.to_radians();
        let weft = shear.cos() * weft + shear.sin() * warp;
        let origin = self.centre + (ou - hu * sigma) * warp + (ov - hv * sigma) * weft;
        let mut positions = topology.rest_positions(origin, warp, weft);
        if let Some(gap) = self.fold_gap {
            // Crossings beyond the middle of the warp go onto their mirror images, `gap` above.
            let fold = (nu - 1) / 2;
            let up = weft.cross(warp).normalize();
            for (p, &(i, _)) in positions.iter_mut().zip(&topology.grid_coords) {
                let i = i as usize;
                if i > fold {
                    let back = 2.0 * (i - fold) as f64 * sigma;
                    *p += gap * up - back * warp;
                }
            }
        }
        (topology, positions)
    }

    /// Adds the cloth's bodies, joints and pins to `world`. Its step must stay below
    /// [`crate::forces::explicit_step_limits`] for explicit forces (no guard runs here).
    pub fn build_parts(self, world: &mut PhysicsWorld) -> ClothParts {
        let (topology, mut positions) = self.grid();
        let topology = Arc::new(topology);
        let (amplitude, seed) = self.perturbation;
        if amplitude > 0.0 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            for p in &mut positions {
                p.y += amplitude * rng.random_range(-1.0..=1.0);
            }
        }
        let sigma = topology.spacing;
        let masses = topology.node_masses(self.fabric.areal_density, self.node_mass);
        let options = NodeOptions {
            masses: masses.clone(),
            radius: self.node_radius.unwrap_or(sigma / 2.0),
            rope_links: self.effects.stretch == StretchModel::Constraint,
            contact: self.contact,
            self_collision: self.self_collision,
            gravity: self.gravity,
        };
        let bodies = ClothBodies::spawn(world, &topology, &positions, &options);
        // Nodes pinned to a body that cannot move: the implicit solve holds them too.
        let mut held = Vec::new();
        for pin in &self.pins {
            if let Some(node) = topology.grid_coords.iter().position(|&c| c == pin.node) {
                if world.bodies.get(pin.body).is_some_and(|b| !b.is_dynamic()) {
                    held.push(node);
                }
                let joint = SphericalJointBuilder::new()
                    .local_anchor1(pin.anchor)
                    .local_anchor2(Vec3::ZERO)
                    .contacts_enabled(false);
                world.insert_impulse_joint(pin.body, bodies.handles[node], joint);
            }
        }
        ClothParts {
            effects: Effects::build(&self.effects, &topology, &self.fabric, &masses),
            implicit: match self.integrator {
                Integrator::Explicit => None,
                Integrator::Implicit(settings) => {
                    let mut solver = ImplicitSolver::with_masses(topology.clone(), masses, settings);
                    for node in held {
                        solver.hold(node);
                    }
                    // Friction in the solve needs every force on a node in the solve: Rapier's
                    // rope joints are not (docs/model.md §12).
                    let rope = self.effects.stretch == StretchModel::Constraint;
                    solver.apply_friction(settings.friction.unwrap_or(!rope));
                    Some(solver)
                }
            },
            state: ClothState::new(topology.clone(), positions),
            bodies,
        }
    }

    /// Builds a cloth to drive from a plain Rapier loop.
    pub fn build(self, world: &mut PhysicsWorld) -> super::KesCloth {
        super::KesCloth::from_parts(self.build_parts(world))
    }
}
