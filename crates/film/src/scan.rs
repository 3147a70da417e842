//! Scanned films: reading PNG and TIFF (8 or 16 bit, grey or RGB), the
//! channel analysed, and the pixel size.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::{DynamicImage, ImageFormat};

use crate::error::{FilmError, Result, check_positive};

/// Smallest pixel size of a scan, m (10 nm: below the optical resolution of
/// any scanner or microscope). Smaller, the pixel area underflows and
/// the unit is likely wrong.
pub const MIN_PIXEL_SIZE: f64 = 1e-8;

/// Largest pixel size of a scan, m (10 mm, 2.54 dpi: a print a few
/// millimetres wide would not fill one pixel). Larger, areas and forces
/// grow absurd (to infinity at 1e300 m) and the unit is likely wrong.
pub const MAX_PIXEL_SIZE: f64 = 1e-2;

/// The pixel size if it lies in [`MIN_PIXEL_SIZE`]–[`MAX_PIXEL_SIZE`].
fn check_pixel_size(pixel_size: f64) -> Result<f64> {
    check_positive("pixel size", pixel_size)?;
    if !(MIN_PIXEL_SIZE..=MAX_PIXEL_SIZE).contains(&pixel_size) {
        return Err(FilmError::InvalidParameter {
            name: "pixel size",
            value: pixel_size,
            requirement: "between 1e-8 m and 1e-2 m (10 nm to 10 mm): in metres, not µm or mm",
        });
    }
    Ok(pixel_size)
}

/// Which channel of a colour scan is analysed.
///
/// Prescale prints are magenta. A magenta dye absorbs green light (roughly
/// 500–570 nm) and reflects red and blue, so as the colour density grows the
/// green channel darkens most while red and blue barely change: the green
/// channel carries nearly all of the signal and has the widest dynamic range.
/// [`Channel::Auto`] therefore uses green for RGB scans and the single
/// channel of grey scans (a grey scan of a magenta print is a weighted mix in
/// which green dominates as well). Alpha is ignored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Channel {
    /// Green for colour images, the grey channel for grey images.
    #[default]
    Auto,
    /// The red channel (grey channel for grey images).
    Red,
    /// The green channel (grey channel for grey images).
    Green,
    /// The blue channel (grey channel for grey images).
    Blue,
    /// Luma, Rec. 709 weights `0.2126 R + 0.7152 G + 0.0722 B`.
    Luma,
}

/// A scanned film: one channel as normalised grey levels in `[0, 1]`
/// (0 = black, 1 = full scale), row-major from the top-left pixel, and the
/// pixel size when known.
#[derive(Debug, Clone, PartialEq)]
pub struct Scan {
    width: usize,
    height: usize,
    grey: Vec<f32>,
    pixel_size: Option<f64>,
    bit_depth: u8,
}

impl Scan {
    /// A scan from normalised grey levels (row-major, `width × height`
    /// values). `bit_depth` is the quantisation of the source (8, 16, or 32
    /// for floating point), used only for reporting and histogram bins.
    ///
    /// Errors: a length that is not `width × height`, or a grey level that
    /// is not finite or lies outside `[0, 1]` ([`FilmError::Image`], naming
    /// the pixel: a grey of −1 would read as a print darker than black, a
    /// saturated one); a bit depth outside 1–32, or a pixel size outside
    /// [`MIN_PIXEL_SIZE`]–[`MAX_PIXEL_SIZE`]
    /// ([`FilmError::InvalidParameter`]).
    pub fn from_grey(
        width: usize,
        height: usize,
        grey: Vec<f32>,
        pixel_size: Option<f64>,
        bit_depth: u8,
    ) -> Result<Self> {
        let image_err = |message: String| FilmError::Image {
            path: PathBuf::from("<memory>"),
            message,
        };
        if width == 0 || height == 0 || width.checked_mul(height) != Some(grey.len()) {
            return Err(image_err(format!(
                "{} grey values for a {width} × {height} image",
                grey.len()
            )));
        }
        if let Some(k) = grey.iter().position(|g| !(0.0..=1.0).contains(g)) {
            return Err(image_err(format!(
                "grey level {} at pixel (col {}, row {}): normalised grey levels are finite \
                 and in [0, 1] (divide 8-bit values by 255, 16-bit ones by 65535)",
                crate::error::readable(crate::error::widen(grey[k])),
                k % width,
                k / width
            )));
        }
        if !(1..=32).contains(&bit_depth) {
            return Err(FilmError::InvalidParameter {
                name: "bit depth",
                value: bit_depth as f64,
                requirement: "1 to 32 bits (8 or 16 for integer scans, 32 for floating point)",
            });
        }
        if let Some(s) = pixel_size {
            check_pixel_size(s)?;
        }
        Ok(Self {
            width,
            height,
            grey,
            pixel_size,
            bit_depth,
        })
    }

