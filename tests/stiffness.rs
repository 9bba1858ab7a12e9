//! The stiffness the implicit integrator solves with is the true tangent stiffness of the forces,
//! and the matrix it solves is symmetric positive definite.
//!
//! * Exact Hessian products, assembled column by column into the 3N × 3N matrix H = ∂²E/∂x²,
//!   match central finite differences of the forces, −∂F/∂x, to a relative 1e-5 of the largest
//!   entry (step 1e-6·σ: truncation ~1e-12, round-off ~1e-16·F/(1e-6·σ·H) ≈ 1e-10 relative),
//!   on random, bent, folded, and sheared grids, for every shipped fabric and sampled curves.
//! * The clamped Hessian bounds the exact one from above (their difference is positive
//!   semi-definite to −1e-10 of the largest entry), so it only adds numerical damping.
//! * The clamped Hessian is symmetric (1e-12 relative: one floating-point sum order against
//!   another) and positive semi-definite (smallest eigenvalue ≥ −1e-10 of the largest), so the
//!   system M + h·C + h²·H is positive definite (its Cholesky factorisation exists) on every
//!   state, and equals the exact Hessian at the flat rest state, where the clamp changes nothing.
//! * Damping products match finite differences of the forces in the velocities.
//! * The matrices the solver assembles ([`LinkMatrix`]) are the ones the products multiply by,
//!   entry for entry (1e-12 relative: the same terms summed in another order), and the
//!   preconditioner's particle blocks are their diagonal blocks.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use kes_cloth::forces::{
    AirDrag, Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Hysteresis, KesTensile,
    LinkCompression, LinkDamping, LinkMatrix, Perturbation, SeedSeparation, Trellising,
};
use kes_cloth::material::Fabric;
use rapier3d::na::DMatrix;

mod common;

const SIGMA: f64 = 0.005;
const NU: usize = 7;
const NV: usize = 5;

fn elastic_generators(topo: &Arc<ClothTopology>, fabric: &Fabric) -> Vec<Box<dyn ForceGenerator>> {
    vec![
        Box::new(Bending::new(topo.clone(), fabric)),
        Box::new(Trellising::new(topo.clone(), fabric)),
        Box::new(SeedSeparation::new(topo.clone(), fabric)),
        Box::new(KesTensile::new(topo.clone(), fabric)),
        Box::new(LinkCompression::new(
            topo.clone(),
            LinkCompression::default_modulus(fabric, SIGMA),
        )),
    ]
}

fn forces(g: &dyn ForceGenerator, topo: &Arc<ClothTopology>, x: &[DVec3], v: &[DVec3]) -> Vec<DVec3> {
    let mut geo = ClothGeometry::new(topo.clone());
    geo.update(x);
    let mut buffer = ForceBuffer::new(topo);
    g.add_forces(&geo, v, &mut buffer);
    buffer.resolve(topo).to_vec()
}

/// The 3N × 3N matrix whose column j is `product(e_j)`.
fn assemble(topo: &Arc<ClothTopology>, product: impl Fn(&Perturbation, &mut ForceBuffer)) -> DMatrix<f64> {
    let n = topo.particle_count;
    let mut m = DMatrix::zeros(3 * n, 3 * n);
    let mut unit = vec![DVec3::ZERO; n];
    let mut dx = Perturbation::new(topo);
    for col in 0..3 * n {
        unit[col / 3][col % 3] = 1.0;
        dx.set(topo, &unit);
        unit[col / 3][col % 3] = 0.0;
        let mut out = ForceBuffer::new(topo);
        product(&dx, &mut out);
        for (p, f) in out.resolve(topo).iter().enumerate() {
            for a in 0..3 {
                m[(3 * p + a, col)] = f[a];
            }
        }
    }
    m
}

fn hessian(g: &dyn ForceGenerator, topo: &Arc<ClothTopology>, x: &[DVec3], definite: bool) -> DMatrix<f64> {
    let mut geo = ClothGeometry::new(topo.clone());
    geo.update(x);
    assemble(topo, |dx, out| {
        g.add_stiffness_product(&geo, dx, 1.0, definite, out)
    })
}

