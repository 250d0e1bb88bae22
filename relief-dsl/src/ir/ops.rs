//! Operators and methods on [`Val`]: arithmetic with Rust operators, comparisons, maths,
//! swizzles and constructors.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use naga::{BinaryOperator, Expression, MathFunction, ScalarKind, SwizzleComponent, UnaryOperator};

use super::types::FloatVec;
use super::{FnBuilder, IntoVal, Ty, Val, Vec2, Vec3, Vec4};

fn bin<'a, T: Ty, U: Ty>(op: BinaryOperator, a: Val<'a, impl Ty>, b: Val<'a, U>) -> Val<'a, T> {
    a.derive(Expression::Binary { op, left: a.handle(), right: b.handle() })
}

/// Same-type arithmetic: `Val<T> ∘ Val<T>`, `Val<T> ∘ host constant`, `host constant ∘ Val<T>`.
macro_rules! arith_same {
    ($t:ty, $lit:ty) => {
        arith_same!(@op $t, $lit, Add, add, BinaryOperator::Add);
        arith_same!(@op $t, $lit, Sub, sub, BinaryOperator::Subtract);
        arith_same!(@op $t, $lit, Mul, mul, BinaryOperator::Multiply);
        arith_same!(@op $t, $lit, Div, div, BinaryOperator::Divide);
    };
    (@op $t:ty, $lit:ty, $tr:ident, $f:ident, $op:expr) => {
        impl<'a> $tr<Val<'a, $t>> for Val<'a, $t> {
            type Output = Val<'a, $t>;
            fn $f(self, rhs: Val<'a, $t>) -> Val<'a, $t> {
                bin($op, self, rhs)
            }
        }
        impl<'a> $tr<$lit> for Val<'a, $t> {
            type Output = Val<'a, $t>;
            fn $f(self, rhs: $lit) -> Val<'a, $t> {
                let r: Val<'a, $t> = rhs.into_val(self.builder());
                bin($op, self, r)
            }
        }
        impl<'a> $tr<Val<'a, $t>> for $lit {
            type Output = Val<'a, $t>;
            fn $f(self, rhs: Val<'a, $t>) -> Val<'a, $t> {
                let l: Val<'a, $t> = self.into_val(rhs.builder());
                bin($op, l, rhs)
            }
        }
    };
}
arith_same!(f32, f32);
arith_same!(u32, u32);

/// Vector arithmetic: vector ∘ vector, vector ∘ scalar (splatted), scalar ∘ vector.
macro_rules! arith_vec {
    ($v:ty) => {
        arith_vec!(@op $v, Add, add, BinaryOperator::Add);
        arith_vec!(@op $v, Sub, sub, BinaryOperator::Subtract);
        arith_vec!(@op $v, Mul, mul, BinaryOperator::Multiply);
        arith_vec!(@op $v, Div, div, BinaryOperator::Divide);
    };
    (@op $v:ty, $tr:ident, $f:ident, $op:expr) => {
        impl<'a> $tr<Val<'a, $v>> for Val<'a, $v> {
            type Output = Val<'a, $v>;
            fn $f(self, rhs: Val<'a, $v>) -> Val<'a, $v> {
                bin($op, self, rhs)
            }
        }
        impl<'a> $tr<Val<'a, f32>> for Val<'a, $v> {
            type Output = Val<'a, $v>;
            fn $f(self, rhs: Val<'a, f32>) -> Val<'a, $v> {
                bin($op, self, rhs.splat::<$v>())
            }
        }
        impl<'a> $tr<f32> for Val<'a, $v> {
            type Output = Val<'a, $v>;
            fn $f(self, rhs: f32) -> Val<'a, $v> {
                bin($op, self, self.builder().lit(rhs).splat::<$v>())
            }
        }
        impl<'a> $tr<Val<'a, $v>> for Val<'a, f32> {
            type Output = Val<'a, $v>;
            fn $f(self, rhs: Val<'a, $v>) -> Val<'a, $v> {
                bin($op, self.splat::<$v>(), rhs)
            }
        }
        impl<'a> $tr<Val<'a, $v>> for f32 {
            type Output = Val<'a, $v>;
            fn $f(self, rhs: Val<'a, $v>) -> Val<'a, $v> {
                bin($op, rhs.builder().lit(self).splat::<$v>(), rhs)
            }
        }
    };
}
arith_vec!(Vec2);
arith_vec!(Vec3);
arith_vec!(Vec4);