    /// Reads a PNG or TIFF file (format from its content), taking `channel`.
    /// The pixel size comes from the file's resolution (PNG `pHYs` in pixels
    /// per metre, TIFF `XResolution`/`ResolutionUnit` in inch or cm) when it
    /// has one; override it with [`Scan::with_pixel_size`] or
    /// [`Scan::with_dpi`]. A file whose x and y resolutions differ is refused
    /// ([`FilmError::Image`], "non-square pixels"): the model has one pixel
    /// size, and reading it as square would stretch every print.
    pub fn open(path: &Path, channel: Channel) -> Result<Self> {
        let bytes = tyreroad_core::read_input_file(path).map_err(|reason| FilmError::Io {
            path: path.to_path_buf(),
            reason,
        })?;
        Self::decode(&bytes, channel, path)
    }

    /// Decodes an in-memory PNG or TIFF (`source` names it in errors).
    pub fn decode(bytes: &[u8], channel: Channel, source: &Path) -> Result<Self> {
        let img_err = |message: String| FilmError::Image {
            path: source.to_path_buf(),
            message,
        };
        let format = image::guess_format(bytes).map_err(|e| img_err(e.to_string()))?;
        let pixel_size = match format {
            ImageFormat::Png => png_pixel_size(bytes).map_err(img_err)?,
            ImageFormat::Tiff => tiff_pixel_size(bytes).map_err(img_err)?,
            other => {
                return Err(img_err(format!(
                    "unsupported format {other:?} (PNG or TIFF expected)"
                )));
            }
        };
        let img = image::load_from_memory_with_format(bytes, format)
            .map_err(|e| img_err(decode_message(&e)))?;
        let (grey, bit_depth) = extract_channel(&img, channel).map_err(img_err)?;
        // Software that knows no resolution writes 1 dpi or 1 pixel per
        // metre: read as unknown, so the user is asked for the DPI instead
        // of the file being refused for a pixel size they would override.
        let pixel_size = pixel_size.filter(|&s| check_pixel_size(s).is_ok());
        let (w, h) = (img.width() as usize, img.height() as usize);
        Self::from_grey(w, h, grey, pixel_size, bit_depth).map_err(|e| match e {
            FilmError::Image { message, .. } => img_err(message),
            other => other,
        })
    }

    /// Sets the pixel size (m), between [`MIN_PIXEL_SIZE`] and
    /// [`MAX_PIXEL_SIZE`] (else [`FilmError::InvalidParameter`]).
    pub fn with_pixel_size(mut self, pixel_size: f64) -> Result<Self> {
        self.pixel_size = Some(check_pixel_size(pixel_size)?);
        Ok(self)
    }

