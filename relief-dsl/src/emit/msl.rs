//! The MSL form (`NAME.lib.metal`). Metal has no global resources, so every function that
//! reads one takes it as an extra argument (naga's convention): `relief_trace(uv, view_ts,
//! depth_scale, relief_height, relief_sampler, …)`, in the order the header lists for each
//! function. The module is validated by naga before it is written.

use naga::back::msl;

use super::common::{err, header_lines, Header, ResourceArguments, Written};
use crate::compose::library::{Library, LibraryOptions, ResourceKind};
use crate::spec::Pipeline;
use crate::CompileError;

const HEADER: Header = Header {
    arguments: ResourceArguments::ModuleOrder,
    intro: "// Resources (Metal has none global: each function above takes those it reads as extra\n\
            // arguments after its own, in the order listed; the bindings are for the other languages):\n",
    resource_type: msl_type,
    by_name: false,
    no_nearest_sampler: false,
};

fn msl_type(kind: ResourceKind) -> &'static str {
    match kind {
        ResourceKind::Sampler => "metal::sampler",
        ResourceKind::Texture2d => "metal::texture2d<float, metal::access::sample>",
        ResourceKind::Texture3d => "metal::texture3d<float, metal::access::sample>",
    }
}

/// `NAME.lib.metal`.
pub(crate) fn write(p: &Pipeline, lib: &Library, opts: &LibraryOptions) -> Result<Vec<Written>, CompileError> {
    let options = msl::Options { lang_version: (2, 0), force_loop_bounding: false, ..msl::Options::default() };
    let (body, _) = msl::write_string(&lib.module, &lib.info, &options, &msl::PipelineOptions::default())
        .map_err(|e| err("msl", e))?;
    let text = header_lines(p, lib, opts, &HEADER) + &body;
    Ok(vec![Written { name: format!("{}.lib.metal", p.file_stem()), text, code: Some(body) }])
}
