//! The study's measures: shape error against a known surface, the grid, default detection.

use glam::DVec3;
use kes_cloth::forces::ClothTopology;
use kes_cloth::study::{ReferenceSurface, Refusal, StudyPlan, Vary};

mod common;

/// A plan varying only the step over `steps`, against a 0.125 ms reference.
fn step_plan(steps: &str, placements: usize) -> StudyPlan {
    StudyPlan {
        vary: vec![format!("integration.dt_s={steps}").parse::<Vary>().unwrap()],
        reference: vec!["integration.dt_s=0.000125".into()],
        placements,
    }
}

/// `drape_wool`, explicit, at 1 cm and 0.25 ms, a coarse setting these studies are sized for, and a short
/// run of `max_time_s` seconds.
fn wool_at_1cm(max_time_s: f64) -> Vec<String> {
    let mut sets = common::explicit_drape("wool");
    sets.extend([
        "cloth.spacing_m=0.01".to_string(),
        "integration.dt_s=0.00025".to_string(),
        format!("integration.max_time_s={max_time_s}"),
    ]);
    sets
}

/// Numbers the batch folders of this file's studies.
static STUDIES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Runs `plan` on `drape_wool` at 1 cm for `max_time_s` seconds, on two threads.
fn wool_study(plan: &StudyPlan, max_time_s: f64) -> kes_cloth::study::Study {
    let scene = common::crate_path("scenes/drape_wool.ron");
    let dir = common::fresh_dir(&format!(
        "study-{}",
        STUDIES.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    ));
    kes_cloth::study::run_study(&scene, &wool_at_1cm(max_time_s), plan, &dir, 2, |_, _| {}).unwrap()
}

/// Writes `study` into a fresh temporary folder named after `tag` and returns its `study.md`
/// and `study.csv`, removing the folder again.
fn written(study: &kes_cloth::study::Study, tag: &str) -> (String, String) {
    let dir = std::env::temp_dir().join(format!("kes-cloth-study-{tag}-{}", std::process::id()));
    kes_cloth::study::write_study(study, &dir).unwrap();
    let md = std::fs::read_to_string(dir.join("study.md")).unwrap();
    let csv = std::fs::read_to_string(dir.join("study.csv")).unwrap();
    assert!(dir.join("work_precision.png").exists());
    let report = std::fs::read_to_string(dir.join("report.html")).expect("the study's report");
    assert!(report.contains("<img src=\"work_precision.png\""), "{report}");
    std::fs::remove_dir_all(&dir).ok();
    (md, csv)
}

/// Points 1 mm above a flat reference sheet (inside its outline) are 1 mm from it (f32
/// geometry: 1e-6 relative); the sheet's own nodes are at distance 0.
#[test]
fn shape_error_of_an_offset_sheet_is_the_offset() {
    let topo = ClothTopology::rectangle(11, 11, 0.01);
    let flat = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    let surface = ReferenceSurface::new(&topo, &flat).unwrap();
    assert!(surface.rms_distance(&flat) < 1e-7);
    let raised: Vec<DVec3> = flat.iter().map(|p| *p + DVec3::new(0.0, 0.001, 0.0)).collect();
    let e = surface.rms_distance(&raised);
    assert!((e - 0.001).abs() < 1e-6, "RMS distance {e} m, expected 0.001 m");
}

#[test]
fn the_grid_is_the_product_of_the_varied_values() {
    let plan = StudyPlan {
        vary: vec![
            "cloth.spacing_m=0.01,0.0075".parse::<Vary>().unwrap(),
            "integration.dt_s=0.00035,0.00025,0.000125"
                .parse::<Vary>()
                .unwrap(),
        ],
        reference: vec![],
        placements: 1,
    };
    let grid = plan.settings();
    assert_eq!(grid.len(), 6);
    assert_eq!(grid[1][1].1, "0.00025");
    assert_eq!(grid[3][0].1, "0.0075");
    assert!("integration.dt_s".parse::<Vary>().is_err());
    assert!("integration.dt_s=".parse::<Vary>().is_err());
}

