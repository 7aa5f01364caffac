use nanobeam::diagnose::{forward, synthetic};
use std::time::Instant;
fn main() {
    let mut b = synthetic::nominal_beam();
    b.nonlocal_e0a_nm = 1.0;
    b.internal_variables = vec![nanobeam::beam::InternalVariable{delta:0.4, omega_rad_s:5e11}];
    for v in 0..3 {
        let mut b = b.clone();
        if v == 1 { b.point_mass = Some(nanobeam::beam::PointMass{mass_kg: 1e-24, x_nm: 3.0}); }
        if v == 2 { b.support_rotational_stiffness_n_m_rad = 1e-19; }
        let t = Instant::now();
        let n = 2000;
        for _ in 0..n { std::hint::black_box(forward::predict(&b, 6).unwrap()); }
        println!("{v}: {:?} per eval", t.elapsed() / n);
    }
}
