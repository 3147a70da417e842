//! Indenter layouts, the film frame, and matching prints to indenters.

use std::path::Path;

use crate::analysis::Detection;
use tyreroad_core::Grid;

use crate::error::{FilmError, Result};

/// One indenter: its number and expected position (m) in the film frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Indenter {
    /// Indenter number.
    pub number: u32,
    /// Position x, m.
    pub x: f64,
    /// Position y, m.
    pub y: f64,
}

/// A set of indenters with distinct numbers and positions.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    indenters: Vec<Indenter>,
}

impl Layout {
    /// Checks and builds a layout: at least one indenter, finite positions,
    /// distinct numbers and distinct positions.
    pub fn new(indenters: Vec<Indenter>) -> Result<Self> {
        if indenters.is_empty() {
            return Err(FilmError::LayoutMismatch("empty layout".into()));
        }
        for (k, a) in indenters.iter().enumerate() {
            if !(a.x.is_finite() && a.y.is_finite()) {
                return Err(FilmError::LayoutMismatch(format!(
                    "indenter {} has a non-finite position",
                    a.number
                )));
            }
            for b in &indenters[..k] {
                if a.number == b.number {
                    return Err(FilmError::LayoutMismatch(format!(
                        "indenter number {} appears twice",
                        a.number
                    )));
                }
                if a.x == b.x && a.y == b.y {
                    return Err(FilmError::LayoutMismatch(format!(
                        "indenters {} and {} share a position",
                        b.number, a.number
                    )));
                }
            }
        }
        Ok(Self { indenters })
    }

    /// The paper's 25 balls: a 5 × 5 grid at `pitch` (10 mm in the paper)
    /// centred on the origin, numbered in a snake from 1 at `(2p, −2p)` along
    /// the row to 5 at `(−2p, −2p)`, then 6 at `(−2p, −p)` back to 10 at
    /// `(2p, −p)`, and so on up to 25 at `(−2p, 2p)` (Cesbron et al. 2006, section 3).
    pub fn paper_grid(pitch: f64) -> Self {
        let mut v = Vec::with_capacity(25);
        for row in 0..5 {
            let y = (row as f64 - 2.0) * pitch;
            for k in 0..5 {
                let col = if row % 2 == 0 { 4 - k } else { k };
                v.push(Indenter {
                    number: (row * 5 + k + 1) as u32,
                    x: (col as f64 - 2.0) * pitch,
                    y,
                });
            }
        }
        Self { indenters: v }
    }

    /// Parses a layout CSV: `#` comments, header exactly `indenter,x_m,y_m`,
    /// one row per indenter.
    pub fn parse_csv(text: &str, source: &Path) -> Result<Self> {
        let csv_err = |line: usize, message: String| FilmError::Csv {
            path: source.to_path_buf(),
            line,
            message,
        };
        let mut header = false;
        let mut v = Vec::new();
        for (n, line) in crate::data_lines(text) {
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            if !header {
                if cols != ["indenter", "x_m", "y_m"] {
                    return Err(csv_err(
                        n + 1,
                        "expected header \"indenter,x_m,y_m\"".into(),
                    ));
                }
                header = true;
                continue;
            }
            if cols.len() != 3 {
                return Err(csv_err(
                    n + 1,
                    format!("expected 3 columns, got {}", cols.len()),
                ));
            }
            let number: u32 = cols[0]
                .parse()
                .map_err(|_| csv_err(n + 1, format!("bad indenter number {:?}", cols[0])))?;
            let num = |s: &str| -> Result<f64> {
                s.parse()
                    .map_err(|_| csv_err(n + 1, format!("not a number: {s:?}")))
            };
            v.push(Indenter {
                number,
                x: num(cols[1])?,
                y: num(cols[2])?,
            });
        }
        if !header {
            return Err(csv_err(0, "no header line".into()));
        }
        Self::new(v)
    }

    /// Reads a layout CSV file ([`Layout::parse_csv`]).
    pub fn read_csv(path: &Path) -> Result<Self> {
        let text = tyreroad_core::read_input_text(path).map_err(|reason| FilmError::Io {
            path: path.to_path_buf(),
            reason,
        })?;
        Self::parse_csv(&text, path)
    }

    /// The indenters.
    pub fn indenters(&self) -> &[Indenter] {
        &self.indenters
    }

