//! The library output: a pipeline's stages as functions for a user's own shader (the
//! interface: [`crate::compose::library`]), written in each [`LibraryForm`] asked for.
//!
//! Every file starts with a header comment that lists the interface and the resources with
//! their bindings. Each form has its own module under `emit/` (`wgsl`, `wesl`, `glsl`,
//! `glsl_es`, `tsl`, `hlsl`, `msl`, `unity`, `unreal`) that says what differs in its
//! language; this module checks the options against the forms' limits, builds the library
//! once, hands it to each form's writer and checks the names that came out.

use super::common::{has_word, Written};
use super::limits;
use super::LibraryForm;
use super::{glsl, glsl_es, hlsl, msl, tsl, unity, unreal, wesl, wgsl};
use crate::compose::library::{camel, Library, LibraryBinding, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

/// The four library files of one pipeline.
#[derive(Clone, Debug)]
pub struct LibraryFiles {
    /// `NAME.lib.wgsl`.
    pub wgsl: String,
    /// `NAME.lib.glsl` (an include file, GLSL 450).
    pub glsl: String,
    /// `NAME.lib.hlsl`.
    pub hlsl: String,
    /// `NAME.lib.metal`.
    pub msl: String,
    /// The resources, in binding order.
    pub bindings: Vec<LibraryBinding>,
    /// Whether `P_shadow` exists.
    pub has_shadow: bool,
    /// Whether `P_ao` exists.
    pub has_ao: bool,
}

/// One file of a library.
#[derive(Clone, Debug)]
pub struct LibraryFile {
    /// The form it belongs to.
    pub form: LibraryForm,
    /// Its file name (`NAME.lib.wgsl`).
    pub name: String,
    /// Its text.
    pub text: String,
}

/// The files of one pipeline's library in the forms asked for.
#[derive(Clone, Debug)]
pub struct LibraryForms {
    /// The files, in the order of the forms asked for.
    pub files: Vec<LibraryFile>,
    /// The resources, in binding order.
    pub bindings: Vec<LibraryBinding>,
    /// Whether `P_shadow` exists.
    pub has_shadow: bool,
    /// Whether `P_ao` exists.
    pub has_ao: bool,
}

impl LibraryForms {
    /// The text of the file `name`.
    pub fn text(&self, name: &str) -> Option<&str> {
        self.files.iter().find(|f| f.name == name).map(|f| f.text.as_str())
    }
}

/// Builds the library of `p` and writes it in the four default languages
/// ([`library_forms`] with [`LibraryForm::DEFAULT`]).
pub fn library(p: &Pipeline, opts: &LibraryOptions) -> Result<LibraryFiles, CompileError> {
    let forms = library_forms(p, opts, &LibraryForm::DEFAULT)?;
    let mut texts = forms.files.into_iter().map(|f| f.text);
    let mut next = || texts.next().unwrap_or_default();
    let (wgsl, glsl, hlsl, msl) = (next(), next(), next(), next());
    Ok(LibraryFiles {
        wgsl,
        glsl,
        hlsl,
        msl,
        bindings: forms.bindings,
        has_shadow: forms.has_shadow,
        has_ao: forms.has_ao,
    })
}

/// Builds the library of `p` and writes it in each of `forms`. The options are checked
/// against every form's language limits first ([`super::limits`]), and the names as written
/// against what was asked for, so a file that would not compile, or whose functions a writer
/// renamed, is an error instead.
pub fn library_forms(p: &Pipeline, opts: &LibraryOptions, forms: &[LibraryForm]) -> Result<LibraryForms, CompileError> {
    limits::check_all(forms, &opts.prefix, opts.group, opts.binding)?;
    let lib = crate::compose::library::compose_library(p, opts)?;
    let last = lib.bindings.last().map_or(opts.binding, |b| b.binding);
    limits::check_all(forms, &opts.prefix, opts.group, last)?;
    check_name_lengths(&lib, &opts.prefix)?;
    let mut files = Vec::new();
    for &form in forms {
        if let Some(why) = mesh_form_refused(p, form) {
            return Err(CompileError { stage: "library".into(), message: why });
        }
        let write = match form {
            LibraryForm::Wgsl => wgsl::write,
            LibraryForm::Wesl => wesl::write,
            LibraryForm::Glsl => glsl::write,
            LibraryForm::GlslEs => glsl_es::write,
            LibraryForm::Tsl => tsl::write,
            LibraryForm::Hlsl => hlsl::write,
            LibraryForm::Msl => msl::write,
            LibraryForm::Unity => unity::write,
            LibraryForm::Unreal => unreal::write,
        };
        for Written { name, text, code } in write(p, &lib, opts)? {
            if let Some(code) = code {
                check_names_kept(&lib, &opts.prefix, form, &code)?;
            }
            files.push(LibraryFile { form, name, text });
        }
    }
    Ok(LibraryForms { files, bindings: lib.bindings, has_shadow: lib.has_shadow, has_ao: lib.has_ao })
}

/// Why `p`'s library cannot be written in `form`, if it cannot (besides what no library can
/// express, [`crate::compose::library::inexpressible`]): the one-line error writing it gives.
/// Every form can write every such pipeline today (GLSL ES 3.00's missing `textureGather`
/// is lowered to `texelFetch`, see [`LibraryForm::GlslEs`]); a pipeline whose GLSL ES text still
/// needs what ES 3.00 lacks is refused here with the reason. `relief gen --all --library`
/// skips such a pipeline in that form.
pub fn inexpressible_in(p: &Pipeline, form: LibraryForm) -> Option<String> {
    if let Some(why) = mesh_form_refused(p, form) {
        return Some(why);
    }
    if form != LibraryForm::GlslEs {
        return None;
    }
    let opts = LibraryOptions::default();
    let lib = crate::compose::library::compose_library(p, &opts).ok()?;
    glsl_es::body(&lib, &opts).err().map(|e| e.message)
}

/// Why a mesh library (`curved=…`) has no `form`, if it has none: the forms that write
/// their own caller of the flat `P_trace(uv, view_ts, depth_scale)` (three.js's TSL node,
/// Unity's and Unreal's nodes) do not have the mesh form's inputs yet.
fn mesh_form_refused(p: &Pipeline, form: LibraryForm) -> Option<String> {
    let curved = p.curved?;
    matches!(form, LibraryForm::Tsl | LibraryForm::Unity | LibraryForm::Unreal).then(|| {
        format!(
            "curved={curved} has no {} form yet: its node calls the flat tile's trace; use wgsl, wesl, glsl, glsl-es, hlsl or msl",
            form.name()
        )
    })
}

/// The module's names may add at most [`limits::LONGEST_SUFFIX`] characters to the
/// prefix (what the limits assumed when they checked the prefix's length).
fn check_name_lengths(lib: &Library, prefix: &str) -> Result<(), CompileError> {
    let m = &lib.module;
    let names = m
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.as_deref())
        .chain(m.global_variables.iter().filter_map(|(_, g)| g.name.as_deref()))
        .chain(m.types.iter().filter_map(|(_, t)| t.name.as_deref()))
        .chain(m.constants.iter().filter_map(|(_, c)| c.name.as_deref()));
    let longest = names.max_by_key(|n| n.chars().count()).unwrap_or("");
    let extra = longest.chars().count().saturating_sub(prefix.chars().count());
    if extra > limits::LONGEST_SUFFIX {
        return Err(CompileError {
            stage: "library".into(),
            message: format!(
                "the name `{longest}` adds {extra} characters to the prefix, more than the {} the languages' name limits allow for",
                limits::LONGEST_SUFFIX
            ),
        });
    }
    Ok(())
}

