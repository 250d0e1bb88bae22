//! The three.js TSL form (`NAME.tsl.wgsl`): WGSL with every texture and sampler a trailing
//! argument of the functions that read it, in binding order. three.js's node system declares
//! the bindings itself, so a `wgslFn` can only hand the library the textures it was given as
//! arguments.

use naga::back::wgsl;

use super::common::{err, header_lines, resources_as_arguments, wgsl_type, Header, ResourceArguments, Written};
use crate::compose::library::{Library, LibraryOptions};
use crate::spec::Pipeline;
use crate::CompileError;

const HEADER: Header = Header {
    arguments: ResourceArguments::BindingOrder,
    intro: "// three.js TSL (`wgsl(this)` as an include of your `wgslFn`): no resource is global; each function\n\
            // above takes those it reads as extra arguments after its own, in the order listed (the group and\n\
            // binding numbers are for the other forms; TSL binds what you pass):\n",
    resource_type: wgsl_type,
    by_name: false,
};

/// `NAME.tsl.wgsl`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let (module, info) = resources_as_arguments(lib)?;
    let body = wgsl::write_string(&module, &info, wgsl::WriterFlags::empty()).map_err(|e| err("tsl", e))?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.tsl.wgsl", p.file_stem()), text, code: Some(body) }])
}
