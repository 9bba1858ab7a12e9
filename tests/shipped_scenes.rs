//! Every shipped scene loads, runs to rest with finite values, and drapes as a cloth should:
//! resting on its disk or table and hanging around it, links nearly inextensible, no node
//! inside a collider, outputs written.
//!
//! A drape that settles: on the shipped drapemeter, Cusick and tablecloth scenes, both fabrics,
//! the cloth comes to rest within 5 s of simulated time (thick cotton) or its scene's budget
//! (thin wool) and then stays put: 5 more simulated seconds move no node more than 0.5 mm and
//! the cloth's centroid less than 0.5 mm (no creep, no slide-off); and at no step does a node
//! centre sit more than 0.5 mm inside the disk, the table or the floor. At the end, no node
//! moves faster than 1 mm/s over a step (measured from positions: Rapier's stored velocity of
//! a node resting on the rim reads 5–26 mm/s while the node stays put).
//! These are the bounds kes-cloth promises for a settled cloth; they are not loosened here.
//! Every shipped scene steps at 1/30 s once quiet (`integration.rest_dt_s`), so the
//! confirmation and the 5 s watch run at that step, as a user's run does (`tests/rest_step.rs`
//! compares it with the constant step).
//!
//! Every simulation runs once, in one pool: the four drapes with the 5 s watch after settling
//! serve both claims (the centred drapemeter runs, and thick cotton's centred Cusick run, also
//! serve as one of three lattice placements); the two tablecloths, also watched for 5 s, serve
//! their checks, the same rest bounds and the seed's claim on the table (cotton's skirt folds
//! less than wool's).

use std::sync::OnceLock;

use kes_cloth::repeat::simulate_all;
use kes_cloth::run::{RunOutcome, write_outputs};
use kes_cloth::scene::{Scene, describe};

mod common;

const SCENES: [&str; 6] = [
    "drape_wool",
    "drape_cotton",
    "cusick_wool",
    "cusick_cotton",
    "tablecloth_wool",
    "tablecloth_cotton",
];

