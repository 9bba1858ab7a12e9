//! Building a KES cloth inside a Rapier world.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use rapier3d::prelude::*;

use super::BuildError;
use super::Roughness;
use crate::bodies::{ClothBodies, NodeOptions};
use crate::forces::{EffectChoice, Effects, NodeMass, StepLimit, StretchModel};
use crate::implicit::{ImplicitSettings, ImplicitSolver, Integrator};
use crate::material::Fabric;
use crate::schedule::ClothState;

mod lattice;

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

/// The least height (m) of a node's centre above a fixed collider it rests on with
/// [`ClothBuilder::rest_on_lower_face`], whatever the fabric's thickness: a ball whose centre
/// reaches the surface meets it along an ill-defined normal, and a flat cloth resting so on a
/// plane at 1/60 s jitters at 3–17 mm/s where with 0.05 mm it is still.
pub const LOWEST_CLEARANCE: f64 = 5e-5;

/// Builds a KES cloth into a Rapier world. Defaults: a 0.3 m square, 1 cm spacing, centred at
/// the origin, warp along +x, stretch as a constraint, bending and trellising on, link damping
/// 150/s, no hysteresis, contact with the world on, no self-collision, gravity on, no pins, and
/// the integrator chosen from the world's step (explicit where the fabric's explicit forces are
/// stable at it, implicit otherwise; [`Self::integrator`]).
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
    roughness: Roughness,
    node_mass: NodeMass,
    effects: EffectChoice,
    contact: bool,
    self_collision: bool,
    gravity: bool,
    pins: Vec<Pin>,
    integrator: Option<Integrator>,
    step_guard: bool,
    /// Whether [`Self::stretch`] was called.
    stretch_set: bool,
    /// [`Self::rest_on_lower_face`].
    lower_face: bool,
    /// [`Self::link_support`] (Hz).
    link_support_hz: Option<f64>,
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
            roughness: Roughness::PerNode,
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
            integrator: None,
            step_guard: true,
            stretch_set: false,
            lower_face: false,
            link_support_hz: None,
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

    /// Contact radius of the nodes (m; default half the spacing, so neighbouring nodes touch and
    /// bodies dropped on the cloth cannot slip between them; the mid-surface then rests that far
    /// above a surface).
    pub fn node_radius(mut self, radius: f64) -> Self {
        self.node_radius = Some(radius);
        self
    }

    /// Whether a cloth from [`Self::build`] rests on the world's fixed and kinematic colliders
    /// with its lower face, its mid-surface (the node centres) half the fabric's thickness
    /// above them (at least [`LOWEST_CLEARANCE`]), instead of one node radius above (default
    /// `false`). The host's shapes stay as they are: [`super::SheetContacts`] reads each node's
    /// contact with them that much deeper than Rapier measures its ball, so the world must be
    /// stepped with those hooks, as [`super::KesCloth::step`] does. Dynamic bodies still meet
    /// the nodes' balls, which keep them from slipping between nodes. Not the default: over a
    /// table's sharp edge at 1/60 s some fabrics take longer to come to rest
    /// (`docs/rapier.md`). Cloths from [`Self::build_parts`] (the bevy_ecs way in) rest one node
    /// radius above.
    pub fn rest_on_lower_face(mut self, on: bool) -> Self {
        self.lower_face = on;
        self
    }

    /// Whether the links between nodes, not only the nodes, rest on the edges of the world's
    /// fixed and kinematic colliders (a drapemeter's rim, a table's edge), and how stiffly: a
    /// penalty spring at the point of a link an edge presses, of natural frequency `hz` (Hz) on
    /// the link's mean node mass, shared by its two nodes ([`crate::implicit::LinkSupport`];
    /// `docs/model.md` §1, "Link support"). Default `None`: a cloth leaves an edge at a node.
    /// Acts in the implicit solve only; an explicit cloth keeps node contact.
    pub fn link_support(mut self, hz: Option<f64>) -> Self {
        self.link_support_hz = hz;
        self
    }

    /// A seeded start roughness of up to `amplitude` (m), drawn as [`Self::roughness`] says
    /// (default: an independent offset in ±`amplitude` at every node). Default none.
    pub fn perturbation(mut self, amplitude: f64, seed: u64) -> Self {
        self.perturbation = (amplitude, seed);
        self
    }

    /// How the start roughness of [`Self::perturbation`] is drawn (default
    /// [`Roughness::PerNode`]; [`Roughness::Smooth`]: one smooth field over the flat cloth, the
    /// same at every spacing and lattice placement).
    pub fn roughness(mut self, kind: Roughness) -> Self {
        self.roughness = kind;
        self
    }

    /// How the cloth's mass is shared among its nodes (default [`NodeMass::Uniform`]).
    pub fn node_mass(mut self, rule: NodeMass) -> Self {
        self.node_mass = rule;
        self
    }

    /// How the threads resist stretch. Unset, [`StretchModel::Constraint`] (Rapier's rope
    /// joints) for an explicit cloth and [`StretchModel::Kes`] for one the builder makes
    /// implicit ([`Self::integrator`]): rope joints cannot hold a cloth at long steps
    /// (`docs/rapier.md`, "Embedding at the host's step").
    pub fn stretch(mut self, model: StretchModel) -> Self {
        self.effects.stretch = model;
        self.stretch_set = true;
        self
    }

    /// With stretch as a constraint, the link compression spring's in-plane modulus (N/m; each
    /// link's stiffness), or `None` (default) for the default modulus. The
    /// default is [`crate::forces::LinkCompression::default_modulus`]. A stiffer spring needs a
    /// shorter explicit step ([`Self::step_limits`]).
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

    /// How our forces are integrated. Unset (the default), the world's step decides when the
    /// cloth is built: [`Integrator::Explicit`] when the step is within every effect's explicit
    /// limit ([`Self::step_limits`]), otherwise [`Integrator::Implicit`] with
    /// [`ImplicitSettings::default`], stable at any step, with the KES tensile law unless
    /// [`Self::stretch`] was set. Asked for explicitly at a step beyond
    /// the limit, the build is refused ([`BuildError::StepTooLong`]) unless
    /// [`Self::step_guard`] is off.
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = Some(integrator);
        self
    }

    /// Whether an explicit cloth at a world step beyond its stability limit is refused (default
    /// true). Off, it is built anyway: the divergence checks of [`super::KesCloth::step`] are
    /// then what stops it.
    pub fn step_guard(mut self, on: bool) -> Self {
        self.step_guard = on;
        self
    }

    /// The explicit step limit of every effect this cloth runs, tightest first (s;
    /// `docs/model.md` §10): thick cotton at 1 cm with stretch as a constraint allows 0.139 ms.
    pub fn step_limits(&self) -> Vec<StepLimit> {
        crate::forces::step_limits(&self.fabric, self.spacing, &self.effects, self.node_mass)
    }

    /// The integrator a world step of `dt` (s) gets: the one set, or the one the step allows.
    pub fn integrator_at(&self, dt: f64) -> Result<Integrator, BuildError> {
        let tightest = self.step_limits().first().copied();
        let too_long = tightest.filter(|l| dt > l.max_step);
        match (self.integrator, too_long) {
            (Some(Integrator::Explicit), Some(limit)) if self.step_guard => Err(BuildError::StepTooLong {
                dt_s: dt,
                effect: limit.effect,
                max_step_s: limit.max_step,
                spacing_m: self.spacing,
            }),
            (Some(integrator), _) => Ok(integrator),
            (None, Some(_)) => Ok(Integrator::Implicit(ImplicitSettings::default())),
            (None, None) => Ok(Integrator::Explicit),
        }
    }

    /// The fabric.
    pub fn fabric(&self) -> &Fabric {
        &self.fabric
    }

    /// The settings' ranges, checked before anything is added to a world whose step is `dt`
    /// (s).
    fn check(&self, dt: f64) -> Result<(), BuildError> {
        let invalid = |setting, value: f64, allowed: &str| {
            Err(BuildError::Invalid {
                setting,
                value,
                allowed: allowed.to_string(),
            })
        };
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(dt) {
            return invalid("integration_parameters.dt", dt, "must be a positive step (s)");
        }
        if !(self.spacing.is_finite() && self.spacing >= 1e-4) {
            return invalid("spacing", self.spacing, "must be at least 1e-4 m (0.1 mm)");
        }
        let sizes = match self.outline {
            ClothOutline::Circle(d) => vec![("outline (circle diameter)", d)],
            ClothOutline::Rectangle { warp, weft } => {
                vec![("outline (warp length)", warp), ("outline (weft length)", weft)]
            }
        };
        for (setting, size) in sizes {
            if !(size.is_finite() && size >= 2.0 * self.spacing && size <= 1e4 * self.spacing) {
                return invalid(
                    setting,
                    size,
                    &format!(
                        "must lie in [2σ, 10⁴σ] = [{}, {}] m at σ = {} m",
                        2.0 * self.spacing,
                        1e4 * self.spacing,
                        self.spacing
                    ),
                );
            }
        }
        if let Some(hz) = self.link_support_hz.filter(|hz| !positive(*hz)) {
            return invalid("link_support", hz, "must be positive (Hz)");
        }
        if let Some(r) = self.node_radius.filter(|r| !positive(*r)) {
            return invalid("node_radius", r, "must be positive (m)");
        }
        let (nu, nv) = self.grid_size();
        let (topology, _) = self.grid();
        for pin in &self.pins {
            if !topology.grid_coords.contains(&pin.node) {
                return Err(BuildError::PinOutsideCloth {
                    node: pin.node,
                    grid: (nu, nv),
                    circle: matches!(self.outline, ClothOutline::Circle(_)),
                });
            }
        }
        Ok(())
    }

    /// Adds the cloth's bodies, joints and pins to `world`, integrated as
    /// [`Self::integrator_at`] the world's step decides. Refused, with nothing added to the
    /// world, when a setting is out of range, a pin names no node, or explicit forces were asked
    /// for at a step they cannot take.
    pub fn build_parts(self, world: &mut PhysicsWorld) -> Result<ClothParts, BuildError> {
        self.checked_parts(world, false)
    }

    /// [`Self::build_parts`], resting on its lower face if `lower_face` and
    /// [`Self::rest_on_lower_face`] both ask for it.
    fn checked_parts(self, world: &mut PhysicsWorld, lower_face: bool) -> Result<ClothParts, BuildError> {
        let dt = world.integration_parameters.dt as f64;
        self.check(dt)?;
        let integrator = self.integrator_at(dt)?;
        let mut builder = self;
        if builder.integrator.is_none() && !builder.stretch_set && integrator != Integrator::Explicit {
            builder.effects.stretch = StretchModel::Kes;
        }
        let lower_face = lower_face && builder.lower_face;
        Ok(builder.assemble(world, integrator, lower_face))
    }

    /// [`Self::build_parts`] for a scene, which has validated every setting (with the place in
    /// its file) and run its own stability guard: the integrator it set, no check.
    pub(crate) fn build_scene_parts(self, world: &mut PhysicsWorld) -> ClothParts {
        let integrator = self.integrator.unwrap_or(Integrator::Explicit);
        self.assemble(world, integrator, false)
    }

    /// Adds the bodies, joints and pins, with `integrator`, resting on the lower face if
    /// `lower_face` ([`Self::rest_on_lower_face`]).
    fn assemble(self, world: &mut PhysicsWorld, integrator: Integrator, lower_face: bool) -> ClothParts {
        let (mut topology, mut positions) = self.grid();
        // Nodes pinned to a body that cannot move: held in place, as a clamp holds them.
        let held: Vec<usize> = self
            .pins
            .iter()
            .filter(|pin| world.bodies.get(pin.body).is_some_and(|b| !b.is_dynamic()))
            .filter_map(|pin| topology.grid_coords.iter().position(|&c| c == pin.node))
            .collect();
        topology.hold_rigidly(&held);
        if self.node_mass.shares_outline() {
            topology.share_outline_widths();
        }
        let topology = Arc::new(topology);
        let (amplitude, seed) = self.perturbation;
        if amplitude > 0.0 {
            let offsets = self
                .roughness
                .offsets(amplitude, seed, &self.flat_coordinates(&topology));
            for (p, dy) in positions.iter_mut().zip(offsets) {
                p.y += dy;
            }
        }
        let masses = self.masses_of(&topology);
        let radius = self.node_radius.unwrap_or(topology.spacing / 2.0);
        let options = NodeOptions {
            masses: masses.clone(),
            radius,
            rope_links: self.effects.stretch == StretchModel::Constraint,
            contact: self.contact,
            self_collision: self.self_collision,
            gravity: self.gravity,
            surface_depth: match lower_face {
                true => radius - (0.5 * self.fabric.thickness).max(LOWEST_CLEARANCE),
                false => 0.0,
            },
            link_support_hz: self.link_support_hz,
        };
        let mut bodies = ClothBodies::spawn(world, &topology, &positions, &options);
        for pin in &self.pins {
            if let Some(node) = topology.grid_coords.iter().position(|&c| c == pin.node) {
                match world.bodies.get(pin.body) {
                    Some(b) if b.is_kinematic() => bodies.moving_pins.push((node, pin.body, pin.anchor)),
                    Some(b) if b.is_dynamic() => bodies.dynamic_pins.push((node, pin.body, pin.anchor)),
                    _ => {}
                }
                let joint = SphericalJointBuilder::new()
                    .local_anchor1(pin.anchor)
                    .local_anchor2(Vec3::ZERO)
                    .contacts_enabled(false);
                world.insert_impulse_joint(pin.body, bodies.handles[node], joint);
            }
        }
        // The state starts from what Rapier holds (its positions are f32), as every later step
        // does: a cloth stepped by the schedule and one stepped by `KesCloth` start alike.
        let mut state = ClothState::new(topology.clone(), positions);
        bodies.read(world, &mut state.positions, &mut state.velocities);
        state.previous_positions.clone_from(&state.positions);
        state.geometry.update(&state.positions);
        ClothParts {
            effects: Effects::build(&self.effects, &topology, &self.fabric, &masses),
            implicit: match integrator {
                Integrator::Explicit => None,
                Integrator::Implicit(settings) => {
                    // The held nodes stay put in the implicit solve too; a node pinned to a
                    // dynamic body moves with it there (`implicit::Carriers`).
                    let mut solver = ImplicitSolver::with_masses(topology.clone(), masses, settings);
                    for node in held.into_iter().chain(bodies.dynamic_pins.iter().map(|p| p.0)) {
                        solver.hold(node);
                    }
                    // Friction in the solve needs every force on a node in the solve: Rapier's
                    // rope joints are not (docs/model.md §12).
                    let rope = self.effects.stretch == StretchModel::Constraint;
                    solver.apply_friction(settings.friction.unwrap_or(!rope));
                    Some(solver)
                }
            },
            state,
            bodies,
        }
    }

    /// Builds a cloth to drive from a plain Rapier loop ([`Self::build_parts`]'s checks), resting
    /// on its lower face if [`Self::rest_on_lower_face`] asked for it ([`super::KesCloth::step`]
    /// steps the world with [`super::SheetContacts`]).
    pub fn build(self, world: &mut PhysicsWorld) -> Result<super::KesCloth, BuildError> {
        Ok(super::KesCloth::from_parts(self.checked_parts(world, true)?))
    }
}
