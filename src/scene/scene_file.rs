//! The scene file schema (`scenes/*.ron`): SI units, the unit in every field name.
//!
//! Unknown fields are rejected. Optional fields have the defaults their docs give. The engine
//! never reads this type: [`crate::scene::Scene::from_file`] validates it into a
//! [`crate::scene::Scene`].

use serde::{Deserialize, Serialize};

pub use crate::embed::Roughness;
pub use crate::forces::{NodeMass, StretchModel};
use crate::material::KesFabric;

/// The schema version this build reads.
pub const SCENE_VERSION: u32 = 1;

/// A whole scene as written in a `.ron` file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Schema version; must be 1.
    pub version: u32,
    /// Scene name, used for the default output folder `out/<name>/`.
    pub name: String,
    /// The fabric: a KES fabric file (path relative to the scene file) or inline KES values.
    pub fabric: FabricSource,
    /// The cloth sample: shape, node spacing, placement.
    pub cloth: ClothSpec,
    /// Seed of the start roughness (`cloth.perturbation_m`; default 0).
    #[serde(default)]
    pub seed: u64,
    /// The rigid world: gravity and colliders.
    pub world: WorldSpec,
    /// What the run measures once the cloth settles: `Drape(disk: "disk")`,
    /// `Tablecloth(table: "table")` or `None` (motion and rest only).
    pub measure: MeasureSpec,
    /// The effects this scene simulates; anything not asked for never runs.
    pub effects: EffectsSpec,
    /// Time stepping, solver and stopping.
    pub integration: IntegrationSpec,
    /// Which output files to write.
    #[serde(default)]
    pub output: OutputSpec,
}

impl SceneFile {
    /// The step (s) the run takes while the cloth is quiet: `integration.rest_dt_s` where it
    /// applies, an implicit integrator whose solve holds the stretch (not Rapier's rope joints)
    /// and the supports' friction (not `implicit_solver.friction: Some(false)`) and a step longer
    /// than `dt_s`; `None` elsewhere (`docs/model.md` §12, "The step at rest").
    pub fn rest_step_s(&self) -> Option<f64> {
        let i = &self.integration;
        let held_by_the_solve = i.integrator != IntegratorSpec::Explicit
            && self.effects.stretch != StretchModel::Constraint
            && i.implicit_solver.friction != Some(false);
        (i.rest_dt_s > i.dt_s && held_by_the_solve).then_some(i.rest_dt_s)
    }
}

/// Where the fabric comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FabricSource {
    /// A fabric file in KES units, relative to the scene file's folder.
    File(String),
    /// KES values written in the scene itself.
    Inline(Box<KesFabric>),
}

/// The cloth sample before it drapes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClothSpec {
    /// Outline of the flat sample.
    pub shape: ClothShape,
    /// σ, node spacing: distance between neighbouring warp/weft crossings (m), > 0.
    pub spacing_m: f64,
    /// Centre of the flat sample (m), +y up.
    pub centre_m: [f64; 3],
    /// Angle of the warp from the +x axis, about +y (degrees; default 0).
    #[serde(default)]
    pub warp_angle_deg: f64,
    /// Initial in-plane shear φ: the weft starts leaning towards the warp by this angle, links
    /// at their rest length (degrees, within ±60; default 0). For release tests.
    #[serde(default)]
    pub initial_shear_deg: f64,
    /// Shift of a circular cloth's node lattice against its outline, along warp and weft (m, each
    /// within ± half the spacing; default (0, 0): a node at the centre). The outline stays where
    /// it is; which nodes fall inside it, and where they meet the disk's rim, change. For
    /// measuring how much a result owes to where the grid happens to fall (`docs/accuracy.md`).
    #[serde(default)]
    pub lattice_offset_m: [f64; 2],
    /// Peak height of the seeded start roughness (m; default 0), drawn as `roughness` says: at
    /// most a quarter of the spacing per node, at most 1.6 mm for a smooth field (whatever the
    /// spacing, so one start serves a convergence study).
    /// Breaks the symmetry of a perfectly flat start so repeats can differ, like laboratory
    /// repeats.
    #[serde(default)]
    pub perturbation_m: f64,
    /// How the start roughness is drawn: `PerNode` (default: an independent offset in
    /// ±`perturbation_m` at every node) or `Smooth` (one smooth random height field over the
    /// flat cloth, wavelengths 2–20 cm, RMS a quarter of `perturbation_m`: the same start at
    /// every spacing and lattice placement; `docs/model.md` §1).
    #[serde(default)]
    pub roughness: Roughness,
    /// Points (m) at which the cloth is pinned to the world: the node nearest each point in the
    /// flat layout is held there by a spherical joint to a fixed body (default none). Each point
    /// must lie within one spacing of a node.
    #[serde(default)]
    pub pins_m: Vec<[f64; 3]>,
    /// How the cloth's mass is shared among its nodes: `Uniform` (default: ρ_A·σ² each, outline
    /// nodes included), `CellArea` (the cell area each node stands for: ½σ² on an edge, ¼σ² at
    /// a corner, and each bending spring the width it stands for; `docs/model.md` §1) or
    /// `TrueArea` (as `CellArea`, with a circle's outline nodes carrying the part of the cut
    /// circle around them, so the nodes weigh what the specimen weighs).
    #[serde(default)]
    pub node_mass: NodeMass,
    /// Length (m) of the strip's root held as by a clamp: every node of the flat cloth within
    /// this distance of its −warp end is pinned where it lies (default 0: none). The cantilever
    /// test (`measure: Cantilever`) reads its angle from the clamp's edge; use a multiple of the
    /// spacing so that a row of nodes lies on the edge.
    #[serde(default)]
    pub clamp_m: f64,
    /// Contact radius of each node (m; default half the spacing). Node centres rest on the true
    /// collider surfaces: colliders are shrunk by this radius (see `docs/rapier.md`).
    #[serde(default)]
    pub node_radius_m: Option<f64>,
    /// Start folded flat onto itself across the middle of the warp: the far half lies on the near
    /// half, `gap_m` above it (m, at least two node radii so the layers do not overlap, at most
    /// half a spacing; default: not folded). The bending springs at the fold start almost closed
    /// (θ = atan(gap/σ)); the two layers need `effects.self_collision`.
    #[serde(default)]
    pub fold_gap_m: Option<f64>,
}