/// A two-point study of a short drop: both runs and the reference are run (the reference is
/// not one of the grid points), the scene's own step is marked as the default, and the three
/// files are written with one CSV row per grid point.
#[test]
fn a_small_study_writes_its_table_and_diagram() {
    let scene = common::crate_path("scenes/drape_wool.ron");
    let plan = step_plan("0.00035,0.00025", 1);
    let base = wool_at_1cm(0.1);
    let study = kes_cloth::study::run_study(
        &scene,
        &base,
        &plan,
        &common::fresh_dir("study-small"),
        2,
        |_, _| {},
    )
    .unwrap();
    assert_eq!(study.rows.len(), 2);
    assert!(!study.rows[0].is_default && study.rows[1].is_default);
    assert!((study.reference.as_ref().unwrap().dt_s - 0.000125).abs() < 1e-12);
    for row in &study.rows {
        let e = row.shape_error_m.expect("shape error measured");
        // After 0.1 s the cloth has only fallen onto the disk: the runs differ by far less than
        // a node spacing from the reference.
        assert!(e.is_finite() && e < 0.01, "shape error {e} m");
    }
    let (_, csv) = written(&study, "test");
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .starts_with("integration.dt_s,particles")
    );
}

/// A tablecloth has no drape coefficient: its study measures how low the corners hang against
/// the reference, in the table and on the diagram, next to the shape error.
#[test]
fn a_tablecloth_study_reports_the_corner_hang_error() {
    let scene = common::crate_path("scenes/tablecloth_wool.ron");
    let plan = step_plan("0.00035,0.00025", 1);
    // At 1 cm (1,681 nodes; the table's edge lies on a row there too): a study's plumbing does
    // not need the shipped lattice.
    let base = ["cloth.spacing_m=0.01", "integration.max_time_s=0.15"]
        .map(String::from)
        .to_vec();
    let study = kes_cloth::study::run_study(
        &scene,
        &base,
        &plan,
        &common::fresh_dir("study-table"),
        2,
        |_, _| {},
    )
    .unwrap();
    for row in &study.rows {
        assert!(row.dc_error.is_none());
        let e = row.hang_error_m.expect("hang error measured");
        // 0.15 s into the fall the three runs differ by millimetres, not by the 40 cm cloth.
        assert!(e.is_finite() && e < 0.02, "hang error {e} m");
    }
    let (md, csv) = written(&study, "table");
    assert!(
        md.contains("corner hang (mm) | skirt folds | hang error (mm)"),
        "{md}"
    );
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .contains("hang_corners_m,skirt_folds,hang_error_m")
    );
}

/// With placements, every grid point and the reference run N times (seed k, lattice placement k)
/// and the table reports means with their spread; a rectangle, whose lattice fills its outline,
/// cannot be placed and is refused with the field named.
#[test]
fn a_study_over_placements_runs_each_point_n_times_and_reports_the_spread() {
    let plan = step_plan("0.00025", 3);
    let base = wool_at_1cm(0.05);
    let total = std::sync::atomic::AtomicUsize::new(0);
    let scene = common::crate_path("scenes/drape_wool.ron");
    let study = kes_cloth::study::run_study(
        &scene,
        &base,
        &plan,
        &common::fresh_dir("study-placed"),
        2,
        |_, t| total.store(t, std::sync::atomic::Ordering::Relaxed),
    )
    .unwrap();
    assert_eq!(
        total.into_inner(),
        6,
        "two points (grid and reference) × three placements"
    );
    assert_eq!(study.placements, 3);
    assert!(study.rows[0].dc_std.is_some() && study.reference_dc_std.is_some());
    let (md, _) = written(&study, "placed");
    assert!(md.contains("means over 3 runs") && md.contains(" ± "), "{md}");

    let table = common::crate_path("scenes/tablecloth_wool.ron");
    let Err(err) = kes_cloth::study::run_study(
        &table,
        &base,
        &plan,
        &common::fresh_dir("study-rectangle"),
        2,
        |_, _| {},
    ) else {
        panic!("a rectangle cannot be placed");
    };
    assert!(err.to_string().contains("circular cloths"), "{err}");
}

/// A grid point whose explicit step the stability guard refuses is reported, not run, and the
/// rest of the study goes on (thin wool at 1 cm: link compression allows 0.388 ms).
#[test]
fn a_study_skips_and_reports_steps_the_guard_refuses() {
    let plan = step_plan("0.0005,0.00025", 1);
    let study = wool_study(&plan, 0.05);
    assert_eq!(study.rows.len(), 1);
    assert_eq!(study.rows[0].setting[0].1, "0.00025");
    assert_eq!(study.refused.len(), 1);
    let Refusal::StepTooLong { effect, max_step_s } = study.refused[0].why.clone() else {
        panic!("{:?}", study.refused[0]);
    };
    assert_eq!(effect, "compression");
    assert!((max_step_s - 3.877e-4).abs() < 0.01e-4);
    let (md, _) = written(&study, "refused");
    assert!(
        md.contains("refused by the stability guard") && md.contains("0.0005"),
        "{md}"
    );
    // Nothing left to run is an error that lists what was refused, not an empty study.
    let (scene, base) = (common::crate_path("scenes/drape_wool.ron"), wool_at_1cm(0.05));
    let Err(err) = kes_cloth::study::run_study(
        &scene,
        &base,
        &step_plan("0.0005", 1),
        &common::fresh_dir("study-refused"),
        2,
        |_, _| {},
    ) else {
        panic!("a study with every point refused must fail");
    };
    assert!(err.to_string().contains("every grid point is refused"), "{err}");
}

