//! Height-map loading: formats, channels, bit depths, the depth flag and bad input.

use relief_runtime::io::npy::npy_bytes;
use relief_runtime::{Channel, HeightMap, HeightMapError, LoadOptions};
use std::path::PathBuf;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("relief-heightmap-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn opts(channel: Option<Channel>, depth: bool) -> LoadOptions {
    LoadOptions { channel, depth }
}

#[test]
fn gray_png_8_and_16_bit() {
    let d = dir();
    let img8 = image::GrayImage::from_fn(5, 3, |x, y| image::Luma([(x * 50 + y) as u8]));
    let p8 = d.join("g8.png");
    img8.save(&p8).unwrap();
    let m = HeightMap::load(&p8, &LoadOptions::default()).unwrap();
    assert_eq!((m.width, m.height), (5, 3));
    assert_eq!(m.data[2 * 5 + 4], (4 * 50 + 2) as f32 / 255.0);

    let img16 = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(4, 4, |x, y| {
        image::Luma([(x * 16000 + y * 7) as u16])
    });
    let p16 = d.join("g16.png");
    img16.save(&p16).unwrap();
    let m = HeightMap::load(&p16, &LoadOptions::default()).unwrap();
    // 16-bit precision survives: 48007 is not a multiple of 257.
    assert_eq!(m.data[3 * 4 + 3], (3 * 16000 + 3 * 7) as f32 / 65535.0);
}

#[test]
fn channel_pick_and_depth_flag() {
    let d = dir();
    let img = image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([10 * x as u8, 200, 30 + y as u8, 255 - x as u8]));
    let p = d.join("rgba.png");
    img.save(&p).unwrap();
    let g = HeightMap::load(&p, &opts(Some(Channel::G), false)).unwrap();
    assert!(g.data.iter().all(|&v| v == 200.0 / 255.0));
    let a = HeightMap::load(&p, &opts(Some(Channel::A), false)).unwrap();
    assert_eq!(a.data[2], 253.0 / 255.0);
    let b = HeightMap::load(&p, &opts(Some(Channel::B), true)).unwrap();
    assert_eq!(b.data[3], 1.0 - 31.0 / 255.0);
    let r = HeightMap::load(&p, &opts(Some(Channel::R), false)).unwrap();
    assert_eq!(r.data[1], 10.0 / 255.0);
    // TGA and BMP through the same path.
    let rgb = image::RgbImage::from_fn(4, 4, |x, _| image::Rgb([x as u8 * 60, 0, 0]));
    for ext in ["tga", "bmp"] {
        let p = d.join(format!("c.{ext}"));
        rgb.save(&p).unwrap();
        let m = HeightMap::load(&p, &opts(Some(Channel::R), false)).unwrap();
        assert_eq!(m.data[3], 180.0 / 255.0, "{ext}");
    }
    // Depth maps: white = deep.
    let white = image::GrayImage::from_pixel(2, 2, image::Luma([255]));
    let pw = d.join("white.png");
    white.save(&pw).unwrap();
    assert!(HeightMap::load(&pw, &opts(None, true)).unwrap().data.iter().all(|&v| v == 0.0));
}

#[test]
fn missing_channel_is_an_error() {
    let d = dir();
    let p = d.join("gray.png");
    image::GrayImage::new(2, 2).save(&p).unwrap();
    let e = HeightMap::load(&p, &opts(Some(Channel::R), false)).unwrap_err();
    assert!(matches!(e, HeightMapError::MissingChannel { channel: Channel::R, .. }), "{e}");
    assert!(e.to_string().contains("gray.png"));
    let p = d.join("rgb.png");
    image::RgbImage::new(2, 2).save(&p).unwrap();
    let e = HeightMap::load(&p, &opts(Some(Channel::A), false)).unwrap_err();
    assert!(matches!(e, HeightMapError::MissingChannel { .. }), "{e}");
}

#[test]
fn bad_files_give_errors_naming_the_file() {
    let d = dir();
    let e = HeightMap::load(d.join("nope.png"), &LoadOptions::default()).unwrap_err();
    assert!(matches!(e, HeightMapError::Missing { .. }) && e.to_string().contains("nope.png"));

    let p = d.join("corrupt.png");
    std::fs::write(&p, b"\x89PNG\r\n\x1a\nthis is not a png at all").unwrap();
    let e = HeightMap::load(&p, &LoadOptions::default()).unwrap_err();
    assert!(matches!(e, HeightMapError::Corrupt { .. }), "{e}");
    assert!(e.to_string().contains("corrupt.png"));

    let p = d.join("empty.bmp");
    std::fs::write(&p, b"").unwrap();
    assert!(HeightMap::load(&p, &LoadOptions::default()).is_err());

    let p = d.join("file.txt");
    std::fs::write(&p, b"1 2 3").unwrap();
    assert!(matches!(HeightMap::load(&p, &LoadOptions::default()).unwrap_err(), HeightMapError::Unsupported { .. }));
}