/// Outline of the flat sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ClothShape {
    /// A circle (drape tests).
    Circle {
        /// Diameter (m).
        diameter_m: f64,
    },
    /// A square, sides along warp and weft (tablecloths).
    Square {
        /// Side length (m).
        side_m: f64,
    },
    /// A rectangle, sides along warp and weft (strips: KES and bending-length specimens).
    Rectangle {
        /// Length along the warp (m).
        warp_m: f64,
        /// Length along the weft (m).
        weft_m: f64,
    },
}

impl ClothShape {
    /// Lengths of the outline's bounding box along warp and weft (m).
    pub fn extent_m(&self) -> [f64; 2] {
        match *self {
            ClothShape::Circle { diameter_m } => [diameter_m; 2],
            ClothShape::Square { side_m } => [side_m; 2],
            ClothShape::Rectangle { warp_m, weft_m } => [warp_m, weft_m],
        }
    }
}

/// What a run measures once the cloth settles, on which of the scene's colliders.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum MeasureSpec {
    /// Nothing beyond motion, strain, penetration and rest.
    None,
    /// The drape test: drape coefficient, nodes and outline around the named collider, a
    /// `Cylinder` (the drapemeter disk).
    Drape {
        /// Name of the disk's collider.
        disk: String,
    },
    /// A rectangular cloth on a table: the hang of its corners and mid-sides below the table
    /// top (m) and its skirt's folds, around the named collider, a `Cuboid`.
    Tablecloth {
        /// Name of the table's collider.
        table: String,
    },
    /// The cantilever bending test (BS 3356, ASTM D1388) on a strip whose root is held by
    /// `cloth.clamp_m`: the angle of the chord from the clamp's edge to the free (+warp) end,
    /// from the clamp's direction (below the horizontal under the usual gravity along −y),
    /// beside the heavy elastica's exact angle for the fabric's warp bending rigidity, the same
    /// overhang and the clamp's angle to gravity (gravity turned back along the warp makes the
    /// strip an upright heavy column, which bends to either side alike).
    Cantilever,
}

/// The rigid world.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// Gravity (m/s²; default (0, −9.80665, 0)).
    #[serde(default = "default_gravity")]
    pub gravity_m_per_s2: [f64; 3],
    /// Fixed colliders the cloth can touch.
    pub colliders: Vec<ColliderSpec>,
    /// How stiff contacts are (default: 960 Hz against fixed colliders, 30 Hz between moving
    /// bodies).
    #[serde(default)]
    pub contact: ContactSpec,
}

