//! KES → SI conversion factors, each checked against its hand derivation from g_n = 9.80665.

use kes_cloth::material::{GRAM_FORCE, KesUnit, STANDARD_GRAVITY};

/// Relative tolerance: the factors are exact products of powers of ten and g_n, so only the
/// last bits of the f64 representation may differ.
const EXACT: f64 = 1e-14;

fn assert_factor(unit: KesUnit, expected: f64) {
    let got = unit.factor();
    assert!(
        ((got - expected) / expected).abs() < EXACT,
        "{unit:?}: factor {got}, expected {expected}"
    );
    // Round trip through the inverse used for reports.
    let v = 1.2345;
    assert!(
        (unit.from_si(unit.to_si(v)) - v).abs() < 1e-14,
        "{unit:?} round trip"
    );
}

#[test]
fn gram_force_is_exactly_g_n_milli_newton() {
    assert_eq!(STANDARD_GRAVITY, 9.80665);
    assert!((GRAM_FORCE - 9.80665e-3).abs() < 1e-18);
}

#[test]
fn bending_rigidity_gf_cm2_per_cm_to_newton_metre() {
    assert_factor(KesUnit::BendingRigidity, 9.80665e-5);
}

#[test]
fn moment_per_width_gf_cm_per_cm_to_newton() {
    assert_factor(KesUnit::MomentPerWidth, 9.80665e-3);
}

#[test]
fn curvature_per_cm_to_per_metre() {
    assert_factor(KesUnit::Curvature, 100.0);
}

/// G is per degree: forgetting the 180/π makes shear 57 times too soft.
#[test]
fn shear_rigidity_per_degree_becomes_per_radian_times_180_over_pi() {
    let per_degree = 0.980665; // gf/cm in N/m
    assert_factor(KesUnit::ShearRigidity, per_degree * 180.0 / std::f64::consts::PI);
    assert!((KesUnit::ShearRigidity.factor() - 56.18800).abs() < 1e-4);
}

#[test]
fn force_per_length_gf_per_cm_to_newton_per_metre() {
    assert_factor(KesUnit::ForcePerLength, 0.980665);
}

#[test]
fn tensile_energy_gf_cm_per_cm2_to_joule_per_m2() {
    assert_factor(KesUnit::TensileEnergy, 0.980665);
}

#[test]
fn areal_weight_mg_per_cm2_to_kg_per_m2() {
    assert_factor(KesUnit::ArealWeight, 0.01);
}

#[test]
fn thickness_mm_to_metre() {
    assert_factor(KesUnit::Thickness, 1e-3);
}

#[test]
fn percent_to_fraction() {
    assert_factor(KesUnit::Percent, 0.01);
}

#[test]
fn degree_to_radian() {
    assert_factor(KesUnit::Degree, std::f64::consts::PI / 180.0);
}