    /// Smallest distance between two indenters (`∞` for one indenter).
    pub fn min_spacing(&self) -> f64 {
        let mut d = f64::INFINITY;
        for (k, a) in self.indenters.iter().enumerate() {
            for b in &self.indenters[..k] {
                d = d.min((a.x - b.x).hypot(a.y - b.y));
            }
        }
        d
    }
}

/// The film frame of a scan: pixel coordinates `(col, row)` (continuous,
/// the centre of pixel `(i, j)` at `(i + 0.5, j + 0.5)`, rows going down)
/// map to film coordinates in metres, x to the right and y up:
///
/// ```text
/// x = (col − origin_col) · s,    y = (origin_row − row) · s
/// ```
///
/// A film scanned face down is mirrored: flip the image before analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Pixel size `s`, m.
    pub pixel_size: f64,
    /// Column of the film origin (continuous pixel coordinate).
    pub origin_col: f64,
    /// Row of the film origin (continuous pixel coordinate).
    pub origin_row: f64,
}

impl Frame {
    /// The frame of a scan rendered from a pressure map on `grid` (see
    /// [`crate::render`]): image row `r` holds the grid's row `ny − 1 − r`,
    /// so the top edge of the image is the grid's top edge
    /// `y = y0 + (ny − ½)·s` and its left edge `x = x0 − ½·s`, where
    /// `(x0, y0)` is the centre of the grid's cell `(0, 0)`.
    ///
    /// # Errors
    /// [`FilmError::InvalidPressureMap`] if the grid's cells are not square
    /// (`dx ≠ dy`): a scan has one pixel size.
    pub fn of_grid(grid: &Grid) -> Result<Self> {
        let s = square_pixel_size(grid)?;
        let [x0, y0] = grid.origin();
        Ok(Self {
            pixel_size: s,
            origin_col: 0.5 - x0 / s,
            origin_row: y0 / s + grid.ny() as f64 - 0.5,
        })
    }

    /// The film origin as an [`Origin`] for [`match_layout`].
    pub fn origin(&self) -> Origin {
        Origin::Pixel {
            col: self.origin_col,
            row: self.origin_row,
        }
    }

    /// Film coordinates (m) of a pixel position.
    pub fn to_film(&self, col: f64, row: f64) -> (f64, f64) {
        (
            (col - self.origin_col) * self.pixel_size,
            (self.origin_row - row) * self.pixel_size,
        )
    }

    /// Pixel position of film coordinates (m).
    pub fn to_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.origin_col + x / self.pixel_size,
            self.origin_row - y / self.pixel_size,
        )
    }
}

/// Where the film origin lies in the scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Origin {
    /// Given, in continuous pixel coordinates.
    Pixel {
        /// Column.
        col: f64,
        /// Row.
        row: f64,
    },
    /// Estimated: the centroid of the prints is put on the centroid of the
    /// layout, then refined on the matched prints. A one-indenter layout
    /// has no geometry to place: on a scan of several prints it needs the
    /// origin given.
    Centroid,
}

/// One indenter matched to its print.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Match {
    /// The indenter.
    pub indenter: Indenter,
    /// Index of its print in [`Detection::prints`].
    pub print: usize,
    /// Print centroid in the film frame, m.
    pub centroid: (f64, f64),
    /// Distance from the expected position, m.
    pub distance: f64,
}

/// Prints matched to a layout.
#[derive(Debug, Clone, PartialEq)]
pub struct Matching {
    /// The film frame used.
    pub frame: Frame,
    /// One match per indenter, in layout order.
    pub matches: Vec<Match>,
    /// Prints matched to no indenter (specks, stray marks).
    pub unmatched_prints: Vec<usize>,
}