macro_rules! neg {
    ($t:ty) => {
        impl<'a> Neg for Val<'a, $t> {
            type Output = Val<'a, $t>;
            fn neg(self) -> Val<'a, $t> {
                self.derive(Expression::Unary { op: UnaryOperator::Negate, expr: self.handle() })
            }
        }
    };
}
neg!(f32);
neg!(Vec2);
neg!(Vec3);
neg!(Vec4);

impl<'a> BitAnd for Val<'a, bool> {
    type Output = Val<'a, bool>;
    fn bitand(self, rhs: Self) -> Self {
        bin(BinaryOperator::LogicalAnd, self, rhs)
    }
}
impl<'a> BitOr for Val<'a, bool> {
    type Output = Val<'a, bool>;
    fn bitor(self, rhs: Self) -> Self {
        bin(BinaryOperator::LogicalOr, self, rhs)
    }
}
impl<'a> Not for Val<'a, bool> {
    type Output = Val<'a, bool>;
    fn not(self) -> Self {
        self.derive(Expression::Unary { op: UnaryOperator::LogicalNot, expr: self.handle() })
    }
}

/// Scalars that compare.
pub trait Ordered: Ty {}
impl Ordered for f32 {}
impl Ordered for u32 {}

impl<'a, T: Ordered> Val<'a, T> {
    fn cmp(self, op: BinaryOperator, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        let r = rhs.into_val(self.builder());
        bin(op, self, r)
    }
    /// `self < rhs`
    pub fn lt(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.cmp(BinaryOperator::Less, rhs)
    }
    /// `self <= rhs`
    pub fn le(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.cmp(BinaryOperator::LessEqual, rhs)
    }
    /// `self > rhs`
    pub fn gt(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.cmp(BinaryOperator::Greater, rhs)
    }
    /// `self >= rhs`
    pub fn ge(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.cmp(BinaryOperator::GreaterEqual, rhs)
    }
}

/// Float scalars and vectors: the maths library.
pub trait Float: Ty {}
impl Float for f32 {}
impl Float for Vec2 {}
impl Float for Vec3 {}
impl Float for Vec4 {}

impl<'a, T: Float> Val<'a, T> {
    fn math(self, fun: MathFunction, args: &[naga::Handle<Expression>]) -> Val<'a, T> {
        self.derive(Expression::Math {
            fun,
            arg: self.handle(),
            arg1: args.first().copied(),
            arg2: args.get(1).copied(),
            arg3: None,
        })
    }
    /// `|self|`
    pub fn abs(self) -> Self {
        self.math(MathFunction::Abs, &[])
    }
    /// Component-wise minimum.
    pub fn min(self, o: impl IntoSame<'a, T>) -> Self {
        let o = o.into_same(self.builder());
        self.math(MathFunction::Min, &[o.handle()])
    }
    /// Component-wise maximum.
    pub fn max(self, o: impl IntoSame<'a, T>) -> Self {
        let o = o.into_same(self.builder());
        self.math(MathFunction::Max, &[o.handle()])
    }
    /// `clamp(self, lo, hi)`.
    pub fn clamp(self, lo: impl IntoSame<'a, T>, hi: impl IntoSame<'a, T>) -> Self {
        let s = self.builder();
        let lo = lo.into_same(s);
        let hi = hi.into_same(s);
        self.math(MathFunction::Clamp, &[lo.handle(), hi.handle()])
    }
    /// `sqrt(self)`
    pub fn sqrt(self) -> Self {
        self.math(MathFunction::Sqrt, &[])
    }
    /// `floor(self)`
    pub fn floor(self) -> Self {
        self.math(MathFunction::Floor, &[])
    }
    /// `ceil(self)`
    pub fn ceil(self) -> Self {
        self.math(MathFunction::Ceil, &[])
    }
    /// `round(self)`, halves to even (WGSL's `round`).
    pub fn round(self) -> Self {
        self.math(MathFunction::Round, &[])
    }
    /// `log2(self)`
    pub fn log2(self) -> Self {
        self.math(MathFunction::Log2, &[])
    }
    /// `exp2(self)`
    pub fn exp2(self) -> Self {
        self.math(MathFunction::Exp2, &[])
    }
    /// `self · m + a` as one fused multiply-add (`fma`; GLSL versions without `fma` get the
    /// product and the sum). For values whose rounding does not matter (a sample's
    /// coordinate): a compiler keeps it one instruction where it may otherwise factor
    /// `x·s + s·k` into an add and a multiply.
    pub fn mul_add(self, m: impl IntoSame<'a, T>, a: impl IntoSame<'a, T>) -> Self {
        let s = self.builder();
        let m = m.into_same(s);
        let a = a.into_same(s);
        self.math(MathFunction::Fma, &[m.handle(), a.handle()])
    }
    /// Linear interpolation `mix(self, o, f)`.
    pub fn mix(self, o: impl IntoSame<'a, T>, f: impl IntoSame<'a, T>) -> Self {
        let s = self.builder();
        let o = o.into_same(s);
        let f = f.into_same(s);
        self.math(MathFunction::Mix, &[o.handle(), f.handle()])
    }
}

