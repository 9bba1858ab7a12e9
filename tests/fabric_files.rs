//! Fabric files: every shipped fabric loads and is plausible; every bad file in
//! `tests/bad_fabrics/` is rejected with the message its `// expect:` lines give, naming the
//! file and the field (or line and column), without a panic.

use kes_cloth::material::{Fabric, Thread};

mod common;

#[test]
fn every_shipped_fabric_loads_with_an_honest_source() {
    let paths = common::shipped_fabric_paths();
    assert!(paths.len() >= 4, "ship at least four fabrics");
    for path in paths {
        let f = Fabric::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!f.source.trim().is_empty());
        // Broad physical plausibility of woven apparel fabrics, in SI.
        assert!(
            (0.05..0.6).contains(&f.areal_density),
            "{}: ρ_A {}",
            f.name,
            f.areal_density
        );
        for t in [Thread::Warp, Thread::Weft] {
            let c = f.bending_length(t);
            assert!((0.005..0.1).contains(&c), "{}: bending length {c} m", f.name);
        }
    }
}

#[test]
fn the_seed_fabrics_are_shipped_and_ordered() {
    let cotton = common::shipped_fabric("thick_cotton");
    let wool = common::shipped_fabric("thin_wool");
    // The seed's premise: thick cotton is stiffer in bending and shear, and heavier.
    assert!(cotton.bending_length(Thread::Warp) > wool.bending_length(Thread::Warp));
    assert!(cotton.shear.rigidity > wool.shear.rigidity);
    assert!(cotton.areal_density > wool.areal_density);
}

/// A generated shear curve F = G·sin φ reproduces the KES slope G between 0.5° and 5° within
/// 0.2 % (the sine bends by 0.1 % over that range).
#[test]
fn generated_shear_curve_has_the_kes_slope() {
    let f = common::shipped_fabric("thick_cotton");
    let (a, b) = (0.5f64.to_radians(), 5f64.to_radians());
    let slope = (f.shear_force_at_angle(b) - f.shear_force_at_angle(a)) / (b - a);
    assert!((slope / f.shear.rigidity - 1.0).abs() < 2e-3);
}

/// The tensile power law reproduces EMT (T(EMT) = T_m) and WT (its work to EMT), exactly.
#[test]
fn tensile_law_reproduces_emt_and_wt() {
    for path in common::shipped_fabric_paths() {
        let f = Fabric::load(&path).unwrap();
        for t in [Thread::Warp, Thread::Weft] {
            let p = f.tensile(t);
            let emt = p.law.strain_at_max_load;
            assert!((p.law.tension(emt) / p.law.max_load - 1.0).abs() < 1e-12);
            // WT in the file is rounded; the law's work equals LT·T_m·EMT/2 exactly and WT
            // within the 5 % the loader accepts.
            let work = p.law.energy_density(emt);
            assert!((work / (p.linearity * p.law.max_load * emt / 2.0) - 1.0).abs() < 1e-12);
            assert!((work / p.energy - 1.0).abs() < 0.05);
        }
    }
}

#[test]
fn bad_fabric_files_give_their_expected_messages() {
    let dir = common::crate_path("tests/bad_fabrics");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let expects = common::expect_lines(&path);
        assert!(!expects.is_empty(), "{}: no `// expect:` line", path.display());
        let message = common::rejection_message(&path, || Fabric::load(&path));
        assert!(
            message.contains(&path.display().to_string()),
            "message lacks the path: {message}"
        );
        for e in &expects {
            assert!(
                message.contains(e.as_str()),
                "{}:\n  got      {message}\n  expected {e}",
                path.display()
            );
        }
        count += 1;
    }
    assert!(count >= 10);
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let e = Fabric::load("assets/fabrics/no_such_fabric.ron").unwrap_err();
    assert!(
        e.to_string()
            .contains("no_such_fabric.ron: cannot read fabric file")
    );
}