/// Regression (a study putting the explicit and the implicit integrator on one grid stopped at
/// its first point: explicit damping of 150/s is invalid at 1/240 s, which only the implicit
/// points can take): such a point is listed with the field and its range, the others run.
#[test]
fn a_study_lists_points_another_rule_refuses_and_runs_the_rest() {
    let plan = StudyPlan {
        vary: vec![
            "integration.dt_s=0.0041666667".parse::<Vary>().unwrap(),
            "integration.integrator=Explicit,Implicit"
                .parse::<Vary>()
                .unwrap(),
        ],
        reference: vec![
            "integration.dt_s=0.00025".into(),
            "integration.integrator=Explicit".into(),
        ],
        placements: 1,
    };
    let study = wool_study(&plan, 0.05);
    assert_eq!(study.rows.len(), 1);
    assert_eq!(study.rows[0].setting[1].1, "Implicit");
    assert_eq!(study.refused.len(), 1);
    let Refusal::Invalid { field, message } = &study.refused[0].why else {
        panic!("{:?}", study.refused[0]);
    };
    assert_eq!(field, "effects.damping.rate_per_s");
    assert!(message.contains("1/(4·dt)"), "{message}");
    let (md, _) = written(&study, "invalid");
    assert!(md.contains("effects.damping.rate_per_s"), "{md}");
}

/// Regression (a failed reference was not flagged): a reference that diverges (thin wool at
/// 1 ms with the guard off: link compression allows 0.388 ms) is named in `study.md`, and no
/// row gets an error against it.
#[test]
fn a_failed_reference_is_flagged_and_not_compared_with() {
    let plan = StudyPlan {
        vary: vec!["integration.dt_s=0.00025".parse::<Vary>().unwrap()],
        reference: vec![
            "integration.step_guard=false".into(),
            "integration.dt_s=0.001".into(),
        ],
        placements: 1,
    };
    let study = wool_study(&plan, 0.1);
    assert!(
        study.reference.as_ref().unwrap().failure.is_some(),
        "the reference was meant to diverge"
    );
    let row = &study.rows[0];
    assert!(row.metrics.failure.is_none());
    assert_eq!((row.dc_error, row.shape_error_m), (None, None));
    let (md, csv) = written(&study, "failed-reference");
    assert!(md.contains("The reference failed"), "{md}");
    assert!(!md.contains("Errors are against the reference"), "{md}");
    // The CSV says so too, and its error column is empty.
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let column = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    assert_eq!(column("dc_error"), "");
    assert_eq!(column("reference_failed"), "true");
}

/// Regression (a study of the clamped strip reported empty tablecloth columns): a cantilever
/// study compares chord angles, beside the heavy elastica's exact angle, and its chord error
/// against a 2.5 mm reference shrinks from 1 cm to 5 mm (the strip converges, `tests/cantilever.rs`).
#[test]
fn a_cantilever_study_compares_chord_angles() {
    let scene = common::crate_path("scenes/bending_length/cantilever_wool.ron");
    let plan = StudyPlan {
        vary: vec!["cloth.spacing_m=0.01,0.005".parse::<Vary>().unwrap()],
        reference: vec!["cloth.spacing_m=0.0025".into()],
        placements: 1,
    };
    let dir = common::fresh_dir("study-cantilever");
    let study = kes_cloth::study::run_study(&scene, &[], &plan, &dir, 2, |_, _| {}).unwrap();
    assert_eq!(study.measure(), kes_cloth::study::StudyMeasure::CantileverChord);
    let errors: Vec<f64> = study
        .rows
        .iter()
        .map(|r| r.chord_error_deg.expect("a chord error"))
        .collect();
    assert!(
        errors[1] < errors[0],
        "chord errors {errors:?} (deg) do not shrink with the spacing"
    );
    let (md, csv) = written(&study, "cantilever");
    assert!(md.contains("chord (°) | exact (°) | chord error (°)"), "{md}");
    assert!(csv.lines().next().unwrap().ends_with("chord_error_deg"), "{csv}");
}