/// Matches each indenter of `layout` to the nearest print within
/// `tolerance` (m; default 0.4 × the layout's smallest spacing). Errors:
/// [`FilmError::PrintNotFound`] when an indenter has no print near it,
/// [`FilmError::LayoutMismatch`] when two indenters claim the same print or
/// there are fewer prints than indenters, [`FilmError::AmbiguousMatch`] for
/// a one-indenter layout on several prints with [`Origin::Centroid`].
pub fn match_layout(
    detection: &Detection,
    layout: &Layout,
    origin: Origin,
    tolerance: Option<f64>,
) -> Result<Matching> {
    let s = detection.pixel_size;
    let tol = tolerance.unwrap_or_else(|| 0.4 * layout.min_spacing());
    if tol.is_nan() || tol <= 0.0 {
        return Err(FilmError::InvalidParameter {
            name: "matching tolerance",
            value: tol,
            requirement: "> 0",
        });
    }
    let ind = layout.indenters();
    // One indenter fixes no geometry: put on the prints' centroid, it
    // would take whichever print lies nearest it, a coin toss between two.
    if let ([only], Origin::Centroid) = (ind, origin)
        && detection.prints.len() > 1
    {
        return Err(FilmError::AmbiguousMatch {
            indenter: only.number,
            prints: detection.prints.len(),
        });
    }
    if detection.prints.len() < ind.len() {
        return Err(FilmError::LayoutMismatch(format!(
            "{} indenters in the layout but only {} prints in the scan",
            ind.len(),
            detection.prints.len()
        )));
    }
    let mut frame = match origin {
        Origin::Pixel { col, row } => Frame {
            pixel_size: s,
            origin_col: col,
            origin_row: row,
        },
        Origin::Centroid => {
            let np = detection.prints.len() as f64;
            let (mc, mr) = detection.prints.iter().fold((0.0, 0.0), |(a, b), p| {
                (a + p.centroid_px.0 / np, b + p.centroid_px.1 / np)
            });
            let ni = ind.len() as f64;
            let (mx, my) = ind
                .iter()
                .fold((0.0, 0.0), |(a, b), i| (a + i.x / ni, b + i.y / ni));
            Frame {
                pixel_size: s,
                origin_col: mc - mx / s,
                origin_row: mr + my / s,
            }
        }
    };
    let mut result = assign(detection, ind, &frame, tol);
    if origin == Origin::Centroid {
        // Refine the offset on the matched prints (robust to stray prints
        // that pulled the first centroid), then match again.
        if let Ok(ms) = &result {
            let n = ms.len() as f64;
            let (dc, dr) = ms.iter().fold((0.0, 0.0), |(a, b), m| {
                let p = &detection.prints[m.print];
                let (ec, er) = frame.to_pixel(m.indenter.x, m.indenter.y);
                (
                    a + (p.centroid_px.0 - ec) / n,
                    b + (p.centroid_px.1 - er) / n,
                )
            });
            frame.origin_col += dc;
            frame.origin_row += dr;
            result = assign(detection, ind, &frame, tol);
        }
    }
    let matches = result?;
    let mut used = vec![false; detection.prints.len()];
    for m in &matches {
        used[m.print] = true;
    }
    let unmatched_prints = (0..used.len()).filter(|&k| !used[k]).collect();
    Ok(Matching {
        frame,
        matches,
        unmatched_prints,
    })
}

fn assign(detection: &Detection, ind: &[Indenter], frame: &Frame, tol: f64) -> Result<Vec<Match>> {
    let mut owner: Vec<Option<u32>> = vec![None; detection.prints.len()];
    let mut out = Vec::with_capacity(ind.len());
    for i in ind {
        let mut best: Option<(usize, f64, (f64, f64))> = None;
        for (k, p) in detection.prints.iter().enumerate() {
            let c = frame.to_film(p.centroid_px.0, p.centroid_px.1);
            let d = (c.0 - i.x).hypot(c.1 - i.y);
            if best.is_none_or(|(_, bd, _)| d < bd) {
                best = Some((k, d, c));
            }
        }
        match best {
            Some((k, d, c)) if d <= tol => {
                if let Some(other) = owner[k] {
                    return Err(FilmError::LayoutMismatch(format!(
                        "indenters {other} and {} both match the print at ({:.4e}, {:.4e}) m",
                        i.number, c.0, c.1
                    )));
                }
                owner[k] = Some(i.number);
                out.push(Match {
                    indenter: *i,
                    print: k,
                    centroid: c,
                    distance: d,
                });
            }
            _ => {
                return Err(FilmError::PrintNotFound {
                    indenter: i.number,
                    x_m: i.x,
                    y_m: i.y,
                    tolerance_m: tol,
                    scale_hint: scale_hint(detection, ind),
                });
            }
        }
    }
    Ok(out)
}

