//! The two small traits that let one copy of the physics math serve both precisions:
//! `f64` + [`DVec3`] in the reference backend, `f32` + [`Vec3A`]/[`Vec3`] in the fast one.
//! They expose exactly the operations the equations use, with glam's own implementations.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use glam::{DVec3, Vec3, Vec3A};

/// A floating-point scalar (`f32` or `f64`).
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// Converts (rounding) from `f64`.
    fn from_f64(x: f64) -> Self;
    /// Converts (exactly) to `f64`.
    fn to_f64(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Larger of two values.
    fn max(self, other: Self) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;
}

macro_rules! impl_real {
    ($t:ty) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline]
            fn max(self, other: Self) -> Self {
                <$t>::max(self, other)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}
impl_real!(f32);
impl_real!(f64);

/// A 3-vector over a [`Real`].
pub trait Vector:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<<Self as Vector>::Real, Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// The scalar type.
    type Real: Real;
    /// (0, 0, 0).
    const ZERO: Self;
    /// (0, 1, 0): the up direction and the floor's normal.
    const UNIT_Y: Self;
    /// Dot product.
    fn dot(self, other: Self) -> Self::Real;
    /// Cross product.
    fn cross(self, other: Self) -> Self;
    /// Euclidean length.
    fn length(self) -> Self::Real;
    /// The Y component (height above the floor).
    fn y(self) -> Self::Real;
    /// All components finite.
    fn is_finite(self) -> bool;
    /// Converts (rounding) from a double-precision vector.
    fn from_dvec3(v: DVec3) -> Self;
    /// Converts (exactly) to a double-precision vector.
    fn to_dvec3(self) -> DVec3;
}

macro_rules! impl_vector {
    ($v:ty, $r:ty, $from:expr, $to:expr) => {
        impl Vector for $v {
            type Real = $r;
            const ZERO: Self = <$v>::ZERO;
            const UNIT_Y: Self = <$v>::Y;
            #[inline]
            fn dot(self, other: Self) -> $r {
                <$v>::dot(self, other)
            }
            #[inline]
            fn cross(self, other: Self) -> Self {
                <$v>::cross(self, other)
            }
            #[inline]
            fn length(self) -> $r {
                <$v>::length(self)
            }
            #[inline]
            fn y(self) -> $r {
                self.y
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$v>::is_finite(self)
            }
            #[inline]
            fn from_dvec3(v: DVec3) -> Self {
                $from(v)
            }
            #[inline]
            fn to_dvec3(self) -> DVec3 {
                $to(self)
            }
        }
    };
}
impl_vector!(DVec3, f64, |v| v, |v| v);
impl_vector!(Vec3, f32, |v: DVec3| v.as_vec3(), |v: Vec3| v.as_dvec3());
impl_vector!(
    Vec3A,
    f32,
    |v: DVec3| Vec3A::from(v.as_vec3()),
    |v: Vec3A| v.as_dvec3()
);
