//! Chart labels that never overlap: each label is a box of known size (monospace text), placed
//! greedily at the first free spot around its point, trying the eight neighbouring positions
//! at growing distances; a label moved away from its point gets a leader line. A label for
//! which no free spot exists inside the bounds is not placed (the caller says so), never
//! drawn on top of another.

/// An axis-aligned box: top-left corner and size, in SVG pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rect {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl Rect {
    /// A box of size `w × h` centred on (`cx`, `cy`).
    pub(crate) fn around(cx: f64, cy: f64, w: f64, h: f64) -> Rect {
        Rect { x: cx - w / 2.0, y: cy - h / 2.0, w, h }
    }

    /// Whether the two boxes share any area (touching edges do not count).
    pub(crate) fn intersects(&self, o: &Rect) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    /// Whether `self` lies wholly inside `o`.
    #[cfg(test)]
    pub(crate) fn inside(&self, o: &Rect) -> bool {
        self.x >= o.x && self.y >= o.y && self.x + self.w <= o.x + o.w && self.y + self.h <= o.y + o.h
    }

    /// The point of the box nearest to (`px`, `py`), where a leader line ends.
    pub(crate) fn nearest(&self, px: f64, py: f64) -> (f64, f64) {
        (px.clamp(self.x, self.x + self.w), py.clamp(self.y, self.y + self.h))
    }
}

/// Font size of chart labels, in pixels; labels are drawn in a monospace font.
pub(crate) const FONT: f64 = 10.0;
/// Advance of one character at [`FONT`]: 0.64 em, above the 0.60 em of common monospace
/// fonts (DejaVu Sans Mono, Liberation Mono, Courier), so the box holds the drawn text.
pub(crate) const CHAR_W: f64 = 0.64 * FONT;
/// Height of a label box: the font size plus room for descenders.
pub(crate) const LINE_H: f64 = 1.25 * FONT;
/// Clear space kept around every label box.
const PAD: f64 = 1.5;

/// The box a label of `text` needs.
pub(crate) fn text_size(text: &str) -> (f64, f64) {
    (text.chars().count() as f64 * CHAR_W + 2.0 * PAD, LINE_H + 2.0 * PAD)
}

/// One label to place: the point it belongs to and its box size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Want {
    pub px: f64,
    pub py: f64,
    pub w: f64,
    pub h: f64,
}

/// Where a label went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placed {
    /// Its box (padding included).
    pub rect: Rect,
    /// Whether it sits away from its point (then a leader line joins them).
    pub leader: bool,
}

