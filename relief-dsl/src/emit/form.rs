//! The one list of library targets: [`LibraryForm`], what `relief gen --library --target NAME`
//! writes. The language limits ([`super::limits`]) and the writers (one module per form, see
//! [`super::library_forms`]) are keyed by it.

use crate::CompileError;

/// One form of a library: what `relief gen --library --target NAME` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LibraryForm {
    /// `NAME.lib.wgsl`: WGSL to concatenate, or to import through `naga_oil` with
    /// [`LibraryOptions::import_path`](super::LibraryOptions::import_path).
    Wgsl,
    /// `NAME_ident.wesl` (the stem with `-` as `_`, a WESL module name): the same module as a
    /// WESL module to `import`.
    Wesl,
    /// `NAME.lib.glsl`: a GLSL 450 include file.
    Glsl,
    /// `NAME.lib.es.glsl`: GLSL ES 3.00 for WebGL2 (three.js, Babylon.js `ShaderMaterial`).
    /// ES 3.00 has no `textureGather`: each gather (the `form=safe` cone marches, maxmip's
    /// and the `sample=min4` reads) is four `texelFetch` reads at level 0 that apply
    /// [`LibraryOptions::edge_clamp`](super::LibraryOptions::edge_clamp) to the texel
    /// coordinates themselves, since GLSL ES cannot see the sampler's address mode. Where the
    /// library addresses texels itself the file refuses to compile (`#error`) unless the user
    /// defines `PREFIX_EDGE_REPEAT` or `PREFIX_EDGE_CLAMP` (the prefix in capitals) to match
    /// the edge mode it was generated for.
    GlslEs,
    /// `NAME.tsl.wgsl`: WGSL with the resources as function arguments, for three.js's
    /// WebGPU renderer (TSL `wgsl` / `wgslFn`).
    Tsl,
    /// `NAME.lib.hlsl`: HLSL, shader model 5.1, resources at registers.
    Hlsl,
    /// `NAME.lib.metal`: MSL, resources as arguments.
    Msl,
    /// `NAME.unity.hlsl`: a Custom Function file for Unity's Shader Graph.
    Unity,
    /// `NAME.ush` and `NAME.custom.hlsl`: an include file and a Custom node's code for Unreal.
    Unreal,
}

impl LibraryForm {
    /// Every form, in the order of `--target`'s list.
    pub const ALL: [LibraryForm; 9] = [
        LibraryForm::Wgsl,
        LibraryForm::Wesl,
        LibraryForm::Glsl,
        LibraryForm::GlslEs,
        LibraryForm::Tsl,
        LibraryForm::Hlsl,
        LibraryForm::Msl,
        LibraryForm::Unity,
        LibraryForm::Unreal,
    ];
    /// The forms written when no `--target` is named, one per shading language.
    pub const DEFAULT: [LibraryForm; 4] = [LibraryForm::Wgsl, LibraryForm::Glsl, LibraryForm::Hlsl, LibraryForm::Msl];

    /// The name `--target` takes.
    pub fn name(self) -> &'static str {
        match self {
            LibraryForm::Wgsl => "wgsl",
            LibraryForm::Wesl => "wesl",
            LibraryForm::Glsl => "glsl",
            LibraryForm::GlslEs => "glsl-es",
            LibraryForm::Tsl => "tsl",
            LibraryForm::Hlsl => "hlsl",
            LibraryForm::Msl => "msl",
            LibraryForm::Unity => "unity",
            LibraryForm::Unreal => "unreal",
        }
    }

    /// The form named `name`; an unknown name is a one-line error with the valid names and the
    /// nearest one.
    pub fn from_name(name: &str) -> Result<LibraryForm, CompileError> {
        if let Some(f) = LibraryForm::ALL.into_iter().find(|f| f.name() == name) {
            return Ok(f);
        }
        let names: Vec<&str> = LibraryForm::ALL.iter().map(|f| f.name()).collect();
        let near = names
            .iter()
            .copied()
            .min_by_key(|n| strsim::levenshtein(n, name))
            .filter(|n| strsim::levenshtein(n, name) <= 2);
        Err(CompileError {
            stage: "library".into(),
            message: format!(
                "unknown target `{name}`; expected one of: {}{}",
                names.join(", "),
                near.map(|n| format!("; did you mean `{n}`?")).unwrap_or_default()
            ),
        })
    }

    /// Why this form's resources carry no group (bind group, descriptor set, register space)
    /// to set, or `None` where they do: WGSL and WESL declare `@group`, GLSL 450 `set` (under
    /// `VULKAN`), HLSL `space`.
    pub fn without_groups(self) -> Option<&'static str> {
        match self {
            LibraryForm::Wgsl | LibraryForm::Wesl | LibraryForm::Glsl | LibraryForm::Hlsl => None,
            LibraryForm::GlslEs => Some("WebGL 2 binds its uniforms by name"),
            LibraryForm::Tsl | LibraryForm::Msl => Some("its resources are function arguments"),
            LibraryForm::Unity | LibraryForm::Unreal => Some("the engine passes its textures as node inputs"),
        }
    }
}