/// Stiffness of Rapier's soft contacts, as the natural frequency of the contact spring (Hz).
/// A body under a load F sinks about F/(m·(2π·f)²) into what it touches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Contacts with fixed colliders (Hz, > 0; default 960: the drapemeter's rim holds a node
    /// within 0.2 mm).
    #[serde(default = "default_fixed_hz")]
    pub fixed_hz: f64,
    /// Contacts between moving bodies: cloth nodes with each other and with thrown balls (Hz,
    /// > 0; default 30, Rapier's own).
    #[serde(default = "default_moving_hz")]
    pub moving_hz: f64,
    /// Whether the links between nodes, not only the nodes, rest on the fixed colliders' edges
    /// (a drapemeter's rim, a table's edge), with the stiffness of `fixed_hz` (default false:
    /// the cloth leaves an edge at a node; implicit integrators only; `docs/model.md` §1,
    /// "Link support").
    #[serde(default)]
    pub link_support: bool,
}

impl ContactSpec {
    /// The settings Rapier's world is configured with.
    pub fn stiffness(&self) -> crate::bodies::ContactStiffness {
        crate::bodies::ContactStiffness {
            fixed_hz: self.fixed_hz,
            moving_hz: self.moving_hz,
        }
    }
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            fixed_hz: default_fixed_hz(),
            moving_hz: default_moving_hz(),
            link_support: false,
        }
    }
}

fn default_fixed_hz() -> f64 {
    crate::bodies::ContactStiffness::default().fixed_hz
}

fn default_moving_hz() -> f64 {
    crate::bodies::ContactStiffness::default().moving_hz
}

fn default_gravity() -> [f64; 3] {
    [0.0, -crate::material::STANDARD_GRAVITY, 0.0]
}

/// A fixed rigid collider.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSpec {
    /// Name used in messages and measurements (e.g. "disk", "table").
    pub name: String,
    /// Shape and size.
    pub shape: ColliderShape,
    /// Centre of the shape (m).
    pub centre_m: [f64; 3],
    /// Coulomb friction coefficient against the cloth (dimensionless, ≥ 0; default 0.5).
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Fixed in place (default), or a free rigid body thrown into the scene.
    #[serde(default)]
    pub motion: ColliderMotion,
}

/// Whether a collider stays put or moves as a rigid body.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum ColliderMotion {
    /// Fixed in the world (a disk, a table, the floor).
    #[default]
    Fixed,
    /// A dynamic rigid body under gravity, contact and friction, e.g. a ball thrown at the
    /// cloth. Only `Ball` shapes may move (the penetration check follows their centre).
    Dynamic {
        /// Mass (kg), > 0.
        mass_kg: f64,
        /// Initial velocity (m/s).
        velocity_m_per_s: [f64; 3],
    },
}

fn default_friction() -> f64 {
    0.5
}

/// Collider shapes, axis-aligned, +y up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ColliderShape {
    /// A vertical cylinder, e.g. a drapemeter disk.
    Cylinder {
        /// Radius (m).
        radius_m: f64,
        /// Half its height (m).
        half_height_m: f64,
    },
    /// A box, e.g. a table top or the floor.
    Cuboid {
        /// Half extents along x, y, z (m).
        half_extents_m: [f64; 3],
    },
    /// A sphere.
    Ball {
        /// Radius (m).
        radius_m: f64,
    },
}

/// The effects a scene asks for. Each effect that is off costs nothing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectsSpec {
    /// Gravity acts on the cloth (default true).
    #[serde(default = "yes")]
    pub gravity: bool,
    /// How warp and weft resist stretching.
    pub stretch: StretchModel,
    /// With `stretch: Constraint`, the in-plane modulus (N/m, in (0, 1e7]) of the one-sided
    /// spring that keeps rope-jointed links from shortening (`docs/model.md` §9): each link gets
    /// stiffness k = this value, whatever the spacing and step. Default: 100·π²·B/σ²
    /// (`forces::LinkCompression::default_modulus`), 100 times the Euler load of a strip one
    /// spacing long; an explicit step must stay below its limit (`kes-cloth check` prints it).
    #[serde(default)]
    pub compression_modulus_n_per_m: Option<f64>,
    /// KES bending M(K) along warp and weft (seed eq. 2).
    pub bending: bool,
    /// KES trellising F(φ) (seed eq. 3).
    pub trellising: bool,
    /// Contact with the colliders (default true).
    #[serde(default = "yes")]
    pub contact: bool,
    /// Friction in those contacts (default true; off sets μ = 0).
    #[serde(default = "yes")]
    pub friction: bool,
    /// The cloth's nodes collide with each other (default false).
    #[serde(default)]
    pub self_collision: bool,
    /// Damping of relative motion along and across links (default none).
    #[serde(default)]
    pub damping: Option<DampingSpec>,
    /// Aerodynamic drag against still air (default none).
    #[serde(default)]
    pub air_drag: Option<AirDragSpec>,
    /// Hysteresis (internal friction) of bending and shear from the fabric's 2HB, 2HG and 2HG5
    /// (default false: the elastic mean curves alone). Needs bending or trellising on.
    #[serde(default)]
    pub hysteresis: bool,
}

