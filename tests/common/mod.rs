//! Helpers shared by the integration tests: shipped fabrics, grids and a tiny seeded RNG.
#![allow(dead_code)]

use std::path::PathBuf;

use glam::DVec3;
use kes_cloth::material::Fabric;

/// Path of a file in the crate.
pub fn crate_path(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// A shipped fabric by file stem, e.g. `"thick_cotton"`.
pub fn shipped_fabric(stem: &str) -> Fabric {
    Fabric::load(crate_path(&format!("assets/fabrics/{stem}.ron"))).expect("shipped fabric loads")
}

/// Every shipped fabric file.
pub fn shipped_fabric_paths() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(crate_path("assets/fabrics"))
        .expect("assets/fabrics exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    paths.sort();
    paths
}

/// xorshift64*: deterministic randomness without a dependency.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [-1, 1).
    pub fn signed(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
    pub fn vec(&mut self, scale: f64) -> DVec3 {
        DVec3::new(self.signed(), self.signed(), self.signed()) * scale
    }
}

/// The `// expect: ...` lines of a bad input file: fragments its rejection message must hold.
pub fn expect_lines(path: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("bad input file is readable");
    text.lines()
        .filter_map(|l| l.strip_prefix("// expect: "))
        .map(String::from)
        .collect()
}

/// The message of a load that must fail without panicking.
pub fn rejection_message<T, E: std::fmt::Display>(
    path: &std::path::Path,
    load: impl FnOnce() -> Result<T, E> + std::panic::UnwindSafe,
) -> String {
    match std::panic::catch_unwind(load) {
        Ok(Err(e)) => e.to_string(),
        Ok(Ok(_)) => panic!("{} was accepted", path.display()),
        Err(_) => panic!("{} made the loader panic", path.display()),
    }
}
