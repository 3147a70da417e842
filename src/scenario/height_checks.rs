//! Plausibility of a height map read from a file: the warnings a run says
//! before anything is solved (docs/texture.md, "Plausibility"). Each names
//! what looks wrong and what the user may have meant: sentinel values and
//! spikes, a roughness or slopes in another unit, a tilted map.

use tyreroad_core::readable3;
use tyreroad_texture::HeightMap;

/// A height farther than this many times the span of the middle 98 % of
/// the heights (1st to 99th percentile) beyond that span is no road
/// surface: a road's deepest pore or highest chipping lies within the
/// span, or just beyond it. The rule that tells a repeated "no data"
/// marker, so a lone spike is warned of exactly where a repeated one is
/// read as missing.
const OUTLIER_SPANS: f64 = tyreroad_texture::sentinel::SENTINEL_SPANS;

/// Sq above this (m) is no road texture (theirs are tenths of a millimetre
/// to a few millimetres): heights in µm or mm read as metres.
const LARGEST_ROAD_SQ: f64 = 0.05;

/// An RMS slope (Sdq) above this is no road texture measured in metres:
/// an asphalt's is a few tenths at sub-millimetre spacings, a tined
/// concrete's vertical groove walls reach 5 at 0.1 mm (the synthetic
/// `transverse_tining`: 4.9). Heights in millimetres read as metres give
/// hundreds.
const STEEPEST_ROAD_SDQ: f64 = 20.0;

/// A best-fit plane that rises more than this many times the texture's Sq
/// (about the plane) across the map, and by more than [`LEVEL_SLOPE`]: the
/// map is tilted, and the load goes to its high edge.
const TILT_SQS: f64 = 2.0;

/// The plane slope below which a map counts as level whatever its Sq: a
/// road's cross-fall is a few percent, and a window of a few stones (the
/// synthetic `pave`, 40 × 30 mm) leans 3.9 % on their domes.
const LEVEL_SLOPE: f64 = 0.1;

/// A spacing coarser than this (m) is no texture measurement's (a tenth
/// of a millimetre to a millimetre: macrotexture's wavelengths of 0.5 to
/// 50 mm need it): a spacing in millimetres read as metres, most likely
/// (an X3P's increment of 0.25 read as 0.25 m).
const COARSEST_TEXTURE_SPACING: f64 = 0.01;

/// A warning when a map's spacing `dx`, `dy` (m) is coarser than a
/// texture's.
pub(crate) fn spacing_warning(dx: f64, dy: f64) -> Option<String> {
    (dx.max(dy) > COARSEST_TEXTURE_SPACING).then(|| {
        format!(
            "the map's spacing (dx {} mm, dy {} mm) is coarser than any texture measurement's \
             (0.1 to 1 mm; macrotexture's wavelengths of 0.5 to 50 mm need it): is the \
             spacing in millimetres where metres were meant?",
            readable3(dx * 1e3),
            readable3(dy * 1e3)
        )
    })
}

/// The RMS slope `Sdq = √(⟨(∂z/∂x)²⟩ + ⟨(∂z/∂y)²⟩)` of `map` over the pairs
/// of neighbouring valid points (`None` without such a pair).
fn rms_slope(map: &HeightMap) -> Option<f64> {
    let (nx, ny) = (map.nx(), map.ny());
    let (z, ok) = (map.heights(), map.valid());
    // Heights in units of the largest: squares of 1e150 m heights would
    // overflow, and the warning would print "inf".
    let scale = z
        .iter()
        .zip(ok)
        .filter(|(_, ok)| **ok)
        .fold(0.0f64, |m, (h, _)| m.max(h.abs()));
    let unit = if scale > 0.0 { scale } else { 1.0 };
    let mean_square = |di: usize, dj: usize, d: f64| {
        let (mut sum, mut n) = (0.0, 0usize);
        for j in 0..ny - dj {
            for i in 0..nx - di {
                let (a, b) = (j * nx + i, (j + dj) * nx + i + di);
                if ok[a] && ok[b] {
                    sum += ((z[b] / unit - z[a] / unit) / d).powi(2);
                    n += 1;
                }
            }
        }
        (n > 0).then(|| sum / n as f64)
    };
    match (mean_square(1, 0, map.dx()), mean_square(0, 1, map.dy())) {
        (None, None) => None,
        (x, y) => Some(unit * (x.unwrap_or(0.0) + y.unwrap_or(0.0)).sqrt()),
    }
}