    /// Sets the pixel size from the scan resolution in dots per inch
    /// (`pixel = 0.0254 m / dpi`), between 2.54 and 2.54e6 dpi (the pixel
    /// sizes [`MAX_PIXEL_SIZE`] to [`MIN_PIXEL_SIZE`]; else
    /// [`FilmError::InvalidParameter`] naming the dpi).
    pub fn with_dpi(self, dpi: f64) -> Result<Self> {
        let dpi = check_positive("dpi", dpi)?;
        let pixel_size = 0.0254 / dpi;
        if check_pixel_size(pixel_size).is_err() {
            return Err(FilmError::InvalidParameter {
                name: "dpi",
                value: dpi,
                requirement: "between 2.54 and 2.54e6 (pixels of 10 mm to 10 nm)",
            });
        }
        self.with_pixel_size(pixel_size)
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Normalised grey levels, row-major.
    pub fn grey(&self) -> &[f32] {
        &self.grey
    }

    /// Grey level at column `col`, row `row` (`None` outside).
    pub fn get(&self, col: usize, row: usize) -> Option<f32> {
        (col < self.width && row < self.height).then(|| self.grey[row * self.width + col])
    }

    /// Pixel size (m), if known.
    pub fn pixel_size(&self) -> Option<f64> {
        self.pixel_size
    }

    /// Bit depth of the source (8, 16, or 32 for float data).
    pub fn bit_depth(&self) -> u8 {
        self.bit_depth
    }

    /// Writes the scan as a 16-bit (or 8-bit when `bit_depth` is 8) grey PNG.
    pub fn to_image(&self) -> DynamicImage {
        let (w, h) = (self.width as u32, self.height as u32);
        if self.bit_depth == 8 {
            let data: Vec<u8> = self
                .grey
                .iter()
                .map(|&g| (g.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect();
            image::GrayImage::from_raw(w, h, data)
                .map(DynamicImage::ImageLuma8)
                .unwrap_or_else(|| DynamicImage::new_luma8(w, h))
        } else {
            let data: Vec<u16> = self
                .grey
                .iter()
                .map(|&g| (g.clamp(0.0, 1.0) * 65535.0).round() as u16)
                .collect();
            image::ImageBuffer::from_raw(w, h, data)
                .map(DynamicImage::ImageLuma16)
                .unwrap_or_else(|| DynamicImage::new_luma16(w, h))
        }
    }
}

fn extract_channel(
    img: &DynamicImage,
    channel: Channel,
) -> std::result::Result<(Vec<f32>, u8), String> {
    // Weights on (R, G, B) for colour images.
    let w: [f32; 3] = match channel {
        Channel::Auto | Channel::Green => [0.0, 1.0, 0.0],
        Channel::Red => [1.0, 0.0, 0.0],
        Channel::Blue => [0.0, 0.0, 1.0],
        Channel::Luma => [0.2126, 0.7152, 0.0722],
    };
    let rgb = |px: &[f32]| w[0] * px[0] + w[1] * px[1] + w[2] * px[2];
    Ok(match img {
        DynamicImage::ImageLuma8(b) => (b.as_raw().iter().map(|&v| v as f32 / 255.0).collect(), 8),
        DynamicImage::ImageLumaA8(b) => (
            b.as_raw()
                .chunks_exact(2)
                .map(|p| p[0] as f32 / 255.0)
                .collect(),
            8,
        ),
        DynamicImage::ImageLuma16(b) => {
            (b.as_raw().iter().map(|&v| v as f32 / 65535.0).collect(), 16)
        }
        DynamicImage::ImageLumaA16(b) => (
            b.as_raw()
                .chunks_exact(2)
                .map(|p| p[0] as f32 / 65535.0)
                .collect(),
            16,
        ),
        DynamicImage::ImageRgb8(b) => (
            b.as_raw()
                .chunks_exact(3)
                .map(|p| rgb(&[p[0] as f32, p[1] as f32, p[2] as f32]) / 255.0)
                .collect(),
            8,
        ),
        DynamicImage::ImageRgba8(b) => (
            b.as_raw()
                .chunks_exact(4)
                .map(|p| rgb(&[p[0] as f32, p[1] as f32, p[2] as f32]) / 255.0)
                .collect(),
            8,
        ),
        DynamicImage::ImageRgb16(b) => (
            b.as_raw()
                .chunks_exact(3)
                .map(|p| rgb(&[p[0] as f32, p[1] as f32, p[2] as f32]) / 65535.0)
                .collect(),
            16,
        ),
        DynamicImage::ImageRgba16(b) => (
            b.as_raw()
                .chunks_exact(4)
                .map(|p| rgb(&[p[0] as f32, p[1] as f32, p[2] as f32]) / 65535.0)
                .collect(),
            16,
        ),
        other => {
            return Err(format!(
                "unsupported pixel type {:?} (8- or 16-bit grey or RGB expected)",
                other.color()
            ));
        }
    })
}

/// The refusal of a scan whose pixels are not square: the film model uses
/// one pixel size, and reading a 600 × 300 dpi scan as square would stretch
/// every print by two along y.
fn non_square(x_per_m: f64, y_per_m: f64, chunk: &str) -> String {
    format!(
        "non-square pixels: {chunk} gives {:.0} × {:.0} dpi (x × y); the film reader needs \
         square pixels: resample the scan to one resolution",
        x_per_m * 0.0254,
        y_per_m * 0.0254
    )
}

/// Pixel size from a PNG's pHYs chunk (unit metre only; an aspect-ratio-only
/// chunk gives no size but must still be square).
fn png_pixel_size(bytes: &[u8]) -> std::result::Result<Option<f64>, String> {
    let decoder = png::Decoder::new(Cursor::new(bytes));
    let Ok(reader) = decoder.read_info() else {
        // The image decoder reports the damage with its own message.
        return Ok(None);
    };
    let Some(dims) = reader.info().pixel_dims else {
        return Ok(None);
    };
    if dims.xppu != dims.yppu {
        return Err(non_square(dims.xppu as f64, dims.yppu as f64, "pHYs"));
    }
    Ok((dims.unit == png::Unit::Meter && dims.xppu > 0).then(|| 1.0 / dims.xppu as f64))
}

/// Pixel size from a TIFF's XResolution and ResolutionUnit (2 = inch,
/// 3 = centimetre; 1 = none gives no size).
/// What a failed decode says: a file that ends before its image data does
/// is said to be cut short rather than "failed to fill whole buffer".
fn decode_message(e: &image::ImageError) -> String {
    let short = match e {
        image::ImageError::IoError(io) => io.kind() == std::io::ErrorKind::UnexpectedEof,
        other => other.to_string().contains("failed to fill whole buffer"),
    };
    if short {
        format!("the file ends before its image data does (truncated?): {e}")
    } else {
        e.to_string()
    }
}

fn tiff_pixel_size(bytes: &[u8]) -> std::result::Result<Option<f64>, String> {
    use tiff::decoder::ifd::Value;
    use tiff::tags::Tag;
    let Ok(mut dec) = tiff::decoder::Decoder::new(Cursor::new(bytes)) else {
        return Ok(None);
    };
    let mut resolution = |tag| match dec.find_tag(tag).ok().flatten() {
        Some(Value::Rational(n, d)) if d != 0 => Some(n as f64 / d as f64),
        Some(Value::Double(v)) => Some(v),
        Some(Value::Float(v)) => Some(v as f64),
        _ => None,
    };
    let Some(res) = resolution(Tag::XResolution) else {
        return Ok(None);
    };
    let y_res = resolution(Tag::YResolution);
    let unit = dec
        .find_tag_unsigned::<u16>(Tag::ResolutionUnit)
        .ok()
        .flatten()
        .unwrap_or(2);
    let per_metre = match unit {
        2 => 1.0 / 0.0254,
        3 => 1.0 / 0.01,
        _ => return Ok(None),
    };
    if let Some(y) = y_res
        && (y - res).abs() > 1e-9 * res.abs()
    {
        return Err(non_square(
            res * per_metre,
            y * per_metre,
            "XResolution/YResolution",
        ));
    }
    let per_metre = res * per_metre;
    Ok((per_metre.is_finite() && per_metre > 0.0).then(|| 1.0 / per_metre))
}
