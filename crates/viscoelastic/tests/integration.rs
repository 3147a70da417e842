//! The integration tests of `tyreroad-viscoelastic`, one test binary: each file of
//! this folder is a module of it, so that the dependencies' generic code
//! is instantiated and linked once rather than once per file (most of CI's
//! time is compiling). Run one file with
//! `cargo test -p tyreroad-viscoelastic --test integration <file>::`.

mod support;

mod bem_reference;
mod hereditary;
mod master_curve;
mod rolling;
mod rolling_coupled;
mod ting;
mod ting_receding;
mod ting_rolling;
mod trailing_memory;