/// −∂F/∂x by central differences of the forces.
fn finite_difference_hessian(g: &dyn ForceGenerator, topo: &Arc<ClothTopology>, x: &[DVec3]) -> DMatrix<f64> {
    let n = x.len();
    let zero = vec![DVec3::ZERO; n];
    let eps = 1e-6 * SIGMA;
    let mut m = DMatrix::zeros(3 * n, 3 * n);
    let mut xp = x.to_vec();
    for col in 0..3 * n {
        let original = xp[col / 3][col % 3];
        xp[col / 3][col % 3] = original + eps;
        let plus = forces(g, topo, &xp, &zero);
        xp[col / 3][col % 3] = original - eps;
        let minus = forces(g, topo, &xp, &zero);
        xp[col / 3][col % 3] = original;
        for p in 0..n {
            for a in 0..3 {
                m[(3 * p + a, col)] = -(plus[p][a] - minus[p][a]) / (2.0 * eps);
            }
        }
    }
    m
}

fn largest(m: &DMatrix<f64>) -> f64 {
    m.amax()
}

fn check_fabric(fabric: &Fabric) {
    let topo = Arc::new(common::patched_rectangle(NU, NV, SIGMA));
    for (state, x) in common::strained_configurations(&topo) {
        for g in elastic_generators(&topo, fabric) {
            let name = format!("{} / {state} / {}", fabric.name, g.effect());
            let exact = hessian(g.as_ref(), &topo, &x, false);
            let scale = largest(&exact);
            if scale == 0.0 {
                continue; // e.g. no link compressed in this state
            }
            let fd = finite_difference_hessian(g.as_ref(), &topo, &x);
            let error = largest(&(&exact - &fd));
            assert!(
                error <= 1e-5 * scale,
                "{name}: Hessian differs from finite differences by {error:e} (largest entry {scale:e})"
            );
            let asymmetry = largest(&(&exact - exact.transpose()));
            assert!(
                asymmetry <= 1e-12 * scale,
                "{name}: exact Hessian asymmetric by {asymmetry:e}"
            );
            let clamped = hessian(g.as_ref(), &topo, &x, true);
            check_definite(&name, &clamped, fabric);
            // A majorant: clamped − exact is positive semi-definite (extra stiffness only damps).
            let excess = &clamped - &exact;
            let lowest = ((&excess + excess.transpose()) * 0.5)
                .symmetric_eigenvalues()
                .min();
            assert!(
                lowest >= -1e-10 * scale,
                "{name}: clamp is below the exact Hessian by {lowest:e}"
            );
        }
    }
}

/// The clamped Hessian is symmetric and positive semi-definite, and the implicit system at
/// h = 1/240 s with the grid's node mass is positive definite.
fn check_definite(name: &str, h: &DMatrix<f64>, fabric: &Fabric) {
    let scale = largest(h).max(f64::MIN_POSITIVE);
    let asymmetry = largest(&(h - h.transpose()));
    assert!(
        asymmetry <= 1e-12 * scale,
        "{name}: clamped Hessian asymmetric by {asymmetry:e}"
    );
    let symmetric = (h + h.transpose()) * 0.5;
    let lowest = symmetric.clone().symmetric_eigenvalues().min();
    assert!(
        lowest >= -1e-10 * scale,
        "{name}: clamped Hessian has eigenvalue {lowest:e} (largest entry {scale:e})"
    );
    let (mass, step) = (fabric.areal_density * SIGMA * SIGMA, 1.0 / 240.0);
    let n = symmetric.nrows();
    let system = DMatrix::identity(n, n) * mass + symmetric * (step * step);
    assert!(
        system.cholesky().is_some(),
        "{name}: M + h²H is not positive definite"
    );
}

#[test]
fn hessians_match_finite_differences_and_clamps_are_definite_for_every_shipped_fabric() {
    for path in common::shipped_fabric_paths() {
        check_fabric(&Fabric::load(&path).unwrap());
    }
}

#[test]
fn hessians_match_finite_differences_and_clamps_are_definite_with_sampled_curves() {
    check_fabric(&Fabric::load(common::crate_path("tests/fabrics/sampled_curves.ron")).unwrap());
}