/// Places `wants` in order (earlier ones get the closer spots) inside `bounds`, clear of
/// each other and of `obstacles` (markers, say). `None` for a label with no free spot.
///
/// Candidates lie on rings around the point, 6 pixels apart, each ring sampled more finely
/// than the last (8, 16, … up to 64 spots), starting at the upper right; a spot that pokes
/// out of the bounds is pushed back inside. A label whose box ends up more than 12 pixels
/// from its point gets a leader line.
pub(crate) fn place(wants: &[Want], obstacles: &[Rect], bounds: Rect) -> Vec<Option<Placed>> {
    let mut taken: Vec<Rect> = Vec::new();
    let mut out = Vec::with_capacity(wants.len());
    let ring = 6.0;
    let rings = ((bounds.w.max(bounds.h)) / ring).ceil() as usize + 1;
    for want in wants {
        let (w, h) = (want.w, want.h);
        let mut found = None;
        if w <= bounds.w && h <= bounds.h {
            'search: for k in 0..rings {
                let d = 4.0 + k as f64 * ring;
                let n = (8 * (k + 1)).min(64);
                for j in 0..n {
                    let a = -std::f64::consts::FRAC_PI_4 + std::f64::consts::TAU * j as f64 / n as f64;
                    let (cx, cy) = (want.px + a.cos() * (d + w / 2.0), want.py + a.sin() * (d + h / 2.0));
                    let x = (cx - w / 2.0).clamp(bounds.x, bounds.x + bounds.w - w);
                    let y = (cy - h / 2.0).clamp(bounds.y, bounds.y + bounds.h - h);
                    let r = Rect { x, y, w, h };
                    if !taken.iter().chain(obstacles).any(|o| o.intersects(&r)) {
                        let (nx, ny) = r.nearest(want.px, want.py);
                        found = Some(Placed { rect: r, leader: (nx - want.px).hypot(ny - want.py) > 12.0 });
                        break 'search;
                    }
                }
            }
        }
        if let Some(p) = found {
            taken.push(p.rect);
        }
        out.push(found);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(s: &mut u64) -> f64 {
        *s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    fn check(wants: &[Want], obstacles: &[Rect], bounds: Rect) -> usize {
        let placed = place(wants, obstacles, bounds);
        assert_eq!(placed.len(), wants.len());
        let boxes: Vec<Rect> = placed.iter().flatten().map(|p| p.rect).collect();
        for (i, a) in boxes.iter().enumerate() {
            assert!(a.inside(&bounds), "{a:?} outside {bounds:?}");
            for b in &boxes[i + 1..] {
                assert!(!a.intersects(b), "{a:?} overlaps {b:?}");
            }
            for o in obstacles {
                assert!(!a.intersects(o), "{a:?} covers obstacle {o:?}");
            }
        }
        boxes.len()
    }

    #[test]
    fn labels_of_points_on_top_of_each_other_never_overlap() {
        let bounds = Rect { x: 80.0, y: 50.0, w: 560.0, h: 390.0 };
        // 40 labels on one point in the top-left corner (the Pareto chart's worst case: many
        // fast, inaccurate rows at the same place).
        let (w, h) = text_size("40");
        let wants: Vec<Want> = (0..40).map(|_| Want { px: 82.0, py: 52.0, w, h }).collect();
        assert_eq!(check(&wants, &[], bounds), 40, "there is room for all of them");
        // Random clusters with long labels and markers as obstacles.
        let mut s = 7u64;
        for _ in 0..50 {
            let n = 5 + (lcg(&mut s) * 60.0) as usize;
            let (cx, cy) = (bounds.x + lcg(&mut s) * bounds.w, bounds.y + lcg(&mut s) * bounds.h);
            let pts: Vec<(f64, f64)> =
                (0..n).map(|_| (cx + (lcg(&mut s) - 0.5) * 40.0, cy + (lcg(&mut s) - 0.5) * 40.0)).collect();
            let obstacles: Vec<Rect> = pts.iter().map(|&(x, y)| Rect::around(x, y, 7.0, 7.0)).collect();
            let wants: Vec<Want> = pts
                .iter()
                .enumerate()
                .map(|(i, &(px, py))| {
                    let (w, h) = text_size(&"x".repeat(1 + i % 12));
                    Want { px, py, w, h }
                })
                .collect();
            check(&wants, &obstacles, bounds);
        }
    }

    #[test]
    fn a_lone_label_sits_next_to_its_point_without_a_leader() {
        let bounds = Rect { x: 0.0, y: 0.0, w: 200.0, h: 200.0 };
        let (w, h) = text_size("12");
        let p = place(&[Want { px: 100.0, py: 100.0, w, h }], &[], bounds)[0].unwrap();
        assert!(!p.leader);
        // Up and to the right of the point, not covering it, within a few pixels.
        assert!(
            p.rect.x > 100.0 && p.rect.x < 104.0 && p.rect.y + p.rect.h < 100.0 && p.rect.y + p.rect.h > 94.0,
            "{p:?}"
        );
        // No room at all: not placed, rather than drawn over the obstacle.
        let full = [bounds];
        assert_eq!(place(&[Want { px: 100.0, py: 100.0, w, h }], &full, bounds), vec![None]);
    }
}
