//! The grid of a study: `--vary KEY=V1,V2,...` options and their cartesian product.

use std::str::FromStr;

/// One varied scene field and the values it takes.
#[derive(Clone, Debug, PartialEq)]
pub struct Vary {
    /// The field's path, as for `--set` (e.g. `integration.dt_s`).
    pub key: String,
    /// Its values, as written after `=` (numbers, words such as `Implicit`, JSON).
    pub values: Vec<String>,
}

impl FromStr for Vary {
    type Err = String;

    /// Parses `KEY=V1,V2,...`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (key, list) = s
            .split_once('=')
            .ok_or_else(|| format!("`{s}`: expected KEY=V1,V2,..., e.g. integration.dt_s=0.0005,0.00025"))?;
        let values: Vec<String> = list
            .split(',')
            .map(|v| v.trim().to_string())
            .filter(|v| !v.is_empty())
            .collect();
        if key.trim().is_empty() || values.is_empty() {
            return Err(format!("`{s}`: needs a key and at least one value"));
        }
        Ok(Self {
            key: key.trim().to_string(),
            values,
        })
    }
}

/// What a study varies and what it compares against.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StudyPlan {
    /// The varied keys; the grid is their cartesian product.
    pub vary: Vec<Vary>,
    /// `KEY=VALUE` overrides that make the converged reference.
    pub reference: Vec<String>,
    /// Runs per grid point and for the reference (0 or 1: one run with the scene's seed and
    /// lattice). With N > 1, run k takes the k-th lattice placement of
    /// [`crate::repeat::placement_offset`] and seed k (the scene's seed with a `Smooth` start
    /// roughness), and each row reports the mean over the N runs: a single run at 1 cm scatters
    /// by ±0.02 in DC from where the grid falls alone.
    pub placements: usize,
}

impl StudyPlan {
    /// Every grid point as (key, value) pairs, the last key varying fastest.
    pub fn settings(&self) -> Vec<Vec<(String, String)>> {
        let mut grid: Vec<Vec<(String, String)>> = vec![Vec::new()];
        for vary in &self.vary {
            grid = grid
                .into_iter()
                .flat_map(|point| {
                    vary.values.iter().map(move |v| {
                        let mut p = point.clone();
                        p.push((vary.key.clone(), v.clone()));
                        p
                    })
                })
                .collect();
        }
        grid
    }
}

/// Whether a `--set` value `raw` equals a scene field's current value (numbers compared to a
/// relative 1e-9, so `0.00025` matches `2.5e-4`).
pub(crate) fn same_value(current: Option<&serde_json::Value>, raw: &str) -> bool {
    let Some(current) = current else { return false };
    let given: serde_json::Value =
        serde_json::from_str(raw).unwrap_or_else(|_| serde_json::Value::String(raw.to_string()));
    match (current.as_f64(), given.as_f64()) {
        (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * a.abs().max(b.abs()),
        _ => *current == given,
    }
}
