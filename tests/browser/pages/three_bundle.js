// What the three.js pages (threejs.html, threejs_mesh.html) share in drawing a `relief export`
// bundle with three's WebGLRenderer: the renderer as relief's frames need it (no colour
// management, no tone mapping) with its KTX2Loader, a bundle's texture through that loader,
// the clear colour, and one frame drawn into an RGBA8 target and read back.
import * as THREE from '/node_modules/three/build/three.module.js';
import { KTX2Loader } from '/node_modules/three/examples/jsm/loaders/KTX2Loader.js';
import { bytes, clearOf, topRowFirst } from './bundle.js';

/**
 * A WebGLRenderer on a canvas of its own, writing the shader's bytes as they are (linear
 * output colour space, no tone mapping), and a KTX2Loader for it.
 */
export function webglRenderer() {
  const canvas = document.createElement('canvas');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
  renderer.toneMapping = THREE.NoToneMapping;
  return { renderer, loader: ktx2Loader(renderer) };
}

/**
 * A KTX2Loader for `renderer` (WebGL or WebGPU). It needs detectSupport before it loads, even
 * for the uncompressed formats that take no transcoder (the transcoder is fetched only for
 * Basis files).
 */
export const ktx2Loader = (renderer) => new KTX2Loader().detectSupport(renderer);

/**
 * The texture at `url` through `loader` (a KTX2Loader), with `filter` (`nearest` or `linear`)
 * and `address` (`clamp_to_edge` or `repeat`) as relief.json gives them.
 *
 * KTX2Loader makes a file in an uncompressed format (R32F, RG32F, RGBA8, …) a DataTexture
 * without the Basis transcoder: every level of the file is in `mipmaps`, flipY is false (row 0
 * of the file is v = 0, as relief.json's texture_space says), the colour space comes from the
 * file's data format descriptor (sRGB for the albedo). The loader's own filters (nearest,
 * mipmapped where the file has levels) are replaced by relief.json's. The file is fetched here
 * and handed to KTX2Loader.parse: loader.load's streamed fetch (three's FileLoader) gives the
 * same texture, but Chromium reports each such request as aborted (net::ERR_ABORTED), which
 * the test's driver counts as a failure.
 */
export async function ktx2Texture(loader, url, filter, address) {
  const buf = await bytes(url);
  const t = await new Promise((resolve, reject) => loader.parse(buf, resolve, reject));
  if (!t.isDataTexture) throw new Error(`${url}: KTX2Loader made no data texture`);
  const f = filter === 'nearest' ? THREE.NearestFilter : THREE.LinearFilter;
  t.magFilter = f;
  t.minFilter = f;
  t.wrapS = t.wrapT = address === 'clamp_to_edge' ? THREE.ClampToEdgeWrapping : THREE.RepeatWrapping;
  t.needsUpdate = true;
  return t;
}

/** The clear colour as relief writes it (relief.json's, sRGB-encoded), set as raw bytes. */
export function clearTo(renderer, json) {
  const managed = THREE.ColorManagement.enabled;
  THREE.ColorManagement.enabled = false;
  renderer.setClearColor(new THREE.Color(...clearOf(json)), 1);
  THREE.ColorManagement.enabled = managed;
}

/**
 * One `size`² frame of `scene` through `camera` with the WebGL renderer, into an RGBA8 target
 * (with a depth buffer when `depthBuffer`) cleared to relief.json's clear colour: its bytes,
 * top row first as relief's frames. A WebGL error after the frame (a shader that failed to
 * compile is a console error too, which fails the page) is an error naming `json.pipeline`.
 */
export function drawAndRead(renderer, scene, camera, size, json, depthBuffer) {
  const target = new THREE.WebGLRenderTarget(size, size, {
    type: THREE.UnsignedByteType, format: THREE.RGBAFormat, depthBuffer,
    minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
  });
  target.texture.colorSpace = THREE.NoColorSpace;
  renderer.setRenderTarget(target);
  clearTo(renderer, json);
  renderer.clear();
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  const px = new Uint8Array(size * size * 4);
  renderer.readRenderTargetPixels(target, 0, 0, size, size, px);
  const err = gl.getError();
  if (err !== gl.NO_ERROR) throw new Error(`${json.pipeline}: WebGL error ${err}`);
  return topRowFirst(px, size);
}
