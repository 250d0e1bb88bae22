//! Typed values and variables.

use std::marker::PhantomData;

use naga::{Expression, Handle, Literal, Statement};

use super::{FnBuilder, Ty};

/// A value of shader type `T` inside the function being built. `Copy`, like a handle.
///
/// `#[must_use]`: a value built and never read is most likely a step of the algorithm
/// forgotten (an update meant for a variable, a result not returned).
#[must_use = "a value that is built and never read does nothing in the shader"]
pub struct Val<'a, T: Ty> {
    s: &'a FnBuilder<'a>,
    h: Handle<Expression>,
    _t: PhantomData<T>,
}

impl<T: Ty> Clone for Val<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Ty> Copy for Val<'_, T> {}

impl<'a, T: Ty> Val<'a, T> {
    pub(crate) fn from_handle(s: &'a FnBuilder<'a>, h: Handle<Expression>) -> Self {
        Val { s, h, _t: PhantomData }
    }
    /// The naga expression behind the value.
    pub(crate) fn handle(self) -> Handle<Expression> {
        self.h
    }
    /// The builder of the function this value belongs to.
    pub fn builder(self) -> &'a FnBuilder<'a> {
        self.s
    }
    /// Gives the value a name in the generated shader (`let NAME = …;`).
    pub fn named(self, name: &str) -> Self {
        self.s.name(name, self)
    }
    pub(crate) fn derive<U: Ty>(self, e: Expression) -> Val<'a, U> {
        Val::from_handle(self.s, self.s.expr(e))
    }
}

/// Anything that can become a `Val<T>`: the value itself, or a host constant.
pub trait IntoVal<'a, T: Ty> {
    /// Converts, adding a literal to `s` when needed.
    fn into_val(self, s: &'a FnBuilder<'a>) -> Val<'a, T>;
}

impl<'a, T: Ty> IntoVal<'a, T> for Val<'a, T> {
    fn into_val(self, _: &'a FnBuilder<'a>) -> Val<'a, T> {
        self
    }
}
impl<'a> IntoVal<'a, f32> for f32 {
    fn into_val(self, s: &'a FnBuilder<'a>) -> Val<'a, f32> {
        s.lit(self)
    }
}
impl<'a> IntoVal<'a, u32> for u32 {
    fn into_val(self, s: &'a FnBuilder<'a>) -> Val<'a, u32> {
        s.wrap(s.expr(Expression::Literal(Literal::U32(self))))
    }
}
impl<'a> IntoVal<'a, bool> for bool {
    fn into_val(self, s: &'a FnBuilder<'a>) -> Val<'a, bool> {
        s.wrap(s.expr(Expression::Literal(Literal::Bool(self))))
    }
}

impl<'a> FnBuilder<'a> {
    /// An `f32` literal. Panics on a non-finite value, which naga forbids: a host constant
    /// that is NaN or infinite is a bug in the stage.
    pub fn lit(&'a self, x: f32) -> Val<'a, f32> {
        assert!(x.is_finite(), "non-finite shader constant {x}");
        self.wrap(self.expr(Expression::Literal(Literal::F32(x))))
    }
    /// A `u32` literal.
    pub fn lit_u32(&'a self, x: u32) -> Val<'a, u32> {
        x.into_val(self)
    }
    /// A `bool` literal.
    pub fn lit_bool(&'a self, x: bool) -> Val<'a, bool> {
        x.into_val(self)
    }
}

/// A function-local variable of type `T`.
#[must_use = "a variable that is declared and never read or stored does nothing in the shader"]
pub struct Var<'a, T: Ty> {
    s: &'a FnBuilder<'a>,
    ptr: Handle<Expression>,
    _t: PhantomData<T>,
}

impl<T: Ty> Clone for Var<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Ty> Copy for Var<'_, T> {}

impl<'a, T: Ty> Var<'a, T> {
    pub(crate) fn new(s: &'a FnBuilder<'a>, ptr: Handle<Expression>) -> Self {
        Var { s, ptr, _t: PhantomData }
    }
    /// The current value.
    pub fn get(self) -> Val<'a, T> {
        self.s.wrap(self.s.expr(Expression::Load { pointer: self.ptr }))
    }
    /// Stores a new value.
    pub fn set(self, v: impl IntoVal<'a, T>) {
        let v = v.into_val(self.s);
        self.s.stmt(Statement::Store { pointer: self.ptr, value: v.handle() });
    }
}

/// A variable reads as its current value wherever a value is expected: `t + step`,
/// `t.ge(limit)`, `ray.at(t)`; the load is added where the expression is.
impl<'a, T: Ty> IntoVal<'a, T> for Var<'a, T> {
    fn into_val(self, _: &'a FnBuilder<'a>) -> Val<'a, T> {
        self.get()
    }
}

