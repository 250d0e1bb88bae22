// The relief material's fragment shader: relief's library (the `relief export --target wgsl`
// bundle's file, imported by naga_oil as `relief::bundle`) finds the hit, and the fragment
// shades it as `relief render` does (relief.json's `shading`), without Bevy's PBR lighting:
//   rgb = albedo * (ambient * ao + (1 - ambient) * max(dot(n, l), 0) * shadow)
// The quad lies in z = 0 with u along x and v along y, so tangent space is world space.

#import bevy_pbr::{forward_io::VertexOutput, mesh_view_bindings::view}
#import relief::bundle::{relief_trace, relief_shadow, relief_ao}

@group(#{MATERIAL_BIND_GROUP}) @binding(120) var albedo_texture: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(121) var albedo_sampler: sampler;
@group(#{MATERIAL_BIND_GROUP}) @binding(122) var normal_texture: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(123) var normal_sampler: sampler;
// xyz: toward the light; w: the ambient share.
@group(#{MATERIAL_BIND_GROUP}) @binding(130) var<uniform> light: vec4<f32>;
// x: the relief's depth scale.
@group(#{MATERIAL_BIND_GROUP}) @binding(131) var<uniform> relief_params: vec4<f32>;

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    let depth = relief_params.x;
    let view_ts = normalize(in.world_position.xyz - view.world_position);
    let hit = relief_trace(in.uv, view_ts, depth);
    let l = light.xyz;
    let visibility = relief_shadow(hit, l, depth);
    let occlusion = relief_ao(hit);
    let n = normalize(textureSampleLevel(normal_texture, normal_sampler, hit.uv, 0.0).xyz * 2.0 - 1.0);
    let albedo = textureSampleLevel(albedo_texture, albedo_sampler, hit.uv, 0.0).rgb;
    let ambient = light.w;
    let rgb = albedo * (ambient * occlusion + (1.0 - ambient) * max(dot(n, l), 0.0) * visibility);
    return vec4<f32>(clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