/// The exact Hessian of bending is indefinite once a thread is bent (tilting both links out of
/// the plane of the bend lowers the energy): the clamp is needed. At the flat rest state the
/// clamp changes nothing (relative 1e-12), except where it stands in for Rapier's joints.
#[test]
fn clamp_is_needed_when_bent_and_exact_at_rest() {
    let fabric = common::shipped_fabric("thick_cotton");
    let topo = Arc::new(ClothTopology::rectangle(NU, NV, SIGMA));
    let configs = common::strained_configurations(&topo);
    let bent = &configs.iter().find(|(n, _)| n == "bent").unwrap().1;
    let bending = Bending::new(topo.clone(), &fabric);
    let exact = hessian(&bending, &topo, bent, false);
    let lowest = ((&exact + exact.transpose()) * 0.5).symmetric_eigenvalues().min();
    assert!(
        lowest < -1e-6 * largest(&exact),
        "bent bending Hessian unexpectedly PSD: {lowest:e}"
    );

    let flat = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    for g in elastic_generators(&topo, &fabric) {
        let (exact, clamped) = (
            hessian(g.as_ref(), &topo, &flat, false),
            hessian(g.as_ref(), &topo, &flat, true),
        );
        if g.effect() == "compression" {
            // The one deliberate exception: the solver's matrix gives links held by rope joints
            // their compression stiffness in stretch too (docs/model.md §12), where the exact
            // Hessian of the one-sided spring is zero (or, for links a rounding error short of
            // σ, already the same axial stiffness).
            assert!(
                largest(&clamped) > 0.0,
                "compression: no stand-in stiffness for the joints"
            );
            continue;
        }
        let difference = largest(&(&exact - &clamped));
        assert!(
            difference <= 1e-12 * largest(&exact).max(f64::MIN_POSITIVE),
            "{}: clamp changes the rest-state Hessian by {difference:e}",
            g.effect()
        );
    }
}

/// C = −∂F/∂v for the dissipative effects, against differences of the (linear) forces.
#[test]
fn damping_products_match_velocity_derivatives() {
    let fabric = common::shipped_fabric("thin_wool");
    let topo = Arc::new(ClothTopology::rectangle(NU, NV, SIGMA));
    let x = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    let mut geo = ClothGeometry::new(topo.clone());
    geo.update(&x);
    let node_mass = fabric.areal_density * SIGMA * SIGMA;
    let dampers: Vec<Box<dyn ForceGenerator>> = vec![
        Box::new(LinkDamping::new(topo.clone(), 150.0, node_mass)),
        Box::new(AirDrag::new(0.8, SIGMA)),
    ];
    let n = topo.particle_count;
    for g in dampers {
        let c = assemble(&topo, |dv, out| g.add_damping_product(dv, 1.0, out));
        let mut v = vec![DVec3::ZERO; n];
        for col in 0..3 * n {
            v[col / 3][col % 3] = 1.0;
            let f = forces(g.as_ref(), &topo, &x, &v);
            v[col / 3][col % 3] = 0.0;
            for p in 0..n {
                for a in 0..3 {
                    let expected = -f[p][a];
                    assert!(
                        (c[(3 * p + a, col)] - expected).abs() <= 1e-12 * c.amax(),
                        "{}: C[{}, {col}] = {:e}, −∂F/∂v = {expected:e}",
                        g.effect(),
                        3 * p + a,
                        c[(3 * p + a, col)]
                    );
                }
            }
        }
    }
}

/// The default compression spring means what `docs/model.md` §9 says: under the Euler buckling
/// load of the strip it stands for (π²·B/σ² per unit width, π²·B/σ on a link σ wide) a link
/// shortens by σ/`BUCKLING_MARGIN`, whatever the fabric and spacing; stretched, it pushes not at
/// all (the rope joint holds that side). Tolerance 1e-9 relative: one product and a subtraction.
#[test]
fn at_the_strips_buckling_load_a_link_shortens_by_one_over_the_margin() {
    for path in common::shipped_fabric_paths() {
        let fabric = Fabric::load(&path).unwrap();
        let b = fabric
            .bending(kes_cloth::material::Thread::Warp)
            .rigidity
            .max(fabric.bending(kes_cloth::material::Thread::Weft).rigidity);
        for sigma in [0.005, 0.01, 0.02] {
            let topo = Arc::new(ClothTopology::rectangle(2, 1, sigma));
            let spring = LinkCompression::new(topo.clone(), LinkCompression::default_modulus(&fabric, sigma));
            let at = |r: f64| [DVec3::ZERO, DVec3::new(r, 0.0, 0.0)];
            let v = [DVec3::ZERO; 2];
            let euler_load = std::f64::consts::PI.powi(2) * b / sigma;
            let pushed = forces(
                &spring,
                &topo,
                &at(sigma * (1.0 - 1.0 / kes_cloth::forces::BUCKLING_MARGIN)),
                &v,
            );
            assert!(
                (pushed[1].x / euler_load - 1.0).abs() < 1e-9 && pushed[1].x > 0.0,
                "{}: σ {sigma}: force {} N against the Euler load {euler_load} N",
                fabric.name,
                pushed[1].x
            );
            assert!(
                (pushed[0] + pushed[1]).length() < 1e-12 * euler_load,
                "equal and opposite"
            );
            let stretched = forces(&spring, &topo, &at(1.01 * sigma), &v);
            assert_eq!(
                stretched[1],
                DVec3::ZERO,
                "one-sided: no push on a stretched link"
            );
        }
    }
}