fn yes() -> bool {
    true
}

/// Damping of the cloth's internal motion.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Rate (1/s) at which the relative velocity of two linked nodes decays; acts only on
    /// motion inside the cloth, never on free fall.
    pub rate_per_s: f64,
}

/// Air drag on each node, against still air.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AirDragSpec {
    /// Linear drag coefficient per unit cloth area (N·s/m³): force = −c·σ²·v.
    pub coefficient_n_s_per_m3: f64,
}

/// Time stepping and stopping.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegrationSpec {
    /// Time step (s), > 0. With the explicit integrator our KES forces must be stable at this
    /// step (`docs/model.md` §7); the implicit one is stable at any step.
    pub dt_s: f64,
    /// How our forces are integrated over a step (default `Explicit`).
    #[serde(default)]
    pub integrator: IntegratorSpec,
    /// Settings of the implicit solve (ignored by `Explicit`).
    #[serde(default)]
    pub implicit_solver: ImplicitSolverSpec,
    /// Refuse an explicit step longer than the fabric's stability limit (default true;
    /// `docs/model.md` §10). Off only to study instability on purpose.
    #[serde(default = "yes")]
    pub step_guard: bool,
    /// Rapier solver iterations (substeps) per step, 1 to 64 (default 1). Our forces reach
    /// Rapier as a velocity kick before its step, so they stay symplectic at any count; each
    /// substep re-solves joints and contacts, which stiffens links and contacts and lets light
    /// nodes carry heavy bodies, at roughly n times Rapier's cost (`docs/rapier.md`).
    #[serde(default = "default_iterations")]
    pub solver_iterations: usize,
    /// PGS sweeps per substep, for joint and contact accuracy (default 4).
    #[serde(default = "default_pgs")]
    pub internal_pgs_iterations: usize,
    /// Simulated time after which the run stops, settled or not (s), > 0.
    pub max_time_s: f64,
    /// When the cloth counts as at rest.
    #[serde(default)]
    pub settle: SettleSpec,
    /// The step taken while the cloth is quiet (s; default 0: always `dt_s`), 0 to a fifth of
    /// `settle.hold_s` (the settle window's resolution): from the moment a settle window is
    /// quiet, through its confirmation and any creep watch, each step is this long; a
    /// confirmation that fails brings the step back to `dt_s` for the rest of the run. Applies
    /// only where the implicit solve holds the stretch (`Kes`, `Seed`) and the supports'
    /// friction: ignored by `Explicit` (whose step the fabric's stiffness bounds at rest too),
    /// with rope joints (`Constraint`) or `implicit_solver.friction: Some(false)`, and when not
    /// longer than `dt_s`. At rest
    /// the step only has to follow slow motion: the shipped drapes' 1/30 s leaves their DC and
    /// node count as at 1/240 s (`docs/model.md` §12, "The step at rest").
    #[serde(default)]
    pub rest_dt_s: f64,
}

/// How our forces are integrated over a step (`docs/model.md` §7 and §12).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum IntegratorSpec {
    /// Forces at the start of the step, as one velocity kick: cheapest per step, stable only
    /// below the fabric's explicit step limit (0.139 ms for thick cotton at 1 cm, set by the
    /// link compression spring).
    #[default]
    Explicit,
    /// Linearly implicit backward Euler (Baraff & Witkin): stable at the step contact needs;
    /// adds numerical damping that grows with the step.
    Implicit,
    /// The same solve as `Implicit`, stepped by the second-order BDF2 formula: as stable, with
    /// far less numerical damping of slow motion (a 10 Hz mode at 1/240 s keeps 98 % of its
    /// amplitude over a period against 45 %; `docs/model.md` §12, "BDF2").
    Bdf2,
}

