//! Errors of turning KES values into a [`crate::material::Fabric`], and of loading fabric files.

use std::fmt;
use std::path::PathBuf;

/// An allowed interval for a physical value, printed like `(0, 100] gf·cm²/cm`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Allowed {
    /// Lower bound.
    pub low: f64,
    /// Whether the lower bound itself is allowed.
    pub low_inclusive: bool,
    /// Upper bound.
    pub high: f64,
    /// Whether the upper bound itself is allowed.
    pub high_inclusive: bool,
    /// Unit of the bounds, as written in the file.
    pub unit: &'static str,
}

impl Allowed {
    /// (0, high]: strictly positive, at most `high`.
    pub const fn positive(high: f64, unit: &'static str) -> Self {
        Self {
            low: 0.0,
            low_inclusive: false,
            high,
            high_inclusive: true,
            unit,
        }
    }

    /// [0, high].
    pub const fn non_negative(high: f64, unit: &'static str) -> Self {
        Self {
            low: 0.0,
            low_inclusive: true,
            high,
            high_inclusive: true,
            unit,
        }
    }

    /// Whether `value` lies inside (NaN never does).
    pub fn contains(&self, value: f64) -> bool {
        let above = if self.low_inclusive {
            value >= self.low
        } else {
            value > self.low
        };
        let below = if self.high_inclusive {
            value <= self.high
        } else {
            value < self.high
        };
        above && below
    }
}

impl fmt::Display for Allowed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}{}, {}{}{}{}",
            if self.low_inclusive { "[" } else { "(" },
            self.low,
            self.high,
            if self.high_inclusive { "]" } else { ")" },
            if self.unit.is_empty() { "" } else { " " },
            self.unit
        )
    }
}

/// A KES value that is physically invalid, naming the field (as a path in the fabric file).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("field `{field}` = {value}: {reason}")]
pub struct InvalidFabric {
    /// Path of the field in the fabric file, e.g. `bending.warp.b`.
    pub field: String,
    /// The offending value as written.
    pub value: String,
    /// What is allowed, e.g. "must lie in (0, 100] gf·cm²/cm (B, bending rigidity)".
    pub reason: String,
}

/// Loading a fabric file failed.
#[derive(Debug, thiserror::Error)]
pub enum FabricLoadError {
    /// The file could not be read.
    #[error("{}: cannot read fabric file: {source}", path.display())]
    Io {
        /// The fabric file.
        path: PathBuf,
        /// The I/O failure.
        source: std::io::Error,
    },
    /// The file is not valid RON for the fabric schema (syntax, unknown or missing field).
    #[error("{}:{line}:{column}: {message}", path.display())]
    Syntax {
        /// The fabric file.
        path: PathBuf,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// The parser's description, naming the field where it knows it.
        message: String,
    },
    /// The file parsed but a value is physically invalid.
    #[error("{}: {source}", path.display())]
    Invalid {
        /// The fabric file.
        path: PathBuf,
        /// Which field and why.
        source: InvalidFabric,
    },
}
