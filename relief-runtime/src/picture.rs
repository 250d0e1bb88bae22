//! Pictures drawn from measurements (a leaf): the error map written as `error.png`.

/// The error map's colour scale, the same in every picture so that one colour means one
/// error on the whole report page: black at or below `lo` (1e-6, the report's "exact"
/// level), yellow at `hi` (1, a whole ray length) and beyond, logarithmic between (a
/// decade is a sixth of the bar).
pub(crate) const ERROR_SCALE: (f64, f64) = (1e-6, 1.0);

/// Steps of the heat scale: an error's place on [`ERROR_SCALE`] is rounded to a multiple of
/// 1/240 (40 steps a decade, each a factor of 1.06 in error), so that a map has at most 244
/// colours (241 heat, magenta, the background, the legend's text) and is stored as an indexed
/// PNG ([`crate::io::png::write_rgba8`]) at about half the bytes of RGB.
pub(crate) const HEAT_LEVELS: u32 = 240;

/// Per-pixel |t − t_ref| as a heat map on [`ERROR_SCALE`] (black = exact, red = 1e-3,
/// yellow = 1 or more, magenta = no finite hit), with a legend bar and its range below the
/// image.
pub(crate) fn error_map(size: u32, errors: &[(u32, u32, f64)]) -> (u32, u32, Vec<u8>) {
    let legend_h = 24u32;
    let (w, h) = (size.max(96), size + legend_h);
    let mut img = vec![0u8; (w * h * 4) as usize];
    for px in img.chunks_mut(4) {
        px.copy_from_slice(&[40, 40, 48, 255]);
    }
    let (lo, max) = ERROR_SCALE;
    let scale = |e: f64| step(((e.max(lo) / lo).ln() / (max / lo).ln()).clamp(0.0, 1.0));
    let mut put = |x: u32, y: u32, c: [u8; 3]| {
        if x < w && y < h {
            let i = ((y * w + x) * 4) as usize;
            img[i..i + 3].copy_from_slice(&c);
        }
    };
    for &(x, y, e) in errors {
        let c = if e.is_finite() { heat(scale(e)) } else { [255, 0, 255] };
        put(x, y, c);
    }
    // Legend: the colour bar from `lo` (left) to `max` (right), labelled with both.
    for x in 0..w {
        for y in size + 2..size + 8 {
            put(x, y, heat(step(x as f64 / (w - 1).max(1) as f64)));
        }
    }
    draw_text(&mut put, 2, size + 11, &format!("{lo:.0e}"));
    let label = format!("{max:.0e}");
    draw_text(&mut put, w.saturating_sub(4 * label.len() as u32 + 2), size + 11, &label);
    (w, h, img)
}

/// `f` in [0, 1] rounded to the nearest of the scale's [`HEAT_LEVELS`] steps.
fn step(f: f64) -> f64 {
    (f * f64::from(HEAT_LEVELS)).round() / f64::from(HEAT_LEVELS)
}

fn heat(f: f64) -> [u8; 3] {
    // black → red → yellow
    let r = (f * 2.0).min(1.0);
    let g = (f * 2.0 - 1.0).clamp(0.0, 1.0);
    [(r * 255.0) as u8, (g * 255.0) as u8, (g * 80.0) as u8]
}

/// 3×5 pixel glyphs for the legend's numbers.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        'e' => [0, 7, 7, 4, 7],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        _ => [0; 5],
    }
}

fn draw_text(put: &mut impl FnMut(u32, u32, [u8; 3]), x0: u32, y0: u32, s: &str) {
    for (i, c) in s.chars().enumerate() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..3 {
                if bits & (4 >> col) != 0 {
                    put(x0 + 4 * i as u32 + col, y0 + row as u32, [230, 230, 230]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The colour of pixel (x, 0) of an error map.
    fn colour(map: &(u32, u32, Vec<u8>), x: u32) -> [u8; 3] {
        let i = (x * 4) as usize;
        [map.2[i], map.2[i + 1], map.2[i + 2]]
    }

    #[test]
    fn one_error_has_one_colour_in_every_map() {
        // Three decades above 1e-6 is half the bar: pure red; 1e-6 and below black; 1 and
        // above yellow; no finite hit magenta.
        let errors = [
            (0, 0, 1e-9),
            (1, 0, 1e-6),
            (2, 0, 1e-3),
            (3, 0, 1.0),
            (4, 0, 7.0),
            (5, 0, f64::INFINITY),
            (6, 0, f64::NAN),
        ];
        let map = error_map(96, &errors);
        assert_eq!(colour(&map, 0), [0, 0, 0]);
        assert_eq!(colour(&map, 1), [0, 0, 0]);
        let red = colour(&map, 2);
        assert!(red[0] >= 254 && red[1] <= 1, "{red:?}");
        assert_eq!(colour(&map, 3), [255, 255, 80]);
        assert_eq!(colour(&map, 4), [255, 255, 80]);
        assert_eq!(colour(&map, 5), [255, 0, 255]);
        assert_eq!(colour(&map, 6), [255, 0, 255]);
        // The same error beside a near-exact neighbour or beside a gross one: the same colour.
        let quiet = error_map(96, &[(0, 0, 1e-4), (1, 0, 1e-7)]);
        let loud = error_map(96, &[(0, 0, 1e-4), (1, 0, 0.5)]);
        assert_eq!(colour(&quiet, 0), colour(&loud, 0));
        assert_eq!(colour(&quiet, 1), [0, 0, 0]);
    }

    /// Errors spread over every decade of the scale, and beyond it, give a map of at most 256
    /// colours (so it is stored indexed), and errors a factor of 1.2 apart (more than a step,
    /// 1.06) still get different colours.
    #[test]
    fn a_map_has_at_most_256_colours_and_its_steps_still_part_errors() {
        let size = 96u32;
        let errors: Vec<(u32, u32, f64)> = (0..size * size)
            .map(|i| (i % size, i / size, 10f64.powf(-8.0 + 9.0 * f64::from(i) / f64::from(size * size))))
            .chain([(0, 0, f64::INFINITY)])
            .collect();
        let map = error_map(size, &errors);
        let colours: std::collections::HashSet<&[u8]> = map.2.chunks_exact(4).collect();
        assert!(colours.len() <= 256 && colours.len() > 200, "{} colours", colours.len());
        let apart = error_map(96, &[(0, 0, 1e-4), (1, 0, 1.2e-4)]);
        assert_ne!(colour(&apart, 0), colour(&apart, 1));
    }
}
