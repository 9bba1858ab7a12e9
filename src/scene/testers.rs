//! The standard drape testers, built in: a scene for any fabric file on any of them, with the
//! numerical settings the shipped scenes use, chosen from the fabric.
//!
//! Each tester is one of the shipped scene files (compiled into the binary) with the fabric,
//! the specimen and the numerical settings replaced:
//!
//! - spacing, on the drapemeters: the coarsest of 2.5, 1.875 and 1.25 mm that is at most a
//!   sixth of the fabric's shorter bending length c = (B/W)^(1/3). Where the lattice meets the
//!   rim moves a drape by more than 0.01 in DC while the spacing is a quarter of c (thin wool,
//!   c = 1.53 cm, at 3.75 mm: ± 0.012–0.014 over placements) and by ± 0.003–0.004 from a sixth
//!   down (thin wool at 2.5 mm); and a stiff fabric's drape rises with refinement by a term at
//!   the rim of first order, 0.003–0.004 in DC a millimetre of spacing for thick cotton
//!   (c = 2.71 cm), which leaves 3.75 mm 0.012–0.015 below its limit and 2.5 mm within 0.01
//!   (`docs/accuracy.md`). So both shipped fabrics get 2.5 mm. Thin wool's drape on the
//!   Cusick tester is not converged there (0.364 with 9–10 nodes at 2.5 mm, 0.379 with 10–11 at
//!   1.875 mm over four placements). The tablecloth keeps its scene's
//!   3.33 mm, a thirtieth of the table's half-width, so that the table's edge lies on a row of
//!   nodes (its corner hang then lies within 1 % of its limit for both fabrics);
//! - step and integration: the template's (BDF2 at 1/240 s, the KES tensile law), which no
//!   stability limit ties to the spacing.

use std::path::{Path, PathBuf};

use super::{Scene, SceneError};
use crate::material::{Fabric, Thread};

/// A built-in drape tester.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tester {
    /// The seed's drapemeter (Horiba & Shimizu, Fig. 3): a 10 in (25.4 cm) circular specimen
    /// on a 5 in (12.7 cm) disk.
    Seed,
    /// Cusick tester (BS 5058 / ISO 9073-9): a 24 cm specimen on the 18 cm disk.
    Cusick24,
    /// Cusick tester: a 30 cm specimen on the 18 cm disk.
    Cusick30,
    /// Cusick tester: a 36 cm specimen on the 18 cm disk.
    Cusick36,
    /// The seed's tablecloth: a 40 cm × 40 cm square on a 20 cm × 20 cm table.
    Tablecloth,
}

/// Spacings (m) a drapemeter may use, coarsest first: none coarser than 2.5 mm, where thick
/// cotton's rim term (0.003–0.004 in DC a millimetre) stays within 0.01 of the limit.
const SPACINGS: [f64; 3] = [0.0025, 0.001875, 0.00125];

/// The largest spacing a drapemeter allows, as a fraction of the fabric's shorter bending length.
const SPACING_PER_BENDING_LENGTH: f64 = 1.0 / 6.0;

/// The tablecloth's spacing (m), whatever the fabric: a thirtieth of the table's 10 cm
/// half-width, so that the table's edge lies on a row of nodes (3.33 mm; `docs/accuracy.md`).
const TABLECLOTH_SPACING: f64 = 0.1 / 30.0;

impl Tester {
    /// Every tester, in the order `--help` lists them.
    pub const ALL: [Tester; 5] = [
        Tester::Seed,
        Tester::Cusick24,
        Tester::Cusick30,
        Tester::Cusick36,
        Tester::Tablecloth,
    ];

    /// The tester's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Tester::Seed => "seed",
            Tester::Cusick24 => "cusick-24",
            Tester::Cusick30 => "cusick-30",
            Tester::Cusick36 => "cusick-36",
            Tester::Tablecloth => "tablecloth",
        }
    }

    /// The shipped scene the tester is built from (its path in the repository, and its text).
    fn template(self) -> (&'static str, &'static str) {
        match self {
            Tester::Seed => (
                "scenes/drape_wool.ron",
                include_str!("../../scenes/drape_wool.ron"),
            ),
            Tester::Cusick24 | Tester::Cusick30 | Tester::Cusick36 => (
                "scenes/cusick_wool.ron",
                include_str!("../../scenes/cusick_wool.ron"),
            ),
            Tester::Tablecloth => (
                "scenes/tablecloth_wool.ron",
                include_str!("../../scenes/tablecloth_wool.ron"),
            ),
        }
    }

    /// The spacing (m) the tester keeps whatever the fabric; `None`: chosen from the fabric.
    fn fixed_spacing(self) -> Option<f64> {
        (self == Tester::Tablecloth).then_some(TABLECLOTH_SPACING)
    }

    /// The specimen, where it differs from the template's.
    fn specimen(self) -> Option<&'static str> {
        match self {
            Tester::Cusick24 => Some("cloth.shape=Circle(diameter_m: 0.24)"),
            Tester::Cusick36 => Some("cloth.shape=Circle(diameter_m: 0.36)"),
            _ => None,
        }
    }
}

/// The spacing (m) `tester` uses for `fabric` (module docs).
pub fn tester_spacing(tester: Tester, fabric: &Fabric) -> f64 {
    let c = fabric
        .bending_length(Thread::Warp)
        .min(fabric.bending_length(Thread::Weft));
    tester.fixed_spacing().unwrap_or_else(|| {
        SPACINGS
            .iter()
            .copied()
            .find(|s| *s <= c * SPACING_PER_BENDING_LENGTH * (1.0 + 1e-9))
            .unwrap_or(SPACINGS[SPACINGS.len() - 1])
    })
}

/// The scene of `fabric_file` on `tester`, named `<tester>-<fabric file stem>`, with the
/// testers' settings for that fabric, then `overrides` (`--set`) applied.
pub fn tester_scene(tester: Tester, fabric_file: &Path, overrides: &[String]) -> Result<Scene, SceneError> {
    let (template_path, text) = tester.template();
    let origin = PathBuf::from(format!("{template_path} (tester {})", tester.name()));
    let absolute = std::path::absolute(fabric_file).unwrap_or_else(|_| fabric_file.to_path_buf());
    let stem = fabric_file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("fabric");
    let mut set = vec![
        format!("fabric=File({:?})", absolute.display().to_string()),
        format!("name={:?}", format!("{}-{stem}", tester.name())),
    ];
    set.extend(tester.specimen().map(str::to_string));
    // First as the template is, to read the fabric.
    let scene = Scene::from_text(text, origin.clone(), &set)?;
    set.push(format!(
        "cloth.spacing_m={}",
        tester_spacing(tester, &scene.fabric)
    ));
    set.extend(overrides.iter().cloned());
    Scene::from_text(text, origin, &set)
}
