//! Plain-text height maps: the ASCII grid and xyz point lists.

use std::borrow::Cow;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::{TextureError, write_atomic};
use crate::heightmap::{HeightMap, MAX_POINTS, check_size};

const GRID: &str = "ASCII grid";
const XYZ: &str = "xyz";

/// Read an ASCII grid file (format: [`ascii_grid_from_str`]).
pub fn read_ascii_grid(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let s = tyreroad_core::read_input_text(path).map_err(|e| TextureError::io(path, e))?;
    ascii_grid_from_str(&s)
}

/// Parse an ASCII grid.
///
/// ```text
/// # comment lines start with '#', anywhere
/// nx 4            header: one "key value" per line, any order
/// ny 2
/// dx 1e-4         spacing along x (in metres, times `xy_scale`)
/// dy 1e-4
/// z_scale 1e-3    optional: factor from the file's heights to metres (default 1)
/// xy_scale 1      optional: factor from dx, dy to metres (default 1)
/// data            the word `data` ends the header
/// 0.1 0.2 0.3 0.4 ny rows of nx whitespace-separated heights, row j = y index j
/// 0.0 NaN 0.1 0.2 `NaN` (any case) or `*` marks a missing point
/// ```
///
/// Rows may be wrapped over several lines: the values are read in order,
/// exactly `nx·ny` of them. A header value takes no unit (`dx 0.5 mm` is
/// refused, not read as 0.5 m; a `#` comment may follow it), and lines
/// that are rows hold `nx` values: lines all longer than `nx`, or one line
/// off `nx` among rows of `nx`, are refused with the line's number.
pub fn ascii_grid_from_str(s: &str) -> Result<HeightMap, TextureError> {
    let text = text_lines(s);
    let mut lines = text.lines();
    let (mut nx, mut ny, mut dx, mut dy) = (None, None, None, None);
    let (mut zs, mut xys) = (1.0, 1.0);
    let num = |k: &str, v: Option<&str>| -> Result<f64, TextureError> {
        v.and_then(|v| v.parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .ok_or_else(|| TextureError::format(GRID, format!("header {k}: expected a number")))
    };
    let int = |k: &str, v: Option<&str>| -> Result<usize, TextureError> {
        v.and_then(|v| v.parse::<usize>().ok())
            .ok_or_else(|| TextureError::format(GRID, format!("header {k}: expected a size")))
    };
    let mut saw_data = false;
    let mut seen = std::collections::HashSet::new();
    for line in lines.by_ref() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut it = line.split_whitespace();
        let key = it.next().unwrap_or("").to_ascii_lowercase();
        let val = it.next();
        // "dx 0.5 mm" read as 0.5 m was a map a thousand times too wide.
        if matches!(
            key.as_str(),
            "nx" | "ny" | "dx" | "dy" | "z_scale" | "xy_scale"
        ) && let Some(extra) = it.next().filter(|t| !t.starts_with('#'))
        {
            return Err(TextureError::format(
                GRID,
                format!(
                    "header {key}: one value expected, then {extra:?}: header values are bare \
                     numbers (spacings in metres; xy_scale and z_scale convert other units)"
                ),
            ));
        }
        // A key given twice would silently keep its last value.
        if key != "data" && !seen.insert(key.clone()) {
            return Err(TextureError::format(
                GRID,
                format!("header key {key:?} is given twice"),
            ));
        }
        match key.as_str() {
            "nx" => nx = Some(int("nx", val)?),
            "ny" => ny = Some(int("ny", val)?),
            "dx" => dx = Some(num("dx", val)?),
            "dy" => dy = Some(num("dy", val)?),
            "z_scale" => zs = num("z_scale", val)?,
            "xy_scale" => xys = num("xy_scale", val)?,
            "data" => {
                saw_data = true;
                break;
            }
            // Heights where a key should be: the header's last line is missing.
            other if other.parse::<f64>().is_ok() => {
                return Err(TextureError::format(
                    GRID,
                    format!(
                        "a number ({other}) where a header key was expected: is the `data` line \
                         that ends the header missing?"
                    ),
                ));
            }
            other => {
                return Err(TextureError::format(
                    GRID,
                    format!(
                        "unknown header key {other:?} (nx, ny, dx, dy, z_scale, xy_scale, data)"
                    ),
                ));
            }
        }
    }
    if !saw_data {
        return Err(TextureError::format(GRID, "no `data` line ends the header"));
    }
    // A zero or negative scale would flatten or mirror the map silently.
    for (k, v) in [("z_scale", zs), ("xy_scale", xys)] {
        if v <= 0.0 {
            return Err(TextureError::format(
                GRID,
                format!("header {k} = {v}: expected a factor > 0"),
            ));
        }
    }
    let missing = |k| TextureError::format(GRID, format!("header has no {k}"));
    let (nx, ny) = (
        nx.ok_or_else(|| missing("nx"))?,
        ny.ok_or_else(|| missing("ny"))?,
    );
    let (dx, dy) = (
        dx.ok_or_else(|| missing("dx"))?,
        dy.ok_or_else(|| missing("dy"))?,
    );
    let n = check_size(nx, ny).map_err(|e| TextureError::format(GRID, e.to_string()))?;
    let mut h = Vec::new();
    // Values per data line, with the line's number in the file, to tell a
    // wrapped row from rows of the wrong length.
    let mut line_counts: Vec<(usize, usize)> = Vec::new();
    let header_lines = text.lines().count() - lines.clone().count();
    for (k, line) in lines.enumerate() {
        let line = line.trim();
        if line.starts_with('#') {
            continue;
        }
        let before = h.len();
        for tok in line.split_whitespace() {
            if h.len() == n {
                return Err(TextureError::format(
                    GRID,
                    format!("more than nx·ny = {n} values"),
                ));
            }
            let v = if tok == "*" || tok.eq_ignore_ascii_case("nan") {
                f64::NAN
            } else {
                let v: f64 = tok
                    .parse()
                    .map_err(|_| TextureError::format(GRID, format!("{tok:?} is not a number")))?;
                if !v.is_finite() {
                    return Err(TextureError::format(GRID, format!("{tok:?} is not finite")));
                }
                v * zs
            };
            h.push(v);
        }
        if h.len() > before {
            line_counts.push((header_lines + k + 1, h.len() - before));
        }
    }
    if h.len() != n {
        return Err(TextureError::format(
            GRID,
            format!("{} values for nx·ny = {n}", h.len()),
        ));
    }
    check_rows(&line_counts, nx)?;
    HeightMap::from_nan_heights(nx, ny, dx * xys, dy * xys, h)
        .map_err(|e| TextureError::format(GRID, e.to_string()))
}

