//! The WGSL form (`NAME.lib.wgsl`): the library module as naga writes it, resources as
//! globals. With [`LibraryOptions::import_path`] its first line is `#define_import_path PATH`
//! (a `naga_oil` / WESL import).

use std::fmt::Write as _;

use naga::back::wgsl;

use super::common::{err, header_lines, wgsl_type, Header, ResourceArguments, Written};
use crate::compose::library::{Library, LibraryOptions};
use crate::spec::Pipeline;
use crate::CompileError;

/// The WGSL header: resources as globals at their group and binding.
pub(crate) const HEADER: Header = Header {
    arguments: ResourceArguments::Global,
    intro: "// Resources:\n",
    resource_type: wgsl_type,
    by_name: false,
    no_nearest_sampler: false,
};

/// naga's WGSL text of the library module.
pub(crate) fn body(lib: &Library) -> Result<String, CompileError> {
    wgsl::write_string(&lib.module, &lib.info, wgsl::WriterFlags::empty()).map_err(|e| err("wgsl", e))
}

/// `NAME.lib.wgsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let body = body(lib)?;
    let mut text = String::new();
    if let Some(path) = &opts.import_path {
        check_import_path(path)?;
        let _ = writeln!(text, "#define_import_path {path}\n");
    }
    text += &header_lines(p, lib, opts, &HEADER);
    text += &body;
    Ok(vec![Written { name: format!("{}.lib.wgsl", p.file_stem()), text, code: Some(body) }])
}

fn check_import_path(path: &str) -> Result<(), CompileError> {
    let ok = path.split("::").all(|seg| {
        seg.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && seg.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    });
    if ok {
        Ok(())
    } else {
        Err(err("wgsl", format!("import path `{path}` is not `::`-separated identifiers")))
    }
}
