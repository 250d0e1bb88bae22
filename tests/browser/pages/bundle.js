// What the engine pages (babylon.html, threejs.html) share in reading a `relief export`
// bundle as an engine's user would: its relief.json and library text, the light and clear
// colour relief.json gives, the GLSL that shades a hit, and the pictures handed back.

/** The sRGB encoding of a linear channel. */
export const encode = (c) => (c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055);

/** The bytes at `url`, or an error naming it and the status. */
export async function bytes(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: ${r.status}`);
  return await r.arrayBuffer();
}

/**
 * The bundle in the folder `dir` (a URL path): its relief.json, its library's text and the
 * address mode of its edge (`clamp_to_edge` or `repeat`).
 */
export async function readBundle(dir) {
  const json = JSON.parse(new TextDecoder().decode(await bytes(`${dir}/relief.json`)));
  const lib = new TextDecoder().decode(await bytes(`${dir}/${json.library[0]}`));
  return { json, lib, address: json.edge === 'clamp' ? 'clamp_to_edge' : 'repeat' };
}

/** The light uniform as [x, y, z, w]: xyz toward the light (normalized), w the ambient share. */
export function lightOf(json) {
  const l = json.shading.light_dir;
  const len = Math.hypot(l[0], l[1], l[2]);
  return [l[0] / len, l[1] / len, l[2] / len, json.shading.ambient];
}

/** The clear colour as relief writes it: the linear colour sRGB-encoded, [r, g, b]. */
export const clearOf = (json) => json.shading.clear_color_linear.slice(0, 3).map(encode);

/**
 * The GLSL (ES 1.00 and 3.00 alike) that shades the library's hit, given the uniforms
 * u_eye (xyz the eye in tangent space, w the relief depth), u_light (xyz toward the light,
 * w the ambient share), u_albedo and u_normal, the varyings v_world and v_uv, and
 * `srgb_encode` (SRGB_ENCODE): a `vec3 color` in linear light, as relief's render entry
 * shades. (No comment after a semicolon: Babylon splits a uniform's line there.)
 */
export function glslShade(json) {
  const shadow = json.has_shadow ? 'relief_shadow(hit, to_light, depth)' : '1.0';
  const ao = json.has_ao ? 'relief_ao(hit)' : '1.0';
  return `  float depth = u_eye.w;
  vec3 view = normalize(v_world - u_eye.xyz);
  ReliefHit hit = relief_trace(v_uv, view, depth);
  vec3 to_light = u_light.xyz;
  float visibility = ${shadow};
  float occlusion = ${ao};
  vec3 n = normalize(textureLod(u_normal, hit.uv, 0.0).xyz * 2.0 - 1.0);
  vec3 albedo = textureLod(u_albedo, hit.uv, 0.0).rgb;
  float ambient = u_light.w;
  vec3 color = albedo * (ambient * occlusion + (1.0 - ambient) * max(dot(n, to_light), 0.0) * visibility);`;
}

/** `srgb_encode`, the GLSL of `encode` on a vec3. */
export const SRGB_ENCODE = `vec3 srgb_encode(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}`;

/** RGBA8 bytes as hex, for the Rust test. */
export const hex = (px) => Array.from(px, (b) => b.toString(16).padStart(2, '0')).join('');

/** A `size`² RGBA8 picture WebGL read bottom row first, top row first as relief's frames. */
export function topRowFirst(px, size) {
  const out = new Uint8Array(px.length);
  const row = size * 4;
  for (let y = 0; y < size; y++) out.set(px.subarray((size - 1 - y) * row, (size - y) * row), y * row);
  return out;
}