#[test]
fn every_shipped_scene_is_listed_and_loads() {
    let mut found: Vec<String> = std::fs::read_dir(common::crate_path("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    found.sort();
    let mut listed: Vec<String> = SCENES.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed, "every file in scenes/ must be run by this test");
    for name in SCENES {
        let scene = Scene::load(common::crate_path(&format!("scenes/{name}.ron")), &[]).unwrap();
        assert_eq!(scene.spec.name, name);
        assert!(describe(&scene).contains("nodes"));
    }
}

/// The shipped-scene checks on a run of `scene`. `max_strain`: largest |link length/σ − 1|
/// allowed at rest; 3 % is "nearly inextensible" for stretch as a constraint (the table
/// corners, where four flaps meet, come closest).
fn check(scene: &Scene, outcome: &RunOutcome, max_strain: f64) {
    let name = &scene.spec.name;
    let m = &outcome.metrics;
    assert!(m.failure.is_none(), "{name}: {:?}", m.failure);
    assert!(m.settled, "{name}: did not settle in {} s", m.sim_time_s);
    assert!(
        outcome.positions.iter().all(|p| p.is_finite()),
        "{name}: non-finite node"
    );
    assert!(
        m.max_strain < max_strain,
        "{name}: max link strain {:.2} %",
        m.max_strain * 100.0
    );
    // Contact softness lets node centres (the cloth's mid-surface) sink about a millimetre
    // into the support; 2 mm is a fifth of the node spacing.
    assert!(
        m.max_penetration_m < 0.002,
        "{name}: node {:.2} mm inside a collider",
        m.max_penetration_m * 1e3
    );
    // Rests on its support: the centre node is at the top (y = 0) within 2 mm ...
    let centre = outcome
        .positions
        .iter()
        .min_by(|a, b| (a.x * a.x + a.z * a.z).total_cmp(&(b.x * b.x + b.z * b.z)))
        .unwrap();
    assert!(
        centre.y.abs() < 0.002,
        "{name}: centre node at y = {} m",
        centre.y
    );
    // ... and the overhang hangs down by at least 3 cm (overhangs are 6 to 18 cm).
    assert!(
        m.min_height_m < -0.03,
        "{name}: lowest node only at {} m",
        m.min_height_m
    );

    let dir = std::env::temp_dir().join(format!("kes-cloth-test-{name}"));
    write_outputs(scene, outcome, &dir).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "fabric",
        "particles",
        "steps",
        "sim_time_s",
        "wall_time_s",
        "settled",
        "settle_time_s",
        "max_strain",
        "min_height_m",
        "drape_coefficient",
        "nodes",
        "effects",
    ] {
        assert!(json.get(key).is_some(), "{name}: metrics.json lacks `{key}`");
    }
    assert_eq!(json["effects"]["bending"]["calls"], json["steps"]);
    let png = image::open(dir.join("top.png")).unwrap();
    assert_eq!(png.width(), scene.spec.output.image_size_px);
    let obj = std::fs::read_to_string(dir.join("final.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), m.particles);
}

#[test]
fn drape_wool_settles_on_the_disk() {
    let (scene, outcome) = settled_drape("drape_wool");
    check(scene, outcome, 0.03);
}

#[test]
fn drape_cotton_settles_on_the_disk() {
    let (scene, outcome) = settled_drape("drape_cotton");
    check(scene, outcome, 0.03);
}

#[test]
fn cusick_wool_settles_on_the_disk() {
    let (scene, outcome) = settled_drape("cusick_wool");
    check(scene, outcome, 0.03);
}

#[test]
fn cusick_cotton_settles_on_the_disk() {
    let (scene, outcome) = settled_drape("cusick_cotton");
    check(scene, outcome, 0.03);
}

#[test]
fn tablecloth_wool_settles_on_the_table() {
    let (scene, outcome) = tablecloth("tablecloth_wool");
    check(scene, outcome, 0.03);
}

#[test]
fn tablecloth_cotton_settles_on_the_table() {
    let (scene, outcome) = tablecloth("tablecloth_cotton");
    check(scene, outcome, 0.03);
}

/// The tablecloth scenes, run with the 5 s watch after settling.
const TABLECLOTHS: [&str; 2] = ["tablecloth_cotton", "tablecloth_wool"];

/// The tablecloth scenes' runs.
fn tablecloth(name: &str) -> (&'static Scene, &'static RunOutcome) {
    run_named(name, "")
}

/// Every simulation of this file, run once (two at a time, the longest first, so that the
/// two cores stay busy) the first time any test asks: the four drapes with the 5 s watch
/// ([`WATCHED`]), each fabric's next two lattice placements on the drapemeter and thick
/// cotton's on the Cusick tester ([`PLACED`]),
/// thick cotton's drapemeter at 1.875 mm ([`FINER`]) and the two tablecloths. Each entry is
/// (scene, run, which set: [`WATCHED`], [`PLACED`], [`FINER`] or "" for a shipped run).
fn all_runs() -> &'static [(Scene, RunOutcome, &'static str)] {
    static RUNS: OnceLock<Vec<(Scene, RunOutcome, &'static str)>> = OnceLock::new();
    RUNS.get_or_init(|| {
        let watch = [
            "integration.settle.creep_check_s=5".to_string(),
            "integration.max_time_s=26".to_string(),
        ];
        let load = |name: &str, sets: &[String]| {
            Scene::load(common::crate_path(&format!("scenes/{name}.ron")), sets).unwrap()
        };
        let mut scenes: Vec<(Scene, &'static str)> = Vec::new();
        // Thin wool on the Cusick tester (11,289 nodes, and the one that may pass slowly
        // through a shape not at rest) is the longest; thick cotton's Cusick placements and
        // thin wool's drapemeter runs come next.
        scenes.push((load("cusick_wool", &watch), WATCHED));
        let placements =
            |name: &str| kes_cloth::repeat::repeat_scenes(&load(name, &[]), 3, true).split_off(1);
        // One of thick cotton's Cusick placements passes slowly through a skirt shape not at
        // rest (at rest at 12 s).
        for placed in placements("cusick_cotton") {
            scenes.push((placed, PLACED));
        }
        scenes.push((load("drape_wool", &watch), WATCHED));
        for placed in placements("drape_wool") {
            scenes.push((placed, PLACED));
        }
        scenes.push((load("cusick_cotton", &watch), WATCHED));
        let finer = ["cloth.spacing_m=0.001875".to_string()];
        scenes.push((load("drape_cotton", &finer), FINER));
        scenes.push((load("drape_cotton", &watch), WATCHED));
        for placed in placements("drape_cotton") {
            scenes.push((placed, PLACED));
        }
        for name in TABLECLOTHS {
            scenes.push((load(name, &watch), ""));
        }
        let plain: Vec<Scene> = scenes.iter().map(|(s, _)| s.clone()).collect();
        let outcomes = simulate_all(&plain, 2, |_, _| {});
        scenes
            .into_iter()
            .zip(outcomes)
            .map(|((scene, set), outcome)| (scene, outcome, set))
            .collect()
    })
}

/// The drapes run with the 5 s watch after settling.
const WATCHED: &str = "watched";
/// The drapemeter runs, and thick cotton's Cusick runs, at the next lattice placements.
const PLACED: &str = "placed";
/// Thick cotton's drapemeter run on a lattice 1.33 times finer (1.875 mm).
const FINER: &str = "finer";

/// The run of shipped scene `name` in set `set` of [`all_runs`].
fn run_named(name: &str, set: &str) -> (&'static Scene, &'static RunOutcome) {
    all_runs()
        .iter()
        .find(|(scene, _, s)| scene.spec.name == name && *s == set)
        .map(|(scene, outcome, _)| (scene, outcome))
        .unwrap()
}

/// On the tablecloth, thick cotton's skirt forms fewer folds than thin wool's, and wool's
/// corners hang lower (seed 0; the seed's claim on a second support, beside
/// `tests/drape_validation.rs`).
#[test]
fn cotton_tablecloth_skirt_has_fewer_folds_than_wool() {
    let result = |name: &str| {
        let m = &tablecloth(name).1.metrics;
        assert!(m.settled, "{name} did not settle");
        (m.skirt_folds.unwrap(), m.hang_corners_m.unwrap())
    };
    let (cotton_folds, cotton_hang) = result("tablecloth_cotton");
    let (wool_folds, wool_hang) = result("tablecloth_wool");
    assert!(
        cotton_folds < wool_folds,
        "skirt folds: cotton {cotton_folds}, wool {wool_folds}"
    );
    assert!(
        wool_hang > cotton_hang,
        "corner hang: cotton {cotton_hang}, wool {wool_hang}"
    );
}

/// The drapemeter and Cusick scenes, watched for 5 s after they settle.
const DRAPES: [&str; 4] = ["drape_cotton", "drape_wool", "cusick_cotton", "cusick_wool"];

/// Scene `name` of [`DRAPES`] and its run with the 5 s watch.
fn settled_drape(name: &str) -> (&'static Scene, &'static RunOutcome) {
    run_named(name, WATCHED)
}

/// Largest node displacement and centroid displacement allowed over the creep check (m).
const CREEP_BOUND: f64 = 0.5e-3;
/// Deepest a node centre may sit inside a collider at the end of any step (m).
const PENETRATION_BOUND: f64 = 0.5e-3;
/// Fastest a node may move over the last step once settled (m/s): "no jitter", the implicit
/// bound kes-cloth promises for a cloth at rest; these scenes measure 0.11–0.15 mm/s.
const JITTER_BOUND: f64 = kes_cloth::run::AT_REST_STEP_SPEED_M_PER_S;

/// Every shipped scene's run, at every placement the pool runs, leaves its links within the
/// strain limit without it (the limit is for steps long for the lattice, `docs/model.md` §12,
/// "The longest step"): the shipped drapes are the model's, not the limit's. Their largest
/// transients, on landing, are 3–14 %, against the limit's 45 %.
#[test]
fn no_shipped_run_needs_the_strain_limit() {
    for (scene, outcome, set) in all_runs() {
        let m = &outcome.metrics;
        assert_eq!(
            m.strain_limited_steps,
            0,
            "{} ({set}): limited after {} steps, peak strain {:.1} %",
            scene.spec.name,
            m.strain_limited_steps,
            m.peak_strain * 100.0
        );
    }
}

/// Each drape and tablecloth comes to rest (its quiet window closed and confirmed by the
/// scene's 2 s watch) within 5 s for thick cotton and within its scene's budget (20 s on the
/// testers, 12 s on the table) for thin wool, whose last
/// skirt fold relaxes slowly from the smooth start and can pass slowly through a shape not at
/// rest (on the Cusick tester such a passage kept one lattice placement moving until about
/// 14 s; `docs/model.md` §1, "Rest"), and then neither creeps nor jitters over 5 s.
#[test]
fn drapes_come_to_rest_within_their_budget_and_do_not_creep() {
    let drapes = DRAPES.iter().map(|name| settled_drape(name));
    for (scene, outcome) in drapes.chain(TABLECLOTHS.iter().map(|name| tablecloth(name))) {
        let name = scene.spec.name.as_str();
        let m = &outcome.metrics;
        let settle = m.settle_time_s.unwrap_or(f64::INFINITY);
        let budget = if name.ends_with("cotton") {
            5.0
        } else {
            Scene::load(common::crate_path(&format!("scenes/{name}.ron")), &[])
                .unwrap()
                .spec
                .integration
                .max_time_s
        };
        assert!(scene.spec.integration.max_time_s > budget + 5.0);
        // `settle_time_s` opens the quiet window; the window (0.5 s) must also close in budget.
        assert!(
            m.settled && settle + 0.5 <= budget,
            "{name}: settled at {settle} s, budget {budget} s"
        );
        let window = m.creep_window_s.unwrap_or(0.0);
        assert!(
            (window - 5.0).abs() < 1e-6,
            "{name}: watched {window} s after settling, not 5 s"
        );
        assert!(
            m.peak_penetration_m <= PENETRATION_BOUND,
            "{name}: a node sat {:.3} mm inside a collider at the worst step",
            m.peak_penetration_m * 1e3
        );
        let (node, centroid) = (m.creep_max_node_m.unwrap(), m.creep_centroid_m.unwrap());
        assert!(
            node <= CREEP_BOUND && centroid <= CREEP_BOUND,
            "{name}: over 5 s after settling a node moved {:.3} mm, the centroid {:.3} mm",
            node * 1e3,
            centroid * 1e3
        );
        assert!(
            m.max_step_speed_m_per_s < JITTER_BOUND,
            "{name}: a node moved {:.2} mm/s over the last step, 5 s after settling",
            m.max_step_speed_m_per_s * 1e3
        );
    }
}

/// Thin wool's drape as shipped (2.5 mm, a sixth of its bending length) is the fabric's, not
/// the lattice's, to the target of 0.01: on the seed's drapemeter three placements of the
/// lattice, all from the one smooth start at seed 0 (the centred lattice, run above with its 5 s
/// watch, and the next two placements of `--placements`), give a DC standard deviation of at
/// most 0.01 and one node count. Measured over four placements: 0.365 ± 0.003 with 8 nodes
/// each (0.364 ± 0.004 at 1.875 mm), where 3.75 mm gives 0.362 ± 0.015 (`docs/model.md` §1).
/// Thick cotton's counterpart, with its finer lattice, is the next test.
#[test]
fn thin_wools_drape_moves_by_less_than_a_hundredth_with_placement() {
    spread_within_a_hundredth("drape_wool");
}

/// The runs of drape scene `name` at its three lattice placements (the centred one with its
/// 5 s watch), summarised; each must have settled.
fn placements(name: &str) -> kes_cloth::repeat::RepeatSummary {
    let centred = &settled_drape(name).1.metrics;
    let placed = all_runs()
        .iter()
        .filter(|(scene, _, set)| scene.spec.name == name && *set == PLACED);
    let metrics: Vec<_> = std::iter::once(centred)
        .chain(placed.map(|(_, o, _)| &o.metrics))
        .collect();
    assert_eq!(metrics.len(), 3);
    let s = kes_cloth::repeat::summarise_metrics(&metrics);
    assert_eq!(s.settled, 3, "{name}: {s:?}");
    s
}

/// The three placements of drape scene `name` ([`placements`]) give a DC standard deviation of
/// at most 0.01 and one node count; returns their summary and mean DC.
fn spread_within_a_hundredth(name: &str) -> (kes_cloth::repeat::RepeatSummary, f64) {
    let s = placements(name);
    let (mean, sd) = (s.dc_mean.expect("a DC each"), s.dc_std.expect("a DC each"));
    println!("{name}, 2.5 mm: {mean:.4} ± {sd:.4} ({:?})", s.nodes);
    assert!(sd <= 0.01, "{name}: DC {mean:.4} ± {sd:.4}");
    assert!(
        s.nodes.iter().all(|n| *n == s.modal_nodes),
        "{name}: node counts {:?}",
        s.nodes
    );
    (s, mean)
}

/// Thick cotton's drape on the Cusick tester as shipped (2.5 mm, the smooth start) is the
/// fabric's, not where the lattice falls, to the target of 0.01: three placements (the centred
/// one with its 5 s watch, all at seed 0) give a DC standard deviation of at most 0.01 and one
/// node count (measured 0.762 ± 0.005, 6 nodes each: 0.768 / 0.761 / 0.758). Against a finer
/// lattice it is not tested here (a Cusick run at 1.875 mm costs several minutes): the rim's
/// first-order term leaves 2.5 mm 0.008–0.011 below the limit of 0.770–0.773 (`docs/accuracy.md`
/// §4).
#[test]
fn thick_cottons_cusick_drape_moves_by_less_than_a_hundredth_with_placement() {
    spread_within_a_hundredth("cusick_cotton");
}

/// Thick cotton's drape as shipped is the fabric's, not the lattice's, to the target of 0.01:
/// on the seed's drapemeter (2.5 mm, the smooth start), three placements (the centred one with
/// its 5 s watch, all at seed 0) give a DC standard deviation of at most 0.01 and one node
/// count (measured 0.740 ± 0.003 over four, 4 nodes each), and their mean lies within 0.01 of
/// the same drape on a lattice 1.33 times finer (1.875 mm, centred; measured 0.746), with the
/// same node count. The rim's first-order term (0.0038 per mm of spacing) leaves the shipped
/// 2.5 mm 0.009 below the limit of 0.749 (`docs/accuracy.md` §4), and 3.75 mm 0.014 below.
/// Thin wool's ± 0.015 misses the spread target at 3.75 mm and meets it at its shipped 2.5 mm
/// (the test above).
#[test]
fn thick_cottons_drape_moves_by_less_than_a_hundredth_with_placement_or_a_finer_lattice() {
    let (s, mean) = spread_within_a_hundredth("drape_cotton");
    let fine = &run_named("drape_cotton", FINER).1.metrics;
    assert!(fine.settled, "the 1.875 mm drape is not at rest");
    let fine_dc = fine.drape_coefficient.expect("a DC");
    println!(
        "2.5 mm: {mean:.4} ({:?}); 1.875 mm: {fine_dc:.4} ({:?})",
        s.nodes, fine.nodes
    );
    assert!(
        (mean - fine_dc).abs() <= 0.01,
        "2.5 mm: {mean:.4}; 1.875 mm: {fine_dc:.4}"
    );
    assert_eq!(fine.nodes, s.modal_nodes, "nodes at 1.875 mm");
}
