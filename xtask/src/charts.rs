//! Charts as SVG and PNG (plotters), staged in an output set. Text is set
//! in DejaVu Sans, embedded (the `dejavu` crate), so PNG charts need no
//! system fonts; the pressure maps (`pressure_image`) use the same font.

use std::sync::OnceLock;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use tyreroad::scenario::output::OutputSet;

/// Distinguishable line colours (Okabe–Ito), in series order.
const COLOURS: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
];

/// One named series of points.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
}

/// Chart size in pixels (SVG user units).
const SIZE: (u32, u32) = (900, 520);

/// Registers the embedded font under the family name the charts use, once.
pub fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(anyhow!("the embedded chart font could not be loaded"))
    }
}

/// A line-and-marker chart of several series, like the paper's figures 3
/// and 4 (a quantity per indenter, one series per load): staged as SVG
/// `NAME.svg` and PNG `NAME.png`.
pub fn line_chart(
    set: &mut OutputSet,
    name: &str,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    register_font()?;
    let mut svg = String::new();
    draw(
        SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(),
        title,
        x_label,
        y_label,
        series,
    )?;
    let mut pixels = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area(),
        title,
        x_label,
        y_label,
        series,
    )?;
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, pixels)
        .ok_or_else(|| anyhow!("chart {title}: pixel buffer of the wrong size"))?;
    let mut png = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| anyhow!("chart {title}: encoding PNG: {e}"))?;
    set.write(&format!("{name}.svg"), svg.as_bytes())?;
    set.write(&format!("{name}.png"), png.get_ref())?;
    Ok(())
}

/// Steps of a time signal up to which a chart draws every point (and its
/// marker); longer signals are reduced by [`min_max_columns`].
pub const CHART_POINTS: usize = 4000;

/// Time columns a long signal is reduced to: about a pixel column each.
pub const CHART_COLUMNS: usize = 1000;

/// A column being reduced: its number, and its lowest and highest point,
/// each with its place in the input.
type Column = (usize, (usize, (f64, f64)), (usize, (f64, f64)));

/// Points ordered by `x` in `x_span`, reduced to at most two per column
/// of `columns` equal columns of the span: the lowest and the highest
/// point of each, in their original order, so a peak or a dip of a single
/// point is still drawn. Memory and output `O(columns)`, not `O(points)`.
pub fn min_max_columns(
    points: impl Iterator<Item = (f64, f64)>,
    columns: usize,
    [x0, x1]: [f64; 2],
) -> Vec<(f64, f64)> {
    let columns = columns.max(1);
    let width = (x1 - x0) / columns as f64;
    let column = |x: f64| -> usize {
        if width > 0.0 {
            (((x - x0) / width).floor().max(0.0) as usize).min(columns - 1)
        } else {
            0
        }
    };
    let mut out = Vec::with_capacity(2 * columns);
    // The current column, its lowest and highest point with their order.
    let mut current: Option<Column> = None;
    let flush = |out: &mut Vec<(f64, f64)>, (_, low, high): Column| {
        let (first, second) = if low.0 <= high.0 {
            (low, high)
        } else {
            (high, low)
        };
        out.push(first.1);
        if second.0 != first.0 {
            out.push(second.1);
        }
    };
    for (k, p) in points.enumerate() {
        let c = column(p.0);
        match current.as_mut() {
            Some((col, low, high)) if *col == c => {
                if p.1 < low.1.1 {
                    *low = (k, p);
                }
                if p.1 > high.1.1 {
                    *high = (k, p);
                }
            }
            _ => {
                if let Some(done) = current.take() {
                    flush(&mut out, done);
                }
                current = Some((c, (k, p), (k, p)));
            }
        }
    }
    if let Some(done) = current {
        flush(&mut out, done);
    }
    out
}

/// Draws the chart on any plotters backend.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    let (mut x0, mut x1, mut y0, mut y1) =
        (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64, f64::NEG_INFINITY);
    for s in series {
        for &(x, y) in &s.points {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    if !(x0.is_finite() && x1.is_finite() && y1.is_finite()) {
        return Err(anyhow!("chart {title}: no data"));
    }
    let pad = 0.08 * (y1 - y0).max(f64::MIN_POSITIVE);
    {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(x0 - 0.5..x1 + 0.5, y0..y1 + pad)
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .x_labels(((x1 - x0) as usize + 1).min(30))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (k, s) in series.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()].to_rgba();
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(|e| anyhow!("{e}"))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(|e| anyhow!("{e}"))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A long noisy signal with one spike and one dip of a single sample:
    /// at most two points per column, all of them input points, in order,
    /// and the spike, the dip and each column's extremes are kept (checked
    /// against a direct per-column search).
    #[test]
    fn min_max_columns_keeps_every_column_extreme() {
        let n = 100_000;
        let y = |k: usize| -> f64 {
            match k {
                31_337 => 50.0,
                77_001 => -50.0,
                _ => ((k * 7919) % 1000) as f64 * 1e-3,
            }
        };
        let points: Vec<(f64, f64)> = (0..n).map(|k| (k as f64 * 0.01, y(k))).collect();
        let span = [0.0, (n - 1) as f64 * 0.01];
        let kept = min_max_columns(points.iter().copied(), 1000, span);
        assert!(kept.len() <= 2000 && kept.len() >= 1000, "{}", kept.len());
        assert!(kept.windows(2).all(|w| w[0].0 <= w[1].0));
        assert!(kept.iter().all(|p| points.contains(p)));
        assert!(kept.contains(&points[31_337]) && kept.contains(&points[77_001]));
        let width = span[1] / 1000.0;
        for c in 0..1000 {
            let inside = |p: &&(f64, f64)| ((p.0 / width).floor() as usize).min(999) == c;
            let column: Vec<f64> = points.iter().filter(inside).map(|p| p.1).collect();
            let drawn: Vec<f64> = kept.iter().filter(inside).map(|p| p.1).collect();
            let (lo, hi) = column
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            assert!(drawn.contains(&lo) && drawn.contains(&hi), "column {c}");
        }
    }
}
