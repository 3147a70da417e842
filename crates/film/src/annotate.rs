//! Annotated image of an analysis: prints outlined, best-fit ellipses drawn,
//! indenter numbers written with a built-in 3 × 5 bitmap digit font.

use image::{Rgb, RgbImage};

use crate::analysis::Detection;
use crate::layout::Matching;
use crate::scan::Scan;

/// 3 × 5 digit glyphs, one row per `u8` (3 low bits, left = bit 2).
const DIGITS: [[u8; 5]; 10] = [
    [0b111, 0b101, 0b101, 0b101, 0b111],
    [0b010, 0b110, 0b010, 0b010, 0b111],
    [0b111, 0b001, 0b111, 0b100, 0b111],
    [0b111, 0b001, 0b011, 0b001, 0b111],
    [0b101, 0b101, 0b111, 0b001, 0b001],
    [0b111, 0b100, 0b111, 0b001, 0b111],
    [0b111, 0b100, 0b111, 0b101, 0b111],
    [0b111, 0b001, 0b010, 0b010, 0b010],
    [0b111, 0b101, 0b111, 0b101, 0b111],
    [0b111, 0b101, 0b111, 0b001, 0b111],
];

const OUTLINE: Rgb<u8> = Rgb([230, 30, 30]);
const ELLIPSE: Rgb<u8> = Rgb([30, 90, 240]);
const TEXT: Rgb<u8> = Rgb([0, 150, 0]);

fn put(img: &mut RgbImage, x: i64, y: i64, c: Rgb<u8>) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, c);
    }
}

/// Writes the decimal number `n` with its top-left corner at `(x, y)`, each
/// font pixel a `scale × scale` block.
pub fn draw_number(img: &mut RgbImage, n: u32, x: i64, y: i64, scale: i64, colour: Rgb<u8>) {
    let s = n.to_string();
    let scale = scale.max(1);
    for (k, ch) in s.bytes().enumerate() {
        let glyph = &DIGITS[(ch - b'0') as usize];
        let gx = x + k as i64 * 4 * scale;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..3 {
                if bits & (0b100 >> col) != 0 {
                    for dy in 0..scale {
                        for dx in 0..scale {
                            put(
                                img,
                                gx + col * scale + dx,
                                y + row as i64 * scale + dy,
                                colour,
                            );
                        }
                    }
                }
            }
        }
    }
}

/// The scan in grey with, for each print, its outline (reacted pixels with
/// an unreacted edge neighbour) in red and its best-fit ellipse in blue, and
/// when `matching` is given the indenter numbers in green beside the prints.
pub fn annotate(scan: &Scan, detection: &Detection, matching: Option<&Matching>) -> RgbImage {
    let (w, h) = (scan.width(), scan.height());
    let mut img = RgbImage::from_fn(w as u32, h as u32, |x, y| {
        let g = scan.get(x as usize, y as usize).unwrap_or(0.0);
        let v = (g.clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb([v, v, v])
    });
    let labels = &detection.labels;
    for r in 0..h {
        for c in 0..w {
            let l = labels[r * w + c];
            if l == 0 {
                continue;
            }
            let edge = c == 0
                || r == 0
                || c + 1 == w
                || r + 1 == h
                || labels[r * w + c - 1] != l
                || labels[r * w + c + 1] != l
                || labels[(r - 1) * w + c] != l
                || labels[(r + 1) * w + c] != l;
            if edge {
                img.put_pixel(c as u32, r as u32, OUTLINE);
            }
        }
    }
    let s = detection.pixel_size;
    for p in &detection.prints {
        let e = &p.ellipse;
        let (a, b) = (e.semi_major / s, e.semi_minor / s);
        let n = ((2.0 * std::f64::consts::PI * a).ceil() as usize * 2).max(16);
        let (sn, cs) = e.orientation.sin_cos();
        for k in 0..n {
            let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let (u, v) = (a * t.cos(), b * t.sin());
            // Film frame has y up: image rows go down.
            let x = p.centroid_px.0 + u * cs - v * sn;
            let y = p.centroid_px.1 - (u * sn + v * cs);
            put(&mut img, x.floor() as i64, y.floor() as i64, ELLIPSE);
        }
    }
    if let Some(m) = matching {
        let scale = ((w.min(h) as f64 / 300.0).round() as i64).max(1);
        for mt in &m.matches {
            let p = &detection.prints[mt.print];
            let x = p.centroid_px.0 + p.ellipse.semi_major / s + 2.0 * scale as f64;
            let y = p.centroid_px.1 - p.ellipse.semi_major / s - 2.0 * scale as f64;
            draw_number(
                &mut img,
                mt.indenter.number,
                x as i64,
                y as i64,
                scale,
                TEXT,
            );
        }
    }
    img
}

/// [`annotate`], encoded as PNG bytes (for writing whole, e.g. through a
/// temporary file and a rename).
pub fn annotated_png(
    scan: &Scan,
    detection: &Detection,
    matching: Option<&Matching>,
) -> crate::Result<Vec<u8>> {
    let img = annotate(scan, detection, matching);
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| crate::FilmError::Image {
            path: "<annotated>".into(),
            message: e.to_string(),
        })?;
    Ok(png)
}
