//! What each library target can express: the one place that says which prefixes, groups and
//! bindings a library may be written with, per target language, and why.
//!
//! A library's names are the prefix `P` followed by `_` and a word (`P_trace`, `P_height`,
//! `P_impl_coarse_linear`, …) or the prefix in CamelCase followed by a word (`PHit`, `PRay`).
//! Its resources sit in one group at consecutive bindings. Each target language, or the
//! writer and compilers that read it, has limits on those:
//!
//! | target | reserved name prefixes | longest name | group | binding |
//! | --- | --- | --- | --- | --- |
//! | WGSL | `__`, `_naga` (WGSL, naga) | — | ≤ 3 | ≤ 999 |
//! | GLSL | `gl_` (GLSL 4.50 §3.7), `_group`, `_immediates_binding_` (naga) | 1024 (glslang) | `set` ≤ 62 | ≤ 79 |
//! | GLSL ES 3.00 | `gl_` (GLSL ES 3.00 §3.8), `webgl_`, `_webgl_` (WebGL 2), naga's as GLSL | 1024 (WebGL 2) | — | — |
//! | HLSL | `naga_`, `LoadedStorageValueFrom`, `__dynamic_buffer_offsets` (naga) | 1024 (glslang) | `space` ≤ 255 | — |
//! | MSL | `clamped_lod_e`, `ray_query_get_intersection`, `naga_query_…` (naga) | — | — | — |
//!
//! - WGSL: a `@group` must be below the device's `maxBindGroups` and a `@binding` below its
//!   `maxBindingsPerBindGroup`; WebGPU guarantees 4 and 1000 (the defaults every adapter
//!   offers), so those are the limits a library can rely on.
//! - GLSL: glslang refuses a `set` of 63 or more and a name longer than 1024 characters
//!   (`name too long`). The OpenGL branch of the file binds each `sampler2D` at its binding,
//!   which must be below `GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS`: OpenGL 4.5 guarantees 80 (and
//!   glslang checks against that value).
//! - GLSL ES 3.00 has no binding qualifiers: WebGL binds sampler uniforms by name, so no
//!   group or binding limit applies. WebGL 2 refuses identifiers that start with `webgl_` or
//!   `_webgl_` and names longer than 1024 characters.
//! - HLSL: naga writes a register space as an 8-bit number (`space1000` would come out as
//!   `space232`), so groups go up to 255; names are limited like GLSL's when compiled by
//!   glslang's HLSL front end.
//! - A name that starts with a reserved prefix would be renamed by naga's writer (`gen_…`) or
//!   refused by the compiler. As a library's names continue the prefix with anything after
//!   `P_`, a prefix is refused when `P_` and a reserved prefix start alike (one begins the
//!   other), and likewise for the CamelCase form: conservative, never a renamed function.
//!   Keywords cannot collide: no keyword of the four languages has the shape `P_word` or
//!   `PWord` with the words the library uses (and [`super::library()`] checks after writing
//!   that every public name came out as it was given).
//!
//! [`check`] applies a form's limits to one set of options; library emission calls it for
//! every form it writes, with the first binding before anything is built and the last one
//! once the resources are known. The limits belong to languages, and each [`LibraryForm`] is
//! held to its language's: a new form adds one arm to [`limits`], a new language its row.

use super::LibraryForm;
use crate::CompileError;

/// A limit and who sets it (the words that follow "the limit of" in an error).
pub(crate) type Limit<T> = Option<(T, &'static str)>;

/// The limits of one target language.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The language's name in messages (`GLSL ES`).
    pub language: &'static str,
    /// Name prefixes the language or its writer reserves, each with who reserves it.
    pub reserved_prefixes: &'static [(&'static str, &'static str)],
    /// The longest name, in characters.
    pub max_name: Limit<usize>,
    /// The highest group (descriptor set, register space).
    pub max_group: Limit<u32>,
    /// The highest binding.
    pub max_binding: Limit<u32>,
}

