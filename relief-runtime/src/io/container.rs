//! GPU texture containers engines load: KTX2 (Khronos; three.js's `KTX2Loader`, Babylon.js,
//! Bevy, Godot) and DDS with the DX10 header (Unity, Unreal, D3D tools), holding a texture
//! exactly as it is uploaded: its texel format, every mip level, 2D or 3D.
//!
//! Both are written here by hand, byte by byte after the specifications (KTX 2.0, Khronos
//! 2020, with its Data Format Descriptor, Khronos Data Format 1.3; DDS, Microsoft's
//! `DDS_HEADER` + `DDS_HEADER_DXT10`): the `ktx2` crate only reads, and writing both the
//! same way keeps the tests' readers (the `ktx2` and `ddsfile` crates) independent of the
//! writer. No supercompression, no block compression: the maps are data, read texel by
//! texel or filtered as floats.
//!
//! Row order: the first row stored is the texture's row 0, texture coordinate v = 0
//! (relief's texture space). KTX2 says so in its `KTXorientation` key (`rd`, `rdi` for 3D:
//! x right, y down from the first row, as uploaded); an engine that flips images on load
//! must not flip these.
//!
//! ```no_run
//! use relief_runtime::io::container::{self, Texture};
//! // A 2×2 R32Float texture with its 1×1 mip level.
//! let l0: Vec<u8> = [0.0f32, 0.25, 0.5, 1.0].iter().flat_map(|x| x.to_le_bytes()).collect();
//! let l1 = 1.0f32.to_le_bytes().to_vec();
//! let t = Texture { width: 2, height: 2, depth: 1, format: wgpu::TextureFormat::R32Float, levels: &[l0, l1] };
//! std::fs::write("max_mip.ktx2", container::ktx2_bytes(&t).unwrap()).unwrap();
//! std::fs::write("max_mip.dds", container::dds_bytes(&t).unwrap()).unwrap();
//! ```

use wgpu::TextureFormat;

/// A texture as uploaded: level 0's size, its format and the bytes of each mip level
/// (level 0 first, rows tightly packed, slices after one another for 3D).
#[derive(Clone, Copy, Debug)]
pub struct Texture<'a> {
    /// Width of level 0, texels.
    pub width: u32,
    /// Height of level 0, texels.
    pub height: u32,
    /// Slices of level 0: 1 for a 2D texture, more for a 3D one.
    pub depth: u32,
    /// The texel format.
    pub format: TextureFormat,
    /// The bytes of each level, level 0 first.
    pub levels: &'a [Vec<u8>],
}

/// What the containers need to know of a format: the Vulkan format (KTX2), the DXGI format
/// (DDS), bytes per texel, channels, bits per channel, float or unorm, sRGB.
struct FormatInfo {
    vk: u32,
    dxgi: u32,
    texel: u32,
    channels: u32,
    bits: u32,
    float: bool,
    srgb: bool,
}

fn info(f: TextureFormat) -> Option<FormatInfo> {
    let i = |vk, dxgi, channels, bits, float, srgb| FormatInfo {
        vk,
        dxgi,
        texel: channels * bits / 8,
        channels,
        bits,
        float,
        srgb,
    };
    Some(match f {
        TextureFormat::R32Float => i(100, 41, 1, 32, true, false),
        TextureFormat::Rg32Float => i(103, 16, 2, 32, true, false),
        TextureFormat::Rgba32Float => i(109, 2, 4, 32, true, false),
        TextureFormat::R16Float => i(76, 54, 1, 16, true, false),
        TextureFormat::Rg16Float => i(83, 34, 2, 16, true, false),
        TextureFormat::Rgba16Float => i(97, 10, 4, 16, true, false),
        TextureFormat::Rgba8Unorm => i(37, 28, 4, 8, false, false),
        TextureFormat::Rgba8UnormSrgb => i(43, 29, 4, 8, false, true),
        _ => return None,
    })
}

/// Checks the texture's levels against its size and format; the format's facts.
fn check(t: &Texture, container: &str) -> Result<FormatInfo, String> {
    let fi = info(t.format).ok_or_else(|| format!("{:?} cannot be written as {container}", t.format))?;
    if t.width == 0 || t.height == 0 || t.depth == 0 || t.levels.is_empty() {
        return Err(format!("an empty texture cannot be written as {container}"));
    }
    for (i, l) in t.levels.iter().enumerate() {
        let want = level_size(t, i as u32) as usize * fi.texel as usize;
        if l.len() != want {
            return Err(format!("level {i} holds {} bytes, its size and format need {want}", l.len()));
        }
    }
    Ok(fi)
}

/// Texels of level `i`.
fn level_size(t: &Texture, i: u32) -> u64 {
    let s = |n: u32| u64::from((n >> i.min(31)).max(1));
    s(t.width) * s(t.height) * s(t.depth)
}

