//! A single run's numerical error, estimated from a companion run of the same scene on a
//! coarser lattice.
//!
//! A run at spacing σ measures f(σ); the companion, identical but for its spacing rσ, measures
//! f(rσ). With an error of order p, f(σ) − f(0) ≈ (f(rσ) − f(σ))/(rᵖ − 1). kes-cloth takes
//! p = 1, the order its drapes show (`docs/accuracy.md` §4), which overstates the error of a
//! quantity that converges faster (three times for a second-order one at r = 1.5). The estimate
//! also carries where each lattice happens to meet a circular outline (the placement scatter of
//! `docs/accuracy.md` §1a), since the two runs place their lattices differently: it is the
//! error of this one run, not of a mean over placements. `kes-cloth converge` measures the order
//! and extrapolates instead.

use serde::Serialize;

use crate::output::Metrics;
use crate::scene::{Scene, SceneError};

/// The order of convergence in σ assumed by the estimate.
pub const ASSUMED_ORDER: f64 = 1.0;

/// Companion ratios tried, in order.
const RATIOS: [f64; 3] = [1.5, 2.0, 3.0];

/// The companion's spacing over the run's: the first of 1.5, 2 and 3 at which every straight
/// support edge lies against the node rows as it does in the run ([`Scene::support_edges_on_rows`]:
/// a clamp's edge, a table's sides), 1.5 if none is. The cloth leaves such an edge at a row, so
/// a companion whose rows fall otherwise against it differs by where the lattice meets the edge,
/// not by its spacing alone (a table edge on a row at 5 mm lies between rows at 7.5 mm and on
/// one at 1 cm).
pub fn companion_ratio(scene: &Scene) -> f64 {
    let spacing = scene.spec.cloth.spacing_m;
    let run = scene.support_edges_on_rows(spacing);
    RATIOS
        .into_iter()
        .find(|r| scene.support_edges_on_rows(r * spacing) == run)
        .unwrap_or(RATIOS[0])
}

/// The same scene at spacing r·σ ([`companion_ratio`]), everything else (step, seed, lattice
/// offset, settle rule) unchanged.
pub fn companion_scene(scene: &Scene) -> Result<Scene, SceneError> {
    let mut spec = scene.spec.clone();
    spec.cloth.spacing_m *= companion_ratio(scene);
    Scene::from_spec(spec, scene.path.clone())
}

/// One measured quantity's estimate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Estimated {
    /// The companion run's value (same unit as the quantity).
    pub companion: f64,
    /// Estimated numerical error of the run's value, |f(σ) − f(rσ)|/(r^p − 1) (same unit).
    pub error: f64,
}

/// What the companion run gave, and the errors estimated from it. Units are in the keys.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct ErrorEstimate {
    /// The companion's spacing (m).
    pub companion_spacing_m: f64,
    /// The companion's spacing over the run's.
    pub ratio: f64,
    /// The order p assumed ([`ASSUMED_ORDER`]).
    pub assumed_order: f64,
    /// Whether the companion settled (its values are provisional otherwise).
    pub companion_settled: bool,
    /// Drape coefficient (dimensionless).
    pub drape_coefficient: Option<Estimated>,
    /// The companion's node count (the run's is `nodes`).
    pub companion_nodes: Option<u32>,
    /// Tablecloths: mean corner hang (m).
    pub hang_corners_m: Option<Estimated>,
    /// The companion's skirt folds.
    pub companion_skirt_folds: Option<u32>,
    /// Cantilever chord (degrees).
    pub cantilever_chord_deg: Option<Estimated>,
    /// Why there is no estimate, if the companion failed (diverged or was interrupted).
    pub companion_failure: Option<String>,
}

impl ErrorEstimate {
    /// No estimate: the companion at `companion_spacing_m` (m), `ratio` times the run's spacing,
    /// could not be run, for the reason `why`.
    pub fn not_run(companion_spacing_m: f64, ratio: f64, why: String) -> Self {
        Self {
            companion_spacing_m,
            ratio,
            assumed_order: ASSUMED_ORDER,
            companion_settled: false,
            drape_coefficient: None,
            companion_nodes: None,
            hang_corners_m: None,
            companion_skirt_folds: None,
            cantilever_chord_deg: None,
            companion_failure: Some(why),
        }
    }

    /// The estimate from the run's metrics and its companion's, at ratio `ratio`.
    pub fn from_runs(run: &Metrics, companion: &Metrics, ratio: f64) -> Self {
        let factor = 1.0 / (ratio.powf(ASSUMED_ORDER) - 1.0);
        let failure = match (&companion.failure, companion.interrupted) {
            (Some(f), _) => Some(format!(
                "the companion run diverged at step {} ({})",
                f.step, f.effect
            )),
            (None, true) => Some("the companion run was interrupted".to_string()),
            _ => None,
        };
        let usable = failure.is_none();
        let pair = |f: fn(&Metrics) -> Option<f64>| match (f(run), f(companion)) {
            (Some(a), Some(b)) if usable => Some(Estimated {
                companion: b,
                error: (a - b).abs() * factor,
            }),
            _ => None,
        };
        Self {
            companion_spacing_m: companion.spacing_m,
            ratio,
            assumed_order: ASSUMED_ORDER,
            companion_settled: companion.settled,
            drape_coefficient: pair(|m| m.drape_coefficient),
            companion_nodes: companion.nodes.filter(|_| usable),
            hang_corners_m: pair(|m| m.hang_corners_m),
            companion_skirt_folds: companion.skirt_folds.filter(|_| usable),
            cantilever_chord_deg: pair(|m| m.cantilever_chord_deg),
            companion_failure: failure,
        }
    }
}

/// Whether the scene measures anything an error can be estimated for.
pub fn measures_something(scene: &Scene) -> bool {
    scene.spec.measure != crate::scene::MeasureSpec::None
}
