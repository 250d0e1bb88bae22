// Parallax occlusion mapping written by hand, the way a graphics programmer would without
// relief: Burger 2018 Algorithm 1 (linear search, 32 steps) then Algorithm 2 (binary search,
// 5 steps), inline in the fragment shader. Same inputs, bindings and shading as relief's
// generated render entry, so that the two can be timed against each other.

struct Params {
    view_proj: mat4x4<f32>,
    camera: vec4<f32>,   // xyz: eye in tangent space, w: depth scale
    light: vec4<f32>,    // xyz: toward the light, w: ambient
    quad: vec4<f32>,     // x: quad size (tiling)
}

struct VertexOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var height_map: texture_2d<f32>;
@group(0) @binding(2) var linear_sampler: sampler;
@group(0) @binding(4) var normal_map: texture_2d<f32>;
@group(0) @binding(5) var albedo_map: texture_2d<f32>;

const LINEAR_STEPS: u32 = 32u;
const BINARY_STEPS: u32 = 5u;

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32) -> VertexOutput {
    let corner = vec2<f32>(f32(vertex & 1u), f32(vertex >> 1u)) * params.quad.x;
    var out: VertexOutput;
    out.clip = params.view_proj * vec4<f32>(corner, 0.0, 1.0);
    out.world = corner;
    return out;
}

fn height(uv: vec2<f32>) -> f32 {
    return textureSampleLevel(height_map, linear_sampler, uv, 0.0).r;
}

@fragment
fn fs_main(@location(0) world: vec2<f32>) -> @location(0) vec4<f32> {
    let view = normalize(vec3<f32>(world, 0.0) - params.camera.xyz);
    let dir = vec3<f32>(view.xy * (params.camera.w / -view.z), -1.0);

    // Algorithm 1: linear search.
    let step_size = 1.0 / f32(LINEAR_STEPS);
    var t = 0.0;
    for (var i = 0u; i < LINEAR_STEPS; i++) {
        let p = vec3<f32>(world + dir.xy * t, 1.0 + dir.z * t);
        if (height(p.xy) >= p.z) {
            break;
        }
        t += step_size;
    }

    // Algorithm 2: binary search.
    var s = step_size / 2.0;
    t -= s;
    for (var i = 0u; i < BINARY_STEPS; i++) {
        let p = vec3<f32>(world + dir.xy * t, 1.0 + dir.z * t);
        s /= 2.0;
        if (height(p.xy) >= p.z) {
            t -= s;
        } else {
            t += s;
        }
    }

    let uv = world + dir.xy * t;
    let n = normalize(textureSampleLevel(normal_map, linear_sampler, uv, 0.0).xyz * 2.0 - 1.0);
    let albedo = textureSampleLevel(albedo_map, linear_sampler, uv, 0.0).rgb;
    let ambient = params.light.w;
    let diffuse = max(dot(n, params.light.xyz), 0.0);
    return vec4<f32>(albedo * (ambient + (1.0 - ambient) * diffuse), 1.0);
}