/// The least-squares plane `z = a + b x + c y` through the valid points of
/// `map`: its slope `√(b² + c²)`, its rise across the map, and the RMS of
/// the heights about it. `None` for fewer than three points or points on
/// a line.
fn best_plane(map: &HeightMap) -> Option<(f64, f64, f64)> {
    let (nx, ny) = (map.nx(), map.ny());
    let (z, ok) = (map.heights(), map.valid());
    // Centred coordinates keep the normal equations well conditioned.
    let (cx, cy) = (0.5 * (nx - 1) as f64, 0.5 * (ny - 1) as f64);
    let (mut n, mut sz, mut sx, mut sy) = (0.0, 0.0, 0.0, 0.0);
    let (mut sxx, mut syy, mut sxy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if !ok[k] {
                continue;
            }
            let (x, y) = ((i as f64 - cx) * map.dx(), (j as f64 - cy) * map.dy());
            n += 1.0;
            sz += z[k];
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
            sxz += x * z[k];
            syz += y * z[k];
        }
    }
    if n < 3.0 {
        return None;
    }
    let (mx, my, mz) = (sx / n, sy / n, sz / n);
    let (vxx, vyy, vxy) = (sxx / n - mx * mx, syy / n - my * my, sxy / n - mx * my);
    let (vxz, vyz) = (sxz / n - mx * mz, syz / n - my * mz);
    let det = vxx * vyy - vxy * vxy;
    if !(det > 1e-12 * (vxx * vyy).max(f64::MIN_POSITIVE)) {
        // Points on a line (one row or column): no plane to speak of.
        return None;
    }
    let b = (vxz * vyy - vyz * vxy) / det;
    let c = (vyz * vxx - vxz * vxy) / det;
    let mut sum = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if ok[k] {
                let (x, y) = ((i as f64 - cx) * map.dx(), (j as f64 - cy) * map.dy());
                sum += (z[k] - mz - b * (x - mx) - c * (y - my)).powi(2);
            }
        }
    }
    let rise = (b * (nx - 1) as f64 * map.dx()).abs() + (c * (ny - 1) as f64 * map.dy()).abs();
    Some((b.hypot(c), rise, (sum / n).sqrt()))
}

/// The warnings on `map`'s slopes: steeper than a road's, or tilted.
fn slope_warnings(map: &HeightMap) -> Vec<String> {
    let mut warnings = Vec::new();
    if let Some(sdq) = rms_slope(map).filter(|s| *s > STEEPEST_ROAD_SDQ) {
        warnings.push(format!(
            "the RMS slope of the map (Sdq) is {sdq:.3e}: a road's is a few tenths (a tined \
             concrete's a few), and the half-space theory takes slopes as small; are the \
             heights and the spacing both in metres, or does the map hold spikes?"
        ));
    }
    if let Some((slope, rise, sq)) = best_plane(map)
        && slope > LEVEL_SLOPE
        && rise > TILT_SQS * sq
    {
        warnings.push(format!(
            "the map is tilted: its best-fit plane rises {} mm across it (slope {:.1} %), \
             more than {TILT_SQS} times its Sq about that plane ({} mm); the load goes to \
             the high edge. Level it (subtract the plane) if the tilt is the measurement's",
            readable3(rise * 1e3),
            slope * 100.0,
            readable3(sq * 1e3)
        ));
    }
    warnings
}

/// `map` with its "no data" markers ([`tyreroad_texture::find_sentinels`])
/// read as missing points, and a note for each marker (none: `map` as is).
pub(crate) fn markers_as_missing(
    map: HeightMap,
) -> Result<(HeightMap, Vec<String>), tyreroad_texture::TextureError> {
    let markers = tyreroad_texture::find_sentinels(&map);
    if markers.is_empty() {
        return Ok((map, Vec::new()));
    }
    let notes = markers
        .iter()
        .map(|s| {
            format!(
                "{} point(s) at {:e} m, a value repeated far outside the other heights (a \
                 \"no data\" marker), are read as missing points",
                s.points, s.value
            )
        })
        .collect();
    Ok((map.without_values(&markers)?, notes))
}

