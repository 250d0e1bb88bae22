//! The WESL form (`NAME_ident.wesl`): the WGSL form's module under a WESL module name, with
//! the `import` line to use it in its header.

use std::fmt::Write as _;

use super::common::{header_lines, Written};
use super::wgsl;
use crate::compose::library::{camel, Library, LibraryOptions};
use crate::spec::Pipeline;
use crate::CompileError;

/// The WESL module name of a pipeline's file stem: WESL names modules by identifiers, so
/// `-` becomes `_` (`linear_10__binary_5__shadow-soft_30` → `linear_10__binary_5__shadow_soft_30`).
pub fn wesl_module_name(stem: &str) -> String {
    stem.replace('-', "_")
}

/// `NAME_ident.wesl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let body = wgsl::body(lib)?;
    let module = wesl_module_name(&p.file_stem());
    let mut text = header_lines(p, lib, opts, &wgsl::HEADER);
    let _ = writeln!(
        text,
        "// As a WESL module: `import package::{module}::{{{pre}_trace, {camel}Hit}};` with this file at the\n// package's root.\n",
        pre = opts.prefix,
        camel = camel(&opts.prefix)
    );
    text += &body;
    Ok(vec![Written { name: format!("{module}.wesl"), text, code: Some(body) }])
}
