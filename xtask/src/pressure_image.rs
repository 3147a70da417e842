//! A pressure map as a PNG, what a pressure film would show: one pixel per
//! map cell, zero pressure white, contact pressures through the viridis
//! colour map, and a colour bar labelled in MPa with a built-in bitmap font
//! (no system fonts needed).

use std::path::Path;

use anyhow::Result;
use image::{ImageFormat, Rgb, RgbImage};
use tyreroad::two_scale::PressureField;

use crate::output::write_atomic;

/// Viridis at 0, 1/8, …, 1 (matplotlib's table, sampled), interpolated
/// linearly in between.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Viridis colour of `t ∈ [0, 1]`.
pub fn viridis(t: f64) -> Rgb<u8> {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let mut c = [0u8; 3];
    for (ch, out) in c.iter_mut().enumerate() {
        let a = f64::from(VIRIDIS[k][ch]);
        let b = f64::from(VIRIDIS[k + 1][ch]);
        *out = (a + f * (b - a)).round() as u8;
    }
    Rgb(c)
}

/// Glyphs 5 rows high; each row's bits read left to right over `width`.
fn glyph(c: char) -> Option<(u8, [u8; 5])> {
    Some(match c {
        '0' => (3, [0b111, 0b101, 0b101, 0b101, 0b111]),
        '1' => (3, [0b010, 0b110, 0b010, 0b010, 0b111]),
        '2' => (3, [0b111, 0b001, 0b111, 0b100, 0b111]),
        '3' => (3, [0b111, 0b001, 0b011, 0b001, 0b111]),
        '4' => (3, [0b101, 0b101, 0b111, 0b001, 0b001]),
        '5' => (3, [0b111, 0b100, 0b111, 0b001, 0b111]),
        '6' => (3, [0b111, 0b100, 0b111, 0b101, 0b111]),
        '7' => (3, [0b111, 0b001, 0b010, 0b010, 0b010]),
        '8' => (3, [0b111, 0b101, 0b111, 0b101, 0b111]),
        '9' => (3, [0b111, 0b101, 0b111, 0b001, 0b111]),
        '.' => (1, [0, 0, 0, 0, 1]),
        ' ' => (2, [0; 5]),
        'M' => (5, [0b10001, 0b11011, 0b10101, 0b10001, 0b10001]),
        'P' => (3, [0b110, 0b101, 0b110, 0b100, 0b100]),
        'a' => (3, [0b000, 0b011, 0b101, 0b101, 0b011]),
        'N' => (4, [0b1001, 0b1101, 0b1011, 0b1001, 0b1001]),
        'm' => (5, [0b00000, 0b11010, 0b10101, 0b10101, 0b10101]),
        _ => return None,
    })
}

/// Width in pixels of `text` at `scale`.
fn text_width(text: &str, scale: u32) -> u32 {
    text.chars()
        .filter_map(glyph)
        .map(|(w, _)| (u32::from(w) + 1) * scale)
        .sum()
}

/// Draws `text` with its top-left corner at `(x, y)`; unknown characters
/// are skipped.
fn draw_text(img: &mut RgbImage, text: &str, x: u32, y: u32, scale: u32, colour: Rgb<u8>) {
    let mut cx = x;
    for (w, rows) in text.chars().filter_map(glyph) {
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..u32::from(w) {
                if bits >> (u32::from(w) - 1 - col) & 1 == 1 {
                    fill(
                        img,
                        cx + col * scale,
                        y + r as u32 * scale,
                        scale,
                        scale,
                        colour,
                    );
                }
            }
        }
        cx += (u32::from(w) + 1) * scale;
    }
}

fn fill(img: &mut RgbImage, x: u32, y: u32, w: u32, h: u32, colour: Rgb<u8>) {
    for yy in y..(y + h).min(img.height()) {
        for xx in x..(x + w).min(img.width()) {
            img.put_pixel(xx, yy, colour);
        }
    }
}