#[test]
fn raw_float_npy() {
    let d = dir();
    let p = d.join("h.npy");
    let vals: Vec<f32> = (0..12).map(|i| i as f32 / 11.0).collect();
    std::fs::write(&p, npy_bytes(&[3, 4], &vals)).unwrap();
    let m = HeightMap::load(&p, &LoadOptions::default()).unwrap();
    assert_eq!((m.width, m.height), (4, 3));
    assert_eq!(m.data, vals);
    let m = HeightMap::load(&p, &opts(None, true)).unwrap();
    assert_eq!(m.data[11], 0.0);

    // [h, w, c] with a channel.
    let p = d.join("hc.npy");
    let vals: Vec<f32> = (0..2 * 2 * 3).map(|i| i as f32 / 20.0).collect();
    std::fs::write(&p, npy_bytes(&[2, 2, 3], &vals)).unwrap();
    let m = HeightMap::load(&p, &opts(Some(Channel::B), false)).unwrap();
    assert_eq!(m.data, vec![2.0 / 20.0, 5.0 / 20.0, 8.0 / 20.0, 11.0 / 20.0]);
    assert!(matches!(
        HeightMap::load(&p, &opts(Some(Channel::A), false)).unwrap_err(),
        HeightMapError::MissingChannel { .. }
    ));

    // NaN, out of range, zero size, too large (rejected from the header alone), truncated.
    let p = d.join("nan.npy");
    std::fs::write(&p, npy_bytes(&[2, 2], &[0.0, f32::NAN, 0.0, 0.0])).unwrap();
    let e = HeightMap::load(&p, &LoadOptions::default()).unwrap_err();
    assert!(matches!(e, HeightMapError::NotFinite { x: 1, y: 0, .. }), "{e}");
    assert!(e.to_string().contains("nan.npy"));
    let p = d.join("range.npy");
    std::fs::write(&p, npy_bytes(&[1, 2], &[0.5, 1.5])).unwrap();
    assert!(matches!(HeightMap::load(&p, &LoadOptions::default()).unwrap_err(), HeightMapError::OutOfRange { .. }));
    let p = d.join("zero.npy");
    std::fs::write(&p, npy_bytes(&[0, 4], &[])).unwrap();
    assert!(matches!(HeightMap::load(&p, &LoadOptions::default()).unwrap_err(), HeightMapError::ZeroSize { .. }));
    let p = d.join("huge.npy");
    std::fs::write(&p, npy_bytes(&[100000, 100000], &[])).unwrap();
    assert!(matches!(HeightMap::load(&p, &LoadOptions::default()).unwrap_err(), HeightMapError::TooLarge { .. }));
    let p = d.join("short.npy");
    std::fs::write(&p, npy_bytes(&[4, 4], &[0.5; 3])).unwrap();
    assert!(matches!(HeightMap::load(&p, &LoadOptions::default()).unwrap_err(), HeightMapError::Corrupt { .. }));
    let p = d.join("garbage.npy");
    std::fs::write(&p, b"\x93NUMPY\x01\x00\xff\xff{'descr").unwrap();
    assert!(HeightMap::load(&p, &LoadOptions::default()).is_err());
}

#[test]
fn content_hash_is_stable_and_sensitive() {
    let a = HeightMap::from_fn(8, 8, |x, y| (x * y) as f32 / 64.0);
    let mut b = a.clone();
    assert_eq!(a.content_hash(), b.content_hash());
    b.data[9] += 1e-6;
    assert_ne!(a.content_hash(), b.content_hash());
    let c = HeightMap::new(4, 16, a.data.clone());
    assert_ne!(a.content_hash(), c.content_hash());
}

/// An 8-bit pattern uniform over each 8×8 block (JPEG's block size): a baseline JPEG at
/// quality 100 stores such a block in its DC coefficient alone, with a quantisation step of
/// 1, so the decoder gives back every value exactly.
fn block_pattern(w: u32, h: u32) -> image::GrayImage {
    image::GrayImage::from_fn(w, h, |x, y| image::Luma([((x / 8) * 37 + (y / 8) * 91 + 5) as u8 % 251]))
}