/// The most characters a library's names add to the prefix (`_impl_shadow_hard_…`); the
/// library checks its module's names against it once built, so a longer name is an error,
/// not a file a compiler refuses.
pub const LONGEST_SUFFIX: usize = 96;

const WGSL: Limits = Limits {
    language: "WGSL",
    reserved_prefixes: &[("__", "WGSL"), ("_naga", "naga's WGSL writer")],
    max_name: None,
    max_group: Some((3, "WebGPU's guaranteed maxBindGroups (4)")),
    max_binding: Some((999, "WebGPU's guaranteed maxBindingsPerBindGroup (1000)")),
};

const GLSL: Limits = Limits {
    language: "GLSL",
    reserved_prefixes: &[
        ("gl_", "GLSL"),
        ("_group", "naga's GLSL writer"),
        ("_immediates_binding_", "naga's GLSL writer"),
    ],
    max_name: Some((1024, "glslang")),
    max_group: Some((62, "glslang (`set` below 63)")),
    max_binding: Some((79, "OpenGL 4.5's guaranteed GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS (80)")),
};

const GLSL_ES: Limits = Limits {
    language: "GLSL ES",
    reserved_prefixes: &[
        ("gl_", "GLSL ES"),
        ("webgl_", "WebGL"),
        ("_webgl_", "WebGL"),
        ("_group", "naga's GLSL writer"),
        ("_immediates_binding_", "naga's GLSL writer"),
    ],
    max_name: Some((1024, "WebGL 2")),
    max_group: None,
    max_binding: None,
};

const HLSL: Limits = Limits {
    language: "HLSL",
    reserved_prefixes: &[
        ("naga_", "naga's HLSL writer"),
        ("LoadedStorageValueFrom", "naga's HLSL writer"),
        ("__dynamic_buffer_offsets", "naga's HLSL writer"),
    ],
    max_name: Some((1024, "glslang's HLSL front end")),
    max_group: Some((255, "naga's HLSL writer (register spaces are 8-bit)")),
    max_binding: None,
};

const MSL: Limits = Limits {
    language: "MSL",
    reserved_prefixes: &[
        ("clamped_lod_e", "naga's MSL writer"),
        ("ray_query_get_intersection", "naga's MSL writer"),
        ("naga_query_init_tracker_for_", "naga's MSL writer"),
        ("naga_query_tmax_tracker_for_", "naga's MSL writer"),
    ],
    max_name: None,
    max_group: None,
    max_binding: None,
};

/// The limits of the language `form` is written in (see the module docs for where each comes
/// from): the WGSL forms share WGSL's, the engine forms HLSL's.
pub fn limits(form: LibraryForm) -> Limits {
    match form {
        LibraryForm::Wgsl | LibraryForm::Wesl | LibraryForm::Tsl => WGSL,
        LibraryForm::Glsl => GLSL,
        LibraryForm::GlslEs => GLSL_ES,
        LibraryForm::Hlsl | LibraryForm::Unity | LibraryForm::Unreal => HLSL,
        LibraryForm::Msl => MSL,
    }
}

fn refuse(lang: &str, message: String) -> CompileError {
    CompileError { stage: format!("library {lang}"), message }
}

/// Whether one of `a` and `b` begins the other.
fn overlap(a: &str, b: &str) -> bool {
    a.starts_with(b) || b.starts_with(a)
}