/// [`TextureSummary::warnings`] of `map`.
pub(crate) fn height_warnings(map: &HeightMap) -> Vec<String> {
    let mut z: Vec<f64> = map
        .heights()
        .iter()
        .zip(map.valid())
        .filter(|(_, ok)| **ok)
        .map(|(h, _)| *h)
        .collect();
    let mut warnings = Vec::new();
    if z.len() >= 100 {
        let n = z.len();
        let mut percentile = |q: usize| {
            *z.select_nth_unstable_by(q * (n - 1) / 100, f64::total_cmp)
                .1
        };
        let (low, high) = (percentile(1), percentile(99));
        let span = high - low;
        let (lo, hi) = (low - OUTLIER_SPANS * span, high + OUTLIER_SPANS * span);
        let outside: Vec<f64> = z.iter().copied().filter(|h| *h < lo || *h > hi).collect();
        if span == 0.0 && z.iter().any(|h| *h != low) {
            // Flat but for a few points (fewer than 2 %): no span to
            // measure them against, and nothing road-like about them.
            let odd: Vec<f64> = z.iter().copied().filter(|h| *h != low).collect();
            let worst = odd.iter().copied().fold(low, |w, h| {
                if (h - low).abs() > (w - low).abs() {
                    h
                } else {
                    w
                }
            });
            warnings.push(format!(
                "the map is flat at {low:e} m but for {} height(s), the farthest at {worst:e} m: \
                 sentinel values or spikes? give missing points as NaN (docs/texture.md)",
                odd.len()
            ));
        }
        if span > 0.0 && !outside.is_empty() {
            let beyond = |h: f64| (low - h).max(h - high);
            let worst = outside
                .iter()
                .copied()
                .fold(high, |w, h| if beyond(h) > beyond(w) { h } else { w });
            warnings.push(format!(
                "{} height(s) lie more than {OUTLIER_SPANS} times the span of the others \
                 ({:.3} mm, 1st to 99th percentile) outside it, the farthest at {worst:e} m: \
                 sentinel values or spikes? give missing points as NaN (docs/texture.md)",
                outside.len(),
                span * 1e3
            ));
        }
    }
    warnings.extend(missing_points_warning(
        map.valid_count(),
        map.heights().len(),
    ));
    warnings.extend(map.rms().and_then(roughness_warning));
    warnings.extend(spacing_warning(map.dx(), map.dy()));
    warnings.extend(slope_warnings(map));
    warnings
}

/// A warning when some of a map's `total` points are missing (`valid` hold
/// a height).
pub(crate) fn missing_points_warning(valid: usize, total: usize) -> Option<String> {
    (valid < total).then(|| {
        let missing = total - valid;
        format!(
            "{missing} of {total} points ({:.2} %) are missing (NaN or the format's marker): \
             asperities are segmented around them, so one crossed by missing points may be \
             split or lost (docs/texture.md)",
            100.0 * missing as f64 / total as f64
        )
    })
}