/// The assembled matrix of `fill` (which adds its blocks into a cleared [`LinkMatrix`]) as a
/// dense 3N × 3N matrix, read through the assembled product, and its particle diagonal blocks.
fn assembled(topo: &Arc<ClothTopology>, fill: impl Fn(&mut LinkMatrix)) -> (DMatrix<f64>, Vec<DMat3>) {
    let mut matrix = LinkMatrix::new(topo);
    fill(&mut matrix);
    let dense = assemble(topo, |dx, out| {
        matrix.product(topo, dx, out);
    });
    let mut blocks = vec![DMat3::ZERO; topo.particle_count];
    matrix.add_particle_diagonal(topo, &mut blocks);
    (dense, blocks)
}

fn check_same(name: &str, expected: &DMatrix<f64>, (dense, blocks): &(DMatrix<f64>, Vec<DMat3>)) {
    let scale = largest(expected).max(f64::MIN_POSITIVE);
    let error = largest(&(dense - expected));
    assert!(
        error <= 1e-12 * scale,
        "{name}: assembled matrix differs from the product's by {error:e} (largest entry {scale:e})"
    );
    for (p, block) in blocks.iter().enumerate() {
        for (a, column) in [block.x_axis, block.y_axis, block.z_axis].iter().enumerate() {
            for r in 0..3 {
                let e = expected[(3 * p + r, 3 * p + a)];
                assert!(
                    (column[r] - e).abs() <= 1e-12 * scale,
                    "{name}: diagonal block of particle {p} entry ({r}, {a}) is {:e}, not {e:e}",
                    column[r]
                );
            }
        }
    }
}

/// What the solver assembles is what the matrix-free products (checked above against finite
/// differences) multiply by: every elastic effect including friction, on every strained state,
/// and the dissipative effects.
#[test]
fn assembled_matrices_equal_the_products() {
    let fabric = common::shipped_fabric("thick_cotton");
    let topo = Arc::new(common::patched_rectangle(NU, NV, SIGMA));
    let flat = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    for (state, x) in common::strained_configurations(&topo) {
        let mut geo = ClothGeometry::new(topo.clone());
        // Friction elements carry state: advance them from the flat sheet, as a run would.
        let mut hysteresis = Hysteresis::new(topo.clone(), &fabric, true, true);
        geo.update(&flat);
        hysteresis.advance_state(&geo);
        geo.update(&x);
        let mut generators = elastic_generators(&topo, &fabric);
        generators.push(Box::new(hysteresis));
        for g in &generators {
            let name = format!("{state} / {}", g.effect());
            let expected = hessian(g.as_ref(), &topo, &x, true);
            let got = assembled(&topo, |m| g.add_stiffness_blocks(&geo, 1.0, m));
            check_same(&name, &expected, &got);
        }
    }
    let node_mass = fabric.areal_density * SIGMA * SIGMA;
    let dampers: Vec<Box<dyn ForceGenerator>> = vec![
        Box::new(LinkDamping::new(topo.clone(), 150.0, node_mass)),
        Box::new(AirDrag::new(0.8, SIGMA)),
    ];
    for g in dampers {
        let expected = assemble(&topo, |dv, out| g.add_damping_product(dv, 1.0, out));
        let got = assembled(&topo, |m| g.add_damping_blocks(1.0, m));
        check_same(g.effect(), &expected, &got);
    }
}
