//! Links, not only nodes, rest on a fixed collider's sharp edge: the point of a link the edge
//! presses, how deep and along which normal, against the geometry of a line passing a corner.

use glam::DVec3;
use kes_cloth::bodies::{ClothBodies, ContactStiffness, NodeOptions, configure_world};
use kes_cloth::forces::ClothTopology;
use kes_cloth::implicit::Supports;
use rapier3d::prelude::*;

/// Node contact radius (m); the nodes' centres keep this clearance from a surface.
const RADIUS: f64 = 5e-4;
/// Node mass (kg) and link support stiffness (Hz).
const MASS: f64 = 4e-6;
const HZ: f64 = 960.0;

/// Two nodes linked across the edge x = 0, y = 0 (along z) of a box filling x < 0, y < 0 (μ =
/// 0.5), at `p` and `q` (m), with no gravity and no motion, after one step: Rapier's world, the
/// nodes and their topology.
fn edge_world(p: DVec3, q: DVec3) -> (PhysicsWorld, ClothBodies, ClothTopology) {
    let mut world = PhysicsWorld::default();
    configure_world(&mut world, [0.0; 3], 1e-3, (1, 1), ContactStiffness::default());
    let topology = ClothTopology::rectangle(2, 1, (q - p).length());
    let options = NodeOptions {
        masses: vec![MASS; 2],
        radius: RADIUS,
        rope_links: false,
        contact: true,
        self_collision: false,
        gravity: false,
        surface_depth: 0.0,
        link_support_hz: Some(HZ),
    };
    let nodes = ClothBodies::spawn(&mut world, &topology, &[p, q], &options);
    let table = ColliderBuilder::cuboid(0.05, 0.05, 0.05)
        .translation(Vector::new(-0.05, -0.05, 0.0))
        .friction(0.5)
        .build();
    world.insert_collider(table, None);
    world.step();
    let mut positions = [DVec3::ZERO; 2];
    let mut velocities = [DVec3::ZERO; 2];
    nodes.read(&world, &mut positions, &mut velocities);
    assert!((positions[0] - p).length() < 1e-9 && (positions[1] - q).length() < 1e-9);
    (world, nodes, topology)
}

/// The link supports of two nodes at `p` and `q` across the edge ([`edge_world`]).
fn supports_of(p: DVec3, q: DVec3) -> Supports {
    let (world, nodes, topology) = edge_world(p, q);
    let mut supports = Supports::new(2);
    nodes.read_supports(&world, &mut supports);
    nodes.read_link_supports(&world, &topology.links, &[p, q], &mut supports);
    supports
}

/// A link from a node 0.1 mm above its resting clearance over the table top to one hanging 2 mm
/// beyond the edge passes 0.097 mm from the edge: the edge presses it at the foot of the
/// perpendicular from the edge, 0.403 mm into the nodes' 0.5 mm clearance, along the direction
/// from the edge to that foot. Tolerances: f32 geometry (a box 5 cm from the origin: distances
/// to about 4e-9 m) leaves the depth flat near its maximum to within a few 1e-4 of the link's
/// length, so the point pressed is held to 1e-4 of the link, the normal, which turns by 44 rad
/// per unit of that position here, to 2e-3 rad, and the depth to 1e-7 m.
#[test]
fn an_edge_presses_a_link_that_cuts_its_corner_at_the_foot_of_the_perpendicular() {
    let (p, q) = (DVec3::new(-2e-3, 6e-4, 0.0), DVec3::new(2e-3, -4e-4, 0.0));
    let supports = supports_of(p, q);
    assert_eq!(supports.links.len(), 1, "{:?}", supports.links);
    let s = supports.links[0];
    let d = q - p;
    let at = -p.dot(d) / d.length_squared();
    let foot = p + at * d;
    assert!((s.at - at).abs() < 1e-4, "at {} vs {at}", s.at);
    assert!(
        (s.depth - (RADIUS - foot.length())).abs() < 1e-7,
        "depth {} vs {}",
        s.depth,
        RADIUS - foot.length()
    );
    assert!(
        (s.normal - foot.normalize()).length() < 2e-3,
        "normal {} vs {}",
        s.normal,
        foot.normalize()
    );
    let omega = std::f64::consts::TAU * HZ;
    assert!((s.stiffness - MASS * omega * omega).abs() < 1e-9 * s.stiffness);
    assert_eq!(s.nodes, [0, 1]);
}

