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

/// Size and alignment under WGSL's layout rules, for the types relief uses.
pub(crate) fn size_align(inner: &TypeInner) -> (u32, u32) {
    match inner {
        TypeInner::Scalar(s) => (s.width as u32, s.width as u32),
        TypeInner::Vector { size, scalar } => {
            let w = scalar.width as u32;
            match size {
                VectorSize::Bi => (2 * w, 2 * w),
                VectorSize::Tri => (3 * w, 4 * w),
                VectorSize::Quad => (4 * w, 4 * w),
            }
        }
        TypeInner::Matrix { columns, rows, scalar } => {
            let (col_size, align) = size_align(&TypeInner::Vector { size: *rows, scalar: *scalar });
            let stride = col_size.div_ceil(align) * align;
            (stride * *columns as u32, align)
        }
        other => panic!("no layout rule for {other:?}"),
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
