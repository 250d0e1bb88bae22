// relief report, live: the sweep's pipelines drawn with WebGPU from the browser data that
// `relief report` writes under browser/ (see relief-runtime/src/report/browser.rs), and
// measured on the reader's GPU. The page works without this script, and without WebGPU the
// section says so.
//
// What it needs from the browser: WebGPU with `float32-filterable` (the heights and maps are
// 32-bit float textures sampled with linear filtering); `timestamp-query` when granted
// (frame times are then device time, else wall clock, recorded as such); `DecompressionStream`
// (the data files are gzip-compressed).
"use strict";

(function () {
  var M = window.RELIEF_MANIFEST;
  var root = document.getElementById("live-view");
  var statusEl = document.getElementById("live-status");
  function say(t) { if (statusEl) statusEl.textContent = t; }

  // ---------------------------------------------------------------------------------------
  // Data files: each sets window.RELIEF_DATA[name] = { meta, gz, shuffle, bytes } when loaded
  // as a script, which works from file:// as well as over http. `gz` is base64 of the gzip of
  // the bytes split into `shuffle`-byte planes (report/browser.rs, `pack`): inflated here with
  // the browser's DecompressionStream, then the planes put back.
  async function inflate(d) {
    var bin = atob(d.gz);
    var packed = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) packed[i] = bin.charCodeAt(i);
    var stream = new Blob([packed]).stream().pipeThrough(new DecompressionStream("gzip"));
    var planes = new Uint8Array(await new Response(stream).arrayBuffer());
    if (planes.length !== d.bytes) throw new Error("inflated " + planes.length + " bytes, not " + d.bytes);
    return unshuffle(planes, d.shuffle);
  }
  // The inverse of the writer's `shuffle`: byte b of element i is at b * n + i.
  function unshuffle(planes, elem) {
    if (elem <= 1) return planes;
    var n = Math.floor(planes.length / elem), out = new Uint8Array(planes.length);
    for (var b = 0; b < elem; b++) {
      var from = b * n;
      for (var i = 0; i < n; i++) out[i * elem + b] = planes[from + i];
    }
    out.set(planes.subarray(n * elem), n * elem);
    return out;
  }
  var cache = {};
  function load(name) {
    if (cache[name]) return cache[name];
    cache[name] = new Promise(function (resolve, reject) {
      var s = document.createElement("script");
      s.src = "browser/" + name + ".js";
      s.onload = function () {
        var d = (window.RELIEF_DATA || {})[name];
        if (!d) { reject(new Error("browser/" + name + ".js set no data")); return; }
        delete window.RELIEF_DATA[name];
        inflate(d).then(function (bytes) { resolve({ meta: d.meta, bytes: bytes }); },
          function (e) { reject(new Error("browser/" + name + ".js: " + e.message)); });
      };
      s.onerror = function () { reject(new Error("cannot load browser/" + name + ".js")); };
      document.head.appendChild(s);
    });
    return cache[name];
  }

  // ---------------------------------------------------------------------------------------
  // The device.
  var G = null; // { device, adapter description, timestamps }
  var gpuPromise = null;
  function gpu() {
    if (!gpuPromise) gpuPromise = openGpu();
    return gpuPromise;
  }
  async function openGpu() {
    if (!navigator.gpu) throw new Error("this browser has no WebGPU (navigator.gpu is missing)");
    if (typeof DecompressionStream === "undefined") throw new Error("this browser has no DecompressionStream, which inflates the browser data");
    var adapter = await navigator.gpu.requestAdapter({ powerPreference: "high-performance" });
    if (!adapter) throw new Error("this browser offers no WebGPU adapter");
    if (!adapter.features.has("float32-filterable")) throw new Error("the WebGPU adapter lacks float32-filterable, which the 32-bit float height and map textures need");
    var features = ["float32-filterable"];
    var timestamps = adapter.features.has("timestamp-query");
    if (timestamps) features.push("timestamp-query");
    var device = await adapter.requestDevice({
      requiredFeatures: features,
      requiredLimits: { maxSampledTexturesPerShaderStage: adapter.limits.maxSampledTexturesPerShaderStage },
    });
    device.addEventListener("uncapturederror", function (e) { console.error("WebGPU: " + e.error.message); });
    var info = adapter.info || {};
    var desc = [info.vendor, info.architecture, info.device, info.description].filter(function (x) { return x; }).join(" ");
    G = { device: device, adapter: desc || "unknown WebGPU adapter", timestamps: timestamps };
    return G;
  }

  var BPP = { r32float: 4, r16float: 2, rgba8unorm: 4, "rgba8unorm-srgb": 4, rg32float: 8, rgba32float: 16 };
  function texture(device, d) {
    var m = d.meta;
    var t = device.createTexture({
      size: [m.width, m.height, m.depth], format: m.format, dimension: m.dimension, mipLevelCount: m.levels.length,
      usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
    });
    var off = 0;
    m.levels.forEach(function (len, l) {
      var w = Math.max(1, m.width >> l), h = Math.max(1, m.height >> l);
      var z = m.dimension === "3d" ? Math.max(1, m.depth >> l) : m.depth;
      device.queue.writeTexture({ texture: t, mipLevel: l }, d.bytes, { offset: off, bytesPerRow: w * BPP[m.format], rowsPerImage: h }, [w, h, z]);
      off += len;
    });
    return t.createView({ dimension: m.view });
  }

  // A scene's textures and samplers on the device, loaded once; its maps are added by
  // `withMaps` when a pipeline that reads them is first drawn or probed.
  var sceneCache = {};
  function sceneRes(scene) {
    if (sceneCache[scene.label]) return sceneCache[scene.label];
    sceneCache[scene.label] = (async function () {
      var device = (await gpu()).device;
      var r = { maps: {}, mapTextures: {} };
      for (var k of ["height", "normal", "albedo"]) r[k] = texture(device, await load(scene.textures[k]));
      var mode = scene.edge === "clamp" ? "clamp-to-edge" : "repeat";
      r.linear = device.createSampler({ addressModeU: mode, addressModeV: mode, magFilter: "linear", minFilter: "linear" });
      r.nearest = device.createSampler({ addressModeU: mode, addressModeV: mode, magFilter: "nearest", minFilter: "nearest" });
      return r;
    })();
    return sceneCache[scene.label];
  }
  // The scene's resources with every map pipeline `p` binds on the device (each loaded or
  // computed once, `loadMap`).
  async function withMaps(p, scene) {
    var res = await sceneRes(scene), device = (await gpu()).device;
    var slugs = p.render_bindings.concat(p.probe_bindings).map(function (b) { return b[1]; })
      .filter(function (src) { return src.indexOf("map:") === 0; }).map(function (src) { return src.slice(4); });
    for (var slug of slugs) {
      if (!res.mapTextures[slug]) res.mapTextures[slug] = loadMap(scene, slug).then(function (d) { return texture(device, d); });
      res.maps[slug] = await res.mapTextures[slug];
    }
    return res;
  }

  // A pipeline's shader module, checked, loaded once.
  var moduleCache = {};
  function shaderModule(p) {
    if (moduleCache[p.pipeline]) return moduleCache[p.pipeline];
    moduleCache[p.pipeline] = (async function () {
      var device = (await gpu()).device;
      var code = new TextDecoder().decode((await load(p.wgsl)).bytes);
      var module = device.createShaderModule({ code: code, label: p.pipeline });
      var info = await module.getCompilationInfo();
      var errors = info.messages.filter(function (m) { return m.type === "error"; });
      if (errors.length) throw new Error(p.pipeline + ": " + errors.map(function (m) { return m.message; }).join("; "));
      return module;
    })();
    return moduleCache[p.pipeline];
  }

  function bindGroup(device, layout, list, res, buffers) {
    var entries = list.map(function (b) {
      var n = b[0], src = b[1], resource;
      if (src === "params" || src === "rays" || src === "hits") resource = { buffer: buffers[src] };
      else if (src === "linear" || src === "nearest") resource = res[src];
      else if (src.indexOf("map:") === 0) resource = res.maps[src.slice(4)];
      else resource = res[src];
      if (!resource) throw new Error("no resource for binding " + n + " (" + src + ")");
      return { binding: n, resource: resource };
    });
    return device.createBindGroup({ layout: layout, entries: entries });
  }

  // ---------------------------------------------------------------------------------------
  // The camera (relief-runtime/src/scene/camera.rs) and the Params block (its layout from
  // the manifest, which takes it from the ABI).
  function rad(d) { return d * Math.PI / 180; }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function scale(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function norm(a) { return scale(a, 1 / Math.sqrt(dot(a, a))); }

  function eye(c) {
    var a = rad(c.angle_deg), az = rad(c.azimuth_deg);
    return [c.target[0] + c.distance * Math.sin(a) * Math.cos(az), c.target[1] + c.distance * Math.sin(a) * Math.sin(az), c.target[2] + c.distance * Math.cos(a)];
  }
  function basis(c) {
    var a = rad(c.angle_deg), az = rad(c.azimuth_deg);
    var f = [-Math.sin(a) * Math.cos(az), -Math.sin(a) * Math.sin(az), -Math.cos(a)];
    var u = [-Math.cos(a) * Math.cos(az), -Math.cos(a) * Math.sin(az), Math.sin(a)];
    return { f: f, r: cross(f, u), u: u };
  }
  // Column-major projection × view, right-handed, depth 0..1 (glam's perspective_rh and
  // look_at_rh).
  function viewProj(c, aspect) {
    var e = eye(c), up = basis(c).u;
    var f = norm(sub(c.target, e)), s = norm(cross(f, up)), u = cross(s, f);
    var view = [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, -dot(s, e), -dot(u, e), dot(f, e), 1];
    var near = c.distance * 0.01, far = c.distance * 100;
    var h = 1 / Math.tan(rad(c.fov_deg) / 2), w = h / aspect, r = far / (near - far);
    var proj = [w, 0, 0, 0, 0, h, 0, 0, 0, 0, r, -1, 0, 0, r * near, 0];
    var out = new Array(16);
    for (var col = 0; col < 4; col++) for (var row = 0; row < 4; row++) {
      var x = 0;
      for (var k = 0; k < 4; k++) x += proj[k * 4 + row] * view[col * 4 + k];
      out[col * 4 + row] = x;
    }
    return out;
  }
  function pixelSize(c, height) { return 2 * Math.tan(rad(c.fov_deg) / 2) / height; }

  // The view the page draws: the scene's own, changed by the sliders and the drag.
  function viewOf(scene, v) {
    var c = JSON.parse(JSON.stringify(scene.camera));
    var tiling = v && v.tiling ? v.tiling : scene.tiling;
    var k = tiling / scene.tiling;
    c.distance *= k;
    c.target = scale(c.target, k);
    if (v && v.angle !== undefined) c.angle_deg = v.angle;
    if (v && v.azimuth !== undefined) c.azimuth_deg = v.azimuth;
    return { camera: c, tiling: tiling, depth: v && v.depth ? v.depth : scene.depth_scale };
  }

  function params(scene, view, aspect, pxSize) {
    var c = view.camera, e = eye(c), b = basis(c), l = norm(scene.light_dir);
    var values = {
      view_proj: viewProj(c, aspect),
      camera: [e[0], e[1], e[2], view.depth],
      light: [l[0], l[1], l[2], M.ambient],
      quad: [view.tiling, scene.edge === "clamp" ? 1 : 0, 0, 0],
      pixel_right: [b.r[0], b.r[1], b.r[2], pxSize],
      pixel_up: [b.u[0], b.u[1], b.u[2], 0],
    };
    var out = new Float32Array(M.params.size / 4);
    M.params.members.forEach(function (m) {
      var v = values[m.name];
      if (!v) throw new Error("the page does not know the Params member " + m.name);
      out.set(v, m.offset / 4);
    });
    return out;
  }

  // One probe ray per pixel that sees the quad (Scene::rays_wh), as the ABI's records.
  function rays(scene, view, size) {
    var c = view.camera, e = eye(c), b = basis(c), ty = Math.tan(rad(c.fov_deg) / 2);
    var buf = new ArrayBuffer(size * size * M.ray_bytes), dv = new DataView(buf), n = 0, ps = pixelSize(c, size);
    for (var py = 0; py < size; py++) for (var px = 0; px < size; px++) {
      var nx = 2 * (px + 0.5) / size - 1, ny = 1 - 2 * (py + 0.5) / size;
      var d = norm([b.f[0] + nx * ty * b.r[0] + ny * ty * b.u[0], b.f[1] + nx * ty * b.r[1] + ny * ty * b.u[1], b.f[2] + nx * ty * b.r[2] + ny * ty * b.u[2]]);
      if (!(e[2] > 0 && d[2] < 0)) continue;
      var s = -e[2] / d[2], x = e[0] + s * d[0], y = e[1] + s * d[1];
      if (x < 0 || x > view.tiling || y < 0 || y > view.tiling) continue;
      var k = view.depth / -d[2], o = n * M.ray_bytes;
      [x, y, d[0] * k, d[1] * k, -1].forEach(function (v, i) { dv.setFloat32(o + 4 * i, v, true); });
      dv.setUint32(o + 20, px, true);
      dv.setUint32(o + 24, py, true);
      dv.setFloat32(o + 28, ps, true);
      n++;
    }
    return { bytes: new Uint8Array(buf, 0, n * M.ray_bytes), count: n };
  }

  // The probe rays of the measured view at size², as the runtime's Scene::rays gives them (every
  // `stride`-th when the frame has more than the manifest says): computed from the f32 terms the
  // manifest ships as bit patterns (`rays_from`), every operation rounded to f32 in Rust's order,
  // so the records are the runtime's bit for bit (tests/report_browser.rs checks it).
  function probeRays(scene, size) {
    var F = Math.fround, t = scene.rays_from, word = new DataView(new ArrayBuffer(4));
    function f32(b) { word.setUint32(0, b, true); return word.getFloat32(0, true); }
    function vec(b) { return b.map(f32); }
    var e = vec(t.eye), fw = vec(t.forward), r = vec(t.right), u = vec(t.up), ty = f32(t.tan_half_fov);
    var depth = f32(t.depth_scale), tiling = f32(t.tiling), w = F(size), h = F(size), aspect = F(w / h);
    var ps = F(F(2 * ty) / h), out = [], n = 0;
    for (var py = 0; py < size; py++) for (var px = 0; px < size; px++) {
      var nx = F(F(F(2 * F(px + 0.5)) / w) - 1), ny = F(1 - F(F(2 * F(py + 0.5)) / h));
      var a = F(F(nx * ty) * aspect), b = F(ny * ty), v = [0, 1, 2].map(function (i) { return F(F(fw[i] + F(a * r[i])) + F(b * u[i])); });
      var rec = F(1 / F(Math.sqrt(F(F(F(v[0] * v[0]) + F(v[1] * v[1])) + F(v[2] * v[2])))));
      v = v.map(function (c) { return F(c * rec); });
      if (!(e[2] > 0 && v[2] < 0)) continue;
      var s = F(-e[2] / v[2]), x = F(e[0] + F(s * v[0])), y = F(e[1] + F(s * v[1]));
      if (!(x >= 0 && x <= tiling && y >= 0 && y <= tiling)) continue;
      var k = F(depth / -v[2]);
      out.push([x, y, F(v[0] * k), F(v[1] * k), px, py]);
      n++;
    }
    var stride = Math.max(1, Math.ceil(n / M.max_probe_rays)), kept = Math.ceil(n / stride);
    var buf = new ArrayBuffer(kept * M.ray_bytes), dv = new DataView(buf);
    for (var i = 0; i < kept; i++) {
      var q = out[i * stride], o = i * M.ray_bytes;
      [q[0], q[1], q[2], q[3], -1].forEach(function (c, j) { dv.setFloat32(o + 4 * j, c, true); });
      dv.setUint32(o + 20, q[4], true);
      dv.setUint32(o + 24, q[5], true);
      dv.setFloat32(o + 28, ps, true);
    }
    return { meta: { rays: kept, all_rays: n, stride: stride }, bytes: new Uint8Array(buf) };
  }

  // ---------------------------------------------------------------------------------------
  // The 3D distance field (relief-runtime/src/maps/distance_field.rs), not shipped but computed
  // here from the scene's f32 heights (level 0 of the height file): the box bound from the
  // 3×3 maxima, one Felzenszwalb–Huttenlocher lower envelope along x then along y per slice
  // (wrapping lines unrolled three times), max(0, B − δ), rounded down to f32. Every f64
  // operation is the generator's, in its order (JS numbers are f64 and Math.sqrt is correctly
  // rounded), so the field is the runtime's bit for bit (tests/report_browser.rs checks it).

  // out[i] = min over j of (spacing (i − j))² + f[j] on n values; v, z scratch of n and n + 1.
  function envelope(f, n, spacing, out, v, z) {
    var k = 0;
    v[0] = 0;
    z[0] = -Infinity;
    z[1] = Infinity;
    for (var q = 1; q < n; q++) {
      var pq = q * spacing, fq = f[q] + pq * pq;
      for (;;) {
        var p = v[k], pp = p * spacing;
        var s = (fq - (f[p] + pp * pp)) / (2 * (pq - pp));
        if (s <= z[k] && k > 0) { k--; continue; }
        if (s <= z[k]) { v[0] = q; z[1] = Infinity; break; }
        k++;
        v[k] = q;
        z[k] = s;
        z[k + 1] = Infinity;
        break;
      }
    }
    k = 0;
    for (var i = 0; i < n; i++) {
      var pi = i * spacing;
      while (z[k + 1] < pi) k++;
      var d = pi - v[k] * spacing;
      out[i] = d * d + f[v[k]];
    }
  }
  // One line, wrapping (three copies, the middle one kept) or not; `sc` holds scratch for 3n.
  function envelopeLine(f, n, spacing, wrap, out, sc) {
    if (wrap && n > 1) {
      for (var c = 0; c < 3; c++) sc.ext.set(f.subarray(0, n), c * n);
      envelope(sc.ext, 3 * n, spacing, sc.res, sc.v, sc.z);
      out.set(sc.res.subarray(n, 2 * n));
    } else {
      envelope(f, n, spacing, out, sc.v, sc.z);
    }
  }
  // The largest f32 not above v (encode.rs, f32_down): Math.fround rounds to nearest, so one
  // step down when it rounded up, through the bit pattern (0 steps to −2^-149).
  var downF = new Float32Array(1), downU = new Uint32Array(downF.buffer);
  function f32Down(v) {
    var f = Math.fround(v);
    if (!(f > v)) return f;
    if (f === 0) return -Math.pow(2, -149);
    downF[0] = f;
    downU[0] = f > 0 ? downU[0] - 1 : downU[0] + 1;
    return downF[0];
  }
  // The field of `heights` (w × h f32 values, row-major) with edge mode `edge` ("repeat" or
  // "clamp") and `depth` slices: w·h·depth f32 values, slice-major, slice 0 at the bottom.
  function distanceField(heights, w, h, edge, depth) {
    if (edge !== "repeat" && edge !== "clamp") throw new Error("edge mode " + edge + " is neither repeat nor clamp");
    if (heights.length !== w * h || w < 1 || h < 1 || !(depth >= 1)) throw new Error("a " + w + " × " + h + " × " + depth + " distance field from " + heights.length + " heights");
    var wrap = edge === "repeat";
    var at = function (i, n) { return wrap ? ((i % n) + n) % n : Math.min(Math.max(i, 0), n - 1); };
    // H_q: the largest of the 3×3 texels around q (f32's max, which passes over NaN).
    var hmax = new Float64Array(w * h);
    for (var y = 0; y < h; y++) for (var x = 0; x < w; x++) {
      var m = -Infinity;
      for (var dy = -1; dy <= 1; dy++) for (var dx = -1; dx <= 1; dx++) {
        var t = heights[at(y + dy, h) * w + at(x + dx, w)];
        if (t > m) m = t;
      }
      hmax[y * w + x] = m;
    }
    var a = 1 / w, b = 1 / h, c = 1 / depth, diag = Math.sqrt(a * a + b * b + c * c) * (1 + 1e-12);
    var n3 = 3 * Math.max(w, h);
    var sc = { ext: new Float64Array(n3), res: new Float64Array(n3), v: new Int32Array(n3), z: new Float64Array(n3 + 1) };
    var out = new Float32Array(w * h * depth), g = new Float64Array(w * h);
    var rowOut = new Float64Array(w), col = new Float64Array(h), colOut = new Float64Array(h);
    for (var k = 0; k < depth; k++) {
      var zk = (k + 0.5) / depth;
      for (var i = 0; i < w * h; i++) {
        var d = zk - hmax[i];
        d = d > 0 ? d : 0; // f64::max(d, 0.0): NaN gives 0
        g[i] = d * d;
      }
      for (y = 0; y < h; y++) {
        envelopeLine(g.subarray(y * w, (y + 1) * w), w, 1 / w, wrap, rowOut, sc);
        g.set(rowOut, y * w);
      }
      var base = k * w * h;
      for (x = 0; x < w; x++) {
        for (y = 0; y < h; y++) col[y] = g[y * w + x];
        envelopeLine(col, h, 1 / h, wrap, colOut, sc);
        for (y = 0; y < h; y++) {
          var sq = colOut[y] > 0 ? colOut[y] : 0, e = Math.sqrt(sq) - diag;
          out[base + y * w + x] = f32Down(e > 0 ? e : 0);
        }
      }
    }
    return out;
  }

  // The patch map (relief-runtime's maps/cell/patch.rs) of `heights` (w × h f32 values,
  // row-major) under `edge`: per cell of the cell grid (w × h under repeat; (w + 1) × (h + 1)
  // under clamp, whose first and last columns and rows are the border strips with both corners
  // on the border texel), [h00, h10 − h00, h01 − h00, (h11 − h10) − (h01 − h00)], row-major.
  // Each difference is taken in double and rounded once to f32 (Math.fround): the difference
  // of two f32 values rounded to double and then to f32 is the correctly rounded f32
  // difference (double has more than 2·24 + 2 bits), so the values are the runtime's bit for bit.
  function cellPatch(heights, w, h, edge) {
    if (edge !== "repeat" && edge !== "clamp") throw new Error("edge mode " + edge + " is neither repeat nor clamp");
    if (heights.length !== w * h || w < 1 || h < 1) throw new Error("a " + w + " × " + h + " patch map from " + heights.length + " heights");
    var wrap = edge === "repeat", cw = wrap ? w : w + 1, ch = wrap ? h : h + 1;
    var ends = function (i, n) {
      return wrap ? [i, (i + 1) % n] : [Math.min(Math.max(i - 1, 0), n - 1), Math.min(i, n - 1)];
    };
    var out = new Float32Array(cw * ch * 4);
    for (var j = 0; j < ch; j++) {
      var y = ends(j, h);
      for (var i = 0; i < cw; i++) {
        var x = ends(i, w), o = (j * cw + i) * 4;
        var h00 = heights[y[0] * w + x[0]], h10 = heights[y[0] * w + x[1]];
        var h01 = heights[y[1] * w + x[0]], h11 = heights[y[1] * w + x[1]];
        var dy = Math.fround(h01 - h00);
        out[o] = h00;
        out[o + 1] = Math.fround(h10 - h00);
        out[o + 2] = dy;
        out[o + 3] = Math.fround(Math.fround(h11 - h10) - dy);
      }
    }
    return out;
  }

  // A scene's map by its slug: its data file, or, for a map the manifest marks
  // `computed_in_page` (the distance field, the patch map), computed here from the scene's
  // height file, once.
  var computed = {};
  function loadMap(scene, slug) {
    var m = scene.maps[slug];
    if (m === undefined) return Promise.reject(new Error("scene " + scene.label + " has no map " + slug));
    if (typeof m === "string") return load(m);
    var key = scene.label + "|" + slug;
    if (!computed[key]) computed[key] = (async function () {
      var kind = m.computed_in_page;
      if (kind !== "distance_field" && kind !== "cell_patch") throw new Error("the page cannot compute a map of kind " + kind);
      var hs = kind === "cell_patch" ? m.height_size : m.size, w = hs[0], h = hs[1];
      var hd = await load(scene.textures.height);
      if (hd.meta.format !== "r32float" || hd.meta.width !== w || hd.meta.height !== h)
        throw new Error(scene.label + ": the height file is " + hd.meta.width + " × " + hd.meta.height + " " + hd.meta.format + ", the " + slug + " map wants " + w + " × " + h + " r32float");
      // Level 0 of the height file: the heights the runtime builds its maps from.
      var heights = new Float32Array(hd.bytes.buffer.slice(hd.bytes.byteOffset, hd.bytes.byteOffset + w * h * 4));
      if (kind === "cell_patch") {
        var patch = cellPatch(heights, w, h, m.edge);
        return { meta: { width: m.size[0], height: m.size[1], depth: 1, format: "rgba32float", dimension: "2d", view: "2d", levels: [patch.byteLength] }, bytes: new Uint8Array(patch.buffer) };
      }
      var depth = m.size[2], field = distanceField(heights, w, h, m.edge, depth), dim = depth > 1 ? "3d" : "2d";
      return { meta: { width: w, height: h, depth: depth, format: "r32float", dimension: dim, view: dim, levels: [field.byteLength] }, bytes: new Uint8Array(field.buffer) };
    })();
    return computed[key];
  }

  // ---------------------------------------------------------------------------------------
  // Drawing, timing and probing.
  function pipelineOf(text) { return M.pipelines.find(function (p) { return p.pipeline === text; }); }
  function sceneOf(label) { return M.scenes.find(function (s) { return s.label === label; }); }

  var renderCache = {};
  async function renderer(p, scene) {
    var key = p.pipeline + "|" + scene.label;
    if (!renderCache[key]) renderCache[key] = (async function () {
      var device = (await gpu()).device;
      var module = await shaderModule(p);
      var res = await withMaps(p, scene);
      var pipe = await device.createRenderPipelineAsync({
        layout: "auto",
        vertex: { module: module, entryPoint: "vs_main" },
        fragment: { module: module, entryPoint: "fs_main", targets: [{ format: M.frame_format }] },
        primitive: { topology: "triangle-strip" },
        depthStencil: p.writes_depth ? { format: "depth32float", depthWriteEnabled: true, depthCompare: "always" } : undefined,
      });
      var ub = device.createBuffer({ size: M.params.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
      var bg = bindGroup(device, pipe.getBindGroupLayout(0), p.render_bindings, res, { params: ub });
      return { pipe: pipe, ub: ub, bg: bg, device: device };
    })();
    return renderCache[key];
  }

  function target(device, size) {
    return device.createTexture({ size: [size, size], format: M.frame_format, usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC });
  }

  function pass(enc, r, view, ts) {
    var c = M.clear;
    var desc = { colorAttachments: [{ view: view, loadOp: "clear", storeOp: "store", clearValue: { r: c[0], g: c[1], b: c[2], a: c[3] } }] };
    if (ts) desc.timestampWrites = ts;
    var p = enc.beginRenderPass(desc);
    p.setPipeline(r.pipe);
    p.setBindGroup(0, r.bg);
    p.draw(4);
    p.end();
  }

  // Draws pipeline `text` on scene `label` at `size²` at the measured view (or `v`; with
  // `v.params`, that Params block as given) and returns the frame's RGBA8 bytes (sRGB), rows from the top, and the Params it used.
  async function frame(text, label, size, v) {
    var p = pipelineOf(text), scene = sceneOf(label);
    if (!p || !scene) throw new Error("no pipeline " + text + " or scene " + label + " in the browser data");
    var r = await renderer(p, scene), device = r.device;
    var view = viewOf(scene, v);
    var pr = v && v.params ? new Float32Array(v.params) : params(scene, view, 1, pixelSize(view.camera, size));
    device.queue.writeBuffer(r.ub, 0, pr);
    var t = target(device, size), row = Math.ceil(size * 4 / 256) * 256;
    var out = device.createBuffer({ size: row * size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
    var enc = device.createCommandEncoder();
    pass(enc, r, t.createView(), null);
    enc.copyTextureToBuffer({ texture: t }, { buffer: out, bytesPerRow: row, rowsPerImage: size }, [size, size]);
    device.queue.submit([enc.finish()]);
    await out.mapAsync(GPUMapMode.READ);
    var padded = new Uint8Array(out.getMappedRange()), rgba = new Uint8Array(size * size * 4);
    for (var y = 0; y < size; y++) rgba.set(padded.subarray(y * row, y * row + size * 4), y * size * 4);
    out.unmap();
    t.destroy();
    return { rgba: rgba, params: Array.from(pr) };
  }

  // A clock: timestamp queries around a block of frames when granted, else the wall clock
  // from submission to completion.
  function clock(device, timestamps) {
    if (!timestamps) return { kind: "wall-clock", block: async function (draw, k) {
      var enc = device.createCommandEncoder();
      for (var i = 0; i < k; i++) draw(enc, null);
      var t0 = performance.now();
      device.queue.submit([enc.finish()]);
      await device.queue.onSubmittedWorkDone();
      return performance.now() - t0;
    } };
    var qs = device.createQuerySet({ type: "timestamp", count: 2 });
    var resolve = device.createBuffer({ size: 16, usage: GPUBufferUsage.QUERY_RESOLVE | GPUBufferUsage.COPY_SRC });
    return { kind: "timestamp-query", block: async function (draw, k) {
      var read = device.createBuffer({ size: 16, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
      var enc = device.createCommandEncoder();
      for (var i = 0; i < k; i++) {
        var ts = null;
        if (i === 0 || i === k - 1) {
          ts = { querySet: qs };
          if (i === 0) ts.beginningOfPassWriteIndex = 0;
          if (i === k - 1) ts.endOfPassWriteIndex = 1;
        }
        draw(enc, ts);
      }
      enc.resolveQuerySet(qs, 0, 2, resolve, 0);
      enc.copyBufferToBuffer(resolve, 0, read, 0, 16);
      device.queue.submit([enc.finish()]);
      await read.mapAsync(GPUMapMode.READ);
      var s = new BigUint64Array(read.getMappedRange());
      var ms = s[1] > s[0] ? Number(s[1] - s[0]) / 1e6 : 0;
      read.unmap();
      read.destroy();
      return ms;
    } };
  }

  // Frame times of pipeline `text` on `label` at `size²`, measured view: blocks of k frames
  // with k grown until a block lasts at least min_block_ms (those blocks dropped as
  // warm-up, as the runtime's Clock::calibrate does), then `blocks` timed blocks.
  async function time(text, label, size, blocks) {
    var g = await gpu(), device = g.device;
    var p = pipelineOf(text), scene = sceneOf(label);
    var r = await renderer(p, scene);
    var view = viewOf(scene);
    device.queue.writeBuffer(r.ub, 0, params(scene, view, 1, pixelSize(view.camera, size)));
    var t = target(device, size), tv = t.createView();
    var ck = clock(device, g.timestamps);
    var draw = function (enc, ts) { pass(enc, r, tv, ts); };
    var k = 1;
    for (;;) {
      var ms = await ck.block(draw, k);
      if (ms >= M.min_block_ms || k >= M.max_frames_per_block) break;
      var grow = ms > 0 ? Math.ceil(1.25 * M.min_block_ms / ms * k) : 16 * k;
      k = Math.min(Math.max(grow, 2 * k), M.max_frames_per_block);
    }
    var frame_ms = [];
    for (var b = 0; b < blocks; b++) frame_ms.push((await ck.block(draw, k)) / k);
    t.destroy();
    return { frame_ms: frame_ms, frames_per_block: k, timer: ck.kind };
  }

  // The probe entry of `text` on `label` over `rayBytes` (the ABI's records): the raw hits.
  async function probe(text, label, rayBytes, count, v) {
    var device = (await gpu()).device;
    var p = pipelineOf(text), scene = sceneOf(label);
    var module = await shaderModule(p), res = await withMaps(p, scene);
    var pipe = await device.createComputePipelineAsync({ layout: "auto", compute: { module: module, entryPoint: "probe" } });
    var n = Math.max(count, 1);
    var rb = device.createBuffer({ size: n * M.ray_bytes, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(rb, 0, rayBytes);
    var hb = device.createBuffer({ size: n * M.hit_bytes, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
    var out = device.createBuffer({ size: n * M.hit_bytes, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
    var ub = device.createBuffer({ size: M.params.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(ub, 0, params(scene, viewOf(scene, v), 1, 0));
    var bg = bindGroup(device, pipe.getBindGroupLayout(0), p.probe_bindings, res, { params: ub, rays: rb, hits: hb });
    var enc = device.createCommandEncoder();
    var cp = enc.beginComputePass();
    cp.setPipeline(pipe);
    cp.setBindGroup(0, bg);
    cp.dispatchWorkgroups(Math.ceil(count / M.probe_workgroup));
    cp.end();
    enc.copyBufferToBuffer(hb, 0, out, 0, n * M.hit_bytes);
    device.queue.submit([enc.finish()]);
    await out.mapAsync(GPUMapMode.READ);
    var hits = new Uint8Array(out.getMappedRange().slice(0, count * M.hit_bytes));
    out.unmap();
    [rb, hb, out, ub].forEach(function (b) { b.destroy(); });
    return hits;
  }

  function b64(bytes) {
    var s = "";
    for (var i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(s);
  }

  // Every pipeline of the sweep on this GPU: frame times and the probe's raw hits on the
  // shipped rays, as one results file for `relief report DIR --add FILE`.
  async function measureAll(progress, blocks) {
    var g = await gpu();
    var seen = {}, cells = [];
    M.rows.forEach(function (r) {
      var k = r.pipeline + "|" + r.scene + "|" + r.size;
      if (!seen[k] && pipelineOf(r.pipeline)) { seen[k] = true; cells.push(r); }
    });
    var rows = [], timer = null;
    for (var i = 0; i < cells.length; i++) {
      var c = cells[i], scene = sceneOf(c.scene);
      if (progress) progress(i, cells.length, c);
      var tm = await time(c.pipeline, c.scene, c.size, blocks || 10);
      timer = tm.timer;
      var pd = probeRays(scene, c.size), want = scene.probe[String(c.size)];
      if (pd.meta.rays !== want.rays || pd.meta.stride !== want.stride)
        throw new Error(c.scene + " at " + c.size + "²: the page computed " + pd.meta.rays + " probe rays (stride " + pd.meta.stride + "), the manifest says " + want.rays + " (stride " + want.stride + ")");
      var n = pd.meta.rays;
      var hits = await probe(c.pipeline, c.scene, pd.bytes.subarray(0, n * M.ray_bytes), n);
      rows.push({ pipeline: c.pipeline, scene: c.scene, size: c.size, frame_ms: tm.frame_ms, frames_per_block: tm.frames_per_block,
        probe_rays: n, probe_stride: pd.meta.stride, hits_b64: b64(hits) });
    }
    return { format: "relief-browser-results", version: 1, relief_version: M.relief_version, adapter: g.adapter, timer: timer,
      user_agent: navigator.userAgent, rows: rows };
  }

  window.reliefLive = { gpu: gpu, frame: frame, time: time, probe: probe, measureAll: measureAll, manifest: M, load: load, loadMap: loadMap, probeRays: probeRays, distanceField: distanceField, cellPatch: cellPatch };

  // ---------------------------------------------------------------------------------------
  // The section: two pipelines side by side.
  if (!root || !M) return;
  var el = function (id) { return document.getElementById(id); };
  var selA = el("live-a"), selB = el("live-b"), selScene = el("live-scene");
  var angle = el("live-angle"), depth = el("live-depth"), tiling = el("live-tiling"), mode = el("live-mode");
  var SIZE = 256;
  M.pipelines.forEach(function (p) {
    [selA, selB].forEach(function (s) { var o = document.createElement("option"); o.textContent = p.pipeline; s.appendChild(o); });
  });
  M.scenes.forEach(function (s) { var o = document.createElement("option"); o.textContent = s.label; selScene.appendChild(o); });
  var measured = M.pipelines.filter(function (p) { return p.pipeline !== M.exact; });
  if (measured.length) selA.value = measured[0].pipeline;
  selB.value = measured.length > 1 ? measured[1].pipeline : M.exact;
  var state = { azimuth: undefined };
  function resetView() {
    var s = sceneOf(selScene.value);
    if (!s) return;
    angle.value = s.camera.angle_deg;
    depth.value = s.depth_scale;
    tiling.value = s.tiling;
    state.azimuth = s.camera.azimuth_deg;
  }
  resetView();

  function currentView() {
    return { angle: parseFloat(angle.value), azimuth: state.azimuth, depth: parseFloat(depth.value), tiling: parseFloat(tiling.value) };
  }

  // |t − t_exact| on a log scale: blue at 1e-6 or less, green at 3e-4, red at 1e-1 or more;
  // magenta where the hit is not finite.
  function errorColour(e) {
    if (!isFinite(e)) return [255, 0, 255];
    var x = Math.min(Math.max((Math.log10(Math.max(e, 1e-7)) + 6) / 5, 0), 1);
    return [Math.round(255 * Math.min(1, 2 * x)), Math.round(255 * (1 - Math.abs(2 * x - 1))), Math.round(255 * Math.max(0, 1 - 2 * x))];
  }

  var token = 0;
  async function draw() {
    var my = ++token;
    try {
      var scene = sceneOf(selScene.value), v = currentView();
      el("live-angle-value").textContent = v.angle.toFixed(0) + "°";
      el("live-depth-value").textContent = v.depth.toFixed(3);
      el("live-tiling-value").textContent = v.tiling.toFixed(0);
      var error = mode.checked, r = null, exact = null;
      if (error) {
        r = rays(scene, viewOf(scene, v), SIZE);
        exact = new DataView((await probe(M.exact, scene.label, r.bytes, r.count, v)).buffer);
      }
      for (var side of ["a", "b"]) {
        var text = (side === "a" ? selA : selB).value;
        var canvas = el("live-canvas-" + side), c2 = el("live-error-" + side);
        canvas.hidden = error;
        c2.hidden = !error;
        if (!error) {
          var f = await frame(text, scene.label, SIZE, v);
          if (my !== token) return;
          var ctx = canvas.getContext("2d"), img = ctx.createImageData(SIZE, SIZE);
          img.data.set(f.rgba);
          ctx.putImageData(img, 0, 0);
        } else {
          var hits = new DataView((await probe(text, scene.label, r.bytes, r.count, v)).buffer);
          if (my !== token) return;
          var ctx2 = c2.getContext("2d"), im = ctx2.createImageData(SIZE, SIZE);
          var rv = new DataView(r.bytes.buffer), sum = 0, n = 0;
          for (var i = 0; i < r.count; i++) {
            var e = Math.abs(hits.getFloat32(i * M.hit_bytes, true) - exact.getFloat32(i * M.hit_bytes, true));
            var px = rv.getUint32(i * M.ray_bytes + 20, true), py = rv.getUint32(i * M.ray_bytes + 24, true);
            var col = errorColour(e), o = (py * SIZE + px) * 4;
            im.data[o] = col[0]; im.data[o + 1] = col[1]; im.data[o + 2] = col[2]; im.data[o + 3] = 255;
            if (isFinite(e)) { sum += e * e; n++; }
          }
          ctx2.putImageData(im, 0, 0);
          el("live-note-" + side).textContent = "RMS |t − t_exact| " + (n ? Math.sqrt(sum / n).toExponential(2) : "—") + " over " + r.count + " rays";
        }
        if (!error) el("live-note-" + side).textContent = "";
      }
      say("WebGPU on " + G.adapter + (G.timestamps ? " (timestamp queries granted)" : " (no timestamp queries: wall clock)") + ". Drag a picture to orbit.");
    } catch (e) {
      say("Live view failed: " + e.message);
    }
  }

  // Orbit by dragging either picture.
  ["a", "b"].forEach(function (side) {
    [el("live-canvas-" + side), el("live-error-" + side)].forEach(function (c) {
      var last = null;
      c.addEventListener("pointerdown", function (e) { last = [e.clientX, e.clientY]; c.setPointerCapture(e.pointerId); });
      c.addEventListener("pointerup", function () { last = null; });
      c.addEventListener("pointermove", function (e) {
        if (!last) return;
        state.azimuth -= (e.clientX - last[0]) * 0.5;
        angle.value = Math.min(85, Math.max(0, parseFloat(angle.value) + (e.clientY - last[1]) * 0.3));
        last = [e.clientX, e.clientY];
        draw();
      });
    });
  });
  [selA, selB, angle, depth, tiling, mode].forEach(function (x) { x.addEventListener("input", draw); });
  selScene.addEventListener("input", function () { resetView(); draw(); });
  el("live-reset").addEventListener("click", function () { resetView(); draw(); });

  el("live-measure").addEventListener("click", async function () {
    var btn = this, st = el("live-measure-status");
    btn.disabled = true;
    try {
      var res = await measureAll(function (i, n, c) { st.textContent = "measuring " + (i + 1) + " of " + n + ": " + c.pipeline + " on " + c.scene; });
      var blob = new Blob([JSON.stringify(res)], { type: "application/json" });
      var a = el("live-download");
      a.href = URL.createObjectURL(blob);
      a.hidden = false;
      st.textContent = res.rows.length + " pipelines measured on " + res.adapter + " (" + res.timer + "). Add them with: relief report DIR --add relief-browser-results.json";
    } catch (e) {
      st.textContent = "Measurement failed: " + e.message;
    }
    btn.disabled = false;
  });

  gpu().then(function () { root.hidden = false; draw(); }, function (e) {
    say("No live view: " + e.message + ". The rest of the report does not need WebGPU.");
  });
})();
