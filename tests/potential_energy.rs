//! `metrics.json` gives the final shape's potential energy, gravitational and elastic, so that
//! two rest shapes of one lattice can be ranked. Checked on thin wool's drape at 1 cm (505
//! nodes, BDF2 at 1/240 s): the gravitational part is −Σ mᵢ g·xᵢ of the final positions,
//! recomputed here from the builder's node masses; the drape stores elastic energy; and the
//! whole is below the energy the flat cloth starts with 1 cm above the disk, since contact and
//! damping only take energy away.

use kes_cloth::repeat::simulate_all;
use kes_cloth::scene::Scene;
use kes_cloth::scene::spawn::cloth_builder;

mod common;

#[test]
fn a_settled_drape_reports_less_potential_energy_than_its_flat_start() {
    let sets = ["cloth.spacing_m=0.01", "integration.settle.confirm_s=0"].map(String::from);
    let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
    let outcome = simulate_all(std::slice::from_ref(&scene), 1, |_, _| {}).remove(0);
    let m = &outcome.metrics;
    assert!(m.settled, "{m:?}");
    let masses = cloth_builder(&scene).node_masses();
    let g = 9.80665;
    let gravitational: f64 = outcome
        .positions
        .iter()
        .zip(&masses)
        .map(|(x, m)| m * g * x.y)
        .sum();
    let reported = m.gravitational_energy_j.expect("reported");
    // The same sum in another order: agreement to round-off of a millijoule-sized sum.
    assert!(
        (reported - gravitational).abs() <= 1e-12,
        "{reported} J against {gravitational} J"
    );
    let elastic = m.elastic_energy_j.expect("reported");
    // The start: flat (its smooth roughness is 0.5 mm high, a 20th of its height) 10 mm above
    // the disk's top at y = 0, storing no elastic energy worth counting.
    let start = masses.iter().sum::<f64>() * g * scene.spec.cloth.centre_m[1];
    println!("start {start:.4e} J; at rest: gravitational {gravitational:.4e} J, elastic {elastic:.4e} J");
    assert!(elastic > 0.0, "a drape bends: elastic {elastic} J");
    assert!(
        gravitational + elastic < start,
        "at rest {} J, flat start {start} J",
        gravitational + elastic
    );
}
