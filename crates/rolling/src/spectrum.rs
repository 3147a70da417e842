//! Spectra: the one-third-octave band maths and the Welch periodogram live
//! in `tyreroad-core`; re-exported here so that rolling's callers keep their
//! paths.

pub use tyreroad_core::spectrum::{
    Band, BandLevel, NOMINAL_CENTRES, Psd, band_levels, bands_below, default_segment_len,
    effective_segment_len, resolved_from, third_octave, welch,
};