/// Checks that a library with these options can be written in `form`: the prefix (its
/// reserved starts and its length), the group and a binding it uses. The error names the
/// option and the limit, in one line.
pub fn check(form: LibraryForm, prefix: &str, group: u32, binding: u32) -> Result<(), CompileError> {
    let l = limits(form);
    let lang = l.language;
    let snake = format!("{prefix}_");
    let camel = crate::compose::library::camel(prefix);
    for (reserved, by) in l.reserved_prefixes {
        if overlap(&snake, reserved) || overlap(&camel, reserved) {
            return Err(refuse(
                lang,
                format!(
                    "prefix `{prefix}`: names starting with `{reserved}` are reserved by {by}, and the library's names (`{snake}trace`, `{camel}Hit`) could start so in {lang}; choose another prefix"
                ),
            ));
        }
    }
    if let Some((max, by)) = l.max_name {
        let n = prefix.chars().count();
        if n + LONGEST_SUFFIX > max {
            return Err(refuse(
                lang,
                format!(
                    "prefix of {n} characters: {lang} names are at most {max} characters ({by}) and the library adds up to {LONGEST_SUFFIX}, so a prefix may have at most {}",
                    max - LONGEST_SUFFIX
                ),
            ));
        }
    }
    if let Some((max, by)) = l.max_group {
        if group > max {
            return Err(refuse(lang, format!("group {group} is above {lang}'s limit of {max} ({by})")));
        }
    }
    if let Some((max, by)) = l.max_binding {
        if binding > max {
            return Err(refuse(lang, format!("binding {binding} is above {lang}'s limit of {max} ({by})")));
        }
    }
    Ok(())
}

/// [`check`] for every form in `forms`, first error first.
pub(crate) fn check_all(forms: &[LibraryForm], prefix: &str, group: u32, binding: u32) -> Result<(), CompileError> {
    forms.iter().try_for_each(|f| check(*f, prefix, group, binding))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_starts_are_refused_in_their_language_only() {
        let e = check(LibraryForm::Glsl, "gl", 0, 0).unwrap_err().to_string();
        assert!(e.contains("prefix `gl`") && e.contains("`gl_`") && e.contains("GLSL"), "{e}");
        assert!(check(LibraryForm::Glsl, "gl_x", 0, 0).is_err());
        for fine in ["glow", "g", "relief", "Gl"] {
            assert!(check(LibraryForm::Glsl, fine, 0, 0).is_ok(), "{fine}");
        }
        assert!(check(LibraryForm::Wgsl, "gl", 0, 0).is_ok());
        assert!(check(LibraryForm::Hlsl, "naga", 0, 0).is_err());
        assert!(check(LibraryForm::Hlsl, "nag", 0, 0).is_ok());
        // `clamped_lod` would make `clamped_lod_edge_clamp`, which starts with `clamped_lod_e`.
        assert!(check(LibraryForm::Msl, "clamped_lod", 0, 0).is_err());
        // The CamelCase form: `LoadedStorageValueFrom` + `Hit`.
        assert!(check(LibraryForm::Hlsl, "loaded_storage_value_from", 0, 0).is_err());
    }

    #[test]
    fn lengths_groups_and_bindings_at_the_limit_and_one_past() {
        let max = 1024 - LONGEST_SUFFIX;
        assert!(check(LibraryForm::Glsl, &"a".repeat(max), 0, 0).is_ok());
        let e = check(LibraryForm::Glsl, &"a".repeat(max + 1), 0, 0).unwrap_err().to_string();
        assert!(e.contains(&format!("at most {max}")), "{e}");
        for (t, g, b) in [(LibraryForm::Wgsl, 3, 999), (LibraryForm::Glsl, 62, 79), (LibraryForm::Hlsl, 255, u32::MAX)]
        {
            assert!(check(t, "relief", g, b).is_ok(), "{t:?}");
            let e = check(t, "relief", g + 1, 0).unwrap_err().to_string();
            assert!(e.starts_with(&format!("library {}: group {}", limits(t).language, g + 1)), "{e}");
            if b < u32::MAX {
                let e = check(t, "relief", 0, b + 1).unwrap_err().to_string();
                assert!(e.contains(&format!("binding {} is above", b + 1)), "{e}");
            }
        }
        assert!(check(LibraryForm::Msl, "relief", u32::MAX, u32::MAX).is_ok());
    }
}
