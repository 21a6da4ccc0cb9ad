//! A grey image (a mask obstacle's, the density map) made and painted: a blank one at the
//! world's size, one thresholded from a picture of the level, and the paint tool's marks:
//! a soft brush (size, hardness, opacity), a rectangle and a fill. Plain data: the pictures
//! come in decoded, and a mark is laid on a coverage (how much each pixel takes of the
//! paint, 0 to 1) that a stroke keeps, so a stroke's dabs never build up past its opacity.

use super::types::{MaskImage, Vec2};

/// The longest side a new image takes, pixels (the sides a mask may have are longer: this
/// keeps one made in the editor quick to paint, save and autosave).
pub const NEW_IMAGE_MAX_SIDE: u32 = 4096;

/// A new image of `width` × `height` pixels, every pixel `value`.
pub fn blank(width: u32, height: u32, value: u16) -> MaskImage {
    MaskImage {
        width,
        height,
        luminance: vec![value; width as usize * height as usize],
    }
}

/// The size of a new image over `size` metres at `per_metre` pixels a metre: at least one
/// pixel a side, the longer side at most [`NEW_IMAGE_MAX_SIDE`] (the resolution lowered to
/// fit, the aspect kept).
pub fn size_for(size: Vec2, per_metre: f32) -> (u32, u32) {
    let longer = size[0].max(size[1]).max(1e-3);
    let per_metre = per_metre.max(1e-3).min(NEW_IMAGE_MAX_SIDE as f32 / longer);
    let side = |m: f32| ((m * per_metre).round() as u32).clamp(1, NEW_IMAGE_MAX_SIDE);
    (side(size[0]), side(size[1]))
}

/// A pixel's luma, 0 to 1: Rec. 709's weights on its stored (sRGB-encoded) values, the
/// lightness the designer sees and the grey a mask's reader takes from a grey file.
fn luma(px: &[u8]) -> f32 {
    (0.2126 * f32::from(px[0]) + 0.7152 * f32::from(px[1]) + 0.0722 * f32::from(px[2])) / 255.0
}

/// A grey image from a picture (`rgba`, `width` × `height`, row-major from the top-left):
/// each pixel `on` where its luma (Rec. 709 on the stored sRGB values) is at least `threshold` (below it with `invert`), else
/// `off`; shrunk by whole pixels to at most [`NEW_IMAGE_MAX_SIDE`] a side (a pixel of the
/// image takes the picture's pixel at its centre).
pub fn threshold(
    rgba: &[u8],
    width: u32,
    height: u32,
    threshold: f32,
    invert: bool,
    (on, off): (u16, u16),
) -> MaskImage {
    let step = width.max(height).div_ceil(NEW_IMAGE_MAX_SIDE).max(1);
    let (w, h) = (width.div_ceil(step), height.div_ceil(step));
    let mut luminance = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h {
        let sy = (y * step + step / 2).min(height - 1);
        for x in 0..w {
            let sx = (x * step + step / 2).min(width - 1);
            let k = 4 * (sy as usize * width as usize + sx as usize);
            let lit = (luma(&rgba[k..k + 4]) >= threshold) != invert;
            luminance.push(if lit { on } else { off });
        }
    }
    MaskImage {
        width: w,
        height: h,
        luminance,
    }
}

/// The threshold that best splits a picture's pixels into a dark and a light part (Otsu's:
/// the largest variance between the two), for a first guess a designer can move.
pub fn auto_threshold(rgba: &[u8]) -> f32 {
    let mut hist = [0u64; 256];
    for px in rgba.chunks_exact(4) {
        hist[(luma(px) * 255.0).round() as usize] += 1;
    }
    let total: u64 = hist.iter().sum();
    let sum: f64 = hist
        .iter()
        .enumerate()
        .map(|(k, &n)| k as f64 * n as f64)
        .sum();
    let (mut below, mut below_sum) = (0u64, 0.0f64);
    let (mut best, mut best_k) = (-1.0f64, 127usize);
    for (k, &n) in hist.iter().enumerate() {
        below += n;
        below_sum += k as f64 * n as f64;
        let above = total - below;
        if below == 0 || above == 0 {
            continue;
        }
        let m0 = below_sum / below as f64;
        let m1 = (sum - below_sum) / above as f64;
        let between = below as f64 * above as f64 * (m0 - m1) * (m0 - m1);
        if between > best {
            best = between;
            best_k = k;
        }
    }
    // Lit from the first grey above the dark part.
    (best_k as f32 + 1.0) / 255.0
}

/// How the paint's edge falls off: a pixel at `d` (0 at the centre, 1 at the radius) takes
/// all of it within `hardness` of the radius, none beyond the radius, and a smooth step
/// between.
pub fn falloff(d: f32, hardness: f32) -> f32 {
    let h = hardness.clamp(0.0, 1.0);
    if d <= h {
        return 1.0;
    }
    if d >= 1.0 {
        return 0.0;
    }
    let t = 1.0 - (d - h) / (1.0 - h);
    t * t * (3.0 - 2.0 * t)
}

