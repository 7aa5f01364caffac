//! Forward-mode dual numbers `v + d·ε` (ε² = 0), used to differentiate a
//! factorisation with respect to its scalar parameter (σ or s) in one pass:
//! if A(σ) = L D Lᵀ (or P A = L U) then d/dσ log det A = Σ dᵢ'/dᵢ over the pivots.
//! Hand-written (a dozen lines) because none of the listed crates provides a
//! dual number generic over real *and* complex scalars.

use std::ops::{Add, Div, Mul, Neg, Sub};

use num_complex::Complex64;

/// The scalar operations the factorisations need.
pub trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    fn zero() -> Self;
    /// Magnitude of the value part (for pivot choice).
    fn magnitude(self) -> f64;
}

impl Scalar for f64 {
    fn zero() -> Self {
        0.0
    }
    fn magnitude(self) -> f64 {
        self.abs()
    }
}

impl Scalar for Complex64 {
    fn zero() -> Self {
        Complex64::new(0.0, 0.0)
    }
    /// √(re² + im²) without `hypot`'s over/underflow guard: glibc's hypot was
    /// ~10 % of a coupled-path solve (three calls per pivot of every complex
    /// LDLᵀ in `modal`'s RQI). The guard only matters for |z| outside
    /// (1e-154, 1e154), and the factorised matrices are nondimensional with
    /// entries of order 1 to 1e8; a pivot choice compares magnitudes, which
    /// the two formulas order alike to within one ulp.
    fn magnitude(self) -> f64 {
        self.norm_sqr().sqrt()
    }
}

/// A value and its derivative with respect to one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual<T> {
    pub v: T,
    pub d: T,
}

impl<T> Dual<T> {
    pub fn new(v: T, d: T) -> Self {
        Self { v, d }
    }
}

impl<T: Scalar> Add for Dual<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual::new(self.v + o.v, self.d + o.d)
    }
}
impl<T: Scalar> Sub for Dual<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual::new(self.v - o.v, self.d - o.d)
    }
}
impl<T: Scalar> Mul for Dual<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Dual::new(self.v * o.v, self.v * o.d + self.d * o.v)
    }
}
impl<T: Scalar> Div for Dual<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let q = self.v / o.v;
        Dual::new(q, (self.d - q * o.d) / o.v)
    }
}
impl<T: Scalar> Neg for Dual<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual::new(-self.v, -self.d)
    }
}
impl<T: Scalar> Scalar for Dual<T> {
    fn zero() -> Self {
        Dual::new(T::zero(), T::zero())
    }
    fn magnitude(self) -> f64 {
        self.v.magnitude()
    }
}

impl From<f64> for Dual<f64> {
    fn from(v: f64) -> Self {
        Dual::new(v, 0.0)
    }
}

impl From<f64> for Dual<Complex64> {
    fn from(v: f64) -> Self {
        Dual::new(Complex64::new(v, 0.0), Complex64::new(0.0, 0.0))
    }
}
