//! A pressure map as a PNG, what a pressure film would show: one pixel per
//! map cell, zero pressure white, contact pressures through the viridis
//! colour map, and a colour bar labelled in MPa. Drawn with plotters; text
//! in the charts' embedded DejaVu font (`charts::register_font`).

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use tyreroad::scenario::output::OutputSet;
use tyreroad::two_scale::PressureField;

use crate::charts::register_font;

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
pub fn viridis(t: f64) -> RGBColor {
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
    RGBColor(c[0], c[1], c[2])
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

const MARGIN: i32 = 16;
const BAR_W: i32 = 20;
const TEXT_PX: i32 = 14;

/// Renders the map into RGB pixels: north up (row `j = 0` of the grid at the
/// bottom), colour bar from 0 to the peak pressure on the right, `title` at
/// the top left, and a 10 mm scale bar. Returns `(width, height, pixels)`.
pub fn render(map: &PressureField, title: &str) -> Result<(u32, u32, Vec<u8>)> {
    register_font()?;
    let (nx, ny) = (map.grid().nx() as i32, map.grid().ny() as i32);
    let p_max = map.max().max(f64::MIN_POSITIVE);
    let top = MARGIN + TEXT_PX + 8;
    let bar_x = MARGIN + nx + 24;
    let label_x = bar_x + BAR_W + 8;
    let width = (label_x + 70 + MARGIN) as u32;
    let height = (top + ny + MARGIN + TEXT_PX + 10) as u32;
    let mut pixels = vec![255u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        let e = |e: DrawingAreaErrorKind<_>| anyhow!("pressure map {title}: {e}");
        let font = ("sans-serif", TEXT_PX).into_font().color(&BLACK);
        for j in 0..ny {
            for i in 0..nx {
                let p = map.values()[(j * nx + i) as usize];
                if p > 0.0 {
                    root.draw_pixel((MARGIN + i, top + (ny - 1 - j)), &viridis(p / p_max))
                        .map_err(e)?;
                }
            }
        }
        root.draw(&Rectangle::new(
            [(MARGIN - 1, top - 1), (MARGIN + nx, top + ny)],
            BLACK.stroke_width(1),
        ))
        .map_err(e)?;
        root.draw(&Text::new(
            title.to_string(),
            (MARGIN, MARGIN),
            font.clone(),
        ))
        .map_err(e)?;

        // 10 mm scale bar under the map.
        let ten_mm = (0.01 / map.grid().dx()).round() as i32;
        if ten_mm + 2 < nx {
            let y = top + ny + 8;
            root.draw(&Rectangle::new(
                [(MARGIN, y), (MARGIN + ten_mm, y + 2)],
                BLACK.filled(),
            ))
            .map_err(e)?;
            root.draw(&Text::new(
                "10 mm".to_string(),
                (MARGIN + ten_mm + 6, y + 1),
                font.pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(e)?;
        }

        // Colour bar: 0 at the bottom, p_max at the top.
        let bar_h = ny.max(2);
        for y in 0..bar_h {
            let t = 1.0 - f64::from(y) / f64::from(bar_h - 1);
            root.draw(&Rectangle::new(
                [(bar_x, top + y), (bar_x + BAR_W, top + y + 1)],
                viridis(t).filled(),
            ))
            .map_err(e)?;
        }
        root.draw(&Text::new("MPa".to_string(), (bar_x, MARGIN), font.clone()))
            .map_err(e)?;
        let max_mpa = p_max / 1e6;
        let step = tick_step(max_mpa, 6.0);
        let decimals = (-step.log10().floor()).max(0.0) as usize;
        let mut k = 0.0;
        while k * step <= max_mpa * (1.0 + 1e-9) {
            let v = k * step;
            let y = top + ((1.0 - v / max_mpa) * f64::from(bar_h - 1)).round() as i32;
            root.draw(&PathElement::new(
                vec![(bar_x + BAR_W, y), (bar_x + BAR_W + 4, y)],
                BLACK,
            ))
            .map_err(e)?;
            root.draw(&Text::new(
                format!("{v:.decimals$}"),
                (label_x, y),
                font.pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(e)?;
            k += 1.0;
        }
        root.present().map_err(e)?;
    }
    Ok((width, height, pixels))
}

/// Renders the map (see [`render`]) and stages it as PNG file `name`.
pub fn write_pressure_png(
    set: &mut OutputSet,
    name: &str,
    map: &PressureField,
    title: &str,
) -> Result<()> {
    let (w, h, pixels) = render(map, title)?;
    let img = image::RgbImage::from_raw(w, h, pixels)
        .ok_or_else(|| anyhow!("pressure map {title}: pixel buffer of the wrong size"))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)?;
    set.write(name, bytes.get_ref())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_ticks() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(68, 1, 84));
        assert!((tick_step(2.55, 6.0) - 0.5).abs() < 1e-12);
        assert!((tick_step(3.1, 6.0) - 1.0).abs() < 1e-12);
        assert!((tick_step(0.9, 6.0) - 0.2).abs() < 1e-12);
    }
}