/// A value of type `T` or a host `f32` splatted to `T`.
pub trait IntoSame<'a, T: Ty> {
    /// Converts.
    fn into_same(self, s: &'a FnBuilder<'a>) -> Val<'a, T>;
}
impl<'a, T: Ty> IntoSame<'a, T> for super::Var<'a, T> {
    fn into_same(self, _: &'a FnBuilder<'a>) -> Val<'a, T> {
        self.get()
    }
}
impl<'a, T: Ty> IntoSame<'a, T> for Val<'a, T> {
    fn into_same(self, _: &'a FnBuilder<'a>) -> Val<'a, T> {
        self
    }
}
impl<'a> IntoSame<'a, f32> for f32 {
    fn into_same(self, s: &'a FnBuilder<'a>) -> Val<'a, f32> {
        s.lit(self)
    }
}
macro_rules! into_same_vec {
    ($v:ty) => {
        impl<'a> IntoSame<'a, $v> for f32 {
            fn into_same(self, s: &'a FnBuilder<'a>) -> Val<'a, $v> {
                s.lit(self).splat::<$v>()
            }
        }
    };
}
into_same_vec!(Vec2);
into_same_vec!(Vec3);
into_same_vec!(Vec4);

impl<'a> Val<'a, f32> {
    /// The scalar repeated into a vector.
    pub fn splat<V: FloatVec>(self) -> Val<'a, V> {
        self.derive(Expression::Splat { size: V::SIZE, value: self.handle() })
    }
    /// Truncation to `u32`.
    pub fn to_u32(self) -> Val<'a, u32> {
        self.derive(Expression::As { expr: self.handle(), kind: ScalarKind::Uint, convert: Some(4) })
    }
    /// The value's IEEE 754 bits as a `u32` (WGSL's `bitcast<u32>`): for floats ≥ +0 their
    /// order is the bits' order, and every float with its sign bit set (−0 included) is above
    /// them all.
    pub fn bits(self) -> Val<'a, u32> {
        self.derive(Expression::As { expr: self.handle(), kind: ScalarKind::Uint, convert: None })
    }
}

impl<'a> Val<'a, u32> {
    /// Conversion to `f32`.
    pub fn to_f32(self) -> Val<'a, f32> {
        self.derive(Expression::As { expr: self.handle(), kind: ScalarKind::Float, convert: Some(4) })
    }
    /// Bitwise and.
    pub fn and(self, rhs: u32) -> Val<'a, u32> {
        let r: Val<'a, u32> = rhs.into_val(self.builder());
        bin(BinaryOperator::And, self, r)
    }
    /// Logical shift right.
    pub fn shift_right(self, rhs: u32) -> Val<'a, u32> {
        let r: Val<'a, u32> = rhs.into_val(self.builder());
        bin(BinaryOperator::ShiftRight, self, r)
    }
}