/// Conjugate-gradient settings of the implicit solve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImplicitSolverSpec {
    /// Most matrix products per step (default 200; thick cotton at 1/240 s takes 34 on average
    /// at 1 cm, 88 at 5 mm).
    pub max_iterations: usize,
    /// Relative residual at which a solve stops, in the norm of the preconditioner in use
    /// (dimensionless; default 0.001).
    pub tolerance: f64,
    /// Mass-weighted RMS velocity error at which a solve stops whatever its relative residual
    /// (m/s; default 3e-6; 0 for none): near rest the right-hand side nearly vanishes and the
    /// relative rule alone chases it.
    pub velocity_tolerance_m_per_s: f64,
    /// Coulomb friction of the supports inside the solve: supported nodes held while their
    /// surface's friction can hold them, dragged at μ times the normal impulse when they slide
    /// (`docs/model.md` §12). Default (absent): on when stretch is in the solve (`Kes`,
    /// `Seed`), off with rope joints (`Constraint`), which the solve does not see; there
    /// Rapier's contact applies all friction.
    pub friction: Option<bool>,
    /// The conjugate gradients' preconditioner (`docs/model.md` §12, "Preconditioners"):
    /// `Auto` (default: block Jacobi below 5,000 nodes, two-level from there on), `BlockJacobi`
    /// (cheapest below about 2,000 nodes), `TwoLevel(coarsening: 4)` (thread lines plus a
    /// correction on a lattice 4 times coarser: its products do not grow with the lattice;
    /// thick cotton at 2.5 mm settles in a third of block Jacobi's wall time), `ThreadLines`, or
    /// `Cholesky(refactor_above: K)` (a sparse factor of the whole system; slower than block
    /// Jacobi at every size measured).
    pub preconditioner: crate::implicit::Preconditioner,
    /// When a node held by the supports' static friction, whose impulse leaves the friction
    /// cone, starts to slide: `SameStep` (default: the step is solved again with it sliding)
    /// or `NextStep` (from the next step: one solve a step, each cheaper; from the smooth start
    /// the drapes agree to 0.004 in DC and rest comes no sooner, `docs/model.md` §12, "When a
    /// hold gives way").
    pub friction_release: crate::implicit::FrictionRelease,
}

impl Default for ImplicitSolverSpec {
    fn default() -> Self {
        let d = crate::implicit::ImplicitSettings::default();
        Self {
            max_iterations: d.max_iterations,
            tolerance: d.tolerance,
            velocity_tolerance_m_per_s: d.velocity_tolerance,
            friction: d.friction,
            preconditioner: d.preconditioner,
            friction_release: d.friction_release,
        }
    }
}

fn default_iterations() -> usize {
    1
}

fn default_pgs() -> usize {
    4
}

/// The settle criterion: over a window of `hold_s`, no node travels further than
/// `max_speed_m_per_s × hold_s` (see `measure/settle.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SettleSpec {
    /// Mean speed over the window below which every node counts as at rest (m/s; default 0.001).
    pub max_speed_m_per_s: f64,
    /// Window length (s; default 0.5).
    pub hold_s: f64,
    /// Ignore the first part of the run (s; default 0.2), while the cloth has not yet moved.
    #[serde(default = "default_min_time")]
    pub min_time_s: f64,
    /// After settling, keep simulating this long (s; default 0, no check) and report how far
    /// the nodes and the cloth's centroid still move (`creep_*` in `metrics.json`): rest, not a
    /// slow slide, is what a drape test measures.
    #[serde(default)]
    pub creep_check_s: f64,
    /// After a quiet window, watch this long (s; default 0, no watch) before calling the cloth
    /// settled: if a node then travels further than a quiet window allows (`max_speed_m_per_s ×
    /// hold_s`), the window was a slow passage through a shape that is not at rest, and
    /// settling starts again (`settle_restarts` in `metrics.json`).
    #[serde(default)]
    pub confirm_s: f64,
}

fn default_min_time() -> f64 {
    0.2
}

impl Default for SettleSpec {
    fn default() -> Self {
        Self {
            max_speed_m_per_s: 0.001,
            hold_s: 0.5,
            min_time_s: default_min_time(),
            creep_check_s: 0.0,
            confirm_s: 0.0,
        }
    }
}

/// Output files.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// Write `final.obj` (default true).
    #[serde(default = "yes")]
    pub mesh_obj: bool,
    /// Write `top.png` (default true).
    #[serde(default = "yes")]
    pub top_png: bool,
    /// Width and height of `top.png`, width of `side.png` (pixels; default 800).
    #[serde(default = "default_image_size")]
    pub image_size_px: u32,
    /// Write `side.png`, `final.glb` and `report.html`, the page with the numbers, the
    /// pictures, a 3D view and the fabric (default true).
    #[serde(default = "yes")]
    pub report: bool,
}

fn default_image_size() -> u32 {
    800
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            mesh_obj: true,
            top_png: true,
            image_size_px: default_image_size(),
            report: true,
        }
    }
}