/// A "nice" tick step (1, 2 or 5 × 10^k) for about `count` ticks up to `max`.
fn tick_step(max: f64, count: f64) -> f64 {
    let raw = max / count;
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

/// Renders the map: north up (row `j` of the grid at the bottom for `j = 0`),
/// colour bar from 0 to the peak pressure on the right, `title` at the top
/// left, and a 10 mm scale bar.
pub fn render(map: &PressureField, title: &str) -> RgbImage {
    const SCALE: u32 = 2;
    const MARGIN: u32 = 16;
    const BAR_W: u32 = 20;
    let white = Rgb([255, 255, 255]);
    let black = Rgb([0, 0, 0]);
    let (nx, ny) = (map.grid().nx() as u32, map.grid().ny() as u32);
    let p_max = map.max().max(f64::MIN_POSITIVE);
    let top = MARGIN + 7 * SCALE + 8;
    let bar_x = MARGIN + nx + 24;
    let label_x = bar_x + BAR_W + 8;
    let width = label_x + text_width("00.00 MPa", SCALE) + MARGIN;
    let height = top + ny + MARGIN + 7 * SCALE + 10;
    let mut img = RgbImage::from_pixel(width, height, white);

    for j in 0..ny {
        for i in 0..nx {
            let p = map.values()[(j * nx + i) as usize];
            let c = if p > 0.0 { viridis(p / p_max) } else { white };
            img.put_pixel(MARGIN + i, top + (ny - 1 - j), c);
        }
    }
    // Frame.
    fill(&mut img, MARGIN - 1, top - 1, nx + 2, 1, black);
    fill(&mut img, MARGIN - 1, top + ny, nx + 2, 1, black);
    fill(&mut img, MARGIN - 1, top - 1, 1, ny + 2, black);
    fill(&mut img, MARGIN + nx, top - 1, 1, ny + 2, black);
    draw_text(&mut img, title, MARGIN, MARGIN, SCALE, black);

    // 10 mm scale bar under the map.
    let ten_mm = (0.01 / map.grid().dx()).round() as u32;
    if ten_mm + 2 < nx {
        let y = top + ny + 8;
        fill(&mut img, MARGIN, y, ten_mm, SCALE, black);
        draw_text(
            &mut img,
            "10 mm",
            MARGIN + ten_mm + 6,
            y - 2 * SCALE,
            SCALE,
            black,
        );
    }

    // Colour bar: 0 at the bottom, p_max at the top.
    let bar_h = ny.max(2);
    for y in 0..bar_h {
        let t = 1.0 - f64::from(y) / f64::from(bar_h - 1);
        fill(&mut img, bar_x, top + y, BAR_W, 1, viridis(t));
    }
    draw_text(&mut img, "MPa", bar_x, MARGIN, SCALE, black);
    let max_mpa = p_max / 1e6;
    let step = tick_step(max_mpa, 6.0);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let mut k = 0.0;
    while k * step <= max_mpa * (1.0 + 1e-9) {
        let v = k * step;
        let y = top + ((1.0 - v / max_mpa) * f64::from(bar_h - 1)).round() as u32;
        fill(&mut img, bar_x + BAR_W, y, 4, 1, black);
        let label = format!("{v:.decimals$}");
        let ly = y.saturating_sub(5 * SCALE / 2).max(top.saturating_sub(2));
        draw_text(&mut img, &label, label_x, ly, SCALE, black);
        k += 1.0;
    }
    img
}

/// Renders the map (see [`render`]) and writes it as a PNG, atomically.
pub fn write_pressure_png(path: &Path, map: &PressureField, title: &str) -> Result<()> {
    let img = render(map, title);
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, ImageFormat::Png)?;
    write_atomic(path, bytes.get_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_ticks() {
        assert_eq!(viridis(0.0), Rgb([68, 1, 84]));
        assert_eq!(viridis(1.0), Rgb([253, 231, 37]));
        assert_eq!(viridis(f64::NAN), Rgb([68, 1, 84]));
        assert!((tick_step(2.55, 6.0) - 0.5).abs() < 1e-12);
        assert!((tick_step(3.1, 6.0) - 1.0).abs() < 1e-12);
        assert!((tick_step(0.9, 6.0) - 0.2).abs() < 1e-12);
        assert_eq!(text_width("1.5", 1), 4 + 2 + 4);
    }
}