/// The pixels of an image `w` × `h` placed over `rect` (metres) whose centres lie in the
/// world box `[lo, hi]`, as index ranges (empty where it misses the image).
fn pixel_span(
    (w, h): (u32, u32),
    rect: [Vec2; 2],
    lo: Vec2,
    hi: Vec2,
) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
    let px = [
        (rect[1][0] - rect[0][0]) / w as f32,
        (rect[1][1] - rect[0][1]) / h as f32,
    ];
    let span = |a: f32, b: f32, o: f32, p: f32, n: u32| {
        let first = ((a - o) / p - 0.5).ceil().max(0.0) as usize;
        let end = (((b - o) / p - 0.5).floor() + 1.0).clamp(0.0, n as f32) as usize;
        first..end.max(first)
    };
    (
        span(lo[0], hi[0], rect[0][0], px[0], w),
        span(lo[1], hi[1], rect[0][1], px[1], h),
    )
}

/// The world point at the centre of pixel `(x, y)` of an image `w` × `h` over `rect`.
fn pixel_centre((w, h): (u32, u32), rect: [Vec2; 2], x: usize, y: usize) -> Vec2 {
    [
        rect[0][0] + (x as f32 + 0.5) * (rect[1][0] - rect[0][0]) / w as f32,
        rect[0][1] + (y as f32 + 0.5) * (rect[1][1] - rect[0][1]) / h as f32,
    ]
}

/// A soft brush's dab at world point `centre` of `radius` metres: each pixel of an image
/// `size` over `rect` under it takes at least its [`falloff`] into `cover`. Returns whether
/// any pixel's coverage grew.
pub fn dab(
    size: (u32, u32),
    rect: [Vec2; 2],
    centre: Vec2,
    radius: f32,
    hardness: f32,
    cover: &mut [f32],
) -> bool {
    let r = radius.max(1e-6);
    let (xs, ys) = pixel_span(
        size,
        rect,
        [centre[0] - r, centre[1] - r],
        [centre[0] + r, centre[1] + r],
    );
    let mut grew = false;
    for y in ys {
        for x in xs.clone() {
            let p = pixel_centre(size, rect, x, y);
            let d = (p[0] - centre[0]).hypot(p[1] - centre[1]) / r;
            let c = falloff(d, hardness);
            let k = y * size.0 as usize + x;
            if c > cover[k] {
                cover[k] = c;
                grew = true;
            }
        }
    }
    grew
}

/// A rectangle from world corner `a` to `b`: every pixel whose centre lies inside is wholly
/// covered. Returns whether any pixel's coverage grew.
pub fn rectangle(size: (u32, u32), rect: [Vec2; 2], a: Vec2, b: Vec2, cover: &mut [f32]) -> bool {
    let lo = [a[0].min(b[0]), a[1].min(b[1])];
    let hi = [a[0].max(b[0]), a[1].max(b[1])];
    let (xs, ys) = pixel_span(size, rect, lo, hi);
    let mut grew = false;
    for y in ys {
        for x in xs.clone() {
            let k = y * size.0 as usize + x;
            grew |= cover[k] < 1.0;
            cover[k] = 1.0;
        }
    }
    grew
}

/// A fill from the pixel under world point `seed`: the pixels joined to it (through their
/// four sides) that `same` accepts, as the seed is, wholly covered. Returns how many.
pub fn fill(
    image: &MaskImage,
    rect: [Vec2; 2],
    seed: Vec2,
    same: impl Fn(u16) -> bool,
    cover: &mut [f32],
) -> usize {
    let Some([u, v]) = super::types::image_uv(rect, seed) else {
        return 0;
    };
    let (w, h) = (image.width as usize, image.height as usize);
    let start = ((v * h as f32) as usize).min(h - 1) * w + ((u * w as f32) as usize).min(w - 1);
    if !same(image.luminance[start]) {
        return 0;
    }
    let mut seen = vec![false; w * h];
    let mut todo = vec![start];
    seen[start] = true;
    let mut n = 0;
    while let Some(k) = todo.pop() {
        cover[k] = 1.0;
        n += 1;
        let (x, y) = (k % w, k / w);
        let mut visit = |j: usize| {
            if !seen[j] && same(image.luminance[j]) {
                seen[j] = true;
                todo.push(j);
            }
        };
        if x > 0 {
            visit(k - 1);
        }
        if x + 1 < w {
            visit(k + 1);
        }
        if y > 0 {
            visit(k - w);
        }
        if y + 1 < h {
            visit(k + w);
        }
    }
    n
}

