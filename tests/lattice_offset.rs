//! A circular cloth's node lattice can be shifted against its outline (`cloth.lattice_offset_m`):
//! the outline stays where it is, every node stays inside it, and the lattice moves by the offset.
//! Used to measure how much a drape owes to where the grid happens to fall (`docs/accuracy.md`).

use kes_cloth::scene::Scene;
use kes_cloth::scene::spawn::spawn;
use kes_cloth::schedule::ClothState;

mod common;

/// Flat node positions (x, z) of `drape_wool` at 1 cm (25.4 cm circle, centred at the origin)
/// with the given overrides, before any step.
fn lattice(sets: &[&str]) -> Vec<[f64; 2]> {
    let sets: Vec<String> = std::iter::once("cloth.spacing_m=0.01")
        .chain(sets.iter().copied())
        .map(String::from)
        .collect();
    let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
    let (world, cloth) = spawn(&scene);
    let state = world.entity(cloth).get::<ClothState>().unwrap();
    state.positions.iter().map(|p| [p.x, p.z]).collect()
}

#[test]
fn a_shifted_lattice_stays_inside_the_same_outline() {
    let (r, sigma) = (0.127, 0.01);
    let centred = lattice(&[]);
    // The default lattice: a node at the centre, 505 nodes at 1 cm.
    assert_eq!(centred.len(), 505);
    assert!(centred.iter().any(|p| p[0].hypot(p[1]) < 1e-12));
    for offset in [(0.005, 0.005), (0.0025, 0.0), (-0.004, 0.003)] {
        let nodes = lattice(&[&format!("cloth.lattice_offset_m=({}, {})", offset.0, offset.1)]);
        // Inside the outline (to rounding), and the lattice moved by the offset: every node sits
        // at offset + whole spacings. The state holds what Rapier holds, f32 positions: 1e-8 m
        // is over twice their rounding at 0.1–0.13 m (half an f32 ulp there, 3.7e-9 m).
        for p in &nodes {
            assert!(p[0].hypot(p[1]) <= r + 1e-8, "node {p:?} outside the outline");
            for (c, o) in [(p[0], offset.0), (p[1], offset.1)] {
                let k = ((c - o) / sigma).round();
                assert!(
                    (c - o - k * sigma).abs() < 1e-8,
                    "node {p:?} not on the shifted lattice"
                );
            }
        }
        // Same area to within one ring of nodes: |ΔN| ≤ perimeter / σ ≈ 80.
        let dn = nodes.len() as f64 - centred.len() as f64;
        assert!(
            dn.abs() <= 2.0 * std::f64::consts::PI * r / sigma,
            "{} nodes",
            nodes.len()
        );
        // The outline did not move: the nodes' centroid stays within a quarter spacing of the
        // centre (a lattice clipped by a circle is nearly symmetric about it).
        let n = nodes.len() as f64;
        let (cx, cz) = nodes
            .iter()
            .fold((0.0, 0.0), |(x, z), p| (x + p[0] / n, z + p[1] / n));
        assert!(cx.hypot(cz) < sigma / 4.0, "centroid ({cx}, {cz})");
    }
}

/// The error loading `scene` (a path in the crate) with the lattice shifted by `offset`.
fn refusal(scene: &str, offset: &str) -> String {
    let set = format!("cloth.lattice_offset_m={offset}");
    Scene::load(common::crate_path(scene), &[set])
        .unwrap_err()
        .to_string()
}

#[test]
fn a_lattice_offset_beyond_half_a_spacing_or_on_a_rectangle_is_refused() {
    // Half the shipped 2.5 mm spacing is 1.25 mm.
    let e = refusal("scenes/drape_cotton.ron", "(0.0015, 0.0)");
    assert!(
        e.contains("cloth.lattice_offset_m[0]") && e.contains("0.00125"),
        "{e}"
    );
    let e = refusal("scenes/tablecloth_wool.ron", "(0.001, 0.0)");
    assert!(e.contains("circular cloths only"), "{e}");
    let e = refusal("scenes/hard/folded.ron", "(0.001, 0.0)");
    assert!(e.contains("cloth.fold_gap_m"), "{e}");
}