/// Rows may wrap over several lines, but lines that are rows must be rows
/// of `nx`: every line longer than `nx` (a grid written with nx and ny
/// swapped read as a scrambled map), or one line off `nx` among lines of
/// `nx` (a value missing in one row and one too many in another shifted
/// every row between), is refused, naming the line.
fn check_rows(line_counts: &[(usize, usize)], nx: usize) -> Result<(), TextureError> {
    if let Some(&(line, count)) = line_counts.iter().find(|(_, c)| *c > nx)
        && line_counts.iter().all(|(_, c)| *c == count)
    {
        return Err(TextureError::format(
            GRID,
            format!(
                "every data line holds {count} values but nx = {nx} (line {line}): are nx and ny \
                 swapped?"
            ),
        ));
    }
    let rows = line_counts.iter().filter(|(_, c)| *c == nx).count();
    if rows * 2 > line_counts.len()
        && let Some(&(line, count)) = line_counts.iter().find(|(_, c)| *c != nx)
    {
        return Err(TextureError::format(
            GRID,
            format!("line {line} holds {count} values where the other rows hold nx = {nx}"),
        ));
    }
    Ok(())
}

/// The ASCII grid text of `map` (metres, `NaN` for missing points, 17
/// significant digits: a lossless round trip).
pub fn ascii_grid_to_string(map: &HeightMap) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# tyreroad height map: heights in metres, row j = y index"
    );
    let _ = writeln!(
        s,
        "nx {}\nny {}\ndx {:e}\ndy {:e}\ndata",
        map.nx(),
        map.ny(),
        map.dx(),
        map.dy()
    );
    for j in 0..map.ny() {
        let row: Vec<String> = (0..map.nx())
            .map(|i| match map.get(i, j) {
                Some(h) => format!("{h:e}"),
                None => "NaN".into(),
            })
            .collect();
        let _ = writeln!(s, "{}", row.join(" "));
    }
    s
}