/// The public functions, the hit type and the resources came out of `form`'s writer with
/// the names asked for: a writer renames a name its language reserves (naga prepends `gen_`
/// or appends `_`), which would leave the user calling a function that does not exist.
fn check_names_kept(lib: &Library, prefix: &str, form: LibraryForm, body: &str) -> Result<(), CompileError> {
    let mut names = vec![format!("{prefix}_trace"), format!("{}Hit", camel(prefix))];
    if lib.has_shadow {
        names.push(format!("{prefix}_shadow"));
    }
    if lib.has_ao {
        names.push(format!("{prefix}_ao"));
    }
    // GLSL keeps no sampler (a texture is combined with its sampler); TSL no nearest one
    // (it reads those textures with texel loads).
    let glsl = matches!(form, LibraryForm::Glsl | LibraryForm::GlslEs);
    let kept = |b: &&LibraryBinding| {
        !(glsl && b.kind == ResourceKind::Sampler
            || form == LibraryForm::Tsl && b.resource == crate::ir::Resource::Sampler(crate::ir::Filter::Nearest))
    };
    names.extend(lib.bindings.iter().filter(kept).map(|b| b.name.clone()));
    let lang = limits::limits(form).language;
    match names.iter().find(|n| !has_word(body, n)) {
        None => Ok(()),
        Some(n) => Err(CompileError {
            stage: format!("library {lang}"),
            message: format!(
                "prefix `{prefix}`: the {lang} writer renamed `{n}` (a name the language reserves); choose another prefix"
            ),
        }),
    }
}