/// The texture as a KTX 2.0 file: the Vulkan format of [`Texture::format`], every level,
/// a 3D texture where `depth > 1`, the Basic Data Format Descriptor, and the keys
/// `KTXorientation` and `KTXwriter`.
pub fn ktx2_bytes(t: &Texture) -> Result<Vec<u8>, String> {
    let fi = check(t, ".ktx2")?;
    let n = t.levels.len() as u32;
    // Data Format Descriptor: total size, then one basic block with a sample per channel.
    let mut dfd = Vec::new();
    let block_size = 24 + 16 * fi.channels;
    let word = |v: &mut Vec<u8>, x: u32| v.extend(x.to_le_bytes());
    word(&mut dfd, 4 + block_size);
    word(&mut dfd, 0); // vendor 0 (Khronos), descriptor type 0 (basic)
    word(&mut dfd, 2 | (block_size << 16)); // version 2
    let transfer = if fi.srgb { 2 } else { 1 };
    word(&mut dfd, 1 | (1 << 8) | (transfer << 16)); // model RGBSDA, primaries BT.709, flags 0
    word(&mut dfd, 0); // texel block 1×1×1×1
    word(&mut dfd, fi.texel); // bytes in plane 0
    word(&mut dfd, 0);
    for c in 0..fi.channels {
        let id = if c == 3 { 15 } else { c }; // R, G, B, A
        let qualifiers = if fi.float {
            0x80 | 0x40 // float, signed
        } else if fi.srgb && c == 3 {
            0x10 // alpha is linear in an sRGB format
        } else {
            0
        };
        word(&mut dfd, (c * fi.bits) | ((fi.bits - 1) << 16) | ((id | qualifiers) << 24));
        word(&mut dfd, 0); // sample position
        if fi.float {
            word(&mut dfd, (-1.0f32).to_bits());
            word(&mut dfd, 1.0f32.to_bits());
        } else {
            word(&mut dfd, 0);
            word(&mut dfd, (1u32 << fi.bits) - 1);
        }
    }
    // Key/value data, each entry padded to 4 bytes.
    let mut kvd = Vec::new();
    let orientation = if t.depth > 1 { "rdi" } else { "rd" };
    for (k, v) in [("KTXorientation", orientation), ("KTXwriter", concat!("relief ", env!("CARGO_PKG_VERSION")))] {
        let entry = [k.as_bytes(), &[0], v.as_bytes(), &[0]].concat();
        word(&mut kvd, entry.len() as u32);
        kvd.extend(&entry);
        while kvd.len() % 4 != 0 {
            kvd.push(0);
        }
    }
    let header_len = 80 + 24 * n as usize;
    let dfd_off = header_len;
    let kvd_off = dfd_off + dfd.len();
    let mut data_off = kvd_off + kvd.len();
    // Levels are stored smallest first, each at a multiple of lcm(texel size, 4).
    let align = match fi.texel {
        t if t % 4 == 0 => t as usize,
        t if t % 2 == 0 => 4 * t as usize / 2,
        t => 4 * t as usize,
    };
    let mut offsets = vec![0usize; n as usize];
    for i in (0..n as usize).rev() {
        data_off = data_off.div_ceil(align) * align;
        offsets[i] = data_off;
        data_off += t.levels[i].len();
    }
    let mut out = Vec::with_capacity(data_off);
    out.extend([0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n']);
    for x in [fi.vk, fi.texel / fi.channels, t.width, t.height, if t.depth > 1 { t.depth } else { 0 }, 0, 1, n, 0] {
        word(&mut out, x);
    }
    for x in [dfd_off as u32, dfd.len() as u32, kvd_off as u32, kvd.len() as u32] {
        word(&mut out, x);
    }
    out.extend(0u64.to_le_bytes()); // no supercompression global data
    out.extend(0u64.to_le_bytes());
    for (i, l) in t.levels.iter().enumerate() {
        for x in [offsets[i] as u64, l.len() as u64, l.len() as u64] {
            out.extend(x.to_le_bytes());
        }
    }
    out.extend(&dfd);
    out.extend(&kvd);
    for i in (0..n as usize).rev() {
        out.resize(offsets[i], 0);
        out.extend(&t.levels[i]);
    }
    Ok(out)
}

/// The texture as a DDS file with the DX10 header: the DXGI format of [`Texture::format`],
/// every level (`dwMipMapCount`), a 3D texture (`DDSCAPS2_VOLUME`) where `depth > 1`.
pub fn dds_bytes(t: &Texture) -> Result<Vec<u8>, String> {
    let fi = check(t, ".dds")?;
    let n = t.levels.len() as u32;
    let volume = t.depth > 1;
    let mut out = Vec::new();
    let word = |v: &mut Vec<u8>, x: u32| v.extend(x.to_le_bytes());
    out.extend(b"DDS ");
    word(&mut out, 124);
    // CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT | MIPMAPCOUNT (| DEPTH)
    word(&mut out, 0x1 | 0x2 | 0x4 | 0x8 | 0x1000 | 0x20000 | if volume { 0x80_0000 } else { 0 });
    word(&mut out, t.height);
    word(&mut out, t.width);
    word(&mut out, t.width * fi.texel); // row pitch of level 0
    word(&mut out, if volume { t.depth } else { 0 });
    word(&mut out, n);
    for _ in 0..11 {
        word(&mut out, 0);
    }
    // DDS_PIXELFORMAT: FOURCC "DX10".
    word(&mut out, 32);
    word(&mut out, 0x4);
    out.extend(b"DX10");
    for _ in 0..5 {
        word(&mut out, 0);
    }
    // TEXTURE (| COMPLEX | MIPMAP); VOLUME.
    word(&mut out, 0x1000 | if n > 1 || volume { 0x8 } else { 0 } | if n > 1 { 0x40_0000 } else { 0 });
    word(&mut out, if volume { 0x20_0000 } else { 0 });
    for _ in 0..3 {
        word(&mut out, 0);
    }
    // DDS_HEADER_DXT10: format, dimension (3: 2D, 4: 3D), misc, array size, misc 2.
    for x in [fi.dxgi, if volume { 4 } else { 3 }, 0, 1, 0] {
        word(&mut out, x);
    }
    for l in t.levels {
        out.extend(l);
    }
    Ok(out)
}
