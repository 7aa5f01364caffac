//! The oscillatory poles of shear deformation with viscous damping or
//! relaxation on the bordered wavenumber-block pencil of `shear_blocks`:
//! Newton on its determinant from the certified eigenpairs.

use num_complex::Complex64;

use crate::beam::fast::axial_spectrum::secular_families;
use crate::beam::fast::jet::Modulus;
use crate::beam::fast::secular::CERTIFY_GAP;
use crate::beam::fast::shear_blocks::ShearPencil;
use crate::beam::linalg::dual::Dual;
use crate::beam::solve::family::Roots;

/// The poles of families 1..=n_modes (scaled units) of the beam whose
/// pencil is `pencil`, with damping c̃ and internal variables `ivs`, into
/// `roots`: every pole when `all`, else the oscillatory pairs only. Family r
/// starts, as the coupled reference does (`coupled.rs`), from the one-term
/// family of the certified r-th eigenpair (c_φ = c̃·xᵀM̃_bx/xᵀM̃x); Newton on
/// the bordered determinant that keeps the eigenvector's dominant block
/// ([`ShearPencil::determinant`]), with the reference's acceptance tests
/// (`axial_spectrum::accept_pair`). `false` when the path declines (a count
/// that fails, a real start when `all`, a root that fails a test): the
/// caller then runs the reference.
pub fn family_roots(
    pencil: &ShearPencil,
    c: f64,
    ivs: &[(f64, f64)],
    n_modes: usize,
    all: bool,
    roots: &mut Vec<Roots>,
) -> bool {
    let mut floor = 0.0;
    let family = |r0| {
        let lambda = pencil.eigenvalue(r0, floor)?;
        // the count is certified r0 + 1 there (`eigenvalue`); at λ itself it
        // is not (S and the nearest block are singular to rounding)
        floor = lambda * (1.0 + CERTIFY_GAP);
        let md = pencil.mode(lambda)?;
        Some(((md.a, md.b, c * md.damping_share), md.block))
    };
    let step = |&block: &_, s| match pencil.determinant(coefficients(s, c, ivs), Some(block), |_| ()) {
        Some(det) => det.v / det.d,
        None => Complex64::new(f64::NAN, f64::NAN),
    };
    // a loss factor is not taken on the Timoshenko paths (`modal.rs`)
    secular_families(n_modes, all, Modulus::relaxed(ivs), roots, family, step)
}

/// The coefficients (s², s c̃, G(s), 1) at s with G = 1 + Σᵢ Δᵢ s/(s + Ωᵢ),
/// each with its derivative in s.
pub fn coefficients(s: Complex64, c: f64, ivs: &[(f64, f64)]) -> [Dual<Complex64>; 4] {
    let one = Complex64::new(1.0, 0.0);
    let zero = Complex64::new(0.0, 0.0);
    let (mut g, mut dg) = (one, zero);
    for &(d, w) in ivs {
        let den = s + w;
        g += d * s / den;
        dg += d * w / (den * den);
    }
    [Dual::new(s * s, 2.0 * s), Dual::new(s * c, Complex64::new(c, 0.0)), Dual::new(g, dg), Dual::new(one, zero)]
}
