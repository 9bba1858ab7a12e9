//! Scenes: the RON schema, its validation, `--set` overrides, and spawning into a world.
//!
//! `scenes/*.ron` → [`SceneFile`] (schema, SI) → [`Scene`] (validated, fabric loaded) →
//! [`spawn`] (a bevy_ecs `World` holding the Rapier world and the cloth). The engine
//! (`forces`, `schedule`, `measure`) never sees RON.

mod describe;
mod field_location;
mod scene_error;
mod scene_file;
mod scene_overrides;
mod scene_validation;
pub mod spawn;
mod testers;

use std::path::{Path, PathBuf};

pub use describe::describe;
pub use scene_error::SceneError;
pub use scene_file::*;
pub use scene_validation::MAX_NODES;
pub use testers::{Tester, tester_scene, tester_spacing};

use crate::material::Fabric;

/// A validated scene, its fabric loaded and converted to SI.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file it came from (for messages).
    pub path: PathBuf,
    /// The validated description (SI).
    pub spec: SceneFile,
    /// The fabric, in SI.
    pub fabric: Fabric,
}

impl Scene {
    /// The current value of the field at `key` (a `--set` path, e.g. `integration.dt_s`), as
    /// JSON; `None` if there is no such field.
    pub fn field(&self, key: &str) -> Option<serde_json::Value> {
        scene_overrides::read(&self.spec, key)
    }

    /// Reads `path`, applies `--set` overrides in order, validates, and loads the fabric.
    pub fn load(path: impl AsRef<Path>, overrides: &[String]) -> Result<Self, SceneError> {
        let path = path.as_ref().to_path_buf();
        let text = std::fs::read_to_string(&path).map_err(|source| SceneError::Io {
            path: path.clone(),
            source,
        })?;
        Self::from_text(&text, path, overrides)
    }

    /// Parses scene text as if read from `path` (fabric files resolve against its folder).
    pub fn from_text(text: &str, path: PathBuf, overrides: &[String]) -> Result<Self, SceneError> {
        let mut spec: SceneFile = crate::ron_file::parse(text).map_err(|e| SceneError::Syntax {
            path: path.clone(),
            line: e.line,
            column: e.column,
            message: e.message,
        })?;
        for assignment in overrides {
            spec = scene_overrides::apply(&spec, assignment).map_err(|reason| SceneError::Override {
                path: path.clone(),
                assignment: assignment.clone(),
                reason,
            })?;
        }
        Self::from_spec(spec, path).map_err(|e| e.located(text, overrides))
    }

    /// Validates an already parsed scene.
    pub fn from_spec(spec: SceneFile, path: PathBuf) -> Result<Self, SceneError> {
        scene_validation::validate(&spec).map_err(|(field, value, reason)| SceneError::Invalid {
            path: path.clone(),
            at: None,
            field,
            value,
            reason,
        })?;
        let fabric = match &spec.fabric {
            FabricSource::File(file) => {
                let base = path.parent().unwrap_or(Path::new("."));
                Fabric::load(base.join(file))
            }
            FabricSource::Inline(kes) => {
                Fabric::from_kes(kes).map_err(|source| crate::material::FabricLoadError::Invalid {
                    path: path.clone(),
                    source,
                })
            }
        }
        .map_err(|source| SceneError::Fabric {
            path: path.clone(),
            source,
        })?;
        check_explicit_step(&spec, &fabric).map_err(|(limit, reason)| SceneError::StepTooLong {
            path: path.clone(),
            at: None,
            dt_s: spec.integration.dt_s,
            effect: limit.effect,
            max_step_s: limit.max_step,
            reason,
        })?;
        let scene = Self { path, spec, fabric };
        scene
            .check_pins()
            .map_err(|(field, value, reason)| SceneError::Invalid {
                path: scene.path.clone(),
                at: None,
                field,
                value,
                reason,
            })?;
        Ok(scene)
    }

    /// For each of `cloth.pins_m`, the index of the nearest node of the flat layout.
    pub fn pinned_nodes(&self) -> Vec<usize> {
        let (_, flat) = spawn::cloth_grid(self);
        self.spec
            .cloth
            .pins_m
            .iter()
            .map(|p| {
                let p = glam::DVec3::from_array(*p);
                (0..flat.len())
                    .min_by(|&a, &b| flat[a].distance(p).total_cmp(&flat[b].distance(p)))
                    .unwrap_or(0)
            })
            .collect()
    }

    /// Unit vector along the warp of the flat cloth.
    pub fn warp_direction(&self) -> glam::DVec3 {
        let angle = self.spec.cloth.warp_angle_deg.to_radians();
        glam::DVec3::new(angle.cos(), 0.0, -angle.sin())
    }

