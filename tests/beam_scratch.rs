use nanobeam::beam::*;
#[test]
fn scratch() {
    let mut b = BeamSpec { length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1e12, density_kg_m3: 2300.0,
        support: Support::SimplySupported, elements: 20, nonlocal_e0a_nm: 0.0, viscous_damping_n_s_m2: 0.0,
        internal_variables: vec![], support_rotational_stiffness_n_m_rad: 0.0, point_mass: None };
    println!("{:?}", modal(&b, 3));
    b.nonlocal_e0a_nm = 0.5; b.viscous_damping_n_s_m2 = 1e-5;
    b.internal_variables = vec![InternalVariable{delta:0.1, omega_rad_s: 1e11}, InternalVariable{delta:0.05, omega_rad_s: 3e12}];
    for sup in Support::ALL { b.support = sup;
    let f = modal(&b, 3).unwrap(); let s = modal_state_space(&b, 3).unwrap();
    println!("{:?}\n{:?}", f, s);
    b.support_rotational_stiffness_n_m_rad = 1e-18;
    b.point_mass = Some(PointMass{mass_kg: 1e-24, x_nm: 3.0});
    let f = modal(&b, 3).unwrap(); let s = modal_state_space(&b, 3).unwrap();
    println!("EXT {:?}\n{:?}", f, s);
    b.support_rotational_stiffness_n_m_rad = 0.0; b.point_mass = None;
    }
    let t = std::time::Instant::now();
    for _ in 0..1000 { modal(&b, 3).unwrap(); }
    println!("fast {:?}", t.elapsed()/1000);
    b.support_rotational_stiffness_n_m_rad = 1e-18;
    let t = std::time::Instant::now();
    for _ in 0..100 { modal(&b, 3).unwrap(); }
    println!("general {:?}", t.elapsed()/100);
    let t = std::time::Instant::now();
    for _ in 0..10 { modal_state_space(&b, 3).unwrap(); }
    println!("ss {:?}", t.elapsed()/10);
}