impl<'a, T: super::ops::Ordered> Var<'a, T> {
    /// `self < rhs`
    pub fn lt(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.get().lt(rhs)
    }
    /// `self <= rhs`
    pub fn le(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.get().le(rhs)
    }
    /// `self > rhs`
    pub fn gt(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.get().gt(rhs)
    }
    /// `self >= rhs`
    pub fn ge(self, rhs: impl IntoVal<'a, T>) -> Val<'a, bool> {
        self.get().ge(rhs)
    }
}

/// `host ∘ Var` is `host ∘ Var.get()` for host constants of the listed types.
macro_rules! host_lhs {
    ($tr:ident $f:ident: $($lit:ty),*) => {$(
        impl<'a, T: Ty> std::ops::$tr<Var<'a, T>> for $lit
        where
            $lit: std::ops::$tr<Val<'a, T>>,
        {
            type Output = <$lit as std::ops::$tr<Val<'a, T>>>::Output;
            fn $f(self, rhs: Var<'a, T>) -> Self::Output {
                std::ops::$tr::$f(self, rhs.get())
            }
        }
    )*};
}

/// `Var ∘ x` is `Var.get() ∘ x`, `x ∘ Var` is `x ∘ Var.get()` for every operator `Val` has, and
/// `var ∘= x` stores `var ∘ x` (a load, the operation, a store).
macro_rules! var_ops {
    ($($tr:ident $f:ident $tr_assign:ident $f_assign:ident),*) => {$(
        impl<'a, T: Ty, R> std::ops::$tr<R> for Var<'a, T>
        where
            Val<'a, T>: std::ops::$tr<R>,
        {
            type Output = <Val<'a, T> as std::ops::$tr<R>>::Output;
            fn $f(self, rhs: R) -> Self::Output {
                std::ops::$tr::$f(self.get(), rhs)
            }
        }
        impl<'a, T: Ty, U: Ty> std::ops::$tr<Var<'a, U>> for Val<'a, T>
        where
            Val<'a, T>: std::ops::$tr<Val<'a, U>>,
        {
            type Output = <Val<'a, T> as std::ops::$tr<Val<'a, U>>>::Output;
            fn $f(self, rhs: Var<'a, U>) -> Self::Output {
                std::ops::$tr::$f(self, rhs.get())
            }
        }
        host_lhs!($tr $f: f32, u32);
        impl<'a, T: Ty, R> std::ops::$tr_assign<R> for Var<'a, T>
        where
            Val<'a, T>: std::ops::$tr<R, Output = Val<'a, T>>,
        {
            fn $f_assign(&mut self, rhs: R) {
                self.set(std::ops::$tr::$f(self.get(), rhs));
            }
        }
    )*};
}
var_ops!(Add add AddAssign add_assign, Sub sub SubAssign sub_assign, Mul mul MulAssign mul_assign, Div div DivAssign div_assign);

impl<'a, T: Ty> std::ops::Neg for Var<'a, T>
where
    Val<'a, T>: std::ops::Neg,
{
    type Output = <Val<'a, T> as std::ops::Neg>::Output;
    fn neg(self) -> Self::Output {
        -self.get()
    }
}
impl<'a> std::ops::Not for Var<'a, bool> {
    type Output = Val<'a, bool>;
    fn not(self) -> Val<'a, bool> {
        !self.get()
    }
}
impl<'a, R> std::ops::BitAnd<R> for Var<'a, bool>
where
    Val<'a, bool>: std::ops::BitAnd<R, Output = Val<'a, bool>>,
{
    type Output = Val<'a, bool>;
    fn bitand(self, rhs: R) -> Val<'a, bool> {
        self.get() & rhs
    }
}
impl<'a, R> std::ops::BitOr<R> for Var<'a, bool>
where
    Val<'a, bool>: std::ops::BitOr<R, Output = Val<'a, bool>>,
{
    type Output = Val<'a, bool>;
    fn bitor(self, rhs: R) -> Val<'a, bool> {
        self.get() | rhs
    }
}
impl<'a> std::ops::BitAnd<Var<'a, bool>> for Val<'a, bool> {
    type Output = Val<'a, bool>;
    fn bitand(self, rhs: Var<'a, bool>) -> Val<'a, bool> {
        self & rhs.get()
    }
}
impl<'a> std::ops::BitOr<Var<'a, bool>> for Val<'a, bool> {
    type Output = Val<'a, bool>;
    fn bitor(self, rhs: Var<'a, bool>) -> Val<'a, bool> {
        self | rhs.get()
    }
}