/// Write an ASCII grid file (whole or not at all).
pub fn write_ascii_grid(map: &HeightMap, path: impl AsRef<Path>) -> Result<(), TextureError> {
    write_atomic(path.as_ref(), ascii_grid_to_string(map).as_bytes())
}

/// Read an xyz file (format: [`xyz_from_str`]).
pub fn read_xyz(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let s = tyreroad_core::read_input_text(path).map_err(|e| TextureError::io(path, e))?;
    xyz_from_str(&s)
}

/// Parse an xyz point list on a regular grid.
///
/// One point per line, `x y z` in metres separated by whitespace, commas or
/// semicolons; `#` lines and a first line that does not parse (a header) are
/// skipped. The grid is recovered from the points: `dx` (`dy`) is the
/// smallest gap between distinct x (y) values; every point must then lie on
/// `x₀ + i·dx` within 1 % of `dx`. Grid points without a line, and points
/// whose z is `NaN`, are missing. A duplicated grid point is an error, and
/// so is a grid more than 64 times larger than the point count.
pub fn xyz_from_str(s: &str) -> Result<HeightMap, TextureError> {
    let s = text_lines(s);
    let mut pts: Vec<[f64; 3]> = Vec::new();
    for (ln, line) in s.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let toks: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|t| !t.is_empty())
            .collect();
        let vals: Option<Vec<f64>> = toks.iter().map(|t| t.parse::<f64>().ok()).collect();
        match vals {
            Some(v) if v.len() == 3 => {
                if !(v[0].is_finite() && v[1].is_finite()) || v[2].is_infinite() {
                    return Err(TextureError::format(
                        XYZ,
                        format!("line {}: non-finite coordinate", ln + 1),
                    ));
                }
                pts.push([v[0], v[1], v[2]]);
            }
            _ if pts.is_empty() && ln == 0 => continue,
            _ => {
                return Err(TextureError::format(
                    XYZ,
                    format!("line {}: expected three numbers `x y z`", ln + 1),
                ));
            }
        }
    }
    if pts.is_empty() {
        return Err(TextureError::format(XYZ, "no point"));
    }
    let axis = |c: usize| -> Result<(f64, f64, usize), TextureError> {
        let mut v: Vec<f64> = pts.iter().map(|p| p[c]).collect();
        v.sort_by(f64::total_cmp);
        let (lo, hi) = (v[0], v[v.len() - 1]);
        let span = hi - lo;
        // Gaps under the coordinates' own rounding are one grid line;
        // georeferenced coordinates (x ≈ 4e5 m at a 0.1 mm step) resolve
        // their step although it is 1e-10 of their size.
        let rounding = 64.0 * f64::EPSILON * lo.abs().max(hi.abs());
        let tol = (1e-9 * span.abs()).max(rounding).max(1e-300);
        let step = v
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|d| *d > tol)
            .fold(f64::INFINITY, f64::min);
        if !step.is_finite() {
            return Ok((lo, 1.0, 1));
        }
        let n = (span / step).round() + 1.0;
        if !(n.is_finite() && n <= MAX_POINTS as f64) {
            return Err(TextureError::format(XYZ, "grid too large"));
        }
        // The whole span over its steps: the smallest gap alone carries
        // the rounding of two printed coordinates (2e-6 of a 0.1 mm step
        // at y ≈ 5.6e6 m).
        Ok((lo, span / (n - 1.0).max(1.0), n as usize))
    };
    let (x0, dx, nx) = axis(0)?;
    let (y0, dy, ny) = axis(1)?;
    let (dx, dy) = match (nx, ny) {
        (1, 1) => {
            return Err(TextureError::format(
                XYZ,
                "every point is at one (x, y): a height map needs at least two grid points",
            ));
        }
        (1, _) => (dy, dy),
        (_, 1) => (dx, dx),
        _ => (dx, dy),
    };
    // The fill first: points off a regular grid (jittered by a few µm, or
    // rounded unevenly) make the smallest gap a fraction of the spacing and
    // the grid absurdly large, which the size check would say as "exceeds".
    if (nx as f64 * ny as f64) / 64.0 > pts.len() as f64 {
        return Err(TextureError::format(
            XYZ,
            format!(
                "{} points do not fill a {nx} × {ny} grid: the smallest gaps between their \
                 coordinates (dx = {dx:e}, dy = {dy:e} m) are not the spacing; are the points \
                 off a regular grid (jittered or unevenly rounded)?",
                pts.len()
            ),
        ));
    }
    let n = check_size(nx, ny).map_err(|e| TextureError::format(XYZ, e.to_string()))?;
    let mut h = vec![f64::NAN; n];
    let mut seen = vec![false; n];
    for p in &pts {
        let fi = (p[0] - x0) / dx;
        let fj = (p[1] - y0) / dy;
        let (i, j) = (fi.round(), fj.round());
        if (fi - i).abs() > 0.01 || (fj - j).abs() > 0.01 {
            return Err(TextureError::format(
                XYZ,
                format!(
                    "point ({}, {}) is not on the grid dx = {dx}, dy = {dy}",
                    p[0], p[1]
                ),
            ));
        }
        let k = j as usize * nx + i as usize;
        if k >= n || seen[k] {
            return Err(TextureError::format(
                XYZ,
                format!("point ({}, {}) appears twice", p[0], p[1]),
            ));
        }
        seen[k] = true;
        h[k] = p[2];
    }
    HeightMap::from_nan_heights(nx, ny, dx, dy, h)
        .map_err(|e| TextureError::format(XYZ, e.to_string()))
}