/// `original` with `value` laid over it as `cover` says, at `opacity` (0 to 1): each pixel
/// moves from its own value toward `value` by its coverage times the opacity.
pub fn blend(original: &MaskImage, cover: &[f32], value: u16, opacity: f32) -> MaskImage {
    let o = opacity.clamp(0.0, 1.0);
    let luminance = (original.luminance.iter().zip(cover))
        .map(|(&l, &c)| {
            let t = c * o;
            if t <= 0.0 {
                l
            } else {
                (f32::from(l) + (f32::from(value) - f32::from(l)) * t).round() as u16
            }
        })
        .collect();
    MaskImage {
        width: original.width,
        height: original.height,
        luminance,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WORLD: [Vec2; 2] = [[0.0, 0.0], [10.0, 10.0]];

    /// A hard brush paints whole pixels within its radius and nothing past it; a soft one
    /// fades to nothing at its edge; opacity caps a stroke however often it passes.
    #[test]
    fn a_brush_s_hardness_and_opacity_shape_its_mark() {
        let image = blank(10, 10, 0);
        let mut cover = vec![0.0; 100];
        assert!(dab((10, 10), WORLD, [5.0, 5.0], 2.0, 1.0, &mut cover));
        let hard = blend(&image, &cover, 1000, 1.0);
        assert_eq!(hard.luminance[5 * 10 + 5], 1000, "the centre");
        assert_eq!(hard.luminance[5 * 10 + 7], 0, "a pixel centre 2.5 m away");
        assert_eq!(hard.luminance.iter().filter(|&&l| l == 1000).count(), 12);
        let mut soft = vec![0.0; 100];
        dab((10, 10), WORLD, [5.0, 5.0], 2.0, 0.0, &mut soft);
        let inner = soft[5 * 10 + 5];
        let outer = soft[5 * 10 + 6];
        assert!(inner > outer && outer > 0.0, "{inner} {outer}");
        // Two passes of a stroke at half opacity: half, not three quarters.
        dab((10, 10), WORLD, [5.0, 5.0], 2.0, 1.0, &mut cover);
        assert_eq!(blend(&image, &cover, 1000, 0.5).luminance[55], 500);
    }

    #[test]
    fn rectangles_and_fills_cover_what_they_should() {
        let mut image = blank(10, 10, 60_000);
        // A wall across x = 4 splits the image.
        for y in 0..10 {
            image.luminance[y * 10 + 4] = 0;
        }
        let mut cover = vec![0.0; 100];
        assert_eq!(
            fill(&image, WORLD, [1.0, 1.0], |l| l > 30_000, &mut cover),
            40
        );
        assert_eq!(cover[5], 0.0, "the fill stops at the wall");
        let mut cover = vec![0.0; 100];
        assert!(rectangle(
            (10, 10),
            WORLD,
            [2.0, 2.0],
            [0.0, 0.0],
            &mut cover
        ));
        assert_eq!(cover.iter().filter(|&&c| c == 1.0).count(), 4);
    }

    #[test]
    fn a_picture_thresholds_into_a_mask_and_new_images_fit_the_world() {
        // Black left half, white right half.
        let rgba: Vec<u8> = (0..4 * 2)
            .flat_map(|k| {
                if k % 4 < 2 {
                    [0, 0, 0, 255]
                } else {
                    [255, 255, 255, 255]
                }
            })
            .collect();
        let m = threshold(&rgba, 4, 2, 0.5, false, (u16::MAX, 0));
        assert_eq!(
            m.luminance,
            vec![0, 0, u16::MAX, u16::MAX, 0, 0, u16::MAX, u16::MAX]
        );
        let inv = threshold(&rgba, 4, 2, 0.5, true, (u16::MAX, 0));
        assert_eq!(inv.luminance[0], u16::MAX);
        // A mid-grey (128 of 255) is lit at 0.5: the stored value, as a grey file reads.
        let grey = threshold(&[128, 128, 128, 255], 1, 1, 0.5, false, (1, 0));
        assert_eq!(grey.luminance, vec![1]);
        // Dark buildings on a lighter field: the automatic threshold falls between them.
        let picture: Vec<u8> = (0..100)
            .flat_map(|k| {
                if k < 30 {
                    [40, 40, 40, 255]
                } else {
                    [90, 143, 60, 255]
                }
            })
            .collect();
        let t = auto_threshold(&picture);
        assert!(t > 40.0 / 255.0 && t <= 0.49, "{t}");
        let split = threshold(&picture, 100, 1, t, false, (1, 0));
        assert_eq!(split.luminance.iter().filter(|&&l| l == 0).count(), 30);
        assert_eq!(size_for([120.0, 80.0], 4.0), (480, 320));
        assert_eq!(size_for([10_000.0, 5_000.0], 4.0), (4096, 2048));
        let big = vec![255u8; 4 * 8192 * 2];
        let m = threshold(&big, 8192, 2, 0.5, false, (1, 0));
        assert_eq!((m.width, m.height), (4096, 1));
    }
}
