//! The batches kes-cloth plans: a work–precision study, a convergence study, repeats.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{BatchError, Manifest, read_manifest};
use crate::repeat::{RepeatLayout, Repeats, collect_repeats};
use crate::study::{Convergence, ConvergenceLayout, Study, StudyLayout, collect_convergence, collect_study};

/// What a batch folder holds: the layout its manifest records.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum BatchLayout {
    /// A work–precision study (`kes-cloth study`).
    Study(StudyLayout),
    /// A convergence study (`kes-cloth converge`).
    Converge(ConvergenceLayout),
    /// Repeats of one scene over seeds and placements (`kes-cloth run --repeat`).
    Repeat(RepeatLayout),
}

/// A batch's results, combined.
#[derive(Clone, Debug)]
pub enum Collected {
    /// A study.
    Study(Box<Study>),
    /// A convergence study.
    Converge(Convergence),
    /// Repeats.
    Repeat(Box<Repeats>),
}

impl Collected {
    /// Tasks without a result yet.
    pub fn missing(&self) -> &[usize] {
        match self {
            Self::Study(s) => &s.missing,
            Self::Converge(_) => &[],
            Self::Repeat(r) => &r.missing,
        }
    }
}

/// Collects the batch in `dir` from whatever tasks have finished (`kes-cloth collect DIR`).
pub fn collect(dir: &Path) -> Result<Collected, BatchError> {
    let manifest: Manifest<BatchLayout> = read_manifest(dir)?;
    let part = manifest.clone();
    Ok(match manifest.layout {
        BatchLayout::Study(layout) => Collected::Study(Box::new(collect_study(dir, &part.map(|_| layout))?)),
        BatchLayout::Converge(layout) => {
            Collected::Converge(collect_convergence(dir, &part.map(|_| layout))?)
        }
        BatchLayout::Repeat(layout) => {
            Collected::Repeat(Box::new(collect_repeats(dir, &part.map(|_| layout))?))
        }
    })
}