/// The xyz text of `map`: one `x y z` line per valid point (metres).
pub fn xyz_to_string(map: &HeightMap) -> String {
    let mut s = String::from("# x_m y_m z_m\n");
    for j in 0..map.ny() {
        for i in 0..map.nx() {
            if let Some(h) = map.get(i, j) {
                let _ = writeln!(
                    s,
                    "{:e} {:e} {h:e}",
                    i as f64 * map.dx(),
                    j as f64 * map.dy()
                );
            }
        }
    }
    s
}

/// Write an xyz file (whole or not at all).
pub fn write_xyz(map: &HeightMap, path: impl AsRef<Path>) -> Result<(), TextureError> {
    write_atomic(path.as_ref(), xyz_to_string(map).as_bytes())
}

/// `s` without a leading UTF-8 byte-order mark (editors and spreadsheet
/// exports on Windows write one; it is not part of the first key).
pub(crate) fn without_bom(s: &str) -> &str {
    s.strip_prefix('\u{feff}').unwrap_or(s)
}

/// `s` [`without_bom`], its lines ended as `str::lines` reads them: text
/// from classic Mac OS (and some instruments' exports) ends its lines with
/// CR alone, which `lines` would read as one line (an ASCII grid then said
/// "no `data` line ends the header").
fn text_lines(s: &str) -> Cow<'_, str> {
    let s = without_bom(s);
    if s.contains('\r') && !s.contains('\n') {
        Cow::Owned(s.replace('\r', "\n"))
    } else {
        Cow::Borrowed(s)
    }
}