#[test]
fn jpeg_8_bit_gray() {
    let d = dir();
    let img = block_pattern(32, 24);
    let p = d.join("blocks.jpg");
    let mut file = std::io::BufWriter::new(std::fs::File::create(&p).unwrap());
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut file, 100).encode_image(&img).unwrap();
    drop(file);
    let m = HeightMap::load(&p, &LoadOptions::default()).unwrap();
    assert_eq!((m.width, m.height), (32, 24));
    for (i, (got, px)) in m.data.iter().zip(img.pixels()).enumerate() {
        assert_eq!(*got, px.0[0] as f32 / 255.0, "texel {i}");
    }
    // `.jpeg` too, and the depth flag.
    let q = d.join("blocks.JPEG");
    std::fs::copy(&p, &q).unwrap();
    let m = HeightMap::load(&q, &opts(None, true)).unwrap();
    assert_eq!(m.data[9 * 32 + 17], 1.0 - img.get_pixel(17, 9).0[0] as f32 / 255.0);
}

#[test]
fn tiff_8_and_16_bit() {
    let d = dir();
    let img8 = image::GrayImage::from_fn(6, 5, |x, y| image::Luma([(x * 40 + y * 3) as u8]));
    let p8 = d.join("g8.tif");
    img8.save(&p8).unwrap();
    let m = HeightMap::load(&p8, &LoadOptions::default()).unwrap();
    assert_eq!((m.width, m.height), (6, 5));
    assert_eq!(m.data[4 * 6 + 5], (5 * 40 + 4 * 3) as f32 / 255.0);

    let img16 = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(5, 4, |x, y| {
        image::Luma([(x * 13001 + y * 11) as u16])
    });
    let p16 = d.join("g16.tiff");
    img16.save(&p16).unwrap();
    let m = HeightMap::load(&p16, &LoadOptions::default()).unwrap();
    // 16-bit precision survives: 52037 is not a multiple of 257.
    assert_eq!(m.data[3 * 5 + 4], (4 * 13001 + 3 * 11) as f32 / 65535.0);

    // 16-bit RGBA: the alpha channel on request.
    let rgba16 = image::ImageBuffer::<image::Rgba<u16>, Vec<u16>>::from_fn(3, 3, |x, y| {
        image::Rgba([1000, 2000, 3000, (x * 20000 + y * 3) as u16])
    });
    let p = d.join("rgba16.tif");
    rgba16.save(&p).unwrap();
    let m = HeightMap::load(&p, &opts(Some(Channel::A), false)).unwrap();
    assert_eq!(m.data[2 * 3 + 1], (20000 + 2 * 3) as f32 / 65535.0);
}

#[test]
fn webp_8_bit_lossless() {
    let d = dir();
    // image's WebP encoder writes lossless WebP (VP8L): every value comes back.
    let img = image::RgbaImage::from_fn(7, 5, |x, y| {
        image::Rgba([(x * 30) as u8, (y * 50) as u8, 77, (x * 9 + y * 40) as u8])
    });
    let p = d.join("rgba.webp");
    img.save(&p).unwrap();
    let m = HeightMap::load(&p, &opts(Some(Channel::A), false)).unwrap();
    assert_eq!((m.width, m.height), (7, 5));
    assert_eq!(m.data[4 * 7 + 6], (6 * 9 + 4 * 40) as f32 / 255.0);
    let m = HeightMap::load(&p, &opts(Some(Channel::G), false)).unwrap();
    assert_eq!(m.data[3 * 7], (3 * 50) as f32 / 255.0);
    // Gray written as RGB: the default (luma) reads the gray value.
    let gray = image::RgbImage::from_fn(4, 4, |x, y| {
        let v = (x * 60 + y) as u8;
        image::Rgb([v, v, v])
    });
    let p = d.join("gray.webp");
    gray.save(&p).unwrap();
    let m = HeightMap::load(&p, &LoadOptions::default()).unwrap();
    let want = (3 * 60 + 2) as f32 / 255.0;
    assert!((m.data[2 * 4 + 3] - want).abs() < 1e-6, "{} vs {want}", m.data[2 * 4 + 3]);
}

#[test]
fn the_unsupported_message_names_the_new_formats() {
    let d = dir();
    let p = d.join("map.gif");
    std::fs::write(&p, b"GIF89a").unwrap();
    let e = HeightMap::load(&p, &LoadOptions::default()).unwrap_err().to_string();
    assert!(
        e.contains("unsupported file type") && e.contains(".jpg") && e.contains(".tiff") && e.contains(".webp"),
        "{e}"
    );
}
