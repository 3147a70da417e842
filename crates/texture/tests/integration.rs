//! The integration tests of `tyreroad-texture`, one test binary: each file of
//! this folder is a module of it, so that the dependencies' generic code
//! is instantiated and linked once rather than once per file (most of CI's
//! time is compiling). Run one file with
//! `cargo test -p tyreroad-texture --test integration <file>::`.

mod cap_law;
mod indicators;
mod io;
mod io_refusals;
mod roads;
mod segment;
mod segment_split;
mod segment_window;
