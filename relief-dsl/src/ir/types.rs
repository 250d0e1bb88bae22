//! Shader types as Rust marker types.

use naga::{Scalar, TypeInner, VectorSize};

/// A shader type a [`super::Val`] can carry.
pub trait Ty: Copy + 'static {
    /// The naga type.
    fn inner() -> TypeInner;
}

/// `vec2<f32>`.
#[derive(Clone, Copy, Debug)]
pub struct Vec2;
/// `vec3<f32>`.
#[derive(Clone, Copy, Debug)]
pub struct Vec3;
/// `vec4<f32>`.
#[derive(Clone, Copy, Debug)]
pub struct Vec4;

impl Ty for f32 {
    fn inner() -> TypeInner {
        TypeInner::Scalar(Scalar::F32)
    }
}
impl Ty for u32 {
    fn inner() -> TypeInner {
        TypeInner::Scalar(Scalar::U32)
    }
}
impl Ty for bool {
    fn inner() -> TypeInner {
        TypeInner::Scalar(Scalar::BOOL)
    }
}
impl Ty for Vec2 {
    fn inner() -> TypeInner {
        TypeInner::Vector { size: VectorSize::Bi, scalar: Scalar::F32 }
    }
}
impl Ty for Vec3 {
    fn inner() -> TypeInner {
        TypeInner::Vector { size: VectorSize::Tri, scalar: Scalar::F32 }
    }
}
impl Ty for Vec4 {
    fn inner() -> TypeInner {
        TypeInner::Vector { size: VectorSize::Quad, scalar: Scalar::F32 }
    }
}

/// Float vectors (the types a scalar splats into).
pub trait FloatVec: Ty {
    /// Number of components.
    const SIZE: VectorSize;
}
impl FloatVec for Vec2 {
    const SIZE: VectorSize = VectorSize::Bi;
}
impl FloatVec for Vec3 {
    const SIZE: VectorSize = VectorSize::Tri;
}
impl FloatVec for Vec4 {
    const SIZE: VectorSize = VectorSize::Quad;
}

/// The shader type of an ABI record member.
pub(crate) fn member_inner(m: crate::abi::Member) -> TypeInner {
    use crate::abi::Member;
    match m {
        Member::F32 => f32::inner(),
        Member::U32 => u32::inner(),
        Member::Vec2 => Vec2::inner(),
        Member::Vec3 => Vec3::inner(),
        Member::Vec4 => Vec4::inner(),
        Member::Mat4 => Mat4::inner(),
    }
}

/// `mat4x4<f32>`.
#[derive(Clone, Copy, Debug)]
pub struct Mat4;
impl Ty for Mat4 {
    fn inner() -> TypeInner {
        TypeInner::Matrix { columns: VectorSize::Quad, rows: VectorSize::Quad, scalar: Scalar::F32 }
    }
}
/// `vec3<u32>`.
#[derive(Clone, Copy, Debug)]
pub struct UVec3;
impl Ty for UVec3 {
    fn inner() -> TypeInner {
        TypeInner::Vector { size: VectorSize::Tri, scalar: Scalar::U32 }
    }
}

/// `vec2<u32>`.
#[derive(Clone, Copy, Debug)]
pub struct UVec2;
impl Ty for UVec2 {
    fn inner() -> TypeInner {
        TypeInner::Vector { size: VectorSize::Bi, scalar: Scalar::U32 }
    }
}