/// A link lying on the top face, its nodes resting there alike, and one passing clear of the
/// edge (0.6 mm from it, beyond the clearance) get no support: node contact carries the first,
/// nothing touches the second.
#[test]
fn a_link_on_a_face_or_clear_of_the_edge_is_not_pressed() {
    let flat = supports_of(DVec3::new(-6e-3, RADIUS, 0.0), DVec3::new(-2e-3, RADIUS, 0.0));
    assert!(flat.links.is_empty(), "{:?}", flat.links);
    let clear = supports_of(DVec3::new(-2e-3, 1.2e-3, 0.0), DVec3::new(2e-3, 0.0, 0.0));
    assert!(clear.links.is_empty(), "{:?}", clear.links);
}

/// Static friction at the edge: once a link is pressed, moving both nodes along the edge by
/// less than μ·depth (0.5 × 0.403 mm) shifts the held point by exactly that, pulling back with
/// k times it; moving them further slips, and the shift stays at μ·depth (the friction force at
/// μ times the normal force). Tolerance 1e-7 m: f32 geometry, as above.
#[test]
fn the_edge_holds_a_pressed_link_by_static_friction_up_to_mu_times_its_push() {
    let (p, q) = (DVec3::new(-2e-3, 6e-4, 0.0), DVec3::new(2e-3, -4e-4, 0.0));
    let (world, nodes, topology) = edge_world(p, q);
    let mut supports = Supports::new(2);
    let read = |moved: DVec3, supports: &mut Supports| {
        nodes.read_supports(&world, supports);
        nodes.read_link_supports(&world, &topology.links, &[p + moved, q + moved], supports);
        assert_eq!(supports.links.len(), 1, "{:?}", supports.links);
        supports.links[0]
    };
    let first = read(DVec3::ZERO, &mut supports);
    assert!(
        first.shift.length() < 1e-12,
        "a new contact starts held where it touches"
    );
    let limit = 0.5 * first.depth;
    let held = read(DVec3::new(0.0, 0.0, 0.5 * limit), &mut supports);
    assert!(
        (held.shift - DVec3::new(0.0, 0.0, 0.5 * limit)).length() < 1e-7,
        "{:?}",
        held.shift
    );
    assert!((held.held_at - first.at).abs() < 1e-12);
    let slipped = read(DVec3::new(0.0, 0.0, 3.0 * limit), &mut supports);
    assert!(
        (slipped.shift.length() - limit).abs() < 1e-7,
        "{:?} vs {limit}",
        slipped.shift
    );
    assert!(slipped.shift.z > 0.0, "friction pulls back against the motion");
}

/// The stiffness the implicit solve is given is the derivative of the force the edge applies,
/// the point pressed and the normal held over the step: moving the two nodes by a small δ
/// (about 1 µm, across the link and along the edge, within friction's hold) changes the nodes'
/// forces by −H·δ, H from `LinkSupport::add_stiffness_blocks`, up to the normal's turn, which H
/// leaves out. That term is the push k·depth turning by δ over the distance from the edge to the
/// link's centre line: depth/distance = 0.031/0.469 mm, 7 % of the spring's k·δ here (the drapes
/// press 5–60 µm into a 0.5 mm clearance), hence a tolerance of 10 % of the change.
#[test]
fn the_solves_stiffness_is_the_derivative_of_the_edges_force() {
    use kes_cloth::forces::{ForceBuffer, LinkMatrix, Perturbation};
    let (p, q) = (DVec3::new(-2e-3, 6e-4, 0.0), DVec3::new(2e-3, 3.4e-4, 0.0));
    let (world, nodes, topology) = edge_world(p, q);
    let mut supports = Supports::new(2);
    let forces_at = |moved: [DVec3; 2], supports: &mut Supports| {
        nodes.read_supports(&world, supports);
        nodes.read_link_supports(&world, &topology.links, &[p + moved[0], q + moved[1]], supports);
        assert_eq!(supports.links.len(), 1, "{:?}", supports.links);
        let mut f = [DVec3::ZERO; 2];
        supports.links[0].add_forces(&mut f);
        (f, supports.links[0])
    };
    let (before, support) = forces_at([DVec3::ZERO; 2], &mut supports);
    let delta = [DVec3::new(3e-7, -8e-7, 4e-7), DVec3::new(-5e-7, 2e-7, 6e-7)];
    let (after, _) = forces_at(delta, &mut supports);
    let mut matrix = LinkMatrix::new(&topology);
    support.add_stiffness_blocks(1.0, &mut matrix);
    let mut pert = Perturbation::new(&topology);
    pert.set(&topology, &delta);
    let mut buffer = ForceBuffer::new(&topology);
    let h_delta = matrix.product(&topology, &pert, &mut buffer).to_vec();
    for i in 0..2 {
        let change = after[i] - before[i];
        assert!(
            (change + h_delta[i]).length() <= 0.1 * change.length(),
            "node {i}: force changed by {change}, −H·δ = {}",
            -h_delta[i]
        );
    }
}