/// `--repeat N --placements`: run k takes the k-th offset of an even sequence over ± half a
/// spacing and seed k (the default per-node roughness is another start on every lattice
/// anyway); run 0 keeps the scene's own lattice, and no two runs share a placement. With a
/// smooth start roughness, one start for every lattice, every run keeps the scene's seed.
#[test]
fn repeats_with_placements_spread_the_lattice_over_half_a_spacing() {
    let scene = Scene::load(
        common::crate_path("scenes/drape_wool.ron"),
        &["cloth.roughness=PerNode".to_string()],
    )
    .unwrap();
    let sigma = scene.spec.cloth.spacing_m;
    let runs = kes_cloth::repeat::repeat_scenes(&scene, 10, true);
    let offsets: Vec<[f64; 2]> = runs.iter().map(|s| s.spec.cloth.lattice_offset_m).collect();
    assert_eq!(offsets[0], [0.0, 0.0]);
    for (k, (run, o)) in runs.iter().zip(&offsets).enumerate() {
        assert_eq!(run.spec.seed, k as u64);
        assert!(o.iter().all(|c| c.abs() <= sigma / 2.0), "run {k}: {o:?}");
        for p in &offsets[..k] {
            // Distinct by at least a tenth of a spacing (the R2 sequence's first ten points are
            // further apart than that).
            assert!(
                (o[0] - p[0]).hypot(o[1] - p[1]) > sigma / 10.0,
                "{o:?} near {p:?}"
            );
        }
    }
    // Every quadrant of the placement square is visited.
    for (sx, sz) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        assert!(
            offsets.iter().any(|o| o[0] * sx > 0.0 && o[1] * sz > 0.0),
            "quadrant ({sx}, {sz})"
        );
    }
    // Without placements every run keeps the scene's lattice.
    let plain = kes_cloth::repeat::repeat_scenes(&scene, 3, false);
    assert!(plain.iter().all(|s| s.spec.cloth.lattice_offset_m == [0.0, 0.0]));
    assert!(plain.iter().enumerate().all(|(k, s)| s.spec.seed == k as u64));
    let smooth = Scene::load(
        common::crate_path("scenes/drape_wool.ron"),
        &["cloth.roughness=Smooth".to_string(), "seed=5".to_string()],
    )
    .unwrap();
    let runs = kes_cloth::repeat::repeat_scenes(&smooth, 3, true);
    assert!(runs.iter().all(|s| s.spec.seed == 5));
    assert_ne!(runs[1].spec.cloth.lattice_offset_m, [0.0, 0.0]);
}

/// With `cloth.roughness: Smooth` the start roughness belongs to the cloth, not to its
/// lattice:
/// every node, at any lattice placement and spacing, starts at the height of one seeded field
/// at its flat position (along warp = +x and weft = +z from the centre), so shifted and refined
/// lattices sample one start. Tolerance: positions are Rapier's f32 (half an ulp at 0.1 m is
/// 3.7e-9 m). With `PerNode`, the same node position gets another offset on another lattice.
#[test]
fn a_smooth_start_roughness_is_the_same_field_on_every_lattice() {
    let (amplitude, seed) = (0.0005, 3);
    let field = kes_cloth::embed::SmoothRoughness::new(amplitude, seed);
    let centre = Scene::load(common::crate_path("scenes/drape_wool.ron"), &[])
        .unwrap()
        .spec
        .cloth
        .centre_m;
    for (spacing, offset) in [
        (0.01, (0.0, 0.0)),
        (0.01, (0.003, -0.002)),
        (0.0075, (-0.001, 0.0)),
    ] {
        let sets = [
            format!("cloth.spacing_m={spacing}"),
            format!("cloth.lattice_offset_m=({}, {})", offset.0, offset.1),
            "cloth.roughness=Smooth".into(),
            format!("cloth.perturbation_m={amplitude}"),
            format!("seed={seed}"),
        ];
        let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
        let (world, cloth) = spawn(&scene);
        let state = world.entity(cloth).get::<ClothState>().unwrap();
        let mut largest = 0.0f64;
        for p in &state.positions {
            let expected = centre[1] + field.height(p.x - centre[0], p.z - centre[2]);
            assert!(
                (p.y - expected).abs() < 1e-8,
                "σ {spacing}, offset {offset:?}: node {p:?} at {} m, the field gives {expected} m",
                p.y
            );
            largest = largest.max((p.y - centre[1]).abs());
        }
        // The field is not flat over the cloth: it lifts some node by a good part of its bound.
        assert!(
            largest > 0.3 * amplitude && largest <= amplitude + 1e-8,
            "{largest} m"
        );
    }
    // PerNode: a different offset at the same flat position on another lattice (the centre node
    // of the centred 1 cm and 5 mm lattices).
    let centre_height = |spacing: f64| {
        let sets = [
            format!("cloth.spacing_m={spacing}"),
            format!("cloth.perturbation_m={amplitude}"),
            "cloth.roughness=PerNode".into(),
        ];
        let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
        let (world, cloth) = spawn(&scene);
        let state = world.entity(cloth).get::<ClothState>().unwrap();
        state
            .positions
            .iter()
            .find(|p| (p.x - centre[0]).hypot(p.z - centre[2]) < 1e-6)
            .unwrap()
            .y
    };
    assert_ne!(centre_height(0.01), centre_height(0.005));
}

/// A smooth start's bound is the cloth's, not the lattice's: the shipped thin wool drape's
/// 0.5 mm smooth start loads at 1.25 mm (where a per-node start is held to a quarter of the
/// spacing, 0.31 mm, and refused with its field and range).
#[test]
fn a_smooth_start_keeps_its_amplitude_on_fine_lattices() {
    let load = |roughness: &str| {
        Scene::load(
            common::crate_path("scenes/drape_wool.ron"),
            &[
                "cloth.spacing_m=0.00125".to_string(),
                format!("cloth.roughness={roughness}"),
            ],
        )
    };
    let smooth = load("Smooth").expect("a 0.5 mm smooth start at 1.25 mm loads");
    assert_eq!(smooth.spec.cloth.perturbation_m, 0.0005);
    let Err(e) = load("PerNode") else {
        panic!("a 0.5 mm per-node start at 1.25 mm loaded");
    };
    let e = e.to_string();
    assert!(
        e.contains("cloth.perturbation_m") && e.contains("0.0003125"),
        "{e}"
    );
}