/// A warning when `sq` (m) is no road texture's roughness.
pub(crate) fn roughness_warning(sq: f64) -> Option<String> {
    (sq > LARGEST_ROAD_SQ).then(|| {
        let mm = readable3(sq * 1e3);
        format!(
            "Sq {mm} mm is no road texture's (a few millimetres at most): are the heights \
             in metres?"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine texture of 0.5 mm amplitude on 0.1 mm cells, some cells
    /// replaced by `cells` (index, height), one missing.
    fn texture(cells: &[(usize, f64)]) -> HeightMap {
        let mut z: Vec<f64> = (0..100 * 100)
            .map(|k| 0.5e-3 * ((k % 100) as f64 * 0.3).sin() * ((k / 100) as f64 * 0.2).cos())
            .collect();
        z[17] = f64::NAN;
        for &(k, h) in cells {
            z[k] = h;
        }
        HeightMap::from_nan_heights(100, 100, 1e-4, 1e-4, z).expect("a map")
    }

    #[test]
    fn sentinel_heights_and_a_roughness_in_another_unit_are_warned_of() {
        // The one missing point (z[17]) is counted, and nothing else said.
        let missing = "1 of 10000 points (0.01 %) are missing";
        let w = height_warnings(&texture(&[]));
        assert!(w.len() == 1 && w[0].starts_with(missing), "{w:?}");
        // A 3 mm bump on a 0.5 mm texture is a road's; 9999 m is not.
        assert_eq!(height_warnings(&texture(&[(500, 3e-3)])), w);
        let w = height_warnings(&texture(&[(500, 9999.0), (900, -9999.5)]));
        assert_eq!(w.len(), 4, "{w:?}");
        assert!(
            w[3].starts_with("the RMS slope of the map (Sdq) is 2.462e6"),
            "{w:?}"
        );
        assert!(
            w[0].starts_with("2 height(s)") && w[0].contains("-9.9995e3 m"),
            "{w:?}"
        );
        assert!(w[1].starts_with(missing), "{w:?}");
        assert!(w[2].contains("are the heights in metres"), "{w:?}");
        // Micrometres read as metres: every height 1e6 times too large.
        let scaled = texture(&[]);
        let um: Vec<f64> = scaled.heights().iter().map(|h| h * 1e6).collect();
        let w =
            height_warnings(&HeightMap::from_nan_heights(100, 100, 1e-4, 1e-4, um).expect("a map"));
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[1].starts_with("Sq "), "{w:?}");
        assert!(
            w[2].starts_with("the RMS slope of the map (Sdq) is 9.045e5"),
            "{w:?}"
        );
        // A flat map has no span to measure against: nothing said.
        let flat = HeightMap::new(10, 10, 1e-4, 1e-4, vec![0.0; 100]).expect("a map");
        assert!(height_warnings(&flat).is_empty());
        // Flat but for one spike (the 1st-99th percentile span is 0): found
        // by an adversarial run (2026-12-01), then said nothing.
        let mut spiked = vec![0.0; 1600];
        spiked[820] = 1.0;
        let spiked = HeightMap::new(40, 40, 5e-4, 5e-4, spiked).expect("a map");
        let w = height_warnings(&spiked);
        assert!(
            w[0].starts_with("the map is flat at 0e0 m but for 1 height(s), the farthest at 1e0 m"),
            "{w:?}"
        );
        // Tilted 20 % under bumps of 0.25 mm: the load goes to the high edge.
        let tilted: Vec<f64> = (0..1600)
            .map(|k| {
                let (i, j) = ((k % 40) as f64, (k / 40) as f64);
                0.2 * i * 5e-4 + 2.5e-4 * ((i * 0.785).cos() + (j * 0.785).cos())
            })
            .collect();
        let tilted = HeightMap::new(40, 40, 5e-4, 5e-4, tilted).expect("a map");
        let w = height_warnings(&tilted);
        assert!(
            // 20 % over the 19.5 mm between the first and last columns.
            w.len() == 1 && w[0].contains("the map is tilted") && w[0].contains("rises 3.900 mm"),
            "{w:?}"
        );
        // Heights in millimetres read as metres (a 0.25 mm texture as 250 mm):
        // slopes of hundreds.
        let mm: Vec<f64> = (0..1600)
            .map(|k| 0.25 * (((k % 40) as f64 * 0.785).cos() + ((k / 40) as f64 * 0.785).cos()))
            .collect();
        let w = height_warnings(&HeightMap::new(40, 40, 5e-4, 5e-4, mm.clone()).expect("a map"));
        assert!(w.iter().any(|w| w.contains("RMS slope")), "{w:?}");
        // The same map at 1e150 m: the squares of its slopes overflow, and
        // Sdq read "inf" (adversarial run, 2026-12-01); Sq prints in
        // scientific notation, not in 150 digits.
        let huge: Vec<f64> = mm.iter().map(|h| h * 4e150).collect();
        let w = height_warnings(&HeightMap::new(40, 40, 5e-4, 5e-4, huge).expect("a map"));
        let sdq = w
            .iter()
            .find(|w| w.contains("RMS slope"))
            .expect("an Sdq warning");
        assert!(sdq.contains("e153:") && !sdq.contains("inf"), "{sdq}");
        assert!(w.iter().any(|w| w.starts_with("Sq 9.998e152 mm")), "{w:?}");
        // An X3P's increment in millimetres read as metres (adversarial
        // run, 2026-12-01): the 0.25 mm map above at 0.25 m.
        let coarse: Vec<f64> = mm.iter().map(|h| h * 1e-3).collect();
        let w = height_warnings(&HeightMap::new(40, 40, 0.25, 0.25, coarse).expect("a map"));
        assert!(
            w.len() == 1 && w[0].starts_with("the map's spacing (dx 250.000 mm, dy 250.000 mm)"),
            "{w:?}"
        );
        let fine: Vec<f64> = mm.iter().map(|h| h * 1e-3).collect();
        assert!(
            height_warnings(&HeightMap::new(40, 40, 1e-3, 1e-3, fine).expect("a map")).is_empty()
        );
    }
}
