//! The integration tests of `tyreroad-rolling`, one test binary: each file of
//! this folder is a module of it, so that the dependencies' generic code
//! is instantiated and linked once rather than once per file (most of CI's
//! time is compiling). Run one file with
//! `cargo test -p tyreroad-rolling --test integration <file>::`.

mod checkpoint;
mod contact_gap;
mod placement;
mod rolling;
mod sensors;
