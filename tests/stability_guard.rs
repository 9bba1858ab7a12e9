//! The stability guard: from the fabric's tangent stiffness, node mass and spacing it bounds the
//! explicit step (ω·dt ≤ 1.6, `docs/model.md` §10). A run just inside the bound is stable and
//! settles; well outside it, with the guard switched off, the run diverges; with the guard on,
//! such a scene is refused with a message naming the effect, the step it needs and the way out.

use kes_cloth::forces::explicit_step_limits;
use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::{Scene, StretchModel};

mod common;

/// A compression spring soft enough (100 N/m, limit 0.47 ms) that trellising is thick cotton's
/// tightest limit at 1 cm, so the tests below probe a KES force.
const SOFT_COMPRESSION: f64 = 100.0;

fn cotton_limit() -> (f64, &'static str) {
    let fabric = common::shipped_fabric("thick_cotton");
    let limits = explicit_step_limits(
        &fabric,
        0.01,
        true,
        true,
        false,
        StretchModel::Constraint,
        Some(SOFT_COMPRESSION),
    );
    (limits[0].max_step, limits[0].effect)
}

fn drape(sets: &[String]) -> Result<kes_cloth::run::RunOutcome, kes_cloth::scene::SceneError> {
    let mut sets: Vec<String> = common::explicit_drape("cotton")
        .into_iter()
        .chain(sets.iter().cloned())
        .collect();
    sets.push(format!("effects.compression_modulus_n_per_m={SOFT_COMPRESSION}"));
    let scene = Scene::load(common::crate_path("scenes/drape_cotton.ron"), &sets)?;
    Ok(simulate(&scene, &RunOptions::default()))
}

#[test]
fn the_guard_names_the_effect_and_the_step_it_needs() {
    let (limit, effect) = cotton_limit();
    assert_eq!(effect, "trellising", "thick cotton's tightest explicit KES limit");
    // Trellising: k = 4G with G = 3 gf/cm/deg = 168.5 N/m/rad, m = 35 mg: ω = 4.39e3 1/s.
    assert!((limit - 3.64e-4).abs() < 0.02e-4, "limit {limit} s");
    let Err(err) = drape(&[format!("integration.dt_s={}", 2.0 * limit)]) else {
        panic!("twice the bound must be refused");
    };
    let text = err.to_string();
    for needle in [
        "integration.dt_s",
        "trellising",
        "Implicit",
        "step_guard",
        "docs/model.md",
    ] {
        assert!(text.contains(needle), "`{needle}` missing from: {text}");
    }
}

/// With its default compression spring (100·π²·B/σ², `docs/model.md` §9) thick cotton at 1 cm is
/// limited by that spring: B = 1.2 gf·cm²/cm = 1.177e-4 N·m gives 1,161 N/m, k = 4·1,161 N/m per
/// node of 35 mg, ω = 1.152e4 1/s and 1.6/ω = 0.1389 ms. The seed's explicit drape at 0.125 ms passes;
/// the 0.25 ms it used before the spring had a fixed modulus is refused.
#[test]
fn the_default_compression_spring_sets_thick_cottons_step_at_one_centimetre() {
    let fabric = common::shipped_fabric("thick_cotton");
    let limits = explicit_step_limits(&fabric, 0.01, true, true, false, StretchModel::Constraint, None);
    assert_eq!(limits[0].effect, "compression");
    assert!(
        (limits[0].max_step - 1.389e-4).abs() < 0.002e-4,
        "limit {} s",
        limits[0].max_step
    );
    let path = common::crate_path("scenes/drape_cotton.ron");
    let explicit = common::explicit_drape("cotton");
    let seed_model = Scene::load(&path, &explicit).unwrap();
    assert!(seed_model.spec.integration.dt_s <= limits[0].max_step);
    let mut too_long = explicit.clone();
    too_long.push("integration.dt_s=0.00025".to_string());
    let refused = Scene::load(&path, &too_long).unwrap_err();
    assert!(refused.to_string().contains("compression"), "{refused}");
}

#[test]
fn just_inside_the_bound_is_stable_and_far_outside_it_diverges() {
    let (limit, _) = cotton_limit();
    let inside = drape(&[
        format!("integration.dt_s={}", 0.95 * limit),
        // Settled (1-2 s) and confirmed by the scene's 2 s watch.
        "integration.max_time_s=5".into(),
    ])
    .unwrap()
    .metrics;
    assert!(inside.failure.is_none(), "{:?}", inside.failure);
    assert!(inside.settled, "just inside the bound, the drape did not settle");
    let outside = drape(&[
        format!("integration.dt_s={}", 3.0 * limit),
        "integration.max_time_s=1".into(),
        "integration.step_guard=false".into(),
    ])
    .unwrap()
    .metrics;
    assert!(
        outside.failure.is_some(),
        "3× the bound should diverge without the guard"
    );
}
