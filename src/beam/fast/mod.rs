//! The exact accelerators. Each computes what a reference solver of `solve`
//! computes, faster, on the models where an exact structure allows it, and
//! declines (returns `None`/`false`) elsewhere, so the dispatch falls back to
//! the reference. Each is certified: an interpolant carries its error bound,
//! a secular root its inertia count.
//!
//! Interpolated spectra (eigenvalues as certified Chebyshev interpolants):
//! - `spectrum`: the Euler–Bernoulli pencil in (e0a/L)², per mesh, mode and
//!   e0a piece;
//! - `shear_spectrum`: the nonlocal Timoshenko pencil in ((e0a/L)², 1/g̃),
//!   per mesh and dyadic cell;
//! - `mass_spectrum`: a point mass with C = 0, a secular equation over the
//!   whole spectrum, its eigenpairs interpolated with an error bound per
//!   evaluation.
//!
//! Wavenumber blocks (a uniform simply supported mesh split exactly into one
//! small block per wavenumber, the invariance checked on the assembled mesh):
//! - `axial_spectrum`: the axial force (2 × 2 blocks; Newton on each block's
//!   determinant for the oscillatory poles);
//! - `spring_spectrum`: support rotational springs, with or without the
//!   axial force, a rank ≤ 2 update of the blocks (a 1 × 1 or 2 × 2 secular
//!   determinant in O(n_e); partial fractions without an axial force);
//! - `secular`: what the secular paths share: the blocks' algebra, the
//!   certified eigenvalue search, the blocks' spectrum;
//! - `spring_mass`: springs and a point mass together (a secular determinant
//!   of order ≤ 3, its removed poles bordered);
//! - `mass_blocks`: a point mass with viscous damping, an axial force or
//!   internal variables (a rank-1 update, one scalar secular function per
//!   pole);
//! - `axial_spectrum`, `spring_spectrum`, `spring_mass` and `mass_blocks`
//!   take a hysteretic loss factor as well (G(s)(1 + iη) in every block,
//!   `jet::Modulus`; `axial_spectrum`'s module doc);
//! - `shear_blocks`: the Timoshenko mesh as a mirror mesh split into 5 × 5
//!   blocks bordered by χ₀, χ_L, s_L (det T̃(s) as block determinants times
//!   a 3 × 3 Schur complement, the order by Haynsworth's inertia), and
//!   `shear_poles`, Newton on its bordered determinant for the oscillatory
//!   poles (opt-in: `ModalSolver::with_shear_blocks`; a tension, not a
//!   compression: `modal.rs`'s `families_below`);
//! - `shear_continuum`: the uniform simply supported Timoshenko beam with an
//!   axial force, viscous damping, springs or a point mass in closed form
//!   (the mesh's continuum limit, within the mesh's discretisation error),
//!   with `continuum_tail` (the blocks beyond the kept ones in closed form);
//! - `jet`: a value and its derivative over f64 or Complex64, for the
//!   secular functions, and the modulus G(s)(1 + iη) they relax K̃ by.
//!
//! - `gradient_blocks`: the strain gradient (l > 0, the C² mesh of
//!   `fe::model::GradientMesh`) on a uniform simply supported mesh without
//!   springs or a point mass: 3 × 3 blocks (w, w′, w″ per node), with or
//!   without relaxations, viscous damping, an axial force, a foundation, a
//!   loss factor; the eigenvalues and the poles' functional by Gauss energy
//!   sums on the block vector.
//!
//! Only `gradient_blocks` holds a strain gradient: every other path was
//! derived for the fourth-order operator on the cubic (or Timoshenko) mesh
//! and declines the C² mesh (the dispatch sends it to `gradient_blocks`
//! first); a strain-gradient beam off that path's hypotheses (clamped or
//! free ends, springs, a point mass) takes the reference solvers of `solve`.
//!
//! Invariant: used only by the dispatch (`beam::modal`) and by the beam's
//! face for the certificates tests read; `tests/tidy.rs` holds every room of
//! `beam` to the table in ARCHITECTURE.md. The comparisons every path is held
//! to are in `tests/fast_path_check`.

pub(crate) mod axial_spectrum;
pub(crate) mod continuum_tail;
pub(crate) mod gradient_blocks;
pub(crate) mod jet;
pub(crate) mod mass_blocks;
pub(crate) mod mass_spectrum;
pub(crate) mod secular;
pub(crate) mod shear_blocks;
pub(crate) mod shear_continuum;
pub(crate) mod shear_poles;
pub(crate) mod shear_spectrum;
pub(crate) mod spectrum;
pub(crate) mod spring_mass;
pub(crate) mod spring_spectrum;
