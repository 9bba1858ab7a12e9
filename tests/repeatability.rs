//! The same scene, seed and build give bit-identical results: every metric except wall-clock
//! times, and every node position, bit for bit (the simulation is single-threaded and
//! deterministic; parallel repeats run whole scenes per thread, and the two runs here run side
//! by side on two threads).

use kes_cloth::repeat::simulate_all;
use kes_cloth::scene::Scene;

mod common;

#[test]
fn a_scene_run_twice_gives_bit_identical_results() {
    // The explicit path, the implicit one with rope joints, and the shipped scene (BDF2).
    for (scene, base, sets) in [
        (
            "scenes/drape_wool.ron",
            common::explicit_drape("wool"),
            vec!["integration.max_time_s=0.3", "seed=3"],
        ),
        (
            "scenes/drape_cotton.ron",
            common::explicit_drape("cotton"),
            vec![
                "integration.max_time_s=0.3",
                "integration.integrator=Implicit",
                "integration.dt_s=0.002",
            ],
        ),
        (
            "scenes/drape_wool.ron",
            Vec::new(),
            vec!["integration.max_time_s=0.3", "seed=3"],
        ),
    ] {
        let sets: Vec<String> = base
            .into_iter()
            .chain(sets.into_iter().map(String::from))
            .collect();
        let scene = Scene::load(common::crate_path(scene), &sets).unwrap();
        // The two runs side by side, one on each of two threads.
        let [a, b]: [_; 2] = simulate_all(&[scene.clone(), scene.clone()], 2, |_, _| {})
            .try_into()
            .expect("two outcomes");
        assert_eq!(
            common::without_clock_times(&a.metrics),
            common::without_clock_times(&b.metrics)
        );
        assert!(
            a.positions
                .iter()
                .zip(&b.positions)
                .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits)),
            "{}: positions differ between identical runs",
            scene.spec.name
        );
    }
}
