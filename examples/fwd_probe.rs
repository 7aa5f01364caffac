use nanobeam::diagnose::{forward, synthetic};
use std::time::Instant;
fn main() {
    let mut b = synthetic::nominal_beam();
    b.nonlocal_e0a_nm = 1.0;
    b.internal_variables = vec![nanobeam::beam::InternalVariable{delta:0.4, omega_rad_s:5e11}];
    let t = Instant::now();
    let n = 2000;
    for _ in 0..n { std::hint::black_box(forward::predict(&b, 6).unwrap()); }
    println!("{:?} per eval", t.elapsed() / n);
}
