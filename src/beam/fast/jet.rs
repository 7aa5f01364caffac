//! A value and its first derivative over [`Num`] (f64 on the real axis,
//! Complex64 at a pole): the form the secular functions of the block paths
//! (`spring_spectrum.rs`, `mass_blocks.rs`) and the continuum tails
//! (`continuum_tail.rs`) are written in, one Newton step needing both. Apart
//! from those files so that each can use it without a circle between them;
//! the factorisations' dual numbers are `dual.rs`'s.

use num_complex::Complex64;

/// A number the secular functions are evaluated in: f64 on the real axis,
/// Complex64 at a pole.
pub(crate) trait Num:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Add<f64, Output = Self>
    + std::ops::Mul<f64, Output = Self>
    + From<f64>
{
    /// |x|: the continuum tail's validity test reads magnitudes.
    fn modulus(self) -> f64;
    /// The number as a complex one, and back (the real part on the real
    /// axis, where the continuum's closed forms are real up to rounding).
    fn to_complex(self) -> Complex64;
    fn from_complex(c: Complex64) -> Self;
    /// 1/x: one real division for a complex x (num_complex's `1 / x` is a
    /// full complex quotient, two), which the partial-fraction sums of
    /// `spring_spectrum.rs` take once per term.
    fn recip(self) -> Self;
}
impl Num for f64 {
    fn modulus(self) -> f64 {
        self.abs()
    }
    fn to_complex(self) -> Complex64 {
        Complex64::new(self, 0.0)
    }
    fn from_complex(c: Complex64) -> Self {
        c.re
    }
    fn recip(self) -> Self {
        1.0 / self
    }
}
impl Num for Complex64 {
    fn modulus(self) -> f64 {
        self.norm()
    }
    fn to_complex(self) -> Complex64 {
        self
    }
    fn from_complex(c: Complex64) -> Self {
        c
    }
    fn recip(self) -> Self {
        let w = 1.0 / self.norm_sqr();
        Complex64::new(self.re * w, -self.im * w)
    }
}

/// A value with its derivative.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Jet<T> {
    pub(crate) v: T,
    pub(crate) d: T,
}

impl<T: Num> Jet<T> {
    pub(crate) fn c(v: f64) -> Self {
        Jet { v: T::from(v), d: T::from(0.0) }
    }
    pub(crate) fn mul(self, o: Self) -> Self {
        Jet { v: self.v * o.v, d: self.d * o.v + self.v * o.d }
    }
    pub(crate) fn add(self, o: Self) -> Self {
        Jet { v: self.v + o.v, d: self.d + o.d }
    }
    pub(crate) fn sub(self, o: Self) -> Self {
        Jet { v: self.v - o.v, d: self.d - o.d }
    }
    pub(crate) fn scale(self, c: f64) -> Self {
        Jet { v: self.v * T::from(c), d: self.d * T::from(c) }
    }
    pub(crate) fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Jet { v, d: (self.d - v * o.d) / o.v }
    }
}

/// The modulus the secular paths relax the stiffness by: the internal
/// variables' G(s) times (1 + iη) with a hysteretic loss factor η ≥ 0, as
/// the coupled reference takes it (`ScaledModel::relaxation`: the modulus
/// of positive frequencies, valid in the upper half plane where the
/// oscillatory poles are found; a loss factor has no real poles). Only the
/// relaxed stiffness K̃ carries it: the springs, the axial force and the
/// foundation are elastic (`fe::scaling`'s module doc).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Modulus<'a> {
    /// (Δᵢ, Ω̃ᵢ) of the active internal variables.
    pub(crate) ivs: &'a [(f64, f64)],
    /// η (0: none).
    pub(crate) loss: f64,
}

impl<'a> Modulus<'a> {
    /// The modulus of the internal variables alone (η = 0).
    pub(crate) fn relaxed(ivs: &'a [(f64, f64)]) -> Self {
        Modulus { ivs, loss: 0.0 }
    }

    /// G(s)(1 + iη) and its derivative at `s`; exactly [`relaxation`]'s
    /// bits when η = 0.
    pub(crate) fn at(&self, s: Complex64) -> Jet<Complex64> {
        let g = relaxation(self.ivs, s);
        if self.loss == 0.0 {
            return g;
        }
        let h = Complex64::new(1.0, self.loss);
        Jet { v: g.v * h, d: g.d * h }
    }
}

/// G(s) = 1 + Σᵢ Δᵢ s/(s + Ω̃ᵢ) and G′(s) = Σᵢ Δᵢ Ω̃ᵢ/(s + Ω̃ᵢ)² of the internal
/// variables `ivs` = (Δᵢ, Ω̃ᵢ) (`model.rs`: the relaxation factor of the
/// stiffness).
pub(crate) fn relaxation(ivs: &[(f64, f64)], s: Complex64) -> Jet<Complex64> {
    let (mut g, mut dg) = (Complex64::new(1.0, 0.0), Complex64::new(0.0, 0.0));
    for &(d, w) in ivs {
        let den = s + w;
        g += d * s / den;
        dg += d * w / (den * den);
    }
    Jet { v: g, d: dg }
}
