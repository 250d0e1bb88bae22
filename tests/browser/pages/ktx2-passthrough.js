// A stand-in for Babylon.js's KTX2 decoder module (babylon.ktx2Decoder.js), for
// babylon.html's probe of Babylon's own KTX2 loader (tests/babylon.rs). Babylon's decoder is
// served only from Babylon's CDN (no npm package holds it), which no test here can reach; the
// page points `BABYLON.KhronosTextureContainer2.URLConfig.jsDecoderModule` at this file, as
// a user points it at a local copy of Babylon's, and Babylon's worker loads it with
// importScripts.
//
// It hands every level of an uncompressed KTX 2.0 file (no supercompression) through as it
// is, named by the WebGL2 sized format of its Vulkan format. For RGBA8 that is what Babylon's
// own decoder does (a straight copy, engine format RGBA8, gamma from the data format
// descriptor); for the float formats it is the most any decoder could do. What Babylon then
// makes of each file is Babylon's code, which the probe checks.
/* global self */
(function () {
  // Vulkan format → [WebGL2 sized format, in gamma space].
  const FORMATS = {
    37: [0x8058, false], // R8G8B8A8_UNORM → RGBA8
    43: [0x8058, true], // R8G8B8A8_SRGB → RGBA8, gamma
    76: [0x822d, false], // R16_SFLOAT → R16F
    83: [0x822f, false], // R16G16_SFLOAT → RG16F
    97: [0x881a, false], // R16G16B16A16_SFLOAT → RGBA16F
    100: [0x822e, false], // R32_SFLOAT → R32F
    103: [0x8230, false], // R32G32_SFLOAT → RG32F
    109: [0x8814, false], // R32G32B32A32_SFLOAT → RGBA32F
  };

  class KTX2Decoder {
    async decode(data) {
      const d = new DataView(data.buffer, data.byteOffset, data.byteLength);
      const u32 = (o) => d.getUint32(o, true);
      const u64 = (o) => Number(d.getBigUint64(o, true));
      const vk = u32(12);
      const f = FORMATS[vk];
      if (!f) throw new Error(`the stand-in decoder knows no Vulkan format ${vk}`);
      if (u32(44) !== 0) throw new Error('the stand-in decoder reads no supercompressed file');
      const width = u32(20);
      const height = Math.max(1, u32(24));
      const mipmaps = [];
      for (let k = 0; k < Math.max(1, u32(40)); k++) {
        const at = 80 + 24 * k;
        const start = data.byteOffset + u64(at);
        // Each level its own buffer: the worker transfers them one by one.
        const level = new Uint8Array(data.buffer.slice(start, start + u64(at + 8)));
        mipmaps.push({ data: level, width: Math.max(1, width >> k), height: Math.max(1, height >> k) });
      }
      return { width, height, transcodedFormat: f[0], mipmaps, isInGammaSpace: f[1], hasAlpha: true, transcoderName: 'relief stand-in (pass-through)' };
    }
  }

  self.KTX2DECODER = { KTX2Decoder, Transcoder: {}, MSCTranscoder: {}, WASMMemoryManager: {} };
})();