    /// The nodes `cloth.clamp_m` holds: those of the flat layout within that distance of the
    /// cloth's −warp end (none for 0).
    pub fn clamped_nodes(&self) -> Vec<usize> {
        let clamp = self.spec.cloth.clamp_m;
        if clamp <= 0.0 {
            return Vec::new();
        }
        let (_, flat) = spawn::cloth_grid(self);
        let warp = self.warp_direction();
        let along: Vec<f64> = flat.iter().map(|p| p.dot(warp)).collect();
        let start = along.iter().copied().fold(f64::INFINITY, f64::min);
        let tolerance = 1e-6 * self.spec.cloth.spacing_m;
        (0..flat.len())
            .filter(|&k| along[k] - start <= clamp + tolerance)
            .collect()
    }

    /// For each straight edge of a support the cloth may leave along a node row (the clamp's
    /// edge, at `cloth.clamp_m` along the warp; the four vertical sides of every fixed `Cuboid`
    /// collider), whether a row of nodes of the flat cloth at spacing `spacing` (m) lies on it
    /// (within a millionth of the spacing). Contact is node-only, so the cloth leaves such an
    /// edge at a row: on it, or up to a spacing beyond it.
    pub fn support_edges_on_rows(&self, spacing: f64) -> Vec<bool> {
        let mut spec = self.spec.clone();
        spec.cloth.spacing_m = spacing;
        let lattice = Scene {
            spec,
            fabric: self.fabric.clone(),
            path: self.path.clone(),
        };
        let (_, flat) = spawn::cloth_grid(&lattice);
        let tolerance = 1e-6 * spacing;
        let on_row = |axis: glam::DVec3, at: f64| flat.iter().any(|p| (p.dot(axis) - at).abs() <= tolerance);
        let mut edges = Vec::new();
        if self.spec.cloth.clamp_m > 0.0 {
            let warp = self.warp_direction();
            let start = flat.iter().map(|p| p.dot(warp)).fold(f64::INFINITY, f64::min);
            edges.push(on_row(warp, start + self.spec.cloth.clamp_m));
        }
        for c in &self.spec.world.colliders {
            if let (ColliderShape::Cuboid { half_extents_m: h }, ColliderMotion::Fixed) =
                (&c.shape, &c.motion)
            {
                for (axis, k) in [(glam::DVec3::X, 0), (glam::DVec3::Z, 2)] {
                    for side in [-1.0, 1.0] {
                        edges.push(on_row(axis, c.centre_m[k] + side * h[k]));
                    }
                }
            }
        }
        edges
    }

    fn check_pins(&self) -> Result<(), (String, String, String)> {
        let (_, flat) = spawn::cloth_grid(self);
        let sigma = self.spec.cloth.spacing_m;
        for (k, (p, node)) in self.spec.cloth.pins_m.iter().zip(self.pinned_nodes()).enumerate() {
            let d = flat
                .get(node)
                .map_or(f64::INFINITY, |n| n.distance(glam::DVec3::from_array(*p)));
            if d > sigma {
                return Err((
                    format!("cloth.pins_m[{k}]"),
                    format!("{p:?}"),
                    format!(
                        "must lie within one spacing ({sigma} m) of a node of the flat cloth; the nearest is {d:.4} m away"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Node contact radius (m): the scene's value or half the spacing.
    pub fn node_radius(&self) -> f64 {
        self.spec
            .cloth
            .node_radius_m
            .unwrap_or(self.spec.cloth.spacing_m / 2.0)
    }
}

/// The explicit step limit of every effect the scene asks for, tightest first
/// (`forces::step_limits`).
pub(crate) fn step_limits(spec: &SceneFile, fabric: &Fabric) -> Vec<crate::forces::StepLimit> {
    let fx = &spec.effects;
    let choice = crate::forces::EffectChoice {
        stretch: fx.stretch,
        compression_modulus: fx.compression_modulus_n_per_m,
        bending: fx.bending,
        trellising: fx.trellising,
        damping: None,
        air_drag: None,
        hysteresis: fx.hysteresis,
    };
    crate::forces::step_limits(fabric, spec.cloth.spacing_m, &choice, spec.cloth.node_mass)
}

/// The stability guard: an explicit step longer than the tightest limit of the scene's effects
/// (`forces::explicit_step_limits`) is refused, naming the effect and the step it needs.
fn check_explicit_step(spec: &SceneFile, fabric: &Fabric) -> Result<(), (crate::forces::StepLimit, String)> {
    let i = &spec.integration;
    if i.integrator != IntegratorSpec::Explicit || !i.step_guard {
        return Ok(());
    }
    match step_limits(spec, fabric).first() {
        Some(tightest) if i.dt_s > tightest.max_step => Err((
            *tightest,
            format!(
                "must lie in (0, {:.3e}] s: explicit {} of this fabric at σ = {} m is stable only \
                 below 1.6/ω = {:.3e} s (docs/model.md §10); use a smaller step, or \
                 `integration.integrator: Implicit`,{} or `integration.step_guard: false` to run it anyway",
                tightest.max_step,
                tightest.effect,
                spec.cloth.spacing_m,
                tightest.max_step,
                if tightest.effect == "compression" {
                    " or a softer `effects.compression_modulus_n_per_m` (docs/model.md §9),"
                } else {
                    ""
                }
            ),
        )),
        _ => Ok(()),
    }
}