/// Median distance to the nearest other point (None below two points).
fn median_nearest(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let mut nearest: Vec<f64> = points
        .iter()
        .enumerate()
        .map(|(k, a)| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != k)
                .map(|(_, b)| (a.0 - b.0).hypot(a.1 - b.1))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    nearest.sort_by(f64::total_cmp);
    Some(nearest[nearest.len() / 2])
}

/// When an indenter finds no print, says whether the scale is the likely
/// cause: the prints' median nearest-neighbour spacing (at the scan's pixel
/// size) more than 20 % off the indenters'. A wrong dpi moves every print
/// but the first, which a bare "print not found" does not suggest.
fn scale_hint(detection: &Detection, ind: &[Indenter]) -> String {
    let s = detection.pixel_size;
    let prints: Vec<(f64, f64)> = detection
        .prints
        .iter()
        .map(|p| (p.centroid_px.0 * s, p.centroid_px.1 * s))
        .collect();
    let indenters: Vec<(f64, f64)> = ind.iter().map(|i| (i.x, i.y)).collect();
    let (Some(printed), Some(laid)) = (median_nearest(&prints), median_nearest(&indenters)) else {
        return String::new();
    };
    let ratio = printed / laid;
    if (0.8..=1.25).contains(&ratio) || !ratio.is_finite() {
        return String::new();
    }
    format!(
        "; at the pixel size {s:.4e} m the prints are {printed:.3e} m apart, the layout's \
         indenters {laid:.3e} m ({ratio:.3}×): the pixel size (dpi) is likely wrong, by a \
         factor {:.3} (or the layout's pitch is)",
        1.0 / ratio
    )
}

/// Detects a rectangular grid in the prints: rows are split where the
/// sorted vertical positions jump by more than half the median
/// nearest-neighbour distance; each row is sorted by x. Prints are numbered
/// row-major from the top-left (1, 2, … along the top row), positions taken
/// from their centroids relative to the centroid of all prints (y up). Every
/// row must hold the same number of prints, else
/// [`FilmError::LayoutMismatch`].
pub fn detect_grid(detection: &Detection) -> Result<Layout> {
    let s = detection.pixel_size;
    let n = detection.prints.len();
    if n == 0 {
        return Err(FilmError::LayoutMismatch("no prints".into()));
    }
    let pts: Vec<(f64, f64)> = detection
        .prints
        .iter()
        .map(|p| (p.centroid_px.0 * s, -p.centroid_px.1 * s))
        .collect();
    let mut nn: Vec<f64> = pts
        .iter()
        .enumerate()
        .map(|(k, a)| {
            pts.iter()
                .enumerate()
                .filter(|&(j, _)| j != k)
                .map(|(_, b)| (a.0 - b.0).hypot(a.1 - b.1))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    nn.sort_by(f64::total_cmp);
    let gap = 0.5 * nn[n / 2];
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| pts[b].1.total_cmp(&pts[a].1)); // top first
    let mut rows: Vec<Vec<usize>> = vec![vec![order[0]]];
    for w in order.windows(2) {
        if pts[w[0]].1 - pts[w[1]].1 > gap {
            rows.push(Vec::new());
        }
        if let Some(r) = rows.last_mut() {
            r.push(w[1]);
        }
    }
    let per_row = rows[0].len();
    if rows.iter().any(|r| r.len() != per_row) {
        return Err(FilmError::LayoutMismatch(format!(
            "prints do not form a grid: rows of {:?} prints",
            rows.iter().map(Vec::len).collect::<Vec<_>>()
        )));
    }
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(a, b), p| {
        (a + p.0 / n as f64, b + p.1 / n as f64)
    });
    let mut v = Vec::with_capacity(n);
    for r in &mut rows {
        r.sort_by(|&a, &b| pts[a].0.total_cmp(&pts[b].0));
        for &k in r.iter() {
            v.push(Indenter {
                number: v.len() as u32 + 1,
                x: pts[k].0 - mx,
                y: pts[k].1 - my,
            });
        }
    }
    Layout::new(v)
}

/// The pixel side of a pressure map's grid, whose cells must be square: a
/// scan and its frame have one pixel size.
pub(crate) fn square_pixel_size(grid: &Grid) -> Result<f64> {
    if grid.dx() == grid.dy() {
        Ok(grid.dx())
    } else {
        Err(FilmError::InvalidPressureMap(format!(
            "pixels must be square, got dx = {} m, dy = {} m",
            grid.dx(),
            grid.dy()
        )))
    }
}
