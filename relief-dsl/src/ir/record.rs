//! Structs that cross function boundaries: a Rust struct of [`Val`](super::Val)s in stage code, a naga
//! struct in the module.

use naga::{Expression, Handle, TypeInner};

use super::{FnBuilder, ModuleCtx};

/// A Rust struct of [`Val`](super::Val)s that is one struct value in the shader (the stages' ray, bracket
/// and hit): how it is declared, packed into one value and unpacked again, so that a record
/// passes into and out of a function whole. Implemented with the crate's `record!` macro.
pub trait Record<'a>: Sized {
    /// The struct's name in the shader.
    const NAME: &'static str;
    /// The members' names and types, in declaration order.
    fn members() -> Vec<(&'static str, TypeInner)>;
    /// The members' values, in declaration order.
    fn parts(&self) -> Vec<Handle<Expression>>;
    /// The record whose members are those of the struct value `value`.
    fn from_value(s: &'a FnBuilder<'a>, value: Handle<Expression>) -> Self;
}

/// Implements [`Record`] for a struct of `Val`s from one list of its fields and their
/// shader types: `record!(Ray "Ray" { origin: Vec2, dir: Vec3, cos_view: f32 });`.
macro_rules! record {
    ($ty:ident $name:literal { $($field:ident : $t:ty),+ $(,)? }) => {
        impl<'a> $crate::ir::Record<'a> for $ty<'a> {
            const NAME: &'static str = $name;
            fn members() -> Vec<(&'static str, naga::TypeInner)> {
                vec![$((stringify!($field), <$t as $crate::ir::Ty>::inner())),+]
            }
            fn parts(&self) -> Vec<naga::Handle<naga::Expression>> {
                vec![$(self.$field.handle()),+]
            }
            fn from_value(s: &'a $crate::ir::FnBuilder<'a>, value: naga::Handle<naga::Expression>) -> Self {
                let mut index = 0u32;
                $(
                    let $field = s.field::<$t>(value, index);
                    index += 1;
                )+
                let _ = index;
                $ty { $($field),+ }
            }
        }
    };
}
pub(crate) use record;

impl ModuleCtx {
    /// The struct type of the record `R`.
    pub(crate) fn record_type<'a, R: Record<'a>>(&self) -> Handle<naga::Type> {
        self.struct_ty(R::NAME, &R::members())
    }
}

impl<'a> FnBuilder<'a> {
    /// The record packed into one struct value.
    pub fn pack<R: Record<'a>>(&'a self, r: &R) -> Handle<Expression> {
        self.make_struct(self.ctx.record_type::<R>(), &r.parts())
    }
    /// The record held by the struct value `value`.
    pub fn unpack<R: Record<'a>>(&'a self, value: Handle<Expression>) -> R {
        R::from_value(self, value)
    }
    /// The `i`-th argument of the function, a record.
    pub fn arg_record<R: Record<'a>>(&'a self, i: u32) -> R {
        let value = self.expr(Expression::FunctionArgument(i));
        self.unpack(value)
    }
    /// Finishes the function, returning the record `r`.
    pub(crate) fn finish_record<R: Record<'a>>(&'a self, r: &R) -> naga::Function {
        let value = self.pack(r);
        self.finish(Some((self.ctx.record_type::<R>(), None, value)))
    }
}
