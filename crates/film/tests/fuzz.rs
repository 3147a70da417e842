//! Every film reader fed arbitrary and mutated input: scans (PNG bytes),
//! calibration tables, layouts and model CSVs must give a value or a clear
//! error, never a panic.

use std::io::Cursor;
use std::path::Path;

use image::{ImageBuffer, ImageFormat, Luma};
use proptest::prelude::*;
use tyreroad_film::{Calibration, Channel, Layout, LlwChart, Scan, parse_model_csv};

fn readers(bytes: &[u8]) {
    let source = Path::new("fuzz");
    let _ = Scan::decode(bytes, Channel::Luma, source);
    let _ = Scan::decode(bytes, Channel::Green, source);
    let text = String::from_utf8_lossy(bytes);
    let _ = Calibration::parse_csv(&text, source);
    let _ = LlwChart::parse_csv(&text, source);
    let _ = Layout::parse_csv(&text, source);
    let _ = parse_model_csv(&text, source);
}

/// A small valid 16-bit grey scan, as PNG bytes.
fn png() -> Vec<u8> {
    let img: ImageBuffer<Luma<u16>, Vec<u16>> =
        ImageBuffer::from_fn(24, 16, |x, y| Luma([(x * 2000 + y * 300) as u16]));
    let mut bytes = Vec::new();
    img.write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
        .expect("PNG encodes");
    bytes
}

const CSV: [&str; 3] = [
    "pressure_pa,density\n0.5e6,0.1\n1e6,0.4\n2e6,0.9\n",
    "indenter,x_m,y_m\n1,0.02,-0.02\n2,0.01,-0.02\n",
    "load_n,indenter,x_m,y_m,force_n,radius_m\n500,1,0.02,-0.02,26.26,2.243e-3\n",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, .. ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2048)) {
        readers(&bytes);
    }

    #[test]
    fn mutated_scans_and_tables_never_panic(
        which in 0usize..4,
        cut in 0.0f64..1.0,
        flips in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..8),
    ) {
        let mut b = if which == 3 { png() } else { CSV[which].as_bytes().to_vec() };
        for (pos, v) in &flips {
            let k = ((pos * b.len() as f64) as usize).min(b.len() - 1);
            b[k] ^= v;
        }
        readers(&b);
        let n = (cut * b.len() as f64) as usize;
        readers(&b[..n]);
    }
}
