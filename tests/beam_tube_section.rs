//! The tube section of the beam file (`section: { tube: { wall_nm } }`).
//!
//! References, none computed by the code under test: the annulus' area and
//! second moment written out from its radii (d ± t)/2; Cowper's (1966) shear
//! coefficients; the clamped–clamped and clamped–free Euler–Bernoulli
//! frequencies (βL)² √(EI/ρA)/L² with the tabulated roots βL of
//! cos βL cosh βL = ±1 (Blevins, *Formulas for Natural Frequency and Mode
//! Shape*, Table 8-1). The beams are hand-written YAML; no generator.

use std::f64::consts::PI;
use std::process::Command;

use nanobeam::beam::{modal, BeamSpec, Support};

/// A (5,5) carbon nanotube as a tube: mean diameter 0.678 nm, wall 0.34 nm.
const TUBE: &str = "length_nm: 7.4\ndiameter_nm: 0.678\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2270\n\
                    support: clamped-clamped\nelements: 40\nsection: { tube: { wall_nm: 0.34 } }\n";

fn tube(extra: &str) -> Result<BeamSpec, String> {
    BeamSpec::from_yaml(&format!("{TUBE}{extra}")).map_err(|e| e.to_string())
}

#[test]
fn area_and_second_moment_are_the_annulus() {
    let b = tube("").unwrap();
    let (d, t) = (0.678e-9, 0.34e-9);
    // from the radii: A = π(ro² − ri²), I = π(ro⁴ − ri⁴)/4
    let (ro, ri) = ((d + t) / 2.0, (d - t) / 2.0);
    let a_radii = PI * (ro * ro - ri * ri);
    let i_radii = PI * (ro.powi(4) - ri.powi(4)) / 4.0;
    // the closed forms: A = π d t, I = π d³ t/8 (1 + (t/d)²)
    let a_closed = PI * d * t;
    let i_closed = PI * d.powi(3) * t / 8.0 * (1.0 + (t / d).powi(2));
    // a handful of roundings of O(1) operations: 1e-14 relative is ~50 ulp
    for (got, want) in
        [(b.area_m2(), a_radii), (b.area_m2(), a_closed), (b.inertia_m4(), i_radii), (b.inertia_m4(), i_closed)]
    {
        assert!((got / want - 1.0).abs() < 1e-14, "{got} vs {want}");
    }
}

#[test]
fn without_a_section_the_beam_is_the_solid_circle_unchanged() {
    let yaml = "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1e12\ndensity_kg_m3: 2300\nsupport: clamped-free\nelements: 20\n";
    let b = BeamSpec::from_yaml(yaml).unwrap();
    assert_eq!(b.section, None);
    assert!((b.area_m2() / (PI * 1e-18 / 4.0) - 1.0).abs() < 1e-15);
    assert!((b.inertia_m4() / (PI * 1e-36 / 64.0) - 1.0).abs() < 1e-15);
    // written back without a `section` key: existing outputs keep their bytes
    assert!(!serde_yaml::to_string(&b).unwrap().contains("section"));
    let t = tube("").unwrap();
    let back = BeamSpec::from_yaml(&serde_yaml::to_string(&t).unwrap()).unwrap();
    assert_eq!(back, t);
}

#[test]
fn shear_coefficient_defaults_to_the_sections() {
    let nu: f64 = 0.2;
    let t = tube("shear_deformation: { poisson_ratio: 0.2 }\n").unwrap();
    // Cowper (1966), Table 1: thin-walled round tube 2(1+ν)/(4+3ν)
    let k = t.shear_deformation.unwrap().shear_coefficient;
    assert!((k - 2.0 * (1.0 + nu) / (4.0 + 3.0 * nu)).abs() < 1e-15, "{k}");
    assert!((k - 0.5217).abs() < 1e-4, "{k}");
    let s = BeamSpec::from_yaml(
        "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1e12\ndensity_kg_m3: 2300\nsupport: clamped-free\n\
         elements: 20\nshear_deformation: { poisson_ratio: 0.2 }\n",
    )
    .unwrap();
    // Cowper (1966), Table 1: solid circle 6(1+ν)/(7+6ν)
    let k = s.shear_deformation.unwrap().shear_coefficient;
    assert!((k - 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)).abs() < 1e-15, "{k}");
    // a given coefficient is kept
    let g = tube("shear_deformation: { poisson_ratio: 0.2, shear_coefficient: 0.7 }\n").unwrap();
    assert_eq!(g.shear_deformation.unwrap().shear_coefficient, 0.7);
}

#[test]
fn bad_walls_are_refused_naming_field_value_and_range() {
    let with_wall = |w: &str| {
        BeamSpec::from_yaml(&TUBE.replace("wall_nm: 0.34", &format!("wall_nm: {w}"))).map_err(|e| e.to_string())
    };
    let e = with_wall("0.7").unwrap_err();
    assert!(e.starts_with("invalid section.tube.wall_nm = 0.7: allowed 0 < wall_nm < diameter_nm = 0.678"), "{e}");
    assert!(!e.contains('\n'));
    let e = with_wall("0.678").unwrap_err();
    assert!(e.starts_with("invalid section.tube.wall_nm = 0.678"), "{e}");
    for bad in ["0", "-0.1", ".nan"] {
        let e = with_wall(bad).unwrap_err();
        assert!(e.starts_with("invalid section.tube.wall_nm"), "{bad}: {e}");
    }
    let e = BeamSpec::from_yaml(&TUBE.replace("wall_nm: 0.34", "wall_nm: 0.34, mean_diameter_nm: 0.7"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("mean_diameter_nm"), "{e}");
}

/// Euler–Bernoulli closed form with the annulus' EI and ρA, against the
/// Hermite-cubic FE model of 200 elements. The cubic element's eigenvalue
/// error is ≈ (βh)⁴/720 relative with h = L/200 (O(h⁴)); for the highest
/// root used, βL = 14.14, that is 3.5e-8 in λ, 1.7e-8 in ω. The tabulated βL
/// carry 8 digits (relative error ≤ 2e-8 in (βL)²). 1e-6 holds both with
/// a 20-fold margin.
#[test]
fn modal_frequencies_match_euler_bernoulli_with_the_tube_section() {
    let (d, t, l, e, rho) = (0.678e-9, 0.34e-9, 7.4e-9, 1.0e12, 2270.0);
    let ei = e * PI * d * t * (d * d + t * t) / 8.0;
    let rho_a = rho * PI * d * t;
    // roots of cos βL cosh βL = 1 (clamped–clamped) and = −1 (clamped–free)
    let cases = [
        (Support::ClampedClamped, [4.730_040_7, 7.853_204_6, 10.995_607_8, 14.137_165_5]),
        (Support::ClampedFree, [1.875_104_1, 4.694_091_1, 7.854_757_4, 10.995_540_7]),
    ];
    for (support, roots) in cases {
        let mut b = tube("").unwrap();
        b.support = support;
        b.elements = 200;
        let modes = modal(&b, 4).unwrap().modes;
        for (m, bl) in modes.iter().zip(roots) {
            let want = bl * bl * (ei / rho_a).sqrt() / (l * l);
            assert!((m.omega_rad_s / want - 1.0).abs() < 1e-6, "{support:?}: {} vs {want}", m.omega_rad_s);
        }
    }
}

#[test]
fn cli_refuses_a_wall_thicker_than_the_diameter_with_exit_2_and_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("b.yaml");
    std::fs::write(&p, TUBE.replace("wall_nm: 0.34", "wall_nm: 1.2")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(["modal", p.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("section.tube.wall_nm = 1.2"), "{err}");
    assert!(out.stdout.is_empty());
}