impl<'a, V: FloatVec> Val<'a, V> {
    fn comp(self, i: u32) -> Val<'a, f32> {
        self.derive(Expression::AccessIndex { base: self.handle(), index: i })
    }
    fn swizzle<U: FloatVec>(self, p: [SwizzleComponent; 4]) -> Val<'a, U> {
        self.derive(Expression::Swizzle { size: U::SIZE, vector: self.handle(), pattern: p })
    }
    /// First component.
    pub fn x(self) -> Val<'a, f32> {
        self.comp(0)
    }
    /// Second component.
    pub fn y(self) -> Val<'a, f32> {
        self.comp(1)
    }
    /// First two components.
    pub fn xy(self) -> Val<'a, Vec2> {
        use SwizzleComponent::*;
        self.swizzle([X, Y, X, X])
    }
    /// Dot product.
    pub fn dot(self, o: Val<'a, V>) -> Val<'a, f32> {
        self.derive(Expression::Math {
            fun: MathFunction::Dot,
            arg: self.handle(),
            arg1: Some(o.handle()),
            arg2: None,
            arg3: None,
        })
    }
    /// Euclidean length.
    pub fn length(self) -> Val<'a, f32> {
        self.derive(Expression::Math {
            fun: MathFunction::Length,
            arg: self.handle(),
            arg1: None,
            arg2: None,
            arg3: None,
        })
    }
    /// Unit vector in the same direction.
    pub fn normalize(self) -> Val<'a, V> {
        self.derive(Expression::Math {
            fun: MathFunction::Normalize,
            arg: self.handle(),
            arg1: None,
            arg2: None,
            arg3: None,
        })
    }
}

impl<'a> Val<'a, Vec3> {
    /// Third component.
    pub fn z(self) -> Val<'a, f32> {
        self.comp(2)
    }
}
impl<'a> Val<'a, Vec4> {
    /// Third component.
    pub fn z(self) -> Val<'a, f32> {
        self.comp(2)
    }
    /// Fourth component.
    pub fn w(self) -> Val<'a, f32> {
        self.comp(3)
    }
    /// First three components.
    pub fn xyz(self) -> Val<'a, Vec3> {
        use SwizzleComponent::*;
        self.swizzle([X, Y, Z, X])
    }
    /// Last two components.
    pub fn zw(self) -> Val<'a, Vec2> {
        use SwizzleComponent::*;
        self.swizzle([Z, W, X, X])
    }
}

impl<'a> FnBuilder<'a> {
    fn compose<V: Ty>(&'a self, parts: &[naga::Handle<Expression>]) -> Val<'a, V> {
        let ty = self.ctx.ty(V::inner());
        self.wrap(self.expr(Expression::Compose { ty, components: parts.to_vec() }))
    }
    /// `vec2(x, y)`
    pub fn vec2(&'a self, x: impl IntoVal<'a, f32>, y: impl IntoVal<'a, f32>) -> Val<'a, Vec2> {
        let (x, y) = (x.into_val(self), y.into_val(self));
        self.compose(&[x.handle(), y.handle()])
    }
    /// `vec3(xy, z)`
    pub fn vec3(&'a self, xy: Val<'a, Vec2>, z: impl IntoVal<'a, f32>) -> Val<'a, Vec3> {
        let z = z.into_val(self);
        self.compose(&[xy.handle(), z.handle()])
    }
    /// `vec4(xyz, w)`
    pub fn vec4(&'a self, xyz: Val<'a, Vec3>, w: impl IntoVal<'a, f32>) -> Val<'a, Vec4> {
        let w = w.into_val(self);
        self.compose(&[xyz.handle(), w.handle()])
    }
}

impl<'a> Mul<Val<'a, Vec4>> for Val<'a, super::types::Mat4> {
    type Output = Val<'a, Vec4>;
    fn mul(self, rhs: Val<'a, Vec4>) -> Val<'a, Vec4> {
        bin(BinaryOperator::Multiply, self, rhs)
    }
}

impl<'a> Val<'a, super::types::UVec3> {
    /// First component.
    pub fn x(self) -> Val<'a, u32> {
        self.derive(Expression::AccessIndex { base: self.handle(), index: 0 })
    }
}

impl<'a> Val<'a, Vec3> {
    /// The cross product `self × o`.
    pub fn cross(self, o: Val<'a, Vec3>) -> Val<'a, Vec3> {
        self.derive(Expression::Math {
            fun: MathFunction::Cross,
            arg: self.handle(),
            arg1: Some(o.handle()),
            arg2: None,
            arg3: None,
        })
    }
}

impl<'a> Val<'a, Vec2> {
    /// Conversion to `vec2<u32>` (truncation; the components must be non-negative).
    pub fn to_u32(self) -> Val<'a, super::types::UVec2> {
        self.derive(Expression::As { expr: self.handle(), kind: ScalarKind::Uint, convert: Some(4) })
    }
}
